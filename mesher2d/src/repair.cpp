// The targeted repair and the size pass of the optimizer (§7.3.6, §7.5.2).
//
// The worst elements left by relocation and swaps sit where the point pattern is
// strained (rows of the saturation too far apart or too close for their spacing) or
// where the valence is wrong; no relocation fixes those. Each bad triangle is tried
// with, in turn: max-min relocation of its vertices, an edge swap, the collapse of one
// of its edges (§7.3.6 "remove edges by merging their endpoints") and the split of its
// longest edge. A topological operation is taken only when the worst 1/Q_K of the
// triangles it replaces strictly rises (the new vertex placed by maxmin_core first), so
// the sorted quality vector rises with every change and the loop terminates.
#include <algorithm>
#include <cmath>

#include "optimizer.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

namespace {
// The repair's work budget, in triangle evaluations per triangle of the mesh.
constexpr std::int64_t kRepairWork = 20;
}  // namespace

double Optimizer::ball_min(VertId v, const std::vector<VertId>& ring) const {
  double m = 1e300;
  for (std::size_t k = 0; k < ring.size(); ++k)
    m = std::min(m, tri_q(v, ring[k], ring[k + 1 == ring.size() ? 0 : k + 1]));
  return m;
}

bool Optimizer::has_constrained_edge(VertId v) const {
  const TriId t0 = ms.tri.vertex_tri(v);
  TriId t = t0;
  int guard = 0;
  do {
    int k = 0;
    while (ms.tri.vertex(t, k) != v) ++k;
    if (ms.tri.constraint(3 * t + detail::next3(k)) != kNone ||
        ms.tri.constraint(3 * t + detail::prev3(k)) != kNone)
      return true;
    const std::int32_t h = ms.tri.twin(3 * t + detail::next3(k));
    if (h == kNone || ++guard > 256) return true;
    t = h / 3;
  } while (t != t0);
  return false;
}

bool Optimizer::try_swap(TriId t) {
  for (int i = 0; i < 3; ++i) {
    const std::int32_t h = 3 * t + i;
    if (ms.tri.constraint(h) != kNone || ms.tri.twin(h) == kNone) continue;
    const std::int32_t g = ms.tri.twin(h);
    const VertId c = ms.tri.apex(h), a = ms.tri.vertex(t, detail::next3(i)),
                 b = ms.tri.vertex(t, detail::prev3(i));
    const VertId d = ms.tri.apex(g);
    const double before = std::min(tri_q(c, a, b), tri_q(d, b, a));
    const double after = std::min(tri_q(c, a, d), tri_q(d, b, c));
    if (after > before * (1 + 1e-9) && ms.tri.flippable(h)) {
      ms.tri.flip(h);
      return true;
    }
  }
  return false;
}

// Collapse of an edge of t: v (free, no constrained edge) merges into u. When u is
// free too the merged vertex is placed by maxmin_core on the union of both rings.
bool Optimizer::try_collapse(TriId t) {
  std::array<std::pair<double, int>, 3> order;
  for (int i = 0; i < 3; ++i)
    order[i] = {rank_len2(ms.tri.vertex(t, detail::next3(i)), ms.tri.vertex(t, detail::prev3(i))),
                i};
  std::sort(order.begin(), order.end());
  for (const auto& [len, i] : order) {
    const VertId e0 = ms.tri.vertex(t, detail::next3(i)), e1 = ms.tri.vertex(t, detail::prev3(i));
    for (const auto& [v, u] : {std::pair{e0, e1}, std::pair{e1, e0}})
      if (collapse_into(v, u, 0, false)) return true;
  }
  return false;
}

