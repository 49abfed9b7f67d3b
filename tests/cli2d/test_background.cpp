// Background size fields: SPD log/exp, point location (inside, outside, in holes),
// log-Euclidean interpolation, and the bundled background files.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "cli2d_test_util.h"
#include "uvmesh2d/background.h"
#include "uvmesh2d/locate.h"

using namespace uvmesh::cli2d;
using uvmesh::m2d::Metric2;
using uvmesh::m2d::Vec2;

namespace {

// Metric with principal sizes h1 along angle t and h2 across it (eq. 7.11).
Metric2 metric_of(double h1, double h2, double t) {
  const double c = std::cos(t), s = std::sin(t), a = 1 / (h1 * h1), b = 1 / (h2 * h2);
  return {a * c * c + b * s * s, (a - b) * c * s, a * s * s + b * c * c};
}

bool close(const Metric2& a, const Metric2& b, double rel) {
  const double scale =
      std::max({std::fabs(a.m11), std::fabs(a.m22), std::fabs(b.m11), std::fabs(b.m22)});
  return std::fabs(a.m11 - b.m11) <= rel * scale && std::fabs(a.m12 - b.m12) <= rel * scale &&
         std::fabs(a.m22 - b.m22) <= rel * scale;
}

MeditMesh2 two_triangles() {  // unit square, diagonal (0,0)-(1,1)
  MeditMesh2 m;
  m.vertices = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.vertex_refs = {0, 0, 0, 0};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangle_refs = {0, 0};
  return m;
}

MeditSol scalar_sol(std::vector<double> h) {
  MeditSol s;
  s.type = MeditSol::Type::Scalar;
  s.values = std::move(h);
  return s;
}

}  // namespace

TEST_CASE("background: spd_exp(spd_log(M)) == M, also strongly anisotropic",
          "[cli2d][background]") {
  std::mt19937 rng(12345);
  std::uniform_real_distribution<double> lh(-7, 1), ang(0, 3.14159);
  for (int i = 0; i < 1000; ++i) {
    const Metric2 m = metric_of(std::pow(10.0, lh(rng)), std::pow(10.0, lh(rng)), ang(rng));
    INFO("m = " << m.m11 << " " << m.m12 << " " << m.m22);
    CHECK(close(spd_exp(spd_log(m)), m, 1e-9));
  }
  // Eigenvalues 1e12 and 1e-12: the small one must not cancel to zero.
  const Metric2 l = spd_log({1e12, 0, 1e-12});
  CHECK(l.m11 == Approx(std::log(1e12)));
  CHECK(l.m22 == Approx(std::log(1e-12)));
  // Identity multiples.
  const Metric2 e = spd_exp({std::log(4.0), 0, std::log(4.0)});
  CHECK(e.m11 == Approx(4));
  CHECK(e.m12 == 0);
}

TEST_CASE("background: spd_bound_size caps the size in every direction", "[cli2d][background]") {
  const Metric2 m = metric_of(1.0, 0.01, 0.3);  // sizes 1 along 0.3 rad, 0.01 across
  const Metric2 b = spd_bound_size(m, 0.1);
  CHECK(close(b, metric_of(0.1, 0.01, 0.3), 1e-12));
  CHECK(close(spd_bound_size(m, 10.0), m, 1e-12));  // no effect when already smaller
}

TEST_CASE("locate: every point of a grid mesh is found in a triangle that contains it",
          "[cli2d][background]") {
  const uvmesh::m2d::Mesh g = cli2d_test::grid_mesh(37);
  TriangleLocator loc;
  REQUIRE(loc.build(g.vertices, g.triangles));
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  for (int i = 0; i < 5000; ++i) {
    const Vec2 p{u(rng), u(rng)};
    const auto l = loc.locate(p);
    REQUIRE(l.inside);
    const auto& t = g.triangles[static_cast<std::size_t>(l.triangle)];
    double x = 0, y = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      CHECK(l.w[k] >= -1e-12);
      x += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].x;
      y += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].y;
    }
    CHECK(x == Approx(p.x).margin(1e-12));
    CHECK(y == Approx(p.y).margin(1e-12));
  }
  // Vertices and edge midpoints are on triangle boundaries: still found.
  CHECK(loc.locate({0.5, 0.5}).inside);
  CHECK(loc.locate({1, 1}).inside);
  CHECK(loc.locate({0, 0.5 / 37}).inside);
}

