// Seeded generators of planar straight line graphs for the mesher2d tests and fuzzer.
//
// Every generator is a pure function of its seed (SplitMix64 and explicit arithmetic,
// never std:: distributions, whose output differs between standard libraries), so a
// failing case is reproduced from its family name and seed alone:
//
//   uvmesh::m2d::gen::Case c = uvmesh::m2d::gen::star_with_holes(17);
//   auto r = uvmesh::m2d::mesh(c.pslg, uvmesh::m2d::SizeSpec::uniform(c.h));
//
// A Case carries what the tests may expect of a correct mesh: whether every input point
// lies in the closed domain, how many input points repeat an earlier one exactly, the
// hole polygons (no triangle may lie inside), the polygons carrying region attributes,
// and a mesh size suited to the case. Families (each one property of the input):
//   random_points       uniform random points, no segments
//   grid_points         subsets of a coarse integer grid: collinear and cocircular
//   duplicate_points    exact duplicates and 1-ulp neighbours (nextafter)
//   star_with_holes     star-shaped polygon, random radii, star-shaped holes
//   comb_with_holes     concave comb (teeth of random height), holes in base and teeth
//   nested_squares      square in square in square, region seeds with attributes
//   small_angles        segments meeting at 1-10 degrees, thin wedges, slivers
//   random_segments     grid-snapped segments, non-crossing by exact orient tests
//   triangulation_edges random subsets of the edges of a jittered-grid triangulation
// and the special inputs of the error-path tests: crossing_pair, segment_through_vertex,
// open_boundary.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::gen {

// ---------------------------------------------------------------------------------------
// Random numbers: SplitMix64 (Steele, Lea, Flood 2014); identical on every platform.
class Rng {
 public:
  explicit Rng(std::uint64_t seed) : s_(seed ^ 0x5DEECE66DA3B5C4Full) { next(); }
  std::uint64_t next() {
    std::uint64_t z = (s_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double a, double b) { return a + (b - a) * uniform(); }
  int integer(int lo, int hi) {  // [lo, hi]
    return lo + static_cast<int>(next() % static_cast<std::uint64_t>(hi - lo + 1));
  }
  bool chance(double p) { return uniform() < p; }

 private:
  std::uint64_t s_;
};

// ---------------------------------------------------------------------------------------
// Geometry helpers (exact where it decides).
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return pred::orient2d(&a.x, &b.x, &c.x);
}

inline bool same(const Vec2& a, const Vec2& b) {
  return a.x == b.x && a.y == b.y;
}

// p lies on the closed segment ab (exact).
inline bool on_segment(const Vec2& a, const Vec2& b, const Vec2& p) {
  if (orient(a, b, p) != 0) return false;
  return std::min(a.x, b.x) <= p.x && p.x <= std::max(a.x, b.x) && std::min(a.y, b.y) <= p.y &&
         p.y <= std::max(a.y, b.y);
}

// Closed segments ab and cd have a point in common (exact).
inline bool segments_meet(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0)))
    return true;
  return on_segment(a, b, c) || on_segment(a, b, d) || on_segment(c, d, a) || on_segment(c, d, b);
}

// Segments ab and cd cross at a point interior to both (exact).
inline bool segments_cross_properly(const Vec2& a, const Vec2& b, const Vec2& c, const Vec2& d) {
  const double o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a),
               o4 = orient(c, d, b);
  return ((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0));
}

// Even-odd point-in-polygon in floating point; for test points well inside or outside.
inline bool inside_polygon(const std::vector<Vec2>& poly, Vec2 p) {
  bool in = false;
  for (std::size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Vec2 &a = poly[i], &b = poly[j];
    if ((a.y > p.y) != (b.y > p.y) && p.x < (b.x - a.x) * (p.y - a.y) / (b.y - a.y) + a.x) in = !in;
  }
  return in;
}

// Number of distinct points (exact comparison).
inline std::int64_t distinct_count(const std::vector<Vec2>& pts) {
  std::vector<std::pair<double, double>> v;
  v.reserve(pts.size());
  for (auto& p : pts) v.emplace_back(p.x, p.y);
  std::sort(v.begin(), v.end());
  return static_cast<std::int64_t>(std::unique(v.begin(), v.end()) - v.begin());
}