// Collapse of edge (v, u) merging v into u (see try_collapse). size_check: refused when
// an edge of the merged vertex would be longer than sqrt2 in the metric.
bool Optimizer::collapse_into(VertId v, VertId u, double floor, bool size_check) {
  const auto& P = ms.tri.points();
  {
    {
      if (ms.fixed[v] || has_constrained_edge(v) || !gather_ring(v, rv_)) return false;
      double old_min = ball_min(v, rv_);
      Vec2 p;
      if (ms.fixed[u]) {
        // u stays: the new triangles are v's ball with v at u, minus the two on (u, v).
        p = P[u];
        double nmin = 1e300;
        const std::size_t n = rv_.size();
        bool ok = true;
        for (std::size_t k = 0; k < n && ok; ++k) {
          const VertId a = rv_[k], b = rv_[k + 1 == n ? 0 : k + 1];
          if (a == u || b == u) continue;
          if (!(pred::orient2d(&p.x, &P[a].x, &P[b].x) > 0))
            ok = false;
          else
            nmin = std::min(nmin, tri_q(u, a, b));
        }
        if (!ok || !accept_q(nmin, old_min, floor)) return false;
        if (size_check)
          for (const VertId w : rv_)
            if (w != u && true_len(p, ms.vm[u], ms.rs[u], w) > measures::kUnitMax) return false;
      } else {
        if (has_constrained_edge(u) || !gather_ring(u, ru_)) return false;
        old_min = std::min(old_min, ball_min(u, ru_));
        // Merged ring: u's ring from x to y, then v's ring after y up to before x, where
        // v's ring reads (.., x, u, y, ..) and u's ring (.., y, v, x, ..).
        const std::size_t nv = rv_.size(), nu = ru_.size();
        std::size_t iu = 0, iv = 0;
        while (iu < nv && rv_[iu] != u) ++iu;
        while (iv < nu && ru_[iv] != v) ++iv;
        if (iu == nv || iv == nu) return false;
        const VertId x = rv_[(iu + nv - 1) % nv], y = rv_[(iu + 1) % nv];
        if (ru_[(iv + 1) % nu] != x || ru_[(iv + nu - 1) % nu] != y) return false;
        merged_.clear();
        for (std::size_t k = (iv + 1) % nu; k != iv; k = (k + 1) % nu)
          merged_.push_back(ru_[k]);  // x .. y
        for (std::size_t k = (iu + 2) % nv; k != (iu + nv - 1) % nv; k = (k + 1) % nv)
          merged_.push_back(rv_[k]);
        // The link condition: no vertex twice.
        std::vector<VertId>& srt = srt_;
        srt.assign(merged_.begin(), merged_.end());
        std::sort(srt.begin(), srt.end());
        if (std::adjacent_find(srt.begin(), srt.end()) != srt.end()) return false;
        const detail::MetricFrame f = frame_of(u);
        load_ring(f, merged_, ms.vm[u]);
        const Vec2 mid{0.5 * (P[u].x + P[v].x), 0.5 * (P[u].y + P[v].y)};
        double best = -1;
        Vec2 bp{};
        // A varying field starts from the midpoint only (the ends as starts cost time
        // on a strongly anisotropic field for the same quality).
        const int starts = iso_uniform_ ? 3 : 1;
        int ns = 0;
        for (const Vec2 s0 : {mid, P[u], P[v]}) {
          if (ns++ >= starts) break;
          Vec2 fp = iso_uniform_ ? s0 : f(s0);
          if (!ball_valid(f, fp, merged_)) continue;
          const double q = maxmin_core(fp, 2.0, 12, f, merged_);
          if (q > best) best = q, bp = fp;
          if (best > old_min || (floor > 0 && best >= floor)) break;
        }
        if (!accept_q(best, old_min, floor)) return false;
        p = iso_uniform_ ? bp : f.inv(bp);
        if (size_check) {
          const Metric2 mp = point_metric(p, ms.rs[u]);
          for (const VertId w : merged_)
            if (true_len(p, mp, ms.rs[u], w) > measures::kUnitMax) return false;
        }
      }
      if (ms.tri.collapse_edge(v, u, p)) {
        set_position(u, p);
        return true;
      }
    }
  }
  return false;
}

// Split of the longest edge of t at its midpoint; the new vertex's ring then absorbs
// the triangles across its four outer edges where that raises the worst quality (the
// swaps that follow a split), and the vertex is placed by maxmin_core.
bool Optimizer::try_split(TriId t) {
  int i = 0;
  double lmax = -1;
  for (int k = 0; k < 3; ++k) {
    const double l =
        rank_len2(ms.tri.vertex(t, detail::next3(k)), ms.tri.vertex(t, detail::prev3(k)));
    if (l > lmax) lmax = l, i = k;
  }
  return split_at(3 * t + i, 0, false);
}

