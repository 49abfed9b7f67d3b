// Tests of uvmesh/surface/check3d.h and of the exact predicates behind it
// (surface/src/predicates3d.h): topology, self-intersections (exact, against brute force),
// orient3d against an exact big-integer reference, quality, edge lengths and chordal
// deviation on analytic surfaces.
#include <gmpxx.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "predicates3d.h"
#include "uvmesh/geom/analytic.h"
#include "uvmesh/geom/project.h"
#include "uvmesh/surface/check3d.h"

using namespace uvmesh;
using geom::Vec2;
using geom::Vec3;
using surface::SurfaceMesh;

namespace {

constexpr double kPi = 3.14159265358979323846;
int sgn(double x) {
  return (x > 0) - (x < 0);
}

SurfaceMesh make_mesh(std::vector<Vec3> pts, std::vector<std::array<surface::NodeId, 3>> tris) {
  SurfaceMesh m;
  m.points = std::move(pts);
  m.triangles = std::move(tris);
  m.triangle_face.assign(m.triangles.size(), 0);
  m.point_dim.assign(m.points.size(), 2);
  m.point_entity.assign(m.points.size(), 0);
  m.point_t.assign(m.points.size(), 0.0);
  return m;
}

// Regular octahedron, outward oriented: 0 +x, 1 -x, 2 +y, 3 -y, 4 +z, 5 -z.
SurfaceMesh octahedron(double r = 1.0) {
  return make_mesh(
      {{r, 0, 0}, {-r, 0, 0}, {0, r, 0}, {0, -r, 0}, {0, 0, r}, {0, 0, -r}},
      {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}});
}

// Unit cube, 12 outward triangles.
SurfaceMesh cube() {
  std::vector<Vec3> p;
  for (int i = 0; i < 8; ++i)
    p.push_back({double(i & 1), double((i >> 1) & 1), double((i >> 2) & 1)});
  // Quads as (a b c d) counter-clockwise seen from outside.
  const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4},
                       {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  std::vector<std::array<surface::NodeId, 3>> t;
  for (const auto& f : q) {
    t.push_back({f[0], f[1], f[2]});
    t.push_back({f[0], f[2], f[3]});
  }
  return make_mesh(p, t);
}

// Latitude-longitude sphere of radius r: nu columns, nv bands (poles are single points),
// triangle_uv filled in the parametrization of geom::make_sphere (seam at u = 0 / 2 pi).
SurfaceMesh uv_sphere(double r, int nu, int nv) {
  SurfaceMesh m;
  auto pos = [&](double u, double v) {
    return Vec3(r * std::cos(v) * std::cos(u), r * std::cos(v) * std::sin(u), r * std::sin(v));
  };
  auto uof = [&](int i) { return 2 * kPi * i / nu; };
  auto vof = [&](int j) { return -kPi / 2 + kPi * j / nv; };
  m.points.push_back({0, 0, -r});  // south pole
  for (int j = 1; j < nv; ++j)
    for (int i = 0; i < nu; ++i) m.points.push_back(pos(uof(i), vof(j)));
  m.points.push_back({0, 0, r});  // north pole
  const int north = static_cast<int>(m.points.size()) - 1;
  auto id = [&](int i, int j) { return 1 + (j - 1) * nu + (i % nu); };
  auto add = [&](std::array<int, 3> t, std::array<Vec2, 3> uv) {
    m.triangles.push_back({t[0], t[1], t[2]});
    m.triangle_uv.push_back(uv);
  };
  for (int i = 0; i < nu; ++i) {
    const double u0 = uof(i), u1 = uof(i + 1), um = 0.5 * (u0 + u1);
    add({0, id(i + 1, 1), id(i, 1)}, {Vec2(um, -kPi / 2), Vec2(u1, vof(1)), Vec2(u0, vof(1))});
    for (int j = 1; j + 1 < nv; ++j) {
      add({id(i, j), id(i + 1, j), id(i + 1, j + 1)},
          {Vec2(u0, vof(j)), Vec2(u1, vof(j)), Vec2(u1, vof(j + 1))});
      add({id(i, j), id(i + 1, j + 1), id(i, j + 1)},
          {Vec2(u0, vof(j)), Vec2(u1, vof(j + 1)), Vec2(u0, vof(j + 1))});
    }
    add({north, id(i, nv - 1), id(i + 1, nv - 1)},
        {Vec2(um, kPi / 2), Vec2(u0, vof(nv - 1)), Vec2(u1, vof(nv - 1))});
  }
  m.triangle_face.assign(m.triangles.size(), 0);
  m.point_dim.assign(m.points.size(), 2);
  m.point_entity.assign(m.points.size(), 0);
  m.point_t.assign(m.points.size(), 0.0);
  return m;
}

// Torus (geom::make_torus parametrization), nu x nv grid, triangle_uv filled.
SurfaceMesh uv_torus(double R, double r, int nu, int nv) {
  SurfaceMesh m;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const double u = 2 * kPi * i / nu, v = 2 * kPi * j / nv;
      m.points.push_back({(R + r * std::cos(v)) * std::cos(u), (R + r * std::cos(v)) * std::sin(u),
                          r * std::sin(v)});
    }
  auto id = [&](int i, int j) { return (j % nv) * nu + (i % nu); };
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const Vec2 a(2 * kPi * i / nu, 2 * kPi * j / nv), b(2 * kPi * (i + 1) / nu, a.y),
          c(b.x, 2 * kPi * (j + 1) / nv), d(a.x, c.y);
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangle_uv.push_back({a, b, c});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
      m.triangle_uv.push_back({a, c, d});
    }
  m.triangle_face.assign(m.triangles.size(), 0);
  m.point_dim.assign(m.points.size(), 2);
  m.point_entity.assign(m.points.size(), 0);
  m.point_t.assign(m.points.size(), 0.0);
  return m;
}

geom::Model one_face_model(std::shared_ptr<geom::Surface> s, geom::SurfaceKind kind) {
  geom::Model model;
  model.format = "analytic";
  geom::Face f;
  f.surface = s;
  f.kind = kind;
  f.uv_box = s->bounds();
  model.faces.push_back(f);
  return model;
}