TEST_CASE("locate: outside points get the nearest point of the nearest triangle",
          "[cli2d][background]") {
  const uvmesh::m2d::Mesh g = cli2d_test::grid_mesh(10);
  TriangleLocator loc;
  REQUIRE(loc.build(g.vertices, g.triangles));
  for (const Vec2 p :
       {Vec2{3, 0.55}, Vec2{-0.2, 0.31}, Vec2{0.77, 5}, Vec2{-4, -4}, Vec2{1e6, 0.5}}) {
    const auto l = loc.locate(p);
    CHECK_FALSE(l.inside);
    const auto& t = g.triangles[static_cast<std::size_t>(l.triangle)];
    double x = 0, y = 0;
    for (std::size_t k = 0; k < 3; ++k) {
      x += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].x;
      y += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].y;
    }
    const Vec2 expect{std::clamp(p.x, 0.0, 1.0),
                      std::clamp(p.y, 0.0, 1.0)};  // projection on the square
    CHECK(x == Approx(expect.x).margin(1e-12));
    CHECK(y == Approx(expect.y).margin(1e-12));
  }
}

TEST_CASE("locate: a point in a hole of the mesh gets the nearest triangle",
          "[cli2d][background]") {
  // Grid with the triangles of the centre cells removed: a square hole [0.4, 0.6]^2.
  uvmesh::m2d::Mesh g = cli2d_test::grid_mesh(10);
  std::vector<std::array<int, 3>> kept;
  for (const auto& t : g.triangles) {
    double cx = 0, cy = 0;
    for (int v : t)
      cx += g.vertices[static_cast<std::size_t>(v)].x / 3,
          cy += g.vertices[static_cast<std::size_t>(v)].y / 3;
    if (!(cx > 0.4 && cx < 0.6 && cy > 0.4 && cy < 0.6)) kept.push_back(t);
  }
  TriangleLocator loc;
  REQUIRE(loc.build(g.vertices, kept));
  const auto l = loc.locate({0.45, 0.5});  // nearest boundary point of the hole: (0.4, 0.5)
  CHECK_FALSE(l.inside);
  const auto& t = kept[static_cast<std::size_t>(l.triangle)];
  double x = 0, y = 0;
  for (std::size_t k = 0; k < 3; ++k) {
    x += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].x;
    y += l.w[k] * g.vertices[static_cast<std::size_t>(t[k])].y;
  }
  CHECK(x == Approx(0.4));
  CHECK(y == Approx(0.5));
}

TEST_CASE("background: sizes interpolate geometrically (log-Euclidean)", "[cli2d][background]") {
  BackgroundLoad b = make_background(two_triangles(), scalar_sol({0.1, 0.4, 0.4, 0.1}), "bg.mesh");
  REQUIRE(b.ok());
  CHECK(b.spec.kind == uvmesh::m2d::SizeSpec::Kind::Scalar);
  CHECK(b.spec.size(0, 0) == Approx(0.1));
  CHECK(b.spec.size(1, 0.5) == Approx(0.4));
  CHECK(b.spec.size(0.5, 0.5) == Approx(0.2));  // sqrt(0.1 * 0.4), not 0.25
  CHECK(b.spec.size(0.25, 0.9) == Approx(std::sqrt(0.1 * std::sqrt(0.1 * 0.4))));
  CHECK(b.spec.size(2.0, 0.5) == Approx(0.4));  // outside: nearest point (1, 0.5)
  CHECK(b.spec.size(-1, -1) == Approx(0.1));    // outside: nearest point (0, 0)
}