// Split of the edge of half-edge h (see try_split). size_check: refused when an edge of
// the new vertex would be shorter than 1/sqrt2 in the metric.
bool Optimizer::split_at(std::int32_t h, double floor, bool size_check) {
  const auto& P = ms.tri.points();
  const TriId t = h / 3;
  const int i = h % 3;
  if (ms.tri.constraint(h) != kNone || ms.tri.twin(h) == kNone) return false;
  const std::int32_t g = ms.tri.twin(h);
  if (!ms.in_domain(g / 3)) return false;
  const VertId c = ms.tri.apex(h), a = ms.tri.vertex(t, detail::next3(i)),
               b = ms.tri.vertex(t, detail::prev3(i));
  const VertId d = ms.tri.apex(g);
  const Vec2 m{0.5 * (P[a].x + P[b].x), 0.5 * (P[a].y + P[b].y)};
  const double rm = iso_uniform_ ? 1.0 : std::max(ms.rs[a], ms.rs[b]);
  const Metric2 mm = iso_uniform_ ? ms.m_uniform : point_metric(m, rm);
  double old_min = std::min(tri_q(t), tri_q(g / 3));
  // Ring of the new vertex, counter-clockwise: c, a, d, b.
  merged_.assign({c, a, d, b});
  absorbed_.clear();
  for (std::size_t k = 0; k < merged_.size() && merged_.size() < 12; ++k) {
    const VertId r0 = merged_[k], r1 = merged_[k + 1 == merged_.size() ? 0 : k + 1];
    const std::int32_t e = ms.tri.find_half_edge(r1, r0);  // the outer triangle (r1, r0, x)
    if (e == kNone || ms.tri.constraint(e) != kNone || !ms.in_domain(e / 3)) continue;
    const VertId x = ms.tri.apex(e);
    const double qo = tri_q(e / 3);
    if (!(pred::orient2d(&m.x, &P[r0].x, &P[x].x) > 0) ||
        !(pred::orient2d(&m.x, &P[x].x, &P[r1].x) > 0))
      continue;
    const double before = std::min(qo, q_of_point(m, mm, r0, r1));
    const double after = std::min(q_of_point(m, mm, r0, x), q_of_point(m, mm, x, r1));
    if (!(after > before)) continue;
    old_min = std::min(old_min, qo);
    absorbed_.push_back({r0, r1});
    merged_.insert(merged_.begin() + static_cast<std::ptrdiff_t>(k) + 1, x);
    --k;  // the new edge (r0, x) is looked at next
  }
  const detail::MetricFrame f(iso_uniform_ ? Metric2{} : mm);
  load_ring(f, merged_, mm);
  Vec2 fp = iso_uniform_ ? m : f(m);
  const double q = maxmin_core(fp, 2.0, 12, f, merged_);
  if (!accept_q(q, old_min, floor)) return false;
  if (size_check) {
    const Vec2 pp = iso_uniform_ ? fp : f.inv(fp);
    const Metric2 mp = point_metric(pp, rm);
    for (const VertId w : merged_)
      if (true_len(pp, mp, rm, w) < measures::kUnitMin) return false;
  }
  const VertId nv = ms.tri.split_edge(h, m);
  if (nv == kNone) return false;
  ms.vm.push_back(iso_uniform_ ? ms.vm[a] : mm);
  ms.rs.push_back(rm);
  ms.fixed.push_back(0);
  ms.vmark.push_back(0);
  for (const auto& [r0, r1] : absorbed_) {
    const std::int32_t e = ms.tri.find_half_edge(r0, r1);
    if (e != kNone && ms.tri.flippable(e)) ms.tri.flip(e);
  }
  // A flip refused above leaves another ring than the one fp was placed for: keep the
  // midpoint then (valid: split_edge checked it).
  if (gather_ring(nv, rv_) && ball_valid(f, fp, rv_))
    set_position(nv, iso_uniform_ ? fp : f.inv(fp));
  return true;
}

