// Frontal field points (Options::field_points = Frontal, §7.4.3): the typical triangle
// quality they are for, and the contracts every mode keeps (checker, determinism, holes,
// regions, fixed boundary, narrow regions, gradation, turning metrics).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "bench_domain.h"
#include "field_point_methods.h"
#include "samples/uvmesh2d/fields.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"

using namespace uvmesh::m2d;
namespace fields = uvmesh::cli2d::fields;

namespace {

constexpr double kPi = 3.14159265358979323846;

// A closed loop of n pieces on the circle of radius r around (cx, cy), counter-clockwise.
void add_circle(Pslg& in, double cx, double cy, double r, int n, int marker) {
  const auto first = static_cast<VertId>(in.points.size());
  for (int i = 0; i < n; ++i)
    in.points.push_back({cx + r * std::cos(2 * kPi * i / n), cy + r * std::sin(2 * kPi * i / n)});
  for (int i = 0; i < n; ++i) in.segments.push_back({first + i, first + (i + 1) % n, marker});
}

// The rectangle [x0, x1] x [y0, y1] as a loop.
void add_rect(Pslg& in, double x0, double y0, double x1, double y1, int marker) {
  const auto first = static_cast<VertId>(in.points.size());
  in.points.insert(in.points.end(), {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}});
  for (int i = 0; i < 4; ++i) in.segments.push_back({first + i, first + (i + 1) % 4, marker});
}

Metric2 field_metric(const SizeSpec& s, Vec2 p) {
  switch (s.kind) {
    case SizeSpec::Kind::Uniform:
      return Metric2::iso(s.h);
    case SizeSpec::Kind::Scalar:
      return Metric2::iso(s.size(p.x, p.y));
    case SizeSpec::Kind::Metric:
      return s.metric(p.x, p.y);
  }
  return {};
}

// Median of q_K = 1 / Q_K (triangle_quality, eq. 7.6) over the mesh, each triangle in the
// field's metric at its centroid.
double median_q(const Mesh& m, const SizeSpec& s) {
  std::vector<double> q;
  q.reserve(m.triangles.size());
  for (const auto& t : m.triangles) {
    const Vec2 a = m.vertices[t[0]], b = m.vertices[t[1]], c = m.vertices[t[2]];
    const Vec2 g{(a.x + b.x + c.x) / 3, (a.y + b.y + c.y) / 3};
    q.push_back(1 / triangle_quality(a, b, c, field_metric(s, g)));
  }
  std::nth_element(q.begin(), q.begin() + q.size() / 2, q.end());
  return q[q.size() / 2];
}

Options frontal() {
  return method_options(FieldPointMethod::Frontal);
}

}  // namespace

TEST_CASE("frontal: the uniform square with a hole is nearly all equilateral", "[frontal]") {
  // The fronts leave rows of unit equilateral triangles; only the seams where fronts meet
  // differ (measured: median q_K 0.9999 at both sizes, Q_M 1.18).
  for (const double h : {0.0095, 0.0043}) {
    INFO("h = " << h);
    const Pslg in = bench_square_with_hole(h);
    const Result r = mesh_valid(in, SizeSpec::uniform(h), frontal());
    CHECK(r.stats.frontal_waves > 10);
    CHECK(median_q(r.mesh, SizeSpec::uniform(h)) >= 0.995);
    CHECK(r.stats.quality.q_max <= 1.2);
    CHECK(r.stats.quality.unit_edge_share >= 0.99);
  }
}

TEST_CASE("frontal: anisotropic ring and boundary layer, median metric quality", "[frontal]") {
  // Edge saturation places points along the edges of the mesh it has, which bounds the
  // typical quality in the metric; the fronts place each point for a unit equilateral
  // triangle (median metric q_K in the metric at the centroid, measured on
  // ring:1e-4,0.01: saturation 0.895, frontal 0.905; bl:1e-4,0.01: saturation below
  // frontal's 0.99).
  struct Case {
    const char* name;
    SizeSpec s;
    double min_median;
  };
  const Case cases[] = {{"ring:1e-4,0.01", fields::ring(0.0001, 0.01), 0.9},
                        {"bl:1e-4,0.01", fields::bl(0.0001, 0.01), 0.99}};
  Pslg in;
  add_rect(in, 0, 0, 1, 1, 1);
  for (const Case& c : cases) {
    INFO(c.name);
    const Result fr = mesh_valid(in, c.s, frontal());
    const Result sat = mesh_valid(in, c.s, method_options(FieldPointMethod::Saturation));
    const double qf = median_q(fr.mesh, c.s), qs = median_q(sat.mesh, c.s);
    INFO("median q frontal " << qf << ", saturation " << qs);
    CHECK(qf >= c.min_median);
    CHECK(qf > qs);
    CHECK(fr.stats.quality.metric_q_max <= 2);
    CHECK(fr.stats.quality.unit_edge_share >= 0.95);
  }
}

TEST_CASE("frontal: two runs give the same mesh, bit for bit", "[frontal][determinism]") {
  const SizeSpec specs[] = {
      SizeSpec::uniform(0.02), fields::ring(0.002, 0.02),
      SizeSpec::scalar([](double x, double y) { return 0.01 + 0.03 * x * y; })};
  const Pslg in = bench_square_with_hole(0.02);
  for (const SizeSpec& s : specs) {
    const Result a = mesh_valid(in, s, frontal()), b = mesh_valid(in, s, frontal());
    require_same_mesh(a.mesh, b.mesh);
  }
}

