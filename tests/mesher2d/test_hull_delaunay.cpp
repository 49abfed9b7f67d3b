// The unconstrained fast path of m2d::mesh (no segments, holes, regions or refinement):
// the Delaunay triangulation of the convex hull built with ghost triangles
// (mesher2d/src/hull_delaunay.cpp). Checked against what the general pipeline promises:
// exact Delaunay, every input point a vertex (exact duplicates merged and reported),
// hull edges as boundary edges split at collinear hull points, Euler's count.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/mesher2d/predicates.h"

using namespace uvmesh::m2d;

namespace {

Options dt_options() {
  Options o;
  o.refine = false;
  return o;
}

// Points of the convex hull boundary (collinear ones included), by brute force: p is on
// the boundary when some line through p has every point on one closed side, i.e. when p
// is a vertex of the hull or lies on a hull edge. Exact predicates; O(n h).
std::set<std::pair<double, double>> hull_boundary_points(const std::vector<Vec2>& pts) {
  std::vector<Vec2> u = pts;
  std::sort(u.begin(), u.end(), [](Vec2 a, Vec2 b) { return a.x != b.x ? a.x < b.x : a.y < b.y; });
  u.erase(std::unique(u.begin(), u.end(), [](Vec2 a, Vec2 b) { return a.x == b.x && a.y == b.y; }),
          u.end());
  // Monotone chain keeping collinear points (<= 0 would drop them; < 0 keeps them).
  std::vector<Vec2> h;
  auto build = [&](auto begin, auto end) {
    const std::size_t base = h.size();
    for (auto it = begin; it != end; ++it) {
      while (h.size() >= base + 2 && pred::orient2d(&h[h.size() - 2].x, &h.back().x, &it->x) < 0)
        h.pop_back();
      h.push_back(*it);
    }
    h.pop_back();
  };
  build(u.begin(), u.end());
  build(u.rbegin(), u.rend());
  std::set<std::pair<double, double>> s;
  for (const Vec2& p : h) s.insert({p.x, p.y});
  return s;
}

void check_hull_dt(const Pslg& in, const Result& r) {
  REQUIRE(r.ok());
  const CheckReport rep = check(r.mesh, in, {.delaunay = true});
  INFO((rep.ok() ? std::string() : rep.errors.front()));
  REQUIRE(rep.ok());
  // Every input point maps to a vertex with its coordinates; equal points share one.
  REQUIRE(r.mesh.input_vertex.size() == in.points.size());
  std::map<std::pair<double, double>, VertId> seen;
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    const VertId v = r.mesh.input_vertex[i];
    REQUIRE(v >= 0);
    REQUIRE(r.mesh.vertices[v].x == in.points[i].x);
    REQUIRE(r.mesh.vertices[v].y == in.points[i].y);
    const auto [it, fresh] = seen.emplace(std::make_pair(in.points[i].x, in.points[i].y), v);
    REQUIRE(it->second == v);
  }
  const auto nv = static_cast<std::int64_t>(seen.size());
  CHECK(static_cast<std::int64_t>(r.mesh.vertices.size()) == nv);
  CHECK(r.stats.duplicates_merged == static_cast<std::int64_t>(in.points.size()) - nv);
  // Hull: the boundary edges pass through every boundary point (collinear ones split the
  // hull edges), and Euler's formula for a triangulated disk: T = 2V - 2 - B.
  const auto hull = hull_boundary_points(in.points);
  std::set<std::pair<double, double>> on_edges;
  for (const auto& e : r.mesh.boundary_edges) {
    CHECK(e.marker == 1);
    for (const VertId v : {e.a, e.b}) on_edges.insert({r.mesh.vertices[v].x, r.mesh.vertices[v].y});
  }
  CHECK(on_edges == hull);
  CHECK(r.mesh.boundary_edges.size() == hull.size());
  CHECK(static_cast<std::int64_t>(r.mesh.triangles.size()) ==
        2 * nv - 2 - static_cast<std::int64_t>(r.mesh.boundary_edges.size()));
  CHECK(r.mesh.triangle_region.size() == r.mesh.triangles.size());
  CHECK(r.mesh.triangle_attribute.size() == r.mesh.triangles.size());
}

}  // namespace

