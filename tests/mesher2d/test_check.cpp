// Tests of the mesh checker (check.h) on hand-made meshes: every valid one passes, every
// invalid one is detected with a message naming the entities. These do not call the
// mesher, so they pin the checker independently of it.
#include <catch2/catch.hpp>
#include <cmath>
#include <ctime>
#include <string>

#include "uvmesh/mesher2d/check.h"

using namespace uvmesh::m2d;

namespace {

// Input square 0(0,0) 1(2,0) 2(2,2) 3(0,2) with its four sides as segments.
Pslg square_pslg() {
  Pslg in;
  in.points = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  return in;
}

// The square cut into four triangles around a centre vertex 4 (1,1):
//
//   3 ------- 2
//   | \  t2 / |
//   |t3  4  t1|
//   | /  t0 \ |
//   0 ------- 1
Mesh square_mesh() {
  Mesh m;
  m.vertices = {{0, 0}, {2, 0}, {2, 2}, {0, 2}, {1, 1}};
  m.triangles = {{0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}};
  m.boundary_edges = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  m.input_vertex = {0, 1, 2, 3};
  m.triangle_region = {0, 0, 0, 0};
  m.triangle_attribute = {0, 0, 0, 0};
  m.vertex_markers = {1, 1, 1, 1, 0};
  return m;
}

bool has_error(const CheckReport& r, const std::string& needle) {
  for (auto& e : r.errors)
    if (e.find(needle) != std::string::npos) return true;
  return false;
}

std::string all(const CheckReport& r) {
  std::string s;
  for (auto& e : r.errors) s += e + "\n";
  return s;
}

}  // namespace

TEST_CASE("check accepts a valid Delaunay mesh of a square", "[check]") {
  const CheckReport r = check(square_mesh(), square_pslg(), {.delaunay = true});
  INFO(all(r));
  CHECK(r.ok());
  CHECK(r.triangles_checked == 4);
  CHECK(r.edges_checked == 8);
}

TEST_CASE("check accepts two triangles on a cocircular square (incircle == 0 is Delaunay)",
          "[check]") {
  Mesh m;
  m.vertices = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.boundary_edges = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  m.input_vertex = {0, 1, 2, 3};
  const CheckReport r = check(m, square_pslg(), {.delaunay = true});
  INFO(all(r));
  CHECK(r.ok());
}

TEST_CASE("check reports a clockwise triangle", "[check]") {
  Mesh m = square_mesh();
  m.triangles[1] = {1, 4, 2};  // clockwise
  const CheckReport r = check(m, square_pslg());
  INFO(all(r));
  CHECK(has_error(r, "triangle 1 (1,4,2) is not counter-clockwise (clockwise)"));
}

TEST_CASE("check reports a degenerate triangle", "[check]") {
  Mesh m;
  m.vertices = {{0, 0}, {1, 0}, {2, 0}, {1, 1}};
  m.triangles = {{0, 1, 3}, {1, 2, 3}, {0, 2, 1}};
  const CheckReport r = check(m, Pslg{}, {.segments_present = false});
  INFO(all(r));
  CHECK(has_error(r, "triangle 2 (0,2,1) is not counter-clockwise (degenerate"));
}

TEST_CASE("check reports out-of-range and repeated triangle vertices", "[check]") {
  Mesh m = square_mesh();
  m.triangles.push_back({0, 1, 7});
  m.triangles.push_back({0, 0, 1});
  m.triangle_region.clear();
  m.triangle_attribute.clear();
  const CheckReport r = check(m, square_pslg());
  INFO(all(r));
  CHECK(has_error(r, "triangle 4 (0,1,7) has a vertex index out of range"));
  CHECK(has_error(r, "triangle 5 (0,0,1) has a repeated vertex"));
}

TEST_CASE("check reports a missing segment", "[check]") {
  // The input also asks for the diagonal 0-2; the mesh has the other diagonal 1-3.
  Pslg in = square_pslg();
  in.segments.push_back({0, 2, 2});
  Mesh m;
  m.vertices = {{0, 0}, {2, 0}, {2, 2}, {0, 2}};
  m.triangles = {{0, 1, 3}, {1, 2, 3}};
  m.boundary_edges = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  m.input_vertex = {0, 1, 2, 3};
  const CheckReport r = check(m, in);
  INFO(all(r));
  CHECK(has_error(r, "segment 4 (input 0-2) is not covered by constrained edges"));
  CHECK(r.errors.size() == 1);
}

