// The Delaunay kernel T(i+1) = T(i) - C(P) + B(P) (§7.1, eq. 7.2 and §7.3.2), its
// anisotropic variant (§7.6.1, eq. 7.15-7.16) and boundary enforcement by diagonal swaps
// (§7.2.2). Every geometric decision goes through the exact predicates.
#include "triangulation.h"

#include <cmath>
#include <deque>
#include <utility>

#include "huge_pages.h"
#include "predicates_filter.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

namespace {
inline double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return pred::detail::orient2d_filtered(&a.x, &b.x, &c.x);
}
}  // namespace

void Triangulation::init_box(double xmin, double ymin, double xmax, double ymax,
                             std::size_t reserve_pts) {
  pts_.clear();
  vtri_.clear();
  tv_.clear();
  opp_.clear();
  seg_.clear();
  tag_.clear();
  free_.clear();
  pts_.reserve(reserve_pts + 4);
  vtri_.reserve(reserve_pts + 4);
  tv_.reserve(6 * reserve_pts + 12);
  opp_.reserve(6 * reserve_pts + 12);
  seg_.reserve(6 * reserve_pts + 12);
  tag_.reserve(2 * reserve_pts + 4);
  pts_ = {{xmin, ymin}, {xmax, ymin}, {xmax, ymax}, {xmin, ymax}};
  // t0 = (0,1,2), t1 = (0,2,3); t0's e1 (2->0) is t1's e2 (0->2).
  tv_ = {0, 1, 2, 0, 2, 3};
  opp_.assign(6, kNone);
  seg_.assign(6, kNone);
  tag_.assign(2, 0);
  link(1, 5);
  vtri_ = {0, 0, 0, 1};
}

void Triangulation::reserve_huge(std::size_t nv) {
  detail::reserve_huge(pts_, nv), detail::reserve_huge(vtri_, nv);
  detail::reserve_huge(tv_, 6 * nv), detail::reserve_huge(opp_, 6 * nv);
  detail::reserve_huge(seg_, 6 * nv), detail::reserve_huge(tag_, 2 * nv);
}

VertId Triangulation::add_vertex(Vec2 p) {
  pts_.push_back(p);
  vtri_.push_back(kNone);
  return static_cast<VertId>(pts_.size() - 1);
}

TriId Triangulation::new_tri() {
  if (!free_.empty()) {
    TriId t = free_.back();
    free_.pop_back();
    return t;
  }
  TriId t = num_tris();
  for (int i = 0; i < 3; ++i) {
    tv_.push_back(kNone);
    opp_.push_back(kNone);
    seg_.push_back(kNone);
  }
  tag_.push_back(0);
  return t;
}

TriId Triangulation::locate(Vec2 p, TriId hint) const {
  return locate(p, hint, nullptr);
}

