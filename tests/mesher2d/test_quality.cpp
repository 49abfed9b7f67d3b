// Quality and sizing of refined meshes (issue 2, "Tests: Sizing / Quality").
//
// Thresholds are the issue's: >= 95% unit edges on every analytic field; at uniform size
// on the unit square and the square with a circular hole Q_M <= 1.2 and min angle >= 40
// deg (lattice field points with a boundary layer, max-min relocation and the targeted
// repair of mesher.cpp); on bl and ring metric Q_M <= 2 and >= 95% of triangles with
// metric Q < 1.5.
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "bench_domain.h"
#include "field_point_methods.h"
#include "samples/uvmesh2d/fields.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"

using namespace uvmesh::m2d;
namespace fields = uvmesh::cli2d::fields;

namespace {

Pslg unit_square() {
  Pslg in;
  in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  return in;
}

Pslg square_with_hole(int n = 128) {
  Pslg in = unit_square();
  const double pi = 3.14159265358979323846;
  for (int i = 0; i < n; ++i) {
    const double a = 2 * pi * i / n;
    in.points.push_back({0.5 + 0.25 * std::cos(a), 0.5 + 0.25 * std::sin(a)});
    in.segments.push_back({4 + i, 4 + (i + 1) % n, 2});
  }
  in.holes.push_back({0.5, 0.5});
  return in;
}

double share_below(const Mesh& m, const SizeSpec& s, double q) {
  std::int64_t n = 0;
  for (const auto& t : m.triangles) {
    const Vec2 c{(m.vertices[t[0]].x + m.vertices[t[1]].x + m.vertices[t[2]].x) / 3,
                 (m.vertices[t[0]].y + m.vertices[t[1]].y + m.vertices[t[2]].y) / 3};
    const Metric2 M = s.kind == SizeSpec::Kind::Metric ? s.metric(c.x, c.y) : Metric2{};
    n += triangle_quality(m.vertices[t[0]], m.vertices[t[1]], m.vertices[t[2]], M) < q;
  }
  return static_cast<double>(n) / static_cast<double>(m.triangles.size());
}

void require_valid(const Result& r, const Pslg& in) {
  INFO("status: " << r.status.message);
  REQUIRE(r.ok());
  const CheckReport rep = check(r.mesh, in);
  INFO((rep.errors.empty() ? std::string() : rep.errors.front()));
  REQUIRE(rep.ok());
}

// The isotropic thresholds at uniform size h.
Result require_uniform_quality(const Pslg& in, double h, FieldPointMethod method) {
  Result r = mesh(in, SizeSpec::uniform(h), method_options(method));
  require_valid(r, in);
  const Quality& q = r.stats.quality;
  INFO(method_name(method) << ", h = " << h << " Q_M = " << q.q_max << " min angle "
                           << q.min_angle_deg << " unit " << q.unit_edge_share);
  CHECK(q.unit_edge_share >= 0.95);
  CHECK(q.q_max <= 1.2);
  CHECK(q.min_angle_deg >= 40);
  // Most triangles near-equilateral (the lattice, or the fronts); the rest is the band along the
  // boundary, a larger share on coarse meshes (measured 0.71 at h = 0.03 with the hole).
  CHECK(share_below(r.mesh, SizeSpec::uniform(h), 1.1) >= 0.65);
  return r;
}

}  // namespace

TEST_CASE("uniform size on the unit square: unit edges and shape", "[quality]") {
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const double h : {0.05, 0.02, 0.01}) {
    const Result r = require_uniform_quality(unit_square(), h, method);
    // The triangle count of a unit mesh is close to the area over the area of a unit
    // equilateral triangle (sqrt(3)/4 h^2).
    const double expected = 1.0 / (0.4330127018922193 * h * h);
    CHECK(static_cast<double>(r.mesh.triangles.size()) > 0.7 * expected);
    CHECK(static_cast<double>(r.mesh.triangles.size()) < 1.4 * expected);
  }
}

TEST_CASE("uniform size on the square with a circular hole", "[quality]") {
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const double h : {0.03, 0.01}) {
    // The hole's polygon has edges of about h, as a boundary discretized at size h has.
    require_uniform_quality(
        square_with_hole(static_cast<int>(std::lround(2 * 3.14159265358979 * 0.25 / h))), h,
        method);
  }
}

