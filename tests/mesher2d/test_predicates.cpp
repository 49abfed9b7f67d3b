// Tests for the exact predicates (mesher2d/include/uvmesh/mesher2d/predicates.h).
//
// Every sign is compared against an independent exact reference: each double is written
// as an integer mantissa times 2^k, all coordinates of one call are brought to the
// smallest exponent, and the determinant is evaluated with a small arbitrary-precision
// integer type defined here (BigInt). No floating-point arithmetic enters the reference.
#include <uvmesh/mesher2d/predicates.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

namespace {

namespace pred = uvmesh::m2d::pred;
__extension__ typedef __int128 Int128;

// ---------------------------------------------------------------------------------------
// Minimal signed big integer: sign and magnitude in base 2^32, little endian.
// ---------------------------------------------------------------------------------------
class BigInt {
 public:
  BigInt() = default;
  explicit BigInt(std::int64_t v) {
    neg_ = v < 0;
    std::uint64_t m = neg_ ? 0 - static_cast<std::uint64_t>(v) : static_cast<std::uint64_t>(v);
    while (m != 0) {
      mag_.push_back(static_cast<std::uint32_t>(m));
      m >>= 32;
    }
    if (mag_.empty()) neg_ = false;
  }

  // |v| * 2^shift with sign, shift >= 0, |v| < 2^63.
  static BigInt shifted(std::int64_t v, int shift) {
    BigInt r(v);
    if (r.mag_.empty()) return r;
    const int words = shift / 32;
    const int bits = shift % 32;
    std::vector<std::uint32_t> out(static_cast<std::size_t>(words), 0u);
    std::uint32_t carry = 0;
    for (std::uint32_t w : r.mag_) {
      if (bits == 0) {
        out.push_back(w);
      } else {
        out.push_back((w << bits) | carry);
        carry = w >> (32 - bits);
      }
    }
    if (carry != 0) out.push_back(carry);
    r.mag_ = std::move(out);
    return r;
  }

  int sign() const { return mag_.empty() ? 0 : (neg_ ? -1 : 1); }

  // Approximate value (top 64 bits), for magnitude checks only.
  double approx() const {
    if (mag_.empty()) return 0.0;
    double v = 0.0;
    const std::size_t n = mag_.size();
    const std::size_t lo = n >= 3 ? n - 3 : 0;
    for (std::size_t i = n; i-- > lo;) v = v * 4294967296.0 + mag_[i];
    v = std::ldexp(v, static_cast<int>(32 * lo));
    return neg_ ? -v : v;
  }

  friend BigInt operator-(BigInt a) {
    if (!a.mag_.empty()) a.neg_ = !a.neg_;
    return a;
  }
  friend BigInt operator+(const BigInt& a, const BigInt& b) {
    if (a.neg_ == b.neg_) return make(add_mag(a.mag_, b.mag_), a.neg_);
    const int c = cmp_mag(a.mag_, b.mag_);
    if (c == 0) return BigInt();
    if (c > 0) return make(sub_mag(a.mag_, b.mag_), a.neg_);
    return make(sub_mag(b.mag_, a.mag_), b.neg_);
  }
  friend BigInt operator-(const BigInt& a, const BigInt& b) { return a + (-b); }
  friend BigInt operator*(const BigInt& a, const BigInt& b) {
    if (a.mag_.empty() || b.mag_.empty()) return BigInt();
    std::vector<std::uint32_t> r(a.mag_.size() + b.mag_.size(), 0u);
    for (std::size_t i = 0; i < a.mag_.size(); ++i) {
      std::uint64_t carry = 0;
      for (std::size_t j = 0; j < b.mag_.size(); ++j) {
        const std::uint64_t t =
            static_cast<std::uint64_t>(a.mag_[i]) * b.mag_[j] + r[i + j] + carry;
        r[i + j] = static_cast<std::uint32_t>(t);
        carry = t >> 32;
      }
      std::size_t k = i + b.mag_.size();
      while (carry != 0) {
        const std::uint64_t t = static_cast<std::uint64_t>(r[k]) + carry;
        r[k] = static_cast<std::uint32_t>(t);
        carry = t >> 32;
        ++k;
      }
    }
    return make(std::move(r), a.neg_ != b.neg_);
  }

