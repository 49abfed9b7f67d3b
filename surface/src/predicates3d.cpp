// Exact orient3d (adaptive precision) and exact triangle/triangle intersection tests.
//
// orient3d(a, b, c, d) = det [a-d; b-d; c-d], evaluated in three stages:
//
//   1. Filter. The determinant in doubles, with the a-priori bound of Shewchuk (1997,
//      "Adaptive precision floating-point arithmetic and fast robust geometric
//      predicates", orient3d "errboundA" = (7 + 56 eps) eps times the permanent; we use
//      (7 + 64 eps) eps for slack), and a floor that covers gradual underflow of the
//      products (each product that underflows adds at most 2^-1075, multiplied at most
//      by |adz|+|bdz|+|cdz| in the next product). When |det| passes both its sign is
//      certain. Overflow gives inf/NaN, which never passes, so such inputs fall through.
//   2. Exact differences. The coordinates are rescaled by a power of two (exact) so that
//      the largest is in [1, 2). When the nine differences a-d, b-d, c-d are exact in
//      doubles (nearby points: Sterbenz) -- the common case for the nearly coplanar
//      neighbours of a flat face -- the determinant of those doubles IS the exact one;
//      it is evaluated with error-free products and sums (a 24-component expansion).
//   3. General case. Every difference as a two-component expansion (value + rounding
//      error), the determinant evaluated exactly in expansion arithmetic (at most 192
//      components). Inputs of extreme dynamic range (nonzero coordinates more than
//      2^300 apart, where double products would underflow) run the same code in long
//      double, whose exponent range holds any product of three doubles.
//
// Expansions: arrays of doubles, nonoverlapping, increasing magnitude, zeros removed;
// the value is the exact sum and its sign is the sign of the last component. Primitives
// (error-free transformations, Knuth/Dekker): two_sum (a + b = x + y exactly),
// two_product via fma (a * b = x + y exactly), and on top of them scaling an expansion
// by a double and adding two expansions (merge by magnitude, then a chain of two_sums;
// nonoverlapping output needs round-to-nearest-even, the IEEE default).
//
// The sign is exact for every finite input (subnormals included); non-finite inputs give
// an unspecified sign.
//
// The triangle tests only combine signs of orient3d and of the exact orient2d of
// mesher2d (on coordinate projections: dropping a coordinate is exact), so they are
// exact as well. Their case analysis is documented at each function.
#include "predicates3d.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <limits>

#include "uvmesh/mesher2d/predicates.h"

#if defined(__FAST_MATH__)
#error "predicates3d.cpp needs IEEE arithmetic: do not compile it with -ffast-math"
#endif
static_assert(std::numeric_limits<double>::is_iec559, "IEEE-754 double required");
static_assert(FLT_EVAL_METHOD == 0, "extended-precision evaluation breaks the error bounds");