TEST_CASE("frontal: holes stay empty and regions keep their attributes", "[frontal]") {
  // Two regions (the left half with attribute 7, the right half 3) split by a segment,
  // with a round hole in each: every front point must land in the component of the
  // triangle it was made for.
  Pslg in;
  add_rect(in, 0, 0, 2, 1, 1);
  const auto s0 = static_cast<VertId>(in.points.size());
  in.points.insert(in.points.end(), {{1, 0}, {1, 1}});
  in.segments.push_back({s0, s0 + 1, 5});
  add_circle(in, 0.5, 0.5, 0.2, 40, 2);
  add_circle(in, 1.5, 0.5, 0.2, 40, 3);
  in.holes = {{0.5, 0.5}, {1.5, 0.5}};
  in.regions = {{{0.1, 0.1}, 7}, {{1.9, 0.1}, 3}};
  const Result r = mesh_valid(in, SizeSpec::uniform(0.03), frontal());
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const auto& k = r.mesh.triangles[t];
    const Vec2 g{(r.mesh.vertices[k[0]].x + r.mesh.vertices[k[1]].x + r.mesh.vertices[k[2]].x) / 3,
                 (r.mesh.vertices[k[0]].y + r.mesh.vertices[k[1]].y + r.mesh.vertices[k[2]].y) / 3};
    INFO("triangle " << t << " at (" << g.x << ", " << g.y << ")");
    REQUIRE(std::hypot(g.x - 0.5, g.y - 0.5) > 0.19);
    REQUIRE(std::hypot(g.x - 1.5, g.y - 0.5) > 0.19);
    REQUIRE(r.mesh.triangle_attribute[t] == (g.x < 1 ? 7 : 3));
  }
}

TEST_CASE("frontal: a strip narrower than the size is meshed across", "[frontal]") {
  // Fronts from the two long sides meet at once: the strip is 0.004 wide for h = 0.02,
  // so no front point fits and saturation alone splits what is too long.
  Pslg in;
  add_rect(in, 0, 0, 1, 0.004, 1);
  const Result r = mesh_valid(in, SizeSpec::uniform(0.02), frontal());
  CHECK(r.mesh.triangles.size() > 40);
}

TEST_CASE("frontal: boundary vertices stay fixed under a graded scalar field", "[frontal]") {
  // As the surface stage calls it: the boundary as given (split_segments off), a fine
  // bottom side graded into a coarser field (Options::boundary_gradation).
  Pslg in;
  const int n = 40;
  for (int i = 0; i < n; ++i) in.points.push_back({static_cast<double>(i) / n, 0});
  in.points.insert(in.points.end(), {{1, 0}, {1, 1}, {0, 1}});
  const auto np = static_cast<VertId>(in.points.size());
  for (VertId i = 0; i < np; ++i) in.segments.push_back({i, (i + 1) % np, 1});
  Options o = frontal();
  o.split_segments = false;
  o.boundary_gradation = 1.3;
  const SizeSpec graded = SizeSpec::scalar([](double x, double) { return 0.2 + 0.05 * x; });
  const Result r = mesh_valid(in, graded, o);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    REQUIRE(r.mesh.input_vertex[i] != kNone);
    CHECK(r.mesh.vertices[r.mesh.input_vertex[i]].x == in.points[i].x);
    CHECK(r.mesh.vertices[r.mesh.input_vertex[i]].y == in.points[i].y);
  }
  CHECK(r.mesh.boundary_edges.size() == in.segments.size());
  // The same grading as saturation: about as many triangles.
  o.field_points = FieldPointMethod::Saturation;
  const double ns = static_cast<double>(mesh(in, graded, o).mesh.triangles.size());
  INFO("triangles: frontal " << r.mesh.triangles.size() << ", saturation " << ns);
  CHECK(std::abs(static_cast<double>(r.mesh.triangles.size()) / ns - 1) < 0.25);
}

TEST_CASE("frontal and saturation: a metric whose axes turn fast", "[frontal]") {
  // The metric's axes turn by a full turn across the square (sizes 0.01 and 0.05): the
  // metric at an edge and at its front point differ in direction, which the correction
  // with the point's metric must absorb.
  const SizeSpec turning = SizeSpec::aniso([](double x, double y) {
    const double a = 2 * kPi * (x + 0.5 * y), c = std::cos(a), s = std::sin(a);
    const double l1 = 1 / (0.01 * 0.01), l2 = 1 / (0.05 * 0.05);
    return Metric2{l1 * c * c + l2 * s * s, (l1 - l2) * c * s, l1 * s * s + l2 * c * c};
  });
  Pslg in;
  add_rect(in, 0, 0, 1, 1, 1);
  const FieldPointMethod method = FIELD_POINT_METHOD;
  INFO(method_name(method));
  const Result r = mesh_valid(in, turning, method_options(method));
  INFO("metric Q_M " << r.stats.quality.metric_q_max << " unit "
                     << r.stats.quality.unit_edge_share);
  CHECK(r.stats.quality.unit_edge_share >= 0.9);
  CHECK(r.stats.quality.metric_q_max <= 3);
}

TEST_CASE("frontal: max_vertices stops the fronts with a usable mesh", "[frontal]") {
  const Pslg in = bench_square_with_hole(0.02);
  Options o = frontal();
  o.max_vertices = 500;
  const Result r = mesh(in, SizeSpec::uniform(0.005), o);
  CHECK(r.status.code == StatusCode::Incomplete);
  REQUIRE(r.usable());
  const CheckReport rep = check(r.mesh, in, {.delaunay = false});
  CHECK(rep.ok());
}