TEST_CASE("uniform size on the square with a hole as the bench discretizes it", "[quality]") {
  // bench_mesher2d's domain (bench_domain.h).
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const double h : {0.0095, 0.0043}) {
    const Pslg in = bench_square_with_hole(h);
    require_uniform_quality(in, h, method);
  }
}

// The thresholds for a varying field on the unit square: >= 95% unit edges,
// metric Q_M <= 2, >= 95% of triangles with metric Q < 1.5. Returns the quality.
Quality require_field_quality(const std::string& name, const SizeSpec& s, FieldPointMethod method) {
  const Pslg in = unit_square();
  const Result r = mesh(in, s, method_options(method));
  require_valid(r, in);
  const Quality& q = r.stats.quality;
  INFO(method_name(method) << ", " << name << ": " << r.mesh.triangles.size()
                           << " triangles, metric Q_M = " << q.metric_q_max << " share<1.5 "
                           << q.metric_share_q_below_1_5 << " unit " << q.unit_edge_share);
  CHECK(q.unit_edge_share >= 0.95);
  CHECK(q.metric_q_max <= 2);
  CHECK(q.metric_share_q_below_1_5 >= 0.95);
  return q;
}

TEST_CASE("linear isotropic field: unit edges", "[quality]") {
  require_field_quality("linear:0.005,0.05", fields::linear(0.005, 0.05), FIELD_POINT_METHOD);
}

TEST_CASE("anisotropic boundary layer bl: metric quality and unit edges", "[quality][aniso]") {
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const auto& [h0, hmax] : {std::pair{0.005, 0.05}, std::pair{0.001, 0.02}}) {
    const Quality q = require_field_quality("bl:" + std::to_string(h0) + "," + std::to_string(hmax),
                                            fields::bl(h0, hmax), method);
    // Anisotropy is real: Euclidean shapes are stretched (bl asks for up to hmax/h0 : 1).
    CHECK(q.q_max > 3);
  }
}

TEST_CASE("anisotropic ring: metric quality and unit edges", "[quality][aniso]") {
  // ring:h0,hmax with hmax small enough to resolve the circle of radius 0.25 (about 80
  // elements around it); at hmax = 0.05 the tangential size is a fifth of the radius and
  // the metric turns by 12 degrees per element, which no straight-edged unit mesh follows.
  // ring:1e-4,0.01 (the bench's 1e5 case: 88 k triangles, anisotropy 100:1 at the
  // circle) is the regression case: with one metric frame per relocated ball and no
  // repair or size pass in the metric it gave metric Q_M 6.3, 92.9% under 1.5 and 91.3%
  // unit edges (ring:2e-4,0.015: 6.4, 91%, 89%); the worst triangles all lay within 10 h0
  // of the circle, where the metric turns by 2-3 degrees per tangential element.
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const auto& [h0, hmax] : {std::pair{0.002, 0.02}, std::pair{0.0001, 0.01}})
    require_field_quality("ring:" + std::to_string(h0) + "," + std::to_string(hmax),
                          fields::ring(h0, hmax), method);
}

TEST_CASE("uniform field: vertices of the boundary stay where the input put them", "[quality]") {
  // The surface stage relies on this: with split_segments off, the boundary vertices are
  // exactly the input points and no other vertex lies on a segment.
  Pslg in = square_with_hole(64);
  Options o = method_options(FIELD_POINT_METHOD);
  o.split_segments = false;
  const Result r = mesh(in, SizeSpec::uniform(0.02), o);
  require_valid(r, in);
  for (std::size_t i = 0; i < in.points.size(); ++i) {
    REQUIRE(r.mesh.input_vertex[i] != kNone);
    CHECK(r.mesh.vertices[r.mesh.input_vertex[i]].x == in.points[i].x);
    CHECK(r.mesh.vertices[r.mesh.input_vertex[i]].y == in.points[i].y);
  }
  CHECK(r.mesh.boundary_edges.size() == in.segments.size());
}
