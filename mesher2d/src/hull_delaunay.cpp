// HullDelaunay (triangulation.h): the Delaunay triangulation of the convex hull of a point
// set by the kernel T(i+1) = T(i) - C(P) + B(P) (§7.1.3, eq. 7.2), with ghost triangles
// at infinity instead of the enclosing box of §7.3.2. Every geometric decision goes
// through the exact predicates (inline filter, exact fallback).
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "huge_pages.h"
#include "predicates_filter.h"
#include "triangulation.h"

// The steps of HullDelaunay::insert are inlined into it: they are its hot path, split for
// reading only.
#define UVMESH_HULL_INLINE inline __attribute__((always_inline))

namespace uvmesh::m2d::detail {

namespace {

inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return pred::detail::orient2d_filtered(&a.x, &b.x, &c.x);
}

// ------------------------------------------------------------------ insertion order
// Hilbert index, four bits of x and four of y per table step. The curve is the classical
// one: at each level the quadrant digit is (3 rx) ^ ry of the coordinates transformed by
// the level's state (swap x/y, complement both), and the state changes when ry = 0 (swap;
// also complement when rx = 1). The table holds, per state and 4+4 input bits, the 8 bits
// of digits and the state after them.
struct HilbertTable {
  std::array<std::uint16_t, 4 * 256> t{};
  constexpr HilbertTable() {
    for (unsigned s0 = 0; s0 < 4; ++s0)
      for (unsigned xy = 0; xy < 256; ++xy) {
        const unsigned x = xy >> 4, y = xy & 15;
        unsigned sw = s0 & 1, cm = s0 >> 1, d = 0;
        for (int b = 3; b >= 0; --b) {
          const unsigned bx = ((sw ? y : x) >> b & 1) ^ cm;
          const unsigned by = ((sw ? x : y) >> b & 1) ^ cm;
          d = d << 2 | ((3 * bx) ^ by);
          if (by == 0) {
            cm ^= bx;
            sw ^= 1;
          }
        }
        t[s0 * 256 + xy] = static_cast<std::uint16_t>(d | (sw | cm << 1) << 8);
      }
  }
};
constexpr HilbertTable kHilbert;

// Hilbert index of (x, y) in [0, 2^16)^2.
inline std::uint32_t hilbert16(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0, s = 0;
  for (int sh = 12; sh >= 0; sh -= 4) {
    const std::uint16_t e = kHilbert.t[s * 256 + ((x >> sh & 15) << 4 | (y >> sh & 15))];
    d = d << 8 | (e & 255u);
    s = e >> 8;
  }
  return d;
}

inline std::uint64_t mix64(std::uint64_t z) {
  z += 0x9E3779B97F4A7C15ull;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  return z ^ (z >> 31);
}

}  // namespace