TEST_CASE("hull Delaunay: grid points (collinear hull sides, cocircular quads, duplicates)",
          "[hull_dt]") {
  std::mt19937_64 rng(7);
  for (int round = 0; round < 200; ++round) {
    const int g = 2 + static_cast<int>(rng() % 12);
    const int n = 3 + static_cast<int>(rng() % 300);
    Pslg in;
    for (int i = 0; i < n; ++i)
      in.points.push_back(
          {static_cast<double>(rng() % g) * 0.1, static_cast<double>(rng() % g) * 0.1});
    const Result r = mesh(in, SizeSpec::uniform(0), dt_options());
    // Fewer than three distinct points or all on a line: reported, as in the general path.
    const auto hull = hull_boundary_points(in.points);
    std::set<std::pair<double, double>> distinct;
    for (const Vec2& p : in.points) distinct.insert({p.x, p.y});
    bool collinear = true;
    const Vec2 a = in.points[0];
    for (const Vec2& b : in.points)
      for (const Vec2& c : in.points)
        collinear = collinear && pred::orient2d(&a.x, &b.x, &c.x) == 0;
    INFO("round " << round << ", grid " << g << ", " << n << " points");
    if (collinear) {
      CHECK(r.status.code == StatusCode::InvalidInput);
      continue;
    }
    check_hull_dt(in, r);
  }
}

TEST_CASE("hull Delaunay: 20000 random points, rotated grid and a circle", "[hull_dt]") {
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1, 1);
  SECTION("uniform random") {
    Pslg in;
    for (int i = 0; i < 20000; ++i) in.points.push_back({u(rng), u(rng)});
    check_hull_dt(in, mesh(in, SizeSpec::uniform(0), dt_options()));
  }
  SECTION("points on one circle (all cocircular) plus its centre") {
    Pslg in;
    // Exactly cocircular: integer Pythagorean points of x^2 + y^2 = 5^4 * 13^2.
    const std::int64_t R2 = 625 * 169;
    for (std::int64_t x = -325; x <= 325; ++x)
      for (std::int64_t y = -325; y <= 325; ++y)
        if (x * x + y * y == R2)
          in.points.push_back({static_cast<double>(x), static_cast<double>(y)});
    REQUIRE(in.points.size() >= 12);
    in.points.push_back({0, 0});
    check_hull_dt(in, mesh(in, SizeSpec::uniform(0), dt_options()));
  }
  SECTION("a fine grid, shuffled, with every point twice") {
    Pslg in;
    for (int i = 0; i < 60; ++i)
      for (int j = 0; j < 60; ++j) in.points.push_back({i * 0.25, j * 0.25});
    const std::size_t n = in.points.size();
    for (std::size_t i = 0; i < n; ++i) in.points.push_back(in.points[i]);
    std::shuffle(in.points.begin(), in.points.end(), rng);
    check_hull_dt(in, mesh(in, SizeSpec::uniform(0), dt_options()));
  }
}

TEST_CASE("hull Delaunay: the duplicate warning names the first copy and its original",
          "[hull_dt]") {
  Pslg in;
  in.points = {{0, 0}, {1, 0}, {0, 1}, {1, 0}, {0, 0}, {1, 1}, {1, 0}};
  in.point_markers = {5, 6, 7, 8, 9, 10, 11};
  const Result r = mesh(in, SizeSpec::uniform(0), dt_options());
  REQUIRE(r.ok());
  CHECK(r.stats.duplicates_merged == 3);
  REQUIRE(r.status.warnings.size() == 1);
  CHECK(r.status.warnings[0] == "3 duplicate point(s) merged (first: point 3 duplicates point 1)");
  // A merged vertex carries the marker of its first input point.
  CHECK(r.mesh.vertex_markers[r.mesh.input_vertex[3]] == 6);
  CHECK(r.mesh.vertex_markers[r.mesh.input_vertex[4]] == 5);
  CHECK(r.mesh.vertex_markers[r.mesh.input_vertex[5]] == 10);
  check_hull_dt(in, r);
}