TriId Triangulation::locate(Vec2 p, TriId hint, double* orients) const {
  TriId t = hint;
  if (t == kNone || t >= num_tris() || dead(t)) {
    t = kNone;
    for (TriId s = num_tris() - 1; s >= 0; --s)
      if (!dead(s)) {
        t = s;
        break;
      }
    if (t == kNone) return kNone;
  }
  // Stochastic visibility walk: it terminates with probability one in any triangulation,
  // Delaunay or not (constrained, or after swaps); the cap is a guard against bugs. The
  // edge a step entered by is not tested again: p is strictly on its inner side (the
  // exact orientation is antisymmetric, and it was negative from the other side), so
  // its orientation is reported as 1; of the other two, a random one first.
  const std::int64_t cap = 4 * static_cast<std::int64_t>(num_tris()) + 64;
  const VertId* const TV = tv_.data();
  const Vec2* const P = pts_.data();
  auto side = [&](TriId s, int i) {
    return orient(P[TV[3 * s + next3(i)]], P[TV[3 * s + prev3(i)]], p);
  };
  int entered = -1;
  for (std::int64_t step = 0; step < cap; ++step) {
    rng_ ^= rng_ << 13;
    rng_ ^= rng_ >> 7;
    rng_ ^= rng_ << 17;
    int cross = -1;
    double o[3];
    if (entered < 0) {
      const int r = static_cast<int>(rng_ % 3);
      for (int k = 0; k < 3; ++k) {
        const int i = (r + k) % 3;
        o[i] = side(t, i);
        if (o[i] < 0) {
          cross = i;
          break;
        }
      }
    } else {
      o[entered] = 1;
      const bool swap = (rng_ >> 17) & 1;
      const int i1 = swap ? prev3(entered) : next3(entered),
                i2 = swap ? next3(entered) : prev3(entered);
      o[i1] = side(t, i1);
      if (o[i1] < 0) {
        cross = i1;
      } else {
        o[i2] = side(t, i2);
        if (o[i2] < 0) cross = i2;
      }
    }
    if (cross < 0) {
      if (orients) orients[0] = o[0], orients[1] = o[1], orients[2] = o[2];
      return t;
    }
    const std::int32_t h = opp_[3 * t + cross];
    if (h == kNone) return kNone;  // outside the box
    t = h / 3;
    entered = h - 3 * t;
  }
  // Fallback (never seen): exhaustive search.
  for (TriId s = 0; s < num_tris(); ++s) {
    if (dead(s)) continue;
    bool in = true;
    for (int i = 0; i < 3 && in; ++i)
      in = orient(pts_[tv_[3 * s + next3(i)]], pts_[tv_[3 * s + prev3(i)]], p) >= 0;
    if (in) {
      if (orients)
        for (int i = 0; i < 3; ++i)
          orients[i] = orient(pts_[tv_[3 * s + next3(i)]], pts_[tv_[3 * s + prev3(i)]], p);
      return s;
    }
  }
  return kNone;
}

bool Triangulation::in_cavity_metric(TriId t, Vec2 p,
                                     const InsertParams& /*prm: its frame is frame_*/) const {
  const Vec2& a = pts_[tv_[3 * t]];
  const Vec2& b = pts_[tv_[3 * t + 1]];
  const Vec2& c = pts_[tv_[3 * t + 2]];
  // eq. 7.15-7.16 with M approached by M(P): in coordinates where M(P) is the identity
  // (x -> R x with M = R^T R, R upper triangular with a positive diagonal, so orientation is
  // kept) the metric circumcircle of K is the Euclidean one, and alpha_M(P)(P,K) < 1 is an
  // incircle test. Coordinates are taken relative to P to keep the rounding local.
  // R is factored once per insertion (insert_located sets frame_), not once per tested
  // triangle: two square roots and a division fewer on every cavity test.
  const double l11 = frame_[0], l12 = frame_[1], l22 = frame_[2];
  auto tr = [&](const Vec2& q) {
    const double dx = q.x - p.x, dy = q.y - p.y;
    return Vec2{l11 * dx + l12 * dy, l22 * dy};
  };
  const Vec2 ta = tr(a), tb = tr(b), tc = tr(c), tp{0, 0};
  return pred::detail::incircle_filtered(&ta.x, &tb.x, &tc.x, &tp.x) > 0;
}

InsertResult Triangulation::insert_point(Vec2 p, TriId hint, const InsertParams& prm) {
  const VertId v = add_vertex(p);
  InsertResult r = insert(v, hint, prm);
  if (r.status != InsertStatus::Inserted) {
    pts_.pop_back();
    vtri_.pop_back();
  }
  return r;
}

InsertResult Triangulation::insert(VertId v, TriId hint, const InsertParams& prm) {
  double o0[3];
  const TriId t0 = locate(pts_[v], hint, o0);
  if (t0 == kNone) return {InsertStatus::Outside, kNone};
  return insert_located(v, t0, o0, prm);
}

InsertResult Triangulation::insert_point_located(Vec2 p, TriId t0, const double* o0,
                                                 const InsertParams& prm) {
  const VertId v = add_vertex(p);
  InsertResult r = insert_located(v, t0, o0, prm);
  if (r.status != InsertStatus::Inserted) {
    pts_.pop_back();
    vtri_.pop_back();
  }
  return r;
}