 private:
  static BigInt make(std::vector<std::uint32_t> m, bool neg) {
    while (!m.empty() && m.back() == 0) m.pop_back();
    BigInt r;
    r.mag_ = std::move(m);
    r.neg_ = !r.mag_.empty() && neg;
    return r;
  }
  static int cmp_mag(const std::vector<std::uint32_t>& a, const std::vector<std::uint32_t>& b) {
    if (a.size() != b.size()) return a.size() < b.size() ? -1 : 1;
    for (std::size_t i = a.size(); i-- > 0;) {
      if (a[i] != b[i]) return a[i] < b[i] ? -1 : 1;
    }
    return 0;
  }
  static std::vector<std::uint32_t> add_mag(const std::vector<std::uint32_t>& a,
                                            const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> r(std::max(a.size(), b.size()) + 1, 0u);
    std::uint64_t carry = 0;
    for (std::size_t i = 0; i < r.size(); ++i) {
      const std::uint64_t t = carry + (i < a.size() ? a[i] : 0u) + (i < b.size() ? b[i] : 0u);
      r[i] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    return r;
  }
  // |a| >= |b|
  static std::vector<std::uint32_t> sub_mag(const std::vector<std::uint32_t>& a,
                                            const std::vector<std::uint32_t>& b) {
    std::vector<std::uint32_t> r(a.size(), 0u);
    std::int64_t borrow = 0;
    for (std::size_t i = 0; i < a.size(); ++i) {
      std::int64_t t = static_cast<std::int64_t>(a[i]) - (i < b.size() ? b[i] : 0u) - borrow;
      borrow = t < 0 ? 1 : 0;
      if (t < 0) t += (std::int64_t{1} << 32);
      r[i] = static_cast<std::uint32_t>(t);
    }
    return r;
  }

  std::vector<std::uint32_t> mag_;
  bool neg_ = false;
};

// x = m * 2^e with integer m, |m| < 2^53 (exact for every finite double, subnormals too).
struct Dyadic {
  std::int64_t m = 0;
  int e = 0;
};
Dyadic decompose(double x) {
  if (x == 0.0) return {0, 0};
  int k = 0;
  const double f = std::frexp(x, &k);  // x = f 2^k, 0.5 <= |f| < 1
  return {static_cast<std::int64_t>(std::ldexp(f, 53)), k - 53};
}

// All coordinates of one call as big integers in a common unit 2^e0 (a positive factor
// that does not change any sign).
std::vector<BigInt> to_common_unit(const std::vector<double>& v) {
  std::vector<Dyadic> d;
  int e0 = std::numeric_limits<int>::max();
  for (double x : v) {
    d.push_back(decompose(x));
    if (x != 0.0) e0 = std::min(e0, d.back().e);
  }
  std::vector<BigInt> r;
  for (const Dyadic& q : d) r.push_back(q.m == 0 ? BigInt() : BigInt::shifted(q.m, q.e - e0));
  return r;
}

BigInt ref_orient_value(const double* a, const double* b, const double* c) {
  const auto v = to_common_unit({a[0], a[1], b[0], b[1], c[0], c[1]});
  const BigInt acx = v[0] - v[4], acy = v[1] - v[5], bcx = v[2] - v[4], bcy = v[3] - v[5];
  return acx * bcy - acy * bcx;
}
int ref_orient(const double* a, const double* b, const double* c) {
  return ref_orient_value(a, b, c).sign();
}

int ref_incircle(const double* a, const double* b, const double* c, const double* d) {
  const auto v = to_common_unit({a[0], a[1], b[0], b[1], c[0], c[1], d[0], d[1]});
  const BigInt adx = v[0] - v[6], ady = v[1] - v[7];
  const BigInt bdx = v[2] - v[6], bdy = v[3] - v[7];
  const BigInt cdx = v[4] - v[6], cdy = v[5] - v[7];
  const BigInt alift = adx * adx + ady * ady;
  const BigInt blift = bdx * bdx + bdy * bdy;
  const BigInt clift = cdx * cdx + cdy * cdy;
  return (alift * (bdx * cdy - cdx * bdy) + blift * (cdx * ady - adx * cdy) +
          clift * (adx * bdy - bdx * ady))
      .sign();
}

int sgn(double x) {
  return x > 0.0 ? 1 : (x < 0.0 ? -1 : 0);
}

using P2 = std::array<double, 2>;

double ulp_step(double x, int k) {
  const double dir =
      k > 0 ? std::numeric_limits<double>::infinity() : -std::numeric_limits<double>::infinity();
  for (int i = 0; i < std::abs(k); ++i) x = std::nextafter(x, dir);
  return x;
}

// Counts sign disagreements with the reference and records the first few.
struct Tally {
  long cases = 0;
  long wrong = 0;
  long fast_wrong = 0;
  std::string first;
};

void check_orient(Tally& t, const P2& a, const P2& b, const P2& c) {
  const int ref = ref_orient(a.data(), b.data(), c.data());
  const int got = sgn(pred::orient2d(a.data(), b.data(), c.data()));
  ++t.cases;
  if (got != ref) {
    if (t.wrong++ == 0) {
      char buf[256];
      std::snprintf(buf, sizeof buf,
                    "orient2d((%.17g,%.17g),(%.17g,%.17g),(%.17g,%.17g)) = %d, ref %d", a[0], a[1],
                    b[0], b[1], c[0], c[1], got, ref);
      t.first = buf;
    }
  }
  if (sgn(pred::orient2d_fast(a.data(), b.data(), c.data())) != ref) ++t.fast_wrong;
}

void check_incircle(Tally& t, const P2& a, const P2& b, const P2& c, const P2& d) {
  const int ref = ref_incircle(a.data(), b.data(), c.data(), d.data());
  const int got = sgn(pred::incircle(a.data(), b.data(), c.data(), d.data()));
  ++t.cases;
  if (got != ref) {
    if (t.wrong++ == 0) {
      char buf[320];
      std::snprintf(
          buf, sizeof buf,
          "incircle((%.17g,%.17g),(%.17g,%.17g),(%.17g,%.17g),(%.17g,%.17g)) = %d, ref %d", a[0],
          a[1], b[0], b[1], c[0], c[1], d[0], d[1], got, ref);
      t.first = buf;
    }
  }
  if (sgn(pred::incircle_fast(a.data(), b.data(), c.data(), d.data())) != ref) ++t.fast_wrong;
}

#define REQUIRE_TALLY(t)                                                                       \
  do {                                                                                         \
    INFO("cases " << (t).cases << ", wrong " << (t).wrong << ", fast wrong " << (t).fast_wrong \
                  << "; first: " << (t).first);                                                \
    CHECK((t).cases > 0);                                                                      \
    CHECK((t).wrong == 0);                                                                     \
  } while (0)

P2 lerp(const P2& a, const P2& b, double t) {
  return {a[0] + t * (b[0] - a[0]), a[1] + t * (b[1] - a[1])};
}

// Integer points on the circle x^2 + y^2 = r^2.
std::vector<std::array<long, 2>> lattice_circle(long r) {
  std::vector<std::array<long, 2>> pts;
  for (long x = -r; x <= r; ++x) {
    const long y2 = r * r - x * x;
    const long y = std::lround(std::sqrt(static_cast<double>(y2)));
    if (y * y == y2) {
      pts.push_back({x, y});
      if (y != 0) pts.push_back({x, -y});
    }
  }
  return pts;
}

}  // namespace

TEST_CASE("BigInt reference agrees with 128-bit integers on small values", "[predicates]") {
  std::mt19937_64 rng(101);
  std::uniform_int_distribution<std::int64_t> dist(-(std::int64_t{1} << 40), std::int64_t{1} << 40);
  for (int i = 0; i < 2000; ++i) {
    const std::int64_t a = dist(rng), b = dist(rng), c = dist(rng), d = dist(rng);
    const Int128 exact = static_cast<Int128>(a) * b - static_cast<Int128>(c) * d;
    const BigInt big = BigInt(a) * BigInt(b) - BigInt(c) * BigInt(d);
    const int es = exact > 0 ? 1 : (exact < 0 ? -1 : 0);
    REQUIRE(big.sign() == es);
    REQUIRE(big.approx() == Approx(static_cast<double>(exact)).epsilon(1e-15));
  }
  // Shifts: 3 * 2^100 - 3 * 2^100 == 0, 2^100 > 2^99 * 1.
  CHECK((BigInt::shifted(3, 100) - BigInt::shifted(3, 100)).sign() == 0);
  CHECK((BigInt::shifted(1, 100) - BigInt::shifted(1, 99) * BigInt(2)).sign() == 0);
  CHECK((BigInt::shifted(-5, 7) + BigInt(640)).sign() == 0);
  // Reference on a hand-computed determinant: (0,0),(1,0),(0,1) is CCW.
  const double o[2] = {0, 0}, x[2] = {1, 0}, y[2] = {0, 1};
  CHECK(ref_orient(o, x, y) == 1);
  CHECK(ref_orient(x, o, y) == -1);
  const double in[2] = {0.25, 0.25}, out[2] = {2, 2};
  CHECK(ref_incircle(o, x, y, in) == 1);
  CHECK(ref_incircle(o, x, y, out) == -1);
}

TEST_CASE("orient2d and incircle on random points", "[predicates]") {
  std::mt19937_64 rng(1);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Tally to, ti;
  for (int i = 0; i < 4000; ++i) {
    const P2 a{u(rng), u(rng)}, b{u(rng), u(rng)}, c{u(rng), u(rng)}, d{u(rng), u(rng)};
    check_orient(to, a, b, c);
    check_incircle(ti, a, b, c, d);
  }
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

TEST_CASE("orient2d on nearly collinear points", "[predicates]") {
  std::mt19937_64 rng(2);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> ut(-1.0, 2.0);
  Tally t;
  const double offsets[] = {0.0, 0.3, 1234.5, -7.0e5};  // inexact differences too
  for (int i = 0; i < 1500; ++i) {
    const double off = offsets[i % 4];
    const P2 a{off + u(rng), off + u(rng)}, b{off + u(rng), off + u(rng)};
    const P2 c0 = lerp(a, b, ut(rng));
    for (int kx = -2; kx <= 2; ++kx) {
      for (int ky = -1; ky <= 1; ++ky) {
        const P2 c{ulp_step(c0[0], kx), ulp_step(c0[1], ky)};
        check_orient(t, a, b, c);
      }
    }
  }
  REQUIRE_TALLY(t);
}

TEST_CASE("orient2d on exactly collinear integer grid points", "[predicates]") {
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> small(-1000, 1000);
  std::uniform_int_distribution<int> dir(-30, 30);
  std::uniform_int_distribution<int> step(-20, 20);
  Tally t;
  for (int i = 0; i < 3000; ++i) {
    const long ax = small(rng), ay = small(rng), dx = dir(rng), dy = dir(rng);
    const long j = step(rng), k = step(rng);
    const P2 a{double(ax), double(ay)};
    const P2 b{double(ax + j * dx), double(ay + j * dy)};
    const P2 c{double(ax + k * dx), double(ay + k * dy)};
    REQUIRE(pred::orient2d(a.data(), b.data(), c.data()) == 0.0);
    check_orient(t, a, b, c);
    // Off-line by one grid unit: value is the exact small integer determinant.
    const P2 c1{c[0] + 1.0, c[1]};
    const double exact = double((b[0] - a[0]) * (c1[1] - a[1]) - (b[1] - a[1]) * (c1[0] - a[0]));
    REQUIRE(pred::orient2d(a.data(), b.data(), c1.data()) == exact);
    check_orient(t, a, b, c1);
  }
  REQUIRE_TALLY(t);
}

TEST_CASE("incircle on cocircular lattice points", "[predicates]") {
  std::mt19937_64 rng(4);
  Tally t;
  // Circles with many lattice points (radii are products of primes 1 mod 4).
  for (long r : {5L, 25L, 65L, 325L, 1105L}) {
    const auto pts = lattice_circle(r);
    REQUIRE(pts.size() >= 12);
    std::uniform_int_distribution<std::size_t> pick(0, pts.size() - 1);
    std::uniform_int_distribution<long> ctr(-5000, 5000);
    for (int i = 0; i < 300; ++i) {
      const long cx = ctr(rng), cy = ctr(rng);
      std::array<P2, 4> q;
      std::array<std::size_t, 4> idx;
      for (int k = 0; k < 4; ++k) {
        bool fresh = false;
        while (!fresh) {
          idx[k] = pick(rng);
          fresh = std::find(idx.begin(), idx.begin() + k, idx[k]) == idx.begin() + k;
        }
        q[k] = {double(cx + pts[idx[k]][0]), double(cy + pts[idx[k]][1])};
      }
      REQUIRE(pred::incircle(q[0].data(), q[1].data(), q[2].data(), q[3].data()) == 0.0);
      check_incircle(t, q[0], q[1], q[2], q[3]);
      // Push d off the circle by one ulp in each direction.
      for (int kx = -1; kx <= 1; ++kx) {
        for (int ky = -1; ky <= 1; ++ky) {
          const P2 d{ulp_step(q[3][0], kx), ulp_step(q[3][1], ky)};
          check_incircle(t, q[0], q[1], q[2], d);
        }
      }
      // Same circle scaled to a dyadic grid and shifted by a non-integer dyadic offset.
      const double s = 0x1p-20, off = 0.375;
      std::array<P2, 4> w;
      for (int k = 0; k < 4; ++k) w[k] = {q[k][0] * s + off, q[k][1] * s - off};
      REQUIRE(pred::incircle(w[0].data(), w[1].data(), w[2].data(), w[3].data()) == 0.0);
      check_incircle(t, w[0], w[1], w[2], P2{ulp_step(w[3][0], 1), w[3][1]});
    }
  }
  REQUIRE_TALLY(t);
}

TEST_CASE("incircle on nearly cocircular points", "[predicates]") {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> ang(0.0, 6.283185307179586);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> lr(-3.0, 3.0);
  Tally t;
  for (int i = 0; i < 1500; ++i) {
    const double cx = (i % 3 == 0) ? 0.0 : u(rng) * 100.0;
    const double cy = (i % 3 == 0) ? 0.0 : u(rng) * 100.0;
    const double r = std::pow(10.0, lr(rng));
    std::array<P2, 4> q;
    for (auto& p : q) {
      const double th = ang(rng);
      p = {cx + r * std::cos(th), cy + r * std::sin(th)};
    }
    for (int kx = -1; kx <= 1; ++kx) {
      for (int ky = -1; ky <= 1; ++ky) {
        const P2 d{ulp_step(q[3][0], kx), ulp_step(q[3][1], ky)};
        check_incircle(t, q[0], q[1], q[2], d);
      }
    }
  }
  // Rectangles on a decimal grid: cocircular in the reals, rounding decides.
  for (int i = 0; i < 500; ++i) {
    const int x0 = int(u(rng) * 50), y0 = int(u(rng) * 50);
    const int w = 1 + int((u(rng) + 1.0) * 10), h = 1 + int((u(rng) + 1.0) * 10);
    const double g = 0.1;
    const P2 a{x0 * g, y0 * g}, b{(x0 + w) * g, y0 * g}, c{(x0 + w) * g, (y0 + h) * g},
        d{x0 * g, (y0 + h) * g};
    check_incircle(t, a, b, c, d);
    check_incircle(t, b, c, d, a);
  }
  REQUIRE_TALLY(t);
}

// Exactly degenerate inputs whose coordinate differences are NOT exact in doubles: the
// points lie on the line 3y = 5x through the origin at very different distances, so
// every difference loses low-order bits and only the exact stages can prove zero. Four
// collinear points are also (degenerately) cocircular: incircle is exactly zero.
TEST_CASE("degenerate inputs with inexact coordinate differences", "[predicates]") {
  std::mt19937_64 rng(11);
  std::uniform_int_distribution<std::int64_t> mant(std::int64_t{1} << 49,
                                                   (std::int64_t{1} << 50) - 1);
  std::uniform_int_distribution<int> ex(-60, 60);
  std::uniform_int_distribution<int> nudge(-2, 2);
  Tally to, ti;
  auto on_line = [&](int e) {
    const double s = std::ldexp(static_cast<double>(mant(rng)), e - 50);  // 50-bit mantissa
    return P2{3.0 * s, 5.0 * s};                                          // both exact
  };
  for (int i = 0; i < 3000; ++i) {
    const P2 a = on_line(ex(rng)), b = on_line(ex(rng)), c = on_line(ex(rng)), d = on_line(ex(rng));
    REQUIRE(pred::orient2d(a.data(), b.data(), c.data()) == 0.0);
    REQUIRE(pred::incircle(a.data(), b.data(), c.data(), d.data()) == 0.0);
    check_orient(to, a, b, c);
    check_incircle(ti, a, b, c, d);
    const P2 cn{ulp_step(c[0], nudge(rng)), ulp_step(c[1], nudge(rng))};
    const P2 dn{ulp_step(d[0], nudge(rng)), ulp_step(d[1], nudge(rng))};
    check_orient(to, a, b, cn);
    check_orient(to, cn, a, b);
    check_incircle(ti, a, b, c, dn);
    check_incircle(ti, a, b, cn, d);
    check_incircle(ti, dn, a, b, c);
  }
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

TEST_CASE("predicates at scales from 1e-300 to 1e30 and on subnormals", "[predicates]") {
  std::mt19937_64 rng(6);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> ut(-0.5, 1.5);
  std::uniform_real_distribution<double> ang(0.0, 6.283185307179586);
  Tally to, ti;
  for (int e10 = -300; e10 <= 30; e10 += 6) {
    const double s = std::pow(10.0, e10);
    for (int i = 0; i < 60; ++i) {
      // Random, nearly collinear, and shifted-away configurations at this scale.
      const P2 a{u(rng) * s, u(rng) * s}, b{u(rng) * s, u(rng) * s};
      const P2 c0 = lerp(a, b, ut(rng));
      for (int k = -1; k <= 1; ++k) check_orient(to, a, b, P2{ulp_step(c0[0], k), c0[1]});
      const P2 sh{7.0 * s, -3.0 * s};
      check_orient(to, P2{a[0] + sh[0], a[1] + sh[1]}, P2{b[0] + sh[0], b[1] + sh[1]},
                   P2{c0[0] + sh[0], c0[1] + sh[1]});
      // Nearly cocircular at this scale.
      std::array<P2, 4> q;
      for (auto& p : q) {
        const double th = ang(rng);
        p = {s * (0.25 + std::cos(th)), s * (-0.5 + std::sin(th))};
      }
      for (int k = -1; k <= 1; ++k)
        check_incircle(ti, q[0], q[1], q[2], P2{ulp_step(q[3][0], k), q[3][1]});
      check_incircle(ti, a, b, c0, P2{u(rng) * s, u(rng) * s});
    }
  }
  // Exact powers of two down into the subnormal range: integer lattice times 2^k.
  std::uniform_int_distribution<int> small(-40, 40);
  const auto circle = lattice_circle(25);
  for (int k = -1074; k <= 900; k += 13) {
    for (int i = 0; i < 20; ++i) {
      const P2 a{std::ldexp(small(rng), k), std::ldexp(small(rng), k)};
      const P2 b{std::ldexp(small(rng), k), std::ldexp(small(rng), k)};
      const P2 c{std::ldexp(small(rng), k), std::ldexp(small(rng), k)};
      const P2 d{std::ldexp(small(rng), k), std::ldexp(small(rng), k)};
      check_orient(to, a, b, c);
      check_incircle(ti, a, b, c, d);
      // Collinear and cocircular stay exactly degenerate under exact scaling.
      const P2 m{std::ldexp(2 * small(rng), k), std::ldexp(2 * small(rng), k)};
      const P2 mid{(a[0] + m[0]) / 2, (a[1] + m[1]) / 2};
      if (k > -1073) REQUIRE(pred::orient2d(a.data(), m.data(), mid.data()) == 0.0);
      std::array<P2, 4> q;
      for (int j = 0; j < 4; ++j) {
        const auto& p = circle[(static_cast<std::size_t>(i) * 5 + static_cast<std::size_t>(j) * 7) %
                               circle.size()];
        q[j] = {std::ldexp(double(p[0] + 40), k), std::ldexp(double(p[1] - 40), k)};
      }
      check_incircle(ti, q[0], q[1], q[2], q[3]);
    }
  }
  // Mixed magnitudes inside one call (within the documented dynamic range).
  std::uniform_int_distribution<int> ek(-150, 150);
  for (int i = 0; i < 1500; ++i) {
    const P2 a{std::ldexp(u(rng), ek(rng)), std::ldexp(u(rng), ek(rng))};
    const P2 b{std::ldexp(u(rng), ek(rng)), std::ldexp(u(rng), ek(rng))};
    const P2 c = lerp(a, b, ut(rng));
    check_orient(to, a, b, c);
    check_orient(to, a, b, P2{ulp_step(c[0], 1), c[1]});
    const P2 d{std::ldexp(u(rng), ek(rng)), std::ldexp(u(rng), ek(rng))};
    check_incircle(ti, a, b, c, d);
    check_incircle(ti, a, b, d, c);
  }
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

// Coordinates from the smallest subnormal to nearly DBL_MAX in one call (differences
// overflow in the filter). Beyond a spread of about
// 2^350 (incircle) / 2^850 (orient2d) the exact determinant needs bits below 2^-1074 and
// the implementation switches from expansions to exact integers; both must agree with
// the reference.
TEST_CASE("predicates on inputs spanning the whole double range", "[predicates]") {
  std::mt19937_64 rng(12);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> ut(-0.5, 1.5);
  std::uniform_int_distribution<int> ek(-1074, 1024);  // ldexp(u, 1024) < DBL_MAX
  std::uniform_int_distribution<int> nudge(-1, 1);
  Tally to, ti;
  auto any = [&]() {
    const int e = ek(rng);
    return e < -1022 ? std::ldexp(std::round(u(rng) * 8.0), e) : std::ldexp(u(rng), e);
  };
  for (int i = 0; i < 1500; ++i) {
    const P2 a{any(), any()}, b{any(), any()}, c{any(), any()}, d{any(), any()};
    check_orient(to, a, b, c);
    check_incircle(ti, a, b, c, d);
    // Nearly degenerate: c on the segment ab, nudged; d mixing tiny and large.
    const P2 m = lerp(a, b, ut(rng));
    if (std::isfinite(m[0]) && std::isfinite(m[1])) {
      const P2 mn{ulp_step(m[0], nudge(rng)), ulp_step(m[1], nudge(rng))};
      check_orient(to, a, b, mn);
      check_incircle(ti, a, b, mn, d);
    }
    // Tiny offsets from points with one huge and one tiny coordinate.
    const double dn = std::numeric_limits<double>::denorm_min();
    const P2 p{-dn * (1 + i % 5), std::nextafter(3.0, 4.0)}, q{0.0, -dn}, o{0.0, 0.0};
    check_orient(to, p, q, o);
    check_orient(to, P2{a[0], dn}, P2{a[0], 0.0}, P2{ulp_step(a[0], nudge(rng)), -dn});
    check_incircle(ti, p, q, o, P2{dn, dn * (i % 3)});
    check_incircle(ti, P2{b[0], 0.0}, P2{-b[0], 0.0}, P2{0.0, b[0]},
                   P2{dn * (i % 4), ulp_step(b[0], nudge(rng))});
  }
  // Exactly degenerate across the whole range: collinear multiples of (tiny, huge).
  for (int k = 0; k < 40; ++k) {
    const double x = std::ldexp(1.0 + k, -1074 + k),
                 y = std::ldexp(3.0 - k * 0x1p-40, 900 - 10 * k);
    const P2 p0{0.0, 0.0}, p1{x, y}, p2{2 * x, 2 * y}, p3{3 * x, 3 * y};
    CHECK(pred::orient2d(p0.data(), p1.data(), p2.data()) == 0.0);
    CHECK(pred::orient2d(p1.data(), p3.data(), p2.data()) == 0.0);
    CHECK(pred::incircle(p0.data(), p1.data(), p2.data(), p3.data()) == 0.0);
    check_orient(to, p1, p2, P2{ulp_step(p3[0], 1), p3[1]});
    check_incircle(ti, p0, p1, p2, P2{p3[0], ulp_step(p3[1], -1)});
  }
  // Named case: (-d, 3 + ulp), (0, -d), (0, 0) has orientation d*d > 0 (about 2.4e-647).
  const double dn = std::numeric_limits<double>::denorm_min();
  const double a[2] = {-dn, std::nextafter(3.0, 4.0)}, b[2] = {0.0, -dn}, c[2] = {0.0, 0.0};
  CHECK(pred::orient2d(a, b, c) > 0.0);
  CHECK(pred::orient2d(b, a, c) < 0.0);
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

TEST_CASE("predicates on duplicate and nearly duplicate points", "[predicates]") {
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-10.0, 10.0);
  Tally to, ti;
  for (int i = 0; i < 1000; ++i) {
    const P2 a{u(rng), u(rng)}, b{u(rng), u(rng)}, c{u(rng), u(rng)};
    CHECK(pred::orient2d(a.data(), a.data(), b.data()) == 0.0);
    CHECK(pred::orient2d(a.data(), b.data(), a.data()) == 0.0);
    CHECK(pred::orient2d(b.data(), a.data(), a.data()) == 0.0);
    CHECK(pred::orient2d(a.data(), a.data(), a.data()) == 0.0);
    CHECK(pred::incircle(a.data(), a.data(), b.data(), c.data()) == 0.0);
    CHECK(pred::incircle(a.data(), b.data(), c.data(), a.data()) == 0.0);
    CHECK(pred::incircle(a.data(), b.data(), c.data(), c.data()) == 0.0);
    CHECK(pred::incircle(a.data(), a.data(), a.data(), a.data()) == 0.0);
    const P2 a1{ulp_step(a[0], 1), a[1]}, a2{a[0], ulp_step(a[1], -1)};
    check_orient(to, a, a1, b);
    check_orient(to, a, a1, a2);
    check_incircle(ti, a, a1, a2, b);
    check_incircle(ti, a, b, c, a1);
  }
  const double z[2] = {0.0, 0.0};
  CHECK(pred::orient2d(z, z, z) == 0.0);
  CHECK(pred::incircle(z, z, z, z) == 0.0);
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

// Kettner, Mehlhorn, Pion, Schirra, Yap, "Classroom examples of robustness problems in
// geometric computations" (2008), Figure 2: orientation of p = (0.5 + x u, 0.5 + y u),
// u = 2^-53 (one ulp of 0.5), 0 <= x, y < 256, against a fixed line qr. The plain
// double evaluation paints a noisy, non-convex pattern of wrong signs around the line.
TEST_CASE("orient2d on the Kettner et al. 256x256 ulp grid near (0.5, 0.5)", "[predicates]") {
  struct Line {
    P2 p0, q, r;
  };
  const Line lines[] = {
      {{0.5, 0.5}, {12.0, 12.0}, {24.0, 24.0}},
      {{0.50000000000002531, 0.5000000000000171},
       {17.300000000000001, 17.300000000000001},
       {24.00000000000005, 24.0000000000000053}},
      {{0.5, 0.5}, {8.8000000000000007, 7.7000000000000002}, {12.1, 10.1}},
  };
  const double step = 0x1p-53;
  long fast_wrong_total = 0;
  for (const Line& l : lines) {
    Tally t;
    long positive = 0, negative = 0, zero = 0;
    for (int x = 0; x < 256; ++x) {
      for (int y = 0; y < 256; ++y) {
        const P2 p{l.p0[0] + x * step, l.p0[1] + y * step};
        check_orient(t, p, l.q, l.r);
        const int s = sgn(pred::orient2d(p.data(), l.q.data(), l.r.data()));
        positive += s > 0;
        negative += s < 0;
        zero += s == 0;
      }
    }
    INFO("positive " << positive << " negative " << negative << " zero " << zero);
    REQUIRE_TALLY(t);
    fast_wrong_total += t.fast_wrong;
  }
  // The test has teeth: the naive predicate really is wrong on this input.
  CHECK(fast_wrong_total > 0);
}

TEST_CASE("orient2d and incircle permutation invariants", "[predicates]") {
  std::mt19937_64 rng(8);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::uniform_real_distribution<double> ang(0.0, 6.283185307179586);
  for (int i = 0; i < 1500; ++i) {
    // Half random, half nearly degenerate.
    const P2 a{u(rng), u(rng)}, b{u(rng), u(rng)};
    const P2 c = (i % 2 == 0) ? P2{u(rng), u(rng)}
                              : P2{ulp_step(lerp(a, b, 0.3)[0], i % 5 - 2), lerp(a, b, 0.3)[1]};
    const int o = sgn(pred::orient2d(a.data(), b.data(), c.data()));
    REQUIRE(sgn(pred::orient2d(b.data(), a.data(), c.data())) == -o);
    REQUIRE(sgn(pred::orient2d(a.data(), c.data(), b.data())) == -o);
    REQUIRE(sgn(pred::orient2d(b.data(), c.data(), a.data())) == o);
    REQUIRE(sgn(pred::orient2d(c.data(), a.data(), b.data())) == o);

    std::array<P2, 4> q;
    if (i % 2 == 0) {
      for (auto& p : q) p = {u(rng), u(rng)};
    } else {
      for (auto& p : q) {
        const double th = ang(rng);
        p = {0.3 + std::cos(th), 0.7 + std::sin(th)};
      }
    }
    const int base = sgn(pred::incircle(q[0].data(), q[1].data(), q[2].data(), q[3].data()));
    REQUIRE(base == ref_incircle(q[0].data(), q[1].data(), q[2].data(), q[3].data()));
    std::array<int, 4> perm{0, 1, 2, 3};
    do {
      int inversions = 0;
      for (int x = 0; x < 4; ++x)
        for (int y = x + 1; y < 4; ++y) inversions += perm[x] > perm[y];
      const int parity = inversions % 2 == 0 ? 1 : -1;
      const int s = sgn(pred::incircle(q[perm[0]].data(), q[perm[1]].data(), q[perm[2]].data(),
                                       q[perm[3]].data()));
      REQUIRE(s == parity * base);
    } while (std::next_permutation(perm.begin(), perm.end()));
  }
}

TEST_CASE("predicates are invariant under exact translations and power-of-two scaling",
          "[predicates]") {
  std::mt19937_64 rng(9);
  const double unit = 0x1p-30;
  std::uniform_int_distribution<long> coord(-(1L << 30), 1L << 30);
  std::uniform_int_distribution<long> shift(-(1L << 52), 1L << 52);  // |offset| <= 2^22
  std::uniform_int_distribution<int> nudge(-2, 2);
  std::uniform_int_distribution<int> pw(-200, 200);
  Tally to, ti;
  const auto circle = lattice_circle(1105);
  std::uniform_int_distribution<std::size_t> pick(0, circle.size() - 1);
  for (int i = 0; i < 2000; ++i) {
    // Nearly collinear on a dyadic grid: c is the grid point nearest to the line, nudged.
    const long ax = coord(rng), ay = coord(rng), bx = coord(rng), by = coord(rng);
    const long cx = ax + (bx - ax) / 3 + nudge(rng), cy = ay + (by - ay) / 3 + nudge(rng);
    const P2 a{ax * unit, ay * unit}, b{bx * unit, by * unit}, c{cx * unit, cy * unit};
    const long ox = shift(rng), oy = shift(rng);
    const double tx = ox * unit, ty = oy * unit;
    // Every translated coordinate is an integer multiple of 2^-30 below 2^53 units.
    const P2 at{a[0] + tx, a[1] + ty}, bt{b[0] + tx, b[1] + ty}, ct{c[0] + tx, c[1] + ty};
    REQUIRE(at[0] - tx == a[0]);
    const int o = sgn(pred::orient2d(a.data(), b.data(), c.data()));
    REQUIRE(o == ref_orient(a.data(), b.data(), c.data()));
    REQUIRE(sgn(pred::orient2d(at.data(), bt.data(), ct.data())) == o);
    check_orient(to, at, bt, ct);
    const double f = std::ldexp(1.0, pw(rng));
    const P2 as{a[0] * f, a[1] * f}, bs{b[0] * f, b[1] * f}, cs{c[0] * f, c[1] * f};
    REQUIRE(sgn(pred::orient2d(as.data(), bs.data(), cs.data())) == o);

    // Cocircular lattice points (radius 1105 units), one of them nudged, translated.
    std::array<P2, 4> q, qt;
    const long mx = coord(rng) / 4, my = coord(rng) / 4;
    for (int k = 0; k < 4; ++k) {
      const auto& p = circle[pick(rng)];
      q[k] = {(mx + p[0]) * unit, (my + p[1]) * unit};
    }
    q[3][0] += nudge(rng) * unit;
    for (int k = 0; k < 4; ++k) qt[k] = {q[k][0] + tx, q[k][1] + ty};
    const int s = sgn(pred::incircle(q[0].data(), q[1].data(), q[2].data(), q[3].data()));
    REQUIRE(s == ref_incircle(q[0].data(), q[1].data(), q[2].data(), q[3].data()));
    REQUIRE(sgn(pred::incircle(qt[0].data(), qt[1].data(), qt[2].data(), qt[3].data())) == s);
    check_incircle(ti, qt[0], qt[1], qt[2], qt[3]);
  }
  REQUIRE_TALLY(to);
  REQUIRE_TALLY(ti);
}

TEST_CASE("orient2d returns an accurate value, not only a sign", "[predicates]") {
  std::mt19937_64 rng(10);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const double eps = 0x1p-53;
  for (int i = 0; i < 3000; ++i) {
    const P2 a{0.3 + u(rng), 0.7 + u(rng)}, b{0.3 + u(rng), 0.7 + u(rng)};
    const P2 c0 = lerp(a, b, 0.5 + 0.5 * u(rng));
    const P2 c{ulp_step(c0[0], i % 3 - 1), c0[1]};
    const double got = pred::orient2d(a.data(), b.data(), c.data());
    // The reference is in units of 2^e0 per coordinate, so of 2^(2 e0) for the value.
    std::vector<double> v{a[0], a[1], b[0], b[1], c[0], c[1]};
    int e0 = std::numeric_limits<int>::max();
    for (double x : v)
      if (x != 0.0) e0 = std::min(e0, decompose(x).e);
    const double ref = std::ldexp(ref_orient_value(a.data(), b.data(), c.data()).approx(), 2 * e0);
    const double acx = a[0] - c[0], acy = a[1] - c[1], bcx = b[0] - c[0], bcy = b[1] - c[1];
    const double ds = std::fabs(acx * bcy) + std::fabs(acy * bcx);
    // Filter path: error <= 3 eps ds; slow path: nearly correctly rounded.
    REQUIRE(std::fabs(got - ref) <= 4.0 * eps * ds + 1e-14 * std::fabs(ref));
  }
}
