// Stage 2, one face (reference chapter §7.6.2): the (u,v) PSLG is built from the edge
// nodes through each use's pcurve at the same curve parameters (never by projection);
// mesher2d meshes it under the induced metric M_uv = J^T M3 J; the vertices are mapped
// back through sigma and the mesh is improved in 3D.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>
#include <unordered_map>

#include "internal.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface::detail {

namespace {

// Parameter of a use's pcurve for the curve parameter t: the same when the use's range is
// the edge's (OCC's SameParameter), otherwise the affine map between the two ranges.
double pcurve_param(const geom::Edge& e, const geom::EdgeUse& u, double t) {
  if (u.range.lo == e.range.lo && u.range.hi == e.range.hi) return t;
  const double L = e.range.length();
  const double s = L != 0 ? (t - e.range.lo) / L : 0.0;
  return u.range.lo + s * u.range.length();
}

// A degenerate edge (pole, cone apex) is a run of (u,v) points mapping to one 3D vertex.
// How many: as many as the first ring of triangles around the pole will have, estimated
// as the metric length of the pole side moved inward until sigma moves by about one
// local size (on the side itself the induced metric is singular and capped).
int pole_segments(const geom::EdgeUse& use, const geom::Surface& s,
                  const param::FaceSizeField& field, const geom::Box2& box) {
  const geom::Vec2 a = use.pcurve->point(use.range.lo), b = use.pcurve->point(use.range.hi);
  const geom::Vec2 mid = 0.5 * (a + b);
  const geom::Vec2 centre{box.u.mid(), box.v.mid()};
  const geom::Vec3 pole = s.point(mid.x, mid.y);
  const param::Metric3 m3 = field.metric3(mid.x, mid.y);
  const auto sz = m3.sizes();
  const double h = *std::min_element(sz.begin(), sz.end());
  double frac = 1e-3;
  geom::Vec2 shift{0.0};
  for (; frac < 0.5; frac *= 2) {
    shift = frac * (centre - mid);
    if (glm::length(s.point(mid.x + shift.x, mid.y + shift.y) - pole) >= 0.5 * h) break;
  }
  double L = 0;
  const int n = 32;
  geom::Vec2 prev = a + shift;
  for (int k = 1; k <= n; ++k) {
    const geom::Vec2 q = use.pcurve->point(use.range.at(double(k) / n)) + shift;
    const param::Metric2 mm = field.metric_uv(0.5 * (prev.x + q.x), 0.5 * (prev.y + q.y));
    L += mm.length(q - prev);
    prev = q;
  }
  return std::clamp(static_cast<int>(std::lround(L)), 1, 512);
}

// The induced metric on a lazily filled (u,v) grid, interpolated bilinearly component
// by component (a convex combination of SPD tensors is SPD). mesher2d asks for the metric
// many times per vertex (edge sampling, eq. 7.10; relocation); each exact value costs a
// surface evaluation and two 3x3 eigen-decompositions, while the field behind it is
// itself a smooth background grid (§7.5.1). Only the cells the mesher visits are filled.
//
// The 3D field is smooth, but J need not be: where a spline patch's parametrization is
// strongly non-uniform (knots crowded in one corner, a nearly collapsed control row, a
// terrain patch whose (u,v) speed varies across it) J^T J changes by large factors
// inside one cell of the 64 x 64 grid. Interpolated there, the (u,v) metric is right at
// the nodes and wrong in between, and the mesh follows the wrong sizes. So a cell is
// checked against the exact metric at its centre when first visited, and split in four
// (recursively, a quadtree, down to kMaxDepth levels) while the interpolated metric
// measures some direction more than kTol off the exact one. Hanging nodes make the field
// slightly discontinuous across a split cell's side, which the mesher's edge sampling
// tolerates.
//
// The grid is a cache: every node is an exact induced metric (a surface evaluation with
// derivatives), and it pays only where the mesher's queries (every quarter of a unit
// length along each edge it measures, mesher2d's sample_edge) fall several to a cell.
// The top level therefore has about kCellsPerUnit cells per unit length in each
// direction (grid_cells), not a fixed 64 x 64: on a face a few elements across (a
// subdivision patch, about 8 on catmark_pawn) 64 cells were a tenth of an element, and
// nearly every query filled new nodes (1.66M exact metrics for 2.28M queries on
// catmark_pawn, 35% of its CPU time; 0.34M with 16 cells). Cells of about one unit are
// far finer than the variation of the 3D field (sizes change by at most the gradation,
// 1.3, per unit), and where J varies faster the cells split as before.
class UvMetricGrid {
 public:
  // nu x nv cells at the top level (see grid_cells).
  UvMetricGrid(const param::FaceSizeField& field, const geom::Box2& box, unsigned singular_sides,
               int nu, int nv)
      : field_(field),
        box_(box),
        singular_(singular_sides),
        nu_(nu),
        nv_(nv),
        vals_(static_cast<std::size_t>((nu + 1) * (nv + 1))),
        has_(vals_.size(), 0),
        state_(static_cast<std::size_t>(nu * nv), kUnknown) {}
  m2d::Metric2 operator()(double u, double v) {
    const double fu = frac(box_.u, u), fv = frac(box_.v, v);
    int level = 0;
    for (;;) {
      const int cu = nu_ << level, cv = nv_ << level;
      const int i = std::min(static_cast<int>(fu * cu), cu - 1);
      const int j = std::min(static_cast<int>(fv * cv), cv - 1);
      const double tu = fu * cu - i, tv = fv * cv - j;
      std::int8_t& st = state(level, i, j);
      if (st == kUnknown) st = split_needed(level, i, j) ? kSplit : kLeaf;
      if (st == kLeaf) {
        const param::Metric2 m = bilinear(level, i, j, tu, tv);
        return {m(0, 0), m(0, 1), m(1, 1)};
      }
      ++level;
    }
  }

 private:
  static constexpr int kMaxDepth = 8;
  static constexpr double kTol = 1.25;  // ratio of metric lengths, either way
  enum : std::int8_t { kUnknown = 0, kLeaf = 1, kSplit = 2 };