InsertResult Triangulation::insert_located(VertId v, TriId t0, const double* o0,
                                           const InsertParams& prm) {
  const Vec2 p = pts_[v];
  if (prm.use_metric) {
    // M(P) = R^T R, R = [[l11, l12], [0, l22]]: the frame of in_cavity_metric's test.
    const double l11 = std::sqrt(prm.m.m11);
    const double l12 = prm.m.m12 / l11;
    frame_ = {l11, l12, std::sqrt(std::max(prm.m.m22 - l12 * l12, 1e-300))};
  }
  if (o0[0] != 0 && o0[1] != 0 && o0[2] != 0 && cavity_unmarked(t0, p, prm))
    return make_ball(v, t0, prm, fcav_.data(), fnc_, fbd_.data(), fm_);
  if (mark_.size() < static_cast<std::size_t>(num_tris()) + 8) mark_.resize(2 * num_tris() + 8, 0);
  if (epoch_ > 0xFFFFFFF0u) {
    std::fill(mark_.begin(), mark_.end(), 0);
    epoch_ = 0;
  }
  epoch_ += 3;
  const std::uint32_t IN = epoch_, OUT = epoch_ + 1, CAND = epoch_ + 2;
  std::uint32_t* const mark = mark_.data();
  const VertId* const TV = tv_.data();
  const std::int32_t* const OPP = opp_.data();
  const std::int32_t* const SEG = seg_.data();
  const Vec2* const P = pts_.data();

  cav_.clear();
  cav_.push_back(t0);
  mark[t0] = IN;
  // The base (§7.3.2 step 1): the triangle containing P, plus its neighbour when P lies on
  // an edge. A point on a vertex is a duplicate.
  for (int i = 0; i < 3; ++i) {
    if (o0[i] != 0) continue;
    const VertId a = TV[3 * t0 + next3(i)], b = TV[3 * t0 + prev3(i)];
    if (P[a].x == p.x && P[a].y == p.y) return {InsertStatus::Duplicate, a};
    if (P[b].x == p.x && P[b].y == p.y) return {InsertStatus::Duplicate, b};
    const std::int32_t h = OPP[3 * t0 + i];
    if (h == kNone) return {InsertStatus::Outside, kNone};
    if (SEG[3 * t0 + i] != kNone && !prm.allow_on_constraint)
      return {InsertStatus::OnConstraint, kNone};
    if (mark[h / 3] != IN) {
      mark[h / 3] = IN;
      cav_.push_back(h / 3);
    }
  }
  const std::size_t nbase = cav_.size();

  // Cavity grown by adjacency, never across a constrained edge (§7.2.1). The boundary
  // half-edges (inside side) are collected on the way: a neighbour's status is decided the
  // first time it is seen and never changes.
  bnd_.clear();
  for (std::size_t k = 0; k < cav_.size(); ++k) {
    const TriId t = cav_[k];
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = OPP[3 * t + i];
      if (h == kNone || SEG[3 * t + i] != kNone) {
        if (h == kNone || mark[h / 3] != IN) bnd_.push_back(3 * t + i);
        continue;
      }
      const TriId n = h / 3;
      const std::uint32_t mk = mark[n];
      if (mk == IN) continue;
      const bool in = mk != OUT && in_cavity(n, p, prm);
      if (in) {
        mark[n] = IN;
        cav_.push_back(n);
      } else {
        mark[n] = OUT;
        bnd_.push_back(3 * t + i);
      }
    }
  }

  // One pass over the boundary: the star-shapedness check, the field-point filter and the
  // boundary edges of the ball.
  // Star-shapedness check and correction: every boundary edge of the cavity must see P
  // strictly on its left. Guaranteed for the exact isotropic kernel on a (constrained)
  // Delaunay mesh (§7.1.3); needed for the anisotropic kernel (§7.6.1), where the
  // criterion uses M(P) only. Checked always: a few filtered orientation tests.
  // Field-point filter (after the loop): the nearest existing vertex is a cavity vertex.
  auto& bd = bd_;
  for (int attempt = 0;; ++attempt) {
    bd.resize(bnd_.size());
    BoundaryEdge* const B = bd.data();
    bool bad = false;
    for (std::size_t k = 0; k < bnd_.size(); ++k) {
      const std::int32_t h = bnd_[k];
      const int i = h % 3;
      const std::int32_t base = h - i;
      const VertId a = TV[base + next3(i)], b = TV[base + prev3(i)];
      B[k] = {a, b, OPP[h], SEG[h]};
      if (pred::detail::orient2d_filtered(&P[a].x, &P[b].x, &p.x) <= 0) {
        bad = true;
        break;
      }
    }
    if (!bad) break;
    if (attempt > 0 || !star_correct(p, nbase, IN, OUT, CAND))
      return {InsertStatus::BadCavity, kNone};
  }
  return make_ball(v, t0, prm, cav_.data(), cav_.size(), bd.data(), bnd_.size());
}

