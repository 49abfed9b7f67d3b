// Local feature size of the PSLG (Options::feature_size): the size field capped, at every
// boundary point, by the distance to the nearest boundary feature across the domain
// (Ruppert's lfs, the radius of the smallest disk touching two disjoint features), the
// cap grown into the domain at the gradation rate (the H-correction, eq. 7.11). A gap or
// a spike narrower than the requested size then gets triangles as wide as the gap instead
// of needles spanning it (the 2D counterpart of the surface stage's proximity rule).
//
// Two segments that share a vertex are one feature there, as in Ruppert's definition,
// except at a sharp angle: the two sides of a thin spike made of two segments are each
// other's only close features, and the lfs alone (the spike's length) would leave the
// spike in needles. Across an angle under kSharpDeg a point at distance t from the
// apex counts the other side (t sin(angle), the spike's width there), down to a distance
// kApexShare of the shorter side from the apex: the cap shrinks geometrically towards
// the apex, so the spike gets a layer of well shaped triangles per width, and only the
// apex triangle keeps the input's angle.
#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>

#include "mesh_state.h"

namespace uvmesh::m2d::detail {

namespace {

constexpr double kSharpDeg = 30;  // a corner triangle with an apex of 30 degrees has Q 1.45
constexpr double kApexShare = 1.0 / 64;
// The cap across a spike is this share of its width: two layers of triangles. With one,
// the split points of its two sides face each other (the sides are split alike) and
// each pair of triangles across it has one above Q 1.5 once the width grows along it
// (Q 1.53-1.69 for apex angles of 15-30 degrees whatever the spacing).
constexpr double kSpikeShare = 0.5;
constexpr double kAcrossDeg = 45;
// A feature at least this share of the field's size away is left to the unit mesh (its
// edges are within [1/sqrt2, sqrt2] of the size anyway): the cap does not apply there, so
// that a boundary split a little finer than the size (the corner of a square split at
// 1 / ceil(1 / h)) does not turn a uniform size into a scalar field.
constexpr double kBindShare = 0.75;
constexpr double kDeg = 3.14159265358979323846 / 180;
// The cap grows at this ratio when Options::boundary_gradation sets none (the ratio
// Gmsh and bamg users get for a graded size by default is between 1.2 and 1.5).
constexpr double kDefaultGradation = 1.3;

struct Seg {
  VertId a, b;
  Vec2 pa, pb;
};

// The point of segment s nearest to p.
Vec2 nearest_on(Vec2 p, const Seg& s) {
  const double dx = s.pb.x - s.pa.x, dy = s.pb.y - s.pa.y;
  const double l2 = dx * dx + dy * dy;
  double t = l2 > 0 ? ((p.x - s.pa.x) * dx + (p.y - s.pa.y) * dy) / l2 : 0;
  t = std::clamp(t, 0.0, 1.0);
  return {s.pa.x + t * dx, s.pa.y + t * dy};
}

// The segments in a uniform bucket grid (a segment in every cell its line crosses), and
// the nearest feature of a boundary point by rings of cells around it.
class SegmentGrid {
 public:
  explicit SegmentGrid(std::vector<Seg> segs) : segs_(std::move(segs)) {
    double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
    for (const Seg& s : segs_)
      for (Vec2 p : {s.pa, s.pb})
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y), x1 = std::max(x1, p.x),
        y1 = std::max(y1, p.y);
    const double diag = std::hypot(x1 - x0, y1 - y0);
    cs_ = std::max(diag / std::sqrt(static_cast<double>(segs_.size()) + 1), diag * 1e-3);
    x0_ = x0, y0_ = y0;
    nx_ = std::min(2048, static_cast<int>((x1 - x0) / cs_) + 1);
    ny_ = std::min(2048, static_cast<int>((y1 - y0) / cs_) + 1);
    cells_.assign(static_cast<std::size_t>(nx_) * ny_, {});
    for (std::size_t i = 0; i < segs_.size(); ++i) bucket(static_cast<std::int32_t>(i));
    stamp_.assign(segs_.size(), 0);
  }

