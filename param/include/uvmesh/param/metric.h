// uvmesh::param metrics: symmetric positive definite N x N matrices (N = 2: the (u,v)
// plane; N = 3: space) that prescribe sizes and directions (chapter 7.6.1, eq. 7.11:
// M = R^T diag(1/h_i^2) R). A vector e has length sqrt(e^T M e); a mesh is a unit mesh
// when its edges have metric length in [1/sqrt(2), sqrt(2)] (7.5.2).
//
//   param::Metric2 m = param::Metric2::from_sizes({{1,0},{0,1}}, {0.1, 2.0});
//   double l = m.length({0.1, 0.0});                        // 1
//   param::Metric2 both = param::intersect(m, param::Metric2::isotropic(0.5));
//   param::Metric2 mid = param::interpolate(m, both, 0.5);  // SPD
//
// Header-only templates on N; Metric2 and Metric3 are the instances used.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <functional>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>

namespace uvmesh::param {

template <int N>
using VecN = glm::vec<N, double, glm::defaultp>;

template <int N>
struct Eigen;

/// Symmetric N x N metric (stored full, kept symmetric by every operation).
template <int N>
class Metric {
 public:
  using Vec = VecN<N>;
  std::array<std::array<double, N>, N> m{};

  Metric() = default;
  static Metric identity() { return diagonal(1.0); }
  static Metric diagonal(double d) {
    Metric r;
    for (int i = 0; i < N; ++i) r.m[i][i] = d;
    return r;
  }
  /// Isotropic size h: M = I / h^2.
  static Metric isotropic(double h) { return diagonal(1.0 / (h * h)); }
  /// M = sum_i d_i d_i^T / h_i^2 for orthonormal directions d_i and sizes h_i.
  static Metric from_sizes(const std::array<Vec, N>& dirs, const std::array<double, N>& h) {
    std::array<double, N> lam;
    for (int i = 0; i < N; ++i) lam[i] = 1.0 / (h[i] * h[i]);
    return from_eigen(dirs, lam);
  }
  /// M = sum_i lambda_i d_i d_i^T.
  static Metric from_eigen(const std::array<Vec, N>& dirs, const std::array<double, N>& lam) {
    Metric r;
    for (int k = 0; k < N; ++k)
      for (int i = 0; i < N; ++i)
        for (int j = 0; j < N; ++j) r.m[i][j] += lam[k] * dirs[k][i] * dirs[k][j];
    r.symmetrize();
    return r;
  }

  double operator()(int i, int j) const { return m[i][j]; }
  Vec apply(const Vec& v) const {
    Vec r(0.0);
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) r[i] += m[i][j] * v[j];
    return r;
  }
  /// e^T M e.
  double dot(const Vec& a, const Vec& b) const { return glm::dot(a, apply(b)); }
  /// Length of e in this (constant) metric: sqrt(e^T M e).
  double length(const Vec& e) const { return std::sqrt(std::max(0.0, dot(e, e))); }
  double determinant() const;
  Metric operator*(double s) const {
    Metric r = *this;
    for (auto& row : r.m)
      for (double& x : row) x *= s;
    return r;
  }
  Metric operator+(const Metric& o) const {
    Metric r = *this;
    for (int i = 0; i < N; ++i)
      for (int j = 0; j < N; ++j) r.m[i][j] += o.m[i][j];
    return r;
  }
  void symmetrize() {
    for (int i = 0; i < N; ++i)
      for (int j = i + 1; j < N; ++j) m[i][j] = m[j][i] = 0.5 * (m[i][j] + m[j][i]);
  }

  Eigen<N> eigen() const;
  /// M^p through the eigen-decomposition (p = -1: inverse, 1/2: square root, ...).
  Metric power(double p) const;
  bool is_spd() const;
  /// Sizes h_i = 1/sqrt(lambda_i), smallest first.
  std::array<double, N> sizes() const;
  /// Anisotropy ratio h_max / h_min.
  double anisotropy() const;
  /// Same metric with h_max / h_min <= r: small eigenvalues raised to lambda_max / r^2
  /// (sizes along the long directions shortened, the finest size kept).
  Metric capped(double r) const;
  /// Sizes clamped to [hmin, hmax] direction by direction.
  Metric clamped(double hmin, double hmax) const;
};

template <int N>
struct Eigen {
  std::array<double, N> values;    ///< ascending
  std::array<VecN<N>, N> vectors;  ///< orthonormal, vectors[i] for values[i]
};

using Metric2 = Metric<2>;
using Metric3 = Metric<3>;

