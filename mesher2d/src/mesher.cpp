// The mesher2d pipeline: classical Delaunay meshing (§7.3.1) governed by a size or metric
// field (§7.5, §7.6.1). Stages and their sections are listed in mesher2d.h.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numeric>
#include <string>
#include <unordered_set>

#include "huge_pages.h"
#include "key_set.h"
#include "metric_util.h"
#include "triangulation.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d {

namespace {

using detail::InsertParams;
using detail::InsertStatus;
using detail::Triangulation;

// Unit mesh bounds (§7.5.2): an edge conforms when its metric length is in [1/sqrt2, sqrt2].
constexpr double kSqrt2 = 1.4142135623730951;
// Field-point filter (§7.3.5): a candidate closer than this (metric length) to an existing
// vertex is dropped. Just above 1/sqrt2, so that no edge shorter than the unit-mesh lower
// bound is created by refinement.
constexpr double kFilterDist = 0.74;
// Saturation skips the full sampling of an edge whose metric lengths at both ends and at
// the midpoint, and their Simpson mean, are under this (margin under sqrt2).
constexpr double kSkipSample = 1.25;
// Saturation waves stop when no edge is longer than sqrt2 or after this many waves.
constexpr int kMaxWaves = 200;
// Coordinates beyond this magnitude could overflow the exact predicates' products.
constexpr double kMaxCoord = 1e100;
// Relocation (§7.3.6): vertices whose ball is already this good (1/Q) are left alone; a
// move is taken when the ball's worst quality stays above kSmoothAccept times the old
// one. Accepting a slight loss lets the smoothing escape the local optimum where each
// single move only trades one triangle against another (measured on the square with a
// hole at h = 0.01: triangles with Q > 1.3 drop from 330 to 130 against strict gain).
constexpr double kSmoothSkip = 0.97;
constexpr double kSmoothAccept = 0.95;
// Max-min relocation (maxmin_relocate) stops once the ball's worst 1/Q_K reaches this:
// 1 / 1.15, a margin under the issue's Q_M <= 1.2.
constexpr double kMaxminStop = 1 / 1.15;
constexpr double kMaxminStopVarying = 1 / 1.3;
// Varying-field swaps are tried on the edges of triangles with Q_K > 1.3 only.
constexpr double kSwapSkipVarying = 1 / 1.3;
// Targeted repair (Mesher::repair) works on triangles worse than this: Q_K > 1.18.
constexpr double kRepairBad = 1 / 1.18;
// For a varying field (scalar or metric) the repair works on triangles with Q_K > 1.4:
// the issue asks for Q_M <= 2 and 95% under 1.5 there.
constexpr double kRepairBadVarying = 1 / 1.4;
// The size pass (Mesher::size_pass) may lower a ball's worst 1/Q_K down to this.
constexpr double kSizeFloor = 1 / 1.45;
// Its work budget, in triangle evaluations per triangle of the mesh.
constexpr std::int64_t kRepairWork = 20;

std::string fmt_pt(Vec2 p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g)", p.x, p.y);
  return buf;
}