// ---- exact reference for orient3d: GMP rationals (a double converts exactly) ----------
int exact_orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  // Explicit return type: a gmpxx expression must not outlive its temporaries.
  auto D = [&](const Vec3& p, int i) -> mpq_class { return mpq_class(p[i]) - mpq_class(d[i]); };
  const mpq_class adx = D(a, 0), ady = D(a, 1), adz = D(a, 2);
  const mpq_class bdx = D(b, 0), bdy = D(b, 1), bdz = D(b, 2);
  const mpq_class cdx = D(c, 0), cdy = D(c, 1), cdz = D(c, 2);
  const mpq_class det =
      adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) + cdz * (adx * bdy - bdx * ady);
  return sgn(det);
}

std::size_t brute_force_count(const SurfaceMesh& m) {
  std::size_t n = 0;
  for (int i = 0; i < static_cast<int>(m.triangles.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(m.triangles.size()); ++j)
      n += surface::triangles_intersect(m, i, j);
  return n;
}

}  // namespace

// =======================================================================================
// Topology
// =======================================================================================

TEST_CASE("check3d: topology: closed octahedron", "[check3d][topology]") {
  const auto r = surface::check_topology(octahedron());
  CHECK(r.edges == 12);
  CHECK(r.free_edges == 0);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.inconsistent_edges == 0);
  CHECK(r.degenerate_triangles == 0);
  CHECK(r.unreferenced_points == 0);
  CHECK(r.euler_characteristic == 2);
  CHECK(r.close_points.pairs == 0);
  CHECK(r.watertight());
}

TEST_CASE("check3d: topology: cube, and the cube with one triangle removed",
          "[check3d][topology]") {
  auto m = cube();
  CHECK(surface::check_topology(m).watertight());
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  m.triangles.erase(m.triangles.begin() + 5);
  m.triangle_face.erase(m.triangle_face.begin() + 5);
  const auto r = surface::check_topology(m);
  CHECK(r.free_edges == 3);
  CHECK(r.free_list.size() == 3);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.inconsistent_edges == 0);
  CHECK(r.euler_characteristic == 1);  // a disc
  for (const auto& e : r.free_list) {
    CHECK(e.a < e.b);
    REQUIRE(e.triangles.size() == 1);
    CHECK(e.faces.size() == 1);
  }
}

TEST_CASE("check3d: topology: three triangles on one edge", "[check3d][topology]") {
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}},
                     {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}});
  m.triangle_face = {7, 8, 9};
  const auto r = surface::check_topology(m);
  CHECK(r.non_manifold_edges == 1);
  REQUIRE(r.non_manifold_list.size() == 1);
  CHECK(r.non_manifold_list[0].a == 0);
  CHECK(r.non_manifold_list[0].b == 1);
  CHECK(r.non_manifold_list[0].triangles == std::vector<surface::TriId>{0, 1, 2});
  CHECK(r.non_manifold_list[0].faces == std::vector<geom::Id>{7, 8, 9});
  CHECK(r.free_edges == 6);
}

TEST_CASE("check3d: topology: a flipped triangle", "[check3d][topology]") {
  auto m = octahedron();
  std::swap(m.triangles[3][0], m.triangles[3][1]);
  const auto r = surface::check_topology(m);
  CHECK(r.free_edges == 0);
  CHECK(r.non_manifold_edges == 0);
  CHECK(r.inconsistent_edges == 3);
  REQUIRE(r.inconsistent_list.size() == 3);
  for (const auto& e : r.inconsistent_list)
    CHECK(std::find(e.triangles.begin(), e.triangles.end(), 3) != e.triangles.end());
  CHECK_FALSE(r.watertight());
}

TEST_CASE("check3d: topology: degenerate triangles and unreferenced points",
          "[check3d][topology]") {
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {2, 0, 0}, {5, 5, 5}},
                     {{0, 1, 2}, {0, 1, 3}, {1, 1, 2}, {0, 1, 9}});
  const auto r = surface::check_topology(m);
  CHECK(r.zero_area_triangles == 1);  // 0 1 3 collinear
  CHECK(r.repeated_index_triangles == 1);
  CHECK(r.bad_index_triangles == 1);
  CHECK(r.degenerate_triangles == 3);
  CHECK(r.degenerate_list == std::vector<surface::TriId>{1, 2, 3});
  CHECK(r.unreferenced_points == 1);
  CHECK(r.unreferenced_list == std::vector<surface::NodeId>{4});
}

TEST_CASE("check3d: close points: threshold, duplicates, and brute force", "[check3d][topology]") {
  std::vector<Vec3> p = {
      {0, 0, 0},    {1, 1, 1},    {0.5, 0.5, 0.5},        {0.5, 0.5, 0.5 + 1e-10},
      {0.25, 0, 0}, {0.25, 0, 0}, {0.75, 0.5, 0.5 + 1e-6}};
  auto r = surface::find_close_points(p, 1e-8);
  CHECK(r.pairs == 2);
  REQUIRE(r.list.size() == 2);
  CHECK(r.list[0].a == 2);
  CHECK(r.list[0].b == 3);
  CHECK(r.list[0].distance == Approx(1e-10).epsilon(1e-3));
  CHECK(r.list[1].a == 4);
  CHECK(r.list[1].b == 5);
  CHECK(r.min_distance == 0.0);
  // Exact duplicates count even with a zero tolerance.
  CHECK(surface::find_close_points(p, 0.0).pairs == 1);

  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> U(0, 1);
  std::vector<Vec3> q;
  for (int i = 0; i < 3000; ++i)
    q.push_back({U(rng), U(rng), std::floor(U(rng) * 4) / 4});  // planes
  const double rel = 0.01;
  const double tol = rel * [&] {
    geom::Box3 b;
    for (auto& x : q) b.add(x);
    return b.diagonal();
  }();
  std::size_t brute = 0;
  for (std::size_t i = 0; i < q.size(); ++i)
    for (std::size_t j = i + 1; j < q.size(); ++j) {
      const double d = glm::length(q[i] - q[j]);
      brute += d < tol || d == 0;
    }
  r = surface::find_close_points(q, rel, 5);
  CHECK(r.pairs == brute);
  CHECK(brute > 10);
  CHECK(r.list.size() == 5);
}