// Insertion order: BRIO (Amenta, Choi, Rote): point i joins round r with probability
// 2^-(r+1) counted from the last round (a deterministic hash of i, so the output does not
// depend on anything but the input), rounds inserted from the smallest; inside a round,
// Hilbert order, so that consecutive points are neighbours and the walk from the last
// inserted triangle is a few steps. The random rounds keep the triangulation of the
// inserted points well spread (no long thin triangles across the domain whose huge
// circumdisks make large cavities, as a pure space-filling order builds). Keys of 30
// bits (4-bit round, 26-bit Hilbert index: 8192^2 cells) carry the input index in the
// low 32 bits of every record; records are distinct, so sorting them as integers is the
// stable sort by key (equal keys keep the input order) and any correct sort gives the
// same order. Most significant digit first: one scatter over the whole array by the top
// 10 bits (1024 buckets, whose write positions stay within the second-level TLB), counted
// while the keys are made, then every bucket sorted by its low 20 bits while it is in
// cache (two 10-bit passes, or std::sort for a small bucket). The former three 10-bit
// LSD passes scattered the whole array three times; the scatter was 60% of the sort's
// samples, the sort 11% of the 1e6-point triangulation.
void brio_order(const std::vector<Vec2>& in, std::vector<std::uint64_t>& rec) {
  const std::size_t n = in.size();
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (const Vec2& p : in) {
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  const double sx = 65535.0 / std::max(xmax - xmin, 1e-300),
               sy = 65535.0 / std::max(ymax - ymin, 1e-300);
  auto q = [](double v) {
    return static_cast<std::uint32_t>(!(v > 0) ? 0.0 : v < 65535.0 ? v : 65535.0);
  };
  const int lg = static_cast<int>(std::bit_width(static_cast<std::uint64_t>(n)));
  const int rounds = std::clamp(lg - 8, 1, 15);
  constexpr int kHigh = 52;  // the top digit: key bits 20..29 (record bits 52..61)
  std::vector<std::uint32_t> cnt(1025, 0u);
  std::vector<std::uint64_t> tmp;
  reserve_huge(tmp, n);
  tmp.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t h = hilbert16(q((in[i].x - xmin) * sx), q((in[i].y - ymin) * sy)) >> 6;
    const int level = std::min(std::countr_zero(mix64(i) | 1ull << 62), rounds - 1);
    const std::uint32_t key = static_cast<std::uint32_t>(rounds - 1 - level) << 26 | h;
    const std::uint64_t r = static_cast<std::uint64_t>(key) << 32 | static_cast<std::uint32_t>(i);
    tmp[i] = r;
    ++cnt[(r >> kHigh) + 1];
  }
  // Stable LSD passes of 10 bits over the low key bits of [src, src + s) (record bits
  // sh0, sh0 + 10, ...; an even count of passes leaves the result in src), dst scratch.
  std::uint32_t c[1024];
  auto lsd = [&c](std::uint64_t* src, std::uint64_t* dst, std::size_t s, int sh0, int passes) {
    for (int pass = 0; pass < passes; ++pass) {
      const int sh = sh0 + 10 * pass;
      std::fill(c, c + 1024, 0u);
      for (std::size_t k = 0; k < s; ++k) ++c[(src[k] >> sh) & 1023];
      std::uint32_t sum = 0;
      for (auto& x : c) {
        const std::uint32_t x0 = x;
        x = sum;
        sum += x0;
      }
      for (std::size_t k = 0; k < s; ++k) dst[c[(src[k] >> sh) & 1023]++] = src[k];
      std::swap(src, dst);
    }
  };
  for (std::size_t b = 1; b <= 1024; ++b) cnt[b] += cnt[b - 1];  // cnt[b]: start of bucket b
  reserve_huge(rec, n);
  rec.resize(n);
  if (n < (std::size_t{1} << 18)) {
    // Everything is in cache (2 MB at most): LSD passes all through, the last one by the
    // top digit already counted.
    lsd(tmp.data(), rec.data(), n, 32, 2);
    std::vector<std::uint32_t> pos(cnt.begin(), cnt.end() - 1);
    for (const std::uint64_t r : tmp) rec[pos[r >> kHigh]++] = r;
    return;
  }
  {
    std::vector<std::uint32_t> pos(cnt.begin(), cnt.end() - 1);
    for (const std::uint64_t r : tmp) rec[pos[r >> kHigh]++] = r;
  }
  // Every bucket by key bits 0..19 (record bits 32..51), with tmp as scratch.
  for (std::size_t b = 0; b < 1024; ++b) {
    std::uint64_t* const lo = rec.data() + cnt[b];
    const std::size_t s = cnt[b + 1] - cnt[b];
    if (s < 256)
      std::sort(lo, lo + s);
    else
      lsd(lo, tmp.data(), s, 32, 2);
  }
}

