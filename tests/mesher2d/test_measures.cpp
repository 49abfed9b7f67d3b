// The one definition of each measure (uvmesh/mesher2d/measures.h) on triangles and edges
// whose values are known in closed form.
#include <catch2/catch.hpp>
#include <cmath>

#include "uvmesh/mesher2d/measures.h"

namespace ms = uvmesh::measures;

namespace {
// Edge lengths and twice the area of the triangle (0,0), (1,0), (x,y), y > 0.
struct Tri {
  double ab, bc, ca, area2;
};
Tri tri(double x, double y) {
  return {1.0, std::hypot(x - 1.0, y), std::hypot(x, y), y};
}
}  // namespace

TEST_CASE("measures: Q_K is 1 for the equilateral and alpha h_max / rho otherwise", "[measures]") {
  const Tri eq = tri(0.5, std::sqrt(3.0) / 2);
  CHECK(ms::shape_Q(eq.ab, eq.bc, eq.ca, eq.area2) == Approx(1.0).epsilon(1e-15));
  CHECK(ms::shape_q(eq.ab, eq.bc, eq.ca, eq.area2) == Approx(1.0).epsilon(1e-15));
  // Right isosceles: h_max = sqrt2, perimeter 2 + sqrt2, area 1/2, rho = 1/(2 + sqrt2).
  const Tri r = tri(0.0, 1.0);
  const double expect = std::sqrt(3.0) / 6 * std::sqrt(2.0) * (2 + std::sqrt(2.0));
  CHECK(ms::shape_Q(r.ab, r.bc, r.ca, r.area2) == Approx(expect).epsilon(1e-14));
  CHECK(ms::shape_q(r.ab, r.bc, r.ca, r.area2) == Approx(1 / expect).epsilon(1e-14));
  // Invariant under scaling and under the order of the edges.
  CHECK(ms::shape_Q(3 * r.ca, 3 * r.ab, 3 * r.bc, 9 * r.area2) ==
        Approx(ms::shape_Q(r.ab, r.bc, r.ca, r.area2)).epsilon(1e-14));
}

TEST_CASE("measures: Q_K grows without bound as the triangle flattens, q_K of a flat one is 0",
          "[measures]") {
  double last = 1.0;
  for (double y : {0.5, 0.1, 1e-3, 1e-6, 1e-9}) {
    const Tri t = tri(0.5, y);
    const double Q = ms::shape_Q(t.ab, t.bc, t.ca, t.area2);
    CHECK(Q > last);
    CHECK(ms::shape_q(t.ab, t.bc, t.ca, t.area2) == Approx(1 / Q).epsilon(1e-12));
    last = Q;
  }
  CHECK(last > 1e8);
  CHECK(ms::shape_q(1.0, 0.5, 0.5, 0.0) == 0.0);
}

TEST_CASE("measures: metric length and the edge-length rule", "[measures]") {
  // M = I / h^2: the Euclidean length over h.
  CHECK(ms::metric_length(1 / 0.04, 0, 1 / 0.04, 0.3, 0.4) == Approx(2.5).epsilon(1e-15));
  // Anisotropic: sizes 1 along x, 0.1 along y, rotated by 45 degrees.
  const double a = 1.0, b = 100.0;  // eigenvalues 1/h^2
  const double m11 = (a + b) / 2, m12 = (a - b) / 2, m22 = (a + b) / 2;
  const double s = std::sqrt(0.5);
  CHECK(ms::metric_length(m11, m12, m22, s, s) == Approx(1.0).epsilon(1e-14));
  CHECK(ms::metric_length(m11, m12, m22, s, -s) == Approx(10.0).epsilon(1e-14));
  // A metric that rounds to slightly indefinite gives 0, not NaN.
  CHECK(ms::metric_length(1, 1 + 1e-12, 1, 1, -1) == 0.0);
  // Simpson's rule: exact for a constant metric, and for a length varying linearly.
  CHECK(ms::edge_length(0.8, 0.8, 0.8) == Approx(0.8).epsilon(1e-15));
  CHECK(ms::edge_length(0.5, 1.0, 1.5) == Approx(1.0).epsilon(1e-15));
}

TEST_CASE("measures: unit edges are [1/sqrt2, sqrt2], both ends included", "[measures]") {
  CHECK(ms::kUnitMin == Approx(std::sqrt(0.5)).epsilon(1e-15));
  CHECK(ms::kUnitMax == std::sqrt(2.0));
  CHECK(ms::is_unit(ms::kUnitMin));
  CHECK(ms::is_unit(ms::kUnitMax));
  CHECK(ms::is_unit(1.0));
  CHECK_FALSE(ms::is_unit(std::nextafter(ms::kUnitMin, 0.0)));
  CHECK_FALSE(ms::is_unit(std::nextafter(ms::kUnitMax, 2.0)));
  ms::UnitEdges u;
  CHECK(u.share() == 0.0);
  for (double L : {0.1, 0.7, 0.71, 1.0, 1.41, 1.42, 5.0}) u.add(L);
  CHECK(u.edges == 7);
  CHECK(u.short_edges == 2);
  CHECK(u.unit == 3);
  CHECK(u.long_edges == 2);
  CHECK(u.share() == Approx(3.0 / 7));
  ms::UnitEdges v;
  v.add(1.0);
  u.add(v);
  CHECK(u.edges == 8);
  CHECK(u.unit == 4);
}

TEST_CASE("measures: the two-end edge length is exact for a geometric size variation",
          "[measures]") {
  // Size h(s) = h0 r^s along an edge of length 1 in its own arc length s: the metric
  // length is the integral of 1 / h(s), (1/h0)(1 - 1/r) / ln r, and the two end lengths
  // are 1/h0 and 1/(h0 r).
  const double h0 = 0.5, r = 3.0;
  const double exact = (1 / h0) * (1 - 1 / r) / std::log(r);
  CHECK(ms::edge_length(1 / h0, 1 / (h0 * r)) == Approx(exact).epsilon(1e-14));
  CHECK(ms::edge_length(1 / (h0 * r), 1 / h0) == Approx(exact).epsilon(1e-14));
  // Equal ends: the common length; one end zero: the mean.
  CHECK(ms::edge_length(0.9, 0.9) == 0.9);
  CHECK(ms::edge_length(0.0, 2.0) == 1.0);
}
