// Stage 7 of mesher2d: optimization (§7.3.6, §7.5.2): valence and quality swaps,
// relocation, max-min relocation, then the size passes and the targeted repair
// (repair.cpp); the relocation kernels are in relocation.cpp.
#include <algorithm>
#include <cmath>

#include "optimizer.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

namespace {

// Relocation (§7.3.6): vertices whose ball is already this good (1/Q) are left alone; a
// move is taken when the ball's worst quality stays above kSmoothAccept times the old
// one. Accepting a slight loss lets the smoothing escape the local optimum where each
// single move only trades one triangle against another (on a square with a hole it
// leaves less than half the triangles with Q > 1.3 that strict gain leaves).
constexpr double kSmoothSkip = 0.97;
constexpr double kSmoothAccept = 0.95;
// Max-min relocation (maxmin_relocate) stops once the ball's worst 1/Q_K reaches this:
// 1 / 1.15, a margin under the target Q_M <= 1.2 of a uniform field.
constexpr double kMaxminStop = 1 / 1.15;
constexpr double kMaxminStopVarying = 1 / 1.3;
// Varying-field swaps are tried on the edges of triangles with Q_K > 1.3 only.
constexpr double kSwapSkipVarying = 1 / 1.3;
// Targeted repair (Optimizer::repair) works on triangles worse than this: Q_K > 1.18.
constexpr double kRepairBad = 1 / 1.18;
// For a varying field (scalar or metric) the repair works on triangles with Q_K > 1.4:
// the target there is Q_M <= 2 with 95% of the triangles under 1.5.
constexpr double kRepairBadVarying = 1 / 1.4;
// The size pass (Optimizer::size_pass) may lower a ball's worst 1/Q_K down to this.
constexpr double kSizeFloor = 1 / 1.45;

}  // namespace

std::int64_t Optimizer::swap_pass() {
  if (multi_frame_) return swap_pass_varying();
  std::int64_t swaps = 0;
  const TriId nt = ms.tri.num_tris();
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (ms.tri.constraint(h) != kNone) continue;
      const std::int32_t g = ms.tri.twin(h);
      if (g == kNone) continue;
      const VertId c = ms.tri.apex(h), a = ms.tri.vertex(t, detail::next3(i)),
                   b = ms.tri.vertex(t, detail::prev3(i));
      const VertId d = ms.tri.apex(g);
      const auto& P = ms.tri.points();
      const Metric2 m = iso_uniform_ ? Metric2{} : quad_metric(a, b, c, d);
      const double before =
          std::min(quality_in(m, P[c], P[a], P[b]), quality_in(m, P[d], P[b], P[a]));
      const double after =
          std::min(quality_in(m, P[c], P[a], P[d]), quality_in(m, P[d], P[b], P[c]));
      // Swap only for a clear gain (the factor keeps cocircular quads from flipping back).
      if (after > before * (1 + 1e-6) && ms.tri.flippable(h)) {
        ms.tri.flip(h);
        ++swaps;
        break;  // t changed; its other edges are seen in a later pass
      }
    }
  }
  return swaps;
}

// swap_pass for a varying field: each triangle judged in the mean of its vertex metrics
// (tri_q, as the measure), computed once per pass; only edges whose worse triangle has
// Q_K above 1/kSwapSkipVarying are tried (a swap among better triangles changes nothing
// the repair and the measure look at, and most edges of a unit mesh are such).
std::int64_t Optimizer::swap_pass_varying() {
  std::int64_t swaps = 0;
  const TriId nt = ms.tri.num_tris();
  tq_.resize(nt);
  for (TriId t = 0; t < nt; ++t) tq_[t] = ms.in_domain(t) ? tri_q(t) : 0.0;
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t) || !(tq_[t] < kSwapSkipVarying)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (ms.tri.constraint(h) != kNone) continue;
      const std::int32_t g = ms.tri.twin(h);
      if (g == kNone || !ms.in_domain(g / 3)) continue;
      const VertId c = ms.tri.apex(h), a = ms.tri.vertex(t, detail::next3(i)),
                   b = ms.tri.vertex(t, detail::prev3(i));
      const VertId d = ms.tri.apex(g);
      const double before = std::min(tq_[t], tq_[g / 3]);
      const double q1 = tri_q(c, a, d), q2 = tri_q(d, b, c);
      if (std::min(q1, q2) > before * (1 + 1e-6) && ms.tri.flippable(h)) {
        ms.tri.flip(h);  // t becomes (c, a, d), g / 3 becomes (d, b, c)
        tq_[t] = q1;
        tq_[g / 3] = q2;
        ++swaps;
        break;
      }
    }
  }
  return swaps;
}