TEST_CASE("background: tensor fields", "[cli2d][background]") {
  MeditSol s;
  s.type = MeditSol::Type::Tensor;
  const Metric2 a = metric_of(0.5, 0.01, 0.2), c = metric_of(0.1, 0.1, 0);
  for (int i = 0; i < 4; ++i) {
    const Metric2& m = i % 2 ? c : a;  // a at (0,0) and (1,1); c at (1,0) and (0,1)
    s.values.insert(s.values.end(), {m.m11, m.m12, m.m22});
  }
  BackgroundLoad b = make_background(two_triangles(), s, "bg.mesh");
  REQUIRE(b.ok());
  CHECK(b.spec.kind == uvmesh::m2d::SizeSpec::Kind::Metric);
  CHECK(close(b.spec.metric(0, 0), a, 1e-12));
  CHECK(close(b.spec.metric(1, 0), c, 1e-12));
  CHECK(close(b.spec.metric(0.5, 0.5), a, 1e-12));  // on the diagonal between two a's
  // Halfway between a and c (on the edge (0,0)-(1,0)): exp((log a + log c) / 2), whose
  // determinant is the geometric mean of the two determinants.
  const Metric2 h = b.spec.metric(0.5, 0);
  auto det = [](const Metric2& m) { return m.m11 * m.m22 - m.m12 * m.m12; };
  CHECK(det(h) == Approx(std::sqrt(det(a) * det(c))).epsilon(1e-9));
  CHECK(h.m11 > 0);
  CHECK(det(h) > 0);
}

TEST_CASE("background: errors", "[cli2d][background][errors]") {
  MeditMesh2 flat;
  flat.vertices = {{0, 0}, {1, 0}, {2, 0}};
  flat.triangles = {{0, 1, 2}};
  BackgroundLoad b = make_background(flat, scalar_sol({1, 1, 1}), "flat.mesh");
  REQUIRE_FALSE(b.ok());
  CHECK(b.error->str() == "flat.mesh: the background mesh has no triangle with a non-zero area");
  BackgroundLoad n = make_background(two_triangles(), scalar_sol({1, 1}), "bg.mesh");
  REQUIRE_FALSE(n.ok());
  CHECK(n.error->str() == "bg.mesh: the mesh has 4 vertices, but the solution has values for 2");
  BackgroundLoad f = load_background(cli2d_test::sample("bg_square.mesh"), "/nonexistent.sol");
  REQUIRE_FALSE(f.ok());
  CHECK(f.error->str() == "/nonexistent.sol: cannot open the file for reading");
  // The .sol of another mesh: vertex counts differ.
  cli2d_test::ScratchDir dir("bgerr");
  cli2d_test::write_file(
      dir / "small.sol",
      "MeshVersionFormatted 2\nDimension 2\nSolAtVertices\n3\n1 1\n1\n1\n1\nEnd\n");
  BackgroundLoad g = load_background(cli2d_test::sample("bg_square.mesh"), dir / "small.sol");
  REQUIRE_FALSE(g.ok());
  CHECK(g.error->str() ==
        dir / "small.sol" +
            ":4: the solution has values at 3 vertices, but the background mesh has 289");
}

TEST_CASE("background: the bundled shock metric", "[cli2d][background]") {
  BackgroundLoad b =
      load_background(cli2d_test::sample("bg_square.mesh"), cli2d_test::sample("bg_square.sol"));
  REQUIRE(b.ok());
  // (0.5, 0.5) is a grid vertex on the shock x + y = 1: h_n = 0.004 across, 0.1 along.
  const Metric2 m = b.spec.metric(0.5, 0.5);
  CHECK(close(m, metric_of(0.004, 0.1, 3.14159265358979 / 4), 1e-9));
  BackgroundLoad s =
      load_background(cli2d_test::sample("bg_square.mesh"), cli2d_test::sample("bg_square_h.sol"));
  REQUIRE(s.ok());
  CHECK(s.spec.size(1, 1) == Approx(0.01 + 0.08 * std::sqrt(2.0)).epsilon(1e-9));
}