HullDelaunay::Status HullDelaunay::build(const std::vector<Vec2>& in) {
  const std::size_t n = in.size();
  tris.clear();
  dups.clear();
  std::vector<std::uint64_t> order;
  brio_order(in, order);
  // Coordinates in insertion order, and the inverse permutation (input point -> vertex):
  // the gather and the scatter are the only random accesses, to the same index, both
  // prefetched a few points ahead (the scatter was a separate pass of the output, 60% of
  // its time at 1e6 points).
  reserve_huge(pts, n + 1);
  reserve_huge(src, n);
  reserve_huge(vert_of, n);
  pts.resize(n + 1);
  src.resize(n);
  vert_of.resize(n);
  ghost_id = static_cast<VertId>(n);
  pts[n] = {std::numeric_limits<double>::quiet_NaN(), std::numeric_limits<double>::quiet_NaN()};
  constexpr std::size_t kAhead = 16;
  for (std::size_t k = 0; k < n; ++k) {
    if (k + kAhead < n) {
      const std::uint32_t ia = static_cast<std::uint32_t>(order[k + kAhead] & 0xFFFFFFFFu);
      __builtin_prefetch(&in[ia]);
      __builtin_prefetch(&vert_of[ia], 1);
    }
    const std::uint32_t i = static_cast<std::uint32_t>(order[k] & 0xFFFFFFFFu);
    pts[k] = in[i];
    src[k] = static_cast<std::int32_t>(i);
    vert_of[i] = static_cast<VertId>(k);
  }
  if (n < 3) return Status::Collinear;

  // The first triangle: vertex 0, the first vertex different from it, the first vertex
  // off their line (the vertices skipped meanwhile are inserted later like any other).
  const VertId nv = static_cast<VertId>(n);
  VertId v1 = 1;
  while (v1 < nv && pts[v1].x == pts[0].x && pts[v1].y == pts[0].y) ++v1;
  if (v1 >= nv) return Status::Collinear;
  VertId v2 = v1 + 1;
  double o = 0;
  while (v2 < nv && (o = orient(pts[0], pts[v1], pts[v2])) == 0) ++v2;
  if (v2 >= nv) return Status::Collinear;
  const VertId a = 0, b = o > 0 ? v1 : v2, c = o > 0 ? v2 : v1, G = ghost_id;
  reserve_huge(tris, 2 * n + 8);
  // t0 = (a, b, c) counter-clockwise; ghosts (b, a, G), (c, b, G), (a, c, G) across its
  // edges 2, 0, 1; each ghost meets the next one around the hull at G.
  tris.push_back({{a, b, c}, {4 * 2 + 2, 4 * 3 + 2, 4 * 1 + 2}});
  tris.push_back({{b, a, G}, {4 * 3 + 1, 4 * 2 + 0, 4 * 0 + 2}});  // hull edge (a, b)
  tris.push_back({{c, b, G}, {4 * 1 + 1, 4 * 3 + 0, 4 * 0 + 0}});  // hull edge (b, c)
  tris.push_back({{a, c, G}, {4 * 2 + 1, 4 * 1 + 0, 4 * 0 + 1}});  // hull edge (c, a)
  last_ = 0;
  for (VertId v = 1; v < nv; ++v) {
    if (v == v1 || v == v2) continue;
    if (!insert(v)) return Status::Internal;
  }
  return Status::Ok;
}

bool HullDelaunay::conflict_slow(const Tri& r, Vec2 p) const {
  const Vec2* const P = pts.data();
  if (!ghost(r))
    return pred::detail::incircle_slow(&P[r.v[0]].x, &P[r.v[1]].x, &P[r.v[2]].x, &p.x) > 0;
  // Ghost (a, b, G): the hull edge a -> b has the outside on its left. Its circumdisk is
  // the open half-plane on that side plus the open edge (a point on the edge splits it).
  const int g = ghost_corner(r);
  const Vec2& a = P[r.v[next3(g)]];
  const Vec2& b = P[r.v[prev3(g)]];
  const double o = orient(a, b, p);
  if (o != 0) return o > 0;
  // Collinear: strictly between a and b, compared exactly along a coordinate in which
  // they differ (coordinates are monotone along a line).
  if (a.x != b.x) return (a.x < p.x && p.x < b.x) || (b.x < p.x && p.x < a.x);
  return (a.y < p.y && p.y < b.y) || (b.y < p.y && p.y < a.y);
}