namespace uvmesh::surface::pred3 {

using geom::Vec3;

namespace {

constexpr double kEps = 0x1p-53;  // unit roundoff
constexpr double kO3A = (7.0 + 64.0 * kEps) * kEps;

// ---- error-free transformations and expansions ----------------------------------------
// Templated on the floating type: double for the usual inputs, long double (64-bit
// significand, exponent range +-16382 on x86-64 Linux) for inputs whose dynamic range
// would make double products underflow; the algorithms hold for any binary format with
// round-to-nearest-even.
template <class T>
inline void two_sum(T a, T b, T& x, T& y) {
  x = a + b;
  const T bv = x - a;
  const T av = x - bv;
  y = (a - av) + (b - bv);
}
template <class T>
inline void two_product(T a, T b, T& x, T& y) {
  x = a * b;
  y = std::fma(a, b, -x);
}

// h = e * b; returns the length of h (at most 2n). h must not alias e.
template <class T>
int scale_expansion(const T* e, int n, T b, T* h) {
  if (n == 0 || b == 0) return 0;
  int k = 0;
  T q, hh;
  two_product(e[0], b, q, hh);
  if (hh != 0) h[k++] = hh;
  for (int i = 1; i < n; ++i) {
    T p1, p0, sum;
    two_product(e[i], b, p1, p0);
    two_sum(q, p0, sum, hh);
    if (hh != 0) h[k++] = hh;
    // |p1| >= |sum| in exact arithmetic (nonoverlapping input); two_sum needs no order.
    two_sum(p1, sum, q, hh);
    if (hh != 0) h[k++] = hh;
  }
  if (q != 0) h[k++] = q;
  return k;
}

// h = e + f; returns the length (at most n + m <= 256). h must not alias e or f.
template <class T>
int sum_expansion(const T* e, int n, const T* f, int m, T* h) {
  // Merge the components by increasing magnitude, then accumulate with a chain of
  // two_sums, emitting the nonzero rounding errors.
  T g[256];
  int i = 0, j = 0, len = 0;
  while (i < n && j < m) g[len++] = (std::fabs(e[i]) < std::fabs(f[j])) ? e[i++] : f[j++];
  while (i < n) g[len++] = e[i++];
  while (j < m) g[len++] = f[j++];
  if (len == 0) return 0;
  int k = 0;
  T q = g[0];
  for (int t = 1; t < len; ++t) {
    T s, r;
    two_sum(q, g[t], s, r);
    if (r != 0) h[k++] = r;
    q = s;
  }
  if (q != 0) h[k++] = q;
  return k;
}

// h = e * f for f of length <= 2 and e of length <= 16; returns the length.
template <class T>
int mul_expansion(const T* e, int n, const T* f, int m, T* h) {
  if (m == 0 || n == 0) return 0;
  if (m == 1) return scale_expansion(e, n, f[0], h);
  T t0[64], t1[64];
  const int l0 = scale_expansion(e, n, f[0], t0);
  const int l1 = scale_expansion(e, n, f[1], t1);
  return sum_expansion(t0, l0, t1, l1, h);
}

// A difference as an expansion of length 0..2.
template <class T>
struct Diff {
  T c[2];
  int n;
};
template <class T>
Diff<T> make_diff(T a, T b) {
  T x, y;
  two_sum(a, -b, x, y);
  Diff<T> d{{0, 0}, 0};
  if (y != 0) d.c[d.n++] = y;
  if (x != 0) d.c[d.n++] = x;
  return d;
}

// x*y - z*w for differences; result length <= 16.
template <class T>
int cross_term(const Diff<T>& x, const Diff<T>& y, const Diff<T>& z, const Diff<T>& w, T* h) {
  T p[8], q[8];
  const int lp = mul_expansion(x.c, x.n, y.c, y.n, p);
  const int lq = mul_expansion(z.c, z.n, w.c, w.n, q);
  for (int i = 0; i < lq; ++i) q[i] = -q[i];
  return sum_expansion(p, lp, q, lq, h);
}

// The exact determinant as an expansion (stages 2 and 3: with exact differences the
// zero elimination keeps every expansion short, so stage 2 is this code on short input).
// Returns the sign; `approx` receives an approximation of the value.
template <class T>
int det_expansion(const T (&p)[12], T& approx) {
  const Diff<T> adx = make_diff(p[0], p[9]), ady = make_diff(p[1], p[10]),
                adz = make_diff(p[2], p[11]);
  const Diff<T> bdx = make_diff(p[3], p[9]), bdy = make_diff(p[4], p[10]),
                bdz = make_diff(p[5], p[11]);
  const Diff<T> cdx = make_diff(p[6], p[9]), cdy = make_diff(p[7], p[10]),
                cdz = make_diff(p[8], p[11]);
  // det = adz (bdx cdy - cdx bdy) + bdz (cdx ady - adx cdy) + cdz (adx bdy - bdx ady)
  T mi[16], t0[64], t1[64], t2[64], s01[128], det[192];
  int lm = cross_term(bdx, cdy, cdx, bdy, mi);
  const int l0 = mul_expansion(mi, lm, adz.c, adz.n, t0);
  lm = cross_term(cdx, ady, adx, cdy, mi);
  const int l1 = mul_expansion(mi, lm, bdz.c, bdz.n, t1);
  lm = cross_term(adx, bdy, bdx, ady, mi);
  const int l2 = mul_expansion(mi, lm, cdz.c, cdz.n, t2);
  const int l01 = sum_expansion(t0, l0, t1, l1, s01);
  const int ld = sum_expansion(s01, l01, t2, l2, det);
  approx = 0;
  if (ld == 0) return 0;
  for (int i = 0; i < ld; ++i) approx += det[i];
  return det[ld - 1] > 0 ? 1 : -1;
}

// Stages 2-3. The coordinates are rescaled by 2^-ex so that the largest is in [1, 2)
// (exact). If every nonzero coordinate is then >= 2^-300, all products of three
// differences are multiples of 2^-1056 below 64: no underflow, no overflow, so double
// expansions are exact. Otherwise (pathological ranges, e.g. 1 and 1e-320 in one call)
// the same computation runs in long double, whose exponent range holds any product of
// three doubles.
double orient3d_exact(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3* pts[4] = {&a, &b, &c, &d};
  double big = 0, small = std::numeric_limits<double>::infinity();
  for (const Vec3* p : pts)
    for (int i = 0; i < 3; ++i) {
      const double v = std::fabs((*p)[i]);
      big = std::max(big, v);
      if (v > 0) small = std::min(small, v);
    }
  if (big == 0) return 0;
  const int ex = std::ilogb(big);
  int sign;
  double mag;
  if (std::ilogb(small) - ex >= -300) {
    double q[12];
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) q[3 * k + i] = std::ldexp((*pts[k])[i], -ex);
    double approx;
    sign = det_expansion(q, approx);
    mag = std::ldexp(std::fabs(approx), 3 * ex);  // undo the scaling (may over/underflow)
  } else {
    static_assert(LDBL_MAX_EXP >= 4 * DBL_MAX_EXP && LDBL_MANT_DIG > DBL_MANT_DIG,
                  "the wide-range fallback needs an extended long double");
    long double q[12];
    for (int k = 0; k < 4; ++k)
      for (int i = 0; i < 3; ++i) q[3 * k + i] = (*pts[k])[i];
    long double approx;
    sign = det_expansion(q, approx);
    mag = static_cast<double>(std::fabs(approx));
  }
  if (sign == 0) return 0;
  // Keep the exact sign even when the magnitude is outside the double range.
  if (mag == 0) mag = std::numeric_limits<double>::denorm_min();
  return sign > 0 ? mag : -mag;
}

}  // namespace

