// Local modification operators for mesh optimization (reference chapter §7.3.6: "remove
// edges (by merging their endpoints)" and edge splits), kept apart from the Delaunay
// kernel in triangulation.cpp. Both operators keep every triangle counter-clockwise
// (checked with the exact orientation predicate before anything changes) and the
// neighbour and constraint arrays symmetric.
#include <algorithm>

#include "triangulation.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

namespace {
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return pred::orient2d(&a.x, &b.x, &c.x);
}
}  // namespace

bool Triangulation::collapse_edge(VertId v, VertId u, Vec2 p) {
  if (v < 4 || u < 4 || v == u || vtri_[v] == kNone || vtri_[u] == kNone) return false;
  // The ball of v, counter-clockwise; every edge around v must be unconstrained.
  std::vector<TriId>& ball = cav_;
  ball.clear();
  const TriId t0 = vtri_[v];
  TriId t = t0;
  int guard = 0;
  do {
    int k = 0;
    while (tv_[3 * t + k] != v) ++k;
    if (seg_[3 * t + next3(k)] != kNone || seg_[3 * t + prev3(k)] != kNone) return false;
    ball.push_back(t);
    const std::int32_t h = opp_[3 * t + next3(k)];
    if (h == kNone || ++guard > 256) return false;
    t = h / 3;
  } while (t != t0);
  // The two triangles holding the edge (v, u), and the link condition: the common
  // neighbours of u and v are exactly their third vertices.
  TriId rem[2] = {kNone, kNone};
  int nrem = 0;
  for (const TriId b : ball)
    for (int i = 0; i < 3; ++i)
      if (tv_[3 * b + i] == u) {
        if (nrem == 2) return false;
        rem[nrem++] = b;
      }
  if (nrem != 2) return false;
  auto third = [&](TriId b) {
    for (int i = 0; i < 3; ++i)
      if (tv_[3 * b + i] != u && tv_[3 * b + i] != v) return tv_[3 * b + i];
    return kNone;
  };
  const VertId x = third(rem[0]), y = third(rem[1]);
  // Neighbours of u (turning through opp_; u may lie on a constrained edge, never on the box).
  std::vector<VertId>& nbu = nb_scratch_;
  nbu.clear();
  std::vector<TriId>& ballu = stack_;
  ballu.clear();
  {
    const TriId s0 = vtri_[u];
    TriId s = s0;
    guard = 0;
    do {
      int k = 0;
      while (tv_[3 * s + k] != u) ++k;
      nbu.push_back(tv_[3 * s + next3(k)]);
      ballu.push_back(s);
      const std::int32_t h = opp_[3 * s + next3(k)];
      if (h == kNone || ++guard > 256) return false;
      s = h / 3;
    } while (s != s0);
  }
  for (const TriId b : ball) {
    int k = 0;
    while (tv_[3 * b + k] != v) ++k;
    const VertId w = tv_[3 * b + next3(k)];
    if (w != u && w != x && w != y && std::find(nbu.begin(), nbu.end(), w) != nbu.end())
      return false;
  }
  // Orientation of every surviving triangle with u at p (those of v become u's).
  for (const TriId b : ball) {
    if (b == rem[0] || b == rem[1]) continue;
    int k = 0;
    while (tv_[3 * b + k] != v) ++k;
    if (orient(p, pts_[tv_[3 * b + next3(k)]], pts_[tv_[3 * b + prev3(k)]]) <= 0) return false;
  }
  for (const TriId b : ballu) {
    if (b == rem[0] || b == rem[1]) continue;
    int k = 0;
    while (tv_[3 * b + k] != u) ++k;
    if (orient(p, pts_[tv_[3 * b + next3(k)]], pts_[tv_[3 * b + prev3(k)]]) <= 0) return false;
  }
  // Remove the two triangles: across each, the neighbours of its edges (u, z) and (z, v)
  // become neighbours of each other (the edge (v, z) turns into (u, z)).
  for (const TriId r : rem) {
    int kv = 0, ku = 0;
    while (tv_[3 * r + kv] != v) ++kv;
    while (tv_[3 * r + ku] != u) ++ku;
    const std::int32_t huz = opp_[3 * r + kv];  // edge opposite v: (u, z)
    const std::int32_t hzv = opp_[3 * r + ku];  // edge opposite u: (z, v)
    const std::int32_t s = seg_[3 * r + kv];
    if (huz != kNone) opp_[huz] = hzv;
    if (hzv != kNone) opp_[hzv] = huz;
    if (hzv != kNone) seg_[hzv] = s;
    const VertId z = tv_[3 * r + 3 - kv - ku];
    vtri_[z] = huz != kNone ? huz / 3 : hzv / 3;
  }
  for (const TriId b : ball) {
    if (b == rem[0] || b == rem[1]) continue;
    for (int i = 0; i < 3; ++i)
      if (tv_[3 * b + i] == v) tv_[3 * b + i] = u;
    vtri_[u] = b;
  }
  for (const TriId r : rem) {
    tv_[3 * r] = kNone;
    free_.push_back(r);
  }
  if (vtri_[u] == rem[0] || vtri_[u] == rem[1])
    for (const TriId b : ballu)
      if (b != rem[0] && b != rem[1]) vtri_[u] = b;
  vtri_[v] = kNone;
  pts_[u] = p;
  return true;
}