// Point location: visibility walk from the last triangle made (§7.3.2 step 1), never
// back through the edge just crossed. It terminates in a Delaunay triangulation
// (acyclicity of the in-front relation), which this always is; the step cap guards
// against bugs. Crossing a hull edge ends in its ghost: p is outside the hull.
// G's coordinates are NaN: an orientation test involving G is NaN (never < 0), so the
// walk stops in the first ghost it enters without testing for ghosts on every step.
// Returns the triangle reached (o: p's orientations against its edges), or -1.
UVMESH_HULL_INLINE std::int32_t HullDelaunay::walk(Vec2 p, double* o) const {
  const Tri* const T = tris.data();
  const Vec2* const P = pts.data();
  auto side = [&](VertId a, VertId b) {
    const double d = pred::detail::orient2d_filter(&P[a].x, &P[b].x, &p.x);
    if (d != 0) [[likely]]
      return d;
    if (a == ghost_id || b == ghost_id) return std::numeric_limits<double>::quiet_NaN();
    return pred::detail::orient2d_slow(&P[a].x, &P[b].x, &p.x);
  };
  std::int32_t t = last_;
  const Tri& r = T[t];
  int cross = -1;
  for (int i = 0; i < 3; ++i) {
    o[i] = side(r.v[next3(i)], r.v[prev3(i)]);
    if (o[i] < 0) {
      cross = i;
      break;
    }
  }
  const std::int64_t cap = static_cast<std::int64_t>(tris.size()) + 64;
  for (std::int64_t steps = 0; cross >= 0; ++steps) {
    if (steps > cap) return -1;
    const std::int32_t h = T[t].n[cross];
    t = h >> 2;
    const Tri& s = T[t];
    // Entered through edge j: p is strictly inside it; test the two others.
    const int j = h & 3, i1 = next3(j), i2 = prev3(j);
    o[j] = 1;
    cross = -1;
    o[i1] = side(s.v[i2], s.v[j]);
    if (o[i1] < 0) {
      cross = i1;
      continue;
    }
    o[i2] = side(s.v[j], s.v[i1]);
    if (o[i2] < 0) cross = i2;
  }
  return t;
}

// Cavity (§7.1.3): the triangles whose open circumdisk holds p, grown by adjacency from
// the base t (which holds p, or is the ghost of a hull edge p is beyond). Depth first,
// each triangle's far edges in counter-clockwise order, so that the boundary edges come
// out as one counter-clockwise chain around p. In a Delaunay triangulation the cavity
// is a disk with every vertex on its boundary (its dual is a tree): no triangle is
// reached twice, no marks are needed; the edge count checks it. Fills cav_ (nc
// triangles) and ball_ (m boundary edges); false when it is not a disk.
UVMESH_HULL_INLINE bool HullDelaunay::grow_cavity(std::int32_t t, Vec2 p, std::size_t& nc,
                                                  std::size_t& m) {
  const Tri* const T = tris.data();
  const Vec2* const P = pts.data();
  auto conflict = [&](const Tri& r) {
    // The inline filter decides almost always; a ghost (NaN coordinates) or a nearly
    // cocircular case falls through to conflict_slow.
    const double det =
        pred::detail::incircle_filter(&P[r.v[0]].x, &P[r.v[1]].x, &P[r.v[2]].x, &p.x);
    if (det != 0) [[likely]]
      return det > 0;
    return conflict_slow(r, p);
  };
  // Scratch arrays, grown on demand (a cavity can be large on cocircular input).
  const std::size_t cap_need = 3 * (tris.size() < 64 ? tris.size() : 64) + 8;
  if (stack_.size() < cap_need) {
    stack_.resize(cap_need);
    cav_.resize(cap_need);
    ball_.resize(cap_need);
  }
  std::int32_t* stk = stack_.data();
  std::int32_t* cav = cav_.data();
  NewTri* ball = ball_.data();
  std::size_t ns = 0;
  nc = 0, m = 0;
  // The triangles across the edges about to be tested are fetched ahead (the cavity test
  // of a neighbour waits on its vertex ids, then on their coordinates).
  __builtin_prefetch(&T[T[t].n[0] >> 2]);
  __builtin_prefetch(&T[T[t].n[1] >> 2]);
  __builtin_prefetch(&T[T[t].n[2] >> 2]);
  cav[nc++] = t;
  stk[ns++] = 4 * t + 2;
  stk[ns++] = 4 * t + 1;
  stk[ns++] = 4 * t + 0;
  while (ns > 0) {
    const std::int32_t h = stk[--ns];
    const Tri& r = T[h >> 2];
    const int e = h & 3;
    const std::int32_t g = r.n[e];
    const std::int32_t u = g >> 2;
    if (conflict(T[u])) {
      if (nc + 4 > cav_.size() || ns + 3 > stack_.size()) [[unlikely]] {
        cav_.resize(2 * cav_.size());
        stack_.resize(2 * stack_.size());
        ball_.resize(2 * ball_.size());
        stk = stack_.data();
        cav = cav_.data();
        ball = ball_.data();
      }
      cav[nc++] = u;
      const int j = g & 3;
      __builtin_prefetch(&T[T[u].n[prev3(j)] >> 2]);
      __builtin_prefetch(&T[T[u].n[next3(j)] >> 2]);
      stk[ns++] = 4 * u + prev3(j);
      stk[ns++] = 4 * u + next3(j);
    } else {
      // Boundary edge (a, b) of the cavity, seen from inside; g is its outer twin.
      ball[m++] = {r.v[next3(e)], r.v[prev3(e)], g};
    }
  }
  return m == nc + 2;  // else not a disk: cannot happen (exact predicates)
}