  static double frac(const geom::Interval& r, double x) {
    const double len = r.length() > 0 ? r.length() : 1.0;
    return std::clamp((x - r.lo) / len, 0.0, 1.0);
  }
  std::int8_t& state(int level, int i, int j) {
    if (level == 0) return state_[static_cast<std::size_t>(i * nv_ + j)];
    return deep_state_[key(level, i, j)];
  }
  static std::uint64_t key(int level, int i, int j) {
    return (static_cast<std::uint64_t>(level) << 56) | (static_cast<std::uint64_t>(i) << 28) |
           static_cast<std::uint64_t>(j);
  }
  // Node (i, j) of level `level`: nodes shared with a coarser level are stored once, at
  // the coarsest level that has them.
  const param::Metric2& node(int level, int i, int j) {
    while (level > 0 && i % 2 == 0 && j % 2 == 0) i /= 2, j /= 2, --level;
    if (level == 0) {
      const auto k = static_cast<std::size_t>(i * (nv_ + 1) + j);
      if (!has_[k]) {
        vals_[k] = exact(0, i, j);
        has_[k] = 1;
      }
      return vals_[k];
    }
    const std::uint64_t k = key(level, i, j);
    auto it = deep_vals_.find(k);
    if (it == deep_vals_.end()) it = deep_vals_.emplace(k, exact(level, i, j)).first;
    return it->second;
  }
  param::Metric2 exact(int level, double i, double j) const {
    return field_.metric_uv(box_.u.at(i / static_cast<double>(nu_ << level)),
                            box_.v.at(j / static_cast<double>(nv_ << level)));
  }
  param::Metric2 bilinear(int level, int i, int j, double tu, double tv) {
    const param::Metric2 &a = node(level, i, j), &b = node(level, i + 1, j),
                         &c = node(level, i, j + 1), &d = node(level, i + 1, j + 1);
    const double w00 = (1 - tu) * (1 - tv), w10 = tu * (1 - tv), w01 = (1 - tu) * tv, w11 = tu * tv;
    param::Metric2 m = a;
    for (int r = 0; r < 2; ++r)
      for (int k = r; k < 2; ++k) {
        m.m[r][k] = w00 * a(r, k) + w10 * b(r, k) + w01 * c(r, k) + w11 * d(r, k);
        m.m[k][r] = m.m[r][k];
      }
    return m;
  }
  // The interpolated metric at the cell's centre against the exact one, along the two
  // axes and the two diagonals of the cell.
  bool split_needed(int level, int i, int j) {
    if (level >= kMaxDepth) return false;
    // Cells on a singular side (a pole: a cone's apex, a sphere's) stay as they are: J
    // is singular there by construction and the mesher's pole handling expects the
    // smoothed field (splitting them made a fold at occt_cone_catia's apex).
    if (((singular_ & geom::kSideUMin) && i == 0) ||
        ((singular_ & geom::kSideUMax) && i == (nu_ << level) - 1) ||
        ((singular_ & geom::kSideVMin) && j == 0) ||
        ((singular_ & geom::kSideVMax) && j == (nv_ << level) - 1))
      return false;
    const param::Metric2 mi = bilinear(level, i, j, 0.5, 0.5);
    const param::Metric2 me = exact(level, i + 0.5, j + 0.5);
    const double du = box_.u.length(), dv = box_.v.length();
    const double dirs[4][2] = {{du, 0}, {0, dv}, {du, dv}, {du, -dv}};
    for (const auto& d : dirs) {
      const double li =
          mi(0, 0) * d[0] * d[0] + 2 * mi(0, 1) * d[0] * d[1] + mi(1, 1) * d[1] * d[1];
      const double le =
          me(0, 0) * d[0] * d[0] + 2 * me(0, 1) * d[0] * d[1] + me(1, 1) * d[1] * d[1];
      if (!(le > 0) || !(li > 0)) continue;  // a degenerate point: nothing to compare
      const double r = li / le;              // squared ratio of lengths
      if (r > kTol * kTol || r < 1 / (kTol * kTol)) return true;
    }
    return false;
  }
  const param::FaceSizeField& field_;
  geom::Box2 box_;
  unsigned singular_;  ///< geom::SideBits of the surface's poles
  int nu_, nv_;
  std::vector<param::Metric2> vals_;
  std::vector<char> has_;
  std::vector<std::int8_t> state_;
  std::unordered_map<std::uint64_t, std::int8_t> deep_state_;
  std::unordered_map<std::uint64_t, param::Metric2> deep_vals_;
};

// Top-level cells of a face's UvMetricGrid along u and v, from its metric length across
// the box in each direction (the largest metric speed of the samples times the side):
// kCellsPerUnit cells per unit length, as a power of two between 16 (the size field's own
// grid, FaceSizeField's 17 x 17 nodes, whose lines then are grid lines) and 64 (the fixed
// size before; a face more than 32 units across keeps it). Exact metrics over
// catmark_car, pawn, nonman_edges and pole64: 2 cells per unit 4.4M, 1 cell 2.7M, 1 cell
// down to 8 x 8 2.2M, with the same shares of Q < 1.5 to 0.006 (but at 8 the size field's
// grid lines fall inside cells).
// A face with a pole keeps 64 x 64: the cells along a singular side are never split
// (UvMetricGrid::split_needed), so their size is the width of the smoothed field the
// pole handling sees; 16 cells there left two triangles of Q 3.3-3.6 at occt_crankarm's
// face 45 (test "caps wedged between sub-hmin features").
// CAD surfaces keep 64 x 64 too: the counts from the metric speed moved gmsh_t20_part at
// --hmax D/40 --angle 30 from 0 to 4 self-intersecting pairs and one triangle of Q 4.5
// (faces 1 and 4). A subdivision patch (SurfaceKind::Other) is one smooth polynomial
// piece a few elements across, where the count from the speed is what saves the time.
constexpr double kCellsPerUnit = 1.0;
std::array<int, 2> grid_cells(const std::vector<param::Metric2>& samples, const geom::Box2& box,
                              unsigned singular_sides, geom::SurfaceKind kind) {
  if (singular_sides != 0u || kind != geom::SurfaceKind::Other) return {64, 64};
  double su = 0, sv = 0;
  for (const param::Metric2& g : samples) {
    if (std::isfinite(g(0, 0)) && g(0, 0) > 0) su = std::max(su, std::sqrt(g(0, 0)));
    if (std::isfinite(g(1, 1)) && g(1, 1) > 0) sv = std::max(sv, std::sqrt(g(1, 1)));
  }
  auto cells = [](double units) {
    int n = 16;
    while (n < 64 && n < kCellsPerUnit * units) n *= 2;
    return n;
  };
  return {cells(su * box.u.length()), cells(sv * box.v.length())};
}

std::string fmt_uv(const geom::Vec2& p) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << p.x << ", " << p.y << ")";
  return o.str();
}