VertId Triangulation::split_edge(std::int32_t h, Vec2 p) {
  const std::int32_t g = opp_[h];
  if (g == kNone || seg_[h] != kNone) return kNone;
  const TriId t = h / 3, u = g / 3;
  const int i = h % 3, j = g % 3;
  // t = (c, a, b) seen from edge i, u = (d, b, a).
  const VertId c = tv_[3 * t + i], a = tv_[3 * t + next3(i)], b = tv_[3 * t + prev3(i)];
  const VertId d = tv_[3 * u + j];
  if (orient(pts_[c], pts_[a], p) <= 0 || orient(pts_[c], p, pts_[b]) <= 0 ||
      orient(pts_[d], pts_[b], p) <= 0 || orient(pts_[d], p, pts_[a]) <= 0)
    return kNone;
  const VertId m = add_vertex(p);
  const std::int32_t n_bc = opp_[3 * t + next3(i)], s_bc = seg_[3 * t + next3(i)];
  const std::int32_t n_ca = opp_[3 * t + prev3(i)], s_ca = seg_[3 * t + prev3(i)];
  const std::int32_t n_ad = opp_[3 * u + next3(j)], s_ad = seg_[3 * u + next3(j)];
  const std::int32_t n_db = opp_[3 * u + prev3(j)], s_db = seg_[3 * u + prev3(j)];
  const TriId t2 = new_tri(), u2 = new_tri();
  const std::int32_t the_tag = tag_[t];
  // t = (c, a, m), t2 = (c, m, b), u = (d, b, m), u2 = (d, m, a).
  auto set = [&](TriId s, VertId p0, VertId p1, VertId p2) {
    tv_[3 * s] = p0, tv_[3 * s + 1] = p1, tv_[3 * s + 2] = p2;
    seg_[3 * s] = seg_[3 * s + 1] = seg_[3 * s + 2] = kNone;
    tag_[s] = the_tag;
  };
  set(t, c, a, m);
  set(t2, c, m, b);
  set(u, d, b, m);
  set(u2, d, m, a);
  // Local numbering (edge i opposite vertex i): t = (c, a, m): e0 (a, m), e1 (m, c),
  // e2 (c, a); t2 = (c, m, b): e0 (m, b), e1 (b, c), e2 (c, m); u = (d, b, m): e0 (b, m),
  // e1 (m, d), e2 (d, b); u2 = (d, m, a): e0 (m, a), e1 (a, d), e2 (d, m).
  link(3 * t + 2, n_ca), seg_[3 * t + 2] = s_ca;
  link(3 * t2 + 1, n_bc), seg_[3 * t2 + 1] = s_bc;
  link(3 * u + 2, n_db), seg_[3 * u + 2] = s_db;
  link(3 * u2 + 1, n_ad), seg_[3 * u2 + 1] = s_ad;
  link(3 * t + 0, 3 * u2 + 0);
  link(3 * t + 1, 3 * t2 + 2);
  link(3 * t2 + 0, 3 * u + 0);
  link(3 * u + 1, 3 * u2 + 2);
  vtri_[m] = t;
  vtri_[a] = t, vtri_[b] = u, vtri_[c] = t, vtri_[d] = u;
  if (mark_.size() < static_cast<std::size_t>(num_tris())) mark_.resize(2 * num_tris() + 8, 0);
  return m;
}

}  // namespace uvmesh::m2d::detail