// Cavity of a point strictly inside t0 (§7.3.2 steps 2-3) without the marks of the
// general path: breadth first from t0 in the same order as insert_located's, a
// neighbour reached through the edge a triangle was entered by being its parent. When the
// cavity is a disk whose triangles' dual is a tree (every valid cavity: a disk with all
// its vertices on the boundary) this collects the same cavity and the same boundary
// half-edges in the same order, and checks that every boundary edge sees P strictly on
// its left (star shape). A cycle among conflicting triangles (a vertex inside, or a
// region around an obstacle) makes the walk revisit triangles forever, stopped by the
// size cap; that, a boundary edge not seeing P, or a larger cavity returns false and the
// general path decides (with marks, star-shape correction and its counts). Reading and
// writing the per-triangle marks (a word per triangle, away from the triangle's own data)
// was a cache miss per tested neighbour.
bool Triangulation::cavity_unmarked(TriId t0, Vec2 p, const InsertParams& prm) {
  const VertId* const TV = tv_.data();
  const std::int32_t* const OPP = opp_.data();
  const std::int32_t* const SEG = seg_.data();
  const Vec2* const P = pts_.data();
  TriId* const cav = fcav_.data();
  std::int32_t* const par = fpar_.data();
  BoundaryEdge* const bd = fbd_.data();
  std::size_t nc = 0, m = 0;
  cav[nc] = t0;
  par[nc++] = kNone;
  for (std::size_t k = 0; k < nc; ++k) {
    const TriId t = cav[k];
    const std::int32_t entry = par[k];
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (h == entry) continue;
      const std::int32_t g = OPP[h];
      if (g != kNone && SEG[h] == kNone) {
        const TriId n = g / 3;
        if (in_cavity(n, p, prm)) {
          if (nc >= kMaxFastCavity) return false;
          cav[nc] = n;
          par[nc++] = g;
          continue;
        }
      }
      const VertId a = TV[3 * t + next3(i)], b = TV[3 * t + prev3(i)];
      if (pred::detail::orient2d_filtered(&P[a].x, &P[b].x, &p.x) <= 0) return false;
      bd[m++] = {a, b, g, SEG[h]};
    }
  }
  fnc_ = nc;
  fm_ = m;
  return true;
}