// =======================================================================================
// Exact orient3d
// =======================================================================================

TEST_CASE("check3d: orient3d: sign convention and simple cases", "[check3d][predicates]") {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  // a b c counter-clockwise seen from +z; d below is positive.
  CHECK(surface::pred3::orient3d(a, b, c, {0, 0, -1}) > 0);
  CHECK(surface::pred3::orient3d(a, b, c, {0, 0, 1}) < 0);
  CHECK(surface::pred3::orient3d(a, b, c, {0.3, 0.7, 0}) == 0);
  CHECK(surface::pred3::orient3d(a, b, c, {0, 0, -1}) == Approx(1.0));
}

TEST_CASE("check3d: orient3d: exact sign against an exact rational reference",
          "[check3d][predicates]") {
  std::mt19937_64 rng(12345);
  std::uniform_real_distribution<double> U(-1, 1);
  using surface::pred3::orient3d;
  int fast_wrong = 0, zeros = 0;
  for (int it = 0; it < 30000; ++it) {
    const int mode = it % 5;
    Vec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng)), c(U(rng), U(rng), U(rng)), d;
    if (mode == 0) {
      d = {U(rng), U(rng), U(rng)};  // generic
    } else {
      // Nearly coplanar: d on the plane of a b c up to rounding, then a few ulps away;
      // modes 2-4 move the whole configuration far from the origin (inexact differences)
      // or to tiny / huge scales.
      const double s = U(rng), t = U(rng);
      const Vec3 off = mode == 2 ? Vec3(1e3, -2e3, 3e3) * (1 + U(rng)) : Vec3(0.0);
      const double scale = mode == 3 ? 0x1p-300 : (mode == 4 ? 0x1p+200 : 1.0);
      a = (a + off) * scale;
      b = (b + off) * scale;
      c = (c + off) * scale;
      d = a + s * (b - a) + t * (c - a);
      const int k = static_cast<int>(rng() % 3), ulps = static_cast<int>(rng() % 5) - 2;
      for (int u = 0; u < std::abs(ulps); ++u)
        d[k] = std::nextafter(d[k], ulps > 0 ? INFINITY : -INFINITY);
      if (it % 50 == 1) d = b;  // exactly degenerate
    }
    const int ref = exact_orient3d(a, b, c, d);
    const int got = sgn(orient3d(a, b, c, d));
    REQUIRE(got == ref);
    // Permutation consistency: an odd permutation flips the sign.
    REQUIRE(sgn(orient3d(b, a, c, d)) == -ref);
    fast_wrong += sgn(surface::pred3::orient3d_fast(a, b, c, d)) != ref;
    zeros += ref == 0;
  }
  // The adversarial inputs are adversarial: plain doubles get many of them wrong.
  INFO("plain double evaluation wrong in " << fast_wrong << " of 30000");
  CHECK(fast_wrong > 100);
  CHECK(zeros > 0);
}

TEST_CASE("check3d: orient3d: exactly coplanar grids and one-ulp moves", "[check3d][predicates]") {
  using surface::pred3::orient3d;
  // Points on the plane x + 2y - z = 0.1 with dyadic-free coordinates: z computed
  // exactly when the sum is representable; check against the reference anyway.
  std::mt19937_64 rng(99);
  std::uniform_int_distribution<int> I(-1000, 1000);
  for (int it = 0; it < 2000; ++it) {
    auto P = [&] {
      const double x = I(rng) / 64.0, y = I(rng) / 64.0;
      return Vec3(x, y, x + 2 * y - 0.125);  // exact
    };
    const Vec3 a = P(), b = P(), c = P();
    Vec3 d = P();
    REQUIRE(orient3d(a, b, c, d) == 0);
    d.z = std::nextafter(d.z, INFINITY);
    REQUIRE(sgn(orient3d(a, b, c, d)) == exact_orient3d(a, b, c, d));
  }
}

// =======================================================================================
// Self-intersections
// =======================================================================================

TEST_CASE("check3d: self-intersection: two crossing triangles", "[check3d][intersect]") {
  auto m = make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, -1}, {0.5, 0.5, 1}, {3, 3, 0.2}},
                     {{0, 1, 2}, {3, 4, 5}});
  m.triangle_face = {4, 6};
  const auto r = surface::find_self_intersections(m);
  CHECK(r.intersecting_pairs == 1);
  REQUIRE(r.pairs.size() == 1);
  CHECK(r.pairs[0].t0 == 0);
  CHECK(r.pairs[0].t1 == 1);
  CHECK(r.pairs[0].f0 == 4);
  CHECK(r.pairs[0].f1 == 6);
  CHECK(r.pairs[0].kind == surface::PairKind::Disjoint);
  // Moved apart: none.
  m.points[5] = {3, 3, 5};
  m.points[3] = {0.5, 0.5, 0.5};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
}

TEST_CASE("check3d: self-intersection: shared vertex", "[check3d][intersect]") {
  // Touching only at the shared vertex 0: nothing.
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {-1, 0, 0.5}, {0, -1, 0.5}},
                     {{0, 1, 2}, {0, 3, 4}});
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  // Coplanar, opposite wedges: nothing.
  m.points[3] = {-1, 0, 0};
  m.points[4] = {0, -1, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  // Coplanar, wedges overlapping (one edge runs inside the other triangle).
  m.points[3] = {1, 1, 0};
  m.points[4] = {2, 0.5, 0};
  auto r = surface::find_self_intersections(m);
  CHECK(r.intersecting_pairs == 1);
  REQUIRE(r.pairs.size() == 1);
  CHECK(r.pairs[0].kind == surface::PairKind::SharedVertex);
  // Coplanar, sharing an edge direction exactly (collinear edges from v).
  m.points[3] = {2, 0, 0};
  m.points[4] = {0, -1, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  // Not coplanar, the opposite edge of the second pierces the first.
  m.points[3] = {0.2, 0.2, -1};
  m.points[4] = {0.2, 0.2, 1};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  // Not coplanar, an edge from v lies in the other triangle's plane inside its wedge.
  m.points[3] = {0.25, 0.25, 0};
  m.points[4] = {0, 0, 1};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  // ... and outside its wedge: nothing.
  m.points[3] = {-0.25, -0.25, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
}

TEST_CASE("check3d: self-intersection: shared edge (folds)", "[check3d][intersect]") {
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 1, 0}, {0.5, -1, 0}}, {{0, 1, 2}, {1, 0, 3}});
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);  // flat, opposite sides
  m.points[3] = {0.5, -1, 0.3};                                        // a dihedral angle
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  m.points[3] = {0.5, 1e-300, 1e-300};  // very sharp dihedral, still not a fold
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  m.points[3] = {0.3, 0.5, 0};  // folded back onto the first triangle
  const auto r = surface::find_self_intersections(m);
  CHECK(r.intersecting_pairs == 1);
  REQUIRE(r.pairs.size() == 1);
  CHECK(r.pairs[0].kind == surface::PairKind::SharedEdge);
  m.points[3] = {3, 5, 0};  // folded, third vertex far outside: still overlapping along ab
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  // Duplicate triangle.
  m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2}, {2, 1, 0}});
  const auto d = surface::find_self_intersections(m);
  CHECK(d.intersecting_pairs == 1);
  REQUIRE(d.pairs.size() == 1);
  CHECK(d.pairs[0].kind == surface::PairKind::Duplicate);
}

