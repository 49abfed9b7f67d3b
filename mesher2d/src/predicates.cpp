// Exact adaptive-precision orient2d and incircle on doubles.
//
// Technique (published: Dekker 1971, Knuth TAOCP vol. 2 §4.2.2, Priest 1991, Shewchuk
// 1997 "Adaptive precision floating-point arithmetic and fast robust geometric
// predicates"); this is an independent implementation with its own error analysis:
//
//   1. Filter: the determinant in plain double arithmetic plus an a-priori error bound
//      (derived below). When |det| exceeds the bound the sign is certain. This is the
//      only code on the hot path; everything else lives in out-of-line slow functions.
//   2. Stage B: exact expansion of the determinant of the *rounded* coordinate
//      differences. If every difference was computed exactly (common for nearby points,
//      Sterbenz), this IS the exact determinant. Otherwise it is accepted when its
//      magnitude, compared exactly, exceeds a bound on the effect of the lost tails.
//   3. Stage C: stage B plus a first-order tail correction evaluated in doubles, again
//      accepted against a proven bound (exact comparison).
//   4. Stage D: the determinant evaluated exactly from two-term expansions of every
//      difference. Always exact.
//   (Inputs spanning more magnitudes than expansions can hold use exact big integers.)
//
// Expansions are arrays of doubles, nonoverlapping, in increasing magnitude, with zero
// components removed (length 0 means zero). The sign of an expansion is the sign of its
// last (largest) component.
//
// ASSUMPTIONS (checked where possible at compile time):
//   * IEEE-754 binary64, round-to-nearest-even, no x87 extended precision
//     (FLT_EVAL_METHOD == 0), no -ffast-math. FMA contraction is harmless to the bounds
//     (it only removes roundings) and TwoProduct uses std::fma whenever the target has
//     FMA, so Dekker splitting is only used where contraction cannot happen.
//   * Inputs are finite. Non-finite inputs give an unspecified (but memory-safe) result.
//   * The filter is valid for ALL finite inputs, including ones whose products underflow
//     (a floor on the accepted magnitude makes gradual-underflow errors negligible) or
//     overflow (inf/NaN in the filter always falls through to the slow path).
//   * The slow path rescales the points by an exact power of two when needed, so the
//     absolute scale does not matter (subnormals .. 1e308 all work). Expansions need a
//     bounded DYNAMIC RANGE within one call: with M the largest and m the smallest
//     nonzero coordinate magnitude,
//         orient2d:  log2(M) - log2(m) <= 850   (about 1e255)
//         incircle:  log2(M) - log2(m) <= 350   (about 1e105)
//     (see RangeLimits). Wider inputs, such as 5e-324 and 3.0 in one call, whose exact
//     determinant needs bits far below 2^-1074, go to an exact fixed-size integer
//     fallback (slow, but such inputs are pathological). So the sign is exact for EVERY
//     finite input.
//
// The returned value has the exact sign. Its magnitude approximates the determinant no
// worse than plain double evaluation does (error <= about 3 eps (|acx bcy| + |acy bcx|)
// for orient2d and 10 eps * permanent for incircle), and on the slow path usually to a
// few ulps; a nonzero result too small for a double is returned as +-denorm_min.
#include "uvmesh/mesher2d/predicates.h"

#include <bit>
#include <cfloat>
#include <cmath>
#include <cstdint>
#include <limits>

#include "predicates_filter.h"

#if defined(__FAST_MATH__)
#error "predicates.cpp must not be compiled with -ffast-math: the error bounds need IEEE arithmetic"
#endif
static_assert(std::numeric_limits<double>::is_iec559, "IEEE-754 double required");
static_assert(std::numeric_limits<double>::digits == 53, "binary64 required");
static_assert(FLT_EVAL_METHOD == 0, "extended-precision evaluation (x87) breaks the error bounds");

#if defined(__FMA__) || defined(__ARM_FEATURE_FMA) || defined(__FP_FAST_FMA)
#define UVMESH_PRED_HAVE_FMA 1
#else
#define UVMESH_PRED_HAVE_FMA 0
#endif

#if defined(__GNUC__)
#define UVMESH_PRED_INLINE inline __attribute__((always_inline))
#define UVMESH_PRED_COLD __attribute__((noinline, cold))
#else
#define UVMESH_PRED_INLINE inline
#define UVMESH_PRED_COLD
#endif