// The rest of an insertion once the cavity (cav[0..nc)) and its boundary edges
// (bd[0..m)) are known and the cavity is star-shaped.
InsertResult Triangulation::make_ball(VertId v, TriId t0, const InsertParams& prm, const TriId* cav,
                                      std::size_t nc, const BoundaryEdge* bd, std::size_t m) {
  const Vec2* const P = pts_.data();
  const Vec2 p = P[v];
  // A star-shaped topological disk with m boundary edges holds m - 2 triangles; more
  // means a vertex strictly inside the cavity, which the ball would lose.
  if (m != nc + 2) {
    ++bad_cavities;
    return {InsertStatus::BadCavity, kNone};
  }
  if (prm.min_dist > 0)
    for (std::size_t k = 0; k < m; ++k)
      if (filter_too_close(prm, bd[k].a, P[bd[k].a], p)) return {InsertStatus::TooClose, bd[k].a};

  // Replace the cavity by the ball: one new triangle (a, b, P) per boundary edge (a, b).
  // The cavity's slots are reused, last first (the order in which a free list would hand
  // them back), and the two more (m = |cavity| + 2) come from the free list or the end of
  // the arrays.
  const std::int32_t the_tag = tag_[t0];
  if (vstart_.size() < pts_.size()) vstart_.resize(pts_.size() + pts_.size() / 2 + 16);
  auto& nt = nt_;
  nt.resize(m);
  for (std::size_t k = 0; k < m; ++k) nt[k] = k < nc ? cav[nc - 1 - k] : new_tri();
  VertId* const TVw = tv_.data();
  std::int32_t* const OPPw = opp_.data();
  std::int32_t* const SEGw = seg_.data();
  std::int32_t* const TAG = tag_.data();
  std::int32_t* const VS = vstart_.data();
  for (std::size_t k = 0; k < m; ++k) {
    const TriId t = nt[k];
    const BoundaryEdge& e = bd[k];
    TVw[3 * t] = e.a;
    TVw[3 * t + 1] = e.b;
    TVw[3 * t + 2] = v;
    SEGw[3 * t] = SEGw[3 * t + 1] = kNone;
    SEGw[3 * t + 2] = e.s;
    TAG[t] = the_tag;
    OPPw[3 * t + 2] = e.out;
    if (e.out != kNone) OPPw[e.out] = 3 * t + 2;
    VS[e.a] = static_cast<std::int32_t>(k);
    vtri_[e.a] = t;
  }
  for (std::size_t k = 0; k < m; ++k) {
    // Edge 0 of (a, b, P) is (b, P); its twin is edge 1 (P, b) of the triangle starting at b.
    const TriId t = nt[k];
    const TriId u = nt[VS[bd[k].b]];
    OPPw[3 * t] = 3 * u + 1;
    OPPw[3 * u + 1] = 3 * t;
  }
  vtri_[v] = nt[0];
  if (mark_.size() < static_cast<std::size_t>(num_tris())) mark_.resize(2 * num_tris() + 8, 0);
  return {InsertStatus::Inserted, v};
}

bool Triangulation::star_correct(Vec2 p, std::size_t nbase, std::uint32_t IN, std::uint32_t OUT,
                                 std::uint32_t CAND) {
  ++star_corrections;
  for (int round = 0; round < 64; ++round) {
    // Drop every non-base triangle having a boundary edge that does not see P.
    bool changed = false;
    for (std::size_t k = nbase; k < cav_.size(); ++k) {
      const TriId t = cav_[k];
      if (mark_[t] != IN) continue;
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = opp_[3 * t + i];
        if (h != kNone && seg_[3 * t + i] == kNone && mark_[h / 3] == IN) continue;
        if (orient(pts_[tv_[3 * t + next3(i)]], pts_[tv_[3 * t + prev3(i)]], p) <= 0) {
          mark_[t] = OUT;
          changed = true;
          break;
        }
      }
    }
    // Keep only what is still connected to the base.
    std::size_t w = 0;
    for (std::size_t k = 0; k < cav_.size(); ++k)
      if (mark_[cav_[k]] == IN) {
        mark_[cav_[k]] = CAND;
        cav_[w++] = cav_[k];
      }
    cav_.resize(w);
    stack_.clear();
    for (std::size_t k = 0; k < nbase; ++k) {
      mark_[cav_[k]] = IN;
      stack_.push_back(cav_[k]);
    }
    while (!stack_.empty()) {
      const TriId t = stack_.back();
      stack_.pop_back();
      for (int i = 0; i < 3; ++i) {
        if (seg_[3 * t + i] != kNone) continue;
        const std::int32_t h = opp_[3 * t + i];
        if (h != kNone && mark_[h / 3] == CAND) {
          mark_[h / 3] = IN;
          stack_.push_back(h / 3);
        }
      }
    }
    w = 0;
    for (std::size_t k = 0; k < cav_.size(); ++k) {
      if (mark_[cav_[k]] == IN)
        cav_[w++] = cav_[k];
      else
        mark_[cav_[k]] = OUT;
    }
    cav_.resize(w);
    // Recollect the boundary and check it.
    bnd_.clear();
    bool bad = false;
    for (const TriId t : cav_)
      for (int i = 0; i < 3; ++i) {
        const std::int32_t h = opp_[3 * t + i];
        if (h != kNone && seg_[3 * t + i] == kNone && mark_[h / 3] == IN) continue;
        bnd_.push_back(3 * t + i);
        if (orient(pts_[tv_[3 * t + next3(i)]], pts_[tv_[3 * t + prev3(i)]], p) <= 0) bad = true;
      }
    if (!bad) return true;
    if (!changed) return false;  // a base triangle does not see P: cannot correct
  }
  return false;
}