TEST_CASE("check3d: self-intersection: coplanar, no shared index", "[check3d][intersect]") {
  auto m = make_mesh({{0, 0, 0}, {2, 0, 0}, {0, 2, 0}, {0.5, 0.5, 0}, {3, 0.5, 0}, {0.5, 3, 0}},
                     {{0, 1, 2}, {3, 4, 5}});
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);  // overlap
  m.points[3] = {0.25, 0.25, 0};
  m.points[4] = {0.5, 0.25, 0};
  m.points[5] = {0.25, 0.5, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);  // one inside the other
  m.points[3] = {1, 1, 0};  // a vertex exactly on the hypotenuse: touching
  m.points[4] = {3, 1, 0};
  m.points[5] = {1, 3, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  m.points[3] = {std::nextafter(1.0, 2.0), 1, 0};  // one ulp away: disjoint
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  // Same in an oblique plane x + y + z = 1 (exact dyadic coordinates).
  m = make_mesh({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {0.5, 0.5, 0}, {1, 0.5, -0.5}, {0.5, 1, -0.5}},
                {{0, 1, 2}, {3, 4, 5}});
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);  // touches at a point
  m.points[3].x = std::nextafter(0.5, 1.0);
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);  // 1 ulp off the plane
}

TEST_CASE("check3d: self-intersection: one-ulp perturbations across a plane",
          "[check3d][intersect]") {
  // T0 in the plane x + y + z = 1; T1 has its apex p exactly on T0 (dyadic), the other
  // two vertices above the plane.
  const Vec3 p(0.375, 0.25, 0.375);
  auto m = make_mesh({{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, p, {1, 1, 1}, {1, 0.5, 1.5}},
                     {{0, 1, 2}, {3, 4, 5}});
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);  // touching
  m.points[3].z = std::nextafter(p.z, 1.0);                            // 1 ulp above
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  m.points[3].z = std::nextafter(p.z, 0.0);  // 1 ulp below: pierces
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  // The apex on an edge of T0 (on the line x + y = 1, z = 0).
  m.points[3] = {0.625, 0.375, 0};
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  m.points[3].x = std::nextafter(0.625, 1.0);  // just outside the edge, above the plane
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
  // Shared vertex with a far edge touching exactly, then 1 ulp away.
  m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0.5, 0.5, 0}, {0.5, 0.5, 1}},
                {{0, 1, 2}, {0, 3, 4}});
  // triangle 1 = (0, p3, p4): p3 on the hypotenuse of T0, its edge 0-p3 lies in T0.
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 1);
  m.points[3] = {0.5, 0.5, std::nextafter(0.0, 1.0)};  // lifted by the smallest double
  CHECK(surface::find_self_intersections(m).intersecting_pairs == 0);
}

TEST_CASE("check3d: self-intersection: random soups against brute force", "[check3d][intersect]") {
  std::mt19937_64 rng(2024);
  for (int trial = 0; trial < 6; ++trial) {
    std::uniform_real_distribution<double> U(0, 1);
    std::uniform_int_distribution<int> G(0, 8);
    SurfaceMesh m;
    // A pool of points, some on coarse grids (exact coplanarity, shared coordinates),
    // so that shared vertices, shared edges and coplanar contacts all occur.
    const int np = 150;
    for (int i = 0; i < np; ++i) {
      if (trial % 2 == 0 || i % 3 == 0)
        m.points.push_back({G(rng) / 8.0, G(rng) / 8.0, trial % 3 == 0 ? 0.5 : G(rng) / 8.0});
      else
        m.points.push_back({U(rng), U(rng), U(rng)});
    }
    std::uniform_int_distribution<int> P(0, np - 1);
    for (int t = 0; t < 400; ++t) {
      const int a = P(rng);
      // Prefer nearby points so triangles are small and many pairs are near each other.
      int b = P(rng), c = P(rng);
      for (int k = 0; k < 20 && glm::length(m.points[b] - m.points[a]) > 0.35; ++k) b = P(rng);
      for (int k = 0; k < 20 && glm::length(m.points[c] - m.points[a]) > 0.35; ++k) c = P(rng);
      m.triangles.push_back({a, b, c});
    }
    // Reuse some edges and vertices explicitly.
    for (int t = 0; t < 100; ++t) {
      const auto tr = m.triangles[static_cast<std::size_t>(P(rng)) % m.triangles.size()];
      m.triangles.push_back({tr[0], tr[1], P(rng)});
    }
    m.triangle_face.assign(m.triangles.size(), 0);
    const std::size_t brute = brute_force_count(m);
    const auto r = surface::find_self_intersections(m, 1000000);
    CHECK(r.intersecting_pairs == brute);
    CHECK(r.pairs.size() == brute);
    for (std::size_t k = 0; k < r.pairs.size(); ++k) {
      CHECK(surface::triangles_intersect(m, r.pairs[k].t0, r.pairs[k].t1));
      if (k > 0)
        CHECK(std::make_pair(r.pairs[k - 1].t0, r.pairs[k - 1].t1) <
              std::make_pair(r.pairs[k].t0, r.pairs[k].t1));
    }
    // Same answer with one thread and a short report.
    const auto r1 = surface::find_self_intersections(m, 10, 1);
    CHECK(r1.intersecting_pairs == brute);
    CHECK(r1.candidate_pairs == r.candidate_pairs);
    REQUIRE(r1.pairs.size() == std::min<std::size_t>(10, brute));
    for (std::size_t k = 0; k < r1.pairs.size(); ++k) CHECK(r1.pairs[k].t0 == r.pairs[k].t0);
    // Restricted to pairs with a triangle of a random subset (a third of the soup, the
    // vector shorter than the mesh): exactly the matching pairs of the whole answer.
    std::vector<char> subset(m.triangles.size() - 7, 0);
    for (auto& s : subset) s = P(rng) % 3 == 0;
    auto in = [&](surface::TriId t) {
      return static_cast<std::size_t>(t) < subset.size() && subset[t];
    };
    std::vector<std::pair<surface::TriId, surface::TriId>> want, got;
    for (const auto& p : r.pairs)
      if (in(p.t0) || in(p.t1)) want.push_back({p.t0, p.t1});
    for (int threads : {1, 2}) {
      const auto rs = surface::find_intersections_with(m, subset, 1000000, threads);
      got.clear();
      for (const auto& p : rs.pairs) got.push_back({p.t0, p.t1});
      CHECK(got == want);
      CHECK(rs.intersecting_pairs == want.size());
    }
    CHECK(!want.empty());
    CHECK(want.size() < r.pairs.size());
    INFO("trial " << trial << ": " << brute << " intersecting pairs of " << r.candidate_pairs
                  << " candidates");
    CHECK(brute > 0);
  }
}