// ----------------------------------------------------------------------------------
// Implementation

namespace detail {
/// Cyclic Jacobi rotations for a symmetric matrix: robust, accurate to rounding for the
/// 2x2 / 3x3 metrics here (converges quadratically; 50 sweeps is a hard cap never hit).
template <int N>
Eigen<N> jacobi(std::array<std::array<double, N>, N> a) {
  std::array<std::array<double, N>, N> v{};
  for (int i = 0; i < N; ++i) v[i][i] = 1.0;
  for (int sweep = 0; sweep < 50; ++sweep) {
    double off = 0.0, diag = 0.0;
    for (int i = 0; i < N; ++i) {
      diag += a[i][i] * a[i][i];
      for (int j = i + 1; j < N; ++j) off += a[i][j] * a[i][j];
    }
    if (off <= 1e-32 * diag || off == 0.0) break;
    for (int p = 0; p < N; ++p)
      for (int q = p + 1; q < N; ++q) {
        if (a[p][q] == 0.0) continue;
        const double theta = (a[q][q] - a[p][p]) / (2.0 * a[p][q]);
        const double t =
            (theta >= 0 ? 1.0 : -1.0) / (std::abs(theta) + std::sqrt(theta * theta + 1.0));
        const double c = 1.0 / std::sqrt(t * t + 1.0), s = t * c;
        for (int k = 0; k < N; ++k) {  // A <- A J (columns p, q)
          const double akp = a[k][p], akq = a[k][q];
          a[k][p] = c * akp - s * akq;
          a[k][q] = s * akp + c * akq;
        }
        for (int k = 0; k < N; ++k) {  // A <- J^T A (rows p, q)
          const double apk = a[p][k], aqk = a[q][k];
          a[p][k] = c * apk - s * aqk;
          a[q][k] = s * apk + c * aqk;
        }
        for (int k = 0; k < N; ++k) {
          const double vkp = v[k][p], vkq = v[k][q];
          v[k][p] = c * vkp - s * vkq;
          v[k][q] = s * vkp + c * vkq;
        }
      }
  }
  Eigen<N> e;
  std::array<int, N> idx;
  for (int i = 0; i < N; ++i) idx[i] = i;
  std::sort(idx.begin(), idx.end(), [&](int x, int y) { return a[x][x] < a[y][y]; });
  for (int i = 0; i < N; ++i) {
    e.values[i] = a[idx[i]][idx[i]];
    for (int k = 0; k < N; ++k) e.vectors[i][k] = v[k][idx[i]];
  }
  return e;
}
}  // namespace detail

template <int N>
Eigen<N> Metric<N>::eigen() const {
  return detail::jacobi<N>(m);
}

template <int N>
double Metric<N>::determinant() const {
  if constexpr (N == 2)
    return m[0][0] * m[1][1] - m[0][1] * m[1][0];
  else
    return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1]) -
           m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0]) +
           m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

template <int N>
Metric<N> Metric<N>::power(double p) const {
  Eigen<N> e = eigen();
  for (double& l : e.values) l = std::pow(std::max(l, std::numeric_limits<double>::min()), p);
  return from_eigen(e.vectors, e.values);
}

template <int N>
bool Metric<N>::is_spd() const {
  for (const auto& row : m)
    for (double x : row)
      if (!std::isfinite(x)) return false;
  const Eigen<N> e = eigen();
  return e.values[0] > 0.0;
}

template <int N>
std::array<double, N> Metric<N>::sizes() const {
  const Eigen<N> e = eigen();
  std::array<double, N> h;
  for (int i = 0; i < N; ++i) h[i] = 1.0 / std::sqrt(e.values[N - 1 - i]);
  return h;
}

template <int N>
double Metric<N>::anisotropy() const {
  const Eigen<N> e = eigen();
  return std::sqrt(e.values[N - 1] / e.values[0]);
}

template <int N>
Metric<N> Metric<N>::capped(double r) const {
  Eigen<N> e = eigen();
  const double floor = e.values[N - 1] / (r * r);
  for (double& l : e.values) l = std::max(l, floor);
  return from_eigen(e.vectors, e.values);
}

template <int N>
Metric<N> Metric<N>::clamped(double hmin, double hmax) const {
  Eigen<N> e = eigen();
  for (double& l : e.values) l = std::clamp(l, 1.0 / (hmax * hmax), 1.0 / (hmin * hmin));
  return from_eigen(e.vectors, e.values);
}

