// Mesh::boundary_scale: the factor by which Options::boundary_gradation scaled the field's
// metric at each output vertex (vertex_metric[v] = boundary_scale[v] * M(x_v)).
#include <catch2/catch.hpp>
#include <cmath>

#include "field_point_methods.h"
#include "uvmesh/mesher2d/mesher2d.h"

using namespace uvmesh::m2d;

namespace {

// The unit square with its bottom side split into n short segments and the other three
// sides whole: under a coarse field the short segments ask for a finer metric near the
// bottom, which the boundary gradation spreads into the domain.
Pslg square_fine_bottom(int n) {
  Pslg in;
  for (int i = 0; i <= n; ++i) in.points.push_back({static_cast<double>(i) / n, 0.0});
  in.points.push_back({1, 1});
  in.points.push_back({0, 1});
  const int np = static_cast<int>(in.points.size());
  for (int i = 0; i + 1 < np; ++i) in.segments.push_back({i, i + 1, 1});
  in.segments.push_back({np - 1, 0, 1});
  return in;
}

double h_field(double x, double y) {
  return 0.2 + 0.05 * x + 0.02 * y;
}

Options surface_like(double gradation, FieldPointMethod method = FieldPointMethod::Saturation) {
  Options o = method_options(method);
  o.split_segments = false;  // keep the fine boundary as given
  o.boundary_gradation = gradation;
  return o;
}

}  // namespace

TEST_CASE("boundary_scale: vertex_metric is the field's metric times the scale", "[boundary]") {
  const Pslg in = square_fine_bottom(40);
  const FieldPointMethod method = FIELD_POINT_METHOD;
  INFO(method_name(method));
  const Result r = mesh(in, SizeSpec::scalar(h_field), surface_like(1.3, method));
  REQUIRE(r.ok());
  const Mesh& m = r.mesh;
  REQUIRE(m.vertex_metric.size() == m.vertices.size());
  REQUIRE(m.boundary_scale.size() == m.vertices.size());
  std::size_t scaled = 0;
  double smax = 1;
  for (std::size_t v = 0; v < m.vertices.size(); ++v) {
    const double s = m.boundary_scale[v];
    CHECK(s >= 1);
    const Vec2 p = m.vertices[v];
    const Metric2 f = Metric2::iso(h_field(p.x, p.y));
    // The mesher scales the field's tensor by s (each entry times s), so the product is
    // the same double.
    CHECK(m.vertex_metric[v].m11 == f.m11 * s);
    CHECK(m.vertex_metric[v].m12 == f.m12 * s);
    CHECK(m.vertex_metric[v].m22 == f.m22 * s);
    scaled += s > 1;
    smax = std::max(smax, s);
  }
  // The bottom's segments are 1/40 long against h >= 0.2: their vertices get a size ratio
  // of about 1/8, a scale of about 64, and the scale grows back to 1 into the domain.
  CHECK(scaled > 40);
  CHECK(scaled < m.vertices.size());
  CHECK(smax > 30);
  CHECK(smax < 100);
}

TEST_CASE("boundary_scale: 1 everywhere without a boundary gradation", "[boundary]") {
  const Pslg in = square_fine_bottom(40);
  for (const double g : {0.0, 1.0}) {
    const Result r = mesh(in, SizeSpec::scalar(h_field), surface_like(g));
    REQUIRE(r.ok());
    REQUIRE(r.mesh.boundary_scale.size() == r.mesh.vertices.size());
    for (const double s : r.mesh.boundary_scale) CHECK(s == 1);
  }
  // A uniform field is never scaled from the boundary.
  const Result u = mesh(in, SizeSpec::uniform(0.2), surface_like(1.3));
  REQUIRE(u.ok());
  REQUIRE(u.mesh.boundary_scale.size() == u.mesh.vertices.size());
  for (const double s : u.mesh.boundary_scale) CHECK(s == 1);
}

TEST_CASE("boundary_scale: empty without refinement", "[boundary]") {
  Options o = surface_like(1.3);
  o.refine = false;
  const Result r = mesh(square_fine_bottom(8), SizeSpec::scalar(h_field), o);
  REQUIRE(r.ok());
  CHECK(r.mesh.vertex_metric.empty());
  CHECK(r.mesh.boundary_scale.empty());
}