// Independent floating-point reference for generic inputs: segment PQ pierces triangle
// ABC (plane distances and barycentric signs). `margin` is set to false when any
// quantity is too close to zero for doubles to be trusted; such samples are skipped.
bool naive_pierce(const Vec3& P, const Vec3& Q, const Vec3& A, const Vec3& B, const Vec3& C,
                  bool& margin) {
  const Vec3 n = glm::cross(B - A, C - A);
  const double s = glm::length(n) * std::max(glm::length(P - A), glm::length(Q - A));
  const double dP = glm::dot(n, P - A), dQ = glm::dot(n, Q - A);
  if (std::fabs(dP) < 1e-9 * s || std::fabs(dQ) < 1e-9 * s) margin = false;
  if ((dP > 0) == (dQ > 0)) return false;
  const Vec3 X = P + (dP / (dP - dQ)) * (Q - P);
  const double w[3] = {glm::dot(glm::cross(B - A, X - A), n), glm::dot(glm::cross(C - B, X - B), n),
                       glm::dot(glm::cross(A - C, X - C), n)};
  for (double x : w)
    if (std::fabs(x) < 1e-9 * glm::dot(n, n)) margin = false;
  return w[0] > 0 && w[1] > 0 && w[2] > 0;
}

TEST_CASE("check3d: self-intersection: generic random pairs against a floating-point reference",
          "[check3d][intersect]") {
  std::mt19937_64 rng(77);
  std::uniform_real_distribution<double> U(0, 1);
  auto R = [&] { return Vec3(U(rng), U(rng), U(rng)); };
  int compared = 0, hits = 0;
  for (int it = 0; it < 20000; ++it) {
    const bool shared = it % 2 == 1;
    const Vec3 v = R();
    std::vector<Vec3> p = {v, R(), R(), shared ? v : R(), R(), R()};
    auto m = make_mesh(p, {{0, 1, 2}, {shared ? 0 : 3, 4, 5}});
    bool margin = true, expect = false;
    if (shared) {
      // Generic: beyond the shared vertex only through the opposite edges.
      expect = naive_pierce(p[1], p[2], p[0], p[4], p[5], margin) ||
               naive_pierce(p[4], p[5], p[0], p[1], p[2], margin);
    } else {
      for (int i = 0; i < 3; ++i) {
        expect = naive_pierce(p[i], p[(i + 1) % 3], p[3], p[4], p[5], margin) || expect;
        expect = naive_pierce(p[3 + i], p[3 + (i + 1) % 3], p[0], p[1], p[2], margin) || expect;
      }
    }
    if (!margin) continue;
    ++compared;
    hits += expect;
    INFO("iteration " << it);
    REQUIRE(surface::triangles_intersect(m, 0, 1) == expect);
  }
  CHECK(compared > 15000);
  CHECK(hits > 1000);
}

TEST_CASE("check3d: self-intersection: a closed torus is clean; a pushed vertex is found",
          "[check3d][intersect]") {
  auto m = uv_torus(2.0, 0.5, 120, 60);
  const auto topo = surface::check_topology(m);
  CHECK(topo.watertight());
  CHECK(topo.euler_characteristic == 0);
  auto r = surface::find_self_intersections(m);
  CHECK(r.intersecting_pairs == 0);
  CHECK(r.skipped_degenerate == 0);
  CHECK(r.candidate_pairs > m.triangles.size());
  // Push vertex (0, 0) (on the outer equator) through the tube to the other side.
  m.points[0] = {2.0 - 0.75, 0.0, 0.0};
  r = surface::find_self_intersections(m);
  CHECK(r.intersecting_pairs > 0);
  REQUIRE(!r.pairs.empty());
  bool touches = false;
  for (const auto& pr : r.pairs)
    for (auto t : {pr.t0, pr.t1})
      for (auto v : m.triangles[t]) touches = touches || v == 0;
  CHECK(touches);
}