Metric2 Optimizer::quad_metric(VertId a, VertId b, VertId c, VertId d) const {
  const Metric2 m1 = detail::mean3(ms.vm[a], ms.vm[b], ms.vm[c]);
  return detail::mix(m1, ms.vm[d], 0.25);
}

std::int64_t Optimizer::smooth_pass() {
  std::int64_t moved = 0;
  std::vector<VertId> ring;  // the ball's opposite edges (ring[k], ring[k+1])
  const VertId nv = ms.tri.num_verts();
  for (VertId v = 4; v < nv; ++v) {
    if (ms.fixed[v] || !gather_ring(v, ring)) continue;
    const std::size_t n = ring.size();
    const auto& P = ms.tri.points();
    const Vec2 pv = P[v];
    const Metric2 m = ms.vm[v];
    const detail::MetricFrame f(m);
    auto tri_at = [&](std::size_t k, Vec2 p, double& q) {
      // Turning through the edge (prev, v) visits the ring counter-clockwise, so the
      // ball triangles are (p, ring[k], ring[k+1]).
      const Vec2 a = P[ring[k]], b = P[ring[(k + 1) % n]];
      q = iso_uniform_ ? q_inv(p, a, b) : q_inv(f(p), f(a), f(b));
      return pred::orient2d(&p.x, &a.x, &b.x) > 0;
    };
    double qmin_old = 1e300;
    for (std::size_t k = 0; k < n; ++k) {
      double q;
      tri_at(k, pv, q);
      qmin_old = std::min(qmin_old, q);
    }
    if (qmin_old > kSmoothSkip) continue;  // already near-equilateral everywhere
    // Ideal point of each ball triangle: the apex of the equilateral (in the metric)
    // triangle on the opposite edge (§7.4.3 "optimal point"). Over a closed ring their
    // mean is the centroid of the ring (the rotated edge vectors sum to zero), i.e.
    // Laplacian smoothing in the metric frame of v. (Area-weighted circumcentres, the
    // ODT rule, gave a worse Q_M here.)
    Vec2 target{0, 0};
    const Vec2 fv = iso_uniform_ ? pv : f(pv);
    for (std::size_t k = 0; k < n; ++k) {
      const Vec2 a0 = P[ring[k]], b0 = P[ring[(k + 1) % n]];
      const Vec2 a = iso_uniform_ ? a0 : f(a0), b = iso_uniform_ ? b0 : f(b0);
      const Vec2 mid{0.5 * (a.x + b.x), 0.5 * (a.y + b.y)};
      const Vec2 e{b.x - a.x, b.y - a.y};
      // left of a->b (toward the vertex side): rotate +90 degrees
      target.x += mid.x - 0.8660254037844386 * e.y;
      target.y += mid.y + 0.8660254037844386 * e.x;
    }
    target.x /= static_cast<double>(n);
    target.y /= static_cast<double>(n);
    for (const double w : {1.0, 0.5, 0.25}) {
      const Vec2 fq{fv.x + w * (target.x - fv.x), fv.y + w * (target.y - fv.y)};
      const Vec2 q = iso_uniform_ ? fq : f.inv(fq);
      double qmin_new = 1e300;
      bool valid = true;
      for (std::size_t k = 0; k < n && valid; ++k) {
        double qq;
        valid = tri_at(k, q, qq);
        qmin_new = std::min(qmin_new, qq);
      }
      if (valid && qmin_new > qmin_old * kSmoothAccept) {
        ms.tri.set_point(v, q);
        if (!iso_uniform_) {
          ms.vm[v] = ms.metric(q.x, q.y);
          if (static_cast<std::size_t>(v) < ms.rs.size() && ms.rs[v] < 1)
            ms.vm[v] = detail::scaled(ms.vm[v], 1.0 / (ms.rs[v] * ms.rs[v]));
        }
        ++moved;
        break;
      }
    }
  }
  return moved;
}

