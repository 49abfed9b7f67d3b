// Analytic back end: derivatives against finite differences, parametrisation facts,
// poles, arc length.
#include <catch2/catch.hpp>
#include <numbers>
#include <random>

#include "fd_check.h"
#include "uvmesh/geom/analytic.h"

using namespace uvmesh;
using geom::Vec3;

namespace {
const double kPi = std::numbers::pi;

std::vector<Vec3> wavy_grid(int nu, int nv) {
  std::vector<Vec3> c;
  for (int i = 0; i < nu; ++i)
    for (int j = 0; j < nv; ++j)
      c.push_back({1.3 * i, 0.8 * j + 0.1 * i * i, std::sin(1.1 * i) * std::cos(0.7 * j)});
  return c;
}
}  // namespace

TEST_CASE("analytic surfaces: derivatives match finite differences", "[geom][analytic]") {
  const geom::Frame f = geom::Frame::from_axis({1, 2, 3}, {0.2, -0.5, 1.0});
  const std::vector<std::pair<std::string, std::shared_ptr<geom::Surface>>> all = {
      {"plane", geom::make_plane(f, {{-1, 2}, {0, 3}})},
      {"cylinder", geom::make_cylinder(f, 2.0, {-1, 4})},
      {"cone", geom::make_cone(f, 1.5, 0.6, {0, 3})},
      {"sphere", geom::make_sphere(f, 3.0)},
      {"torus", geom::make_torus(f, 4.0, 1.5)},
      {"bspline33", geom::make_bspline_patch(wavy_grid(6, 7), 6, 7, 3, 3)},
      {"bspline23", geom::make_bspline_patch(wavy_grid(5, 8), 5, 8, 2, 3)},
      {"bspline_nonuniform_degree", geom::make_bspline_patch(wavy_grid(8, 4), 8, 4, 5, 1)},
  };
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(0.05, 0.95);
  for (const auto& [name, s] : all) {
    INFO(name);
    const geom::Box2 b = s->bounds();
    const double scale = glm::length(s->point(b.u.lo, b.v.lo) - s->point(b.u.hi, b.v.hi)) + 1.0;
    for (int t = 0; t < 200; ++t) {
      const double u = b.u.at(U(rng)), v = b.v.at(U(rng));
      const double hu = 1e-5 * b.u.length(), hv = 1e-5 * b.v.length();
      CHECK(test::surface_fd_error(*s, u, v, hu, hv, scale) < 1e-9);
    }
  }
}

TEST_CASE("analytic surfaces follow OCC's parametrisations", "[geom][analytic]") {
  const geom::Frame f;
  CHECK(glm::length(geom::make_cylinder(f, 2, {0, 1})->point(kPi / 2, 1.0) - Vec3(0, 2, 1)) <
        1e-15);
  CHECK(glm::length(geom::make_sphere(f, 2)->point(0.0, kPi / 2) - Vec3(0, 0, 2)) < 1e-15);
  CHECK(glm::length(geom::make_torus(f, 3, 1)->point(0.0, kPi) - Vec3(2, 0, 0)) < 1e-15);
  const double a = 0.3;
  CHECK(glm::length(geom::make_cone(f, 1, a, {0, 2})->point(0.0, 2.0) -
                    Vec3(1 + 2 * std::sin(a), 0, 2 * std::cos(a))) < 1e-15);
  // A clamped B-spline interpolates its corner control points.
  const auto c = wavy_grid(6, 7);
  const auto s = geom::make_bspline_patch(c, 6, 7);
  CHECK(glm::length(s->point(0, 0) - c.front()) < 1e-14);
  CHECK(glm::length(s->point(1, 1) - c.back()) < 1e-14);
  CHECK(glm::length(s->point(1, 0) - c[5 * 7]) < 1e-14);
  CHECK_THROWS(geom::make_bspline_patch(c, 6, 6));
}

TEST_CASE("poles: analytic singular sides and the sampling detector agree",
          "[geom][analytic][pole]") {
  const geom::Frame f;
  auto sphere = geom::make_sphere(f, 2.0);
  CHECK(sphere->singular_sides() == (geom::kSideVMin | geom::kSideVMax));
  CHECK(geom::detect_singular_sides(*sphere) == (geom::kSideVMin | geom::kSideVMax));
  auto torus = geom::make_torus(f, 3, 1);
  CHECK(torus->singular_sides() == 0u);
  CHECK(geom::detect_singular_sides(*torus) == 0u);
  const double a = 0.5, r = 2.0;
  auto cone = geom::make_cone(f, r, a, {-r / std::sin(a), 1.0});  // starts at the apex
  CHECK(cone->singular_sides() == geom::kSideVMin);
  CHECK(geom::detect_singular_sides(*cone) == geom::kSideVMin);
  CHECK(geom::make_cone(f, r, a, {0.0, 1.0})->singular_sides() == 0u);
  // A B-spline whose first control row collapses to one point has a pole on u = 0.
  auto c = wavy_grid(5, 5);
  for (int j = 0; j < 5; ++j) c[j] = Vec3(0, 0, 0);
  CHECK(geom::make_bspline_patch(c, 5, 5)->singular_sides() == geom::kSideUMin);
  // Normal is zero at the pole, unit elsewhere.
  CHECK(glm::length(sphere->eval(0.3, kPi / 2).normal()) == 0.0);
  CHECK(glm::length(sphere->eval(0.3, 0.2).normal()) == Approx(1.0));
}

TEST_CASE("periodicity: analytic surfaces repeat with their period", "[geom][analytic][seam]") {
  auto torus = geom::make_torus(geom::Frame{}, 3, 1);
  REQUIRE(torus->u_periodic());
  REQUIRE(torus->v_periodic());
  const auto a = torus->eval(0.4, 0.9),
             b = torus->eval(0.4 + torus->u_period(), 0.9 + torus->v_period());
  CHECK(glm::length(a.p - b.p) < 1e-14);
  CHECK(glm::length(a.du - b.du) < 1e-14);
  auto cyl = geom::make_cylinder(geom::Frame{}, 1, {0, 1});
  CHECK(cyl->u_periodic());
  CHECK_FALSE(cyl->v_periodic());
}

TEST_CASE("curves: derivatives and arc length", "[geom][analytic]") {
  const geom::Frame f = geom::Frame::from_axis({0, 0, 1}, {1, 1, 1});
  auto circle = geom::make_circle(f, 2.5);
  auto line = geom::make_line({1, 2, 3}, {0.5, -1, 2}, {0, 3});
  for (double t : {0.1, 1.0, 2.5, 4.0}) {
    CHECK(test::curve_fd_error(*circle, t, 1e-5, 2.5) < 1e-9);
    CHECK(test::curve_fd_error(*line, t, 1e-5, 1.0) < 1e-9);
  }
  CHECK(geom::arc_length(*circle, 0, 2 * kPi) == Approx(2 * kPi * 2.5).epsilon(1e-12));
  CHECK(geom::arc_length(*line, 0, 3) == Approx(3 * std::sqrt(0.25 + 1 + 4)).epsilon(1e-14));
}
