// uvmesh::measures -- the one definition of each quality and size measure
// (docs/ARCHITECTURE.md, "Where each concept lives"). Used by mesher2d, the surface stage
// (3D improvement, checks), io's report, the CLIs and the tests; standard library only,
// so that mesher2d keeps no dependency.
//
//   double Q = measures::shape_Q(ab, bc, ca, area2);    // 1 for the equilateral
//   measures::UnitEdges u;
//   for (double L : metric_lengths) u.add(L);
//   double share = u.share();                            // edges in [1/sqrt2, sqrt2]
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace uvmesh::measures {

/// alpha = sqrt(3)/6 of eq. 7.6: Q_K = 1 for the equilateral triangle.
inline constexpr double kShapeAlpha = 0.28867513459481287;

/// Q_K = alpha h_max / rho_K (eq. 7.6) from the three edge lengths and twice the area
/// (rho_K = 2 area / perimeter): 1 for the equilateral, growing without bound as the
/// triangle flattens. area2 must be > 0.
inline double shape_Q(double ab, double bc, double ca, double area2) {
  return kShapeAlpha * (ab + bc + ca) * std::max({ab, bc, ca}) / area2;
}

/// q_K = 1 / Q_K in (0, 1] (eq. 7.6), computed directly (no division by a possibly huge
/// Q): 1 for the equilateral, 0 for a flat triangle. area2 may be 0 (gives 0).
inline double shape_q(double ab, double bc, double ca, double area2) {
  return area2 / (kShapeAlpha * (ab + bc + ca) * std::max({ab, bc, ca}));
}

/// Length of the vector (dx, dy) in the 2D metric [[m11 m12][m12 m22]]: sqrt(d^T M d)
/// (the integrand of eq. 7.10). Rounding may make d^T M d slightly negative for a nearly
/// degenerate M; it counts as 0.
inline double metric_length(double m11, double m12, double m22, double dx, double dy) {
  return std::sqrt(std::max(0.0, m11 * dx * dx + 2 * m12 * dx * dy + m22 * dy * dy));
}

/// Length of a mesh edge in a varying metric from the lengths of its vector in the
/// metrics at its two ends and at its middle: Simpson's rule on the integral of eq. 7.10.
/// Exact for a metric constant along the edge.
inline double edge_length(double l_a, double l_mid, double l_b) {
  return (l_a + 4 * l_mid + l_b) / 6;
}

/// The same from the two ends only, when the metric is not known between them: the
/// logarithmic mean of the two lengths, exact when the size varies geometrically along
/// the edge (as a gradated size does, eq. 7.11); their mean when they are within 0.1% of
/// each other (or one is 0), where the two agree and the logarithm would cancel.
inline double edge_length(double l_a, double l_b) {
  const double ratio = l_a > 0 ? l_b / l_a : 1.0;
  return (std::abs(ratio - 1) < 1e-3 || !(ratio > 0)) ? 0.5 * (l_a + l_b)
                                                      : (l_b - l_a) / std::log(ratio);
}

/// The unit mesh of §7.5.2: an edge is unit when its metric length is in
/// [1/sqrt(2), sqrt(2)].
/// sqrt(2) correctly rounded, and 1/sqrt(2) as 1 / kUnitMax rounded (one unit in the last
/// place below sqrt(0.5) correctly rounded; the mesher's decisions are made against this
/// value).
inline constexpr double kUnitMax = 1.4142135623730951;
inline constexpr double kUnitMin = 1 / kUnitMax;
inline bool is_unit(double L) {
  return L >= kUnitMin && L <= kUnitMax;
}

/// Counts of short (< 1/sqrt2), unit and long (> sqrt2) edges, and the unit share.
struct UnitEdges {
  std::int64_t edges = 0, unit = 0, short_edges = 0, long_edges = 0;
  void add(double L) {
    ++edges;
    if (L < kUnitMin)
      ++short_edges;
    else if (L > kUnitMax)
      ++long_edges;
    else
      ++unit;
  }
  void add(const UnitEdges& o) {
    edges += o.edges, unit += o.unit, short_edges += o.short_edges, long_edges += o.long_edges;
  }
  /// Share of unit edges; 0 for no edges.
  double share() const { return edges > 0 ? static_cast<double>(unit) / edges : 0.0; }
};

}  // namespace uvmesh::measures
