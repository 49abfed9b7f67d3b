// Small metric helpers shared by the mesher stages (internal).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::m2d::detail {

// Length of vector d in metric m: sqrt(d^T M d) (the integrand of eq. 7.10).
inline double length(const Metric2& m, Vec2 d) {
  return measures::metric_length(m.m11, m.m12, m.m22, d.x, d.y);
}

// Convex combination of SPD tensors: SPD. Used as the metric of a triangle or an edge
// when only the vertex metrics are known.
inline Metric2 scaled(const Metric2& a, double s) {
  return {a.m11 * s, a.m12 * s, a.m22 * s};
}
inline Metric2 mean3(const Metric2& a, const Metric2& b, const Metric2& c) {
  return {(a.m11 + b.m11 + c.m11) / 3, (a.m12 + b.m12 + c.m12) / 3, (a.m22 + b.m22 + c.m22) / 3};
}
inline Metric2 mix(const Metric2& a, const Metric2& b, double t) {
  return {a.m11 + t * (b.m11 - a.m11), a.m12 + t * (b.m12 - a.m12), a.m22 + t * (b.m22 - a.m22)};
}

// x -> R x with M = R^T R (R upper triangular, positive diagonal): Euclidean geometry in
// the frame is the geometry of M. det R > 0, so orientation is preserved.
struct MetricFrame {
  double l11, l12, l22;
  explicit MetricFrame(const Metric2& m) {
    l11 = std::sqrt(m.m11);
    l12 = m.m12 / l11;
    l22 = std::sqrt(std::max(m.m22 - l12 * l12, 1e-300));
  }
  Vec2 operator()(Vec2 p) const { return {l11 * p.x + l12 * p.y, l22 * p.y}; }
  // Inverse map.
  Vec2 inv(Vec2 q) const {
    const double y = q.y / l22;
    return {(q.x - l12 * y) / l11, y};
  }
};

// Caps the anisotropy: eigenvalues lambda_max / lambda_min <= cap^2 (sizes ratio <= cap),
// keeping the eigenvectors and the smaller size.
inline Metric2 cap_anisotropy(const Metric2& m, double cap) {
  const double tr = m.m11 + m.m22, det = m.m11 * m.m22 - m.m12 * m.m12;
  // Eigenvalue ratio r = l2 / l1 within the cap (r >= 1 / cap^2) without square roots:
  // det / tr^2 = r / (1 + r)^2 grows with r on (0, 1].
  const double c2 = cap * cap;
  if (det * (c2 + 1) * (c2 + 1) >= tr * tr * c2) return m;
  const double disc = std::sqrt(std::max(0.0, tr * tr / 4 - det));
  const double l1 = tr / 2 + disc, l2 = tr / 2 - disc;  // l1 >= l2
  const double lmin = l1 / (cap * cap);
  if (l2 >= lmin) return m;
  // M' = M + (lmin - l2) e2 e2^T with e2 the eigenvector of l2.
  double ex = m.m12, ey = l2 - m.m11;
  if (std::abs(ex) + std::abs(ey) < 1e-300 * (std::abs(l1) + 1e-300)) {
    ex = l2 - m.m22;
    ey = m.m12;
  }
  double n = std::hypot(ex, ey);
  if (!(n > 0)) {  // diagonal: the smaller diagonal entry's axis
    if (m.m11 <= m.m22)
      ex = 1, ey = 0;
    else
      ex = 0, ey = 1;
    n = 1;
  }
  ex /= n;
  ey /= n;
  const double d = lmin - l2;
  return {m.m11 + d * ex * ex, m.m12 + d * ex * ey, m.m22 + d * ey * ey};
}

inline Metric2 metric_at(const SizeSpec& s, double x, double y) {
  switch (s.kind) {
    case SizeSpec::Kind::Uniform:
      return Metric2::iso(s.h);
    case SizeSpec::Kind::Scalar:
      return Metric2::iso(s.size(x, y));
    case SizeSpec::Kind::Metric:
      return s.metric(x, y);
  }
  return {};
}

// measure() with the undirected edges given once each as (a << 32 | b) when the caller
// knows them from its adjacency (the mesher does), else (nullptr) found by sorting.
Quality measure_with_edges(const std::vector<Vec2>& vertices,
                           const std::vector<std::array<VertId, 3>>& tris, const SizeSpec& size,
                           std::vector<std::uint64_t>* known_edges);

}  // namespace uvmesh::m2d::detail