namespace uvmesh::m2d::pred {
namespace {

// The filter constants (kEps, kFloor, kO2A, kIcA) and their error analysis live in
// predicates_filter.h, next to the inline filters that use them.
using detail::kEps;
using detail::kFloor;

// --- slow-path bounds (after rescaling: no underflow, no overflow; see RangeLimits) ----
// orient2d, stage B. Tails t with |t| <= e|x| (|fl(a-b) - (a-b)| <= ulp/2 <= e|fl(a-b)|):
//   |T - B| <= (2e + e^2) S <= (2e + e^2)/(1-e)^2 detsum  <  (2 + 16e) e (1-e) detsum.
constexpr double kO2B = (2.0 + 16.0 * kEps) * kEps;
// orient2d, stage C. C = B + F~, F = first-order tail terms, F~ its double evaluation
// (3 roundings per monomial): |T - B - F| <= e^2 S, |F - F~| <= gamma_3 * 2e S, so
//   |T - C| <= 7.0001 e^2 S <= 7.001 e^2 detsum < 8 e^2 (1-e) detsum.
constexpr double kO2C = 8.0 * kEps * kEps;
// incircle, stage B: |T - B| <= ((1+e)^4 - 1) P <= (4e + 7e^2)(1 + 7.01e) Pc
//   < (4 + 64e) e (1-e) Pc.
constexpr double kIcB = (4.0 + 64.0 * kEps) * kEps;
// incircle, stage C: second and higher order |T - B - F| <= ((1+e)^4 - 1 - 4e) P
// <= 6.01 e^2 P; F~ uses at most 9 roundings per first-order monomial whose absolute
// sum is <= 4e P: |F - F~| <= gamma_9 4e P <= 36.01 e^2 P. Total <= 42.02 e^2 (1+7.01e) Pc
//   < 48 e^2 (1-e) Pc.
constexpr double kIcC = 48.0 * kEps * kEps;

// --- dynamic range handled without rescaling -------------------------------------------
// Let u be the smallest least-significant bit among the nonzero coordinates; with m the
// smallest nonzero magnitude, u >= 2^(ilogb(m) - 52). Every expansion component of a
// degree-k quantity is a multiple of u^k, and every nonzero double computed in stages
// B/C is at least u^k 2^(-53 j), where j counts the cancelling additions (and the bound
// constants, >= 2^-106) along its path: j <= 3 for orient2d, j <= 6 for incircle. No
// underflow anywhere (hence all error-free transforms exact and all bounds valid) needs
//   orient2d: u^2 2^-159 >= 2^-1022, which ilogb(m) >= -370 guarantees,
//   incircle: u^4 2^-318 >= 2^-1022, which ilogb(m) >= -120 guarantees.
// No overflow (including Dekker splitting, |x| < 2^996) needs
//   orient2d: ilogb(M) <= 480 (|det| < 2^(2*482+2)),
//   incircle: ilogb(M) <= 230 (permanent < 2^(4*232+4)).
// Outside these windows the points are scaled by 2^s with ilogb(M 2^s) = hi.
struct RangeLimits {
  int lo;  // required ilogb of the smallest nonzero magnitude
  int hi;  // allowed ilogb of the largest magnitude
};
constexpr RangeLimits kOrientRange{-370, 480};
constexpr RangeLimits kIncircleRange{-120, 230};

// ---------------------------------------------------------------------------------------
// Error-free transformations.
// ---------------------------------------------------------------------------------------

// Knuth's TwoSum: x = fl(a + b), y = (a + b) - x exactly. No precondition.
UVMESH_PRED_INLINE void two_sum(double a, double b, double& x, double& y) {
  const double s = a + b;
  const double bv = s - a;
  const double av = s - bv;
  y = (a - av) + (b - bv);
  x = s;
}

// x = fl(a - b), y = (a - b) - x exactly.
UVMESH_PRED_INLINE void two_diff(double a, double b, double& x, double& y) {
  two_sum(a, -b, x, y);
}

// x = fl(a * b), y = a*b - x exactly (needs no underflow of the error term and, without
// FMA, |a|, |b| < 2^996 for the split).
#if UVMESH_PRED_HAVE_FMA
UVMESH_PRED_INLINE void two_product(double a, double b, double& x, double& y) {
  const double p = a * b;
  y = std::fma(a, b, -p);
  x = p;
}
#else
// Veltkamp/Dekker split: a = hi + lo with hi, lo of at most 26 significant bits each.
constexpr double kSplitter = 0x1p27 + 1.0;
UVMESH_PRED_INLINE void split(double a, double& hi, double& lo) {
  const double c = kSplitter * a;
  const double big = c - a;
  hi = c - big;
  lo = a - hi;
}
UVMESH_PRED_INLINE void two_product(double a, double b, double& x, double& y) {
  const double p = a * b;
  double ah, al, bh, bl;
  split(a, ah, al);
  split(b, bh, bl);
  // Dekker: every operation below is exact.
  y = (((ah * bh - p) + ah * bl) + al * bh) + al * bl;
  x = p;
}
#endif

// ---------------------------------------------------------------------------------------
// Expansion arithmetic with zero elimination. Outputs never alias inputs, except for
// compress, which works in place.
// ---------------------------------------------------------------------------------------

// h = e + b (Grow-Expansion). |h| <= elen + 1.
int grow(int elen, const double* e, double b, double* h) {
  int n = 0;
  double q = b;
  for (int i = 0; i < elen; ++i) {
    double s, t;
    two_sum(q, e[i], s, t);
    if (t != 0.0) h[n++] = t;
    q = s;
  }
  if (q != 0.0) h[n++] = q;
  return n;
}

// h = e + f: merge both by magnitude, then one TwoSum chain (Fast-Expansion-Sum; with
// round-to-even the output is nonoverlapping). TwoSum is used where FastTwoSum would do:
// it yields the same values and needs no magnitude precondition. |h| <= elen + flen.
int sum(int elen, const double* e, int flen, const double* f, double* h) {
  if (elen == 0 || flen == 0) {
    const double* src = elen == 0 ? f : e;
    const int len = elen == 0 ? flen : elen;
    for (int i = 0; i < len; ++i) h[i] = src[i];
    return len;
  }
  // Merge by magnitude on the fly: g is the next smallest component of e and f.
  int i = 0;
  int j = 0;
  int n = 0;
  double q;
  if (std::fabs(e[0]) < std::fabs(f[0])) {
    q = e[i++];
  } else {
    q = f[j++];
  }
  while (i < elen && j < flen) {
    double g;
    if (std::fabs(e[i]) < std::fabs(f[j])) {
      g = e[i++];
    } else {
      g = f[j++];
    }
    double s, t;
    two_sum(q, g, s, t);
    if (t != 0.0) h[n++] = t;
    q = s;
  }
  while (i < elen) {
    double s, t;
    two_sum(q, e[i++], s, t);
    if (t != 0.0) h[n++] = t;
    q = s;
  }
  while (j < flen) {
    double s, t;
    two_sum(q, f[j++], s, t);
    if (t != 0.0) h[n++] = t;
    q = s;
  }
  if (q != 0.0) h[n++] = q;
  return n;
}

// h = e * b (Scale-Expansion). |h| <= 2 elen.
int scale(int elen, const double* e, double b, double* h) {
  if (elen == 0 || b == 0.0) return 0;
  int n = 0;
  double q, t;
  two_product(e[0], b, q, t);
  if (t != 0.0) h[n++] = t;
  for (int i = 1; i < elen; ++i) {
    double p1, p0;
    two_product(e[i], b, p1, p0);
    double s;
    two_sum(q, p0, s, t);
    if (t != 0.0) h[n++] = t;
    two_sum(p1, s, q, t);
    if (t != 0.0) h[n++] = t;
  }
  if (q != 0.0) h[n++] = q;
  return n;
}

// Renormalization (Shewchuk's Compress): a sweep of error-free additions from the largest
// component down, emitting a component whenever the running sum has a nonzero error,
// then a sweep back up. The value is unchanged, the output is nonoverlapping, and it is
// usually much shorter than the input, which keeps later sums and products cheap.
// h may be e (in place); h needs elen entries.
int compress(int elen, const double* e, double* h) {
  if (elen == 0) return 0;
  int bottom = elen - 1;
  double q = e[elen - 1];
  for (int i = elen - 2; i >= 0; --i) {
    double s, t;
    two_sum(q, e[i], s, t);
    if (t != 0.0) {
      h[bottom--] = s;
      q = t;
    } else {
      q = s;
    }
  }
  h[bottom] = q;
  int n = 0;
  q = h[bottom];
  for (int i = bottom + 1; i < elen; ++i) {
    double s, t;
    two_sum(h[i], q, s, t);
    if (t != 0.0) h[n++] = t;  // n <= i - bottom - 1 < i: never overwrites unread input
    q = s;
  }
  if (q != 0.0) h[n++] = q;
  return n;
}

// h = e * f, as the sum over j of e * f_j, renormalized after every step. h needs
// 2 elen flen entries, acc as many, part 2 elen.
int mul(int elen, const double* e, int flen, const double* f, double* h, double* acc,
        double* part) {
  int n = 0;
  for (int j = 0; j < flen; ++j) {
    const int plen = scale(elen, e, f[j], part);
    const int alen = sum(n, h, plen, part, acc);
    n = compress(alen, acc, h);
  }
  return n;
}

void negate(int n, double* h) {
  for (int i = 0; i < n; ++i) h[i] = -h[i];
}

// The exact difference a - b as an expansion of at most two components.
int diff_expansion(double a, double b, double* h) {
  double x, y;
  two_diff(a, b, x, y);
  int n = 0;
  if (y != 0.0) h[n++] = y;
  if (x != 0.0) h[n++] = x;
  return n;
}

// (a1 + a0) - (b1 + b0) for two TwoProduct results; at most 4 components. Two unrolled
// Grow-Expansion steps (subtracting b0, then b1), zeros removed at the end.
int two_two_diff(double a1, double a0, double b1, double b0, double* h) {
  double x0, i, j, k;
  two_sum(a0, -b0, i, x0);
  two_sum(a1, i, j, k);  // (a1 + a0) - b0 = j + k + x0
  double x1, x2, x3, i2;
  two_sum(k, -b1, i2, x1);
  two_sum(j, i2, x3, x2);  // ... - b1 = x3 + x2 + x1 + x0
  int n = 0;
  if (x0 != 0.0) h[n++] = x0;
  if (x1 != 0.0) h[n++] = x1;
  if (x2 != 0.0) h[n++] = x2;
  if (x3 != 0.0) h[n++] = x3;
  return n;
}

// A double with the sign of the expansion and approximately its value.
double approx(int n, const double* h) {
  if (n == 0) return 0.0;
  double s = 0.0;
  for (int i = 0; i < n; ++i) s += h[i];
  const double top = h[n - 1];
  // Summation from the small end is accurate, but guard the sign explicitly.
  if (s == 0.0 || (s > 0.0) != (top > 0.0)) return top;
  return s;
}

// Exactly decides |h| > bound (bound >= 0): the sign of h - sign(h) bound.
bool exceeds(int n, const double* h, double bound, double* scratch) {
  if (n == 0) return false;
  const bool pos = h[n - 1] > 0.0;
  const int m = grow(n, h, pos ? -bound : bound, scratch);
  return m > 0 && ((scratch[m - 1] > 0.0) == pos);
}

// ---------------------------------------------------------------------------------------
// Rescaling by exact powers of two.
// ---------------------------------------------------------------------------------------

// 2^k for k in [-1022, 1023].
constexpr double pow2(int k) {
  return std::bit_cast<double>(static_cast<std::uint64_t>(k + 1023) << 52);
}

// Multiplies v[0..n) by 2^s, exactly as long as no result leaves the normal range.
void scale_pow2(double* v, int n, int s) {
  if (s == 0) return;
  const int s1 = s / 2;
  const int s2 = s - s1;  // |s1|, |s2| <= 1023 for |s| <= 2046
  const double f1 = pow2(s1);
  const double f2 = pow2(s2);
  for (int i = 0; i < n; ++i) v[i] = (v[i] * f1) * f2;
}

enum class Range { kOk, kScale, kWide, kAllZero, kNonFinite };

// Decides whether the N coordinates v satisfy the no-underflow/no-overflow window of
// `lim` (see RangeLimits); otherwise sets the shift s that puts ilogb(max) at lim.hi, or
// reports that no shift can satisfy both ends of the window.
template <int N>
Range check_range(const double* v, RangeLimits lim, int& shift) {
  double big = 0.0;
  double small = std::numeric_limits<double>::infinity();
  double nonfinite = 0.0;  // x - x is 0 for finite x, NaN for inf and NaN
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC unroll 8
#endif
  for (int i = 0; i < N; ++i) {
    const double a = std::fabs(v[i]);
    nonfinite += v[i] - v[i];
    big = a > big ? a : big;
    const double a_or_inf = a != 0.0 ? a : std::numeric_limits<double>::infinity();
    small = a_or_inf < small ? a_or_inf : small;
  }
  shift = 0;
  if (nonfinite != 0.0) return Range::kNonFinite;
  if (big == 0.0) return Range::kAllZero;
  // ilogb(big) <= hi  <=>  big < 2^(hi+1);  ilogb(small) >= lo  <=>  small >= 2^lo.
  if (big < pow2(lim.hi + 1) && small >= pow2(lim.lo)) return Range::kOk;
  shift = lim.hi - std::ilogb(big);
  // Too wide a spread for any power-of-two scaling: exact integer fallback.
  if (std::ilogb(small) + shift < lim.lo) return Range::kWide;
  return Range::kScale;
}

// Undoes a scaling of the determinant by 2^(degree * shift) on the returned value,
// keeping the sign even if the magnitude underflows.
double unscale(double r, int exponent) {
  if (r == 0.0 || exponent == 0) return r;
  const double v = std::ldexp(r, exponent);
  if (v == 0.0) return std::copysign(std::numeric_limits<double>::denorm_min(), r);
  return v;
}

// ---------------------------------------------------------------------------------------
// Exact integer fallback for extreme dynamic range (e.g. 5e-324 and 3.0 in one call):
// the exact determinant may need bits far below 2^-1074, which no expansion of doubles
// can hold. Every coordinate is an integer times 2^e0 (e0 = the smallest exponent of a
// mantissa LSB), so the determinant is an integer times 2^(degree e0), computed here
// with fixed-capacity sign-magnitude integers (32-bit limbs, no allocation). Bit bounds:
// coordinates <= 2098 bits (mantissa LSBs span 2^-1074 .. 2^971, plus 53 bits), their
// differences <= 2099 (66 limbs), degree-2 products and their sums <= 4200 (132 limbs),
// degree-4 terms and their sum <= 8402 (263 limbs). Capacities below exceed these.
// ---------------------------------------------------------------------------------------
template <int Cap>
struct Wide {
  std::uint32_t limb[Cap];
  int n = 0;  // limbs in use, the top one nonzero
  bool neg = false;
};

// Exponent of the least significant mantissa bit of x != 0: x = m 2^lsb_exponent(x).
int lsb_exponent(double x) {
  int k = 0;
  (void)std::frexp(x, &k);
  return k - 53;
}

template <int Cap>
void wide_set(double x, int e0, Wide<Cap>& r) {
  r.n = 0;
  r.neg = x < 0.0;
  if (x == 0.0) {
    r.neg = false;
    return;
  }
  int k = 0;
  const double f = std::frexp(std::fabs(x), &k);
  const auto m = static_cast<std::uint64_t>(std::ldexp(f, 53));  // exact, < 2^53
  const int shift = k - 53 - e0;                                 // >= 0
  const int words = shift / 32;
  const int bits = shift % 32;
  const std::uint64_t low = m << bits;
  const std::uint64_t high = bits == 0 ? 0 : (m >> (64 - bits));
  for (int i = 0; i < words; ++i) r.limb[i] = 0;
  r.limb[words] = static_cast<std::uint32_t>(low);
  r.limb[words + 1] = static_cast<std::uint32_t>(low >> 32);
  r.limb[words + 2] = static_cast<std::uint32_t>(high);
  r.n = words + 3;
  while (r.n > 0 && r.limb[r.n - 1] == 0) --r.n;
}

template <int CA, int CB>
int wide_cmp_mag(const Wide<CA>& a, const Wide<CB>& b) {
  if (a.n != b.n) return a.n < b.n ? -1 : 1;
  for (int i = a.n - 1; i >= 0; --i) {
    if (a.limb[i] != b.limb[i]) return a.limb[i] < b.limb[i] ? -1 : 1;
  }
  return 0;
}

// r = a + (negate_b ? -b : b).
template <int CA, int CB, int CR>
void wide_add(const Wide<CA>& a, const Wide<CB>& b, bool negate_b, Wide<CR>& r) {
  // Capacities are chosen from the bit bounds (see above), which leave room for the carry.
  static_assert(CR >= CA && CR >= CB, "capacity");
  const bool bneg = negate_b ? !b.neg : b.neg;
  if (b.n == 0 || a.n == 0) {
    const bool use_a = b.n == 0;
    const int n = use_a ? a.n : b.n;
    for (int i = 0; i < n; ++i) r.limb[i] = use_a ? a.limb[i] : b.limb[i];
    r.n = n;
    r.neg = n != 0 && (use_a ? a.neg : bneg);
    return;
  }
  if (a.neg == bneg) {
    const int n = a.n > b.n ? a.n : b.n;
    std::uint64_t carry = 0;
    for (int i = 0; i < n; ++i) {
      const std::uint64_t t = carry + (i < a.n ? a.limb[i] : 0u) + (i < b.n ? b.limb[i] : 0u);
      r.limb[i] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    r.n = n;
    if (carry != 0) r.limb[r.n++] = static_cast<std::uint32_t>(carry);
    r.neg = a.neg;
    return;
  }
  // Opposite signs: subtract the smaller magnitude from the larger.
  const int c = wide_cmp_mag(a, b);
  if (c == 0) {
    r.n = 0;
    r.neg = false;
    return;
  }
  const bool a_big = c > 0;
  const std::uint32_t* big = a_big ? a.limb : b.limb;
  const std::uint32_t* small = a_big ? b.limb : a.limb;
  const int nbig = a_big ? a.n : b.n;
  const int nsmall = a_big ? b.n : a.n;
  std::int64_t borrow = 0;
  for (int i = 0; i < nbig; ++i) {
    std::int64_t t = static_cast<std::int64_t>(big[i]) - (i < nsmall ? small[i] : 0u) - borrow;
    borrow = t < 0 ? 1 : 0;
    if (t < 0) t += std::int64_t{1} << 32;
    r.limb[i] = static_cast<std::uint32_t>(t);
  }
  r.n = nbig;
  while (r.n > 0 && r.limb[r.n - 1] == 0) --r.n;
  r.neg = a_big ? a.neg : bneg;
}

template <int CA, int CB, int CR>
void wide_mul(const Wide<CA>& a, const Wide<CB>& b, Wide<CR>& r) {
  static_assert(CR >= CA + CB, "capacity");
  r.n = 0;
  r.neg = false;
  if (a.n == 0 || b.n == 0) return;
  const int n = a.n + b.n;
  for (int i = 0; i < n; ++i) r.limb[i] = 0;
  for (int i = 0; i < a.n; ++i) {
    std::uint64_t carry = 0;
    for (int j = 0; j < b.n; ++j) {
      const std::uint64_t t =
          static_cast<std::uint64_t>(a.limb[i]) * b.limb[j] + r.limb[i + j] + carry;
      r.limb[i + j] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    r.limb[i + b.n] = static_cast<std::uint32_t>(carry);
  }
  r.n = n;
  while (r.n > 0 && r.limb[r.n - 1] == 0) --r.n;
  r.neg = a.neg != b.neg;
}

// Approximately a * 2^exponent, with the exact sign (clamped to +-denorm_min).
template <int Cap>
double wide_value(const Wide<Cap>& a, int exponent) {
  if (a.n == 0) return 0.0;
  double v = 0.0;
  const int lo = a.n >= 3 ? a.n - 3 : 0;
  for (int i = a.n - 1; i >= lo; --i) v = v * 4294967296.0 + a.limb[i];
  v = std::ldexp(v, exponent + 32 * lo);
  if (v == 0.0) v = std::numeric_limits<double>::denorm_min();
  return a.neg ? -v : v;
}

int smallest_lsb_exponent(const double* v, int n) {
  int e0 = std::numeric_limits<int>::max();
  for (int i = 0; i < n; ++i) {
    if (v[i] != 0.0) {
      const int e = lsb_exponent(v[i]);
      e0 = e < e0 ? e : e0;
    }
  }
  return e0;
}

using WideLin = Wide<68>;     // coordinates and differences
using WideQuad = Wide<136>;   // degree 2
using WideQuart = Wide<272>;  // degree 4

UVMESH_PRED_COLD double orient2d_wide(const double* p) {
  const int e0 = smallest_lsb_exponent(p, 6);
  WideLin c[6];
  for (int i = 0; i < 6; ++i) wide_set(p[i], e0, c[i]);
  WideLin acx, acy, bcx, bcy;
  wide_add(c[0], c[4], true, acx);
  wide_add(c[1], c[5], true, acy);
  wide_add(c[2], c[4], true, bcx);
  wide_add(c[3], c[5], true, bcy);
  WideQuad l, r, det;
  wide_mul(acx, bcy, l);
  wide_mul(acy, bcx, r);
  wide_add(l, r, true, det);
  return wide_value(det, 2 * e0);
}

UVMESH_PRED_COLD double incircle_wide(const double* p) {
  const int e0 = smallest_lsb_exponent(p, 8);
  WideLin c[8];
  for (int i = 0; i < 8; ++i) wide_set(p[i], e0, c[i]);
  WideLin d[6];  // adx, ady, bdx, bdy, cdx, cdy
  for (int i = 0; i < 6; ++i) wide_add(c[i], c[6 + (i % 2)], true, d[i]);
  const WideLin &adx = d[0], &ady = d[1], &bdx = d[2], &bdy = d[3], &cdx = d[4], &cdy = d[5];
  // Sum over the three rows of lift(p) * (q_x r_y - r_x q_y).
  const WideLin* rows[3][6] = {{&adx, &ady, &bdx, &cdy, &cdx, &bdy},
                               {&bdx, &bdy, &cdx, &ady, &adx, &cdy},
                               {&cdx, &cdy, &adx, &bdy, &bdx, &ady}};
  WideQuart sum[2], term;  // running sum, ping-ponged between sum[0] and sum[1]
  int cur = 0;
  for (const auto& t : rows) {
    WideQuad sx, sy, u, v, lift, cross;
    wide_mul(*t[0], *t[0], sx);
    wide_mul(*t[1], *t[1], sy);
    wide_add(sx, sy, false, lift);
    wide_mul(*t[2], *t[3], u);
    wide_mul(*t[4], *t[5], v);
    wide_add(u, v, true, cross);
    wide_mul(lift, cross, term);
    wide_add(sum[cur], term, false, sum[1 - cur]);
    cur = 1 - cur;
  }
  return wide_value(sum[cur], 4 * e0);
}

// ---------------------------------------------------------------------------------------
// orient2d slow path.
// ---------------------------------------------------------------------------------------

// Stage D: exact from two-component differences.
double orient2d_exact(const double* p) {
  const double ax = p[0], ay = p[1], bx = p[2], by = p[3], cx = p[4], cy = p[5];
  double acx[2], acy[2], bcx[2], bcy[2];
  const int nacx = diff_expansion(ax, cx, acx);
  const int nacy = diff_expansion(ay, cy, acy);
  const int nbcx = diff_expansion(bx, cx, bcx);
  const int nbcy = diff_expansion(by, cy, bcy);
  double left[8], right[8], acc[8], part[4];
  const int nl = mul(nacx, acx, nbcy, bcy, left, acc, part);
  const int nr = mul(nacy, acy, nbcx, bcx, right, acc, part);
  negate(nr, right);
  double det[16];
  const int nd = sum(nl, left, nr, right, det);
  return approx(nd, det);
}

// Stages B, C, D on coordinates known to be in the safe range.
double orient2d_stages(const double* p) {
  const double ax = p[0], ay = p[1], bx = p[2], by = p[3], cx = p[4], cy = p[5];
  double acx, acxt, acy, acyt, bcx, bcxt, bcy, bcyt;
  two_diff(ax, cx, acx, acxt);
  two_diff(ay, cy, acy, acyt);
  two_diff(bx, cx, bcx, bcxt);
  two_diff(by, cy, bcy, bcyt);

  // Stage B.
  double l1, l0, r1, r0;
  two_product(acx, bcy, l1, l0);
  two_product(acy, bcx, r1, r0);
  double b[4];
  const int nb = two_two_diff(l1, l0, r1, r0, b);
  if (acxt == 0.0 && acyt == 0.0 && bcxt == 0.0 && bcyt == 0.0) return approx(nb, b);
  const double detsum = std::fabs(l1) + std::fabs(r1);
  double scratch[6];
  if (exceeds(nb, b, kO2B * detsum, scratch)) return approx(nb, b);

  // Stage C.
  const double f = (acx * bcyt - acy * bcxt) + (acxt * bcy - acyt * bcx);
  double c[5];
  const int nc = grow(nb, b, f, c);
  if (exceeds(nc, c, kO2C * detsum, scratch)) return approx(nc, c);

  // Stage D.
  return orient2d_exact(p);
}

UVMESH_PRED_COLD double orient2d_slow_impl(const double* pa, const double* pb, const double* pc) {
  double p[6] = {pa[0], pa[1], pb[0], pb[1], pc[0], pc[1]};
  int shift = 0;
  switch (check_range<6>(p, kOrientRange, shift)) {
    case Range::kAllZero:
      return 0.0;
    case Range::kNonFinite:
      return orient2d_fast(pa, pb, pc);
    case Range::kOk:
      return orient2d_stages(p);
    case Range::kWide:
      return orient2d_wide(p);
    case Range::kScale:
      break;
  }
  scale_pow2(p, 6, shift);
  return unscale(orient2d_stages(p), -2 * shift);
}

// ---------------------------------------------------------------------------------------
// incircle slow path.
// ---------------------------------------------------------------------------------------

// lift * cross for one of the three terms, all as expansions: at most 512 components.
int lifted_term(const double* dx, int ndx, const double* dy, int ndy, const double* cross,
                int ncross, double* out, double* acc, double* part) {
  double sx[8], sy[8], lift[16];
  const int nsx = mul(ndx, dx, ndx, dx, sx, acc, part);
  const int nsy = mul(ndy, dy, ndy, dy, sy, acc, part);
  const int nlift = compress(sum(nsx, sx, nsy, sy, lift), lift, lift);
  return mul(ncross, cross, nlift, lift, out, acc, part);
}

// (x1 y2 - x2 y1) with two-component factors: at most 16 components.
int cross_exact(const double* x1, int nx1, const double* y2, int ny2, const double* x2, int nx2,
                const double* y1, int ny1, double* out, double* acc, double* part) {
  double u[8], v[8];
  const int nu = mul(nx1, x1, ny2, y2, u, acc, part);
  const int nv = mul(nx2, x2, ny1, y1, v, acc, part);
  negate(nv, v);
  return compress(sum(nu, u, nv, v, out), out, out);
}

// Stage D: exact from two-component differences.
double incircle_exact(const double* p) {
  double adx[2], ady[2], bdx[2], bdy[2], cdx[2], cdy[2];
  const int nadx = diff_expansion(p[0], p[6], adx);
  const int nady = diff_expansion(p[1], p[7], ady);
  const int nbdx = diff_expansion(p[2], p[6], bdx);
  const int nbdy = diff_expansion(p[3], p[7], bdy);
  const int ncdx = diff_expansion(p[4], p[6], cdx);
  const int ncdy = diff_expansion(p[5], p[7], cdy);

  double acc[512], part[32];
  double bc[16], ca[16], ab[16];
  const int nbc = cross_exact(bdx, nbdx, cdy, ncdy, cdx, ncdx, bdy, nbdy, bc, acc, part);
  const int nca = cross_exact(cdx, ncdx, ady, nady, adx, nadx, cdy, ncdy, ca, acc, part);
  const int nab = cross_exact(adx, nadx, bdy, nbdy, bdx, nbdx, ady, nady, ab, acc, part);

  double t1[512], t2[512], s12[1024], fin[1536];
  const int n1 = lifted_term(adx, nadx, ady, nady, bc, nbc, t1, acc, part);
  const int n2 = lifted_term(bdx, nbdx, bdy, nbdy, ca, nca, t2, acc, part);
  const int n12 = compress(sum(n1, t1, n2, t2, s12), s12, s12);
  const int n3 = lifted_term(cdx, ncdx, cdy, ncdy, ab, nab, t1, acc, part);
  const int nfin = sum(n12, s12, n3, t1, fin);
  return approx(nfin, fin);
}

// (x^2 + y^2) * cross for a 4-component cross and single-double x, y: <= 32 components.
int lift_scale(const double* cross, int ncross, double x, double y, double* out) {
  double t8[8], xx[16], yy[16];
  int n = scale(ncross, cross, x, t8);
  const int nxx = scale(n, t8, x, xx);
  n = scale(ncross, cross, y, t8);
  const int nyy = scale(n, t8, y, yy);
  return sum(nxx, xx, nyy, yy, out);
}

double incircle_stages(const double* p) {
  const double dx = p[6], dy = p[7];
  double adx, adxt, ady, adyt, bdx, bdxt, bdy, bdyt, cdx, cdxt, cdy, cdyt;
  two_diff(p[0], dx, adx, adxt);
  two_diff(p[1], dy, ady, adyt);
  two_diff(p[2], dx, bdx, bdxt);
  two_diff(p[3], dy, bdy, bdyt);
  two_diff(p[4], dx, cdx, cdxt);
  two_diff(p[5], dy, cdy, cdyt);

  // Stage B: exact determinant of the rounded differences.
  double h1, h0, g1, g0;
  double bc[4], ca[4], ab[4];
  two_product(bdx, cdy, h1, h0);
  two_product(cdx, bdy, g1, g0);
  const int nbc = two_two_diff(h1, h0, g1, g0, bc);
  const double bdxcdy = h1, cdxbdy = g1;
  two_product(cdx, ady, h1, h0);
  two_product(adx, cdy, g1, g0);
  const int nca = two_two_diff(h1, h0, g1, g0, ca);
  const double cdxady = h1, adxcdy = g1;
  two_product(adx, bdy, h1, h0);
  two_product(bdx, ady, g1, g0);
  const int nab = two_two_diff(h1, h0, g1, g0, ab);
  const double adxbdy = h1, bdxady = g1;

  double adet[32], bdet[32], cdet[32], abdet[64], fin[96];
  const int na = lift_scale(bc, nbc, adx, ady, adet);
  const int nb = lift_scale(ca, nca, bdx, bdy, bdet);
  const int nc = lift_scale(ab, nab, cdx, cdy, cdet);
  const int nabd = sum(na, adet, nb, bdet, abdet);
  const int nfin = sum(nabd, abdet, nc, cdet, fin);

  if (adxt == 0.0 && adyt == 0.0 && bdxt == 0.0 && bdyt == 0.0 && cdxt == 0.0 && cdyt == 0.0) {
    return approx(nfin, fin);
  }

  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * alift +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * blift +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * clift;
  double scratch[98];
  if (exceeds(nfin, fin, kIcB * permanent, scratch)) return approx(nfin, fin);

  // Stage C: first-order tail correction (derivative of the determinant along the tails).
  const double bcd = bdxcdy - cdxbdy;
  const double cad = cdxady - adxcdy;
  const double abd = adxbdy - bdxady;
  const double ta = 2.0 * (adx * adxt + ady * adyt) * bcd +
                    alift * ((bdx * cdyt + bdxt * cdy) - (cdx * bdyt + cdxt * bdy));
  const double tb = 2.0 * (bdx * bdxt + bdy * bdyt) * cad +
                    blift * ((cdx * adyt + cdxt * ady) - (adx * cdyt + adxt * cdy));
  const double tc = 2.0 * (cdx * cdxt + cdy * cdyt) * abd +
                    clift * ((adx * bdyt + adxt * bdy) - (bdx * adyt + bdxt * ady));
  const double f = (ta + tb) + tc;
  double c[97];
  const int ncc = grow(nfin, fin, f, c);
  if (exceeds(ncc, c, kIcC * permanent, scratch)) return approx(ncc, c);

  // Stage D.
  return incircle_exact(p);
}

UVMESH_PRED_COLD double incircle_slow_impl(const double* pa, const double* pb, const double* pc,
                                           const double* pd) {
  double p[8] = {pa[0], pa[1], pb[0], pb[1], pc[0], pc[1], pd[0], pd[1]};
  int shift = 0;
  switch (check_range<8>(p, kIncircleRange, shift)) {
    case Range::kAllZero:
      return 0.0;
    case Range::kNonFinite:
      return incircle_fast(pa, pb, pc, pd);
    case Range::kOk:
      return incircle_stages(p);
    case Range::kWide:
      return incircle_wide(p);
    case Range::kScale:
      break;
  }
  scale_pow2(p, 8, shift);
  return unscale(incircle_stages(p), -4 * shift);
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Public entry points: the filters. Keep these small; the slow paths are out of line.
// ---------------------------------------------------------------------------------------

namespace detail {
double orient2d_slow(const double* a, const double* b, const double* c) {
  return orient2d_slow_impl(a, b, c);
}
double incircle_slow(const double* a, const double* b, const double* c, const double* d) {
  return incircle_slow_impl(a, b, c, d);
}
}  // namespace detail

double orient2d(const double* a, const double* b, const double* c) {
  return detail::orient2d_filtered(a, b, c);
}

double incircle(const double* a, const double* b, const double* c, const double* d) {
  return detail::incircle_filtered(a, b, c, d);
}

double orient2d_fast(const double* a, const double* b, const double* c) {
  const double acx = a[0] - c[0];
  const double bcx = b[0] - c[0];
  const double acy = a[1] - c[1];
  const double bcy = b[1] - c[1];
  return acx * bcy - acy * bcx;
}

double incircle_fast(const double* a, const double* b, const double* c, const double* d) {
  const double adx = a[0] - d[0];
  const double ady = a[1] - d[1];
  const double bdx = b[0] - d[0];
  const double bdy = b[1] - d[1];
  const double cdx = c[0] - d[0];
  const double cdy = c[1] - d[1];
  const double alift = adx * adx + ady * ady;
  const double blift = bdx * bdx + bdy * bdy;
  const double clift = cdx * cdx + cdy * cdy;
  return alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
         clift * (adx * bdy - bdx * ady);
}

}  // namespace uvmesh::m2d::pred