TEST_CASE("check follows a segment through exactly collinear and rounded Steiner vertices",
          "[check]") {
  // Segment 0-1 from (0,0) to (3,1) split at (1, 1/3) and (2, 2/3) rounded to doubles:
  // not exactly on the line, but within rounding of it.
  Pslg in;
  in.points = {{0, 0}, {3, 1}, {0, 1}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}};
  Mesh m;
  m.vertices = {{0, 0}, {3, 1}, {0, 1}, {1, 1.0 / 3}, {2, 2.0 / 3}};
  m.triangles = {{0, 3, 2}, {3, 4, 2}, {4, 1, 2}};
  m.boundary_edges = {{0, 3, 1}, {3, 4, 1}, {4, 1, 1}, {1, 2, 1}, {2, 0, 1}};
  m.input_vertex = {0, 1, 2};
  {
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(r.ok());
  }
  SECTION("a chain vertex 1e-6 below the line: the segment enters the domain uncovered") {
    m.vertices[4].y -= 1e-6;
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(
        r,
        "segment 0 (input 0-1) is not covered by constrained edges: the chain from vertex 0 toward "
        "vertex 1 stops at vertex 3"));
    CHECK(has_error(r, "constrained edge 1 edge (3,4)"));
  }
  SECTION("a chain vertex 1e-6 above the line: the segment is outside, the chain on no segment") {
    m.vertices[4].y += 1e-6;
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(
        r,
        "constrained edge 1 edge (3,4) (1, 0.33333333333333331)-(2, 0.66666766666666666) is not on "
        "the chain of any input segment"));
    CHECK(has_error(r, "constrained edge 2 edge (4,1)"));
  }
}

TEST_CASE("check follows a chain through a vertex 1 ulp from an input point", "[check]") {
  // Segment 1 from B (1.5,0) to A (1,1) ends with a rounded Steiner vertex X = (1+ulp, 1):
  // X has A's coordinate on the dominant (y) axis of the segment, so only the minor axis
  // tells that the chain advances from X to A (the mesher makes such vertices when it
  // splits a near-crossing at an input point: gen::random_segments(192)).
  const double u = std::nextafter(1.0, 2.0);
  Pslg in;
  in.points = {{0, 0}, {1.5, 0}, {1, 1}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 0, 1}};
  Mesh m;
  m.vertices = {{0, 0}, {1.5, 0}, {u, 1}, {1, 1}};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.boundary_edges = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  m.input_vertex = {0, 1, 3};
  const CheckReport r = check(m, in);
  INFO(all(r));
  CHECK(r.ok());
}

TEST_CASE("check accepts segments removed with the exterior", "[check]") {
  // The square plus a dangling segment 4 from corner 1 (2,0) out to (3,-1): the mesher
  // removes it with the exterior, and input point 4 (outside) has no vertex. The chain
  // of segment 4 stops at vertex 1 where the segment leaves the domain: accepted.
  Pslg in = square_pslg();
  in.points.push_back({3, -1});
  in.segments.push_back({1, 4, 2});
  Mesh m = square_mesh();
  m.input_vertex.push_back(kNone);
  const CheckReport r = check(m, in);
  INFO(all(r));
  CHECK(r.ok());
  SECTION("but not a dangling segment pointing into the domain") {
    in.points.back() = {-1, 3};  // from (2,0) to (-1,3): crosses the square
    m.input_vertex.back() = kNone;
    const CheckReport r2 = check(m, in);
    INFO(all(r2));
    CHECK(has_error(
        r2,
        "segment 4 (input 1-4) is not covered by constrained edges: the chain from vertex 1 toward "
        "input point (-1, 3) stops at vertex 1"));
  }
}

TEST_CASE("check reports a boundary edge that is not constrained", "[check]") {
  Mesh m = square_mesh();
  m.boundary_edges.erase(m.boundary_edges.begin() + 1);  // (1,2)
  Pslg in = square_pslg();
  const CheckReport r = check(m, in, {.segments_present = false});
  INFO(all(r));
  CHECK(has_error(
      r,
      "edge (1,2) is on the domain boundary but is not a constrained edge (triangle 1 (1,2,4))"));
}

TEST_CASE("check reports a constrained edge that is in no triangle", "[check]") {
  Mesh m = square_mesh();
  m.boundary_edges.push_back({0, 2, 5});  // the square has no edge 0-2
  const CheckReport r = check(m, square_pslg());
  INFO(all(r));
  CHECK(has_error(r, "constrained edge 4 edge (0,2) is not an edge of any triangle"));
}

