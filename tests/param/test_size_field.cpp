// Curvature (exact on analytic surfaces), size formulas, induced metric, gradation.
#include <catch2/catch.hpp>
#include <cmath>
#include <numbers>
#include <random>

#include "uvmesh/geom/analytic.h"
#include "uvmesh/param/size_field.h"

using namespace uvmesh;
using geom::Vec3;

namespace {
const double kPi = std::numbers::pi;
geom::Frame tilted() {
  return geom::Frame::from_axis({1.0, -2.0, 0.5}, {0.3, 0.4, 1.0});
}
}  // namespace

TEST_CASE("curvature is exact on sphere, cylinder, cone and torus", "[param][curvature]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  const geom::Frame f = tilted();
  for (int t = 0; t < 100; ++t) {
    const double u = 2 * kPi * U(rng);
    {  // sphere r = 2.5: |k1| = |k2| = 1/r
      auto s = geom::make_sphere(f, 2.5);
      const double v = -1.4 + 2.8 * U(rng);
      const auto c = param::principal_curvatures(s->eval(u, v));
      CHECK(std::abs(c.k1) == Approx(0.4));
      CHECK(std::abs(c.k2) == Approx(0.4));
    }
    {  // cylinder r = 3: 1/r around, 0 along the axis (direction of k2 = axis)
      auto s = geom::make_cylinder(f, 3.0, {0, 10});
      const auto c = param::principal_curvatures(s->eval(u, 10 * U(rng)));
      CHECK(std::abs(c.k1) == Approx(1.0 / 3.0));
      CHECK(c.k2 == Approx(0.0).margin(1e-12));
      CHECK(std::abs(glm::dot(c.dir2, f.z)) == Approx(1.0));
    }
    {  // cone r = 2, half-angle a: k = cos a / (r + v sin a) around, 0 along a ruling
      const double a = 0.4, v = 5 * U(rng);
      auto s = geom::make_cone(f, 2.0, a, {0, 5});
      const auto c = param::principal_curvatures(s->eval(u, v));
      CHECK(std::abs(c.k1) == Approx(std::cos(a) / (2.0 + v * std::sin(a))));
      CHECK(c.k2 == Approx(0.0).margin(1e-12));
    }
    {  // torus R = 5, r = 1: 1/r across the tube, cos v / (R + r cos v) along it
      const double v = 2 * kPi * U(rng);
      auto s = geom::make_torus(f, 5.0, 1.0);
      const auto c = param::principal_curvatures(s->eval(u, v));
      const double ka = 1.0, kb = std::cos(v) / (5.0 + std::cos(v));
      CHECK(std::abs(c.k1) == Approx(std::max(ka, std::abs(kb))));
      CHECK(std::abs(c.k2) == Approx(std::min(ka, std::abs(kb))).margin(1e-12));
    }
  }
  // Plane: zero; pole: flagged singular.
  auto p = geom::make_plane(f, {{0, 1}, {0, 1}});
  CHECK(param::principal_curvatures(p->eval(0.3, 0.3)).k1 == 0.0);
  auto s = geom::make_sphere(f, 1.0);
  CHECK(param::principal_curvatures(s->eval(0.3, kPi / 2)).singular);
}

TEST_CASE("chordal and angle sizes", "[param][size]") {
  // Sagitta of a chord h on radius rho: rho - sqrt(rho^2 - h^2/4) = eps.
  const double rho = 10.0, eps = 0.01;
  const double h = param::chordal_size(rho, eps);
  CHECK(rho - std::sqrt(rho * rho - h * h / 4) == Approx(eps));
  CHECK(std::isinf(param::chordal_size(1.0, 2.0)));
  CHECK(param::angle_size(1.0, kPi / 3) == Approx(1.0));  // hexagon side
}

TEST_CASE("curvature metric: anisotropic on a cylinder, isotropic option", "[param][size]") {
  auto s = geom::make_cylinder(geom::Frame{}, 1.0, {0, 10});
  param::SizeSpec spec;
  spec.hmax = 1.0;
  spec.hmin = 1e-3;
  spec.chordal_tol = 1e-3;
  const param::Metric3 m = param::surface_metric(*s, 0.0, 1.0, spec);
  const double h_around = param::chordal_size(1.0, 1e-3);
  CHECK(m.length({0.0, h_around, 0.0}) == Approx(1.0));  // around the axis at u = 0
  CHECK(m.length({0.0, 0.0, 1.0}) == Approx(1.0));       // hmax along the axis
  spec.isotropic = true;
  const param::Metric3 mi = param::surface_metric(*s, 0.0, 1.0, spec);
  CHECK(mi.anisotropy() == Approx(1.0));
  // Local sizes: face and point.
  spec.isotropic = false;
  spec.face_size[3] = 0.01;
  CHECK(param::surface_metric(*s, 0.0, 1.0, spec, 3).sizes()[2] == Approx(0.01));
  spec.point_size.push_back({{1.0, 0.0, 1.0}, 0.005, 0.1});
  CHECK(param::surface_metric(*s, 0.0, 1.0, spec, 3).sizes()[0] == Approx(0.005));
  CHECK(param::surface_metric(*s, 0.0, 5.0, spec, 3).sizes()[0] > 0.005);
}