// Ball (eq. 7.2): triangle k = (a_k, b_k, p) on boundary edge k; the cavity's slots
// are reused and two are added. Consecutive ones share the edge (b_k = a_k+1, p).
UVMESH_HULL_INLINE bool HullDelaunay::make_ball(VertId pv, std::size_t nc, std::size_t m) {
  Tri* const T = tris.data();
  std::int32_t* cav = cav_.data();
  const NewTri* ball = ball_.data();
  const std::int32_t nt = static_cast<std::int32_t>(tris.size());
  cav[nc++] = nt;
  cav[nc++] = nt + 1;
  cav[m] = cav[0];  // the ring closes (room: the growth check above keeps 4 spare slots)
  tris.resize(tris.size() + 2);  // within the reserved capacity: T stays valid
  std::int32_t real = -1;
  std::int32_t sp = cav[m - 1];
  for (std::size_t k = 0; k < m; ++k) {
    const std::int32_t s = cav[k];
    const std::int32_t sn = cav[k + 1];
    const NewTri b = ball[k];
    Tri& r = T[s];
    r.v[0] = b.a;
    r.v[1] = b.b;
    r.v[2] = pv;
    r.n[0] = 4 * sn + 1;  // (b_k, p)  <->  (p, a_k+1) of the next
    r.n[1] = 4 * sp + 0;  // (p, a_k)  <->  (b_k-1, p) of the previous
    r.n[2] = b.out;
    T[b.out >> 2].n[b.out & 3] = 4 * s + 2;
    if (real < 0 && b.a != ghost_id && b.b != ghost_id) real = s;
    sp = s;
  }
  last_ = real;
  return real >= 0;
}

bool HullDelaunay::insert(VertId pv) {
  const Vec2 p = pts[pv];
  double o[3];
  const std::int32_t t = walk(p, o);
  if (t < 0) return false;
  if (!ghost(tris[t])) {
    // On two edges of t: p is their common vertex, an exact duplicate.
    for (int i = 0; i < 3; ++i)
      if (o[next3(i)] == 0 && o[prev3(i)] == 0) {
        const VertId v = tris[t].v[i];
        if (pts[v].x != p.x || pts[v].y != p.y) return false;  // cannot happen (exact)
        dups.push_back({pv, v});
        return true;
      }
  }
  std::size_t nc = 0, m = 0;
  if (!grow_cavity(t, p, nc, m)) return false;
  return make_ball(pv, nc, m);
}
}  // namespace uvmesh::m2d::detail
