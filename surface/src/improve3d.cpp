// Stage 2b: improvement of a face mesh in 3D (reference chapter §7.3.6 applied to the
// mapped mesh, §7.6.2). The (u,v) mesh was built under the induced metric, which is the
// 3D metric only to first order; on the mapped surface, edge swaps and vertex relocation
// are judged by the 3D shape measure Q_K (eq. 7.6). Vertices move in (u,v) and are
// mapped back through sigma, so they stay exactly on the surface; validity is kept in
// (u,v) (every triangle stays counter-clockwise), boundary vertices never move.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

#include "internal.h"
#include "uvmesh/mesher2d/measures.h"

namespace uvmesh::surface::detail {

double q3(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c) {
  const double la = glm::length(b - c), lb = glm::length(c - a), lc = glm::length(a - b);
  const double area2 = glm::length(glm::cross(b - a, c - a));
  if (!(std::max({la, lb, lc}) > 0)) return 0.0;
  return measures::shape_q(la, lb, lc, area2);
}

namespace {

double orient_uv(const geom::Vec2& a, const geom::Vec2& b, const geom::Vec2& c) {
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

geom::Vec3 unit_normal(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c) {
  const geom::Vec3 n = glm::cross(b - a, c - a);
  const double l = glm::length(n);
  return l > 0 ? n / l : geom::Vec3(0.0);
}

struct Improver {
  LocalMesh& lm;
  const geom::Surface& s;
  std::vector<std::int32_t> opp;  // half-edge 3t+i (edge opposite corner i) -> twin or -1

  double q(int t) const {
    const auto& v = lm.tris[static_cast<std::size_t>(t)];
    return q3(lm.p[v[0]], lm.p[v[1]], lm.p[v[2]]);
  }

  void build_adjacency() {
    const std::size_t nt = lm.tris.size();
    opp.assign(3 * nt, -1);
    std::unordered_map<std::uint64_t, std::int32_t> half;
    half.reserve(3 * nt);
    auto key = [](int a, int b) {
      return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) |
             static_cast<std::uint32_t>(b);
    };
    for (std::size_t t = 0; t < nt; ++t)
      for (int i = 0; i < 3; ++i) {
        const int a = lm.tris[t][(i + 1) % 3], b = lm.tris[t][(i + 2) % 3];
        half[key(a, b)] = static_cast<std::int32_t>(3 * t + i);
      }
    for (std::size_t t = 0; t < nt; ++t)
      for (int i = 0; i < 3; ++i) {
        const int a = lm.tris[t][(i + 1) % 3], b = lm.tris[t][(i + 2) % 3];
        auto it = half.find(key(b, a));
        if (it != half.end()) opp[3 * t + i] = it->second;
      }
  }

  bool same_node(int a, int b) const {
    return a == b ||
           (lm.global[static_cast<std::size_t>(a)] >= 0 &&
            lm.global[static_cast<std::size_t>(a)] == lm.global[static_cast<std::size_t>(b)]);
  }

  // One sweep of quality swaps: the diagonal of two triangles is swapped when the worse
  // of the two 3D qualities improves, both new triangles stay CCW in (u,v), and the fold
  // between them stays moderate (a swap on a curved surface must not turn the
  // approximation inside out).
  int swap_pass() {
    int swaps = 0;
    const auto nt = static_cast<std::int32_t>(lm.tris.size());
    for (std::int32_t t = 0; t < nt; ++t)
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = opp[3 * t + i];
        if (h < 0) continue;
        const std::int32_t u = h / 3;
        const int j = h % 3;
        if (u < t) continue;
        auto& T = lm.tris[static_cast<std::size_t>(t)];
        auto& U = lm.tris[static_cast<std::size_t>(u)];
        const int a = T[i], b = T[(i + 1) % 3], c = T[(i + 2) % 3], d = U[j];
        if (same_node(a, d)) continue;
        const auto &ua = lm.uv[a], &ub = lm.uv[b], &uc = lm.uv[c], &ud = lm.uv[d];
        if (!(orient_uv(ua, ub, ud) > 0) || !(orient_uv(ua, ud, uc) > 0)) continue;
        const auto &pa = lm.p[a], &pb = lm.p[b], &pc = lm.p[c], &pd = lm.p[d];
        const double before = std::min(q3(pa, pb, pc), q3(pd, pc, pb));
        const double after = std::min(q3(pa, pb, pd), q3(pa, pd, pc));
        if (!(after > before * 1.02 + 1e-12)) continue;
        const double fold_old = glm::dot(unit_normal(pa, pb, pc), unit_normal(pd, pc, pb));
        const double fold_new = glm::dot(unit_normal(pa, pb, pd), unit_normal(pa, pd, pc));
        if (fold_new < std::min(fold_old, 0.8)) continue;
        // Both new triangles face the side the old pair faced (two triangles turned over
        // together pass the fold test; near the fold lines of a swept tube they did).
        const geom::Vec3 n_old = unit_normal(pa, pb, pc) + unit_normal(pd, pc, pb);
        if (!(glm::dot(unit_normal(pa, pb, pd), n_old) > 0) ||
            !(glm::dot(unit_normal(pa, pd, pc), n_old) > 0))
          continue;
        // New triangles (a,b,d) in t and (a,d,c) in u; relink the four outer half-edges.
        const std::int32_t o_ab = opp[3 * t + (i + 2) % 3];  // edge a-b of t (opposite c)
        const std::int32_t o_ca = opp[3 * t + (i + 1) % 3];  // edge c-a of t (opposite b)
        const std::int32_t o_bd =
            opp[3 * u + (j + 1) % 3];  // edge b-d of u (U = d,c,b ordered from j)
        const std::int32_t o_dc = opp[3 * u + (j + 2) % 3];  // edge d-c of u
        T = {a, b, d};
        U = {a, d, c};
        auto link = [&](std::int32_t x, std::int32_t y) {
          opp[x] = y;
          if (y >= 0) opp[y] = x;
        };
        // t = (a,b,d): opposite a is b-d, opposite b is d-a, opposite d is a-b.
        // u = (a,d,c): opposite a is d-c, opposite d is c-a, opposite c is a-d.
        link(3 * t + 0, o_bd);
        link(3 * t + 2, o_ab);
        link(3 * u + 0, o_dc);
        link(3 * u + 1, o_ca);
        link(3 * t + 1, 3 * u + 2);
        ++swaps;
      }
    return swaps;
  }