std::int64_t Optimizer::maxmin_pass(double qstop, int iters) {
  std::int64_t moved = 0;
  std::vector<VertId> ring;
  const VertId nv = ms.tri.num_verts();
  if (multi_frame_) {
    // Only the vertices of triangles worse than qstop: maxmin_core leaves a ball whose
    // worst triangle is above qstop as it is, and building the per-triangle frames of
    // every ball to find that out costs more than judging each triangle once.
    std::vector<char> want(nv, 0);
    const TriId nt = ms.tri.num_tris();
    for (TriId t = 0; t < nt; ++t)
      if (ms.in_domain(t) && tri_q(t) < qstop)
        for (int i = 0; i < 3; ++i) want[ms.tri.vertex(t, i)] = 1;
    for (VertId v = 4; v < nv; ++v)
      if (want[v]) moved += maxmin_relocate(v, ring, qstop, iters);
    return moved;
  }
  for (VertId v = 4; v < nv; ++v) moved += maxmin_relocate(v, ring, qstop, iters);
  return moved;
}

// Valence-driven swaps: in a unit mesh the ideal vertex has 6 triangles around it (a
// boundary vertex round(theta / 60deg) for its interior angle theta); valence 4 or 8
// vertices force angles of 90 or 45 degrees that no relocation can repair. A swap is
// taken when it lowers the squared deviation from the ideal counts of its four vertices
// and keeps the worse of its two triangles within kValenceQualityKeep of the current one.
std::int64_t Optimizer::valence_pass() {
  constexpr double kValenceQualityKeep = 0.8;
  const VertId nv = ms.tri.num_verts();
  std::vector<std::int32_t> cnt(nv, 0);
  std::vector<double> ang(nv, 0.0);
  std::vector<char> onb(nv, 0);
  const TriId nt = ms.tri.num_tris();
  const auto& P = ms.tri.points();
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const VertId v = ms.tri.vertex(t, i);
      ++cnt[v];
      if (ms.tri.constraint(3 * t + i) != kNone) {
        onb[ms.tri.vertex(t, detail::next3(i))] = 1;
        onb[ms.tri.vertex(t, detail::prev3(i))] = 1;
      }
      const Vec2 a = P[v], b = P[ms.tri.vertex(t, detail::next3(i))],
                 c = P[ms.tri.vertex(t, detail::prev3(i))];
      const double ux = b.x - a.x, uy = b.y - a.y, wx = c.x - a.x, wy = c.y - a.y;
      ang[v] += std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);
    }
  }
  std::vector<std::int32_t> ideal(nv, 6);
  for (VertId v = 0; v < nv; ++v)
    if (onb[v])
      ideal[v] = std::max(1, static_cast<int>(std::lround(ang[v] / (3.14159265358979323846 / 3))));
  std::int64_t swaps = 0;
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (ms.tri.constraint(h) != kNone) continue;
      const std::int32_t g = ms.tri.twin(h);
      if (g == kNone || g / 3 < t) continue;
      const VertId c = ms.tri.apex(h), a = ms.tri.vertex(t, detail::next3(i)),
                   b = ms.tri.vertex(t, detail::prev3(i));
      const VertId d = ms.tri.apex(g);
      auto dev = [&](VertId v, int delta) {
        const double e = cnt[v] + delta - ideal[v];
        return e * e;
      };
      const double before = dev(a, 0) + dev(b, 0) + dev(c, 0) + dev(d, 0);
      const double after = dev(a, -1) + dev(b, -1) + dev(c, 1) + dev(d, 1);
      if (!(after < before)) continue;
      const Metric2 m = iso_uniform_ ? Metric2{} : quad_metric(a, b, c, d);
      const double qb = std::min(quality_in(m, P[c], P[a], P[b]), quality_in(m, P[d], P[b], P[a]));
      const double qa = std::min(quality_in(m, P[c], P[a], P[d]), quality_in(m, P[d], P[b], P[c]));
      if (qa < kValenceQualityKeep * qb || !ms.tri.flippable(h)) continue;
      ms.tri.flip(h);
      --cnt[a], --cnt[b], ++cnt[c], ++cnt[d];
      ++swaps;
      break;
    }
  }
  return swaps;
}