// Distinct points on the boundary of the convex hull, including points in the interior
// of hull edges (exact; Andrew's monotone chain keeping collinear boundary points).
// Returns 0 when all points are collinear (no 2D hull).
inline std::int64_t hull_vertex_count(const std::vector<Vec2>& pts) {
  std::vector<Vec2> p = pts;
  std::sort(p.begin(), p.end(),
            [](const Vec2& a, const Vec2& b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  p.erase(std::unique(p.begin(), p.end(), same), p.end());
  if (p.size() < 3) return 0;
  bool flat = true;
  for (std::size_t i = 2; i < p.size() && flat; ++i) flat = orient(p[0], p[1], p[i]) == 0;
  if (flat) return 0;
  // Lower and upper chains; a point is popped only when it makes a strict right turn,
  // so collinear boundary points stay.
  auto chain = [&](auto first, auto last) {
    std::vector<Vec2> h;
    for (auto it = first; it != last; ++it) {
      while (h.size() >= 2 && orient(h[h.size() - 2], h.back(), *it) < 0) h.pop_back();
      h.push_back(*it);
    }
    return h;
  };
  const std::vector<Vec2> lower = chain(p.begin(), p.end()), upper = chain(p.rbegin(), p.rend());
  // Both chains contain the two extreme points.
  return static_cast<std::int64_t>(lower.size() + upper.size()) - 2;
}

// ---------------------------------------------------------------------------------------
// A generated input and what a correct mesh of it must satisfy.
struct Case {
  std::string name;  // "family seed=N", for failure messages
  Pslg pslg;
  double h = 0;                      // a uniform size giving a few thousand triangles
  bool all_points_in_domain = true;  // every input point lies in the closed domain
  bool has_segments = false;
  std::int64_t exact_duplicates = 0;     // input points equal to an earlier one
  std::vector<std::vector<Vec2>> holes;  // no triangle may lie inside these
  // (polygon, attribute), outer first: the attribute at a point is that of the last
  // (innermost) polygon containing it.
  std::vector<std::pair<std::vector<Vec2>, double>> attribute_polygons;

  // Expected attribute at p (well inside a region), or NaN when no polygon contains it.
  double attribute_at(Vec2 p) const {
    double a = std::numeric_limits<double>::quiet_NaN();
    for (auto& [poly, att] : attribute_polygons)
      if (inside_polygon(poly, p)) a = att;
    return a;
  }
  bool in_hole(Vec2 p) const {
    for (auto& poly : holes)
      if (inside_polygon(poly, p)) return true;
    return false;
  }
};

namespace detail {

inline std::string name(const char* family, std::uint64_t seed) {
  return std::string(family) + " seed=" + std::to_string(seed);
}

// Appends a closed polygon (its points and segments) to the PSLG.
inline void add_loop(Pslg& g, const std::vector<Vec2>& poly, int marker) {
  const VertId base = static_cast<VertId>(g.points.size());
  const VertId n = static_cast<VertId>(poly.size());
  for (auto& p : poly) g.points.push_back(p);
  for (VertId i = 0; i < n; ++i) g.segments.push_back({base + i, base + (i + 1) % n, marker});
}

// Star-shaped polygon around c: n vertices at jittered, strictly increasing angles
// (every angular gap below pi, so c is in the kernel and the polygon is simple) and radii
// in [rmin, rmax]. It contains the disk of radius rmin * cos(max gap / 2) around c.
inline std::vector<Vec2> star(Rng& rng, Vec2 c, int n, double rmin, double rmax,
                              double* inner = nullptr) {
  const double phase = rng.uniform(0, 2 * std::numbers::pi);
  constexpr double jitter = 0.4;  // gaps in 2pi/n * [1-jitter, 1+jitter] <= pi for n >= 3
  std::vector<double> ang(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i)
    ang[i] = phase + 2 * std::numbers::pi * (i + jitter * (rng.uniform() - 0.5)) / n;
  double maxgap = 0;
  for (int i = 0; i < n; ++i) {
    const double next = i + 1 < n ? ang[i + 1] : ang[0] + 2 * std::numbers::pi;
    maxgap = std::max(maxgap, next - ang[i]);
  }
  std::vector<Vec2> poly;
  double rlo = rmax;
  for (int i = 0; i < n; ++i) {
    const double r = rng.uniform(rmin, rmax);
    rlo = std::min(rlo, r);
    poly.push_back({c.x + r * std::cos(ang[i]), c.y + r * std::sin(ang[i])});
  }
  if (inner) *inner = rlo * std::cos(maxgap / 2);
  return poly;
}

// A similarity x -> s R x + t applied to every coordinate of a case, so that segments
// are not axis-aligned and magnitudes vary. The margins of the generators are far above
// the rounding this introduces.
struct Similarity {
  double s = 1, c = 1, sn = 0, tx = 0, ty = 0;
  static Similarity random(Rng& rng) {
    Similarity f;
    f.s = std::pow(10.0, rng.uniform(-3, 3));
    const double a = rng.chance(0.3) ? 0.0 : rng.uniform(0, 2 * std::numbers::pi);
    f.c = std::cos(a), f.sn = std::sin(a);
    f.tx = rng.uniform(-100, 100) * f.s;
    f.ty = rng.uniform(-100, 100) * f.s;
    return f;
  }
  Vec2 operator()(Vec2 p) const {
    return {s * (c * p.x - sn * p.y) + tx, s * (sn * p.x + c * p.y) + ty};
  }
  void apply(Case& k) const {
    for (auto& p : k.pslg.points) p = (*this)(p);
    for (auto& p : k.pslg.holes) p = (*this)(p);
    for (auto& r : k.pslg.regions) r.seed = (*this)(r.seed);
    for (auto& poly : k.holes)
      for (auto& p : poly) p = (*this)(p);
    for (auto& [poly, att] : k.attribute_polygons)
      for (auto& p : poly) p = (*this)(p);
    k.h *= s;
  }
};

}  // namespace detail

// ---------------------------------------------------------------------------------------
// Point sets (no segments: the mesher triangulates the convex hull).

// n uniform random points in a random square; full-precision coordinates.
inline Case random_points(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("random_points", seed);
  const int n = rng.integer(3, 400);
  for (int i = 0; i < n; ++i) k.pslg.points.push_back({rng.uniform(), rng.uniform()});
  k.h = 0.05;
  detail::Similarity::random(rng).apply(k);
  return k;
}

// A random subset of a k x k integer grid (k in 4..16): lines of collinear points and
// groups of four (or more) cocircular points everywhere. The three corners (0,0), (k-1,0),
// (0,k-1) are always in, so the hull is not flat. Coordinates stay exact integers
// (optionally times a power of two and shifted by an integer).
inline Case grid_points(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("grid_points", seed);
  const int g = rng.integer(4, 16);
  const double keep = rng.uniform(0.2, 1.0);
  const double scale = std::ldexp(1.0, rng.integer(-4, 4));
  const double shift = rng.integer(-1000, 1000);
  for (int j = 0; j < g; ++j)
    for (int i = 0; i < g; ++i) {
      const bool corner = (i == 0 && j == 0) || (i == g - 1 && j == 0) || (i == 0 && j == g - 1);
      if (corner || rng.uniform() < keep)
        k.pslg.points.push_back({(i + shift) * scale, (j + shift) * scale});
    }
  k.h = 0.5 * scale;
  return k;
}

// Random points with exact duplicates and points one ulp away (nextafter in x, in y or
// both) from others. Exact duplicates must be merged; 1-ulp neighbours are distinct
// points and must stay. No coordinate is 0: nextafter(0) is a denormal, and products of
// denormal differences underflow below the smallest double, beyond what floating-point
// expansions can represent (that case is pinned in test_regressions.cpp).
inline Case duplicate_points(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("duplicate_points", seed);
  const int n = rng.integer(3, 150);
  const bool on_grid = rng.chance(0.3);
  auto& P = k.pslg.points;
  for (int i = 0; i < n; ++i) {
    if (on_grid)
      P.push_back(
          {static_cast<double>(rng.integer(1, 10)), static_cast<double>(rng.integer(1, 10))});
    else
      P.push_back({rng.uniform(), rng.uniform()});
  }
  const int base = n;
  const int near = rng.integer(0, n / 3 + 1);
  for (int i = 0; i < near; ++i) {
    Vec2 p = P[rng.integer(0, base - 1)];
    const int which = rng.integer(0, 2);
    if (which != 1) p.x = std::nextafter(p.x, rng.chance(0.5) ? 1e300 : -1e300);
    if (which != 0) p.y = std::nextafter(p.y, rng.chance(0.5) ? 1e300 : -1e300);
    P.push_back(p);
  }
  const int dups = rng.integer(1, n / 2 + 1);
  for (int i = 0; i < dups; ++i) P.push_back(P[rng.integer(0, static_cast<int>(P.size()) - 1)]);
  // Shuffle so duplicates are not all at the end.
  for (std::size_t i = P.size() - 1; i > 0; --i) std::swap(P[i], P[rng.next() % (i + 1)]);
  k.exact_duplicates = static_cast<std::int64_t>(P.size()) - distinct_count(P);
  k.h = on_grid ? 0.5 : 0.05;
  return k;
}

// ---------------------------------------------------------------------------------------
// Polygonal domains with holes.

// Star-shaped polygon (5..60 vertices, random radii in [0.5, 1]) with 0..4 star-shaped
// holes inside its inner disk, disjoint by construction (disks with a margin). The
// domain gets a region seed with attribute 1 half the time.
inline Case star_with_holes(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("star_with_holes", seed);
  k.has_segments = true;
  double inner = 0;
  const auto outer =
      detail::star(rng, {0, 0}, rng.integer(5, 60), rng.uniform(0.3, 0.9), 1.0, &inner);
  detail::add_loop(k.pslg, outer, 1);
  const int want = rng.integer(0, 4);
  std::vector<std::pair<Vec2, double>> disks;
  for (int attempt = 0; attempt < 50 && static_cast<int>(disks.size()) < want; ++attempt) {
    const double rho = rng.uniform(0.05, 0.35) * inner;
    const double r = rng.uniform(0, 0.85 * inner - rho);
    const double a = rng.uniform(0, 2 * std::numbers::pi);
    const Vec2 c{r * std::cos(a), r * std::sin(a)};
    bool ok = r >= 0;
    for (auto& [d, dr] : disks)
      ok = ok && std::hypot(c.x - d.x, c.y - d.y) > rho + dr + 0.05 * inner;
    if (!ok) continue;
    disks.push_back({c, rho});
    const auto hole = detail::star(rng, c, rng.integer(3, 12), 0.4 * rho, rho);
    detail::add_loop(k.pslg, hole, 2 + static_cast<int>(disks.size()));
    k.pslg.holes.push_back(c);  // c is in the kernel of its star, strictly inside
    k.holes.push_back(hole);
  }
  if (rng.chance(0.5)) {
    // Between the hole disks (radius <= 0.85 inner) and the boundary (>= inner).
    const double a = rng.uniform(0, 2 * std::numbers::pi);
    k.pslg.regions.push_back({{0.93 * inner * std::cos(a), 0.93 * inner * std::sin(a)}, 1.0});
    k.attribute_polygons.push_back({outer, 1.0});
  }
  k.h = rng.uniform(0.03, 0.15);
  detail::Similarity::random(rng).apply(k);
  return k;
}

// Concave comb: base strip [0, X] x [0, 1] with 2..12 teeth of random width and slanted
// tops (heights 0.5..4), polygonal holes in the base strip and in some teeth.
inline Case comb_with_holes(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("comb_with_holes", seed);
  k.has_segments = true;
  const int teeth = rng.integer(2, 12);
  struct Tooth {
    double a, b, ha, hb;
  };
  std::vector<Tooth> tt;
  double x = rng.uniform(0.2, 1.0);
  for (int i = 0; i < teeth; ++i) {
    const double w = rng.uniform(0.2, 1.0);
    tt.push_back({x, x + w, rng.uniform(0.5, 4.0), rng.uniform(0.5, 4.0)});
    x += w + rng.uniform(0.2, 1.0);
  }
  const double X = x;
  std::vector<Vec2> poly{{0, 0}, {X, 0}, {X, 1}};
  for (int i = teeth - 1; i >= 0; --i) {
    poly.push_back({tt[i].b, 1});
    poly.push_back({tt[i].b, 1 + tt[i].hb});
    poly.push_back({tt[i].a, 1 + tt[i].ha});
    poly.push_back({tt[i].a, 1});
  }
  poly.push_back({0, 1});
  detail::add_loop(k.pslg, poly, 1);
  // Holes in the base: one per unit-ish x interval, radius below 0.4 (strip half height
  // 0.5), centers at least 0.9 apart.
  for (double cx = 0.5; cx + 0.5 < X; cx += 1.0) {
    if (!rng.chance(0.5)) continue;
    const double rho = rng.uniform(0.1, 0.38);
    const Vec2 c{cx + rng.uniform(-0.05, 0.05), 0.5 + rng.uniform(-0.05, 0.05)};
    const auto hole = detail::star(rng, c, rng.integer(3, 8), 0.4 * rho, rho);
    detail::add_loop(k.pslg, hole, 2);
    k.pslg.holes.push_back(c);
    k.holes.push_back(hole);
  }
  // Holes in teeth: inside [a, b] x [1, 1 + min height].
  for (auto& t : tt) {
    if (!rng.chance(0.3)) continue;
    const double w = t.b - t.a, hmin = std::min(t.ha, t.hb);
    const double rho = 0.8 * std::min(w, hmin) / 2;
    const Vec2 c{(t.a + t.b) / 2, 1 + hmin / 2};
    const auto hole = detail::star(rng, c, rng.integer(3, 8), 0.4 * rho, rho);
    detail::add_loop(k.pslg, hole, 3);
    k.pslg.holes.push_back(c);
    k.holes.push_back(hole);
  }
  k.h = rng.uniform(0.05, 0.3);
  detail::Similarity::random(rng).apply(k);
  return k;
}

// Square in square in square (2..5 levels, random sizes and offsets). Region seeds in
// every ring with distinct attributes (level + 1, or random values); the innermost
// square is a hole half the time. A few free interior points.
inline Case nested_squares(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("nested_squares", seed);
  k.has_segments = true;
  const int levels = rng.integer(2, 5);
  std::vector<Vec2> centers{{0, 0}};
  std::vector<double> half{1.0};
  for (int l = 1; l < levels; ++l) {
    const double s = half.back() * rng.uniform(0.3, 0.7);
    const double room = half.back() - s - 0.1 * half.back();  // margin 0.1 of the parent
    centers.push_back(
        {centers.back().x + rng.uniform(-room, room), centers.back().y + rng.uniform(-room, room)});
    half.push_back(s);
  }
  const bool inner_hole = rng.chance(0.5);
  const bool random_att = rng.chance(0.5);
  for (int l = 0; l < levels; ++l) {
    const Vec2 c = centers[l];
    const double s = half[l];
    const std::vector<Vec2> sq{
        {c.x - s, c.y - s}, {c.x + s, c.y - s}, {c.x + s, c.y + s}, {c.x - s, c.y + s}};
    detail::add_loop(k.pslg, sq, l + 1);
    const double att = random_att ? std::round(rng.uniform(-1000, 1000)) / 8 : l + 1.0;
    const bool last = l + 1 == levels;
    if (last && inner_hole) {
      k.pslg.holes.push_back(c);
      k.holes.push_back(sq);
      continue;
    }
    // Seed in the ring between this square and the next: midway between their left sides.
    Vec2 seedp = c;
    if (!last) seedp = {((c.x - s) + (centers[l + 1].x - half[l + 1])) / 2, centers[l + 1].y};
    k.pslg.regions.push_back({seedp, att});
    k.attribute_polygons.push_back({sq, att});
  }
  // Free points in the outer ring (left of the second square), not on any segment.
  const int free_pts = rng.integer(0, 5);
  for (int i = 0; i < free_pts; ++i) {
    const double xl = centers[0].x - half[0], xr = centers[1].x - half[1];
    k.pslg.points.push_back(
        {rng.uniform(xl + 0.2 * (xr - xl), xr - 0.2 * (xr - xl)),
         rng.uniform(centers[0].y - 0.8 * half[0], centers[0].y + 0.8 * half[0])});
  }
  k.h = rng.uniform(0.03, 0.15);
  detail::Similarity::random(rng).apply(k);
  return k;
}

// Small angles: (0) two segments from a common point meeting at 1..10 degrees inside a
// square; (1) a thin wedge domain with a 1..10 degree apex; (2) a sliver: a polygon with
// a vertex a relative 1e-9..1e-4 off the line of its neighbours; (3) a fan of segments
// at 1-degree steps.
inline Case small_angles(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("small_angles", seed);
  k.has_segments = true;
  constexpr double deg = std::numbers::pi / 180;
  const int variant = rng.integer(0, 3);
  auto square = [&] { detail::add_loop(k.pslg, {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, 1); };
  if (variant == 0) {
    square();
    const double th = (rng.chance(0.3) ? 1.0 : rng.uniform(1, 10)) * deg;
    const Vec2 o{rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3)};
    const double phi = rng.uniform(0, 2 * std::numbers::pi);
    const double r1 = rng.uniform(0.2, 0.6), r2 = rng.uniform(0.2, 0.6);
    const VertId io = static_cast<VertId>(k.pslg.points.size());
    k.pslg.points.push_back(o);
    k.pslg.points.push_back({o.x + r1 * std::cos(phi), o.y + r1 * std::sin(phi)});
    k.pslg.points.push_back({o.x + r2 * std::cos(phi + th), o.y + r2 * std::sin(phi + th)});
    k.pslg.segments.push_back({io, io + 1, 2});
    k.pslg.segments.push_back({io, io + 2, 2});
  } else if (variant == 1) {
    const double th = (rng.chance(0.3) ? 1.0 : rng.uniform(1, 10)) * deg;
    const double l1 = rng.uniform(0.5, 1), l2 = rng.uniform(0.5, 1);
    std::vector<Vec2> w{{0, 0}, {l1, 0}};
    if (rng.chance(0.5))
      w.push_back({0.5 * (l1 + l2 * std::cos(th)), 0.5 * l2 * std::sin(th) * 0.5});  // concave dent
    w.push_back({l2 * std::cos(th), l2 * std::sin(th)});
    detail::add_loop(k.pslg, w, 1);
  } else if (variant == 2) {
    const double eps = std::pow(10.0, rng.uniform(-9, -4));
    const int n = rng.integer(3, 8);
    std::vector<Vec2> poly;
    for (int i = 0; i <= n; ++i)
      poly.push_back({static_cast<double>(i) / n, i == n / 2 ? eps : 0.0});
    poly.push_back({1, 1});
    poly.push_back({0, 1});
    detail::add_loop(k.pslg, poly, 1);
  } else {
    square();
    const int m = rng.integer(2, 8);
    const double r = rng.uniform(0.3, 0.8), phi = rng.uniform(0, 2 * std::numbers::pi);
    const VertId io = static_cast<VertId>(k.pslg.points.size());
    k.pslg.points.push_back({0, 0});
    for (int i = 0; i < m; ++i) {
      k.pslg.points.push_back({r * std::cos(phi + i * deg), r * std::sin(phi + i * deg)});
      k.pslg.segments.push_back({io, io + 1 + i, 2});
    }
  }
  k.h = rng.uniform(0.05, 0.2);
  detail::Similarity::random(rng).apply(k);
  return k;
}

// Random non-crossing segments with endpoints on a g x g grid (g in 6..16) inside the
// square [0, g]^2 (its boundary, corners only), plus free grid points. The grid is
// scaled by a factor that is a power of two (exact, so many triples are exactly
// collinear) or 0.1 (rounded, so many triples are nearly collinear). Segments are kept
// only if they meet no kept segment except at a shared endpoint and contain no kept
// point in their interior, decided with exact orient tests on the final coordinates.
inline Case random_segments(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("random_segments", seed);
  k.has_segments = true;
  const int g = rng.integer(6, 16);
  const double sc = rng.chance(0.5) ? std::ldexp(1.0, rng.integer(-3, 3)) : 0.1;
  auto at = [&](int i, int j) { return Vec2{i * sc, j * sc}; };
  detail::add_loop(k.pslg, {at(0, 0), at(g, 0), at(g, g), at(0, g)}, 1);
  auto& P = k.pslg.points;
  auto& S = k.pslg.segments;
  auto find_or_add = [&](Vec2 p) {
    for (std::size_t i = 0; i < P.size(); ++i)
      if (same(P[i], p)) return static_cast<VertId>(i);
    P.push_back(p);
    return static_cast<VertId>(P.size() - 1);
  };
  auto on_any_segment = [&](Vec2 p) {
    for (auto& s : S)
      if (!same(P[s.a], p) && !same(P[s.b], p) && on_segment(P[s.a], P[s.b], p)) return true;
    return false;
  };
  const int want = rng.integer(3, 40);
  for (int attempt = 0; attempt < 20 * want && static_cast<int>(S.size()) - 4 < want; ++attempt) {
    const Vec2 a = at(rng.integer(1, g - 1), rng.integer(1, g - 1));
    const Vec2 b = at(rng.integer(1, g - 1), rng.integer(1, g - 1));
    if (same(a, b)) continue;
    bool ok = !on_any_segment(a) && !on_any_segment(b);
    for (std::size_t s = 0; s < S.size() && ok; ++s) {
      const Vec2 &c = P[S[s].a], &d = P[S[s].b];
      const bool share_a = same(a, c) || same(a, d), share_b = same(b, c) || same(b, d);
      if (share_a && share_b)
        ok = false;  // same segment
      else if (share_a || share_b) {
        // Touch only at the shared endpoint: the far ends must not lie on the other segment.
        const Vec2 other_new = share_a ? b : a;
        const Vec2 other_old = (same(c, a) || same(c, b)) ? d : c;
        ok = !on_segment(c, d, other_new) && !on_segment(a, b, other_old);
      } else {
        ok = !segments_meet(a, b, c, d);
      }
    }
    for (std::size_t i = 0; i < P.size() && ok; ++i)
      if (!same(P[i], a) && !same(P[i], b) && on_segment(a, b, P[i])) ok = false;
    if (!ok) continue;
    S.push_back({find_or_add(a), find_or_add(b), 2});
  }
  const int free_pts = rng.integer(0, 20);
  for (int i = 0; i < free_pts; ++i) {
    const Vec2 p = at(rng.integer(1, g - 1), rng.integer(1, g - 1));
    bool ok = !on_any_segment(p);
    for (auto& q : P) ok = ok && !same(p, q);
    if (ok) P.push_back(p);
  }
  k.h = rng.uniform(0.3, 1.0) * sc;
  return k;
}

// Random subset of the edges of a triangulation: a g x h grid (4..14) with every point
// jittered by up to 0.15 (cells stay convex) and each cell cut by a random diagonal. Its
// boundary edges are all kept (the domain), interior edges with probability p in
// [0.1, 0.8]. Edges of one triangulation never cross, and the coordinates are in general
// position, so segments meet at vertices from every direction.
inline Case triangulation_edges(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("triangulation_edges", seed);
  k.has_segments = true;
  const int gx = rng.integer(4, 14), gy = rng.integer(4, 14);
  const double p = rng.uniform(0.1, 0.8);
  auto id = [&](int i, int j) { return static_cast<VertId>(j * (gx + 1) + i); };
  for (int j = 0; j <= gy; ++j)
    for (int i = 0; i <= gx; ++i) {
      // Boundary points stay on the boundary lines so that the domain is a rectangle.
      const double dx = (i == 0 || i == gx) ? 0.0 : rng.uniform(-0.15, 0.15);
      const double dy = (j == 0 || j == gy) ? 0.0 : rng.uniform(-0.15, 0.15);
      k.pslg.points.push_back({i + dx, j + dy});
    }
  auto edge = [&](VertId a, VertId b, bool boundary) {
    if (boundary || rng.uniform() < p) k.pslg.segments.push_back({a, b, boundary ? 1 : 2});
  };
  for (int j = 0; j <= gy; ++j)
    for (int i = 0; i < gx; ++i) edge(id(i, j), id(i + 1, j), j == 0 || j == gy);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i <= gx; ++i) edge(id(i, j), id(i, j + 1), i == 0 || i == gx);
  for (int j = 0; j < gy; ++j)
    for (int i = 0; i < gx; ++i) {
      if (rng.chance(0.5))
        edge(id(i, j), id(i + 1, j + 1), false);
      else
        edge(id(i + 1, j), id(i, j + 1), false);
    }
  k.h = rng.uniform(0.15, 0.5);
  detail::Similarity::random(rng).apply(k);
  return k;
}

// ---------------------------------------------------------------------------------------
// Inputs of the error paths.

// The unit square (segments 0..3) and two segments (4 and 5) that cross properly at a
// point interior to both; the crossing point, computed in floating point, is returned
// in *x when asked.
inline Case crossing_pair(std::uint64_t seed, Vec2* x = nullptr) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("crossing_pair", seed);
  k.has_segments = true;
  detail::add_loop(k.pslg, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1);
  Vec2 a, b, c, d;
  do {
    a = {rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)};
    b = {rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)};
    c = {rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)};
    d = {rng.uniform(0.05, 0.95), rng.uniform(0.05, 0.95)};
  } while (!segments_cross_properly(a, b, c, d) || std::abs(orient(a, b, c)) < 1e-3 ||
           std::abs(orient(a, b, d)) < 1e-3 || std::abs(orient(c, d, a)) < 1e-3 ||
           std::abs(orient(c, d, b)) < 1e-3);
  k.pslg.points.insert(k.pslg.points.end(), {a, b, c, d});
  k.pslg.segments.push_back({4, 5, 2});
  k.pslg.segments.push_back({6, 7, 2});
  if (x) {
    const double t = orient(c, d, a) / (orient(c, d, a) - orient(c, d, b));
    *x = {a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
  }
  k.h = 0.1;
  return k;
}