  // Move v to the 3D target c: the step is pulled back to (u,v) through the Jacobian
  // (one Gauss-Newton step of the projection on the surface), then mapped through sigma.
  // Tried at full, half and quarter length; kept when the worst incident quality rises
  // above `floor` and every incident triangle stays counter-clockwise in (u,v). Returns
  // the new worst quality, or -1 (v restored) when no step qualifies.
  double try_move(std::size_t v, const std::vector<std::int32_t>& ring, const geom::SurfacePoint& e,
                  const geom::Vec3& c, double floor) {
    const geom::Vec3 dx = c - lm.p[v];
    const double E = glm::dot(e.du, e.du), F = glm::dot(e.du, e.dv), G = glm::dot(e.dv, e.dv);
    const double det = E * G - F * F;
    if (!(det > 1e-300)) return -1.0;
    const double bu = glm::dot(e.du, dx), bv = glm::dot(e.dv, dx);
    const geom::Vec2 duv{(G * bu - F * bv) / det, (E * bv - F * bu) / det};
    const geom::Vec2 old_uv = lm.uv[v];
    const geom::Vec3 old_p = lm.p[v];
    // The ring's own side: the area-weighted normal of v's triangles before the move. A
    // ring that faces away from sigma_u x sigma_v at v (v on a line where the surface
    // folds over itself) does not move. (Judging every triangle against sigma_u x sigma_v
    // at v instead rejected moves on a terrain surface where a few triangles of a ring
    // already face away, and left triangles above Q 3 there.)
    geom::Vec3 n0(0.0);
    for (std::int32_t t : ring) {
      const auto& T = lm.tris[static_cast<std::size_t>(t)];
      n0 += glm::cross(lm.p[T[1]] - lm.p[T[0]], lm.p[T[2]] - lm.p[T[0]]);
    }
    if (glm::dot(n0, glm::cross(e.du, e.dv)) <= 0)
      return -1.0;  // the ring faces away from the surface
    auto faces_n0 = [&](std::int32_t t) {
      const auto& T = lm.tris[static_cast<std::size_t>(t)];
      return glm::dot(glm::cross(lm.p[T[1]] - lm.p[T[0]], lm.p[T[2]] - lm.p[T[0]]), n0) > 0;
    };
    // Which ring triangles face that side now: only those must still face it after the
    // move (requiring it of all blocked moves that repair a triangle already turned, and
    // left self-intersections and triangles of Q > 3).
    std::uint64_t was_facing = 0;
    for (std::size_t k = 0; k < ring.size() && k < 64; ++k)
      if (faces_n0(ring[k])) was_facing |= std::uint64_t{1} << k;
    for (double step : {1.0, 0.5, 0.25}) {
      lm.uv[v] = old_uv + step * duv;
      bool valid = true;
      for (std::int32_t t : ring) {
        const auto& T = lm.tris[static_cast<std::size_t>(t)];
        if (!(orient_uv(lm.uv[T[0]], lm.uv[T[1]], lm.uv[T[2]]) > 0)) {
          valid = false;
          break;
        }
      }
      if (!valid) continue;
      lm.p[v] = s.point(lm.uv[v].x, lm.uv[v].y);
      // No incident triangle may turn away from the ring's side: where the surface folds
      // over itself (a swept tube whose normal reverses across lines where sigma_u x
      // sigma_v vanishes) a step that is valid in (u,v) can land on the other sheet, and
      // 3D shape alone accepted triangles turned over or flat, with a chordal deviation
      // well beyond the tolerance.
      for (std::size_t k = 0; k < ring.size(); ++k)
        if ((k >= 64 || (was_facing >> k & 1)) && !faces_n0(ring[k])) {
          valid = false;
          break;
        }
      if (!valid) continue;
      double qn = 1.0;
      for (std::int32_t t : ring) qn = std::min(qn, q(t));
      if (qn > floor) return qn;
    }
    lm.uv[v] = old_uv;
    lm.p[v] = old_p;
    return -1.0;
  }