void Optimizer::run() {
  iso_uniform_ = ms.size.kind == SizeSpec::Kind::Uniform;
  if (ms.lattice_used || (ms.fronts_used && iso_uniform_)) {
    // Lattice or front field points of a uniform field: the interior is equilateral
    // already; only the band along the boundary and the lattice's seam with the boundary
    // layer (where fronts meet) need work, found by their quality (global passes would
    // spend their time on nearly perfect triangles).
    const std::vector<VertId> handled = targeted_pass(kMaxminStop, 4);
    repair(kRepairBad, 12, &handled);
    return;
  }
  // A uniform field without the lattice (a thin domain) keeps the full passes; a varying
  // field gets fewer global passes (more give about the same quality after the repair
  // and size passes below, at twice the optimization time).
  multi_frame_ = !iso_uniform_;
  const int kval = iso_uniform_ ? 3 : 1,
            kpre = iso_uniform_ ? ms.opt.optimize_passes : std::min(2, ms.opt.optimize_passes),
            kmm = iso_uniform_ ? 6 : 2;
  for (int pass = 0; pass < kval; ++pass) {
    if (ms.over_time("optimization")) return;
    const std::int64_t s = valence_pass();
    ms.res.stats.swaps += s;
    ms.res.stats.relocations += smooth_pass();
    if (s < 1e-3 * ms.tri.num_verts()) break;
  }
  // Passes stop early once fewer than kSmoothSettled of the vertices still move: the
  // last passes of a converged smoothing only polish the mean, not the worst element.
  constexpr double kSmoothSettled = 0.02;
  for (int pass = 0; pass < kpre && !ms.field_error; ++pass) {
    if (ms.over_time("optimization")) return;
    const std::int64_t s = swap_pass();
    const std::int64_t r = smooth_pass();
    ms.res.stats.swaps += s;
    ms.res.stats.relocations += r;
    if (s == 0 && r < kSmoothSettled * ms.tri.num_verts()) break;
  }
  ms.res.stats.swaps += swap_pass();
  // Max-min relocation and the targeted repair judge each ball triangle in the mean
  // of its vertex metrics (multi_frame_), as the measure does.
  multi_frame_ = !iso_uniform_;
  // Max-min relocation stops at Q_K = 1.3 for a varying field (1.15 gives the same
  // quality after the repair, more slowly).
  const double qs = iso_uniform_ ? kMaxminStop : kMaxminStopVarying;
  for (int pass = 0; pass < kmm; ++pass) {
    const std::int64_t r = maxmin_pass(qs, 8);
    const std::int64_t s = swap_pass();
    ms.res.stats.relocations += r;
    ms.res.stats.swaps += s;
    if (r == 0 && s == 0) break;
  }
  if (iso_uniform_) {
    repair(kRepairBad, 12);
    return;
  }
  // Size, then shape (§7.5.2): two size passes, each followed by max-min relocation
  // and swaps, then the repair of the triangles still worse than Q 1.4. (A repair
  // before and after every size pass gives the same quality for more work.)
  for (int pass = 0; pass < 2; ++pass) {
    if (ms.over_time("optimization")) return;
    const std::int64_t c = size_pass(kSizeFloor);
    if (c == 0) break;
    for (int k = 0; k < 2; ++k) {
      const std::int64_t r = maxmin_pass(qs, 8);
      const std::int64_t sw = swap_pass();
      ms.res.stats.relocations += r;
      ms.res.stats.swaps += sw;
    }
  }
  repair(kRepairBadVarying, 12);
}

void optimize_mesh(MeshState& ms) {
  Optimizer o(ms);
  o.run();
}

}  // namespace uvmesh::m2d::detail