Triangulation::Wedge Triangulation::find_wedge(VertId a, Vec2 q) const {
  // Turn around a until the triangle (a, u, w) whose angle at a holds the direction of q
  // (u strictly right of a->q, w strictly left), or until a neighbour of a lies on the
  // ray from a toward q. Shared by boundary enforcement and segment_clear.
  Wedge r;
  const Vec2 pa = pts_[a];
  TriId t = vtri_[a];
  if (t == kNone) return r;
  const TriId tstart = t;
  auto ahead = [&](VertId z) {
    return (pts_[z].x - pa.x) * (q.x - pa.x) + (pts_[z].y - pa.y) * (q.y - pa.y) > 0;
  };
  for (int guard = 0; guard < (1 << 20); ++guard) {
    int k = 0;
    while (tv_[3 * t + k] != a) ++k;
    const VertId x = tv_[3 * t + next3(k)], y = tv_[3 * t + prev3(k)];
    const double ox = orient(pa, q, pts_[x]), oy = orient(pa, q, pts_[y]);
    if (ox == 0 && ahead(x)) {
      r.ray = x;
      r.ray_edge = 3 * t + prev3(k);  // edge (a, x)
      return r;
    }
    if (oy == 0 && ahead(y)) {
      r.ray = y;
      r.ray_edge = 3 * t + next3(k);  // edge (y, a)
      return r;
    }
    if (ox < 0 && oy > 0) {
      r.t = t, r.u = x, r.w = y;
      return r;
    }
    const std::int32_t g = opp_[3 * t + prev3(k)];
    if (g == kNone) return r;  // a on the box border: never for mesh vertices
    t = g / 3;
    if (t == tstart) return r;  // no wedge: inconsistent triangulation (bug guard)
  }
  return r;
}

bool Triangulation::segment_clear(VertId a, Vec2 p) const {
  // Walk from vertex a toward point p (as the enforcement walk does) and report whether
  // the open segment crosses a constrained edge or passes through a vertex before it
  // reaches the triangle holding p.
  const Vec2 pa = pts_[a];
  const Wedge wg = find_wedge(a, p);
  if (wg.ray != kNone) {
    // Along an edge from a: p lies on that edge (clear if it is not constrained) or
    // beyond its far vertex (not clear: the segment passes through that vertex).
    const Vec2 z = pts_[wg.ray];
    const double dz = (z.x - pa.x) * (z.x - pa.x) + (z.y - pa.y) * (z.y - pa.y);
    const double dp = (p.x - pa.x) * (p.x - pa.x) + (p.y - pa.y) * (p.y - pa.y);
    return dz > dp && seg_[wg.ray_edge] == kNone;
  }
  if (wg.t == kNone) return false;
  TriId t = wg.t;
  VertId u = wg.u, w = wg.w;
  for (int guard = 0; guard < (1 << 24); ++guard) {
    int e = 0;
    while (!(tv_[3 * t + next3(e)] == u && tv_[3 * t + prev3(e)] == w)) ++e;
    const std::int32_t h = 3 * t + e;
    // p inside the current triangle, or on its far edge (clear unless constrained).
    const double op = orient(pts_[u], pts_[w], p);
    if (op > 0) return true;
    if (op == 0) return seg_[h] == kNone;
    if (seg_[h] != kNone) return false;
    const std::int32_t g = opp_[h];
    if (g == kNone) return false;
    const VertId x = tv_[g];
    t = g / 3;
    const double ox = orient(pa, p, pts_[x]);
    if (ox == 0) return false;
    if (ox < 0)
      u = x;
    else
      w = x;
  }
  return false;
}