  // One sweep of relocation (§7.3.6): each free vertex whose incident triangles are not
  // already good moves toward the centroid of its ring. A vertex next to a bad triangle
  // (Q > 1.6) also tries the mean of the ideal points of its ring -- for each incident
  // triangle (v, a, b), the apex over a-b of the equilateral triangle in the tangent plane
  // -- and the ideal point of its worst triangle: a vertex squeezed against one edge (a cap
  // of 140 degrees over a boundary segment) is pushed off that edge, which the centroid
  // alone, pulled by the rest of the ring, does not do. Accepted when the worst incident
  // quality rises.
  int smooth_pass(const std::vector<std::vector<std::int32_t>>& ring) {
    int moves = 0;
    for (std::size_t v = 0; v < lm.uv.size(); ++v) {
      if (lm.fixed[v] || ring[v].empty()) continue;
      double qmin = 1.0;
      std::int32_t worst = -1;
      geom::Vec3 c(0.0);
      int nc = 0;
      for (std::int32_t t : ring[v]) {
        if (const double qt = q(t); qt < qmin) qmin = qt, worst = t;
        for (int k : lm.tris[static_cast<std::size_t>(t)])
          if (k != static_cast<int>(v)) c += lm.p[static_cast<std::size_t>(k)], ++nc;
      }
      if (qmin > 0.9 || nc == 0) continue;
      c /= static_cast<double>(nc);  // each ring vertex counted twice: the mean is unchanged
      const geom::SurfacePoint e = s.eval_first(lm.uv[v].x, lm.uv[v].y);  // sigma_u, sigma_v only
      double best = try_move(v, ring[v], e, c, qmin * 1.001);
      if (qmin < 1.0 / 1.6) {
        // The tangent-plane normal, oriented as the (u,v) triangles are (CCW in (u,v)
        // is CCW around du x dv).
        const geom::Vec3 n = unit_normal(geom::Vec3(0.0), e.du, e.dv);
        geom::Vec3 ideal_sum(0.0), ideal_worst(0.0);
        for (std::int32_t t : ring[v]) {
          const auto& T = lm.tris[static_cast<std::size_t>(t)];
          int k = 0;
          while (T[k] != static_cast<int>(v)) ++k;
          const geom::Vec3 &a = lm.p[T[(k + 1) % 3]], &b = lm.p[T[(k + 2) % 3]];
          // (v, a, b) is CCW: v lies to the left of a -> b, i.e. along n x (b - a).
          const geom::Vec3 apex = 0.5 * (a + b) + (std::sqrt(3.0) / 2.0) * glm::cross(n, b - a);
          ideal_sum += apex;
          if (t == worst) ideal_worst = apex;
        }
        const geom::Vec3 ideal = ideal_sum / static_cast<double>(ring[v].size());
        const geom::Vec3 cands[] = {ideal, 0.5 * (lm.p[v] + ideal_worst), ideal_worst};
        for (const geom::Vec3& cand : cands) {
          const geom::SurfacePoint ev = best > 0 ? s.eval_first(lm.uv[v].x, lm.uv[v].y) : e;
          const double got = try_move(v, ring[v], ev, cand, std::max(qmin, best) * 1.001);
          if (got > 0) best = got;
        }
      }
      if (best > 0) ++moves;
    }
    return moves;
  }