// A face's edges -> their (triangle, opposite corner) uses, two for an interior edge:
// records sorted by edge, then triangle and corner (the order a std::map of vectors gave,
// without a node and a vector per edge; that map was a third of the chordal repair's time).
struct EdgeUses {
  struct Use {
    int a, b;  // a < b
    std::size_t t;
    int i;
    bool operator<(const Use& o) const {
      return std::tie(a, b, t, i) < std::tie(o.a, o.b, o.t, o.i);
    }
  };
  std::vector<Use> recs;
  explicit EdgeUses(const LocalMesh& lm) {
    recs.reserve(3 * lm.tris.size());
    for (std::size_t t = 0; t < lm.tris.size(); ++t)
      for (int i = 0; i < 3; ++i) {
        const int a = lm.tris[t][(i + 1) % 3], b = lm.tris[t][(i + 2) % 3];
        recs.push_back({std::min(a, b), std::max(a, b), t, i});
      }
    std::sort(recs.begin(), recs.end());
  }
  // [first, last) of edge a-b's records.
  std::pair<std::vector<Use>::const_iterator, std::vector<Use>::const_iterator> of(int a,
                                                                                   int b) const {
    const Use key{std::min(a, b), std::max(a, b), 0, 0};
    const auto lo = std::lower_bound(recs.begin(), recs.end(), key);
    auto hi = lo;
    while (hi != recs.end() && hi->a == key.a && hi->b == key.b) ++hi;
    return {lo, hi};
  }
  // Calls f(a, b, number of uses) once per edge, in edge order.
  template <class F>
  void for_each_edge(F&& f) const {
    for (std::size_t k = 0; k < recs.size();) {
      std::size_t e = k + 1;
      while (e < recs.size() && recs[e].a == recs[k].a && recs[e].b == recs[k].b) ++e;
      f(recs[k].a, recs[k].b, e - k);
      k = e;
    }
  }
};

// A new interior point of the face at (u,v) uv; -1 where sigma is not finite.
int add_local_point(LocalMesh& lm, const geom::Surface& s, const geom::Vec2& uv, double scale) {
  const geom::Vec3 q = s.point(uv.x, uv.y);
  if (!std::isfinite(q.x + q.y + q.z)) return -1;
  lm.uv.push_back(uv);
  lm.p.push_back(q);
  lm.global.push_back(-1);
  lm.fixed.push_back(0);
  lm.scale.push_back(scale);
  return static_cast<int>(lm.uv.size()) - 1;
}

// A new point q splits a-b in 3D when it is at least a thousandth of |ab| from both.
bool splits_in_3d(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& q) {
  const double l = 1e-3 * glm::length(b - a);
  return glm::length(q - a) > l && glm::length(q - b) > l;
}

// Splits each edge of to_split (two uses, neither triangle split yet this round: touched)
// at its (u,v) midpoint, 2 triangles to 4; returns the splits made.
int split_edges_at_uv_midpoints(LocalMesh& lm, const geom::Surface& s, const EdgeUses& uses,
                                const std::vector<std::pair<int, int>>& to_split,
                                std::vector<char>& touched) {
  int splits = 0;
  for (auto [a, b] : to_split) {
    const auto u = uses.of(a, b).first;
    const std::size_t t1 = u[0].t, t2 = u[1].t;
    const int i1 = u[0].i, i2 = u[1].i;
    if (touched[t1] || touched[t2]) continue;
    // The (u,v) midpoint lies on the shared (u,v) edge: the four halves stay CCW.
    // Where the surface folds over itself (occt_mesh_hang's swept tube: sigma_u x
    // sigma_v vanishes along lines and the normal reverses across them) the midpoint can
    // map onto an end point or onto a corner opposite the edge: the split would only add
    // zero-area triangles, round after round (6 copies of one point there with 8 rounds).
    const geom::Vec2 mid = 0.5 * (lm.uv[a] + lm.uv[b]);
    const geom::Vec3 q = s.point(mid.x, mid.y);
    const int c1 = lm.tris[t1][i1], c2 = lm.tris[t2][i2];  // the corners opposite a-b
    if (!splits_in_3d(lm.p[a], lm.p[b], q) || !splits_in_3d(lm.p[a], lm.p[c1], q) ||
        !splits_in_3d(lm.p[a], lm.p[c2], q))
      continue;
    const int n = add_local_point(lm, s, mid, 0.5 * (lm.scale[a] + lm.scale[b]));
    if (n < 0) continue;
    for (const auto& [t, i] : {std::pair{t1, i1}, std::pair{t2, i2}}) {
      const auto T = lm.tris[t];  // corner c opposite the edge x-y, CCW
      const int c = T[i], x = T[(i + 1) % 3], y = T[(i + 2) % 3];
      lm.tris[t] = {c, x, n};
      lm.tris.push_back({c, n, y});
      touched[t] = 1;
    }
    ++splits;
  }
  return splits;
}

// One round of the flatness repair of mesh_face (see there): returns the splits made.
int flat_split_round(LocalMesh& lm, const geom::Surface& s, const geom::Box2& box, double rel) {
  const EdgeUses uses(lm);
  std::vector<std::pair<int, int>> to_split;
  uses.for_each_edge([&](int a, int b, std::size_t n) {
    if (n != 2) return;  // on the face's boundary: the curves' discretization
    // A chord between two boundary nodes: an edge a neighbouring face can have too.
    if (!lm.fixed[static_cast<std::size_t>(a)] || !lm.fixed[static_cast<std::size_t>(b)]) return;
    const geom::Vec3 x = 0.5 * (lm.p[a] + lm.p[b]);
    const double len = glm::length(lm.p[b] - lm.p[a]), lim = rel * len;
    // The distance from the chord's midpoint to the surface (not to sigma at the (u,v)
    // midpoint, which moves along a flat but unevenly parametrized surface too). sigma
    // there is a surface point: within lim of x, so is the surface, no projection needed.
    const geom::Vec2 mid = 0.5 * (lm.uv[a] + lm.uv[b]);
    if (glm::length(s.point(mid.x, mid.y) - x) <= lim) return;
    const Projection pr = project_to_surface(s, x, mid, box, len);
    if (pr.converged && pr.distance > lim) to_split.push_back({a, b});
  });
  std::vector<char> touched(lm.tris.size(), 0);
  return split_edges_at_uv_midpoints(lm, s, uses, to_split, touched);
}