  // Distance from p (on segment own) to the nearest other feature when it is under limit
  // (the search stops there), else limit.
  double feature_distance(Vec2 p, std::int32_t own, double limit) {
    ++epoch_;
    const int cx = cell_x(p.x), cy = cell_y(p.y);
    double best = limit;
    for (int k = 0; k <= std::max(nx_, ny_); ++k) {
      if ((k - 1) * cs_ >= best) break;
      for (int j = cy - k; j <= cy + k; ++j) {
        if (j < 0 || j >= ny_) continue;
        const bool edge_row = j == cy - k || j == cy + k;
        for (int i = cx - k; i <= cx + k; i += edge_row ? 1 : 2 * std::max(k, 1)) {
          if (i < 0 || i >= nx_) continue;
          for (const std::int32_t s : cells_[static_cast<std::size_t>(j) * nx_ + i]) {
            if (stamp_[s] == epoch_) continue;
            stamp_[s] = epoch_;
            best = std::min(best, across(p, own, s));
          }
        }
      }
    }
    return best;
  }

  const std::vector<Seg>& segs() const { return segs_; }

 private:
  int cell_x(double x) const { return std::clamp(static_cast<int>((x - x0_) / cs_), 0, nx_ - 1); }
  int cell_y(double y) const { return std::clamp(static_cast<int>((y - y0_) / cs_), 0, ny_ - 1); }

  // Every cell the segment's line passes through, column by column (a slightly larger
  // row range than exact is harmless: the search stamps what it has seen).
  void bucket(std::int32_t id) {
    const Seg& s = segs_[id];
    const int i0 = cell_x(std::min(s.pa.x, s.pb.x)), i1 = cell_x(std::max(s.pa.x, s.pb.x));
    const double dx = s.pb.x - s.pa.x, dy = s.pb.y - s.pa.y;
    for (int i = i0; i <= i1; ++i) {
      double ya = s.pa.y, yb = s.pb.y;
      if (i0 != i1 && dx != 0) {
        const double xl = std::max(x0_ + i * cs_, std::min(s.pa.x, s.pb.x));
        const double xr = std::min(x0_ + (i + 1) * cs_, std::max(s.pa.x, s.pb.x));
        ya = s.pa.y + (xl - s.pa.x) / dx * dy;
        yb = s.pa.y + (xr - s.pa.x) / dx * dy;
      }
      for (int j = cell_y(std::min(ya, yb)); j <= cell_y(std::max(ya, yb)); ++j)
        cells_[static_cast<std::size_t>(j) * nx_ + i].push_back(id);
    }
  }

  // The distance from p on segment own to segment s when s is a feature apart from own:
  // disjoint, or joined at a sharp angle and p away from the apex (the file comment).
  double across(Vec2 p, std::int32_t own, std::int32_t s) const {
    constexpr double inf = std::numeric_limits<double>::infinity();
    if (s == own) return inf;
    const Seg &o = segs_[own], &q = segs_[s];
    // Across the domain: the nearest point is seen at more than kAcrossDeg from p's own
    // segment. The next pieces of a straight side or of a polygonal curve lie ahead
    // along it, at the spacing of the input's vertices, and are no gap.
    const Vec2 n = nearest_on(p, q);
    const double ux = o.pb.x - o.pa.x, uy = o.pb.y - o.pa.y, vx = n.x - p.x, vy = n.y - p.y;
    const double dist = std::hypot(vx, vy);
    if (!(std::abs(ux * vy - uy * vx) > std::sin(kAcrossDeg * kDeg) * std::hypot(ux, uy) * dist))
      return inf;
    VertId apex = kNone;
    if (q.a == o.a || q.a == o.b) apex = q.a;
    if (q.b == o.a || q.b == o.b) apex = apex == kNone ? q.b : kNone - 1;
    if (apex == kNone) return dist;
    if (apex != q.a && apex != q.b) return inf;  // the same two vertices
    const Vec2 v = apex == q.a ? q.pa : q.pb, w = apex == q.a ? q.pb : q.pa;
    const Vec2 u = apex == o.a ? o.pb : o.pa;
    const double lu = std::hypot(u.x - v.x, u.y - v.y), lw = std::hypot(w.x - v.x, w.y - v.y);
    const double c = ((u.x - v.x) * (w.x - v.x) + (u.y - v.y) * (w.y - v.y)) / (lu * lw);
    if (!(c > std::cos(kSharpDeg * kDeg))) return inf;
    if (std::hypot(p.x - v.x, p.y - v.y) < kApexShare * std::min(lu, lw)) return inf;
    return kSpikeShare * dist;
  }