TEST_CASE("hull Delaunay: degenerate inputs are reported", "[hull_dt]") {
  for (const std::vector<Vec2>& pts :
       std::vector<std::vector<Vec2>>{{{0, 0}},
                                      {{0, 0}, {1, 1}},
                                      {{0, 0}, {0, 0}, {0, 0}, {0, 0}},
                                      {{0, 0}, {1, 1}, {2, 2}, {3, 3}, {1, 1}},
                                      {{1e-300, 0}, {2e-300, 0}, {3e-300, 0}}}) {
    Pslg in;
    in.points = pts;
    const Result r = mesh(in, SizeSpec::uniform(0), dt_options());
    CHECK(r.status.code == StatusCode::InvalidInput);
    CHECK(r.status.message == "all points are collinear: there is no triangle to make");
  }
  // Three points far apart in magnitude still make one triangle.
  Pslg in;
  in.points = {{0, 0}, {1e-300, 0}, {0, 1e90}};  // (|coordinates| <= 1e100 is accepted)
  check_hull_dt(in, mesh(in, SizeSpec::uniform(0), dt_options()));
}

TEST_CASE("hull Delaunay: nearly coincident, nearly collinear and nearly cocircular points",
          "[hull_dt]") {
  // Inputs on which the floating-point filters of orient2d and incircle cannot decide, so
  // that the exact stages run inside the walk and the cavity tests.
  std::mt19937_64 rng(23);
  auto nudge = [&](double v) {
    const int k = static_cast<int>(rng() % 5) - 2;  // -2..2 ulps
    for (int i = 0; i < k; ++i) v = std::nextafter(v, 1e300);
    for (int i = 0; i > k; --i) v = std::nextafter(v, -1e300);
    return v;
  };
  for (int round = 0; round < 40; ++round) {
    INFO("round " << round);
    Pslg in;
    const double base = round % 2 ? 1e6 : 0.0;  // far from the origin: differences lose bits
    const int g = 3 + static_cast<int>(rng() % 10);
    for (int i = 0; i < 400; ++i) {
      const double x = base + static_cast<double>(rng() % g) * 0x1p-20;
      const double y = base + static_cast<double>(rng() % g) * 0x1p-20;
      in.points.push_back({nudge(x), nudge(y)});
    }
    // A near-line: y = x plus or minus a few ulps, and a near-circle of radius 2^-18.
    for (int i = 0; i < 100; ++i) {
      const double t = base + static_cast<double>(rng() % 4096) * 0x1p-24;
      in.points.push_back({t, nudge(t)});
      const double a = static_cast<double>(rng() % 100000) * 6.283185307179586e-5;
      in.points.push_back(
          {nudge(base + 0x1p-18 * std::cos(a)), nudge(base + 0x1p-18 * std::sin(a))});
    }
    check_hull_dt(in, mesh(in, SizeSpec::uniform(0), dt_options()));
  }
}

TEST_CASE("Options::measure off: same mesh, no quality statistics, no measure stage", "[hull_dt]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0, 1);
  Pslg dt;
  for (int i = 0; i < 2000; ++i) dt.points.push_back({u(rng), u(rng)});
  Pslg sq;
  sq.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  sq.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  for (const auto& [in, size, refine] : {std::tuple{dt, SizeSpec::uniform(0), false},
                                         std::tuple{sq, SizeSpec::uniform(0.05), true}}) {
    Options on, off;
    on.refine = off.refine = refine;
    off.measure = false;
    const Result a = mesh(in, size, on), b = mesh(in, size, off);
    REQUIRE(a.ok());
    REQUIRE(b.ok());
    CHECK(a.stats.quality.q_max >= 1);
    CHECK(b.stats.quality.q_max == 0);
    CHECK(b.stats.quality.edges == 0);
    auto has_measure = [](const Result& r) {
      return std::any_of(r.stats.stages.begin(), r.stats.stages.end(),
                         [](const Stats::Stage& s) { return s.name == "measure"; });
    };
    CHECK(has_measure(a));
    CHECK_FALSE(has_measure(b));
    CHECK(a.mesh.vertices.size() == b.mesh.vertices.size());
    CHECK(a.mesh.triangles == b.mesh.triangles);
    CHECK(a.mesh.boundary_edges.size() == b.mesh.boundary_edges.size());
    // The quality the mesher would have reported is that of measure() on the mesh.
    CHECK(measure(b.mesh.vertices, b.mesh.triangles, size).q_max == a.stats.quality.q_max);
  }
}
