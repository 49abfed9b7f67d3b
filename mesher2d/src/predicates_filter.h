// Inline floating-point filters of the exact predicates (internal header of mesher2d).
//
// pred::orient2d / pred::incircle (predicates.h) are these filters; the kernel's hot loops
// (point location, cavity growth) include this header so that the filter is inlined and
// only the rare nearly-degenerate cases pay a call to the exact slow path
// (predicates.cpp, stages B-D). Same sign guarantee as the public functions: the
// filter returns the plain double determinant only when its magnitude exceeds a proven
// bound on the rounding error; otherwise the exact code decides.
#pragma once

#include <cmath>

namespace uvmesh::m2d::pred::detail {

// ---------------------------------------------------------------------------------------
// Constants. e = 2^-53 is the unit roundoff: fl(x op y) = (x op y)(1 + d), |d| <= e, for
// results in the normal range. In the subnormal range a product additionally carries an
// absolute error |h| <= eta = 2^-1075 (sums and differences are always exact there).
// All constants below are exactly representable and computed at compile time.
// ---------------------------------------------------------------------------------------
inline constexpr double kEps = 0x1p-53;

// Lower clamp of the filter bounds. Accepting only |det| >= 2^-1000 (times the lift sum
// for incircle) makes the subnormal absolute errors (a few eta) negligible (< 2^-71
// relative) without ever computing with subnormal numbers on the hot path (subnormal
// operands cost a microcode assist on many x86 cores).
inline constexpr double kFloor = 0x1p-1000;

// --- orient2d filter -------------------------------------------------------------------
// x_i are the computed differences, x_i = (true diff)(1 + d_i). Let T be the true
// determinant, l = fl(acx*bcy), r = fl(acy*bcx), D = l - r (exact), det = fl(D).
// Rounding is monotone and fl(D) = 0 only if D = 0, so sign(det) = sign(D), and
// |D| >= |det| / (1 + e). With S = |acx*bcy| + |acy*bcx| (exact products of the computed
// differences):
//   |T - (acx*bcy - acy*bcx)| <= (1/(1-e)^2 - 1) S <= (2e + 4e^2) S   (difference rounding)
//   |(acx*bcy - acy*bcx) - D| <= e S + 2 eta                         (product rounding)
// and S <= (ds + 2 eta) / (1 - e)^2 with ds = fl(|l| + |r|). Hence
//   |T - D| <= (3e + 11e^2) ds + 3 eta.
// Accept when |det| > E = max(fl(A ds), 2^-1000), A = (3 + 32e) e. Then
// ds <= (|det| + eta) / (A (1-e)), so (3e + 11e^2) ds <= (1 - 6e)(|det| + eta), and
// 4 eta <= 2^-71 |det|; altogether |T - D| < (1 - 5e)|det| < |det|/(1+e) <= |D|, so T
// has the sign of D, which is the sign of det.
inline constexpr double kO2A = (3.0 + 32.0 * kEps) * kEps;

// --- incircle filter -------------------------------------------------------------------
// Twelve degree-4 monomials m (in the computed differences), P = sum |m|. Difference
// rounding: |T - B| <= (1/(1-e)^4 - 1) P <= (4e + 11e^2) P, B = exact determinant of the
// computed differences. Evaluation: along every monomial at most 6 roundings happen
// before the last addition (square or product, lift-sum or cross-difference, product
// with the lift, first of the two outer additions), so with D = exact value of the last
// addition, |B - D| <= gamma_6 P + H, gamma_6 <= 6e + 37e^2, where H collects the
// subnormal absolute errors: two per lift (times |cross|), two per cross term (times the
// lift), one per outer product. Using |x y| <= (x^2 + y^2)/2 every |cross| sum is bounded
// by the lift sum, giving H <= eta ((4 + 31e) L + 5) with L = fl(alift + blift + clift).
// The computed permanent Pc satisfies P <= (Pc + H)/(1-e)^7 (7 roundings including the
// last addition). Altogether
//   |T - D| <= (10e + 119e^2) Pc + 2 eta ((4 + 31e) L + 5).
// Accept when |det| > E = max(fl(A Pc), 2^-1000 max(L, 1)), A = (10 + 160e) e. Then
// (10e + 119e^2) Pc <= (1 - 3.1e)(|det| + eta) and the eta terms are below
// 2^-70 |det|, so |T - D| < (1 - 3e)|det| < |D| and the sign of det is exact.
inline constexpr double kIcA = (10.0 + 160.0 * kEps) * kEps;

static_assert(kO2A > 3.0 * kEps && kIcA > 10.0 * kEps, "error-bound constants");

// Exact slow paths (predicates.cpp): called when the filter cannot decide.
double orient2d_slow(const double* a, const double* b, const double* c);
double incircle_slow(const double* a, const double* b, const double* c, const double* d);

// The filters alone: the determinant when its sign is certain, else 0 (a certain
// determinant is never 0: it exceeds a positive bound). NaN inputs give 0.
inline double orient2d_filter(const double* a, const double* b, const double* c) {
  const double acx = a[0] - c[0];
  const double bcx = b[0] - c[0];
  const double acy = a[1] - c[1];
  const double bcy = b[1] - c[1];
  const double detleft = acx * bcy;
  const double detright = acy * bcx;
  const double det = detleft - detright;
  const double bound = kO2A * (std::fabs(detleft) + std::fabs(detright));
  const double errbound = bound > kFloor ? bound : kFloor;
  // One comparison of |det| (the sign is tested by the caller: one data-dependent branch,
  // not two). A NaN det makes it false; an infinite det comes with an infinite
  // bound. Either way the slow path decides.
  if (std::fabs(det) > errbound) [[likely]]
    return det;
  return 0;
}

inline double orient2d_filtered(const double* a, const double* b, const double* c) {
  const double det = orient2d_filter(a, b, c);
  if (det != 0) [[likely]]
    return det;
  return orient2d_slow(a, b, c);
}

inline double incircle_filter(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0];
  const double bdx = b[0] - d[0];
  const double cdx = c[0] - d[0];
  const double ady = a[1] - d[1];
  const double bdy = b[1] - d[1];
  const double cdy = c[1] - d[1];

  const double bdxcdy = bdx * cdy;
  const double cdxbdy = cdx * bdy;
  const double alift = adx * adx + ady * ady;

  const double cdxady = cdx * ady;
  const double adxcdy = adx * cdy;
  const double blift = bdx * bdx + bdy * bdy;

  const double adxbdy = adx * bdy;
  const double bdxady = bdx * ady;
  const double clift = cdx * cdx + cdy * cdy;

  const double det =
      (alift * (bdxcdy - cdxbdy) + blift * (cdxady - adxcdy)) + clift * (adxbdy - bdxady);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  const double lifts = (alift + blift) + clift;
  const double least = kFloor * (lifts > 1.0 ? lifts : 1.0);
  const double bound = kIcA * permanent;
  const double errbound = bound > least ? bound : least;
  if (std::fabs(det) > errbound) [[likely]]
    return det;
  return 0;
}

inline double incircle_filtered(const double* a, const double* b, const double* c,
                                const double* d) {
  const double det = incircle_filter(a, b, c, d);
  if (det != 0) [[likely]]
    return det;
  return incircle_slow(a, b, c, d);
}

}  // namespace uvmesh::m2d::pred::detail