TEST_CASE("induced metric gives the true 3D length of small (u,v) steps", "[param][induced]") {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> U(0.0, 1.0);
  std::vector<geom::Vec3> ctrl;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 6; ++j) ctrl.push_back({i, j, std::sin(i + 0.7 * j)});
  const std::vector<std::shared_ptr<geom::Surface>> surfaces = {
      geom::make_sphere(tilted(), 2.0), geom::make_torus(tilted(), 4.0, 1.0),
      geom::make_cone(tilted(), 1.0, 0.5, {0, 3}), geom::make_bspline_patch(ctrl, 5, 6)};
  param::SizeSpec spec;
  spec.hmax = 0.3;
  spec.chordal_tol = 1e-3;
  for (const auto& s : surfaces) {
    const geom::Box2 b = s->bounds();
    for (int t = 0; t < 50; ++t) {
      const double u = b.u.at(0.1 + 0.8 * U(rng)), v = b.v.at(0.1 + 0.8 * U(rng));
      const param::Metric3 m3 = param::surface_metric(*s, u, v, spec);
      const param::Metric2 muv = param::induced_metric(m3, s->eval(u, v), spec);
      REQUIRE(muv.is_spd());
      const double a = 2 * kPi * U(rng);
      const geom::Vec2 d = 1e-6 * geom::Vec2(std::cos(a), std::sin(a));
      const geom::Vec3 step = s->point(u + d.x, v + d.y) - s->point(u, v);
      CHECK(muv.length(d) == Approx(m3.length(step)).epsilon(1e-4));
    }
  }
}

TEST_CASE("induced metric at a pole is finite, SPD and capped, and periodic across a seam",
          "[param][induced]") {
  auto s = geom::make_sphere(geom::Frame{}, 1.0);
  param::SizeSpec spec;
  spec.hmax = 0.1;
  spec.max_uv_anisotropy = 1e3;
  const param::Metric3 m3 = param::Metric3::isotropic(0.1);
  const param::Metric2 pole = param::induced_metric(m3, s->eval(0.7, kPi / 2), spec);
  REQUIRE(pole.is_spd());
  CHECK(pole.anisotropy() == Approx(1e3));
  // Along v (meridian) the metric is exact: |sigma_v| = 1, so h_v = 0.1 in v.
  CHECK(pole.length({0.0, 0.1}) == Approx(1.0));
  // Seam: same metric at u and u + 2 pi.
  auto cyl = geom::make_torus(geom::Frame{}, 3.0, 1.0);
  const param::Metric2 a =
      param::induced_metric(param::surface_metric(*cyl, 0.0, 0.4, spec), cyl->eval(0.0, 0.4), spec);
  const param::Metric2 b = param::induced_metric(param::surface_metric(*cyl, 2 * kPi, 0.4, spec),
                                                 cyl->eval(2 * kPi, 0.4), spec);
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) CHECK(a(i, j) == Approx(b(i, j)).margin(1e-9 * a(0, 0)));
}

TEST_CASE("gradation: neighbouring sizes never grow faster than beta", "[param][gradation]") {
  // A line of points 0.1 apart; one tiny size in the middle.
  std::vector<geom::Vec3> pts;
  std::vector<param::Metric3> ms;
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < 100; ++i) {
    pts.push_back({0.1 * i, 0.0, 0.0});
    ms.push_back(param::Metric3::isotropic(i == 50 ? 0.001 : 1.0));
    if (i > 0) edges.emplace_back(i - 1, i);
  }
  const double beta = 1.2;
  const int n = param::gradate(ms, pts, edges, beta);
  CHECK(n > 0);
  for (const auto& [i, j] : edges) {
    const double hi = ms[i].sizes()[0], hj = ms[j].sizes()[0];
    CHECK(hj <= (hi + (beta - 1.0) * 0.1) * (1 + 1e-9));
    CHECK(hi <= (hj + (beta - 1.0) * 0.1) * (1 + 1e-9));
  }
  CHECK(ms[50].sizes()[0] == Approx(0.001));              // sizes only get finer
  CHECK(ms[60].sizes()[0] == Approx(0.001 + 0.2 * 1.0));  // h grows linearly with distance
  CHECK(param::gradate(ms, pts, edges, beta) == 0);       // a fixed point
}

TEST_CASE("face size field: background grid is gradated and interpolates", "[param][gradation]") {
  auto s = geom::make_torus(geom::Frame{}, 3.0, 1.0);
  param::SizeSpec spec;
  spec.hmax = 1.0;
  spec.chordal_tol = 1e-3;
  spec.point_size.push_back({{4.0, 0.0, 0.0}, 0.01, 0.05});
  param::FaceSizeField field(*s, s->bounds(), spec, geom::kNone, 33);
  CHECK(field.corrections() > 0);
  const param::Metric2 m = field.metric_uv(1.0, 1.0);
  CHECK(m.is_spd());
  // Near the point size the field is finer than the curvature size elsewhere.
  CHECK(field.metric3(0.0, 0.0).sizes()[0] < field.metric3(kPi, kPi).sizes()[0]);
}