TEST_CASE("check reports a triangle in a hole", "[check]") {
  // Square [0,3]^2 with a hole [1,2]^2 whose seed is (1.5,1.5); the mesh wrongly keeps
  // the two triangles of the hole.
  Pslg in;
  in.points = {{0, 0}, {3, 0}, {3, 3}, {0, 3}, {1, 1}, {2, 1}, {2, 2}, {1, 2}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1},
                 {4, 5, 2}, {5, 6, 2}, {6, 7, 2}, {7, 4, 2}};
  in.holes = {{1.5, 1.5}};
  Mesh m;
  m.vertices = in.points;
  m.triangles = {{0, 1, 5}, {0, 5, 4}, {1, 2, 6}, {1, 6, 5},
                 {2, 3, 7}, {2, 7, 6}, {3, 0, 4}, {3, 4, 7}};
  for (auto& s : in.segments) m.boundary_edges.push_back({s.a, s.b, s.marker});
  m.input_vertex = {0, 1, 2, 3, 4, 5, 6, 7};
  {
    const CheckReport r = check(m, in, {.delaunay = false});
    INFO(all(r));
    CHECK(r.ok());
  }
  m.triangles.push_back({4, 5, 6});
  m.triangles.push_back({4, 6, 7});
  const CheckReport r = check(m, in);
  INFO(all(r));
  CHECK(has_error(r, "hole seed 0 (1.5, 1.5) lies in triangle"));
}

TEST_CASE("check reports a non-Delaunay edge unless it is constrained", "[check]") {
  // Rhombus A(-2,0) B(0,-1) C(2,0) D(0,1): the Delaunay diagonal is BD; the mesh uses AC.
  Pslg in;
  in.points = {{-2, 0}, {0, -1}, {2, 0}, {0, 1}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  Mesh m;
  m.vertices = in.points;
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.boundary_edges = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  m.input_vertex = {0, 1, 2, 3};
  {
    const CheckReport r = check(m, in, {.delaunay = true});
    INFO(all(r));
    CHECK(has_error(
        r,
        "edge (0,2) is not Delaunay: vertex 3 of triangle 1 (0,2,3) is inside the circumcircle of "
        "triangle 0 (0,1,2)"));
  }
  CHECK(check(m, in, {.delaunay = false}).ok());
  // A constrained diagonal (an input segment) is exempt from the Delaunay test.
  Pslg with_diagonal = in;
  with_diagonal.segments.push_back({0, 2, 3});
  m.boundary_edges.push_back({0, 2, 3});
  CHECK(check(m, with_diagonal, {.delaunay = true}).ok());
  // A constrained edge that is no input segment is an error of its own.
  CHECK(has_error(
      check(m, in),
      "constrained edge 4 edge (0,2) (-2, 0)-(2, 0) is not on the chain of any input segment"));
  // The Delaunay diagonal passes.
  m.triangles = {{0, 1, 3}, {1, 2, 3}};
  m.boundary_edges.pop_back();
  CHECK(check(m, in, {.delaunay = true}).ok());
}

TEST_CASE("check reports a non-manifold edge and inconsistent orientation", "[check]") {
  Mesh m;
  m.vertices = {{0, 0}, {1, 0}, {0.5, 1}, {0.5, -1}, {0.5, 2}};
  SECTION("three triangles on one edge") {
    m.triangles = {{0, 1, 2}, {1, 0, 3}, {0, 1, 4}};
    const CheckReport r = check(m, Pslg{}, {.segments_present = false});
    INFO(all(r));
    CHECK(has_error(r,
                    "edge (0,1) is non-manifold: shared by 3 triangles: triangle 0 (0,1,2), "
                    "triangle 1 (1,0,3), "
                    "triangle 2 (0,1,4)"));
  }
  SECTION("two triangles using an edge in the same direction") {
    m.triangles = {{0, 1, 2}, {0, 1, 4}};
    const CheckReport r = check(m, Pslg{}, {.segments_present = false});
    INFO(all(r));
    CHECK(has_error(
        r, "edge (0,1) has inconsistent orientation: triangle 0 (0,1,2) and triangle 1 (0,1,4)"));
  }
}

TEST_CASE("check reports triangles wrapping twice around a vertex", "[check]") {
  // Five triangles around vertex 0, each turning by 144 degrees: every edge is used
  // consistently, but the fan covers the plane twice.
  Mesh m;
  m.vertices = {{0, 0}};
  const double pi = std::acos(-1.0);
  for (int i = 0; i < 5; ++i)
    m.vertices.push_back({std::cos(i * 144 * pi / 180), std::sin(i * 144 * pi / 180)});
  for (int i = 0; i < 5; ++i) {
    m.triangles.push_back({0, 1 + i, 1 + (i + 1) % 5});
    m.boundary_edges.push_back({1 + i, 1 + (i + 1) % 5, 1});
  }
  const CheckReport r = check(m, Pslg{}, {.segments_present = false});
  INFO(all(r));
  CHECK(has_error(r, "vertex 0 (0, 0): the triangles around this interior vertex overlap"));
  CHECK(has_error(r, "720 degrees"));
}

TEST_CASE("check reports coincident vertices", "[check]") {
  Mesh m = square_mesh();
  m.vertices.push_back({2, 2});
  const CheckReport r = check(m, square_pslg());
  INFO(all(r));
  CHECK(has_error(r, "vertices 2 and 5 coincide at (2, 2)"));
}

TEST_CASE("check reports input points and seeds", "[check]") {
  Pslg in = square_pslg();
  SECTION("input point inside the domain without a vertex") {
    in.points.push_back({0.5, 1.0});
    Mesh m = square_mesh();
    m.input_vertex.push_back(kNone);
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(r, "input point 4 (0.5, 1) has no mesh vertex but lies in the domain"));
  }
  SECTION("input point outside the domain may be dropped") {
    in.points.push_back({5, 5});
    Mesh m = square_mesh();
    m.input_vertex.push_back(kNone);
    CHECK(check(m, in).ok());
  }
  SECTION("input point mapped to a vertex elsewhere") {
    Mesh m = square_mesh();
    m.input_vertex[1] = 2;
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(r, "input point 1 (2, 0) maps to vertex 2 at a different place (2, 2)"));
  }
  SECTION("input_vertex of the wrong size") {
    Mesh m = square_mesh();
    m.input_vertex.pop_back();
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(r, "mesh.input_vertex has 3 entries for 4 input points"));
  }
  SECTION("region seed outside every triangle") {
    in.regions.push_back({{3, 3}, 7.0});
    const CheckReport r = check(square_mesh(), in);
    INFO(all(r));
    CHECK(has_error(r, "region seed 0 (3, 3) lies in no triangle"));
  }
  SECTION("region seed with the wrong attribute") {
    in.regions.push_back({{1.5, 0.5}, 7.0});
    Mesh m = square_mesh();
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(r,
                    "region seed 0 (1.5, 0.5) with attribute 7 lies in triangle 0 (0,1,4) whose "
                    "attribute is 0"));
    m.triangle_attribute = {7, 7, 7, 7};
    CHECK(check(m, in).ok());
  }
  SECTION("regions differ across an edge that is not constrained") {
    Mesh m = square_mesh();
    m.triangle_region = {0, 1, 1, 1};
    m.triangle_attribute = {0, 2, 2, 2};
    const CheckReport r = check(m, in);
    INFO(all(r));
    CHECK(has_error(r, "edge (1,4) is not constrained but separates regions"));
    CHECK(has_error(r, "edge (1,4) is not constrained but separates attributes"));
  }
}