// Hilbert index of (x, y) in [0, 2^16)^2: the spatial order of batch insertion (§7.3.2).
std::uint32_t hilbert_d(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0;
  for (std::uint32_t s = 1u << 15; s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1 : 0;
    const std::uint32_t ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {  // rotate the quadrant
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

struct SegRec {
  VertId a, b;
  int marker;
  std::int32_t input;  // input segment index; -1 for convex hull edges
  bool alive = true;
};

double q_inv(Vec2 a, Vec2 b, Vec2 c) {
  // 1 / Q_K (eq. 7.6) = rho / (alpha hmax): 1 for the equilateral, 0 for flat.
  const double ab2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
  const double bc2 = (c.x - b.x) * (c.x - b.x) + (c.y - b.y) * (c.y - b.y);
  const double ca2 = (a.x - c.x) * (a.x - c.x) + (a.y - c.y) * (a.y - c.y);
  const double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(area2 > 0)) return area2 == 0 ? 0.0 : -1.0;
  // sqrt is correctly rounded and monotone: the longest edge's length is the largest of
  // the three roots, bit for bit what sqrt(max(ab2, bc2, ca2)) gave, one sqrt fewer.
  const double ab = std::sqrt(ab2), bc = std::sqrt(bc2), ca = std::sqrt(ca2);
  const double per = ab + bc + ca;
  const double hmax = std::max({ab, bc, ca});
  return area2 / (per * hmax * 0.28867513459481287);
}

class Mesher {
 public:
  Mesher(const Pslg& in, const SizeSpec& size, const Options& opt, Result& res)
      : in_(in), size_(size), opt_(opt), res_(res) {}

  void run() {
    auto t0 = Clock::now();
    if (!validate()) return;
    if (hull_fast_path()) {
      run_hull(t0);
      return;
    }
    merge_duplicates();
    build_segments();
    stage("input", t0);
    if (!triangulate()) return;
    stage("delaunay", t0);
    if (!enforce_all()) return;
    stage("boundary enforcement", t0);
    if (opt_.refine && opt_.split_segments && refine_ok_) {
      // Curves first: split the enforced segments (input segments already split at the
      // input vertices lying on them, and at crossings) at unit metric length.
      if (!discretize_boundary()) return;
      stage("boundary discretization", t0);
    }
    if (!color()) return;
    stage("coloring", t0);
    if (opt_.check && !internal_check("after coloring")) return;
    if (opt_.refine && refine_ok_) {
      refine();
      stage("field points", t0);
      if (opt_.check && !internal_check("after field points")) return;
      if (opt_.optimize && res_.status.code != StatusCode::TimeLimit) {
        optimize();
        stage("optimization", t0);
        if (opt_.check && !internal_check("after optimization")) return;
      }
    }
    output();
    stage("output", t0);
    if (field_error_) return;
    if (opt_.measure) {
      res_.stats.quality = detail::measure_with_edges(res_.mesh.vertices, res_.mesh.triangles,
                                                      measure_spec(), &edges_);
      stage("measure", t0);
    }
    if (opt_.check) {
      CheckReport rep = check(res_.mesh, in_, {.delaunay = !opt_.refine});
      if (!rep.ok()) fail(StatusCode::InternalError, "checker: " + rep.errors.front());
    }
  }

 private:
  using Clock = std::chrono::steady_clock;
  void stage(const char* name, Clock::time_point& t0) {
    const auto t1 = Clock::now();
    res_.stats.stages.push_back({name, std::chrono::duration<double>(t1 - t0).count()});
    t0 = t1;
  }
  bool fail(StatusCode c, std::string msg, std::vector<std::int64_t> ent = {}) {
    res_.status.code = c;
    res_.status.message = std::move(msg);
    res_.status.entities = std::move(ent);
    return false;
  }

  // ---------------------------------------------------------------- size field
  SizeSpec measure_spec() const {
    // Without refinement there is no size to conform to: Euclidean measures only.
    if (!opt_.refine || !refine_ok_) return SizeSpec::uniform(0);
    if (size_.kind == SizeSpec::Kind::Uniform) return SizeSpec::uniform(h_uniform_);
    return size_;
  }
  // The metric at (x, y), validated (SPD, finite) and capped in anisotropy.
  Metric2 metric(double x, double y) {
    Metric2 m;
    if (size_.kind == SizeSpec::Kind::Uniform) return m_uniform_;
    if (size_.kind == SizeSpec::Kind::Scalar) {
      const double h = size_.size(x, y);
      if (!(h > 0) || !std::isfinite(h)) {
        field_fail("the size field returned h = " + std::to_string(h) + " at " + fmt_pt({x, y}));
        return m_uniform_;
      }
      return Metric2::iso(h);
    }
    m = size_.metric(x, y);
    const double det = m.m11 * m.m22 - m.m12 * m.m12;
    if (!(m.m11 > 0) || !(m.m22 > 0) || !(det > 0) || !std::isfinite(m.m11) ||
        !std::isfinite(m.m12) || !std::isfinite(m.m22)) {
      field_fail("the metric field is not symmetric positive definite at " + fmt_pt({x, y}));
      return m_uniform_;
    }
    return detail::cap_anisotropy(m, opt_.max_anisotropy);
  }
  void field_fail(std::string msg) {
    if (!field_error_) fail(StatusCode::InvalidInput, std::move(msg));
    field_error_ = true;
  }

  // ---------------------------------------------------------------- 1. input
  bool validate() {
    const std::size_t n = in_.points.size();
    if (n == 0) return fail(StatusCode::InvalidInput, "empty PSLG: no points");
    if (!in_.point_markers.empty() && in_.point_markers.size() != n)
      return fail(StatusCode::InvalidInput, "point_markers has " +
                                                std::to_string(in_.point_markers.size()) +
                                                " entries for " + std::to_string(n) + " points");
    auto bad = [](Vec2 p) {
      return !std::isfinite(p.x) || !std::isfinite(p.y) || std::abs(p.x) > kMaxCoord ||
             std::abs(p.y) > kMaxCoord;
    };
    for (std::size_t i = 0; i < n; ++i)
      if (bad(in_.points[i]))
        return fail(StatusCode::InvalidInput,
                    "point " + std::to_string(i) + " has a non-finite or out-of-range coordinate " +
                        fmt_pt(in_.points[i]),
                    {static_cast<std::int64_t>(i)});
    for (std::size_t i = 0; i < in_.segments.size(); ++i) {
      const auto& s = in_.segments[i];
      for (VertId v : {s.a, s.b})
        if (v < 0 || static_cast<std::size_t>(v) >= n)
          return fail(StatusCode::InvalidInput,
                      "segment " + std::to_string(i) + " references point " + std::to_string(v) +
                          ", but there are " + std::to_string(n) + " points",
                      {static_cast<std::int64_t>(i)});
    }
    for (std::size_t i = 0; i < in_.holes.size(); ++i)
      if (bad(in_.holes[i]))
        return fail(StatusCode::InvalidInput,
                    "hole " + std::to_string(i) + " has a non-finite coordinate",
                    {static_cast<std::int64_t>(i)});
    for (std::size_t i = 0; i < in_.regions.size(); ++i)
      if (bad(in_.regions[i].seed) || !std::isfinite(in_.regions[i].attribute))
        return fail(StatusCode::InvalidInput,
                    "region " + std::to_string(i) + " has a non-finite value",
                    {static_cast<std::int64_t>(i)});
    switch (size_.kind) {
      case SizeSpec::Kind::Uniform:
        if (!std::isfinite(size_.h))
          return fail(StatusCode::InvalidInput, "uniform size is not finite");
        break;
      case SizeSpec::Kind::Scalar:
        if (!size_.size)
          return fail(StatusCode::InvalidInput, "scalar size field without a function");
        break;
      case SizeSpec::Kind::Metric:
        if (!size_.metric)
          return fail(StatusCode::InvalidInput, "metric size field without a function");
        break;
    }
    if (!(opt_.max_anisotropy >= 1))
      return fail(StatusCode::InvalidInput, "max_anisotropy must be >= 1");
    return true;
  }

  void merge_duplicates() {
    const std::size_t n = in_.points.size();
    // Sort (x, y, index) records directly: an index sort with an indirect comparator is
    // several times slower on a million points (cache misses on every comparison).
    struct Rec {
      double x, y;
      std::int32_t i;
    };
    std::vector<Rec> recs(n);
    for (std::size_t i = 0; i < n; ++i)
      recs[i] = {in_.points[i].x, in_.points[i].y, static_cast<std::int32_t>(i)};
    std::sort(recs.begin(), recs.end(), [](const Rec& p, const Rec& q) {
      if (p.x != q.x) return p.x < q.x;
      if (p.y != q.y) return p.y < q.y;
      return p.i < q.i;
    });
    std::vector<std::int32_t>& order = xy_order_;
    order.resize(n);
    for (std::size_t k = 0; k < n; ++k) order[k] = recs[k].i;
    rep_.assign(n, -1);
    for (std::size_t k = 0; k < n; ++k) {
      const std::int32_t i = order[k];
      if (k > 0) {
        const std::int32_t j = order[k - 1];
        if (in_.points[i].x == in_.points[j].x && in_.points[i].y == in_.points[j].y) {
          rep_[i] = rep_[j];
          continue;
        }
      }
      rep_[i] = i;
    }
    std::int64_t dup = 0;
    for (std::size_t i = 0; i < n; ++i) dup += rep_[i] != static_cast<std::int32_t>(i);
    res_.stats.duplicates_merged = dup;
    if (dup > 0) {
      for (std::size_t i = 0; i < n; ++i)
        if (rep_[i] != static_cast<std::int32_t>(i)) {
          res_.status.warnings.push_back(
              std::to_string(dup) + " duplicate point(s) merged (first: point " +
              std::to_string(i) + " duplicates point " + std::to_string(rep_[i]) + ")");
          break;
        }
    }
  }

  void build_segments() {
    std::unordered_set<std::uint64_t> seen;
    std::int64_t degenerate = 0, repeated = 0;
    for (std::size_t i = 0; i < in_.segments.size(); ++i) {
      const auto& s = in_.segments[i];
      const VertId a = rep_[s.a], b = rep_[s.b];
      if (a == b) {
        ++degenerate;
        continue;
      }
      const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 |
                                static_cast<std::uint32_t>(std::max(a, b));
      if (!seen.insert(key).second) {
        ++repeated;
        continue;
      }
      segs_.push_back({a, b, s.marker, static_cast<std::int32_t>(i)});
    }
    if (degenerate)
      res_.status.warnings.push_back(std::to_string(degenerate) +
                                     " zero-length segment(s) ignored");
    if (repeated)
      res_.status.warnings.push_back(std::to_string(repeated) + " repeated segment(s) ignored");
    // Size for "uniform, h <= 0": the mean input segment length (the chapter's step size
    // from the boundary, §7.3.5 preliminary requirements).
    h_uniform_ = size_.h;
    if (size_.kind == SizeSpec::Kind::Uniform && !(h_uniform_ > 0)) {
      double sum = 0;
      for (const auto& s : segs_) {
        const Vec2 a = in_.points[s.a], b = in_.points[s.b];
        sum += std::hypot(b.x - a.x, b.y - a.y);
      }
      if (segs_.empty() || !(sum > 0)) {
        refine_ok_ = false;
        h_uniform_ = 1;
      } else {
        h_uniform_ = sum / static_cast<double>(segs_.size());
      }
    }
    m_uniform_ = Metric2::iso(h_uniform_);
  }

  // ---------------------------------------------------------------- edge sampling
  // Metric length of the straight edge a -> b (eq. 7.10) by a piecewise-linear rule on a
  // sampling refined until every piece is shorter than kPiece in the metric, so that a
  // size feature between the endpoints (a boundary layer, a ring) is not missed; and the
  // parameters of n - 1 points splitting it in n pieces of equal metric length.
  // Boundary size ratio at parameter t of an edge whose ends have ratios ra, rb (<= 1):
  // the growth at the gradation rate from the nearer end (the H-correction, eq. 7.11);
  // l is the edge's length in the unscaled metric (Options::boundary_gradation). Not an
  // interpolation between the ends: the first waves' edges cross the whole domain between
  // two boundary vertices, and interpolating would keep the small boundary ratio all the
  // way across (a face bounded by tiny segments everywhere was meshed uniformly fine).
  double ratio_at(double ra, double rb, double t, double l) const {
    const double g = opt_.boundary_gradation - 1;
    const double r = std::min({1.0, ra + g * t * l, rb + g * (1 - t) * l});
    return std::max(r, 1e-6);
  }
  struct EdgeSampler {
    std::vector<double> ts, len, cum, nts, nl;
  };
  static constexpr double kPiece = 0.25;
  double sample_edge(Vec2 a, Vec2 b, const Metric2& ma, const Metric2& mb, EdgeSampler& es,
                     double ra = 1, double rb = 1) {
    const Vec2 d{b.x - a.x, b.y - a.y};
    const bool scaled = ra < 1 || rb < 1;
    es.ts.assign({0.0, 1.0});
    es.len.assign({detail::length(ma, d), detail::length(mb, d)});
    for (int it = 0; it < 40; ++it) {
      es.nts.assign(1, 0.0);
      es.nl.assign(1, es.len[0]);
      bool split = false;
      for (std::size_t k = 0; k + 1 < es.ts.size(); ++k) {
        const double piece = (es.ts[k + 1] - es.ts[k]) * 0.5 * (es.len[k] + es.len[k + 1]);
        if (piece > kPiece && es.nts.size() < 1'000'000) {
          const double tm = 0.5 * (es.ts[k] + es.ts[k + 1]);
          es.nts.push_back(tm);
          es.nl.push_back(detail::length(metric(a.x + tm * d.x, a.y + tm * d.y), d));
          split = true;
        }
        es.nts.push_back(es.ts[k + 1]);
        es.nl.push_back(es.len[k + 1]);
      }
      es.ts.swap(es.nts);
      es.len.swap(es.nl);
      if (!split) break;
    }
    if (scaled) {
      // The boundary scale is known in closed form (ratio_at), so it needs no field
      // evaluations: the field's lengths are interpolated on the pieces, divided by the
      // ratio, and pieces are split until each is short in the scaled metric too.
      const double lu = 0.5 * (es.len.front() * ra + es.len.back() * rb);
      // vm_ at the ends is already scaled: undo it so that all samples are field lengths.
      es.len.front() *= ra;
      es.len.back() *= rb;
      for (int it = 0; it < 40; ++it) {
        es.nts.assign(1, 0.0);
        es.nl.assign(1, es.len[0]);
        bool split = false;
        for (std::size_t k = 0; k + 1 < es.ts.size(); ++k) {
          const double t0 = es.ts[k], t1 = es.ts[k + 1];
          const double piece =
              (t1 - t0) * 0.5 *
              (es.len[k] / ratio_at(ra, rb, t0, lu) + es.len[k + 1] / ratio_at(ra, rb, t1, lu));
          if (piece > kPiece && es.nts.size() < 1'000'000) {
            es.nts.push_back(0.5 * (t0 + t1));
            es.nl.push_back(0.5 * (es.len[k] + es.len[k + 1]));
            split = true;
          }
          es.nts.push_back(t1);
          es.nl.push_back(es.len[k + 1]);
        }
        es.ts.swap(es.nts);
        es.len.swap(es.nl);
        if (!split) break;
      }
      for (std::size_t k = 0; k < es.ts.size(); ++k) es.len[k] /= ratio_at(ra, rb, es.ts[k], lu);
    }
    es.cum.assign(es.ts.size(), 0.0);
    for (std::size_t k = 1; k < es.ts.size(); ++k)
      es.cum[k] = es.cum[k - 1] + (es.ts[k] - es.ts[k - 1]) * 0.5 * (es.len[k - 1] + es.len[k]);
    return es.cum.back();
  }
  // Parameters of the points splitting the sampled edge into n equal metric pieces.
  template <class F>
  static void split_params(const EdgeSampler& es, int n, F&& emit) {
    const double L = es.cum.back();
    std::size_t k = 0;
    for (int j = 1; j < n; ++j) {
      const double target = L * j / n;
      while (k + 2 < es.cum.size() && es.cum[k + 1] < target) ++k;
      const double f = (target - es.cum[k]) / std::max(es.cum[k + 1] - es.cum[k], 1e-300);
      emit(es.ts[k] + f * (es.ts[k + 1] - es.ts[k]));
    }
  }

  // ---------------------------------------------------------------- 2. boundary
  // Curves first: every segment is split at unit length in the metric (eq. 7.10),
  // computed on a piecewise subdivision fine enough (pieces of metric length <= 1/4) to
  // follow a varying field.
  bool discretize_boundary() {
    EdgeSampler es;
    std::vector<std::int32_t> work;
    const std::size_t nseg = segs_.size();
    std::vector<VertId> chain;
    for (std::size_t sid = 0; sid < nseg; ++sid) {
      const SegRec s = segs_[sid];
      if (!s.alive) continue;
      const Vec2 a = tri_.pts[s.a], b = tri_.pts[s.b];
      const double L = sample_edge(a, b, metric(a.x, a.y), metric(b.x, b.y), es);
      const int n = std::max(1, static_cast<int>(std::lround(L)));
      if (n == 1) continue;
      tri_.unconstrain(s.a, s.b);
      segs_[sid].alive = false;
      chain.assign(1, s.a);
      InsertParams prm;
      bool ok = true;
      split_params(es, n, [&](double t) {
        if (!ok) return;
        const Vec2 p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
        // A split point is rounded off the segment's line; next to a nearly collinear
        // constrained neighbour it could land on the far side. Such a point is skipped
        // (the piece gets longer) rather than making a crossing.
        if (!tri_.segment_clear(chain.back(), p) || !tri_.segment_clear(s.b, p)) {
          ++res_.stats.boundary_points_skipped;
          return;
        }
        const auto r = tri_.insert_point(p, tri_.vtri[chain.back()], prm);
        if (r.status == InsertStatus::Inserted) {
          fixed_.push_back(1);
          vmark_.push_back(s.marker);
          chain.push_back(r.v);
        } else if (r.status == InsertStatus::Duplicate) {
          if (r.v != chain.back()) chain.push_back(r.v);
        } else {
          ok = false;  // e.g. lands on another constrained edge: keep the segment whole
        }
      });
      chain.push_back(s.b);
      // Enforce the pieces now, so that the next segments' split points see them.
      work.clear();
      for (std::size_t k = chain.size() - 1; k-- > 0;)
        if (chain[k] != chain[k + 1])
          work.push_back(add_seg({chain[k], chain[k + 1], s.marker, s.input}));
      if (!enforce_work(work, /*split_crossings=*/true)) return false;
    }
    return true;
  }

  Vec2 point(VertId i) const { return in_.points[i]; }

  // ---------------------------------------------------------------- 3. Delaunay
  bool triangulate() {
    const std::size_t n = in_.points.size();
    const std::size_t ntot = n;
    double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
    for (std::size_t i = 0; i < ntot; ++i) {
      const Vec2 p = point(static_cast<VertId>(i));
      xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
      ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
    }
    double ext = std::max(xmax - xmin, ymax - ymin);
    if (!(ext > 0)) ext = std::max(1.0, std::abs(xmin) + std::abs(ymin));
    // The box (§7.3.2): far enough that box corners never matter inside the domain.
    const double m = 2.0 * ext;
    tri_.init_box(xmin - m, ymin - m, xmax + m, ymax + m, ntot + 16);
    vid_.assign(ntot, kNone);
    // Batch insertion in Hilbert order.
    std::vector<std::pair<std::uint32_t, VertId>> order;
    order.reserve(ntot);
    const double sx = 65535.0 / std::max(xmax - xmin, 1e-300),
                 sy = 65535.0 / std::max(ymax - ymin, 1e-300);
    for (std::size_t i = 0; i < ntot; ++i) {
      if (i < n && rep_[i] != static_cast<std::int32_t>(i)) continue;
      const Vec2 p = point(static_cast<VertId>(i));
      const auto qx = static_cast<std::uint32_t>(std::clamp((p.x - xmin) * sx, 0.0, 65535.0));
      const auto qy = static_cast<std::uint32_t>(std::clamp((p.y - ymin) * sy, 0.0, 65535.0));
      order.push_back({hilbert_d(qx, qy), static_cast<VertId>(i)});
    }
    std::sort(order.begin(), order.end());
    fixed_.assign(4, 1);
    vmark_.assign(4, 0);
    InsertParams prm;
    TriId hint = 0;
    for (const auto& [key, i] : order) {
      const VertId v = tri_.add_vertex(point(i));
      const auto r = tri_.insert(v, hint, prm);
      if (r.status == InsertStatus::Duplicate) {
        // A boundary split point landing exactly on another point: use that one.
        tri_.pts.pop_back();
        tri_.vtri.pop_back();
        vid_[i] = r.v;
        continue;
      }
      if (r.status != InsertStatus::Inserted)
        return fail(StatusCode::InternalError,
                    "could not insert point " + std::to_string(i) + " " + fmt_pt(point(i)));
      vid_[i] = v;
      fixed_.push_back(1);
      vmark_.push_back(in_.point_markers.empty() ? 0 : in_.point_markers[i]);
      hint = tri_.vtri[v];
    }
    for (std::size_t i = 0; i < n; ++i) vid_[i] = vid_[rep_[i]];
    for (auto& s : segs_) {
      s.a = vid_[s.a];
      s.b = vid_[s.b];
    }
    return true;
  }

  // ---------------------------------------------------------------- 3'. hull fast path
  // No segments, holes, regions or refinement: the result is the Delaunay triangulation
  // of the convex hull of the distinct input points, which HullDelaunay builds directly
  // (ghost triangles instead of box, hull enforcement and coloring). Same exact
  // predicates, same Result: vertices in input order, hull edges as boundary edges
  // (marker 1, split at collinear points), duplicates merged and reported.
  bool hull_fast_path() const {
    return in_.segments.empty() && in_.holes.empty() && in_.regions.empty() &&
           in_.points.size() <= detail::HullDelaunay::kMaxPoints &&
           opt_.triangulate_hull_without_segments && !opt_.domain_from_orientation &&
           (!opt_.refine || (size_.kind == SizeSpec::Kind::Uniform && !(size_.h > 0)));
  }
  void run_hull(Clock::time_point& t0) {
    stage("input", t0);
    detail::HullDelaunay dh;
    const auto st = dh.build(in_.points);
    if (st == detail::HullDelaunay::Status::Collinear) {
      fail(StatusCode::InvalidInput, "all points are collinear: there is no triangle to make");
      return;
    }
    if (st != detail::HullDelaunay::Status::Ok) {
      fail(StatusCode::InternalError,
           "Delaunay triangulation of the convex hull failed (kernel bug guard)");
      return;
    }
    stage("delaunay", t0);
    output_hull(dh);
    stage("output", t0);
    if (opt_.measure) {
      res_.stats.quality = measure(res_.mesh.vertices, res_.mesh.triangles, SizeSpec::uniform(0));
      stage("measure", t0);
    }
    if (opt_.check) {
      CheckReport rep = check(res_.mesh, in_, {.delaunay = true});
      if (!rep.ok()) fail(StatusCode::InternalError, "checker: " + rep.errors.front());
    }
  }
  void output_hull(detail::HullDelaunay& dh) {
    Mesh& M = res_.mesh;
    const std::size_t n = in_.points.size();
    const std::size_t nv = n;  // vertices 0..n-1; dh.ghost_id == n
    // Output vertices in the kernel's insertion order (spatially coherent: BRIO rounds
    // in Hilbert order), so that every later pass over the mesh, ours or the caller's,
    // reads its vertices nearly in sequence; input_vertex maps input points to them.
    // An exact duplicate's vertex is left out; its input point maps to the equal vertex.
    std::vector<VertId> out;
    const bool compact = !dh.dups.empty();
    std::vector<char> dead;
    if (compact) {
      dead.assign(nv, 0);
      for (const auto& d : dh.dups) dead[d.first] = 1;
      out.assign(nv, kNone);
    }
    const std::size_t nout = nv - dh.dups.size();
    detail::assign_huge(M.vertex_markers, nout, 0);
    // Without duplicates input point i is vertex vert_of[i] as it is (the kernel's
    // inverse of its insertion order, made while it gathered the points).
    if (compact)
      M.input_vertex.resize(n);
    else
      M.input_vertex = std::move(dh.vert_of);
    // The marker of a merged vertex is that of its first input point (as in
    // merge_duplicates): msrc = the smallest input index among equal points.
    std::vector<std::int32_t> msrc;
    if (compact) {
      msrc.assign(dh.src.begin(), dh.src.end());
      for (const auto& [d, k] : dh.dups) msrc[k] = std::min(msrc[k], dh.src[d]);
      M.vertices.resize(nout);
    }
    VertId w = 0;
    for (std::size_t v = 0; v < nv; ++v) {
      if (compact) {
        if (dead[v]) continue;
        out[v] = w;
        M.vertices[w] = dh.pts[v];
      }
      if (compact) M.input_vertex[dh.src[v]] = w;
      if (!in_.point_markers.empty())
        M.vertex_markers[w] = in_.point_markers[compact ? msrc[v] : dh.src[v]];
      ++w;
    }
    if (compact) {
      std::int64_t dup_first = -1, dup_of = -1;
      for (const auto& [d, k] : dh.dups) {
        M.input_vertex[dh.src[d]] = out[k];
        for (const std::int32_t i : {dh.src[d], dh.src[k]})
          if (i != msrc[k] && (dup_first < 0 || i < dup_first)) dup_first = i, dup_of = msrc[k];
      }
      const auto dup = static_cast<std::int64_t>(dh.dups.size());
      res_.stats.duplicates_merged = dup;
      res_.status.warnings.push_back(
          std::to_string(dup) + " duplicate point(s) merged (first: point " +
          std::to_string(dup_first) + " duplicates point " + std::to_string(dup_of) + ")");
    } else {
      // Every vertex is output as it is: the kernel's coordinate array, without G.
      M.vertices = std::move(dh.pts);
      M.vertices.pop_back();
    }
    // Triangles and hull edges in one pass; a ghost (a, b, G) stands for the hull edge
    // b -> a of the triangle inside.
    const std::size_t nt = dh.tris.size();
    detail::reserve_huge(M.triangles, nt);
    auto emit = [&](auto id) {
      for (std::size_t t = 0; t < nt; ++t) {
        const auto& r = dh.tris[t];
        if (dh.ghost(r)) [[unlikely]] {
          const int g = dh.ghost_corner(r);
          M.boundary_edges.push_back({id(r.v[detail::prev3(g)]), id(r.v[detail::next3(g)]), 1});
          continue;
        }
        M.triangles.push_back({id(r.v[0]), id(r.v[1]), id(r.v[2])});
      }
    };
    if (compact)
      emit([&](VertId v) { return out[v]; });
    else
      emit([](VertId v) { return v; });
    const std::size_t k = M.triangles.size();
    detail::assign_huge(M.triangle_region, k, 0);
    detail::assign_huge(M.triangle_attribute, k, 0.0);
  }

  // ---------------------------------------------------------------- 4. enforcement
  bool enforce_all() {
    if (segs_.empty() && opt_.triangulate_hull_without_segments) {
      if (!add_hull()) return false;
    }
    std::vector<std::int32_t> work(segs_.size());
    std::iota(work.begin(), work.end(), 0);
    std::reverse(work.begin(), work.end());
    if (!enforce_work(work)) return false;
    if (overlaps_merged_ > 0)
      res_.status.warnings.push_back(std::to_string(overlaps_merged_) +
                                     " piece(s) of overlapping collinear segments merged");
    return true;
  }
  // Enforces the segments in work (a stack), splitting them at the vertices they pass
  // through and, by option, at crossings.
  bool enforce_work(std::vector<std::int32_t>& work, bool split_crossings = false) {
    std::int64_t budget = 16 * static_cast<std::int64_t>(segs_.size()) + 4096;
    while (!work.empty()) {
      const std::int32_t sid = work.back();
      work.pop_back();
      SegRec s = segs_[sid];
      if (!s.alive || s.a == s.b) continue;
      if (--budget < 0)
        return fail(StatusCode::InternalError, "boundary enforcement did not converge");
      if (overlaps_enforced(s, sid)) {
        // Overlapping collinear segments, once split at each other's end points (the
        // ThroughVertex case below), give the same piece twice: it is kept once, as
        // Triangle keeps one subsegment. Two live records of one edge would each be split
        // at unit length in discretize_boundary, the second with points rounded off the
        // first one's chain (a constrained edge on no segment's chain: fuzz_poly_mesh2d).
        segs_[sid].alive = false;
        ++overlaps_merged_;
        continue;
      }
      const auto r = tri_.enforce(s.a, s.b, sid);
      using ES = Triangulation::EnforceStatus;
      if (r.status == ES::Ok) continue;
      if (r.status == ES::ThroughVertex) {
        // A segment passing through a vertex is split there.
        segs_[sid].alive = false;
        ++res_.stats.segments_split_at_vertices;
        work.push_back(add_seg({r.through, s.b, s.marker, s.input}));
        work.push_back(add_seg({s.a, r.through, s.marker, s.input}));
        continue;
      }
      if (r.crossing_seg == kNone)
        return fail(StatusCode::InternalError,
                    "boundary enforcement failed on segment " + seg_name(s));
      const SegRec o = segs_[r.crossing_seg];
      if (!opt_.split_crossing_segments && !split_crossings)
        return fail(StatusCode::CrossingSegments,
                    "segment " + seg_name(s) + " crosses segment " + seg_name(o),
                    {s.input, o.input});
      // Split both at their intersection point.
      const Vec2 pa = tri_.pts[s.a], pb = tri_.pts[s.b], pc = tri_.pts[o.a], pd = tri_.pts[o.b];
      // Parameters on both segments, clamped: for nearly parallel segments the line
      // intersection is ill-conditioned along the lines (not across them), so the point
      // is taken as the mean of the two clamped points, close to both segments.
      const double den = (pb.x - pa.x) * (pd.y - pc.y) - (pb.y - pa.y) * (pd.x - pc.x);
      double t = ((pc.x - pa.x) * (pd.y - pc.y) - (pc.y - pa.y) * (pd.x - pc.x)) / den;
      double u = ((pc.x - pa.x) * (pb.y - pa.y) - (pc.y - pa.y) * (pb.x - pa.x)) / den;
      t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.5;
      u = std::isfinite(u) ? std::clamp(u, 0.0, 1.0) : 0.5;
      const Vec2 x{0.5 * (pa.x + t * (pb.x - pa.x) + pc.x + u * (pd.x - pc.x)),
                   0.5 * (pa.y + t * (pb.y - pa.y) + pc.y + u * (pd.y - pc.y))};
      tri_.unconstrain(o.a, o.b);
      segs_[r.crossing_seg].alive = false;
      segs_[sid].alive = false;
      InsertParams prm;
      auto ir = tri_.insert_point(x, tri_.vtri[s.a], prm);
      VertId xv;
      if (ir.status == InsertStatus::Inserted) {
        xv = ir.v;
        fixed_.push_back(1);
        vmark_.push_back(s.marker);
      } else if (ir.status == InsertStatus::Duplicate) {
        xv = ir.v;
      } else {
        return fail(StatusCode::CrossingSegments,
                    "segment " + seg_name(s) + " crosses segment " + seg_name(o) +
                        " and the crossing point could not be inserted",
                    {s.input, o.input});
      }
      ++res_.stats.crossings_split;
      for (const SegRec& ns :
           {SegRec{o.a, xv, o.marker, o.input}, SegRec{xv, o.b, o.marker, o.input},
            SegRec{xv, s.b, s.marker, s.input}, SegRec{s.a, xv, s.marker, s.input}})
        if (ns.a != ns.b) work.push_back(add_seg(ns));
    }
    return true;
  }
  // True when edge (s.a, s.b) is already in the triangulation, constrained by another
  // live segment record with the same two ends.
  bool overlaps_enforced(const SegRec& s, std::int32_t sid) const {
    std::int32_t h = tri_.find_half_edge(s.a, s.b);
    if (h == kNone) h = tri_.find_half_edge(s.b, s.a);
    if (h == kNone) return false;
    const std::int32_t o = tri_.seg[h];
    if (o == kNone || o == sid || !segs_[o].alive) return false;
    const SegRec& so = segs_[o];
    return (so.a == s.a && so.b == s.b) || (so.a == s.b && so.b == s.a);
  }
  std::int32_t add_seg(SegRec s) {
    segs_.push_back(s);
    return static_cast<std::int32_t>(segs_.size() - 1);
  }
  std::string seg_name(const SegRec& s) const {
    if (s.input < 0) return "convex hull edge";
    const auto& o = in_.segments[s.input];
    return std::to_string(s.input) + " (points " + std::to_string(o.a) + "-" + std::to_string(o.b) +
           ")";
  }

  bool add_hull() {
    // Andrew's monotone chain with exact orientation; collinear points are left out of
    // the hull and later split the hull edges through them (enforcement).
    // The (x, y) order of the unique input points is known from the duplicate merge.
    std::vector<VertId> v;
    v.reserve(xy_order_.size());
    for (const std::int32_t i : xy_order_)
      if (rep_[i] == i && vid_[i] != kNone) v.push_back(vid_[i]);
    auto& P = tri_.pts;
    std::vector<VertId> h(2 * v.size() + 2);
    std::size_t k = 0;
    for (std::size_t i = 0; i < v.size(); ++i) {
      while (k >= 2 && pred::orient2d(&P[h[k - 2]].x, &P[h[k - 1]].x, &P[v[i]].x) <= 0) --k;
      h[k++] = v[i];
    }
    for (std::size_t i = v.size() - 1, t = k + 1; i-- > 0;) {
      while (k >= t && pred::orient2d(&P[h[k - 2]].x, &P[h[k - 1]].x, &P[v[i]].x) <= 0) --k;
      h[k++] = v[i];
    }
    if (k < 4)
      return fail(StatusCode::InvalidInput,
                  "all points are collinear: there is no triangle to make");
    for (std::size_t i = 0; i + 1 < k; ++i) segs_.push_back({h[i], h[i + 1], 1, -1});
    return true;
  }

  // ---------------------------------------------------------------- 5. coloring
  bool color() {
    // §7.3.4: color 0 is the component of the box corners (the exterior); every other
    // connected component (bounded by constrained edges) gets its own color.
    const TriId nt = tri_.num_tris();
    std::vector<std::int32_t>& comp = tri_.tag;
    std::fill(comp.begin(), comp.end(), -1);
    std::vector<TriId> stack;
    std::int32_t ncomp = 0;
    auto flood = [&](TriId s, std::int32_t c) {
      comp[s] = c;
      stack.push_back(s);
      while (!stack.empty()) {
        const TriId t = stack.back();
        stack.pop_back();
        for (int i = 0; i < 3; ++i) {
          if (tri_.seg[3 * t + i] != kNone) continue;
          const std::int32_t h = tri_.opp[3 * t + i];
          if (h != kNone && comp[h / 3] == -1) {
            comp[h / 3] = c;
            stack.push_back(h / 3);
          }
        }
      }
    };
    flood(tri_.vtri[0], ncomp++);
    for (TriId t = 0; t < nt; ++t)
      if (!tri_.dead(t) && comp[t] == -1) flood(t, ncomp++);
    removed_.assign(ncomp, 0);
    removed_[0] = 1;
    attr_.assign(ncomp, 0.0);
    const bool had_domain = ncomp > 1;
    if (opt_.domain_from_orientation) {
      // Vote per component: a constrained half-edge of a CCW triangle runs from
      // tv[next3(i)] to tv[prev3(i)], so the triangle is on the left of its segment when
      // that half-edge runs a -> b. A majority (not unanimity) tolerates a loop that
      // touches itself at a vertex.
      std::vector<std::int64_t> vote(ncomp, 0);
      for (TriId t = 0; t < nt; ++t) {
        if (tri_.dead(t)) continue;
        for (int i = 0; i < 3; ++i) {
          const std::int32_t s = tri_.seg[3 * t + i];
          if (s == kNone || segs_[s].input < 0) continue;
          const VertId from = tri_.tv[3 * t + detail::next3(i)];
          vote[comp[t]] += from == segs_[s].a ? 1 : -1;
        }
      }
      for (std::int32_t c = 1; c < ncomp; ++c)
        if (vote[c] <= 0) removed_[c] = 1;
    }
    for (std::size_t i = 0; i < in_.holes.size(); ++i) {
      const TriId t = tri_.locate(in_.holes[i], tri_.vtri[4 < tri_.num_verts() ? 4 : 0]);
      if (t == kNone || comp[t] == 0) {
        res_.status.warnings.push_back("hole " + std::to_string(i) + " at " + fmt_pt(in_.holes[i]) +
                                       " lies outside the domain and was ignored");
        continue;
      }
      removed_[comp[t]] = 1;
      last_hole_ = static_cast<std::int32_t>(i);
    }
    for (std::size_t i = 0; i < in_.regions.size(); ++i) {
      const TriId t = tri_.locate(in_.regions[i].seed, tri_.vtri[4 < tri_.num_verts() ? 4 : 0]);
      if (t == kNone || removed_[comp[t]]) {
        res_.status.warnings.push_back("region " + std::to_string(i) + " seed " +
                                       fmt_pt(in_.regions[i].seed) +
                                       " lies outside the domain and was ignored");
        continue;
      }
      attr_[comp[t]] = in_.regions[i].attribute;
    }
    bool any = false;
    for (std::int32_t c = 1; c < ncomp; ++c) any |= !removed_[c];
    if (!any) {
      if (!had_domain)
        return fail(StatusCode::OpenBoundary,
                    "the segments enclose no region: the boundary is open (every triangle is "
                    "connected to the outside)");
      // Removed by the orientation vote alone (no hole did it): the loops run the
      // wrong way round, or cross themselves so that no region is on their left.
      if (last_hole_ < 0)
        return fail(
            StatusCode::OpenBoundary,
            "no region lies to the left of its boundary segments (domain_from_orientation): "
            "the loops are clockwise or cross themselves");
      return fail(StatusCode::OpenBoundary,
                  "hole " + std::to_string(last_hole_) + " at " + fmt_pt(in_.holes[last_hole_]) +
                      " removes the whole domain: the boundary around it is open",
                  {last_hole_});
    }
    return true;
  }
  bool in_domain(TriId t) const { return !tri_.dead(t) && !removed_[tri_.tag[t]]; }

  // ---------------------------------------------------------------- 6. field points
  double edge_length(VertId a, VertId b) const {
    // eq. 7.10 with the length of AB varying geometrically between its values in the
    // metrics of A and B (exact for a geometric size progression; the log-mean).
    const Vec2 d{tri_.pts[b].x - tri_.pts[a].x, tri_.pts[b].y - tri_.pts[a].y};
    const double la = detail::length(vm_[a], d), lb = detail::length(vm_[b], d);
    const double r = lb / la;
    if (std::abs(r - 1) < 1e-3) return 0.5 * (la + lb);
    return (lb - la) / std::log(r);
  }

  // Field points of a uniform field on the equilateral lattice of side h: in a constant
  // metric the unit mesh whose every edge has length one (§7.5.2) is that lattice, and
  // all its triangles are optimal. Lattice points closer than kFilterDist to an existing
  // vertex (the boundary) are dropped by the kernel's filter; the band between the
  // boundary and the lattice is then filled by saturation waves and repaired by the
  // optimization. Rows are inserted in serpentine order, each point walking from the
  // previous one.
  void lattice_points(bool aniso) {
    double xmin = 1e300, ymin = 1e300, xmax = -1e300, ymax = -1e300, area2 = 0;
    const TriId nt = tri_.num_tris();
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      {
        const Vec2 a = tri_.pts[tri_.tv[3 * t]], b = tri_.pts[tri_.tv[3 * t + 1]],
                   c = tri_.pts[tri_.tv[3 * t + 2]];
        area2 += (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
      }
      for (int i = 0; i < 3; ++i) {
        const Vec2 p = tri_.pts[tri_.tv[3 * t + i]];
        xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x), ymin = std::min(ymin, p.y),
        ymax = std::max(ymax, p.y);
      }
    }
    if (!(xmax > xmin) || !(ymax > ymin)) return;
    const double h = h_uniform_, dy = 0.8660254037844386 * h;
    const auto nx = static_cast<std::int64_t>((xmax - xmin) / h) + 2,
               ny = static_cast<std::int64_t>((ymax - ymin) / dy) + 2;
    // A domain filling little of its bounding box (a thin diagonal strip) would make the
    // scan mostly point location outside it: saturation alone does that case.
    if (nx * ny > opt_.max_vertices ||
        static_cast<double>(nx * ny) * h * dy > 8 * (0.5 * area2) + 64 * h * h)
      return;
    {
      // Room for the points to come (about the area over a lattice cell), so that the
      // arrays do not grow by reallocation while they are inserted.
      const auto nv = static_cast<std::size_t>(tri_.num_verts()) +
                      static_cast<std::size_t>(0.55 * area2 / (h * dy)) + 1024;
      // Huge pages where the kernel allows them (huge_pages.h: fewer TLB misses and page faults).
      detail::reserve_huge(tri_.pts, nv), detail::reserve_huge(tri_.vtri, nv);
      detail::reserve_huge(tri_.tv, 6 * nv), detail::reserve_huge(tri_.opp, 6 * nv);
      detail::reserve_huge(tri_.seg, 6 * nv), detail::reserve_huge(tri_.tag, 2 * nv);
      vm_.reserve(nv), rs_.reserve(nv), fixed_.reserve(nv), vmark_.reserve(nv);
    }
    InsertParams prm;
    prm.m = m_uniform_;
    prm.use_metric = aniso;
    prm.min_dist = kFilterDist;
    TriId hint = tri_.vtri[tri_.num_verts() - 1];
    std::int64_t inserted = 0;
    auto try_insert = [&](Vec2 p, TriId from) {
      double o[3];
      const TriId t = tri_.locate(p, from, o);
      if (t == kNone) return false;
      hint = t;
      if (!in_domain(t)) return false;
      const auto r = tri_.insert_point_located(p, t, o, prm);
      if (r.status != InsertStatus::Inserted) return false;
      hint = tri_.vtri[r.v];
      vm_.push_back(m_uniform_);
      rs_.push_back(1.0);
      fixed_.push_back(0);
      vmark_.push_back(0);
      ++inserted;
      return true;
    };
    // First the layer along the boundary (§7.4.3, the optimal point of each boundary
    // edge: the apex of the equilateral triangle on it, inside), and before it one
    // point on the bisector of every corner of 90-150 degrees (two triangles of half
    // the angle there; the edges' apexes near it are then filtered out): the boundary
    // vertices get the valence of their angle (round(theta / 60deg)) and the lattice's
    // misfit is pushed off the fixed boundary to where every vertex can move.
    {
      const VertId nv = tri_.num_verts();
      std::vector<VertId> nxt(nv, kNone), prv(nv, kNone);
      std::vector<char> multi(nv, 0);
      for (TriId t = 0; t < nt; ++t) {
        if (!in_domain(t)) continue;
        for (int i = 0; i < 3; ++i) {
          if (tri_.seg[3 * t + i] == kNone) continue;
          const VertId a = tri_.tv[3 * t + detail::next3(i)], b = tri_.tv[3 * t + detail::prev3(i)];
          if (nxt[a] != kNone) multi[a] = 1;
          if (prv[b] != kNone) multi[b] = 1;
          nxt[a] = b;
          prv[b] = a;
        }
      }
      const auto& P = tri_.pts;
      for (VertId v = 4; v < nv; ++v) {
        if (multi[v] || nxt[v] == kNone || prv[v] == kNone) continue;
        const Vec2 pv = P[v], pn = P[nxt[v]], pp = P[prv[v]];
        const double ux = pn.x - pv.x, uy = pn.y - pv.y, wx = pp.x - pv.x, wy = pp.y - pv.y;
        double th = std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);  // from u to w, CCW
        if (th < 0) th += 2 * 3.14159265358979323846;
        if (th < 1.5 || th > 2.6) continue;  // about 86-149 degrees
        const double lu = std::hypot(ux, uy), lw = std::hypot(wx, wy);
        const double bx = ux / lu + wx / lw, by = uy / lu + wy / lw, bl = std::hypot(bx, by);
        if (!(bl > 0)) continue;
        const double r = std::min(h, 0.5 * (lu + lw));
        try_insert({pv.x + r * bx / bl, pv.y + r * by / bl}, tri_.vtri[v]);
      }
      for (VertId a = 4; a < nv; ++a) {
        const VertId b = nxt[a];
        if (b == kNone || multi[a]) continue;
        const Vec2 pa = P[a], pb = P[b];
        // Left normal of a -> b (the domain side), scaled to the height of the equilateral.
        try_insert({0.5 * (pa.x + pb.x) - 0.8660254037844386 * (pb.y - pa.y),
                    0.5 * (pa.y + pb.y) + 0.8660254037844386 * (pb.x - pa.x)},
                   tri_.vtri[a]);
      }
    }
    // The lattice in the kernel's insertion order (BRIO rounds, Hilbert order inside each,
    // as the hull fast path): inserted row by row, every point's cavity held the fan of
    // long thin triangles joining the last row to the far boundary (19 triangles per
    // insertion on average at 5e5 points, against about 4 in this order). The set of
    // points kept does not depend on the order: lattice points are h apart, beyond the
    // filter distance, so only the boundary and its layer (inserted before) filter them.
    // Every point is moved by a deterministic pseudo-random offset of at most 1e-6 h in
    // x and in y: the exact lattice is as degenerate as a point set can be (whole rows on
    // one line, every rectangle and hexagon of lattice points on one circle), and while it
    // is built such quadruples meet in the cavity tests, which the floating-point filter
    // cannot decide (0.35 orientation and 0.2 incircle tests per point went to the exact
    // arithmetic). Offsets far above the rounding make the filter decide; the finished
    // lattice triangulation is the same (an equilateral lattice has no empty circle
    // through four points) and its shapes change by about 1e-6.
    auto jitter = [](std::uint64_t z) {
      z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
      z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
      z ^= z >> 31;
      return (static_cast<double>(z >> 11) * 0x1.0p-53 - 0.5) * 2e-6;
    };
    // Lattice point k = j nx + i. Made again from k when it is inserted rather than read
    // back from the array the order was computed on: in insertion order that read was a
    // cache miss per point, 6% of the whole uniform-field mesher's time at 1e6 triangles.
    auto lattice_point = [&](std::int64_t k) {
      const std::int64_t j = k / nx, i = k - j * nx;
      const auto u = static_cast<std::uint64_t>(k);
      return Vec2{xmin + (static_cast<double>(i) + ((j & 1) ? 0.5 : 0.0) + jitter(2 * u)) * h,
                  ymin + (static_cast<double>(j) + 0.5) * dy + jitter(2 * u + 1) * h};
    };
    std::vector<std::uint64_t> order;
    {
      std::vector<Vec2> lat(static_cast<std::size_t>(nx * ny));
      for (std::int64_t k = 0; k < nx * ny; ++k)
        lat[static_cast<std::size_t>(k)] = lattice_point(k);
      detail::brio_order(lat, order);
    }
    std::size_t since_check = 0;
    for (const std::uint64_t rec : order) {
      if (++since_check == 4096) {
        since_check = 0;
        if (over_time("refinement")) return;
      }
      try_insert(lattice_point(static_cast<std::int64_t>(rec & 0xFFFFFFFFu)), hint);
    }
    res_.stats.field_points_inserted += inserted;
    lattice_used_ = true;
  }

  void refine() {
    const std::size_t nv = tri_.pts.size();
    vm_.resize(nv);
    for (std::size_t v = 4; v < nv; ++v) vm_[v] = metric(tri_.pts[v].x, tri_.pts[v].y);
    vm_[0] = vm_[1] = vm_[2] = vm_[3] = m_uniform_;
    rs_.assign(nv, 1.0);
    const bool from_boundary = opt_.boundary_gradation > 1 && size_.kind != SizeSpec::Kind::Uniform;
    if (from_boundary) {
      // A boundary vertex whose constrained edges are shorter than unit in the field
      // gets that length as its size ratio: its metric is scaled by 1 / ratio^2.
      for (TriId t = 0; t < tri_.num_tris(); ++t) {
        if (!in_domain(t)) continue;
        for (int i = 0; i < 3; ++i) {
          const std::int32_t sg = tri_.seg[3 * t + i];
          if (sg == kNone || segs_[sg].marker < 0) continue;
          const VertId a = tri_.tv[3 * t + detail::next3(i)], b = tri_.tv[3 * t + detail::prev3(i)];
          const double l = edge_length(a, b);
          if (l < 1)
            rs_[a] = std::min(rs_[a], std::max(l, 1e-6)),
            rs_[b] = std::min(rs_[b], std::max(l, 1e-6));
        }
      }
      for (std::size_t v = 4; v < nv; ++v)
        if (rs_[v] < 1) vm_[v] = detail::scaled(vm_[v], 1.0 / (rs_[v] * rs_[v]));
    }
    const bool aniso = size_.kind == SizeSpec::Kind::Metric && opt_.anisotropic_kernel;
    struct Cand {
      Vec2 p;
      VertId hint;   // the edge's first vertex
      bool chained;  // follows the previous candidate on the same edge
      double r = 1;  // boundary size ratio (Options::boundary_gradation)
    };
    if (size_.kind == SizeSpec::Kind::Uniform) lattice_points(aniso);
    std::vector<Cand> cands;
    EdgeSampler es;
    // After the first wave only the triangles around the vertices the last wave inserted,
    // and their neighbours, are scanned, in triangle order as the full scan goes. Every
    // triangle made since the last scan has such a vertex; an edge older than that had
    // its points tried and rejected, and they stay rejected (vertices are only added: the
    // nearest vertex of a point, a cavity vertex, only comes closer; constrained edges
    // stay). Its candidates would be the same again: they depend on its ends (fixed, with
    // their metrics and boundary ratios), the field, and the two vertices opposite it
    // (the bound below), unchanged while its two triangles are. So the points inserted
    // are the same, in the same order, as with the full scan, but for a candidate that an
    // anisotropic cavity refused (not star-shaped: not monotone, a later wave could take
    // it) and the walk's random tie-breaks, which see fewer candidates; measured on
    // surface faces: the same counts and measures, a few coordinates differing in their
    // last bits (the bracket, gmsh_problem_sphere), byte-identical elsewhere. Uniform field: the
    // full scan took a third of the field-point time after the lattice (three passes over a million
    // triangles to insert a few thousand points). Varying field under a boundary gradation (every
    // surface face), where the analysed-edge set does not apply: the later waves sampled every edge
    // again, 40x the first wave's sample_edge calls on kicad_tantalum_c's two large faces, for a
    // few thousand insertions.
    std::vector<VertId> born;
    std::vector<TriId> scan;
    const bool use_analysed = !from_boundary && size_.kind != SizeSpec::Kind::Uniform;
    auto edge_key = [](VertId a, VertId b) {
      return static_cast<std::uint64_t>(std::min(a, b)) << 32 |
             static_cast<std::uint32_t>(std::max(a, b));
    };
    for (int wave = 0; wave < kMaxWaves && !field_error_; ++wave) {
      cands.clear();
      const TriId nt = tri_.num_tris();
      const bool subset = wave > 0;
      if (subset) {
        scan.clear();
        if (tmark_.size() < static_cast<std::size_t>(nt)) tmark_.resize(nt, 0);
        ++tepoch_;
        auto take = [&](TriId t) {
          if (tmark_[t] == tepoch_) return;
          tmark_[t] = tepoch_;
          scan.push_back(t);
        };
        for (const VertId v : born)
          for_ball(v, [&](TriId t) {
            take(t);
            for (int i = 0; i < 3; ++i)
              if (tri_.opp[3 * t + i] != kNone) take(tri_.opp[3 * t + i] / 3);
          });
        std::sort(scan.begin(), scan.end());
      }
      born.clear();
      const TriId nscan = subset ? static_cast<TriId>(scan.size()) : nt;
      for (TriId st = 0; st < nscan; ++st) {
        const TriId t = subset ? scan[st] : st;
        // The vertices of the triangles a few steps ahead are fetched now: triangle slots
        // are reused by later insertions, so a triangle's vertices lie anywhere in the
        // vertex array, and these loads were nearly half of the uniform field's scan.
        if (st + 8 < nscan) {
          const TriId ta = subset ? scan[st + 8] : st + 8;
          for (int k = 0; k < 3; ++k) {
            const VertId w = tri_.tv[3 * ta + k];
            if (w >= 0) __builtin_prefetch(&tri_.pts[w]);
          }
          // And the analysed-edge slots of its edges: the set outgrows the cache, and its
          // lookups were the costliest line of the anisotropic scan.
          if (use_analysed)
            for (int k = 0; k < 3; ++k) {
              const VertId a = tri_.tv[3 * ta + k], b = tri_.tv[3 * ta + (k + 1) % 3];
              analysed_.prefetch(edge_key(a, b));
            }
        }
        if (!in_domain(t)) continue;
        for (int i = 0; i < 3; ++i) {
          if (tri_.seg[3 * t + i] != kNone) continue;
          const std::int32_t g = tri_.opp[3 * t + i];
          if (g / 3 < t) continue;  // each edge once (both sides are in the domain)
          const VertId a = tri_.tv[3 * t + detail::next3(i)], b = tri_.tv[3 * t + detail::prev3(i)];
          const Vec2 pa = tri_.pts[a], pb = tri_.pts[b];
          const Vec2 d{pb.x - pa.x, pb.y - pa.y};
          // §7.5.2: points at unit spacing in the metric along the edge. A uniform field
          // needs no sampling; any other is sampled along the edge (eq. 7.10).
          if (size_.kind == SizeSpec::Kind::Uniform) {
            // Squared length first: after the lattice nearly every edge is short, and
            // a scan is one pass over all the triangles per wave.
            const Metric2& mu = m_uniform_;
            if (!(mu.m11 * d.x * d.x + 2 * mu.m12 * d.x * d.y + mu.m22 * d.y * d.y > 1.99))
              continue;
            const double L = detail::length(m_uniform_, d);
            if (!(L > kSqrt2)) continue;
            const int n = std::max(2, static_cast<int>(std::lround(L)));
            for (int k = 1; k < n; ++k)
              cands.push_back({{pa.x + d.x * k / n, pa.y + d.y * k / n}, a, k > 1});
            continue;
          }
          if (!(edge_length(a, b) > 0.5)) continue;  // short even with a bump in between
          if (!from_boundary) {
            // An edge analysed in an earlier wave gives the same candidates again (its
            // ends never move during refinement and the field is fixed), and those were
            // inserted or rejected by the filter, which only gets stricter as vertices
            // are added: it is not analysed again. Without this every wave re-sampled
            // the whole mesh (ring:3e-4,0.02: 10 k edges and 110 k field evaluations per
            // wave in waves 3-7, for a few dozen insertions).
            if (!analysed_.insert(edge_key(a, b))) continue;
          }
          const double ra = rs_[a], rb = rs_[b];
          if (!(ra < 1) && !(rb < 1)) {
            // Saturated edges are most of the mesh after the first waves: three samples
            // (the ends and the midpoint, Simpson's rule) settle them with one field
            // evaluation instead of the 3-7 of the full sampling. Only an edge short at
            // all three, with a length estimate well under sqrt2, is skipped.
            const double la = detail::length(vm_[a], d), lb = detail::length(vm_[b], d);
            if (la < kSkipSample && lb < kSkipSample) {
              const double lm = detail::length(metric(pa.x + 0.5 * d.x, pa.y + 0.5 * d.y), d);
              if (lm < kSkipSample && (la + 4 * lm + lb) / 6 < kSkipSample) continue;
            }
          }
          const double L = sample_edge(pa, pb, vm_[a], vm_[b], es, ra, rb);
          if (!(L > kSqrt2)) continue;
          const int n = std::max(2, static_cast<int>(std::lround(L)));
          bool first = true;
          // Unscaled metric length of the edge, for the gradation bound of ratio_at.
          const double lu =
              (ra < 1 || rb < 1)
                  ? 0.5 * (detail::length(vm_[a], d) * ra + detail::length(vm_[b], d) * rb)
                  : 0;
          // The vertices opposite the edge bound the ratio too: a long edge leaving a
          // finely split boundary at a shallow angle passes its neighbours closer than
          // its own end, and a point placed with the ratio of the ends alone is then
          // "too close" in its own metric -- rejected wave after wave, which left fans of
          // slivers between a fine and a coarse boundary.
          const VertId oc = tri_.tv[3 * t + i], od = g != kNone ? tri_.tv[g] : kNone;
          auto bound = [&](VertId c, Vec2 p) {
            if (!from_boundary || c == kNone || c < 4 || !(rs_[c] < 1)) return 1.0;
            const Vec2 dc{p.x - tri_.pts[c].x, p.y - tri_.pts[c].y};
            return rs_[c] + (opt_.boundary_gradation - 1) * detail::length(vm_[c], dc) * rs_[c];
          };
          split_params(es, n, [&](double tt) {
            const Vec2 p{pa.x + tt * d.x, pa.y + tt * d.y};
            double r = (ra < 1 || rb < 1) ? ratio_at(ra, rb, tt, lu) : 1.0;
            r = std::max(std::min({r, bound(oc, p), bound(od, p)}), 1e-6);
            cands.push_back({p, a, !first, r});
            first = false;
          });
        }
      }
      if (cands.empty()) break;
      if (over_time("refinement")) return;
      std::int64_t inserted = 0;
      VertId last_v = kNone;
      std::size_t since_check = 0;
      for (const Cand& c : cands) {
        if (++since_check == 4096) {
          since_check = 0;
          if (over_time("refinement")) return;
        }
        if (static_cast<std::int64_t>(tri_.pts.size()) >= opt_.max_vertices) {
          res_.status.code = StatusCode::Incomplete;
          res_.status.message =
              "refinement stopped at max_vertices = " + std::to_string(opt_.max_vertices);
          return;
        }
        InsertParams prm;
        prm.m = metric(c.p.x, c.p.y);
        if (c.r < 1) prm.m = detail::scaled(prm.m, 1.0 / (c.r * c.r));
        prm.use_metric = aniso;
        prm.min_dist = kFilterDist;
        if (from_boundary) prm.vertex_metrics = vm_.data(), prm.num_vertex_metrics = vm_.size();
        // Walk from the previous candidate of the same edge when there is one: on the
        // long edges of the first waves the edge's end can be far away.
        const TriId hint = c.chained && last_v != kNone ? tri_.vtri[last_v] : tri_.vtri[c.hint];
        // The field-point filter first on the vertices of the triangle holding the point
        // (they are cavity vertices, which the kernel's filter checks): most candidates
        // are rejected there without building a cavity.
        double o[3];
        const TriId t0 = tri_.locate(c.p, hint, o);
        if (t0 != kNone && too_close_to_corner(t0, c.p, prm)) {
          last_v = tri_.tv[3 * t0];  // the next candidate of the edge walks from here
          ++res_.stats.field_points_rejected;
          continue;
        }
        const auto r = t0 != kNone ? tri_.insert_point_located(c.p, t0, o, prm)
                                   : tri_.insert_point(c.p, hint, prm);
        last_v = r.v;
        if (r.status == InsertStatus::Inserted) {
          born.push_back(r.v);
          vm_.push_back(prm.m);
          rs_.push_back(c.r);
          fixed_.push_back(0);
          vmark_.push_back(0);
          ++inserted;
        } else {
          ++res_.stats.field_points_rejected;
        }
      }
      res_.stats.field_points_inserted += inserted;
      res_.stats.saturation_waves = wave + 1;
      if (inserted == 0) break;
    }
  }

  // The kernel's field-point filter (InsertParams::min_dist, with vertex_metrics) applied
  // to the three vertices of triangle t.
  bool too_close_to_corner(TriId t, Vec2 p, const InsertParams& prm) const {
    for (int i = 0; i < 3; ++i) {
      const VertId a = tri_.tv[3 * t + i];
      if (detail::filter_too_close(prm, a, tri_.pts[a], p)) return true;
    }
    return false;
  }

  // ---------------------------------------------------------------- 7. optimization
  // §7.3.6 / §7.5.2 optimizations: topological (edge swaps judged by the metric quality)
  // then metric (vertex relocation toward the ideal point of its ball), boundary fixed.
  double quality_in(const Metric2& m, Vec2 a, Vec2 b, Vec2 c) const {
    if (iso_uniform_) return q_inv(a, b, c);
    const detail::MetricFrame f(m);
    return q_inv(f(a), f(b), f(c));
  }

  std::int64_t swap_pass() {
    if (multi_frame_) return swap_pass_varying();
    std::int64_t swaps = 0;
    const TriId nt = tri_.num_tris();
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i;
        if (tri_.seg[h] != kNone) continue;
        const std::int32_t g = tri_.opp[h];
        if (g == kNone) continue;
        const VertId c = tri_.tv[h], a = tri_.tv[3 * t + detail::next3(i)],
                     b = tri_.tv[3 * t + detail::prev3(i)];
        const VertId d = tri_.tv[g];
        const auto& P = tri_.pts;
        const Metric2 m = iso_uniform_ ? Metric2{} : quad_metric(a, b, c, d);
        const double before =
            std::min(quality_in(m, P[c], P[a], P[b]), quality_in(m, P[d], P[b], P[a]));
        const double after =
            std::min(quality_in(m, P[c], P[a], P[d]), quality_in(m, P[d], P[b], P[c]));
        // Swap only for a clear gain (the factor keeps cocircular quads from flipping back).
        if (after > before * (1 + 1e-6) && tri_.flippable(h)) {
          tri_.flip(h);
          ++swaps;
          break;  // t changed; its other edges are seen in a later pass
        }
      }
    }
    return swaps;
  }
  // swap_pass for a varying field: each triangle judged in the mean of its vertex metrics
  // (tri_q, as the measure), computed once per pass; only edges whose worse triangle has
  // Q_K above 1/kSwapSkipVarying are tried (a swap among better triangles changes nothing
  // the repair and the measure look at, and most edges of a unit mesh are such).
  std::int64_t swap_pass_varying() {
    std::int64_t swaps = 0;
    const TriId nt = tri_.num_tris();
    tq_.resize(nt);
    for (TriId t = 0; t < nt; ++t) tq_[t] = in_domain(t) ? tri_q(t) : 0.0;
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t) || !(tq_[t] < kSwapSkipVarying)) continue;
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i;
        if (tri_.seg[h] != kNone) continue;
        const std::int32_t g = tri_.opp[h];
        if (g == kNone || !in_domain(g / 3)) continue;
        const VertId c = tri_.tv[h], a = tri_.tv[3 * t + detail::next3(i)],
                     b = tri_.tv[3 * t + detail::prev3(i)];
        const VertId d = tri_.tv[g];
        const double before = std::min(tq_[t], tq_[g / 3]);
        const double q1 = tri_q(c, a, d), q2 = tri_q(d, b, c);
        if (std::min(q1, q2) > before * (1 + 1e-6) && tri_.flippable(h)) {
          tri_.flip(h);  // t becomes (c, a, d), g / 3 becomes (d, b, c)
          tq_[t] = q1;
          tq_[g / 3] = q2;
          ++swaps;
          break;
        }
      }
    }
    return swaps;
  }
  Metric2 quad_metric(VertId a, VertId b, VertId c, VertId d) const {
    const Metric2 m1 = detail::mean3(vm_[a], vm_[b], vm_[c]);
    return detail::mix(m1, vm_[d], 0.25);
  }

  std::int64_t smooth_pass() {
    std::int64_t moved = 0;
    std::vector<VertId> ring;  // the ball's opposite edges (ring[k], ring[k+1])
    const VertId nv = tri_.num_verts();
    for (VertId v = 4; v < nv; ++v) {
      if (fixed_[v] || !gather_ring(v, ring)) continue;
      const std::size_t n = ring.size();
      const auto& P = tri_.pts;
      const Vec2 pv = P[v];
      const Metric2 m = vm_[v];
      const detail::MetricFrame f(m);
      auto tri_at = [&](std::size_t k, Vec2 p, double& q) {
        // Turning through the edge (prev, v) visits the ring counter-clockwise, so the
        // ball triangles are (p, ring[k], ring[k+1]).
        const Vec2 a = P[ring[k]], b = P[ring[(k + 1) % n]];
        q = iso_uniform_ ? q_inv(p, a, b) : q_inv(f(p), f(a), f(b));
        return pred::orient2d(&p.x, &a.x, &b.x) > 0;
      };
      double qmin_old = 1e300;
      for (std::size_t k = 0; k < n; ++k) {
        double q;
        tri_at(k, pv, q);
        qmin_old = std::min(qmin_old, q);
      }
      if (qmin_old > kSmoothSkip) continue;  // already near-equilateral everywhere
      // Ideal point of each ball triangle: the apex of the equilateral (in the metric)
      // triangle on the opposite edge (§7.4.3 "optimal point"). Over a closed ring their
      // mean is the centroid of the ring (the rotated edge vectors sum to zero), i.e.
      // Laplacian smoothing in the metric frame of v. (Area-weighted circumcentres, the
      // ODT rule, measured worse here: Q_M 1.59 against 1.50 on the square with a hole.)
      Vec2 target{0, 0};
      const Vec2 fv = iso_uniform_ ? pv : f(pv);
      for (std::size_t k = 0; k < n; ++k) {
        const Vec2 a0 = P[ring[k]], b0 = P[ring[(k + 1) % n]];
        const Vec2 a = iso_uniform_ ? a0 : f(a0), b = iso_uniform_ ? b0 : f(b0);
        const Vec2 mid{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
        const Vec2 e{b.x - a.x, b.y - a.y};
        // left of a->b (toward the vertex side): rotate +90 degrees
        target.x += mid.x - 0.8660254037844386 * e.y;
        target.y += mid.y + 0.8660254037844386 * e.x;
      }
      target.x /= static_cast<double>(n);
      target.y /= static_cast<double>(n);
      for (const double w : {1.0, 0.5, 0.25}) {
        const Vec2 fq{fv.x + w * (target.x - fv.x), fv.y + w * (target.y - fv.y)};
        const Vec2 q = iso_uniform_ ? fq : f.inv(fq);
        double qmin_new = 1e300;
        bool valid = true;
        for (std::size_t k = 0; k < n && valid; ++k) {
          double qq;
          valid = tri_at(k, q, qq);
          qmin_new = std::min(qmin_new, qq);
        }
        if (valid && qmin_new > qmin_old * kSmoothAccept) {
          tri_.pts[v] = q;
          if (!iso_uniform_) {
            vm_[v] = metric(q.x, q.y);
            if (static_cast<std::size_t>(v) < rs_.size() && rs_[v] < 1)
              vm_[v] = detail::scaled(vm_[v], 1.0 / (rs_[v] * rs_[v]));
          }
          ++moved;
          break;
        }
      }
    }
    return moved;
  }

  // The ring of vertex v (the ball's opposite edges (ring[k], ring[k+1]), counter-
  // clockwise); false when v is on the box border or its ball is not closed.
  bool gather_ring(VertId v, std::vector<VertId>& ring) const {
    ring.clear();
    const TriId t0 = tri_.vtri[v];
    if (t0 == kNone || !in_domain(t0)) return false;
    TriId t = t0;
    do {
      int k = 0;
      while (tri_.tv[3 * t + k] != v) ++k;
      ring.push_back(tri_.tv[3 * t + detail::next3(k)]);
      const std::int32_t h = tri_.opp[3 * t + detail::next3(k)];  // edge (prev, v)
      if (h == kNone) return false;
      t = h / 3;
    } while (t != t0 && ring.size() < 64);
    return t == t0;
  }

  // Optimization-based relocation (§7.3.6 "metric techniques", max-min form): moves a
  // vertex to raise the worst quality 1/Q_K of its ball, by steepest ascent of the worst
  // triangles (the direction of least norm in the convex hull of the gradients of the
  // nearly worst ones, so that no active triangle gets worse to first order) with a
  // backtracking line search; every accepted step strictly raises the ball's minimum and
  // keeps all ball triangles counter-clockwise (valid(p), exact orientation). Laplacian
  // smoothing improves the mean but stalls where one triangle trades against another;
  // this is what brings the worst elements of a uniform mesh under Q = 1.2.
  // The ball is the closed ring fr_ (frame coordinates: Euclidean for a uniform field,
  // the metric frame of the vertex otherwise); p is moved in place; returns the ball's
  // minimum 1/Q_K at p (-1 if a triangle is inverted at the start).
  template <class Valid>
  double maxmin_core(Vec2& p, double qstop, int iters, Valid&& valid) {
    const std::size_t n = fr_.size();
    qk_.resize(n);
    gk_.resize(n);
    // q = area2 / (alpha * per * hmax) of (p, a, b) and its gradient in p.
    auto eval = [&](Vec2 pp, bool grad) {
      work_ += static_cast<std::int64_t>(n);
      double qmin = 1e300;
      for (std::size_t k = 0; k < n; ++k) {
        Vec2 a, b, P;
        ball_tri(k, pp, a, b, P);
        const double ux = a.x - P.x, uy = a.y - P.y, wx = b.x - P.x, wy = b.y - P.y;
        const double ex = b.x - a.x, ey = b.y - a.y;
        const double area2 = ux * wy - uy * wx;
        if (!(area2 > 0)) return -1.0;
        const double la = std::sqrt(ux * ux + uy * uy), lb = std::sqrt(wx * wx + wy * wy),
                     le = std::sqrt(ex * ex + ey * ey);
        const double per = la + lb + le, hm = std::max({la, lb, le});
        const double q = area2 / (0.28867513459481287 * per * hm);
        qk_[k] = q;
        qmin = std::min(qmin, q);
        if (grad) {
          // d area2 = (-ey, ex); d per = -u/la - w/lb; d hmax = -u/la or -w/lb or 0.
          double gx = -ey / area2 - (-ux / la - wx / lb) / per;
          double gy = ex / area2 - (-uy / la - wy / lb) / per;
          if (hm == la)
            gx += ux / (la * hm), gy += uy / (la * hm);
          else if (hm == lb)
            gx += wx / (lb * hm), gy += wy / (lb * hm);
          gk_[k] = ball_grad(k, {q * gx, q * gy});
        }
      }
      return qmin;
    };
    double qmin = eval(p, true);
    if (!(qmin > 0)) return qmin;
    for (int it = 0; it < iters && qmin < qstop; ++it) {
      // Active set: triangles within a small margin of the minimum.
      const double tol = 0.02 * qmin;
      Vec2 d{0, 0};
      {
        std::size_t act[8];
        int na = 0;
        for (std::size_t k = 0; k < n && na < 8; ++k)
          if (qk_[k] <= qmin + tol) act[na++] = k;
        // Least-norm point of the convex hull of the active gradients: the best of the
        // single gradients and the pairwise segment projections that are ascent
        // directions for every active triangle.
        double best = -1;
        auto consider = [&](Vec2 c) {
          const double nn = c.x * c.x + c.y * c.y;
          if (!(nn > 0)) return;
          for (int j = 0; j < na; ++j)
            if (gk_[act[j]].x * c.x + gk_[act[j]].y * c.y < 0.999 * nn) return;
          if (best < 0 || nn < best) best = nn, d = c;
        };
        for (int i = 0; i < na; ++i) {
          consider(gk_[act[i]]);
          for (int j = i + 1; j < na; ++j) {
            const Vec2 g1 = gk_[act[i]], g2 = gk_[act[j]];
            const double dx = g2.x - g1.x, dy = g2.y - g1.y, dd = dx * dx + dy * dy;
            if (!(dd > 0)) continue;
            const double t = std::clamp(-(g1.x * dx + g1.y * dy) / dd, 0.0, 1.0);
            consider({g1.x + t * dx, g1.y + t * dy});
          }
        }
        if (best < 0) break;  // no common ascent direction: a local max-min optimum
      }
      const double dn2 = d.x * d.x + d.y * d.y;
      // Linear prediction of the step where a non-active triangle becomes the worst,
      // capped at a tenth of the local edge length.
      double step = 1e300;
      for (std::size_t k = 0; k < n; ++k) {
        const double slope = gk_[k].x * d.x + gk_[k].y * d.y;
        if (slope < dn2 && qk_[k] > qmin + tol)
          step = std::min(step, (qk_[k] - qmin) / (dn2 - slope));
      }
      const double ex = fr_[0].x - p.x, ey = fr_[0].y - p.y;
      step = std::min(step, 0.1 * std::sqrt((ex * ex + ey * ey) / dn2));
      bool took = false;
      for (int ls = 0; ls < 6; ++ls, step *= 0.5) {
        const Vec2 np{p.x + step * d.x, p.y + step * d.y};
        const double nq = eval(np, false);
        if (nq > qmin * (1 + 1e-9) && valid(np)) {
          p = np;
          took = true;
          break;
        }
      }
      if (!took) break;
      qmin = eval(p, true);
    }
    return qmin;
  }
  // Relocation by descent of F = sum over the ball of Q_K^p (p = kPnorm): smooth where
  // the max-min is not, so that a sweep over a neighbourhood unpins vertices whose worst
  // triangles hold each other at a kink of the max-min (measured at the corners of the
  // square: Q_M stayed at 1.2005 after max-min sweeps). Same frame and validity as
  // maxmin_core; returns true when p moved.
  template <class Valid>
  bool pnorm_core(Vec2& p, Valid&& valid) {
    constexpr double kPnorm = 8;  // the power in term below
    const std::size_t n = fr_.size();
    // F and its gradient, with Q_K scaled by s (the ball's initial worst) to stay finite.
    double s = 0;
    auto eval = [&](Vec2 pp, bool grad, Vec2& g) {
      work_ += static_cast<std::int64_t>(n);
      double F = 0;
      g = {0, 0};
      for (std::size_t k = 0; k < n; ++k) {
        Vec2 a, b, P;
        ball_tri(k, pp, a, b, P);
        const double ux = a.x - P.x, uy = a.y - P.y, wx = b.x - P.x, wy = b.y - P.y;
        const double ex = b.x - a.x, ey = b.y - a.y;
        const double area2 = ux * wy - uy * wx;
        if (!(area2 > 0)) return 1e300;
        const double la = std::sqrt(ux * ux + uy * uy), lb = std::sqrt(wx * wx + wy * wy),
                     le = std::sqrt(ex * ex + ey * ey);
        const double per = la + lb + le, hm = std::max({la, lb, le});
        const double Q = 0.28867513459481287 * per * hm / area2;
        if (s == 0) continue;
        const double r2 = (Q / s) * (Q / s), r4 = r2 * r2, term = r4 * r4;  // (Q / s)^8
        F += term;
        if (grad) {
          // d log Q = d per / per + d hmax / hmax - d area2 / area2.
          double gx = (-ux / la - wx / lb) / per + ey / area2;
          double gy = (-uy / la - wy / lb) / per - ex / area2;
          if (hm == la)
            gx -= ux / (la * hm), gy -= uy / (la * hm);
          else if (hm == lb)
            gx -= wx / (lb * hm), gy -= wy / (lb * hm);
          const Vec2 gp = ball_grad(k, {gx, gy});
          g.x += kPnorm * term * gp.x;
          g.y += kPnorm * term * gp.y;
        }
      }
      return F;
    };
    Vec2 g;
    // First call finds the scale: the worst Q of the ball.
    {
      double worst = 0;
      for (std::size_t k = 0; k < n; ++k) {
        Vec2 a, b, P;
        ball_tri(k, p, a, b, P);
        const double q = q_inv(P, a, b);
        if (!(q > 0)) return false;
        worst = std::max(worst, 1 / q);
      }
      s = worst;
    }
    double F = eval(p, true, g);
    bool moved = false;
    for (int it = 0; it < 4; ++it) {
      const double gn = std::sqrt(g.x * g.x + g.y * g.y);
      if (!(gn > 0)) break;
      const double ex = fr_[0].x - p.x, ey = fr_[0].y - p.y;
      double step = 0.05 * std::sqrt(ex * ex + ey * ey) / gn;
      bool took = false;
      for (int ls = 0; ls < 8; ++ls, step *= 0.5) {
        const Vec2 np{p.x - step * g.x, p.y - step * g.y};
        Vec2 ng;
        const double nF = eval(np, false, ng);
        if (nF < F && valid(np)) {
          p = np;
          took = true;
          break;
        }
      }
      if (!took) break;
      moved = true;
      F = eval(p, true, g);
    }
    return moved;
  }
  bool pnorm_relocate(VertId v, std::vector<VertId>& ring) {
    if (fixed_[v] || !gather_ring(v, ring)) return false;
    const detail::MetricFrame f = frame_of(v);
    load_ring(f, ring, vm_[v]);
    Vec2 p = iso_uniform_ ? tri_.pts[v] : f(tri_.pts[v]);
    if (!pnorm_core(p, [&](Vec2 fp) { return ball_valid(f, fp, ring); })) return false;
    set_position(v, iso_uniform_ ? p : f.inv(p));
    return true;
  }

  // Frame of vertex v's metric (identity for a uniform field) and the exact validity of
  // a ball (p, ring[k], ring[k+1]) with p given in that frame.
  detail::MetricFrame frame_of(VertId v) const {
    return detail::MetricFrame(iso_uniform_ ? Metric2{} : vm_[v]);
  }
  bool ball_valid(const detail::MetricFrame& f, Vec2 fp, const std::vector<VertId>& ring) const {
    const Vec2 q = iso_uniform_ ? fp : f.inv(fp);
    const auto& P = tri_.pts;
    const std::size_t n = ring.size();
    for (std::size_t k = 0; k < n; ++k)
      if (!(pred::orient2d(&q.x, &P[ring[k]].x, &P[ring[k + 1 == n ? 0 : k + 1]].x) > 0))
        return false;
    return true;
  }
  // mv: the metric of the moving vertex, for the per-triangle frames of a varying field.
  void load_ring(const detail::MetricFrame& f, const std::vector<VertId>& ring, const Metric2& mv) {
    const std::size_t n = ring.size();
    fr_.resize(n);
    for (std::size_t k = 0; k < n; ++k)
      fr_[k] = iso_uniform_ ? tri_.pts[ring[k]] : f(tri_.pts[ring[k]]);
    if (!multi_frame_) return;
    // Each ball triangle in its own frame, that of the mean of its vertex metrics (as
    // tri_q and the measure judge it): one frame for the whole ball misjudges a metric
    // that turns or grades across it (ring: 2.3 degrees and 4% in size per element at
    // the layer). The map from the ball's frame f to triangle k's frame R_k is R_k f^-1,
    // upper triangular like both.
    bt_.resize(n);
    const auto& P = tri_.pts;
    for (std::size_t k = 0; k < n; ++k) {
      const VertId ra = ring[k], rb = ring[k + 1 == n ? 0 : k + 1];
      const detail::MetricFrame r(detail::mean3(mv, vm_[ra], vm_[rb]));
      BallTri& t = bt_[k];
      t.a11 = r.l11 / f.l11;
      t.a12 = r.l12 / f.l22 - r.l11 * f.l12 / (f.l11 * f.l22);
      t.a22 = r.l22 / f.l22;
      t.a = r(P[ra]);
      t.b = r(P[rb]);
    }
  }
  // Triangle k of the loaded ball with its free vertex at pp (ball frame): its three
  // corners in the frame the triangle is judged in.
  void ball_tri(std::size_t k, Vec2 pp, Vec2& a, Vec2& b, Vec2& p) const {
    if (multi_frame_) {
      const BallTri& t = bt_[k];
      a = t.a, b = t.b, p = {t.a11 * pp.x + t.a12 * pp.y, t.a22 * pp.y};
      return;
    }
    const std::size_t n = fr_.size();
    a = fr_[k], b = fr_[k + 1 == n ? 0 : k + 1], p = pp;
  }
  // A gradient in triangle k's frame, as a gradient in the ball frame (A^T g).
  Vec2 ball_grad(std::size_t k, Vec2 g) const {
    if (!multi_frame_) return g;
    const BallTri& t = bt_[k];
    return {t.a11 * g.x, t.a12 * g.x + t.a22 * g.y};
  }
  void set_position(VertId v, Vec2 q) {
    tri_.pts[v] = q;
    if (!iso_uniform_) {
      vm_[v] = metric(q.x, q.y);
      if (static_cast<std::size_t>(v) < rs_.size() && rs_[v] < 1)
        vm_[v] = detail::scaled(vm_[v], 1.0 / (rs_[v] * rs_[v]));
    }
  }

  bool maxmin_relocate(VertId v, std::vector<VertId>& ring, double qstop, int iters) {
    if (fixed_[v] || !gather_ring(v, ring)) return false;
    const detail::MetricFrame f = frame_of(v);
    load_ring(f, ring, vm_[v]);
    const Vec2 p0 = iso_uniform_ ? tri_.pts[v] : f(tri_.pts[v]);
    Vec2 p = p0;
    maxmin_core(p, qstop, iters, [&](Vec2 fp) { return ball_valid(f, fp, ring); });
    if (p.x == p0.x && p.y == p0.y) return false;
    set_position(v, iso_uniform_ ? p : f.inv(p));
    return true;
  }

  // ------------------------------------------------------------ targeted repair
  // The worst elements left by relocation and swaps sit where the point pattern is
  // strained (rows of the saturation too far apart or too close for their spacing) or
  // where the valence is wrong; no relocation fixes those. Each bad triangle is tried
  // with, in turn: max-min relocation of its vertices, an edge swap, the collapse of one
  // of its edges (§7.3.6 "remove edges by merging their endpoints") and the split of its
  // longest edge. A topological operation is taken only when the worst 1/Q_K of the
  // triangles it replaces strictly rises (the new vertex placed by maxmin_core first), so
  // the sorted quality vector rises with every change and the loop terminates.
  double tri_q(VertId a, VertId b, VertId c) const {
    const auto& P = tri_.pts;
    if (iso_uniform_) return q_inv(P[a], P[b], P[c]);
    const detail::MetricFrame f(detail::mean3(vm_[a], vm_[b], vm_[c]));
    return q_inv(f(P[a]), f(P[b]), f(P[c]));
  }
  double tri_q(TriId t) const {
    return tri_q(tri_.tv[3 * t], tri_.tv[3 * t + 1], tri_.tv[3 * t + 2]);
  }
  double ball_min(VertId v, const std::vector<VertId>& ring) const {
    double m = 1e300;
    for (std::size_t k = 0; k < ring.size(); ++k)
      m = std::min(m, tri_q(v, ring[k], ring[k + 1 == ring.size() ? 0 : k + 1]));
    return m;
  }
  bool has_constrained_edge(VertId v) const {
    const TriId t0 = tri_.vtri[v];
    TriId t = t0;
    int guard = 0;
    do {
      int k = 0;
      while (tri_.tv[3 * t + k] != v) ++k;
      if (tri_.seg[3 * t + detail::next3(k)] != kNone ||
          tri_.seg[3 * t + detail::prev3(k)] != kNone)
        return true;
      const std::int32_t h = tri_.opp[3 * t + detail::next3(k)];
      if (h == kNone || ++guard > 256) return true;
      t = h / 3;
    } while (t != t0);
    return false;
  }

  bool try_swap(TriId t) {
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (tri_.seg[h] != kNone || tri_.opp[h] == kNone) continue;
      const std::int32_t g = tri_.opp[h];
      const VertId c = tri_.tv[h], a = tri_.tv[3 * t + detail::next3(i)],
                   b = tri_.tv[3 * t + detail::prev3(i)];
      const VertId d = tri_.tv[g];
      const double before = std::min(tri_q(c, a, b), tri_q(d, b, a));
      const double after = std::min(tri_q(c, a, d), tri_q(d, b, c));
      if (after > before * (1 + 1e-9) && tri_.flippable(h)) {
        tri_.flip(h);
        return true;
      }
    }
    return false;
  }

  // Collapse of an edge of t: v (free, no constrained edge) merges into u. When u is
  // free too the merged vertex is placed by maxmin_core on the union of both rings.
  bool try_collapse(TriId t) {
    std::array<std::pair<double, int>, 3> order;
    for (int i = 0; i < 3; ++i)
      order[i] = {rank_len2(tri_.tv[3 * t + detail::next3(i)], tri_.tv[3 * t + detail::prev3(i)]),
                  i};
    std::sort(order.begin(), order.end());
    for (const auto& [len, i] : order) {
      const VertId e0 = tri_.tv[3 * t + detail::next3(i)], e1 = tri_.tv[3 * t + detail::prev3(i)];
      for (const auto [v, u] : {std::pair{e0, e1}, std::pair{e1, e0}})
        if (collapse_into(v, u, 0, false)) return true;
    }
    return false;
  }
  // A topological change is taken when the worst 1/Q_K of the triangles it makes beats
  // that of the triangles it replaces, or (floor > 0: the size pass) stays >= floor.
  static bool accept_q(double q_new, double q_old, double floor) {
    return q_new > q_old * (1 + 1e-9) || (floor > 0 && q_new >= floor);
  }
  // Collapse of edge (v, u) merging v into u (see try_collapse). size_check: refused when
  // an edge of the merged vertex would be longer than sqrt2 in the metric.
  bool collapse_into(VertId v, VertId u, double floor, bool size_check) {
    const auto& P = tri_.pts;
    {
      {
        if (fixed_[v] || has_constrained_edge(v) || !gather_ring(v, rv_)) return false;
        double old_min = ball_min(v, rv_);
        Vec2 p;
        if (fixed_[u]) {
          // u stays: the new triangles are v's ball with v at u, minus the two on (u, v).
          p = P[u];
          double nmin = 1e300;
          const std::size_t n = rv_.size();
          bool ok = true;
          for (std::size_t k = 0; k < n && ok; ++k) {
            const VertId a = rv_[k], b = rv_[k + 1 == n ? 0 : k + 1];
            if (a == u || b == u) continue;
            if (!(pred::orient2d(&p.x, &P[a].x, &P[b].x) > 0))
              ok = false;
            else
              nmin = std::min(nmin, tri_q(u, a, b));
          }
          if (!ok || !accept_q(nmin, old_min, floor)) return false;
          if (size_check)
            for (const VertId w : rv_)
              if (w != u && true_len(p, vm_[u], rs_[u], w) > kSqrt2) return false;
        } else {
          if (has_constrained_edge(u) || !gather_ring(u, ru_)) return false;
          old_min = std::min(old_min, ball_min(u, ru_));
          // Merged ring: u's ring from x to y, then v's ring after y up to before x, where
          // v's ring reads (.., x, u, y, ..) and u's ring (.., y, v, x, ..).
          const std::size_t nv = rv_.size(), nu = ru_.size();
          std::size_t iu = 0, iv = 0;
          while (iu < nv && rv_[iu] != u) ++iu;
          while (iv < nu && ru_[iv] != v) ++iv;
          if (iu == nv || iv == nu) return false;
          const VertId x = rv_[(iu + nv - 1) % nv], y = rv_[(iu + 1) % nv];
          if (ru_[(iv + 1) % nu] != x || ru_[(iv + nu - 1) % nu] != y) return false;
          merged_.clear();
          for (std::size_t k = (iv + 1) % nu; k != iv; k = (k + 1) % nu)
            merged_.push_back(ru_[k]);  // x .. y
          for (std::size_t k = (iu + 2) % nv; k != (iu + nv - 1) % nv; k = (k + 1) % nv)
            merged_.push_back(rv_[k]);
          // The link condition: no vertex twice.
          std::vector<VertId>& srt = srt_;
          srt.assign(merged_.begin(), merged_.end());
          std::sort(srt.begin(), srt.end());
          if (std::adjacent_find(srt.begin(), srt.end()) != srt.end()) return false;
          const detail::MetricFrame f = frame_of(u);
          load_ring(f, merged_, vm_[u]);
          const Vec2 mid{0.5 * (P[u].x + P[v].x), 0.5 * (P[u].y + P[v].y)};
          double best = -1;
          Vec2 bp{};
          // A varying field starts from the midpoint only (the ends as starts cost 8% of
          // the whole run on ring:1e-4,0.01 for the same quality).
          const int starts = iso_uniform_ ? 3 : 1;
          int ns = 0;
          for (const Vec2 s0 : {mid, P[u], P[v]}) {
            if (ns++ >= starts) break;
            Vec2 fp = iso_uniform_ ? s0 : f(s0);
            if (!ball_valid(f, fp, merged_)) continue;
            const double q =
                maxmin_core(fp, 2.0, 12, [&](Vec2 z) { return ball_valid(f, z, merged_); });
            if (q > best) best = q, bp = fp;
            if (best > old_min || (floor > 0 && best >= floor)) break;
          }
          if (!accept_q(best, old_min, floor)) return false;
          p = iso_uniform_ ? bp : f.inv(bp);
          if (size_check) {
            const Metric2 mp = point_metric(p, rs_[u]);
            for (const VertId w : merged_)
              if (true_len(p, mp, rs_[u], w) > kSqrt2) return false;
          }
        }
        if (tri_.collapse_edge(v, u, p)) {
          set_position(u, p);
          return true;
        }
      }
    }
    return false;
  }

  // Split of the longest edge of t at its midpoint; the new vertex's ring then absorbs
  // the triangles across its four outer edges where that raises the worst quality (the
  // swaps that follow a split), and the vertex is placed by maxmin_core.
  bool try_split(TriId t) {
    int i = 0;
    double lmax = -1;
    for (int k = 0; k < 3; ++k) {
      const double l =
          rank_len2(tri_.tv[3 * t + detail::next3(k)], tri_.tv[3 * t + detail::prev3(k)]);
      if (l > lmax) lmax = l, i = k;
    }
    return split_at(3 * t + i, 0, false);
  }
  // Split of the edge of half-edge h (see try_split). size_check: refused when an edge of
  // the new vertex would be shorter than 1/sqrt2 in the metric.
  bool split_at(std::int32_t h, double floor, bool size_check) {
    const auto& P = tri_.pts;
    const TriId t = h / 3;
    const int i = h % 3;
    if (tri_.seg[h] != kNone || tri_.opp[h] == kNone) return false;
    const std::int32_t g = tri_.opp[h];
    if (!in_domain(g / 3)) return false;
    const VertId c = tri_.tv[h], a = tri_.tv[3 * t + detail::next3(i)],
                 b = tri_.tv[3 * t + detail::prev3(i)];
    const VertId d = tri_.tv[g];
    const Vec2 m{0.5 * (P[a].x + P[b].x), 0.5 * (P[a].y + P[b].y)};
    const double rm = iso_uniform_ ? 1.0 : std::max(rs_[a], rs_[b]);
    const Metric2 mm = iso_uniform_ ? m_uniform_ : point_metric(m, rm);
    double old_min = std::min(tri_q(t), tri_q(g / 3));
    // Ring of the new vertex, counter-clockwise: c, a, d, b.
    merged_.assign({c, a, d, b});
    absorbed_.clear();
    for (std::size_t k = 0; k < merged_.size() && merged_.size() < 12; ++k) {
      const VertId r0 = merged_[k], r1 = merged_[k + 1 == merged_.size() ? 0 : k + 1];
      const std::int32_t e = tri_.find_half_edge(r1, r0);  // the outer triangle (r1, r0, x)
      if (e == kNone || tri_.seg[e] != kNone || !in_domain(e / 3)) continue;
      const VertId x = tri_.tv[e];
      const double qo = tri_q(e / 3);
      if (!(pred::orient2d(&m.x, &P[r0].x, &P[x].x) > 0) ||
          !(pred::orient2d(&m.x, &P[x].x, &P[r1].x) > 0))
        continue;
      const double before = std::min(qo, q_of_point(m, mm, r0, r1));
      const double after = std::min(q_of_point(m, mm, r0, x), q_of_point(m, mm, x, r1));
      if (!(after > before)) continue;
      old_min = std::min(old_min, qo);
      absorbed_.push_back({r0, r1});
      merged_.insert(merged_.begin() + static_cast<std::ptrdiff_t>(k) + 1, x);
      --k;  // the new edge (r0, x) is looked at next
    }
    const detail::MetricFrame f(iso_uniform_ ? Metric2{} : mm);
    load_ring(f, merged_, mm);
    Vec2 fp = iso_uniform_ ? m : f(m);
    const double q = maxmin_core(fp, 2.0, 12, [&](Vec2 z) { return ball_valid(f, z, merged_); });
    if (!accept_q(q, old_min, floor)) return false;
    if (size_check) {
      const Vec2 pp = iso_uniform_ ? fp : f.inv(fp);
      const Metric2 mp = point_metric(pp, rm);
      for (const VertId w : merged_)
        if (true_len(pp, mp, rm, w) < 1 / kSqrt2) return false;
    }
    const VertId nv = tri_.split_edge(h, m);
    if (nv == kNone) return false;
    vm_.push_back(iso_uniform_ ? vm_[a] : mm);
    rs_.push_back(rm);
    fixed_.push_back(0);
    vmark_.push_back(0);
    for (const auto& [r0, r1] : absorbed_) {
      const std::int32_t e = tri_.find_half_edge(r0, r1);
      if (e != kNone && tri_.flippable(e)) tri_.flip(e);
    }
    // A flip refused above leaves another ring than the one fp was placed for: keep the
    // midpoint then (valid: split_edge checked it).
    if (gather_ring(nv, rv_) && ball_valid(f, fp, rv_))
      set_position(nv, iso_uniform_ ? fp : f.inv(fp));
    return true;
  }
  double q_of_point(Vec2 p, const Metric2& mp, VertId a, VertId b) const {
    const auto& P = tri_.pts;
    if (iso_uniform_) return q_inv(p, P[a], P[b]);
    const detail::MetricFrame f(detail::mean3(mp, vm_[a], vm_[b]));
    return q_inv(f(p), f(P[a]), f(P[b]));
  }
  // The metric a vertex created at p gets (the field, scaled by the boundary ratio r).
  Metric2 point_metric(Vec2 p, double r) {
    const Metric2 m = metric(p.x, p.y);
    return r < 1 ? detail::scaled(m, 1.0 / (r * r)) : m;
  }
  // Metric length of the segment from p (metric mp, boundary ratio rp) to vertex w by
  // Simpson's rule on the field (eq. 7.10), as the measure takes it: the endpoints'
  // metrics alone miss how a strongly anisotropic field turns along the edge (at the
  // ring's layer a chord of the circle is tangent at its midpoint only).
  double true_len(Vec2 p, const Metric2& mp, double rp, VertId w) {
    const Vec2 q = tri_.pts[w];
    const Vec2 d{q.x - p.x, q.y - p.y};
    const double rm = std::sqrt(rp * (static_cast<std::size_t>(w) < rs_.size() ? rs_[w] : 1.0));
    const Metric2 mm = point_metric({0.5 * (p.x + q.x), 0.5 * (p.y + q.y)}, rm);
    return (detail::length(mp, d) + 4 * detail::length(mm, d) + detail::length(vm_[w], d)) / 6;
  }
  // Squared length of edge (a, b) for ranking the edges of a triangle: Euclidean for a
  // uniform field, in the metric otherwise (the shortest edge in the plane of an
  // anisotropic triangle is not its shortest in the metric).
  double rank_len2(VertId a, VertId b) const {
    const Vec2 pa = tri_.pts[a], pb = tri_.pts[b];
    if (iso_uniform_) return (pa.x - pb.x) * (pa.x - pb.x) + (pa.y - pb.y) * (pa.y - pb.y);
    const double l = edge_length(a, b);
    return l * l;
  }

  // Calls fn(t) for every triangle around vertex v (the star of a non-box vertex is
  // closed in the triangulation of the box).
  template <class F>
  void for_ball(VertId v, F&& fn) const {
    const TriId t0 = tri_.vtri[v];
    if (t0 == kNone) return;
    TriId t = t0;
    int guard = 0;
    do {
      fn(t);
      int k = 0;
      while (tri_.tv[3 * t + k] != v) ++k;
      const std::int32_t h = tri_.opp[3 * t + detail::next3(k)];
      if (h == kNone || ++guard > 256) return;
      t = h / 3;
    } while (t != t0);
  }
  // The vertices of t and of its three neighbours (after a swap of an edge of t, every
  // changed triangle has one of them).
  void touch_around(TriId t, std::vector<VertId>& out) const {
    for (int i = 0; i < 3; ++i) {
      out.push_back(tri_.tv[3 * t + i]);
      const std::int32_t g = tri_.opp[3 * t + i];
      if (g != kNone) out.push_back(tri_.tv[g]);
    }
  }
  // The in-domain triangles worse than q found in the balls of the vertices vs (each once).
  void bad_in_balls(const std::vector<VertId>& vs, double q, std::vector<TriId>& out) {
    out.clear();
    if (tmark_.size() < static_cast<std::size_t>(tri_.num_tris()))
      tmark_.resize(tri_.num_tris(), 0);
    ++tepoch_;
    for (const VertId v : vs)
      for_ball(v, [&](TriId t) {
        if (tmark_[t] == tepoch_) return;
        tmark_[t] = tepoch_;
        if (in_domain(t) && tri_q(t) < q) out.push_back(t);
      });
  }

  // Rounds of max-min relocation of the vertices of triangles worse than qstop, and
  // swaps of their edges. The first round scans the mesh; a later one looks only at the
  // balls of the vertices handled before (every change is there). Returns the vertices
  // handled: the triangles still bad afterwards lie in their balls.
  std::vector<VertId> targeted_pass(double qstop, int rounds) {
    std::vector<TriId> bad;
    std::vector<VertId> ring, handled, all;
    std::vector<char> seen(tri_.num_verts(), 0);
    const TriId nt = tri_.num_tris();
    for (TriId t = 0; t < nt; ++t)
      if (in_domain(t) && tri_q(t) < qstop) bad.push_back(t);
    for (int round = 0; round < rounds && !bad.empty(); ++round) {
      if (over_time("optimization")) break;
      std::int64_t moved = 0, swaps = 0;
      for (const VertId v : handled) seen[v] = 0;
      handled.clear();
      for (const TriId t : bad) {
        if (!in_domain(t)) continue;
        for (int k = 0; k < 3; ++k) {
          const VertId v = tri_.tv[3 * t + k];
          if (seen[v]) continue;
          seen[v] = 1;
          handled.push_back(v);
          moved += maxmin_relocate(v, ring, qstop, 8);
        }
      }
      const std::size_t nh = handled.size();
      for (const TriId t : bad)
        if (in_domain(t) && tri_q(t) < qstop && try_swap(t)) {
          ++swaps;
          touch_around(t, handled);
        }
      res_.stats.relocations += moved;
      res_.stats.swaps += swaps;
      all.insert(all.end(), handled.begin(), handled.begin() + static_cast<std::ptrdiff_t>(nh));
      if (moved == 0 && swaps == 0) break;
      // Every triangle that changed or stayed bad lies in a ball of a handled vertex:
      // rescanning those balls finds what a scan of the mesh would, in the same order
      // (by triangle id; another order measured worse: a corner of the square at h =
      // 0.02 stayed at Q = 1.202).
      bad_in_balls(handled, qstop, bad);
      std::sort(bad.begin(), bad.end());
    }
    return all;
  }

  // first: when given, the vertices whose balls hold every triangle worse than qbad (the
  // first round then looks only there), else the first round scans the mesh.
  void repair(double qbad, int rounds, const std::vector<VertId>* first = nullptr) {
    std::vector<TriId> bad;
    std::vector<VertId> ring, touched;
    // Work budget (triangle evaluations): where bad elements cannot be repaired (small
    // input angles between fixed boundary edges) the loop would otherwise try them all,
    // round after round. A uniform unit mesh needs a small fraction of it.
    const std::int64_t budget =
        work_ + kRepairWork * static_cast<std::int64_t>(tri_.num_tris()) + 100000;
    for (int round = 0; round < rounds; ++round) {
      if (over_time("optimization") || work_ > budget) return;
      // Later rounds look only at the balls of the vertices the round before touched
      // (the vertices of the triangles it worked on and their neighbours, the new vertex
      // of a split): every triangle that changed or stayed bad is there. Sorted by id,
      // the list is the one a scan of the mesh would give.
      bad.clear();
      if (round == 0 && first) {
        bad_in_balls(*first, qbad, bad);
      } else if (round > 0) {
        bad_in_balls(touched, qbad, bad);
        std::sort(bad.begin(), bad.end());
      } else {
        const TriId nt = tri_.num_tris();
        for (TriId t = 0; t < nt; ++t)
          if (in_domain(t) && tri_q(t) < qbad) bad.push_back(t);
      }
      if (bad.empty()) break;
      touched.clear();
      std::int64_t changes = 0;
      for (const TriId t : bad) {
        if (work_ > budget) return;
        if (!in_domain(t) || !(tri_q(t) < qbad)) continue;
        for (int k = 0; k < 3; ++k) {
          const VertId c = tri_.tv[3 * t + k];
          touched.push_back(c);
          if (gather_ring(c, nbr_)) touched.insert(touched.end(), nbr_.begin(), nbr_.end());
        }
        for (int k = 0; k < 3; ++k) changes += maxmin_relocate(tri_.tv[3 * t + k], ring, 2.0, 8);
        if (!(tri_q(t) < qbad)) continue;
        // A vertex can be held by its neighbours (its ball's worst triangles pinned
        // against each other): relax the neighbours of the triangle's vertices, then the
        // vertices again.
        // The positions are restored unless the worst triangle around them improved.
        {
          saved_.clear();
          for (int k = 0; k < 3; ++k) {
            const VertId c = tri_.tv[3 * t + k];
            saved_.push_back({c, tri_.pts[c]});
            if (!gather_ring(c, nbr_)) continue;
            for (const VertId w : nbr_) saved_.push_back({w, tri_.pts[w]});
          }
          auto region_min = [&] {
            double m = 1e300;
            for (const auto& [w, pw] : saved_)
              if (!fixed_[w] && gather_ring(w, ring)) m = std::min(m, ball_min(w, ring));
            return m;
          };
          const double before = region_min();
          bool any = false;
          // Not for a varying field: there the sweeps cost a third of the optimization
          // and the repair ends better without them (ring:1e-4,0.01: Q_M 1.45 against
          // 1.78 with three sweeps; the restore rule below is judged per triangle frame).
          const int sweeps = iso_uniform_ ? 3 : 0;
          for (int sweep = 0; sweep < sweeps; ++sweep)
            for (const auto& [w, pw] : saved_) any |= pnorm_relocate(w, ring);
          for (int k = 0; k < 3; ++k) any |= maxmin_relocate(tri_.tv[3 * t + k], ring, 2.0, 8);
          if (any && !(region_min() > before)) {
            for (const auto& [w, pw] : saved_) set_position(w, pw);
          } else if (any) {
            ++changes;
          }
        }
        if (!(tri_q(t) < qbad)) continue;
        if (try_swap(t)) {
          ++changes;
          touch_around(t, touched);
          continue;
        }
        if (try_collapse(t)) {
          ++changes;
          continue;
        }
        // A varying field's triangle whose three vertices are all on the boundary lies
        // where the domain is narrower than the field's size (CAD faces: the last
        // micrometres of a tangential contact); a split only puts an interior vertex
        // into that gap (occt_crankarm: six slivers of Q 22 with one, instead of the
        // boundary-only slivers the report counts apart).
        if (!iso_uniform_ && fixed_[tri_.tv[3 * t]] && fixed_[tri_.tv[3 * t + 1]] &&
            fixed_[tri_.tv[3 * t + 2]])
          continue;
        const VertId nv = tri_.num_verts();
        if (try_split(t)) {
          ++changes;
          touched.push_back(nv);
          continue;
        }
      }
      if (changes == 0) break;
    }
  }

  // Size optimization (§7.5.2: "first with respect to the size criterion"): interior edges
  // longer than sqrt2 in the metric (Simpson's rule, true_len) are split, the longest
  // first; then edges shorter than 1/sqrt2 are collapsed, the shortest first. A change is
  // taken when the worst 1/Q_K around it stays >= floor (or improves) and it makes no
  // edge outside the unit range on the other side. Returns the number of changes.
  std::int64_t size_pass(double floor) {
    struct E {
      double l;
      VertId a, b;
    };
    std::vector<E> longs, shorts;
    const TriId nt = tri_.num_tris();
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i, g = tri_.opp[h];
        if (tri_.seg[h] != kNone || g == kNone || g / 3 < t || !in_domain(g / 3)) continue;
        const VertId a = tri_.tv[3 * t + detail::next3(i)], b = tri_.tv[3 * t + detail::prev3(i)];
        const double l = true_len(tri_.pts[a], vm_[a], rs_[a], b);
        if (l > kSqrt2)
          longs.push_back({l, a, b});
        else if (l < 1 / kSqrt2)
          shorts.push_back({l, a, b});
      }
    }
    std::sort(longs.begin(), longs.end(), [](const E& x, const E& y) { return x.l > y.l; });
    std::sort(shorts.begin(), shorts.end(), [](const E& x, const E& y) { return x.l < y.l; });
    std::int64_t changes = 0;
    for (const E& e : longs) {
      if (over_time("optimization")) return changes;
      const std::int32_t h = tri_.find_half_edge(e.a, e.b);
      if (h == kNone || !in_domain(h / 3)) continue;
      if (!(true_len(tri_.pts[e.a], vm_[e.a], rs_[e.a], e.b) > kSqrt2)) continue;
      changes += split_at(h, floor, true);
    }
    if (!opt_.collapse_short_edges) return changes;
    for (const E& e : shorts) {
      if (over_time("optimization")) return changes;
      if (tri_.vtri[e.a] == kNone || tri_.vtri[e.b] == kNone) continue;
      const std::int32_t h = tri_.find_half_edge(e.a, e.b);
      if (h == kNone || !in_domain(h / 3)) continue;
      if (!(true_len(tri_.pts[e.a], vm_[e.a], rs_[e.a], e.b) < 1 / kSqrt2)) continue;
      changes += collapse_into(e.a, e.b, floor, true) || collapse_into(e.b, e.a, floor, true);
    }
    return changes;
  }

  std::int64_t maxmin_pass(double qstop, int iters) {
    std::int64_t moved = 0;
    std::vector<VertId> ring;
    const VertId nv = tri_.num_verts();
    if (multi_frame_) {
      // Only the vertices of triangles worse than qstop: maxmin_core leaves a ball whose
      // worst triangle is above qstop as it is, and building the per-triangle frames of
      // every ball to find that out costs more than judging each triangle once.
      std::vector<char> want(nv, 0);
      const TriId nt = tri_.num_tris();
      for (TriId t = 0; t < nt; ++t)
        if (in_domain(t) && tri_q(t) < qstop)
          for (int i = 0; i < 3; ++i) want[tri_.tv[3 * t + i]] = 1;
      for (VertId v = 4; v < nv; ++v)
        if (want[v]) moved += maxmin_relocate(v, ring, qstop, iters);
      return moved;
    }
    for (VertId v = 4; v < nv; ++v) moved += maxmin_relocate(v, ring, qstop, iters);
    return moved;
  }

  // Valence-driven swaps: in a unit mesh the ideal vertex has 6 triangles around it (a
  // boundary vertex round(theta / 60deg) for its interior angle theta); valence 4 or 8
  // vertices force angles of 90 or 45 degrees that no relocation can repair. A swap is
  // taken when it lowers the squared deviation from the ideal counts of its four vertices
  // and keeps the worse of its two triangles within kValenceQualityKeep of the current one.
  std::int64_t valence_pass() {
    constexpr double kValenceQualityKeep = 0.8;
    const VertId nv = tri_.num_verts();
    std::vector<std::int32_t> cnt(nv, 0);
    std::vector<double> ang(nv, 0.0);
    std::vector<char> onb(nv, 0);
    const TriId nt = tri_.num_tris();
    const auto& P = tri_.pts;
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      for (int i = 0; i < 3; ++i) {
        const VertId v = tri_.tv[3 * t + i];
        ++cnt[v];
        if (tri_.seg[3 * t + i] != kNone) {
          onb[tri_.tv[3 * t + detail::next3(i)]] = 1;
          onb[tri_.tv[3 * t + detail::prev3(i)]] = 1;
        }
        const Vec2 a = P[v], b = P[tri_.tv[3 * t + detail::next3(i)]],
                   c = P[tri_.tv[3 * t + detail::prev3(i)]];
        const double ux = b.x - a.x, uy = b.y - a.y, wx = c.x - a.x, wy = c.y - a.y;
        ang[v] += std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
      }
    }
    std::vector<std::int32_t> ideal(nv, 6);
    for (VertId v = 0; v < nv; ++v)
      if (onb[v])
        ideal[v] =
            std::max(1, static_cast<int>(std::lround(ang[v] / (3.14159265358979323846 / 3))));
    std::int64_t swaps = 0;
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i;
        if (tri_.seg[h] != kNone) continue;
        const std::int32_t g = tri_.opp[h];
        if (g == kNone || g / 3 < t) continue;
        const VertId c = tri_.tv[h], a = tri_.tv[3 * t + detail::next3(i)],
                     b = tri_.tv[3 * t + detail::prev3(i)];
        const VertId d = tri_.tv[g];
        auto dev = [&](VertId v, int delta) {
          const double e = cnt[v] + delta - ideal[v];
          return e * e;
        };
        const double before = dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
        const double after = dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1);
        if (!(after < before)) continue;
        const Metric2 m = iso_uniform_ ? Metric2{} : quad_metric(a, b, c, d);
        const double qb =
            std::min(quality_in(m, P[c], P[a], P[b]), quality_in(m, P[d], P[b], P[a]));
        const double qa =
            std::min(quality_in(m, P[c], P[a], P[d]), quality_in(m, P[d], P[b], P[c]));
        if (qa < kValenceQualityKeep * qb || !tri_.flippable(h)) continue;
        tri_.flip(h);
        --cnt[a], --cnt[b], ++cnt[c], ++cnt[d];
        ++swaps;
        break;
      }
    }
    return swaps;
  }

  // Options::time_limit: true (and the status set) once it is exceeded.
  bool over_time(const char* stage) {
    if (!(opt_.time_limit > 0) || res_.status.code == StatusCode::TimeLimit)
      return res_.status.code == StatusCode::TimeLimit;
    const double s = std::chrono::duration<double>(Clock::now() - t_start_).count();
    if (s <= opt_.time_limit) return false;
    res_.status.code = StatusCode::TimeLimit;
    char buf[64];
    std::snprintf(buf, sizeof buf, "%g", opt_.time_limit);
    res_.status.message = std::string("time limit of ") + buf + " s reached during " + stage;
    return true;
  }

  void optimize() {
    iso_uniform_ = size_.kind == SizeSpec::Kind::Uniform;
    if (lattice_used_) {
      // Lattice field points: the interior is equilateral already; only the band along
      // the boundary and the lattice's seam with the boundary layer need work, found by
      // their quality (global passes would spend their time on perfect triangles).
      const std::vector<VertId> handled = targeted_pass(kMaxminStop, 4);
      repair(kRepairBad, 12, &handled);
      return;
    }
    // A uniform field without the lattice (a thin domain) keeps the full passes; a varying
    // field gets fewer global passes (measured on ring:1e-4,1e-2: 8 swap+smooth and 6
    // max-min passes give the same quality after the repair and size passes below, Q_M
    // 1.50 against 1.44, at twice the optimization time).
    multi_frame_ = !iso_uniform_;
    const int kval = iso_uniform_ ? 3 : 1,
              kpre = iso_uniform_ ? opt_.optimize_passes : std::min(2, opt_.optimize_passes),
              kmm = iso_uniform_ ? 6 : 2;
    for (int pass = 0; pass < kval; ++pass) {
      if (over_time("optimization")) return;
      const std::int64_t s = valence_pass();
      res_.stats.swaps += s;
      res_.stats.relocations += smooth_pass();
      if (s < 1e-3 * tri_.num_verts()) break;
    }
    // Passes stop early once fewer than kSmoothSettled of the vertices still move: the
    // last passes of a converged smoothing only polish the mean, not the worst element.
    constexpr double kSmoothSettled = 0.02;
    for (int pass = 0; pass < kpre && !field_error_; ++pass) {
      if (over_time("optimization")) return;
      const std::int64_t s = swap_pass();
      const std::int64_t r = smooth_pass();
      res_.stats.swaps += s;
      res_.stats.relocations += r;
      if (s == 0 && r < kSmoothSettled * tri_.num_verts()) break;
    }
    res_.stats.swaps += swap_pass();
    // Max-min relocation and the targeted repair judge each ball triangle in the mean
    // of its vertex metrics (multi_frame_), as the measure does.
    multi_frame_ = !iso_uniform_;
    // Max-min relocation stops at Q_K = 1.3 for a varying field (1.15 measured the same
    // quality after the repair on ring:1e-4,0.01, Q_M 1.51 against 1.53, 13% slower).
    const double qs = iso_uniform_ ? kMaxminStop : kMaxminStopVarying;
    for (int pass = 0; pass < kmm; ++pass) {
      const std::int64_t r = maxmin_pass(qs, 8);
      const std::int64_t s = swap_pass();
      res_.stats.relocations += r;
      res_.stats.swaps += s;
      if (r == 0 && s == 0) break;
    }
    if (iso_uniform_) {
      repair(kRepairBad, 12);
      return;
    }
    // Size, then shape (§7.5.2): two size passes, each followed by max-min relocation
    // and swaps, then the repair of the triangles still worse than Q 1.4. (A repair
    // before and after every size pass measured the same quality for 13% more work on
    // ring:1e-4,0.01.)
    for (int pass = 0; pass < 2; ++pass) {
      if (over_time("optimization")) return;
      const std::int64_t c = size_pass(kSizeFloor);
      if (c == 0) break;
      for (int k = 0; k < 2; ++k) {
        const std::int64_t r = maxmin_pass(qs, 8);
        const std::int64_t sw = swap_pass();
        res_.stats.relocations += r;
        res_.stats.swaps += sw;
      }
    }
    repair(kRepairBadVarying, 12);
  }

  // ---------------------------------------------------------------- checks, output
  bool internal_check(const char* when) {
    const TriId nt = tri_.num_tris();
    for (TriId t = 0; t < nt; ++t) {
      if (tri_.dead(t)) continue;
      const auto& P = tri_.pts;
      const VertId a = tri_.tv[3 * t], b = tri_.tv[3 * t + 1], c = tri_.tv[3 * t + 2];
      if (pred::orient2d(&P[a].x, &P[b].x, &P[c].x) <= 0)
        return fail(StatusCode::InternalError, std::string("checker ") + when + ": triangle " +
                                                   std::to_string(t) + " is not CCW");
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i, g = tri_.opp[h];
        if (g == kNone) continue;
        if (tri_.opp[g] != h || tri_.dead(g / 3) || tri_.seg[g] != tri_.seg[h] ||
            tri_.tv[3 * (g / 3) + detail::next3(g % 3)] != tri_.tv[3 * t + detail::prev3(i)])
          return fail(StatusCode::InternalError, std::string("checker ") + when +
                                                     ": neighbours of triangle " +
                                                     std::to_string(t) + " are not symmetric");
      }
    }
    return true;
  }

  void output() {
    Mesh& M = res_.mesh;
    const VertId nv = tri_.num_verts();
    std::vector<VertId> newid(nv, kNone);
    const std::size_t n = in_.points.size();
    // Input points keep their relative order first, then every created vertex.
    std::vector<char> used(nv, 0);
    const TriId nt = tri_.num_tris();
    std::size_t ndom = 0;
    for (TriId t = 0; t < nt; ++t)
      if (in_domain(t)) {
        ++ndom;
        for (int i = 0; i < 3; ++i) used[tri_.tv[3 * t + i]] = 1;
      }
    // Sized once: a million-triangle mesh otherwise grows every array by doubling.
    detail::reserve_huge(M.vertices, M.vertices.size() + static_cast<std::size_t>(nv));
    detail::reserve_huge(M.vertex_markers, M.vertex_markers.size() + static_cast<std::size_t>(nv));
    if (vm_.size() == tri_.pts.size())
      M.vertex_metric.reserve(M.vertex_metric.size() + static_cast<std::size_t>(nv));
    detail::reserve_huge(M.triangles, M.triangles.size() + ndom);
    detail::reserve_huge(M.triangle_region, M.triangle_region.size() + ndom);
    detail::reserve_huge(M.triangle_attribute, M.triangle_attribute.size() + ndom);
    if (opt_.measure) edges_.reserve(edges_.size() + 3 * ndom / 2 + static_cast<std::size_t>(nv));
    auto take = [&](VertId v) {
      if (v == kNone || !used[v] || newid[v] != kNone) return;
      newid[v] = static_cast<VertId>(M.vertices.size());
      M.vertices.push_back(tri_.pts[v]);
      M.vertex_markers.push_back(vmark_[v]);
      if (vm_.size() == tri_.pts.size()) M.vertex_metric.push_back(vm_[v]);
    };
    for (std::size_t i = 0; i < n; ++i) take(vid_[i]);
    for (VertId v = 4; v < nv; ++v) take(v);
    M.input_vertex.resize(n);
    for (std::size_t i = 0; i < n; ++i)
      M.input_vertex[i] = vid_[i] == kNone ? kNone : newid[vid_[i]];
    std::vector<std::int32_t> region_id(removed_.size(), -1);
    std::int32_t nreg = 0;
    for (TriId t = 0; t < nt; ++t) {
      if (!in_domain(t)) continue;
      const std::int32_t c = tri_.tag[t];
      if (region_id[c] < 0) region_id[c] = nreg++;
      M.triangles.push_back(
          {newid[tri_.tv[3 * t]], newid[tri_.tv[3 * t + 1]], newid[tri_.tv[3 * t + 2]]});
      M.triangle_region.push_back(region_id[c]);
      M.triangle_attribute.push_back(attr_[c]);
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = 3 * t + i;
        if (opt_.measure) {
          // Every undirected edge once, for the measures.
          const std::int32_t g = tri_.opp[h];
          if (g == kNone || !in_domain(g / 3) || g > h) {
            const auto a = static_cast<std::uint32_t>(newid[tri_.tv[3 * t + detail::next3(i)]]);
            const auto b = static_cast<std::uint32_t>(newid[tri_.tv[3 * t + detail::prev3(i)]]);
            edges_.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
          }
        }
        const std::int32_t s = tri_.seg[h];
        if (s == kNone) continue;
        const std::int32_t g = tri_.opp[h];
        if (g != kNone && in_domain(g / 3) && g / 3 < t) continue;  // once per edge
        M.boundary_edges.push_back({newid[tri_.tv[3 * t + detail::next3(i)]],
                                    newid[tri_.tv[3 * t + detail::prev3(i)]], segs_[s].marker});
      }
    }
  }

  const Pslg& in_;
  const SizeSpec& size_;
  const Options& opt_;
  Result& res_;
  Triangulation tri_;
  std::vector<std::int32_t> rep_;       // input point -> representative input point
  std::vector<std::int32_t> xy_order_;  // input points sorted by (x, y)
  std::vector<VertId> vid_;             // point index -> triangulation vertex
  std::vector<SegRec> segs_;
  Clock::time_point t_start_ = Clock::now();  // for Options::time_limit
  std::vector<double> rs_;   // per vertex: boundary size ratio (<= 1; Options::boundary_gradation)
  std::vector<char> fixed_;  // per triangulation vertex: not movable
  std::vector<int> vmark_;   // per triangulation vertex: marker
  std::vector<Metric2> vm_;  // per triangulation vertex: metric
  std::vector<char> removed_;  // per component: exterior or hole
  std::vector<double> attr_;   // per component: region attribute
  std::int32_t last_hole_ = -1;
  double h_uniform_ = 0;
  Metric2 m_uniform_;
  bool refine_ok_ = true;
  std::int64_t overlaps_merged_ = 0;  // segment pieces dropped as copies of another (enforce_work)
  bool field_error_ = false;
  bool iso_uniform_ = false;
  bool lattice_used_ = false;         // lattice_points placed the field points
  std::vector<std::uint64_t> edges_;  // output edges, each once (a << 32 | b), for measure
  std::vector<Vec2> fr_, gk_;         // maxmin_relocate scratch: ring in the frame, gradients
  struct BallTri {
    double a11, a12, a22;  // ball frame -> this triangle's frame (upper triangular)
    Vec2 a, b;             // its ring edge in its frame
  };
  std::vector<BallTri> bt_;    // per-triangle frames (multi_frame_)
  std::vector<double> tq_;     // swap_pass_varying: 1/Q_K per triangle
  detail::KeySet64 analysed_;  // refine: edges (a << 32 | b) already analysed
  bool multi_frame_ = false;   // the field varies: each ball triangle in its own frame
  std::vector<VertId> rv_, ru_, merged_, nbr_, srt_;  // repair scratch: rings
  std::vector<std::pair<VertId, Vec2>> saved_;
  std::int64_t work_ = 0;             // triangle evaluations of maxmin_core / pnorm_core
  std::vector<std::uint32_t> tmark_;  // bad_in_balls: triangle marks
  std::uint32_t tepoch_ = 0;
  std::vector<std::pair<VertId, VertId>> absorbed_;
  std::vector<double> qk_;
};

}  // namespace

Result mesh(const Pslg& in, const SizeSpec& size, const Options& opt) {
  Result res;
  Options o = opt;
#ifndef NDEBUG
  o.check = true;
#endif
  Mesher m(in, size, o, res);
  m.run();
  return res;
}

}  // namespace uvmesh::m2d