  std::vector<Seg> segs_;
  std::vector<std::vector<std::int32_t>> cells_;
  std::vector<std::uint32_t> stamp_;
  std::uint32_t epoch_ = 0;
  double x0_ = 0, y0_ = 0, cs_ = 1;
  int nx_ = 1, ny_ = 1;
};

struct Sample {
  Vec2 p;
  double d;
};

// h(y) = min over the samples of d + slope |y - p|: the graded cap, by a k-d tree over the
// samples whose nodes keep their smallest d (a node is skipped when its smallest d plus
// the slope times the distance to its box cannot beat the best found).
class GradedCap {
 public:
  GradedCap(std::vector<Sample> s, double slope) : s_(std::move(s)), slope_(slope) {
    nodes_.reserve(2 * s_.size());
    build(0, static_cast<std::int32_t>(s_.size()), 0);
  }

  // The cap at (x, y) when it is under bound (the field's size there: a larger cap does
  // not bind, and the bound prunes the search to the samples within reach), else bound.
  double operator()(double x, double y, double bound) const {
    double best = bound;
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& n = nodes_[stack[--top]];
      const double bx = std::max({n.x0 - x, 0.0, x - n.x1}),
                   by = std::max({n.y0 - y, 0.0, y - n.y1});
      if (n.dmin + slope_ * std::hypot(bx, by) >= best) continue;
      if (n.left < 0) {
        for (std::int32_t k = n.lo; k < n.hi; ++k)
          best = std::min(best, s_[k].d + slope_ * std::hypot(s_[k].p.x - x, s_[k].p.y - y));
        continue;
      }
      if (top + 2 > 128) continue;  // depth is bounded by the build (log2 of the samples)
      stack[top++] = n.right;
      stack[top++] = n.left;
    }
    return best;
  }

 private:
  struct Node {
    double x0, y0, x1, y1, dmin;
    std::int32_t lo, hi, left = -1, right = -1;
  };

  std::int32_t build(std::int32_t lo, std::int32_t hi, int depth) {
    Node n{1e300, 1e300, -1e300, -1e300, 1e300, lo, hi};
    for (std::int32_t k = lo; k < hi; ++k) {
      n.x0 = std::min(n.x0, s_[k].p.x), n.x1 = std::max(n.x1, s_[k].p.x);
      n.y0 = std::min(n.y0, s_[k].p.y), n.y1 = std::max(n.y1, s_[k].p.y);
      n.dmin = std::min(n.dmin, s_[k].d);
    }
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back(n);
    if (hi - lo <= 8 || depth > 60) return id;
    const std::int32_t mid = lo + (hi - lo) / 2;
    const bool by_x = n.x1 - n.x0 >= n.y1 - n.y0;
    std::nth_element(s_.begin() + lo, s_.begin() + mid, s_.begin() + hi,
                     [by_x](const Sample& a, const Sample& b) {
                       return by_x ? (a.p.x < b.p.x || (a.p.x == b.p.x && a.p.y < b.p.y))
                                   : (a.p.y < b.p.y || (a.p.y == b.p.y && a.p.x < b.p.x));
                     });
    const std::int32_t l = build(lo, mid, depth + 1), r = build(mid, hi, depth + 1);
    nodes_[id].left = l;
    nodes_[id].right = r;
    return id;
  }

  std::vector<Sample> s_;
  std::vector<Node> nodes_;
  double slope_;
};

// Samples of the feature distance along every segment where it binds: its ends, and
// midpoints while a piece is longer than half the smaller distance (or limit) at its ends
// (the distance is 1-Lipschitz along a segment, so the graded cap between samples stays
// within a small factor of it). limit(p): the distance from which a feature is left to
// the unit mesh at p (kBindShare of the field's largest size there).
template <class Limit>
std::vector<Sample> boundary_samples(SegmentGrid& grid, Limit&& limit) {
  std::vector<Sample> out;
  struct Piece {
    double t0, d0, t1, d1;
    int depth;
  };
  std::vector<Piece> work;
  const auto& segs = grid.segs();
  for (std::size_t i = 0; i < segs.size(); ++i) {
    const Seg& s = segs[i];
    const auto id = static_cast<std::int32_t>(i);
    auto sample = [&](double t) {
      const Vec2 p{s.pa.x + t * (s.pb.x - s.pa.x), s.pa.y + t * (s.pb.y - s.pa.y)};
      const double lim = limit(p), d = grid.feature_distance(p, id, lim);
      if (d < lim) out.push_back({p, d});
      return d;  // at most lim
    };
    const double len = std::hypot(s.pb.x - s.pa.x, s.pb.y - s.pa.y);
    work.assign(1, {0, sample(0), 1, sample(1), 0});
    while (!work.empty()) {
      const Piece w = work.back();
      work.pop_back();
      const double dm = std::min(w.d0, w.d1);
      if (w.depth >= 24 || !((w.t1 - w.t0) * len > 0.5 * dm)) continue;
      const double tm = 0.5 * (w.t0 + w.t1), d = sample(tm);
      work.push_back({tm, d, w.t1, w.d1, w.depth + 1});
      work.push_back({w.t0, w.d0, tm, d, w.depth + 1});
    }
  }
  return out;
}