// One round of the chordal repair of mesh_face (see there): returns the splits made.
int chordal_split_round(LocalMesh& lm, const geom::Surface& s, const geom::Box2& box, double lim) {
  auto ccw = [](const geom::Vec2& a, const geom::Vec2& b, const geom::Vec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0;
  };
  auto deviates = [&](const geom::Vec3& x, const geom::Vec2& uv0, double scale, geom::Vec2* foot) {
    // sigma(uv0) is a point of the surface: when it is within lim of x, so is the
    // surface, and the Newton projection (several evaluations with derivatives; 14% of
    // the CPU time of meshing catmark_pawn) is not needed.
    if (!foot) {
      const geom::Vec3 q = s.point(uv0.x, uv0.y);
      if (glm::length(q - x) <= lim) return false;
    }
    const Projection pr = project_to_surface(s, x, uv0, box, scale);
    if (foot) *foot = pr.uv;
    return pr.converged && pr.distance > lim;
  };
  const std::size_t nt = lm.tris.size();
  // Interior edges -> their two (triangle, opposite corner) uses.
  const EdgeUses uses(lm);
  auto interior = [&](int a, int b) {
    const auto [lo, hi] = uses.of(a, b);
    return hi - lo == 2 && !(lm.fixed[a] && lm.fixed[b]);
  };
  std::vector<std::pair<int, int>> to_split;
  std::vector<std::size_t> centroid_split;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto T = lm.tris[t];
    const geom::Vec3 pc = (lm.p[T[0]] + lm.p[T[1]] + lm.p[T[2]]) / 3.0;
    double len[3];
    for (int i = 0; i < 3; ++i) len[i] = glm::length(lm.p[T[(i + 2) % 3]] - lm.p[T[(i + 1) % 3]]);
    if (!deviates(pc, (lm.uv[T[0]] + lm.uv[T[1]] + lm.uv[T[2]]) / 3.0,
                  std::max({len[0], len[1], len[2]}), nullptr))
      continue;
    int best = -1;
    for (int i = 0; i < 3; ++i)
      if (interior(T[(i + 1) % 3], T[(i + 2) % 3]) && (best < 0 || len[i] > len[best])) best = i;
    if (best >= 0)
      to_split.push_back({T[(best + 1) % 3], T[(best + 2) % 3]});
    else
      centroid_split.push_back(t);
  }
  uses.for_each_edge([&](int a, int b, std::size_t) {
    if (!interior(a, b)) return;
    if (deviates(0.5 * (lm.p[a] + lm.p[b]), 0.5 * (lm.uv[a] + lm.uv[b]),
                 glm::length(lm.p[b] - lm.p[a]), nullptr))
      to_split.push_back({a, b});
  });
  std::vector<char> touched(nt, 0);
  int splits = split_edges_at_uv_midpoints(lm, s, uses, to_split, touched);
  for (std::size_t t : centroid_split) {
    if (touched[t]) continue;
    const auto T = lm.tris[t];
    const geom::Vec2 uc = (lm.uv[T[0]] + lm.uv[T[1]] + lm.uv[T[2]]) / 3.0;
    geom::Vec2 foot = uc;
    const geom::Vec3 pc = (lm.p[T[0]] + lm.p[T[1]] + lm.p[T[2]]) / 3.0;
    deviates(pc, uc, glm::length(lm.p[T[1]] - lm.p[T[0]]), &foot);
    // The foot, when it lies inside the (u,v) triangle; else the (u,v) centroid.
    if (!ccw(lm.uv[T[0]], lm.uv[T[1]], foot) || !ccw(lm.uv[T[1]], lm.uv[T[2]], foot) ||
        !ccw(lm.uv[T[2]], lm.uv[T[0]], foot))
      foot = uc;
    {
      const geom::Vec3 q = s.point(foot.x, foot.y);
      if (!splits_in_3d(lm.p[T[0]], lm.p[T[1]], q) || !splits_in_3d(lm.p[T[1]], lm.p[T[2]], q))
        continue;
    }
    const int n =
        add_local_point(lm, s, foot, (lm.scale[T[0]] + lm.scale[T[1]] + lm.scale[T[2]]) / 3.0);
    if (n < 0) continue;
    lm.tris[t] = {T[0], T[1], n};
    lm.tris.push_back({T[1], T[2], n});
    lm.tris.push_back({T[2], T[0], n});
    ++splits;
  }
  return splits;
}

// A face whose (u,v) boundary is unusable -- its pcurves cross, two nodes coincide, the
// loop runs clockwise -- after the crossing rounds of the mesher (mesher.cpp). In the CAD
// corpus these are slivers: occt_caxif_b1's face 58 lies between two curves a few
// micrometres apart, whose pcurves, approximations both, cross each other; the part is
// 3 orders of magnitude below hmin. The face is triangulated from its boundary nodes
// alone, in 3D: the triangulation of the closed polygon that minimizes the sum of the
// triangles' perimeters (each diagonal counts twice, so it is the minimum-weight
// triangulation; on a strip it joins the two sides by their shortest rungs), by the
// O(n^3) dynamic programme over sub-polygons. The result is kept only if it is a
// manifold disc (no edge used three times, no triangle with a repeated node) and lies
// within the chordal tolerance at every centroid and edge midpoint (measured by Newton
// projection, as the report measures); otherwise the face stays failed. Triangles are
// turned to agree with sigma_u x sigma_v, as the (u,v)-CCW triangles of a meshed face are.
constexpr std::size_t kMaxBoundaryTriangulation = 400;  // nodes; O(n^3) work