// A square [0, 16]^2 and one interior segment (4) between integer points with 1..3
// input points exactly on it (integer multiples of a primitive direction), so the
// segment must be split at them.
inline Case segment_through_vertex(std::uint64_t seed, int* on_segment_count = nullptr) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("segment_through_vertex", seed);
  k.has_segments = true;
  detail::add_loop(k.pslg, {{0, 0}, {16, 0}, {16, 16}, {0, 16}}, 1);
  int dx = 0, dy = 0;
  while (dx == 0 && dy == 0) dx = rng.integer(-3, 3), dy = rng.integer(-3, 3);
  const int m = rng.integer(2, 4);
  // Start so that a + m*(dx,dy) stays within [1, 15]^2.
  auto lo = [&](int d) { return d >= 0 ? 1 : 1 - m * d; };
  auto hi = [&](int d) { return d >= 0 ? 15 - m * d : 15; };
  const Vec2 a{static_cast<double>(rng.integer(lo(dx), hi(dx))),
               static_cast<double>(rng.integer(lo(dy), hi(dy)))};
  k.pslg.points.push_back(a);
  k.pslg.points.push_back({a.x + m * dx, a.y + m * dy});
  k.pslg.segments.push_back({4, 5, 2});
  int cnt = 0;
  for (int j = 1; j < m; ++j)
    if (j == 1 || rng.chance(0.5)) k.pslg.points.push_back({a.x + j * dx, a.y + j * dy}), ++cnt;
  if (on_segment_count) *on_segment_count = cnt;
  k.h = 1.0;
  return k;
}