TEST_CASE("check stops collecting at max_errors", "[check]") {
  Mesh m = square_mesh();
  for (auto& t : m.triangles) std::swap(t[0], t[1]);
  const CheckReport r = check(m, square_pslg(), {.max_errors = 3});
  CHECK(r.errors.size() == 3);
}

TEST_CASE("check runs on a million triangles in about a second", "[check][perf]") {
  // Structured n x n grid of integer points, each cell cut by its SW-NE diagonal:
  // 2 (n-1)^2 = 1.0e6 triangles; all cells are cocircular, so incircle is exactly 0 and
  // the Delaunay test takes the exact path of the predicate on every edge.
  const int n = 708;
  Mesh m;
  m.vertices.reserve(static_cast<std::size_t>(n) * n);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      m.vertices.push_back({static_cast<double>(i), static_cast<double>(j)});
  auto id = [&](int i, int j) { return j * n + i; };
  for (int j = 0; j + 1 < n; ++j)
    for (int i = 0; i + 1 < n; ++i) {
      m.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  for (int i = 0; i + 1 < n; ++i) {
    m.boundary_edges.push_back({id(i, 0), id(i + 1, 0), 1});
    m.boundary_edges.push_back({id(n - 1, i), id(n - 1, i + 1), 1});
    m.boundary_edges.push_back({id(i + 1, n - 1), id(i, n - 1), 1});
    m.boundary_edges.push_back({id(0, i + 1), id(0, i), 1});
  }
  Pslg in;
  const double L = n - 1;
  in.points = {{0, 0}, {L, 0}, {L, L}, {0, L}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  in.regions = {{{0.5, 0.25}, 0.0}};
  m.input_vertex = {id(0, 0), id(n - 1, 0), id(n - 1, n - 1), id(0, n - 1)};
  // Processor time, not wall time: the test machines are shared and often loaded.
  const std::clock_t c0 = std::clock();
  const CheckReport r = check(m, in, {.delaunay = true});
  const double sec = static_cast<double>(std::clock() - c0) / CLOCKS_PER_SEC;
  INFO(all(r));
  CHECK(r.ok());
  CHECK(r.triangles_checked == 2 * (n - 1) * (n - 1));
  WARN("check of " << r.triangles_checked << " triangles: " << sec << " s of processor time");
#ifdef NDEBUG
  CHECK(sec < 3.0);  // about 0.7 s on the 2-core test machine
#endif
}