bool triangulate_from_boundary(FaceMesh& out, const geom::Face& f, const geom::Surface& s,
                               const std::vector<NodeId>& gid_in,
                               const std::vector<geom::Vec2>& uv_in,
                               const std::vector<geom::Vec3>& node_points, double chordal_tol,
                               std::string* why) {
  // The polygon: consecutive repeats of a node (a pole's run of (u,v) points) are one corner.
  std::vector<NodeId> g;
  std::vector<geom::Vec2> uv;
  for (std::size_t i = 0; i < gid_in.size(); ++i)
    if (g.empty() || g.back() != gid_in[i]) g.push_back(gid_in[i]), uv.push_back(uv_in[i]);
  while (g.size() > 1 && g.back() == g.front()) g.pop_back(), uv.pop_back();
  const std::size_t n = g.size();
  if (n < 3 || n > kMaxBoundaryTriangulation) {
    *why = std::to_string(n) + " boundary nodes";
    return false;
  }
  std::vector<geom::Vec3> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = node_points[static_cast<std::size_t>(g[i])];
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> W(n * n, 0.0);
  std::vector<std::uint16_t> K(n * n, 0);
  auto cost = [&](std::size_t i, std::size_t k, std::size_t j) {
    if (g[i] == g[k] || g[k] == g[j] || g[i] == g[j]) return inf;  // a seam node seen twice
    return glm::length(p[k] - p[i]) + glm::length(p[j] - p[k]) + glm::length(p[i] - p[j]);
  };
  for (std::size_t len = 2; len < n; ++len)
    for (std::size_t i = 0; i + len < n; ++i) {
      const std::size_t j = i + len;
      double best = inf;
      std::size_t bk = i + 1;
      for (std::size_t k = i + 1; k < j; ++k) {
        const double c = W[i * n + k] + W[k * n + j] + cost(i, k, j);
        if (c < best) best = c, bk = k;
      }
      W[i * n + j] = best;
      K[i * n + j] = static_cast<std::uint16_t>(bk);
    }
  if (!(W[n - 1] < inf)) {
    *why = "no triangulation without a repeated node";
    return false;
  }
  std::vector<std::array<std::size_t, 3>> tris;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j < i + 2) continue;
    const std::size_t k = K[i * n + j];
    tris.push_back({i, k, j});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
  // A manifold disc: every edge between two nodes in at most two triangles, a boundary
  // edge in one (a diagonal may join two nodes that are already neighbours elsewhere).
  std::map<std::pair<NodeId, NodeId>, int> use;
  for (const auto& t : tris)
    for (int e = 0; e < 3; ++e) {
      const NodeId a = g[t[e]], b = g[t[(e + 1) % 3]];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, c] : use)
    if (c > 2) {
      *why = "the triangulation is not a manifold";
      return false;
    }
  // Where the two sides of a strip cross in space (occt_caxif_b1's face 251: a circle
  // and a B-spline copy of it, crossing several times), every triangulation of the
  // polygon folds through itself: two triangles without a common node must not meet.
  {
    // The report's own pair test (exact; pairs sharing a node count when they overlap
    // beyond it), on the face's triangles numbered by their global nodes.
    SurfaceMesh sm;
    std::map<NodeId, NodeId> local;
    for (std::size_t i = 0; i < n; ++i)
      if (local.emplace(g[i], static_cast<NodeId>(sm.points.size())).second)
        sm.points.push_back(p[i]);
    for (const auto& t : tris)
      sm.triangles.push_back({local[g[t[0]]], local[g[t[1]]], local[g[t[2]]]});
    for (std::size_t x = 0; x < tris.size(); ++x)
      for (std::size_t y = x + 1; y < tris.size(); ++y)
        if (triangles_intersect(sm, static_cast<TriId>(x), static_cast<TriId>(y))) {
          *why =
              "its boundary triangulation intersects itself (the sides of the strip cross in "
              "space)";
          return false;
        }
  }
  // Orientation: by area-weighted agreement with the surface normal at the centroids.
  double agree = 0;
  for (const auto& t : tris) {
    const geom::Vec3 nt = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    const geom::Vec2 c = (uv[t[0]] + uv[t[1]] + uv[t[2]]) / 3.0;
    const geom::SurfacePoint sp = s.eval(c.x, c.y);
    agree += glm::dot(nt, sp.normal());
  }
  if (agree < 0)
    for (auto& t : tris) std::swap(t[1], t[2]);
  if (chordal_tol > 0) {
    double worst = 0;
    for (const auto& t : tris) {
      const geom::Vec3 x[4] = {(p[t[0]] + p[t[1]] + p[t[2]]) / 3.0, 0.5 * (p[t[0]] + p[t[1]]),
                               0.5 * (p[t[1]] + p[t[2]]), 0.5 * (p[t[2]] + p[t[0]])};
      const geom::Vec2 u[4] = {(uv[t[0]] + uv[t[1]] + uv[t[2]]) / 3.0, 0.5 * (uv[t[0]] + uv[t[1]]),
                               0.5 * (uv[t[1]] + uv[t[2]]), 0.5 * (uv[t[2]] + uv[t[0]])};
      const double scale = std::max({glm::length(p[t[1]] - p[t[0]]), glm::length(p[t[2]] - p[t[1]]),
                                     glm::length(p[t[0]] - p[t[2]])});
      for (int k = 0; k < 4; ++k) {
        const Projection pr = project_to_surface(s, x[k], u[k], f.uv_box, scale);
        if (pr.converged) worst = std::max(worst, pr.distance);
      }
    }
    if (worst > chordal_tol) {
      std::ostringstream o;
      o << "its boundary triangulation deviates " << worst << " from the surface (tolerance "
        << chordal_tol << ")";
      *why = o.str();
      return false;
    }
  }
  out = {};
  for (auto t : tris) {
    if (f.reversed) std::swap(t[1], t[2]);
    out.tris.push_back({g[t[0]], g[t[1]], g[t[2]]});
    out.tri_uv.push_back({uv[t[0]], uv[t[1]], uv[t[2]]});
  }
  out.stats.boundary_nodes = static_cast<int>(n);
  out.stats.triangles = static_cast<int>(out.tris.size());
  out.from_boundary = true;
  return true;
}

}  // namespace