double orient3d_fast(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  return adz * (bdx * cdy - cdx * bdy) + bdz * (cdx * ady - adx * cdy) +
         cdz * (adx * bdy - bdx * ady);
}

double orient3d(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double adx = a.x - d.x, bdx = b.x - d.x, cdx = c.x - d.x;
  const double ady = a.y - d.y, bdy = b.y - d.y, cdy = c.y - d.y;
  const double adz = a.z - d.z, bdz = b.z - d.z, cdz = c.z - d.z;
  const double bdxcdy = bdx * cdy, cdxbdy = cdx * bdy;
  const double cdxady = cdx * ady, adxcdy = adx * cdy;
  const double adxbdy = adx * bdy, bdxady = bdx * ady;
  const double det = adz * (bdxcdy - cdxbdy) + bdz * (cdxady - adxcdy) + cdz * (adxbdy - bdxady);
  const double aadz = std::fabs(adz), abdz = std::fabs(bdz), acdz = std::fabs(cdz);
  const double permanent = (std::fabs(bdxcdy) + std::fabs(cdxbdy)) * aadz +
                           (std::fabs(cdxady) + std::fabs(adxcdy)) * abdz +
                           (std::fabs(adxbdy) + std::fabs(bdxady)) * acdz;
  // Underflow: accepting only |det| >= 2^-1000 (S + 1), S = |adz| + |bdz| + |cdz|, makes
  // the absolute errors (<= 2^-1070 (S + 1)) below 2^-70 |det|, which the slack of kO3A
  // over Shewchuk's constant absorbs. Written without subnormal intermediates: those
  // cost a microcode assist on x86, which dominated the time on this hot path.
  const double bound = kO3A * permanent;
  if ((det > bound || -det > bound) && std::fabs(det) * 0x1p+1000 > aadz + abdz + acdz + 1.0)
    return det;
  return orient3d_exact(a, b, c, d);
}

int orient3d_sign(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double o = orient3d(a, b, c, d);
  return (o > 0) - (o < 0);
}