/// Intersection by simultaneous reduction: a metric whose unit ball lies inside the unit
/// balls of both A and B (so it asks for the finer size in every direction), and is the
/// largest such ball among those sharing their axes with the common basis. With C = A^{-1/2} B
/// A^{-1/2} = Q D Q^T, P = A^{-1/2} Q reduces both (P^T A P = I, P^T B P = D); the result is
/// A^{1/2} Q diag(max(1, d_i)) Q^T A^{1/2}. Lengths in it are max(|e|_A, |e|_B) along the
/// common eigen-directions and >= both everywhere.
template <int N>
Metric<N> intersect(const Metric<N>& a, const Metric<N>& b) {
  // A^{1/2} and A^{-1/2} from one eigen-decomposition of A (the same one power() makes;
  // the gradation intersects metrics at every update).
  const Eigen<N> ea = a.eigen();
  std::array<double, N> sq, isq;
  for (int i = 0; i < N; ++i) {
    const double l = std::max(ea.values[i], std::numeric_limits<double>::min());
    sq[i] = std::pow(l, 0.5);
    isq[i] = std::pow(l, -0.5);
  }
  const Metric<N> ah = Metric<N>::from_eigen(ea.vectors, sq),
                  aih = Metric<N>::from_eigen(ea.vectors, isq);
  Metric<N> c;
  // c = aih * b * aih
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      double s = 0.0;
      for (int k = 0; k < N; ++k)
        for (int l = 0; l < N; ++l) s += aih.m[i][k] * b.m[k][l] * aih.m[l][j];
      c.m[i][j] = s;
    }
  c.symmetrize();
  Eigen<N> e = c.eigen();
  for (double& d : e.values) d = std::max(1.0, d);
  const Metric<N> mid = Metric<N>::from_eigen(e.vectors, e.values);
  Metric<N> r;
  for (int i = 0; i < N; ++i)
    for (int j = 0; j < N; ++j) {
      double s = 0.0;
      for (int k = 0; k < N; ++k)
        for (int l = 0; l < N; ++l) s += ah.m[i][k] * mid.m[k][l] * ah.m[l][j];
      r.m[i][j] = s;
    }
  r.symmetrize();
  return r;
}

/// Interpolation along an edge, t in [0,1]: M(t) = ((1-t) A^{-1/2} + t B^{-1/2})^{-2}, i.e.
/// sizes (not metric coefficients) vary linearly -- the P1 size interpolation of 7.5.1
/// extended to metrics. A sum of SPD matrices is SPD, so M(t) is SPD.
template <int N>
Metric<N> interpolate(const Metric<N>& a, const Metric<N>& b, double t) {
  return (a.power(-0.5) * (1.0 - t) + b.power(-0.5) * t).power(-2.0);
}

/// Interpolation in a triangle with barycentric weights w (sum 1, each >= 0).
template <int N>
Metric<N> interpolate(const Metric<N>& a, const Metric<N>& b, const Metric<N>& c,
                      const std::array<double, 3>& w) {
  return (a.power(-0.5) * w[0] + b.power(-0.5) * w[1] + c.power(-0.5) * w[2]).power(-2.0);
}

/// Length of the segment A + t e, t in [0,1], in a varying metric M(t) (eq. 7.10):
/// integral of sqrt(e^T M(t) e) by adaptive Simpson quadrature to relative tolerance tol.
template <int N>
double edge_length(const std::function<Metric<N>(double)>& metric_at, const VecN<N>& e,
                   double tol = 1e-6) {
  auto f = [&](double t) { return metric_at(t).length(e); };
  std::function<double(double, double, double, double, double, double, int)> rec =
      [&](double a, double b, double fa, double fm, double fb, double whole, int depth) -> double {
    const double m = 0.5 * (a + b);
    const double lm = f(0.5 * (a + m)), rm = f(0.5 * (m + b));
    const double left = (m - a) / 6.0 * (fa + 4.0 * lm + fm);
    const double right = (b - m) / 6.0 * (fm + 4.0 * rm + fb);
    const double both = left + right;
    if (depth <= 0 || std::abs(both - whole) <= 15.0 * tol * std::max(std::abs(both), 1e-300))
      return both + (both - whole) / 15.0;
    return rec(a, m, fa, lm, fm, left, depth - 1) + rec(m, b, fm, rm, fb, right, depth - 1);
  };
  const double fa = f(0.0), fm = f(0.5), fb = f(1.0);
  return rec(0.0, 1.0, fa, fm, fb, (fa + 4.0 * fm + fb) / 6.0, 30);
}

}  // namespace uvmesh::param