FaceMesh mesh_face(const geom::Model& m, geom::Id fid, const std::vector<EdgeNodes>& edges,
                   const std::vector<geom::Vec3>& node_points, const param::FaceSizeField& field,
                   const MeshOptions& opt, bool boundary_fallback) {
  FaceMesh out;
  out.stats.face = fid;
  const geom::Face& f = m.faces[static_cast<std::size_t>(fid)];
  const geom::Surface& s = *f.surface;

  // ---- the (u,v) PSLG: one point per edge node per use, in loop order.
  m2d::Pslg in;
  std::vector<NodeId> gid;      // PSLG point -> global node
  std::vector<geom::Id> pedge;  // PSLG point -> model edge (for messages)
  std::vector<geom::Id> sedge;  // PSLG segment -> model edge
  // PSLG point -> curve parameters of the piece of its edge starting there (NaN for a
  // pole), so that a crossing names the pieces to split (FaceMesh::refine_at).
  std::vector<std::array<double, 2>> piece;
  std::vector<std::array<double, 2>> spiece;  // PSLG segment -> its piece
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<const geom::EdgeUse*> embedded;  // INTERNAL uses: open chains, added last
  // Boundary segments shorter than the proximity floor exist only because their CAD edge
  // is shorter than the floor (the 1D sizes stop there, proximity_floor()), and the edges
  // beside them are not graded below it. Their length is no size to grade the interior
  // from either: it refined the interior around them down to their length, against
  // boundary segments at the floor, and fans of needles joined the two (occt_caxif_b1:
  // edges of 0.00015 and 0.0028 mm, floor 0.31 mm; interior triangles of Q 3.8 and 3.5).
  const double seg_floor = proximity_floor(opt.size, m.bbox.diagonal());
  for (const geom::Loop& loop : f.loops) {
    const auto start = static_cast<m2d::VertId>(in.points.size());
    for (const geom::EdgeUse& use : loop.uses) {
      if (use.internal) {
        embedded.push_back(&use);
        continue;
      }
      const geom::Edge& e = m.edges[static_cast<std::size_t>(use.edge)];
      if (!use.pcurve) {
        out.error = "edge " + std::to_string(use.edge) + " has no (u,v) curve on this face";
        return out;
      }
      const std::size_t first = in.points.size();
      if (e.degenerate) {
        const int k = pole_segments(use, s, field, f.uv_box);
        const NodeId node = edges[static_cast<std::size_t>(use.edge)].node.front();
        for (int i = 0; i < k; ++i) {
          const double w = use.reversed ? 1.0 - double(i) / k : double(i) / k;
          const geom::Vec2 p = use.pcurve->point(use.range.at(w));
          in.points.push_back({p.x, p.y});
          gid.push_back(node);
          piece.push_back({nan, nan});
        }
      } else {
        const EdgeNodes& en = edges[static_cast<std::size_t>(use.edge)];
        const std::size_t n = en.t.size();
        for (std::size_t i = 0; i + 1 < n; ++i) {
          const std::size_t k = use.reversed ? n - 1 - i : i;
          const geom::Vec2 p = use.pcurve->point(pcurve_param(e, use, en.t[k]));
          in.points.push_back({p.x, p.y});
          gid.push_back(en.node[k]);
          piece.push_back({en.t[k], en.t[use.reversed ? k - 1 : k + 1]});
        }
      }
      for (std::size_t i = first; i < in.points.size(); ++i) pedge.push_back(use.edge);
    }
    const auto end = static_cast<m2d::VertId>(in.points.size());
    if (end == start) continue;  // a wire holding only embedded edges
    for (m2d::VertId i = start; i < end; ++i) {
      const m2d::VertId j = i + 1 < end ? i + 1 : start;
      // Marker edge id + 1; negative on a pole's collapsed side, which must not impose
      // its (u,v) length as a size (Options::boundary_gradation), and on a segment
      // shorter than the proximity floor (seg_floor).
      const geom::Id ei = pedge[static_cast<std::size_t>(i)];
      const bool pole = m.edges[static_cast<std::size_t>(ei)].degenerate;
      const bool sub_floor =
          glm::length(node_points[static_cast<std::size_t>(gid[static_cast<std::size_t>(j)])] -
                      node_points[static_cast<std::size_t>(gid[static_cast<std::size_t>(i)])]) <
          seg_floor;
      in.segments.push_back(
          {i, j, pole || sub_floor ? -(static_cast<int>(ei) + 1) : static_cast<int>(ei) + 1});
      sedge.push_back(ei);
      spiece.push_back(piece[static_cast<std::size_t>(i)]);
    }
  }
  // Embedded edges: every node, ends included, and a segment per piece (no closing
  // segment). Both sides of such a segment lie in the face, so its two half-edges cancel
  // in mesher2d's orientation vote; an end on the boundary is the same node as the
  // boundary's occurrence and merges with it below.
  for (const geom::EdgeUse* use : embedded) {
    const geom::Edge& e = m.edges[static_cast<std::size_t>(use->edge)];
    if (!use->pcurve || e.degenerate) continue;
    const EdgeNodes& en = edges[static_cast<std::size_t>(use->edge)];
    const auto first = static_cast<m2d::VertId>(in.points.size());
    for (std::size_t k = 0; k < en.t.size(); ++k) {
      const geom::Vec2 p = use->pcurve->point(pcurve_param(e, *use, en.t[k]));
      in.points.push_back({p.x, p.y});
      gid.push_back(en.node[k]);
      pedge.push_back(use->edge);
      piece.push_back({en.t[k], k + 1 < en.t.size() ? en.t[k + 1] : nan});
    }
    for (m2d::VertId i = first; i + 1 < static_cast<m2d::VertId>(in.points.size()); ++i)
      in.segments.push_back({i, i + 1, static_cast<int>(use->edge) + 1}),
          sedge.push_back(use->edge), spiece.push_back(piece[static_cast<std::size_t>(i)]);
  }
  // One node, one (u,v) point per side: the pcurves of two edges meeting at a vertex end
  // a few ulps apart, and a loop touching the seam at a vertex would then put a point a
  // hair off the seam's segment. Occurrences of a node closer than a millionth of the
  // (u,v) box are snapped together (mesher2d merges exact duplicates); the copies of a
  // node on the two sides of a seam are a period apart and stay distinct.
  {
    const double ext = std::max(f.uv_box.u.length(), f.uv_box.v.length());
    const double tol = 1e-6 * (ext > 0 ? ext : 1.0);
    std::vector<std::size_t> order(in.points.size());
    for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return gid[a] < gid[b]; });
    for (std::size_t k = 0; k < order.size();) {
      std::size_t e = k;
      while (e < order.size() && gid[order[e]] == gid[order[k]]) ++e;
      for (std::size_t i = k + 1; i < e; ++i)
        for (std::size_t j = k; j < i; ++j) {
          auto& p = in.points[order[i]];
          const auto& q = in.points[order[j]];
          if (std::abs(p.x - q.x) <= tol && std::abs(p.y - q.y) <= tol) {
            p = q;
            break;
          }
        }
      k = e;
    }
  }
  out.stats.boundary_nodes = static_cast<int>(in.points.size());
  if (in.segments.size() < 3) {
    out.error = "the face's loops have fewer than 3 boundary nodes in (u,v)";
    return out;
  }
  for (const auto& p : in.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      out.error = "a (u,v) curve gives a non-finite point";
      return out;
    }
  // An unusable (u,v) boundary, on the last try (mesher.cpp): the face is triangulated
  // from its boundary nodes when that is a manifold disc within the chordal tolerance
  // (triangulate_from_boundary); else the reason is added to the failure.
  const bool one_loop = embedded.empty() && in.segments.size() == in.points.size() &&
                        std::count_if(f.loops.begin(), f.loops.end(), [](const geom::Loop& l) {
                          return std::any_of(l.uses.begin(), l.uses.end(),
                                             [](const geom::EdgeUse& u) { return !u.internal; });
                        }) == 1;
  std::vector<geom::Vec2> uv_raw(in.points.size());
  for (std::size_t i = 0; i < uv_raw.size(); ++i) uv_raw[i] = {in.points[i].x, in.points[i].y};
  auto uv_failure = [&](std::string msg) {
    if (boundary_fallback && one_loop) {
      std::string why;
      if (triangulate_from_boundary(out, f, s, gid, uv_raw, node_points, opt.size.chordal_tol,
                                    &why)) {
        out.stats.face = fid;
        out.error.clear();
        out.refine_at.clear();
        return out;
      }
      msg += "; not triangulated from its boundary either: " + why;
    }
    out.error = std::move(msg);
    out.uv_defect = one_loop;  // worth the last try (mesher.cpp) when it was not this one
    return out;
  };

  // ---- mesher2d under M_uv = J^T M3 J (the field interpolates M3 on a background grid).
  // 9 x 9 exact samples: the grid's cell counts and the v scaling below.
  std::vector<param::Metric2> samples;
  samples.reserve(81);
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      samples.push_back(
          field.metric_uv(f.uv_box.u.at((i + 0.5) / 9.5), f.uv_box.v.at((j + 0.5) / 9.5)));
  const auto [cells_u, cells_v] = grid_cells(samples, f.uv_box, s.singular_sides(), s.kind());
  UvMetricGrid grid(field, f.uv_box, s.singular_sides(), cells_u, cells_v);
  // mesher2d starts from the Delaunay triangulation of the boundary in its own
  // coordinates and refines under the metric from there (§7.6.1). Where the (u,v) metric
  // is strongly anisotropic as a whole -- an angle parameter times a radius against a
  // length, a thin band of a cylinder -- that first triangulation is made of fans of long
  // edges running along the boundary, every point sampled on them is too close to the
  // boundary, and the fans stay (nist_ftc_11 face 2: metric Q 590). So v is scaled by
  // k = mean(sqrt m22) / mean(sqrt m11) over the face, which makes the metric isotropic
  // on average; the metric is transformed accordingly (M' = S^-T M S^-1, S = diag(1, k))
  // and the vertices are scaled back.
  // Not on faces with a pole: there the metric is singular (sqrt m11 -> 0 at a cone's
  // apex), the mean says little, and the fans at the pole's run of (u,v) points are what
  // the pole handling below expects (scaled, occt_cone_catia got a fold at its apex).
  double vscale = 1.0;
  bool has_pole = false;
  for (const geom::Loop& loop : f.loops)
    for (const geom::EdgeUse& use : loop.uses)
      has_pole =
          has_pole || (use.edge >= 0 && m.edges[static_cast<std::size_t>(use.edge)].degenerate);
  if (!has_pole) {
    double lu = 0, lv = 0;
    int n = 0;
    for (const param::Metric2& g : samples) {
      if (!(g(0, 0) > 0) || !(g(1, 1) > 0) || !std::isfinite(g(0, 0)) || !std::isfinite(g(1, 1)))
        continue;
      lu += 0.5 * std::log(g(0, 0)), lv += 0.5 * std::log(g(1, 1)), ++n;
    }
    if (n > 0) {
      const double k = std::exp((lv - lu) / n);
      if (std::isfinite(k) && std::abs(std::log(k)) > std::log(1.5))
        vscale = std::clamp(k, 1e-6, 1e6);
    }
  }
  const std::vector<m2d::Vec2> uv_in = in.points;
  for (auto& p : in.points) p.y *= vscale;
  const m2d::SizeSpec size = m2d::SizeSpec::aniso([&](double u, double v) {
    const m2d::Metric2 g = grid(u, v / vscale);
    return m2d::Metric2{g.m11, g.m12 / vscale, g.m22 / (vscale * vscale)};
  });
  m2d::Options o;
  o.split_segments = false;          // edge nodes are owned by the model edges
  o.domain_from_orientation = true;  // outer loop CCW, holes CW in (u,v)
  o.max_anisotropy = opt.size.max_uv_anisotropy;
  o.boundary_gradation = std::max(opt.size.gradation, 1.05);
  // The (u,v) metric is a sampled lower bound on the density the chordal tolerance needs
  // (the chordal repair below only adds points): mesher2d's size pass may split long
  // edges but must not collapse short ones.
  o.collapse_short_edges = false;
  o.time_limit = opt.face_time_limit;
  o.measure = false;  // the face's quality is measured in 3D below, not in the (u,v) metric
  const m2d::Result r = m2d::mesh(in, size, o);
  if (!r.ok()) {
    std::string msg = r.status.message;
    if (r.status.code == m2d::StatusCode::CrossingSegments && r.status.entities.size() >= 2) {
      const auto e0 = sedge[static_cast<std::size_t>(r.status.entities[0])];
      const auto e1 = sedge[static_cast<std::size_t>(r.status.entities[1])];
      msg = "the (u,v) curves of edges " + std::to_string(e0) + " and " + std::to_string(e1) +
            " cross (" + msg + ")";
      for (int k = 0; k < 2; ++k) {
        const auto sg = static_cast<std::size_t>(r.status.entities[static_cast<std::size_t>(k)]);
        if (std::isfinite(spiece[sg][0]) && std::isfinite(spiece[sg][1]))
          out.refine_at.push_back({sedge[sg], 0.5 * (spiece[sg][0] + spiece[sg][1])});
      }
    }
    msg = "2D mesher: " + msg;
    if (r.status.code == m2d::StatusCode::CrossingSegments ||
        r.status.code == m2d::StatusCode::OpenBoundary ||
        r.status.code == m2d::StatusCode::InvalidInput)
      return uv_failure(std::move(msg));
    out.error = std::move(msg);
    return out;
  }
  if (r.stats.segments_split_at_vertices > 0)
    return uv_failure(
        "a boundary node lies on another edge's (u,v) segment; the face would not conform");

  // ---- map back: boundary vertices are global nodes; the others are new points.
  const m2d::Mesh& mm = r.mesh;
  LocalMesh lm;
  const std::size_t nv = mm.vertices.size();
  lm.uv.resize(nv);
  lm.p.resize(nv);
  lm.global.assign(nv, -1);
  lm.fixed.assign(nv, 0);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    const m2d::VertId v = mm.input_vertex[i];
    if (v == m2d::kNone) {
      return uv_failure("boundary node at " + fmt_uv({uv_in[i].x, uv_in[i].y}) + " of edge " +
                        std::to_string(pedge[i]) +
                        " lies outside the face's (u,v) domain (loop orientation?)");
    }
    const auto vi = static_cast<std::size_t>(v);
    if (lm.global[vi] >= 0 && lm.global[vi] != gid[i]) {
      return uv_failure("nodes " + std::to_string(lm.global[vi]) + " and " +
                        std::to_string(gid[i]) + " (edges " + std::to_string(pedge[i]) +
                        ") coincide in (u,v) at " + fmt_uv({uv_in[i].x, uv_in[i].y}));
    }
    lm.global[vi] = gid[i];
    lm.fixed[vi] = 1;
  }
  lm.scale.assign(nv, 1.0);
  for (std::size_t v = 0; v < nv; ++v) {
    lm.uv[v] = {mm.vertices[v].x, mm.vertices[v].y / vscale};
    if (v < mm.vertex_metric.size()) {
      // The scale mesher2d applied to the field (sizes from the boundary): the ratio of
      // the traces (in mesher2d's coordinates), the scaling being isotropic.
      const param::Metric2 fm = field.metric_uv(lm.uv[v].x, lm.uv[v].y);
      const double tr = fm(0, 0) + fm(1, 1) / (vscale * vscale);
      if (tr > 0)
        lm.scale[v] = std::max(1.0, (mm.vertex_metric[v].m11 + mm.vertex_metric[v].m22) / tr);
    }
    lm.p[v] = lm.global[v] >= 0 ? node_points[static_cast<std::size_t>(lm.global[v])]
                                : s.point(lm.uv[v].x, lm.uv[v].y);
  }
  // Boundary nodes keep their exact (u,v), not the round trip through the v scaling.
  for (std::size_t i = 0; i < uv_in.size(); ++i)
    lm.uv[static_cast<std::size_t>(mm.input_vertex[i])] = {uv_in[i].x, uv_in[i].y};
  lm.tris.reserve(mm.triangles.size());
  for (const auto& t : mm.triangles) {
    // At a pole two (u,v) points are one node: that triangle is an edge in 3D.
    const NodeId g0 = lm.global[static_cast<std::size_t>(t[0])],
                 g1 = lm.global[static_cast<std::size_t>(t[1])],
                 g2 = lm.global[static_cast<std::size_t>(t[2])];
    if (g0 >= 0 && (g0 == g1 || g0 == g2)) continue;
    if (g1 >= 0 && g1 == g2) continue;
    lm.tris.push_back({t[0], t[1], t[2]});
  }

  if (opt.optimize3d) {
    const auto [sw, mv] = improve3d(lm, s, opt.optimize3d_passes);
    out.stats.swaps3d = sw;
    out.stats.moves3d = mv;
  }

  // ---- chordal repair. The sizes come from curvatures sampled on a background grid
  // (§7.5.1) and clamped at hmin, so a narrow high-curvature band of a large freeform
  // face, or the tip of a cone cut in halves, can be missed; the acceptance is the
  // measured deviation, at triangle centroids and edge midpoints (Newton projection).
  // A triangle whose centroid deviates by more than 0.9 tol has its longest interior
  // edge split, and so has an interior edge whose midpoint deviates: 2 triangles to 4 at
  // the (u,v) midpoint, which gives two pairs of halves instead of the 120-degree caps of
  // a 1-to-3 split (t106_blade: 7% of triangles above Q 1.5 with centroid splits). A
  // triangle with no interior edge is split at its centroid's foot. Then 3D swaps and
  // smoothing.
  if (opt.size.chordal_tol > 0)
    for (int round = 0; round < opt.chordal_repair_rounds; ++round) {
      const int n = chordal_split_round(lm, s, f.uv_box, 0.9 * opt.size.chordal_tol);
      out.stats.chordal_splits += n;
      if (n == 0) break;
      if (opt.optimize3d) improve3d(lm, s, 2, /*collapse=*/false);
    }

  // ---- flatness at apexes. Sizes are clamped at hmin, and at a cone's apex (curvature
  // 1/r) nothing below hmin is resolved: without a chordal tolerance (--angle alone) the
  // repair above does not run, and a cone cut in halves then got the same chord through
  // its axis -- even the same triangle (apex, n1, n2) -- in both halves, each the other
  // turned over: non-manifold edges and coincident triangles (occt_cone_catia at --angle
  // 30). On a face with a pole, a chord between two boundary nodes whose midpoint lies
  // farther than a quarter of its length from the surface -- it spans more than about 105
  // degrees of arc -- is split at its (u,v) midpoint, so a half turn keeps at least two
  // edges, each face its own. (Every interior edge, or every face, measured worse: such
  // splits without the sizes' context made slivers on occt_terrain and
  // occt_caxif_b1's face 83, and moved t106_blade and mesh_hang.)
  if (has_pole) {
    constexpr double kFlatRel = 0.25;
    for (int round = 0; round < 4; ++round) {
      const int n = flat_split_round(lm, s, f.uv_box, kFlatRel);
      out.stats.chordal_splits += n;
      if (n == 0) break;
      if (opt.optimize3d) improve3d(lm, s, 2, /*collapse=*/false);
    }
  }

  const std::size_t nvf = lm.uv.size();  // with the points of the chordal repair

  // ---- folds at seams and poles: near a cone apex the (u,v) strip is so narrow in the
  // metric that a vertex can see a seam node on both sides of the period; the two
  // triangles it then makes are one 3D triangle with both orientations (a zero-volume
  // fold). Removing the pair leaves the surrounding fan manifold.
  {
    auto node = [&](int v) {
      return lm.global[v] >= 0 ? static_cast<std::int64_t>(lm.global[v])
                               : -1 - static_cast<std::int64_t>(v);
    };
    std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> seen;
    for (std::size_t t = 0; t < lm.tris.size(); ++t) {
      std::array<std::int64_t, 3> k{node(lm.tris[t][0]), node(lm.tris[t][1]), node(lm.tris[t][2])};
      std::sort(k.begin(), k.end());
      seen[k].push_back(t);
    }
    std::vector<char> drop(lm.tris.size(), 0);
    for (const auto& [k, ts] : seen)
      if (ts.size() == 2) drop[ts[0]] = drop[ts[1]] = 1;
    if (std::find(drop.begin(), drop.end(), 1) != drop.end()) {
      std::size_t w = 0;
      for (std::size_t t = 0; t < lm.tris.size(); ++t)
        if (!drop[t]) lm.tris[w++] = lm.tris[t];
      lm.tris.resize(w);
    }
  }

  // ---- unit edges, measured in this face's metric (the field scaled as mesher2d did).
  {
    std::vector<param::Metric3> m3(nvf);
    std::vector<char> has(nvf, 0);
    auto metric_at = [&](int v) -> const param::Metric3& {
      if (!has[v]) m3[v] = field.metric3(lm.uv[v].x, lm.uv[v].y) * lm.scale[v], has[v] = 1;
      return m3[v];
    };
    // Each edge once. An edge of two triangles is seen from both: counted from the one
    // where it runs a < b; an edge of one triangle (on the face's boundary) always. Both
    // ends on the boundary does not make an edge a boundary edge: a chord across a
    // narrow face joins two boundary nodes and has two triangles (counted twice before,
    // which weighed a strip of chords double: occt_mesh_artifact's face 8).
    const EdgeUses uses(lm);
    for (const auto& t : lm.tris)
      for (int i = 0; i < 3; ++i) {
        const int a = t[i], b = t[(i + 1) % 3];
        if (a > b) {
          const auto [lo, hi] = uses.of(a, b);
          if (hi - lo > 1) continue;
        }
        const geom::Vec3 d = lm.p[b] - lm.p[a];
        const double la = metric_at(a).length(d), lb = metric_at(b).length(d);
        const double ratio = la > 0 ? lb / la : 1.0;
        const double L = (std::abs(ratio - 1) < 1e-3 || !(ratio > 0)) ? 0.5 * (la + lb)
                                                                      : (lb - la) / std::log(ratio);
        ++out.stats.edges;
        if (L < std::sqrt(0.5))
          ++out.stats.short_edges;
        else if (L > std::sqrt(2.0))
          ++out.stats.long_edges;
        else
          ++out.stats.unit_edges;
      }
  }

  // ---- the face's contribution: interior points renumbered -(k+1) in local order.
  std::vector<NodeId> ref(nvf, 0);
  std::vector<char> used(nvf, 0);
  for (const auto& t : lm.tris)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t v = 0; v < nvf; ++v) {
    if (!used[v]) continue;  // e.g. the tip of a removed fold
    if (lm.global[v] >= 0) {
      ref[v] = lm.global[v];
    } else {
      ref[v] = -static_cast<NodeId>(out.points.size()) - 1;
      out.points.push_back(lm.p[v]);
    }
  }
  out.tris.reserve(lm.tris.size());
  out.tri_uv.reserve(lm.tris.size());
  for (const auto& t : lm.tris) {
    // Triangles are CCW in (u,v), so their normal is sigma_u x sigma_v; a reversed face
    // has its material on the other side.
    std::array<int, 3> c = t;
    if (f.reversed) std::swap(c[1], c[2]);
    out.tris.push_back({ref[c[0]], ref[c[1]], ref[c[2]]});
    out.tri_uv.push_back({lm.uv[c[0]], lm.uv[c[1]], lm.uv[c[2]]});
  }
  out.stats.triangles = static_cast<int>(out.tris.size());
  return out;
}

}  // namespace uvmesh::surface::detail