// ---- triangle tests --------------------------------------------------------------------
namespace {

struct P2 {
  double v[2];
};
// Projection along axis k (drop coordinate k). Exact; injective on any plane whose normal
// has a nonzero k component, which is what projection_axis() picks.
P2 proj(const Vec3& p, int k) {
  return {{p[(k + 1) % 3], p[(k + 2) % 3]}};
}

int o2(const P2& a, const P2& b, const P2& c) {
  const double o = m2d::pred::orient2d(a.v, b.v, c.v);
  return (o > 0) - (o < 0);
}

// Closed segments ab and cd in the plane.
bool seg_seg_2d(const P2& a, const P2& b, const P2& c, const P2& d) {
  const int s1 = o2(a, b, c), s2 = o2(a, b, d);
  if (s1 * s2 > 0) return false;
  const int s3 = o2(c, d, a), s4 = o2(c, d, b);
  if (s3 * s4 > 0) return false;
  if (s1 == 0 && s2 == 0 && s3 == 0 && s4 == 0) {
    // All on one line (or points): on a line, overlapping bounding boxes in both
    // coordinates is the same as overlapping intervals along the line.
    for (int i = 0; i < 2; ++i) {
      if (std::max(a.v[i], b.v[i]) < std::min(c.v[i], d.v[i])) return false;
      if (std::max(c.v[i], d.v[i]) < std::min(a.v[i], b.v[i])) return false;
    }
  }
  return true;
}

// x in the closed triangle pqr whose orientation sign is s != 0.
bool in_tri_2d(const P2& p, const P2& q, const P2& r, int s, const P2& x) {
  return o2(p, q, x) * s >= 0 && o2(q, r, x) * s >= 0 && o2(r, p, x) * s >= 0;
}

// Closed segment ab against the closed (non-degenerate) triangle pqr, all in the plane.
bool seg_tri_2d(const P2& a, const P2& b, const P2& p, const P2& q, const P2& r) {
  const int s = o2(p, q, r);
  return in_tri_2d(p, q, r, s, a) || in_tri_2d(p, q, r, s, b) || seg_seg_2d(a, b, p, q) ||
         seg_seg_2d(a, b, q, r) || seg_seg_2d(a, b, r, p);
}

// Direction x - v inside the closed wedge at v spanned by c - v and d - v (v c d a
// non-degenerate triangle, so the wedge is convex), x != v.
bool in_wedge_2d(const P2& v, const P2& c, const P2& d, const P2& x) {
  if (x.v[0] == v.v[0] && x.v[1] == v.v[1]) return false;
  const int s = o2(v, c, d);
  return o2(v, c, x) * s >= 0 && o2(v, x, d) * s >= 0;
}

int axis_of(const Vec3& p, const Vec3& q, const Vec3& r) {
  for (int k = 0; k < 3; ++k)
    if (o2(proj(p, k), proj(q, k), proj(r, k)) != 0) return k;
  return -1;
}

// The line through a and b against the closed triangle pqr, for a segment ab that
// reaches the plane of pqr without lying in it: then the line meets that plane in one
// point, which is on the segment, and it is in the triangle iff the line passes on the
// same side of (or through) the three directed edges: no two of the three orientations
// of ab against the edges have strictly opposite signs.
bool line_hits_tri(const Vec3& a, const Vec3& b, const Vec3& p, const Vec3& q, const Vec3& r) {
  const int s1 = orient3d_sign(a, b, p, q);
  const int s2 = orient3d_sign(a, b, q, r);
  if (s1 * s2 < 0) return false;
  const int s3 = orient3d_sign(a, b, r, p);
  return !((s1 > 0 || s2 > 0 || s3 > 0) && (s1 < 0 || s2 < 0 || s3 < 0));
}

// Closed segment ab against the closed non-degenerate triangle t, given the orientations
// oa, ob of a and b against the plane of t; k = projection axis of t (computed on
// demand when the segment lies in the plane).
bool seg_tri(const Vec3& a, const Vec3& b, int oa, int ob, const Tri& t, int& k) {
  if (oa * ob > 0) return false;
  if (oa == 0 && ob == 0) {
    if (k < 0) k = projection_axis(t);
    return seg_tri_2d(proj(a, k), proj(b, k), proj(t[0], k), proj(t[1], k), proj(t[2], k));
  }
  return line_hits_tri(a, b, t[0], t[1], t[2]);
}

bool all_strict_same(const int* s) {
  return (s[0] > 0 && s[1] > 0 && s[2] > 0) || (s[0] < 0 && s[1] < 0 && s[2] < 0);
}

}  // namespace

int projection_axis(const Tri& t) {
  return axis_of(t[0], t[1], t[2]);
}