  // Edge collapse, the third operator of the optimization (§7.3.6 names swaps, moves and
  // point removal): a triangle still worse than Q = 1.5 (the quality target) after swaps
  // and smoothing -- a cap or needle wedged between sub-hmin boundary features next to a
  // corner, a free vertex squeezed into a strip one element wide, where no position of
  // it helps -- loses one free vertex v, merged into another vertex w of the triangle.
  // (At Q = 3 instead, a cage whose quads repeat a vertex, making cone tips where mesher2d
  // leaves such vertices, kept many more triangles above Q 1.5; the other subdivision
  // cages hardly change between the two.) Kept when the link condition holds (v and w share exactly
  // the two neighbours opposite their edge), every moved triangle stays CCW in (u,v) and
  // turns its normal by less than 60 degrees, and the worst quality of v's ball rises by
  // 5%. Collapsed triangles are marked {-1,-1,-1}; compact() removes them.
  int collapse_pass(std::vector<std::vector<std::int32_t>>& ring) {
    int collapses = 0;
    const auto nt = static_cast<std::int32_t>(lm.tris.size());
    std::vector<int> nv, nw;
    auto alive = [&](std::int32_t t) { return lm.tris[static_cast<std::size_t>(t)][0] >= 0; };
    auto neighbours = [&](int x, std::vector<int>& out) {
      out.clear();
      for (std::int32_t t : ring[static_cast<std::size_t>(x)])
        if (alive(t))
          for (int k : lm.tris[static_cast<std::size_t>(t)])
            if (k != x) out.push_back(k);
      std::sort(out.begin(), out.end());
      out.erase(std::unique(out.begin(), out.end()), out.end());
    };
    for (std::int32_t t = 0; t < nt; ++t) {
      if (!alive(t) || q(t) >= 1.0 / 1.5) continue;
      const std::array<int, 3> T = lm.tris[static_cast<std::size_t>(t)];
      int bv = -1, bw = -1;
      double bq = 0.0;
      for (int v : T) {
        if (lm.fixed[static_cast<std::size_t>(v)]) continue;
        double qold = 1.0;
        for (std::int32_t r : ring[static_cast<std::size_t>(v)])
          if (alive(r)) qold = std::min(qold, q(r));
        neighbours(v, nv);
        for (int w : T) {
          if (w == v) continue;
          neighbours(w, nw);
          int common = 0, shared = 0;
          for (int x : nv) common += std::binary_search(nw.begin(), nw.end(), x);
          for (std::int32_t r : ring[static_cast<std::size_t>(v)]) {
            if (!alive(r)) continue;
            const auto& R = lm.tris[static_cast<std::size_t>(r)];
            shared += R[0] == w || R[1] == w || R[2] == w;
          }
          if (common != 2 || shared != 2) continue;
          double qnew = 1.0;
          bool valid = true;
          for (std::int32_t r : ring[static_cast<std::size_t>(v)]) {
            if (!alive(r)) continue;
            std::array<int, 3> R = lm.tris[static_cast<std::size_t>(r)];
            if (R[0] == w || R[1] == w || R[2] == w) continue;
            const geom::Vec3 n_old = unit_normal(lm.p[R[0]], lm.p[R[1]], lm.p[R[2]]);
            for (int& k : R)
              if (k == v) k = w;
            if (!(orient_uv(lm.uv[R[0]], lm.uv[R[1]], lm.uv[R[2]]) > 0) ||
                glm::dot(n_old, unit_normal(lm.p[R[0]], lm.p[R[1]], lm.p[R[2]])) < 0.5) {
              valid = false;
              break;
            }
            qnew = std::min(qnew, q3(lm.p[R[0]], lm.p[R[1]], lm.p[R[2]]));
          }
          if (valid && qnew > qold * 1.05 && qnew > bq) bq = qnew, bv = v, bw = w;
        }
      }
      if (bv < 0) continue;
      for (std::int32_t r : ring[static_cast<std::size_t>(bv)]) {
        if (!alive(r)) continue;
        auto& R = lm.tris[static_cast<std::size_t>(r)];
        if (R[0] == bw || R[1] == bw || R[2] == bw) {
          R = {-1, -1, -1};
          continue;
        }
        for (int& k : R)
          if (k == bv) k = bw;
        ring[static_cast<std::size_t>(bw)].push_back(r);
      }
      ring[static_cast<std::size_t>(bv)].clear();
      ++collapses;
    }
    return collapses;
  }