std::int32_t Triangulation::find_half_edge(VertId a, VertId b) const {
  const TriId t0 = vtri_[a];
  if (t0 == kNone) return kNone;
  // Turn around a one way; if the box border stops us, turn the other way.
  for (int dir = 0; dir < 2; ++dir) {
    TriId t = t0;
    do {
      int k = 0;
      while (tv_[3 * t + k] != a) ++k;
      if (tv_[3 * t + next3(k)] == b) return 3 * t + prev3(k);
      const std::int32_t h = opp_[3 * t + (dir == 0 ? prev3(k) : next3(k))];
      if (h == kNone) break;
      t = h / 3;
      if (dir == 0 && t == t0) return kNone;
    } while (t != t0);
  }
  return kNone;
}

bool Triangulation::flippable(std::int32_t h) const {
  const std::int32_t g = opp_[h];
  if (g == kNone) return false;
  const TriId t = h / 3;
  const int i = h % 3;
  const VertId c = tv_[3 * t + i], a = tv_[3 * t + next3(i)], b = tv_[3 * t + prev3(i)];
  const VertId d = tv_[g];
  return orient(pts_[c], pts_[a], pts_[d]) > 0 && orient(pts_[d], pts_[b], pts_[c]) > 0;
}

void Triangulation::flip(std::int32_t h) {
  // t = (c, a, b) seen from edge i, u = (d, b, a); after the flip t = (c, a, d), u = (d, b, c).
  const std::int32_t g = opp_[h];
  const TriId t = h / 3, u = g / 3;
  const int i = h % 3, j = g % 3;
  const VertId c = tv_[3 * t + i], a = tv_[3 * t + next3(i)], b = tv_[3 * t + prev3(i)];
  const VertId d = tv_[3 * u + j];
  const std::int32_t n1 = opp_[3 * t + next3(i)], s1 = seg_[3 * t + next3(i)];  // (b, c)
  const std::int32_t n2 = opp_[3 * t + prev3(i)], s2 = seg_[3 * t + prev3(i)];  // (c, a)
  const std::int32_t n3 = opp_[3 * u + next3(j)], s3 = seg_[3 * u + next3(j)];  // (a, d)
  const std::int32_t n4 = opp_[3 * u + prev3(j)], s4 = seg_[3 * u + prev3(j)];  // (d, b)
  tv_[3 * t] = c, tv_[3 * t + 1] = a, tv_[3 * t + 2] = d;
  tv_[3 * u] = d, tv_[3 * u + 1] = b, tv_[3 * u + 2] = c;
  seg_[3 * t] = s3, seg_[3 * t + 1] = kNone, seg_[3 * t + 2] = s2;
  seg_[3 * u] = s1, seg_[3 * u + 1] = kNone, seg_[3 * u + 2] = s4;
  link(3 * t, n3);
  link(3 * t + 2, n2);
  link(3 * u, n1);
  link(3 * u + 2, n4);
  link(3 * t + 1, 3 * u + 1);
  tag_[u] = tag_[t];
  vtri_[a] = t, vtri_[c] = t, vtri_[b] = u, vtri_[d] = u;
}

void Triangulation::restore_delaunay(std::vector<std::pair<VertId, VertId>>& stack) {
  // Lawson's flips, limited to non-constrained edges: ends with the constrained Delaunay
  // triangulation around the edges given (each flip increases the sorted angle vector).
  while (!stack.empty()) {
    const auto [u, w] = stack.back();
    stack.pop_back();
    const std::int32_t h = find_half_edge(u, w);
    if (h == kNone || seg_[h] != kNone || opp_[h] == kNone) continue;
    const TriId t = h / 3;
    const std::int32_t g = opp_[h];
    const VertId d = tv_[g];
    const Vec2 &p0 = pts_[tv_[3 * t]], &p1 = pts_[tv_[3 * t + 1]], &p2 = pts_[tv_[3 * t + 2]];
    if (pred::detail::incircle_filtered(&p0.x, &p1.x, &p2.x, &pts_[d].x) <= 0) continue;
    if (!flippable(h)) continue;  // cannot happen for a non-locally-Delaunay edge
    const int i = h % 3;
    const VertId c = tv_[3 * t + i], a = tv_[3 * t + next3(i)], b = tv_[3 * t + prev3(i)];
    flip(h);
    stack.push_back({a, d});
    stack.push_back({d, b});
    stack.push_back({b, c});
    stack.push_back({c, a});
  }
}