// Two closed non-degenerate triangles intersect iff an edge of one meets the other: the
// intersection is a convex set; if it is not empty, each of its extreme points is where
// the boundary of one triangle enters the other (coplanar or not).
bool closed_triangles_intersect(const Tri& t0, const Tri& t1) {
  int s1[3], s0[3];
  for (int i = 0; i < 3; ++i) s1[i] = orient3d_sign(t0[0], t0[1], t0[2], t1[i]);
  if (all_strict_same(s1)) return false;
  for (int i = 0; i < 3; ++i) s0[i] = orient3d_sign(t1[0], t1[1], t1[2], t0[i]);
  if (all_strict_same(s0)) return false;
  if (s1[0] == 0 && s1[1] == 0 && s1[2] == 0) {
    // Coplanar: one 2D problem in a projection injective on the common plane.
    const int k = projection_axis(t0);
    P2 a[3], b[3];
    for (int i = 0; i < 3; ++i) a[i] = proj(t0[i], k), b[i] = proj(t1[i], k);
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j)
        if (seg_seg_2d(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3])) return true;
    // No boundary crossing: either disjoint or one inside the other.
    return in_tri_2d(b[0], b[1], b[2], o2(b[0], b[1], b[2]), a[0]) ||
           in_tri_2d(a[0], a[1], a[2], o2(a[0], a[1], a[2]), b[0]);
  }
  int k0 = -1, k1 = -1;
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (seg_tri(t0[i], t0[j], s0[i], s0[j], t1, k1)) return true;
  }
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3;
    if (seg_tri(t1[i], t1[j], s1[i], s1[j], t0, k0)) return true;
  }
  return false;
}

// Shared vertex v: T0 = v a b, T1 = v c d. The intersection I is convex and contains v.
// I != {v} iff it has an extreme point w != v; w lies on an edge of one triangle and in
// the other:
//   - on the opposite edge ab (resp. cd): that edge meets the other triangle (and not at
//     v, which is not on ab for a non-degenerate T0);
//   - on va (resp. vb, vc, vd), w != v: then [v, w] lies in the other triangle, so the
//     edge lies in the other triangle's plane and its direction is in the other
//     triangle's wedge at v.
// Conversely each of these gives a common point other than v. So exactly these cases.
bool intersect_beyond_vertex(const Vec3& v, const Vec3& a, const Vec3& b, const Vec3& c,
                             const Vec3& d) {
  const int oa = orient3d_sign(v, c, d, a), ob = orient3d_sign(v, c, d, b);
  const int oc = orient3d_sign(v, a, b, c), od = orient3d_sign(v, a, b, d);
  if (oa == 0 && ob == 0) {
    // Coplanar (T0 non-degenerate with all three vertices in T1's plane).
    const int k = axis_of(v, a, b);
    const P2 pv = proj(v, k), pa = proj(a, k), pb = proj(b, k), pc = proj(c, k), pd = proj(d, k);
    return seg_tri_2d(pa, pb, pv, pc, pd) || seg_tri_2d(pc, pd, pv, pa, pb) ||
           in_wedge_2d(pv, pc, pd, pa) || in_wedge_2d(pv, pc, pd, pb) ||
           in_wedge_2d(pv, pa, pb, pc) || in_wedge_2d(pv, pa, pb, pd);
  }
  // Not coplanar, so oc and od are not both zero either.
  if (oa * ob <= 0 && line_hits_tri(a, b, v, c, d)) return true;
  if (oc * od <= 0 && line_hits_tri(c, d, v, a, b)) return true;
  if (oa == 0 || ob == 0) {
    const int k = axis_of(v, c, d);
    const P2 pv = proj(v, k), pc = proj(c, k), pd = proj(d, k);
    if (oa == 0 && in_wedge_2d(pv, pc, pd, proj(a, k))) return true;
    if (ob == 0 && in_wedge_2d(pv, pc, pd, proj(b, k))) return true;
  }
  if (oc == 0 || od == 0) {
    const int k = axis_of(v, a, b);
    const P2 pv = proj(v, k), pa = proj(a, k), pb = proj(b, k);
    if (oc == 0 && in_wedge_2d(pv, pa, pb, proj(c, k))) return true;
    if (od == 0 && in_wedge_2d(pv, pa, pb, proj(d, k))) return true;
  }
  return false;
}

// Shared edge ab: T0 = a b c, T1 = a b d. Not coplanar: the planes meet in the line ab,
// which meets the non-degenerate T0 in the segment ab only, so I = ab. Coplanar: c and d
// on opposite sides of ab give I = ab; on the same side the triangles overlap along the
// edge (a fold). d cannot be on the line ab (T1 non-degenerate).
bool intersect_beyond_edge(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  if (orient3d_sign(a, b, c, d) != 0) return false;
  const int k = axis_of(a, b, c);
  const P2 pa = proj(a, k), pb = proj(b, k);
  return o2(pa, pb, proj(c, k)) * o2(pa, pb, proj(d, k)) > 0;
}

}  // namespace uvmesh::surface::pred3