  void compact() {
    std::size_t w = 0;
    for (std::size_t t = 0; t < lm.tris.size(); ++t)
      if (lm.tris[t][0] >= 0) lm.tris[w++] = lm.tris[t];
    lm.tris.resize(w);
  }
};

}  // namespace

std::array<int, 2> improve3d(LocalMesh& lm, const geom::Surface& s, int passes, bool collapse) {
  Improver im{lm, s, {}};
  im.build_adjacency();
  int swaps = 0, moves = 0;
  std::vector<std::vector<std::int32_t>> ring;
  for (int pass = 0; pass < passes; ++pass) {
    int sw = 0;
    for (int k = 0; k < 3; ++k) {
      const int n = im.swap_pass();
      sw += n;
      if (n == 0) break;
    }
    ring.assign(lm.uv.size(), {});
    for (std::size_t t = 0; t < lm.tris.size(); ++t)
      for (int k : lm.tris[t])
        ring[static_cast<std::size_t>(k)].push_back(static_cast<std::int32_t>(t));
    const int mv = im.smooth_pass(ring);
    const int cl = collapse ? im.collapse_pass(ring) : 0;
    if (cl > 0) {
      im.compact();
      im.build_adjacency();
    }
    swaps += sw;
    moves += mv;
    if (sw == 0 && cl == 0 && mv < static_cast<int>(lm.uv.size() / 50)) break;
  }
  return {swaps, moves};
}

}  // namespace uvmesh::surface::detail