double Optimizer::q_of_point(Vec2 p, const Metric2& mp, VertId a, VertId b) const {
  const auto& P = ms.tri.points();
  if (iso_uniform_) return q_inv(p, P[a], P[b]);
  const detail::MetricFrame f(detail::mean3(mp, ms.vm[a], ms.vm[b]));
  return q_inv(f(p), f(P[a]), f(P[b]));
}

// The metric a vertex created at p gets (the field, scaled by the boundary ratio r).
Metric2 Optimizer::point_metric(Vec2 p, double r) {
  const Metric2 m = ms.metric(p.x, p.y);
  return r < 1 ? detail::scaled(m, 1.0 / (r * r)) : m;
}

// Metric length of the segment from p (metric mp, boundary ratio rp) to vertex w by
// Simpson's rule on the field (eq. 7.10), as the measure takes it: the endpoints'
// metrics alone miss how a strongly anisotropic field turns along the edge (at the
// ring's layer a chord of the circle is tangent at its midpoint only).
double Optimizer::true_len(Vec2 p, const Metric2& mp, double rp, VertId w) {
  const Vec2 q = ms.tri.point(w);
  const Vec2 d{q.x - p.x, q.y - p.y};
  const double rm = std::sqrt(rp * (static_cast<std::size_t>(w) < ms.rs.size() ? ms.rs[w] : 1.0));
  const Metric2 mm = point_metric({0.5 * (p.x + q.x), 0.5 * (p.y + q.y)}, rm);
  return measures::edge_length(detail::length(mp, d), detail::length(mm, d),
                               detail::length(ms.vm[w], d));
}

// Squared length of edge (a, b) for ranking the edges of a triangle: Euclidean for a
// uniform field, in the metric otherwise (the shortest edge in the plane of an
// anisotropic triangle is not its shortest in the metric).
double Optimizer::rank_len2(VertId a, VertId b) const {
  const Vec2 pa = ms.tri.point(a), pb = ms.tri.point(b);
  if (iso_uniform_) return (pa.x - pb.x) * (pa.x - pb.x) + (pa.y - pb.y) * (pa.y - pb.y);
  const double l = ms.edge_length(a, b);
  return l * l;
}

// The vertices of t and of its three neighbours (after a swap of an edge of t, every
// changed triangle has one of them).
void Optimizer::touch_around(TriId t, std::vector<VertId>& out) const {
  for (int i = 0; i < 3; ++i) {
    out.push_back(ms.tri.vertex(t, i));
    const std::int32_t g = ms.tri.twin(3 * t + i);
    if (g != kNone) out.push_back(ms.tri.apex(g));
  }
}

// The in-domain triangles worse than q found in the balls of the vertices vs (each once).
void Optimizer::bad_in_balls(const std::vector<VertId>& vs, double q, std::vector<TriId>& out) {
  out.clear();
  if (tmark_.size() < static_cast<std::size_t>(ms.tri.num_tris()))
    tmark_.resize(ms.tri.num_tris(), 0);
  ++tepoch_;
  for (const VertId v : vs)
    ms.for_ball(v, [&](TriId t) {
      if (tmark_[t] == tepoch_) return;
      tmark_[t] = tepoch_;
      if (ms.in_domain(t) && tri_q(t) < q) out.push_back(t);
    });
}

// Rounds of max-min relocation of the vertices of triangles worse than qstop, and
// swaps of their edges. The first round scans the mesh; a later one looks only at the
// balls of the vertices handled before (every change is there). Returns the vertices
// handled: the triangles still bad afterwards lie in their balls.
std::vector<VertId> Optimizer::targeted_pass(double qstop, int rounds) {
  std::vector<TriId> bad;
  std::vector<VertId> ring, handled, all;
  std::vector<char> seen(ms.tri.num_verts(), 0);
  const TriId nt = ms.tri.num_tris();
  for (TriId t = 0; t < nt; ++t)
    if (ms.in_domain(t) && tri_q(t) < qstop) bad.push_back(t);
  for (int round = 0; round < rounds && !bad.empty(); ++round) {
    if (ms.over_time("optimization")) break;
    std::int64_t moved = 0, swaps = 0;
    for (const VertId v : handled) seen[v] = 0;
    handled.clear();
    for (const TriId t : bad) {
      if (!ms.in_domain(t)) continue;
      for (int k = 0; k < 3; ++k) {
        const VertId v = ms.tri.vertex(t, k);
        if (seen[v]) continue;
        seen[v] = 1;
        handled.push_back(v);
        moved += maxmin_relocate(v, ring, qstop, 8);
      }
    }
    const std::size_t nh = handled.size();
    for (const TriId t : bad)
      if (ms.in_domain(t) && tri_q(t) < qstop && try_swap(t)) {
        ++swaps;
        touch_around(t, handled);
      }
    ms.res.stats.relocations += moved;
    ms.res.stats.swaps += swaps;
    all.insert(all.end(), handled.begin(), handled.begin() + static_cast<std::ptrdiff_t>(nh));
    if (moved == 0 && swaps == 0) break;
    // Every triangle that changed or stayed bad lies in a ball of a handled vertex:
    // rescanning those balls finds what a scan of the mesh would, in the same order
    // (by triangle id; another order left worse triangles at the corners of a square).
    bad_in_balls(handled, qstop, bad);
    std::sort(bad.begin(), bad.end());
  }
  return all;
}

