// Regression tests of uvmesh::m2d::mesh, each named after the problem it pins, with the
// input inline and a comment on why it is hard. Cases found by the invariant tests name
// the generator family and seed they came from (pslg_gen.h) and were shrunk by hand or
// by deleting points and segments while the failure persisted.
#include <catch2/catch.hpp>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/mesher2d/predicates.h"

using namespace uvmesh::m2d;

namespace {

Options cdt() {
  Options o;
  o.refine = false;
  o.split_segments = false;
  o.optimize = false;
  return o;
}

std::string errors(const CheckReport& r) {
  std::string s;
  for (auto& e : r.errors) s += e + "\n";
  return s;
}

// Runs the mesher and the checker; the result must be ok and valid.
Result mesh_ok(const Pslg& in, const SizeSpec& size, const Options& opt, bool delaunay) {
  Result r = mesh(in, size, opt);
  INFO("status: " << r.status.message);
  REQUIRE(r.ok());
  const CheckReport rep = check(r.mesh, in, {.delaunay = delaunay});
  INFO(errors(rep));
  CHECK(rep.ok());
  return r;
}

void add_loop(Pslg& g, std::initializer_list<Vec2> pts, int marker) {
  const VertId base = static_cast<VertId>(g.points.size());
  const VertId n = static_cast<VertId>(pts.size());
  g.points.insert(g.points.end(), pts);
  for (VertId i = 0; i < n; ++i) g.segments.push_back({base + i, base + (i + 1) % n, marker});
}

int constrained_degree(const Mesh& m, VertId v) {
  int d = 0;
  for (auto& e : m.boundary_edges) d += (e.a == v) + (e.b == v);
  return d;
}

}  // namespace

TEST_CASE("points on a 4x4 integer grid, all cocircular in groups of 4", "[regression]") {
  // Every unit cell has four cocircular corners: incircle is exactly 0 for each of its
  // two diagonals, so the kernel must neither loop flipping them nor build an overlapping
  // cavity; any diagonal is Delaunay. 16 points, 12 on the hull: 2*16 - 2 - 12 = 18.
  Pslg in;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      in.points.push_back({static_cast<double>(i), static_cast<double>(j)});
  const Result r = mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  CHECK(r.mesh.triangles.size() == 18);
  CHECK(r.mesh.vertices.size() == 16);
  CHECK(r.mesh.boundary_edges.size() == 12);  // the hull edges, split at the 8 edge-midpoints
}

TEST_CASE("segment collinear with three input points", "[regression]") {
  // Segment 4 runs from (0,0) to (4,12) through input points (1,3), (2,6), (3,9): it must
  // be split at all three (exactly collinear: orient2d == 0), not recovered as one edge
  // with degenerate triangles along it, nor discretized past them with rounded Steiner
  // points that leave each input point a needle's width off the chain. The segment is
  // slanted on purpose: on an axis-parallel one the Steiner points are exactly collinear
  // too and enforcement happens to split at the input points anyway.
  Pslg in;
  add_loop(in, {{-1, -1}, {5, -1}, {5, 13}, {-1, 13}}, 1);
  in.points.insert(in.points.end(), {{0, 0}, {4, 12}, {1, 3}, {2, 6}, {3, 9}});
  in.segments.push_back({4, 5, 2});
  SECTION("constrained Delaunay, no refinement") {
    const Result r = mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
    CHECK(r.stats.segments_split_at_vertices >= 1);
    for (VertId i = 6; i <= 8; ++i) CHECK(constrained_degree(r.mesh, r.mesh.input_vertex[i]) == 2);
  }
  SECTION("refined with size 0.3") {
    // Found by test_invariants "a segment through input vertices is split there"
    // (gen::segment_through_vertex, most seeds with refine=true), failing at commit
    // cae6781: with split_segments=true the segment was discretized from end to end and
    // the input points on it got no constrained edge (segments_split_at_vertices == 0).
    const Result r = mesh_ok(in, SizeSpec::uniform(0.3), Options{}, false);
    CHECK(r.stats.segments_split_at_vertices >= 1);
    for (VertId i = 6; i <= 8; ++i) {
      INFO("input point " << i);
      CHECK(constrained_degree(r.mesh, r.mesh.input_vertex[i]) == 2);
    }
  }
  SECTION("axis-parallel, refined with size 0.3") {
    Pslg h;
    add_loop(h, {{-1, -1}, {5, -1}, {5, 1}, {-1, 1}}, 1);
    h.points.insert(h.points.end(), {{0, 0}, {4, 0}, {1, 0}, {2, 0}, {3, 0}});
    h.segments.push_back({4, 5, 2});
    const Result r = mesh_ok(h, SizeSpec::uniform(0.3), Options{}, false);
    for (VertId i = 6; i <= 8; ++i) CHECK(constrained_degree(r.mesh, r.mesh.input_vertex[i]) == 2);
  }
}