TEST_CASE(
    "check3d: self-intersection: pairs where the model itself intersects (spindle torus vs pushed "
    "vertex)",
    "[check3d][intersect]") {
  // A ring torus meshed on its parametrization, one vertex pushed through the tube: the
  // mesh intersects itself, the surface does not; no pair is the model's.
  {
    auto m = uv_torus(2.0, 0.5, 120, 60);
    const auto model =
        one_face_model(geom::make_torus(geom::Frame{}, 2.0, 0.5), geom::SurfaceKind::Torus);
    m.points[0] = {2.0 - 0.75, 0.0, 0.0};
    const auto r = surface::find_self_intersections(m, 1000000, 1);
    REQUIRE(r.intersecting_pairs > 0);
    CHECK(surface::pairs_intersecting_in_model(m, model, r.pairs).empty());
  }
  // A spindle torus (major radius below the minor one) intersects itself along a circle
  // and an inner lens: the mesh of its parametrization intersects where it does, and the
  // classification finds most of those pairs the model's. Pairs sharing an edge and
  // pairs whose pieces do not meet stay the mesher's.
  {
    auto m = uv_torus(0.5, 1.0, 80, 60);
    const auto model =
        one_face_model(geom::make_torus(geom::Frame{}, 0.5, 1.0), geom::SurfaceKind::Torus);
    const auto r = surface::find_self_intersections(m, 1000000, 1);
    REQUIRE(r.intersecting_pairs > 100);
    REQUIRE(r.pairs.size() == r.intersecting_pairs);
    const auto in_model = surface::pairs_intersecting_in_model(m, model, r.pairs);
    // Measured: 0.74 of the pairs with k = 4, 0.79 with 6, 0.85 with 8. The others are
    // flat triangles crossing next to the intersection circle while the exact surface
    // pieces under them pass each other: the count is a lower bound.
    CHECK(in_model.size() >= r.intersecting_pairs * 7 / 10);
    for (std::size_t k : in_model) CHECK(r.pairs[k].kind != surface::PairKind::SharedEdge);
  }
}

TEST_CASE("check3d: self-intersection: timing on a large sphere", "[check3d][intersect][.perf]") {
  // 1000 x 500 latitude-longitude sphere: 998,000 triangles.
  const auto m = uv_sphere(1.0, 1000, 500);
  const auto t0 = std::chrono::steady_clock::now();
  const auto r = surface::find_self_intersections(m);
  const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  WARN("find_self_intersections: " << m.triangles.size() << " triangles, " << r.candidate_pairs
                                   << " candidate pairs, " << s << " s");
  CHECK(r.intersecting_pairs == 0);
  const auto t1 = std::chrono::steady_clock::now();
  const auto topo = surface::check_topology(m);
  const double s1 = std::chrono::duration<double>(std::chrono::steady_clock::now() - t1).count();
  WARN("check_topology: " << s1 << " s");
  CHECK(topo.watertight());
}

// =======================================================================================
// Quality and edge lengths
// =======================================================================================

TEST_CASE("check3d: quality: equilateral and right isosceles", "[check3d][quality]") {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0.5, std::sqrt(3.0) / 2, 0);
  CHECK(surface::triangle_Q(a, b, c) == Approx(1.0).epsilon(1e-12));
  // Right isosceles with legs 1: h_max = sqrt2, rho = 1/(2 + sqrt2), so
  // Q = sqrt3/6 * sqrt2 * (2 + sqrt2) = sqrt3 (1 + sqrt2) / 3.
  const double expect = std::sqrt(3.0) * (1 + std::sqrt(2.0)) / 3;
  CHECK(surface::triangle_Q(a, b, {0, 1, 0}) == Approx(expect).epsilon(1e-12));
  // Invariant under rotation into 3D and scaling.
  CHECK(surface::triangle_Q({0, 0, 0}, {0, 3, 3}, {3, 0, 3}) == Approx(1.0).epsilon(1e-12));
  CHECK(std::isinf(surface::triangle_Q(a, b, {2, 0, 0})));

  auto m = make_mesh({a, b, c, {0, 1, 0}}, {{0, 1, 2}, {0, 1, 3}});
  const auto r = surface::measure_quality(m);
  CHECK(r.triangles == 2);
  CHECK(r.Q_max == Approx(expect));
  CHECK(r.q_min == Approx(1 / expect));
  CHECK(r.q_mean == Approx((1 + 1 / expect) / 2));
  CHECK(r.Q_p50 == Approx(1.0));
  CHECK(r.share_Q_lt_1_5 == 1.0);
  CHECK(r.min_angle_deg == Approx(45.0));
  CHECK(r.max_angle_deg == Approx(90.0));
  CHECK(r.bad_away_from_corners == 0);
}

TEST_CASE("check3d: quality: bad triangles away from model vertices", "[check3d][quality]") {
  // Two slivers; the first touches a model vertex (point 0), the second does not.
  auto m = make_mesh({{0, 0, 0},
                      {1, 0, 0},
                      {0.5, 0.05, 0},
                      {5, 0, 0},
                      {6, 0, 0},
                      {5.5, 0.01, 0},
                      {0, 2, 0},
                      {1, 2, 0},
                      {0.5, 2 + std::sqrt(0.75), 0}},
                     {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}});
  m.triangle_face = {1, 2, 3};
  m.point_dim[0] = 0;
  const auto r = surface::measure_quality(m);
  CHECK(r.triangles == 3);
  CHECK(r.bad_at_corners == 1);
  CHECK(r.bad_away_from_corners == 1);
  REQUIRE(r.bad_list.size() == 1);
  CHECK(r.bad_list[0].triangle == 1);
  CHECK(r.bad_list[0].face == 2);
  CHECK(r.bad_list[0].Q == Approx(surface::triangle_Q(m.points[3], m.points[4], m.points[5])));
  CHECK(r.share_Q_lt_3 == Approx(1.0 / 3));
  CHECK(r.Q_p99 == r.Q_max);
}

TEST_CASE("check3d: quality: slivers across a gap narrower than the proximity floor",
          "[check3d][quality]") {
  // Three slivers of width 0.01 and 0.05 (Q well above 3), none touching a model vertex.
  // With a floor of 0.02: the first (all points on model edges, width 0.01) spans a gap
  // narrower than the floor; the second has an interior point (dim 2); the third is wider
  // than the floor. Only the first is counted apart.
  auto m = make_mesh({{0, 0, 0},
                      {1, 0, 0},
                      {0.5, 0.01, 0},
                      {5, 0, 0},
                      {6, 0, 0},
                      {5.5, 0.01, 0},
                      {10, 0, 0},
                      {11, 0, 0},
                      {10.5, 0.05, 0}},
                     {{0, 1, 2}, {3, 4, 5}, {6, 7, 8}});
  for (auto& d : m.point_dim) d = 1;
  m.point_dim[5] = 2;
  const auto none = surface::measure_quality(m);
  CHECK(none.bad_away_from_corners == 3);
  CHECK(none.bad_in_narrow_gaps == 0);
  const auto r = surface::measure_quality(m, 100, 0.02);
  CHECK(r.bad_at_corners == 0);
  CHECK(r.bad_in_narrow_gaps == 1);
  CHECK(r.bad_away_from_corners == 2);
  REQUIRE(r.bad_list.size() == 2);
  CHECK(r.bad_list[0].triangle == 1);  // Q 1 / 0.01 beats Q 1 / 0.05
  CHECK(r.bad_list[1].triangle == 2);
}