// first: when given, the vertices whose balls hold every triangle worse than qbad (the
// first round then looks only there), else the first round scans the mesh.
void Optimizer::repair(double qbad, int rounds, const std::vector<VertId>* first) {
  std::vector<TriId> bad;
  std::vector<VertId> ring, touched;
  // Work budget (triangle evaluations): where bad elements cannot be repaired (small
  // input angles between fixed boundary edges) the loop would otherwise try them all,
  // round after round. A uniform unit mesh needs a small fraction of it.
  const std::int64_t budget =
      work_ + kRepairWork * static_cast<std::int64_t>(ms.tri.num_tris()) + 100000;
  for (int round = 0; round < rounds; ++round) {
    if (ms.over_time("optimization") || work_ > budget) return;
    // Later rounds look only at the balls of the vertices the round before touched
    // (the vertices of the triangles it worked on and their neighbours, the new vertex
    // of a split): every triangle that changed or stayed bad is there. Sorted by id,
    // the list is the one a scan of the mesh would give.
    bad.clear();
    if (round == 0 && first) {
      bad_in_balls(*first, qbad, bad);
    } else if (round > 0) {
      bad_in_balls(touched, qbad, bad);
      std::sort(bad.begin(), bad.end());
    } else {
      const TriId nt = ms.tri.num_tris();
      for (TriId t = 0; t < nt; ++t)
        if (ms.in_domain(t) && tri_q(t) < qbad) bad.push_back(t);
    }
    if (bad.empty()) break;
    touched.clear();
    std::int64_t changes = 0;
    for (const TriId t : bad) {
      if (work_ > budget) return;
      if (!ms.in_domain(t) || !(tri_q(t) < qbad)) continue;
      for (int k = 0; k < 3; ++k) {
        const VertId c = ms.tri.vertex(t, k);
        touched.push_back(c);
        if (gather_ring(c, nbr_)) touched.insert(touched.end(), nbr_.begin(), nbr_.end());
      }
      for (int k = 0; k < 3; ++k) changes += maxmin_relocate(ms.tri.vertex(t, k), ring, 2.0, 8);
      if (!(tri_q(t) < qbad)) continue;
      // A vertex can be held by its neighbours (its ball's worst triangles pinned
      // against each other): relax the neighbours of the triangle's vertices, then the
      // vertices again.
      // The positions are restored unless the worst triangle around them improved.
      {
        saved_.clear();
        for (int k = 0; k < 3; ++k) {
          const VertId c = ms.tri.vertex(t, k);
          saved_.push_back({c, ms.tri.point(c)});
          if (!gather_ring(c, nbr_)) continue;
          for (const VertId w : nbr_) saved_.push_back({w, ms.tri.point(w)});
        }
        auto region_min = [&] {
          double m = 1e300;
          for (const auto& [w, pw] : saved_)
            if (!ms.fixed[w] && gather_ring(w, ring)) m = std::min(m, ball_min(w, ring));
          return m;
        };
        const double before = region_min();
        bool any = false;
        // Not for a varying field: there the sweeps cost a third of the optimization
        // and the repair ends better without them (the restore rule below is judged per
        // triangle frame, which the sweeps' single frame misjudges).
        const int sweeps = iso_uniform_ ? 3 : 0;
        for (int sweep = 0; sweep < sweeps; ++sweep)
          for (const auto& [w, pw] : saved_) any |= pnorm_relocate(w, ring);
        for (int k = 0; k < 3; ++k) any |= maxmin_relocate(ms.tri.vertex(t, k), ring, 2.0, 8);
        if (any && !(region_min() > before)) {
          for (const auto& [w, pw] : saved_) set_position(w, pw);
        } else if (any) {
          ++changes;
        }
      }
      if (!(tri_q(t) < qbad)) continue;
      if (try_swap(t)) {
        ++changes;
        touch_around(t, touched);
        continue;
      }
      if (try_collapse(t)) {
        ++changes;
        continue;
      }
      // A varying field's triangle whose three vertices are all on the boundary lies
      // where the domain is narrower than the field's size (CAD faces: the last
      // micrometres of a tangential contact); a split only puts an interior vertex
      // into that gap (it makes slivers with an interior vertex, worse than the
      // boundary-only slivers the report counts apart).
      if (!iso_uniform_ && ms.fixed[ms.tri.vertex(t, 0)] && ms.fixed[ms.tri.vertex(t, 1)] &&
          ms.fixed[ms.tri.vertex(t, 2)])
        continue;
      const VertId nv = ms.tri.num_verts();
      if (try_split(t)) {
        ++changes;
        touched.push_back(nv);
        continue;
      }
    }
    if (changes == 0) break;
  }
}