TEST_CASE("two segments meeting at 1 degree", "[regression]") {
  // A 1-degree angle between two constrained segments: no triangle can be well shaped
  // there, so a quality-driven refinement would not terminate; a size-driven one must
  // stop, and boundary discretization must not put Steiner points of one segment across
  // the other (at distance r, they are only r * 0.017 apart).
  Pslg in;
  add_loop(in, {{-1, -1}, {1, -1}, {1, 1}, {-1, 1}}, 1);
  const double a = std::numbers::pi / 180;
  in.points.insert(in.points.end(), {{0, 0}, {0.8, 0}, {0.8 * std::cos(a), 0.8 * std::sin(a)}});
  in.segments.push_back({4, 5, 2});
  in.segments.push_back({4, 6, 2});
  SECTION("constrained Delaunay") {
    mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  }
  SECTION("refined") {
    const Result r = mesh_ok(in, SizeSpec::uniform(0.05), Options{}, false);
    CHECK(r.mesh.triangles.size() < 20000);  // 4 / (0.43 * 0.05^2) ~ 3700 expected
  }
}

TEST_CASE("near-duplicate points 1 ulp apart", "[regression]") {
  // (1,1), (1+ulp,1), (1,1+ulp): distinct points 2.2e-16 apart. They are not duplicates
  // and must all be vertices; the triangles between them have areas near 1e-32, where
  // every floating-point orientation is noise and only the exact predicate decides.
  const double u = std::nextafter(1.0, 2.0);
  Pslg in;
  add_loop(in, {{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 1);
  in.points.insert(in.points.end(), {{1, 1}, {u, 1}, {1, u}, {u, u}, {1, 1}});
  SECTION("constrained Delaunay") {
    const Result r = mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
    CHECK(r.stats.duplicates_merged == 1);  // only the exact copy of (1,1)
    CHECK(r.mesh.vertices.size() == 8);
    CHECK(r.mesh.input_vertex[8] == r.mesh.input_vertex[4]);
  }
  SECTION("refined") {
    mesh_ok(in, SizeSpec::uniform(0.2), Options{}, false);
  }
}

TEST_CASE("hole touching the outer boundary at one vertex", "[regression]") {
  // The triangular hole (2,0) (3,2) (1,2) shares vertex (2,0) with the outer boundary:
  // the domain is still connected but vertex (2,0) has two separate fans of triangles,
  // and the coloring must not leak from the hole into the exterior through that vertex.
  Pslg in;
  add_loop(in, {{0, 0}, {2, 0}, {4, 0}, {4, 4}, {0, 4}}, 1);
  in.points.insert(in.points.end(), {{3, 2}, {1, 2}});
  in.segments.push_back({1, 5, 2});
  in.segments.push_back({5, 6, 2});
  in.segments.push_back({6, 1, 2});
  in.holes = {{2, 1}};
  for (const bool refine : {false, true}) {
    DYNAMIC_SECTION("refine=" << refine) {
      const Result r = refine ? mesh_ok(in, SizeSpec::uniform(0.25), Options{}, false)
                              : mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
      double area = 0;
      for (auto& t : r.mesh.triangles) {
        const Vec2 &a = r.mesh.vertices[t[0]], &b = r.mesh.vertices[t[1]],
                   &c = r.mesh.vertices[t[2]];
        area += 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
      }
      CHECK(area == Approx(16.0 - 2.0));  // square minus the hole
    }
  }
}

// ---------------------------------------------------------------------------------------
// Found by the invariant tests.

TEST_CASE("orient2d keeps its sign when the exact value underflows", "[regression][predicates]") {
  // d = 4.9e-324, the smallest denormal. orient2d((-d, 3+ulp), (0,-d), (0,0)) = d*d*(1)
  // exactly (about 2.4e-647, below the smallest double): a floating-point expansion of
  // the products underflows to zero, so the predicate says "collinear" for three points
  // that are not. predicates.h promises the exact sign whatever the doubles.
  const double d = std::numeric_limits<double>::denorm_min();
  const double a[2] = {-d, std::nextafter(3.0, 4.0)}, b[2] = {0, -d}, c[2] = {0, 0};
  CHECK(pred::orient2d(a, b, c) > 0);
  CHECK(pred::orient2d(b, a, c) < 0);
}

TEST_CASE("hull vertex 1 denormal below another point is dropped", "[regression]") {
  // From test_invariants, gen::duplicate_points(227) before that family stopped making
  // denormals (nextafter(0)); shrunk to four points. (0,-d) is a hull vertex, (0,0) is
  // inside the hull by d*d. With orient2d == 0 for that triple (test above) the mesher
  // drops input point 0 and triangulates the other three: 1 triangle instead of 3,
  // input_vertex[0] == kNone although the domain is the convex hull of all points.
  const double d = std::numeric_limits<double>::denorm_min();
  Pslg in;
  in.points = {{0, -d}, {0, 0}, {-d, std::nextafter(3.0, 4.0)}, {4, 1}};
  const Result r = mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  CHECK(r.mesh.input_vertex[0] != kNone);
  CHECK(r.mesh.triangles.size() == 3);
}

TEST_CASE("nearly collinear segments from one point on a 0.1-scaled grid", "[regression]") {
  // From test_invariants, gen::random_segments(30) with refine=true, shrunk: segments
  // (0.6,0.3)-(0.2,0.7) and (0.4,0.5)-(0.2,0.7) share (0.2,0.7) (coordinates are
  // i * 0.1 rounded: 6 * 0.1 is 0.6000000000000001, not the literal 0.6). On paper (0.4,0.5) is on
  // the first segment; in doubles it is 1e-17 off it, so the exact input has no crossing
  // and the constrained Delaunay triangulation is fine. Boundary discretization puts
  // rounded Steiner points on both segments, and the pieces cross: status
  // CrossingSegments "segment 1 (points 2-1) crosses segment 0 (points 0-1)" for an input
  // whose segments do not cross (at commit cae6781).
  Pslg in;
  add_loop(in, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1);
  in.points.insert(
      in.points.end(),
      {{0.6000000000000001, 0.30000000000000004}, {0.2, 0.7000000000000001}, {0.4, 0.5}});
  in.segments.push_back({4, 5, 2});
  in.segments.push_back({6, 5, 2});
  SECTION("constrained Delaunay") {
    mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  }
  SECTION("refined, h = 0.07") {
    mesh_ok(in, SizeSpec::uniform(0.070002963690370873), Options{}, false);
  }
}

TEST_CASE("nearly overlapping collinear segments on a 0.1-scaled grid", "[regression]") {
  // From test_invariants, gen::random_segments(58) with refine=true, shrunk: segments
  // (0.9,0.7)-(1.2,0.4) and (1.0,0.6)-(1.3,0.3) lie on x + y = 1.6 on paper and overlap
  // on [1.0, 1.2]; in doubles the four points are not collinear and the segments are
  // disjoint, 1e-16 apart. The CDT is valid; with refinement the discretized pieces
  // crossed (commit cae6781): CrossingSegments "segment 1 (points 3-0) crosses segment 0
  // (points 1-2)".
  Pslg in;
  add_loop(in, {{0.5, 0}, {1.5, 0}, {1.5, 1}, {0.5, 1}}, 1);
  in.points.insert(in.points.end(), {{1.3, 0.30000000000000004},
                                     {0.9, 0.7000000000000001},
                                     {1.2000000000000002, 0.4},
                                     {1, 0.6000000000000001}});
  in.segments.push_back({5, 6, 2});
  in.segments.push_back({7, 4, 2});
  SECTION("constrained Delaunay") {
    mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  }
  SECTION("refined, h = 0.037") {
    mesh_ok(in, SizeSpec::uniform(0.036975942097876947), Options{}, false);
  }
}

TEST_CASE("three nearly collinear segments from one point on a 0.1-scaled grid", "[regression]") {
  // From test_invariants, gen::random_segments(33) (and 179, the same shape) with
  // refine=true, shrunk: segments from (0.6,0.2) to (0.2,0.6), (0.3,0.5) and (0.4,0.4),
  // all on x + y = 0.8 on paper, pairwise 1e-17 apart in doubles except at the shared
  // end. Crossings among the rounded Steiner points of three segments: status
  // CrossingSegments "segment 6 (points 4-6) crosses segment 4 (points 5-4) and the
  // crossing point could not be inserted" at h = 0.0595 (commit f06920e; 0.03, 0.05 and
  // 0.1 pass), for an input whose segments meet only at their shared end.
  Pslg in;
  add_loop(in, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1);
  in.points.insert(in.points.end(), {{0.6000000000000001, 0.2},
                                     {0.2, 0.6000000000000001},
                                     {0.4, 0.4},
                                     {0.30000000000000004, 0.5}});
  in.segments.push_back({5, 4, 2});
  in.segments.push_back({4, 7, 2});
  in.segments.push_back({4, 6, 2});
  SECTION("constrained Delaunay") {
    mesh_ok(in, SizeSpec::uniform(0), cdt(), true);
  }
  SECTION("refined, h = 0.05") {
    mesh_ok(in, SizeSpec::uniform(0.05), Options{}, false);
  }
  SECTION("refined, h = 0.0595") {
    mesh_ok(in, SizeSpec::uniform(0.059501741166982348), Options{}, false);
  }
  SECTION("the fan of gen::random_segments(179), refined, h = 0.03, 0.05, 0.0636") {
    // From (0.6,0.3) to (0.1,0.8), (0.2,0.7) and (0.3,0.6), on x + y = 0.9 on paper.
    Pslg f;
    add_loop(f, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1);
    f.points.insert(f.points.end(), {{0.2, 0.7000000000000001},
                                     {0.1, 0.8},
                                     {0.30000000000000004, 0.6000000000000001},
                                     {0.6000000000000001, 0.30000000000000004}});
    f.segments.push_back({5, 7, 2});
    f.segments.push_back({7, 4, 2});
    f.segments.push_back({7, 6, 2});
    for (const double h : {0.03, 0.05, 0.063610750451786796}) {
      INFO("h = " << h);
      mesh_ok(f, SizeSpec::uniform(h), Options{}, false);
    }
  }
}

TEST_CASE("two nearly collinear segments from one point enclose nothing", "[regression]") {
  // The same kind of pair as above with no boundary around it: (0.2,0.6)-(0.6,0.2) and
  // (0.6,0.2)-(0.3,0.5) share one end and, in exact arithmetic, enclose no region: the
  // answer is OpenBoundary. With refinement (h = 0.0595) the mesher split a crossing
  // between its own rounded Steiner points, which closed sliver loops, kept those as the
  // domain and dropped the rest: status Ok, input points 1 and 2 missing, and constrained
  // edges such as (0.44,0.36)-(0.4286,0.3714) belonging to no input segment's chain.
  Pslg in;
  in.points = {{0.6000000000000001, 0.2}, {0.2, 0.6000000000000001}, {0.30000000000000004, 0.5}};
  in.segments = {{1, 0, 2}, {0, 2, 2}};
  for (const bool refine : {false, true}) {
    DYNAMIC_SECTION("refine=" << refine) {
      const Result r = refine ? mesh(in, SizeSpec::uniform(0.059501741166982348), Options{})
                              : mesh(in, SizeSpec::uniform(0), cdt());
      INFO("status: " << r.status.message);
      if (r.ok()) {
        const CheckReport rep = check(r.mesh, in);
        INFO(errors(rep));
        CHECK(rep.ok());
      } else {
        CHECK(r.status.code == StatusCode::OpenBoundary);
      }
    }
  }
}

TEST_CASE("domain_from_orientation: a clockwise loop and no hole seed is an error, not a crash",
          "[regression]") {
  // occt_caxif_k1: a face whose only loop came out clockwise in (u,v). Every component was
  // removed by the orientation vote, and the error message then indexed the hole seeds
  // with -1 (no hole had been used): a segmentation fault in color().
  Pslg g;
  add_loop(g, {{0, 0}, {0, 1}, {1, 1}, {1, 0}}, 1);  // clockwise
  Options o = cdt();
  o.domain_from_orientation = true;
  const Result r = mesh(g, SizeSpec::uniform(0.3), o);
  CHECK(r.status.code == StatusCode::OpenBoundary);
  CHECK(r.status.message.find("left") != std::string::npos);
}

TEST_CASE("domain_from_orientation: a dangling segment chain inside keeps the face on both sides",
          "[regression]") {
  // An embedded CAD edge (a crack): its segments have the domain on both sides, so its
  // half-edges cancel in the vote and the constraint is kept in the mesh.
  Pslg g;
  add_loop(g, {{0, 0}, {2, 0}, {2, 2}, {0, 2}}, 1);  // counter-clockwise
  const VertId a = static_cast<VertId>(g.points.size());
  g.points.insert(g.points.end(), {{0.5, 1.0}, {1.0, 1.1}, {1.5, 1.0}});
  g.segments.push_back({a, a + 1, 2});
  g.segments.push_back({a + 1, a + 2, 2});
  Options o;
  o.domain_from_orientation = true;
  o.split_segments = false;
  const Result r = mesh_ok(g, SizeSpec::uniform(0.25), o, false);
  int on_chain = 0;
  for (const auto& e : r.mesh.boundary_edges) on_chain += e.marker == 2;
  CHECK(on_chain == 2);
  double area = 0;
  for (const auto& t : r.mesh.triangles) {
    const Vec2 p = r.mesh.vertices[t[0]], q = r.mesh.vertices[t[1]], s = r.mesh.vertices[t[2]];
    area += 0.5 * ((q.x - p.x) * (s.y - p.y) - (q.y - p.y) * (s.x - p.x));
  }
  CHECK(area == Approx(4.0));
}

TEST_CASE("time_limit: refinement that would run long stops with TimeLimit", "[regression]") {
  // Per-face time limit of the surface mesher (issue 7): a runaway domain is reported,
  // not waited for. A million-triangle request under a microsecond budget must stop.
  Pslg g;
  add_loop(g, {{0, 0}, {1, 0}, {1, 1}, {0, 1}}, 1);
  Options o;
  o.time_limit = 1e-6;
  const Result r = mesh(g, SizeSpec::scalar([](double, double) { return 1e-3; }), o);
  CHECK(r.status.code == StatusCode::TimeLimit);
  CHECK(r.status.message.find("time limit") != std::string::npos);
  CHECK_FALSE(r.ok());
}