TEST_CASE("check3d: quality: slivers across a gap within the two edges' CAD tolerances",
          "[check3d][quality]") {
  // Two slivers of width 0.05, all points on model edges. The first spans edges 0 and 1,
  // whose floors (0.03 + 0.03) exceed its width: a gap the CAD model does not resolve. The
  // second has all three points on edge 2 alone: no gap between two edges, counted bad
  // whatever edge 2's floor. Widths are reported.
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {0.5, 0.05, 0}, {5, 0, 0}, {6, 0, 0}, {5.5, 0.05, 0}},
                     {{0, 1, 2}, {3, 4, 5}});
  for (auto& d : m.point_dim) d = 1;
  m.point_entity = {0, 0, 1, 2, 2, 2};
  const std::vector<double> floors{0.03, 0.03, 1.0};
  const auto r = surface::measure_quality(m, 100, 0.001, &floors);
  CHECK(r.bad_in_narrow_gaps == 1);
  CHECK(r.widest_narrow_gap == Approx(0.05));
  CHECK(r.bad_away_from_corners == 1);
  REQUIRE(r.bad_list.size() == 1);
  CHECK(r.bad_list[0].triangle == 1);
  // Floors that sum below the width: nothing excused.
  const std::vector<double> tight{0.02, 0.02, 1.0};
  const auto t = surface::measure_quality(m, 100, 0.001, &tight);
  CHECK(t.bad_in_narrow_gaps == 0);
  CHECK(t.widest_narrow_gap == 0.0);
  CHECK(t.bad_away_from_corners == 2);
}

TEST_CASE("check3d: edge lengths: unit share and histogram", "[check3d][edges]") {
  auto m = make_mesh({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}}, {{0, 1, 2}, {0, 2, 3}});
  auto len = [&](double s) {
    return [&m, s](surface::NodeId a, surface::NodeId b) {
      return s * glm::length(m.points[a] - m.points[b]);
    };
  };
  auto r = surface::measure_edge_lengths(m, len(1.0));
  CHECK(r.edges == 5);
  CHECK(r.unit == 5);  // four of length 1, the diagonal of length sqrt2 (included)
  CHECK(r.unit_share == 1.0);
  CHECK(r.min == 1.0);
  CHECK(r.max == Approx(std::sqrt(2.0)));
  CHECK(r.mean == Approx((4 + std::sqrt(2.0)) / 5));
  REQUIRE(r.bin_count.size() == r.bin_lo.size());
  CHECK(r.bin_lo[7] == Approx(std::sqrt(0.5)));
  CHECK(r.bin_lo[8] == 1.0);
  CHECK(r.bin_count[8] == 4);
  CHECK(r.bin_count[9] == 1);  // sqrt2 starts the next bin
  r = surface::measure_edge_lengths(m, len(0.5));
  CHECK(r.unit == 1);  // only the diagonal (sqrt2/2 = 1/sqrt2)
  CHECK(r.short_edges == 4);
  CHECK(r.unit_share == Approx(0.2));
  r = surface::measure_edge_lengths(m, len(1.25));
  CHECK(r.unit == 4);
  CHECK(r.long_edges == 1);
}

// =======================================================================================
// Chordal deviation
// =======================================================================================

TEST_CASE("check3d: chordal: octahedron inscribed in a sphere gives the known sagitta",
          "[check3d][chordal]") {
  const double R = 2.0;
  auto m = octahedron(R);
  const double h = kPi / 2;
  // (u, v) of the corners in geom::make_sphere's map; poles take the triangle's mid u,
  // the triangle between +y... and +x on the seam side uses u = 2 pi.
  auto uv_of = [&](surface::NodeId id, double umid, bool seam) -> Vec2 {
    switch (id) {
      case 0:
        return {seam ? 2 * kPi : 0.0, 0.0};
      case 2:
        return {h, 0.0};
      case 1:
        return {kPi, 0.0};
      case 3:
        return {3 * h, 0.0};
      case 4:
        return {umid, h};
      default:
        return {umid, -h};
    }
  };
  for (const auto& t : m.triangles) {
    double umin = 1e9, umax = -1e9;
    bool seam = false;
    for (auto id : t)
      if (id == 3) seam = true;
    for (auto id : t)
      if (id < 4) {
        const double u = uv_of(id, 0, seam).x;
        umin = std::min(umin, u);
        umax = std::max(umax, u);
      }
    std::array<Vec2, 3> uv;
    for (int k = 0; k < 3; ++k) uv[k] = uv_of(t[k], 0.5 * (umin + umax), seam);
    m.triangle_uv.push_back(uv);
  }
  const auto model = one_face_model(geom::make_sphere(geom::Frame{}, R), geom::SurfaceKind::Sphere);
  const auto r = surface::measure_chordal(m, model, 2);
  const double sag_c = R - R / std::sqrt(3.0);  // centroid at R/sqrt3 from the center
  const double sag_e = R - R / std::sqrt(2.0);  // edge midpoints at R/sqrt2
  CHECK(r.triangles == 8);
  CHECK(r.samples == 32);
  CHECK(r.not_converged == 0);
  CHECK(r.skipped_triangles == 0);
  CHECK(r.max == Approx(sag_c).epsilon(1e-10));
  CHECK(r.mean == Approx((sag_c + 3 * sag_e) / 4).epsilon(1e-10));
  REQUIRE(r.face_max.size() == 1);
  CHECK(r.face_max[0] == r.max);
  CHECK(r.worst.which == 0);
  CHECK(glm::length(r.worst.foot) == Approx(R).epsilon(1e-12));
  CHECK(glm::length(glm::cross(r.worst.foot, r.worst.x)) == Approx(0.0).margin(1e-9));
}