// Size optimization (§7.5.2: "first with respect to the size criterion"): interior edges
// longer than sqrt2 in the metric (Simpson's rule, true_len) are split, the longest
// first; then edges shorter than 1/sqrt2 are collapsed, the shortest first. A change is
// taken when the worst 1/Q_K around it stays >= floor (or improves) and it makes no
// edge outside the unit range on the other side. Returns the number of changes.
std::int64_t Optimizer::size_pass(double floor) {
  struct E {
    double l;
    VertId a, b;
  };
  std::vector<E> longs, shorts;
  const TriId nt = ms.tri.num_tris();
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i, g = ms.tri.twin(h);
      if (ms.tri.constraint(h) != kNone || g == kNone || g / 3 < t || !ms.in_domain(g / 3))
        continue;
      const VertId a = ms.tri.vertex(t, detail::next3(i)), b = ms.tri.vertex(t, detail::prev3(i));
      const double l = true_len(ms.tri.point(a), ms.vm[a], ms.rs[a], b);
      if (l > measures::kUnitMax)
        longs.push_back({l, a, b});
      else if (l < measures::kUnitMin)
        shorts.push_back({l, a, b});
    }
  }
  std::sort(longs.begin(), longs.end(), [](const E& x, const E& y) { return x.l > y.l; });
  std::sort(shorts.begin(), shorts.end(), [](const E& x, const E& y) { return x.l < y.l; });
  std::int64_t changes = 0;
  for (const E& e : longs) {
    if (ms.over_time("optimization")) return changes;
    const std::int32_t h = ms.tri.find_half_edge(e.a, e.b);
    if (h == kNone || !ms.in_domain(h / 3)) continue;
    if (!(true_len(ms.tri.point(e.a), ms.vm[e.a], ms.rs[e.a], e.b) > measures::kUnitMax)) continue;
    changes += split_at(h, floor, true);
  }
  if (!ms.opt.collapse_short_edges) return changes;
  for (const E& e : shorts) {
    if (ms.over_time("optimization")) return changes;
    if (ms.tri.vertex_tri(e.a) == kNone || ms.tri.vertex_tri(e.b) == kNone) continue;
    const std::int32_t h = ms.tri.find_half_edge(e.a, e.b);
    if (h == kNone || !ms.in_domain(h / 3)) continue;
    if (!(true_len(ms.tri.point(e.a), ms.vm[e.a], ms.rs[e.a], e.b) < measures::kUnitMin)) continue;
    changes += collapse_into(e.a, e.b, floor, true) || collapse_into(e.b, e.a, floor, true);
  }
  return changes;
}

}  // namespace uvmesh::m2d::detail