bool Triangulation::unconstrain(VertId a, VertId b) {
  const std::int32_t h = find_half_edge(a, b);
  if (h == kNone) return false;
  seg_[h] = kNone;
  if (opp_[h] != kNone) seg_[opp_[h]] = kNone;
  return true;
}

Triangulation::EnforceResult Triangulation::enforce(VertId a, VertId b, std::int32_t sid) {
  EnforceResult res;
  auto set_seg = [&](std::int32_t h) {
    seg_[h] = sid;
    if (opp_[h] != kNone) seg_[opp_[h]] = sid;
  };
  std::int32_t h = find_half_edge(a, b);
  if (h != kNone) {
    set_seg(h);
    return res;
  }
  const Vec2 pa = pts_[a], pb = pts_[b];
  // The triangle around a whose wedge contains the direction of b. A neighbour of a on
  // the ray toward b lies strictly between a and b (b itself would make (a, b) an edge).
  const Wedge wg = find_wedge(a, pb);
  if (wg.ray != kNone) {
    res.status = EnforceStatus::ThroughVertex;
    res.through = wg.ray;
    return res;
  }
  if (wg.t == kNone) {
    res.status = EnforceStatus::Crossing;  // no wedge found: inconsistent (bug guard)
    return res;
  }
  TriId t = wg.t;
  VertId u = wg.u, w = wg.w;
  // Walk along (a, b) collecting the crossed edges (u right of ab, w left).
  std::deque<std::pair<VertId, VertId>> queue;
  for (;;) {
    // half-edge (u, w) of t: edge index e with tv_[next(e)] == u, tv_[prev(e)] == w
    int e = 0;
    while (!(tv_[3 * t + next3(e)] == u && tv_[3 * t + prev3(e)] == w)) ++e;
    h = 3 * t + e;
    if (seg_[h] != kNone) {
      res.status = EnforceStatus::Crossing;
      res.crossing_seg = seg_[h];
      res.crossing_a = u;
      res.crossing_b = w;
      return res;
    }
    queue.push_back({u, w});
    const std::int32_t g = opp_[h];
    const VertId x = tv_[g];
    t = g / 3;
    if (x == b) break;
    const double ox = orient(pa, pb, pts_[x]);
    if (ox == 0) {
      res.status = EnforceStatus::ThroughVertex;
      res.through = x;
      return res;
    }
    if (ox < 0)
      u = x;
    else
      w = x;
  }
  // Swap the crossed diagonals until none crosses (Sloan's scheme for §7.2.2).
  std::vector<std::pair<VertId, VertId>> created;
  std::int64_t guard = 0;
  const std::int64_t cap = 64 * static_cast<std::int64_t>(queue.size() * queue.size()) + 1024;
  while (!queue.empty()) {
    if (++guard > cap) {
      res.status = EnforceStatus::Crossing;  // bug guard: reported as an internal failure
      return res;
    }
    const auto [x, y] = queue.front();
    queue.pop_front();
    const std::int32_t e = find_half_edge(x, y);
    if (e == kNone) continue;
    if (!flippable(e)) {
      queue.push_back({x, y});
      continue;
    }
    const VertId c = tv_[e], d = tv_[opp_[e]];
    flip(e);
    const double oc = orient(pa, pb, pts_[c]), od = orient(pa, pb, pts_[d]);
    if ((oc < 0 && od > 0) || (oc > 0 && od < 0))
      queue.push_back({c, d});
    else
      created.push_back({c, d});
  }
  h = find_half_edge(a, b);
  if (h == kNone) {
    res.status = EnforceStatus::Crossing;
    return res;
  }
  set_seg(h);
  restore_delaunay(created);
  return res;
}

}  // namespace uvmesh::m2d::detail