TEST_CASE("check3d: chordal: fine sphere and torus against the analytic distance",
          "[check3d][chordal]") {
  SECTION("sphere") {
    const double R = 3.0;
    const auto m = uv_sphere(R, 48, 24);
    const auto model =
        one_face_model(geom::make_sphere(geom::Frame{}, R), geom::SurfaceKind::Sphere);
    const auto r = surface::measure_chordal(m, model, 2);
    // Distance of an inner point x to the sphere: R - |x|.
    double emax = 0, esum = 0;
    for (const auto& t : m.triangles) {
      const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
      for (const Vec3& x : {(a + b + c) / 3.0, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)}) {
        emax = std::max(emax, R - glm::length(x));
        esum += R - glm::length(x);
      }
    }
    CHECK(r.not_converged == 0);
    CHECK(r.max == Approx(emax).epsilon(1e-9));
    CHECK(r.mean == Approx(esum / r.samples).epsilon(1e-9));
    // Thread count does not change anything.
    const auto r1 = surface::measure_chordal(m, model, 1);
    CHECK(r1.max == r.max);
    CHECK(r1.mean == r.mean);
    CHECK(r1.worst.triangle == r.worst.triangle);
  }
  SECTION("torus") {
    const double R = 2.0, rr = 0.6;
    const auto m = uv_torus(R, rr, 64, 24);
    const auto model =
        one_face_model(geom::make_torus(geom::Frame{}, R, rr), geom::SurfaceKind::Torus);
    const auto r = surface::measure_chordal(m, model, 0);
    double emax = 0;
    for (const auto& t : m.triangles) {
      const Vec3 a = m.points[t[0]], b = m.points[t[1]], c = m.points[t[2]];
      for (const Vec3& x : {(a + b + c) / 3.0, 0.5 * (a + b), 0.5 * (b + c), 0.5 * (c + a)}) {
        const double rho = std::hypot(x.x, x.y);
        emax = std::max(emax, std::fabs(std::hypot(rho - R, x.z) - rr));
      }
    }
    CHECK(r.not_converged == 0);
    CHECK(r.max == Approx(emax).epsilon(1e-9));
  }
}

TEST_CASE("check3d: chordal: projection from a poor start, and skipped triangles",
          "[check3d][chordal]") {
  const auto s = geom::make_sphere(geom::Frame{}, 1.0);
  // Start far from the foot point and near a pole.
  const Vec3 x = Vec3(0.3, 0.4, 0.5);
  const auto p = geom::project_to_surface(*s, x, Vec2(2.0, 1.5), s->bounds(), 1.0);
  CHECK(p.converged);
  CHECK(p.distance == Approx(1.0 - glm::length(x)).epsilon(1e-10));
  // Point on the axis beyond the pole: the pole itself is the answer (a bound).
  const auto q = geom::project_to_surface(*s, Vec3(0, 0, 2), Vec2(0.3, 1.0), s->bounds(), 1.0);
  CHECK(q.distance == Approx(1.0).epsilon(1e-8));

  auto m = octahedron();
  const auto model = one_face_model(s, geom::SurfaceKind::Sphere);
  CHECK(surface::measure_chordal(m, model).skipped_triangles == 8);  // no triangle_uv
}

TEST_CASE("check3d: chordal: projection converges below the noise of the squared distance",
          "[check3d][chordal]") {
  // A point 3.5e-5 off a cylinder far from the origin, the start a little off: a start
  // 1e-10 off in u is a tangential residual of 7.5e-10, well above the tolerances, whose
  // removal gains less than the rounding noise of |sigma - x|^2 (about 2 d |x| eps): the
  // step must be accepted on the tangential residual, not rejected as "no decrease".
  geom::Frame f = geom::Frame::from_axis({100.0, 200.0, 300.0}, glm::normalize(Vec3(1, 2, 3)));
  const auto cyl = geom::make_cylinder(f, 7.5, {0.0, 5.0});
  int n = 0;
  for (double u0 = 0.1; u0 < 6.2; u0 += 0.37)
    for (double d : {3.5e-5, 1e-7, 0.0})
      for (double du : {1e-6, 1e-10, -3e-10}) {
        const auto e = cyl->eval(u0, 1.2);
        const Vec3 x = e.p + d * e.normal();
        const auto p = geom::project_to_surface(*cyl, x, Vec2(u0 + du, 1.2), cyl->bounds(), 0.07);
        INFO("u0 " << u0 << " d " << d << " iterations " << p.iterations);
        CHECK(p.converged);
        CHECK(p.distance == Approx(d).margin(1e-11));
        ++n;
      }
  CHECK(n > 100);
}

TEST_CASE("check3d: quality: a bad triangle is excused only at a corner under 20 degrees",
          "[check3d][quality]") {
  // Face 1: a 10-degree wedge at model vertex 0, a fan of two bad triangles (Q about 7).
  // Face 2: two bad triangles (Q about 6) at a 90-degree corner (model vertex 4).
  const double a = 10.0 * 3.14159265358979323846 / 180.0;
  auto m = make_mesh({{0, 0, 0},
                      {10, 0, 0},
                      {10 * std::cos(a / 2), 10 * std::sin(a / 2), 0},
                      {10 * std::cos(a), 10 * std::sin(a), 0},
                      {20, 0, 0},
                      {30, 0, 0},
                      {21, 1, 0},
                      {20, 10, 0}},
                     {{0, 1, 2}, {0, 2, 3}, {4, 5, 6}, {4, 6, 7}});
  m.triangle_face = {1, 1, 2, 2};
  m.point_dim[0] = 0;
  m.point_dim[4] = 0;
  const auto r = surface::measure_quality(m);
  REQUIRE(r.bad_at_corners == 4);
  CHECK(r.bad_at_acute_corners == 2);
  CHECK(std::abs(r.smallest_corner_deg - 10.0) < 1e-9);
  CHECK(r.Q_over_10 == 0);  // Q of about 6 and 7
  CHECK(r.bad_away_from_corners == 0);
}