// The largest size of metric m: 1 / sqrt of its smaller eigenvalue (+inf when m is not
// positive definite: no bound).
double largest_size(const Metric2& m) {
  const double tr = m.m11 + m.m22, det = m.m11 * m.m22 - m.m12 * m.m12;
  const double l2 = tr / 2 - std::sqrt(std::max(0.0, tr * tr / 4 - det));
  return l2 > 0 && std::isfinite(tr) ? 1 / std::sqrt(l2) : std::numeric_limits<double>::infinity();
}

// M intersected with the isotropic metric of size h (eigenvalues raised to 1 / h^2,
// eigenvectors kept): the largest metric whose unit ball lies in both unit balls.
Metric2 cap_size(const Metric2& m, double h) {
  const double mu = 1 / (h * h);
  const double tr = m.m11 + m.m22, det = m.m11 * m.m22 - m.m12 * m.m12;
  if (!(m.m11 > 0) || !(det > 0) || !std::isfinite(tr)) return m;  // reported by the caller
  const double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l1 = tr / 2 + disc, l2 = tr / 2 - disc;
  if (l2 >= mu) return m;
  if (l1 <= mu) return Metric2::iso(h);
  double ex = m.m12, ey = l2 - m.m11;  // eigenvector of l2
  if (std::abs(ex) + std::abs(ey) < 1e-300) ex = l2 - m.m22, ey = m.m12;
  const double n = std::hypot(ex, ey);
  if (!(n > 0)) return m.m11 <= m.m22 ? Metric2{mu, 0, m.m22} : Metric2{m.m11, 0, mu};
  ex /= n, ey /= n;
  const double d = mu - l2;
  return {m.m11 + d * ex * ex, m.m12 + d * ex * ey, m.m22 + d * ey * ey};
}

}  // namespace

void apply_feature_size(MeshState& ms) {
  if (!ms.opt.feature_size || !ms.opt.refine || !ms.refine_ok) return;
  std::vector<Seg> segs;
  for (const SegRec& s : ms.segs)
    if (s.alive && s.input >= 0) segs.push_back({s.a, s.b, ms.tri.point(s.a), ms.tri.point(s.b)});
  if (segs.size() < 2) return;
  const bool uniform = ms.size.kind == SizeSpec::Kind::Uniform;
  SegmentGrid grid(std::move(segs));
  std::vector<Sample> samples = boundary_samples(
      grid, [&](Vec2 p) { return kBindShare * largest_size(ms.metric(p.x, p.y)); });
  if (samples.empty() || ms.field_error) return;  // the features never bind: the same mesh
  const double g = ms.opt.boundary_gradation > 1 ? ms.opt.boundary_gradation : kDefaultGradation;
  auto cap = std::make_shared<const GradedCap>(std::move(samples), g - 1);
  SizeSpec& f = ms.field;
  if (uniform) {
    f.kind = SizeSpec::Kind::Scalar;
    f.size = [cap, h = ms.h_uniform](double x, double y) { return (*cap)(x, y, h); };
  } else if (f.kind == SizeSpec::Kind::Scalar) {
    f.size = [cap, field = f.size](double x, double y) {
      const double h = field(x, y);
      return h > 0 ? (*cap)(x, y, h) : h;  // invalid values reach the check
    };
  } else {
    f.metric = [cap, field = f.metric](double x, double y) {
      const Metric2 m = field(x, y);
      const double h = (*cap)(x, y, largest_size(m));
      return std::isfinite(h) ? cap_size(m, h) : m;
    };
  }
}

}  // namespace uvmesh::m2d::detail
