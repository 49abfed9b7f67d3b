// Analytic size fields of fields.h: the formulas at sample points, and the NAME:ARGS parser.
#include <catch2/catch.hpp>
#include <cmath>

#include "uvmesh2d/fields.h"

namespace f = uvmesh::cli2d::fields;
using Kind = uvmesh::m2d::SizeSpec::Kind;
using uvmesh::m2d::Metric2;

namespace {

// Length of the unit vector (cos t, sin t) in the metric: 1 / (size in that direction).
double inv_size(const Metric2& m, double t) {
  const double c = std::cos(t), s = std::sin(t);
  return std::sqrt(m.m11 * c * c + 2 * m.m12 * c * s + m.m22 * s * s);
}

}  // namespace

TEST_CASE("fields: uniform and linear", "[cli2d][fields]") {
  auto u = f::uniform(0.03);
  CHECK(u.kind == Kind::Uniform);
  CHECK(u.h == 0.03);
  auto l = f::linear(0.01, 0.1);
  REQUIRE(l.kind == Kind::Scalar);
  CHECK(l.size(0, 0.3) == Approx(0.01));
  CHECK(l.size(1, 0.7) == Approx(0.1));
  CHECK(l.size(0.25, 0.5) == Approx(0.01 + 0.25 * 0.09));
  CHECK(l.size(-2, 0) == Approx(0.01));  // clamped to the square
  CHECK(l.size(3, 0) == Approx(0.1));
  auto d = f::linear(0.2, 0.05);  // decreasing is fine
  CHECK(d.size(0.5, 0) == Approx(0.125));
}

TEST_CASE("fields: bl", "[cli2d][fields]") {
  const double h0 = 0.001, hmax = 0.1;
  auto s = f::bl(h0, hmax);
  REQUIRE(s.kind == Kind::Metric);
  const Metric2 mid = s.metric(0.3, 0.5);
  CHECK(mid.m11 == Approx(1 / (hmax * hmax)));
  CHECK(mid.m12 == 0);
  CHECK(mid.m22 == Approx(1 / (h0 * h0)));
  const Metric2 q = s.metric(0.9, 0.75);  // h_y = h0 + 2 (hmax - h0) 0.25
  const double hy = h0 + 0.5 * (hmax - h0);
  CHECK(q.m22 == Approx(1 / (hy * hy)));
  CHECK(s.metric(0.1, 0.0).m22 == Approx(1 / (hmax * hmax)));  // h_y = hmax at y = 0 and 1
  CHECK(s.metric(0.1, 1.0).m22 == Approx(1 / (hmax * hmax)));
  CHECK(s.metric(0.1, 7.0).m22 == Approx(1 / (hmax * hmax)));  // clamped outside
  CHECK(s.metric(0.1, 0.25).m22 == Approx(s.metric(0.1, 0.75).m22));
}

TEST_CASE("fields: ring", "[cli2d][fields]") {
  const double h0 = 0.002, hmax = 0.05;
  auto s = f::ring(h0, hmax);
  REQUIRE(s.kind == Kind::Metric);
  // On the circle r = 0.25: h_n = h0 along the radius, hmax along the tangent.
  const Metric2 e = s.metric(0.75, 0.5);  // n = (1, 0)
  CHECK(e.m11 == Approx(1 / (h0 * h0)));
  CHECK(e.m12 == Approx(0).margin(1e-9));
  CHECK(e.m22 == Approx(1 / (hmax * hmax)));
  const Metric2 nth = s.metric(0.5, 0.75);  // n = (0, 1)
  CHECK(nth.m11 == Approx(1 / (hmax * hmax)));
  CHECK(nth.m22 == Approx(1 / (h0 * h0)));
  // Diagonal direction, off the circle: r = 0.3, d = 0.05, h_n = h0 + 4 (hmax - h0) 0.05.
  const double t = 0.7, r = 0.3;
  const Metric2 m = s.metric(0.5 + r * std::cos(t), 0.5 + r * std::sin(t));
  const double hn = h0 + 4 * (hmax - h0) * 0.05;
  CHECK(1 / inv_size(m, t) == Approx(hn));                         // along n
  CHECK(1 / inv_size(m, t + 1.5707963267948966) == Approx(hmax));  // along t
  // Far from the circle h_n is capped at hmax: isotropic.
  const Metric2 far = s.metric(0.5 + 0.7, 0.5);
  CHECK(far.m11 == Approx(1 / (hmax * hmax)));
  CHECK(far.m22 == Approx(1 / (hmax * hmax)));
  // The centre: I / hmax^2, and continuous next to it.
  const Metric2 c = s.metric(0.5, 0.5);
  CHECK(c.m11 == 1 / (hmax * hmax));
  CHECK(c.m12 == 0);
  CHECK(c.m22 == 1 / (hmax * hmax));
  const Metric2 near = s.metric(0.5 + 1e-9, 0.5 - 1e-9);
  CHECK(near.m11 == Approx(c.m11));
  CHECK(near.m22 == Approx(c.m22));
  CHECK(near.m12 == Approx(0).margin(1e-6 * c.m11));
}

TEST_CASE("fields: parse", "[cli2d][fields]") {
  auto ok = f::parse("ring:0.002,0.05");
  REQUIRE(ok.ok());
  CHECK(ok.spec.kind == Kind::Metric);
  CHECK(ok.args == std::vector<double>{0.002, 0.05});
  CHECK(f::parse("uniform:0.1").spec.kind == Kind::Uniform);
  CHECK(f::parse("uniform:+1e-2").spec.h == 0.01);
  CHECK(f::parse("linear:0.1,0.01").spec.kind == Kind::Scalar);
  CHECK(f::parse("bl:1e-3,0.1").spec.kind == Kind::Metric);

  CHECK_THAT(f::parse("spiral:1").error, Catch::StartsWith("unknown size field 'spiral'"));
  CHECK_THAT(f::parse("ring").error, Catch::Contains("expected 2 numbers (ring:h0,hmax), found 0"));
  CHECK_THAT(f::parse("ring:0.1").error,
             Catch::Contains("expected 2 numbers (ring:h0,hmax), found 1"));
  CHECK_THAT(f::parse("uniform:0.1,0.2").error,
             Catch::Contains("expected 1 number (uniform:h), found 2"));
  CHECK_THAT(f::parse("linear:1,abc").error,
             Catch::Contains("'abc' is not a number (expected linear:h0,h1)"));
  CHECK_THAT(f::parse("uniform:").error, Catch::Contains("'' is not a number"));
  CHECK_THAT(f::parse("uniform:-1").error, Catch::Contains("sizes must be finite and > 0"));
  CHECK_THAT(f::parse("uniform:0").error, Catch::Contains("sizes must be finite and > 0"));
  CHECK_THAT(f::parse("uniform:nan").error, Catch::Contains("sizes must be finite and > 0"));
  CHECK_THAT(f::parse("uniform:inf").error, Catch::Contains("sizes must be finite and > 0"));
  CHECK_THAT(f::parse("bl:0.1,0.01").error, Catch::Contains("h0 must not exceed hmax"));
  CHECK_THAT(f::parse("ring:0.1,0.01").error, Catch::Contains("h0 must not exceed hmax"));
}