// A star polygon with one boundary segment left out and a hole seed at its center: the
// hole leaks into the exterior, so nothing is left to mesh.
inline Case open_boundary(std::uint64_t seed) {
  Rng rng(seed);
  Case k;
  k.name = detail::name("open_boundary", seed);
  k.has_segments = true;
  const auto outer = detail::star(rng, {0, 0}, rng.integer(5, 30), 0.5, 1.0);
  detail::add_loop(k.pslg, outer, 1);
  k.pslg.segments.erase(k.pslg.segments.begin() +
                        rng.integer(0, static_cast<int>(outer.size()) - 1));
  k.pslg.holes.push_back({0, 0});
  k.all_points_in_domain = false;
  k.h = 0.1;
  return k;
}

// ---------------------------------------------------------------------------------------
// The random families, for loops over seeds.
struct Family {
  const char* name;
  Case (*make)(std::uint64_t);
  bool points_only;
};

inline const std::vector<Family>& families() {
  static const std::vector<Family> f{
      {"random_points", random_points, true},
      {"grid_points", grid_points, true},
      {"duplicate_points", duplicate_points, true},
      {"star_with_holes", star_with_holes, false},
      {"comb_with_holes", comb_with_holes, false},
      {"nested_squares", nested_squares, false},
      {"small_angles", small_angles, false},
      {"random_segments", random_segments, false},
      {"triangulation_edges", triangulation_edges, false},
  };
  return f;
}

}  // namespace uvmesh::m2d::gen
