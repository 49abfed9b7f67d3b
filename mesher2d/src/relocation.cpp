// Vertex relocation of the optimizer (§7.3.6 "metric techniques"): the ball of a vertex
// in its metric frame, max-min and p-norm relocation.
#include <algorithm>
#include <cmath>

#include "optimizer.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

// The ring of vertex v (the ball's opposite edges (ring[k], ring[k+1]), counter-
// clockwise); false when v is on the box border or its ball is not closed.
bool Optimizer::gather_ring(VertId v, std::vector<VertId>& ring) const {
  ring.clear();
  const TriId t0 = ms.tri.vertex_tri(v);
  if (t0 == kNone || !ms.in_domain(t0)) return false;
  TriId t = t0;
  do {
    int k = 0;
    while (ms.tri.vertex(t, k) != v) ++k;
    ring.push_back(ms.tri.vertex(t, detail::next3(k)));
    const std::int32_t h = ms.tri.twin(3 * t + detail::next3(k));  // edge (prev, v)
    if (h == kNone) return false;
    t = h / 3;
  } while (t != t0 && ring.size() < 64);
  return t == t0;
}

// Optimization-based relocation (§7.3.6 "metric techniques", max-min form): moves a
// vertex to raise the worst quality 1/Q_K of its ball, by steepest ascent of the worst
// triangles (the direction of least norm in the convex hull of the gradients of the
// nearly worst ones, so that no active triangle gets worse to first order) with a
// backtracking line search; every accepted step strictly raises the ball's minimum and
// keeps all ball triangles counter-clockwise (ball_valid in the frame vf of the ring vring, exact
// orientation). Laplacian smoothing improves the mean but stalls where one triangle trades against
// another; this is what brings the worst elements of a uniform mesh under Q = 1.2. The ball is the
// closed ring fr_ (frame coordinates: Euclidean for a uniform field, the metric frame of the vertex
// otherwise); p is moved in place; returns the ball's minimum 1/Q_K at p (-1 if a triangle is
// inverted at the start).
double Optimizer::maxmin_core(Vec2& p, double qstop, int iters, const MetricFrame& vf,
                              const std::vector<VertId>& vring) {
  const std::size_t n = fr_.size();
  qk_.resize(n);
  gk_.resize(n);
  // q = area2 / (alpha * per * hmax) of (p, a, b) and its gradient in p.
  auto eval = [&](Vec2 pp, bool grad) {
    work_ += static_cast<std::int64_t>(n);
    double qmin = 1e300;
    for (std::size_t k = 0; k < n; ++k) {
      Vec2 a, b, P;
      ball_tri(k, pp, a, b, P);
      const double ux = a.x - P.x, uy = a.y - P.y, wx = b.x - P.x, wy = b.y - P.y;
      const double ex = b.x - a.x, ey = b.y - a.y;
      const double area2 = ux * wy - uy * wx;
      if (!(area2 > 0)) return -1.0;
      const double la = std::sqrt(ux * ux + uy * uy), lb = std::sqrt(wx * wx + wy * wy),
                   le = std::sqrt(ex * ex + ey * ey);
      const double per = la + lb + le, hm = std::max({la, lb, le});
      const double q = measures::shape_q(la, lb, le, area2);
      qk_[k] = q;
      qmin = std::min(qmin, q);
      if (grad) {
        // d area2 = (-ey, ex); d per = -u/la - w/lb; d hmax = -u/la or -w/lb or 0.
        double gx = -ey / area2 - (-ux / la - wx / lb) / per;
        double gy = ex / area2 - (-uy / la - wy / lb) / per;
        if (hm == la)
          gx += ux / (la * hm), gy += uy / (la * hm);
        else if (hm == lb)
          gx += wx / (lb * hm), gy += wy / (lb * hm);
        gk_[k] = ball_grad(k, {q * gx, q * gy});
      }
    }
    return qmin;
  };
  double qmin = eval(p, true);
  if (!(qmin > 0)) return qmin;
  for (int it = 0; it < iters && qmin < qstop; ++it) {
    // Active set: triangles within a small margin of the minimum.
    const double tol = 0.02 * qmin;
    Vec2 d{0, 0};
    {
      std::size_t act[8];
      int na = 0;
      for (std::size_t k = 0; k < n && na < 8; ++k)
        if (qk_[k] <= qmin + tol) act[na++] = k;
      // Least-norm point of the convex hull of the active gradients: the best of the
      // single gradients and the pairwise segment projections that are ascent
      // directions for every active triangle.
      double best = -1;
      auto consider = [&](Vec2 c) {
        const double nn = c.x * c.x + c.y * c.y;
        if (!(nn > 0)) return;
        for (int j = 0; j < na; ++j)
          if (gk_[act[j]].x * c.x + gk_[act[j]].y * c.y < 0.999 * nn) return;
        if (best < 0 || nn < best) best = nn, d = c;
      };
      for (int i = 0; i < na; ++i) {
        consider(gk_[act[i]]);
        for (int j = i + 1; j < na; ++j) {
          const Vec2 g1 = gk_[act[i]], g2 = gk_[act[j]];
          const double dx = g2.x - g1.x, dy = g2.y - g1.y, dd = dx * dx + dy * dy;
          if (!(dd > 0)) continue;
          const double t = std::clamp(-(g1.x * dx + g1.y * dy) / dd, 0.0, 1.0);
          consider({g1.x + t * dx, g1.y + t * dy});
        }
      }
      if (best < 0) break;  // no common ascent direction: a local max-min optimum
    }
    const double dn2 = d.x * d.x + d.y * d.y;
    // Linear prediction of the step where a non-active triangle becomes the worst,
    // capped at a tenth of the local edge length.
    double step = 1e300;
    for (std::size_t k = 0; k < n; ++k) {
      const double slope = gk_[k].x * d.x + gk_[k].y * d.y;
      if (slope < dn2 && qk_[k] > qmin + tol)
        step = std::min(step, (qk_[k] - qmin) / (dn2 - slope));
    }
    const double ex = fr_[0].x - p.x, ey = fr_[0].y - p.y;
    step = std::min(step, 0.1 * std::sqrt((ex * ex + ey * ey) / dn2));
    bool took = false;
    for (int ls = 0; ls < 6; ++ls, step *= 0.5) {
      const Vec2 np{p.x + step * d.x, p.y + step * d.y};
      const double nq = eval(np, false);
      if (nq > qmin * (1 + 1e-9) && ball_valid(vf, np, vring)) {
        p = np;
        took = true;
        break;
      }
    }
    if (!took) break;
    qmin = eval(p, true);
  }
  return qmin;
}

// Relocation by descent of F = sum over the ball of Q_K^p (p = kPnorm): smooth where
// the max-min is not, so that a sweep over a neighbourhood unpins vertices whose worst
// triangles hold each other at a kink of the max-min (at the corners of a square Q_M
// stayed just above 1.2 after max-min sweeps alone). Same frame and validity as
// maxmin_core; returns true when p moved.
bool Optimizer::pnorm_core(Vec2& p, const MetricFrame& vf, const std::vector<VertId>& vring) {
  constexpr double kPnorm = 8;  // the power in term below
  const std::size_t n = fr_.size();
  // F and its gradient, with Q_K scaled by s (the ball's initial worst) to stay finite.
  double s = 0;
  auto eval = [&](Vec2 pp, bool grad, Vec2& g) {
    work_ += static_cast<std::int64_t>(n);
    double F = 0;
    g = {0, 0};
    for (std::size_t k = 0; k < n; ++k) {
      Vec2 a, b, P;
      ball_tri(k, pp, a, b, P);
      const double ux = a.x - P.x, uy = a.y - P.y, wx = b.x - P.x, wy = b.y - P.y;
      const double ex = b.x - a.x, ey = b.y - a.y;
      const double area2 = ux * wy - uy * wx;
      if (!(area2 > 0)) return 1e300;
      const double la = std::sqrt(ux * ux + uy * uy), lb = std::sqrt(wx * wx + wy * wy),
                   le = std::sqrt(ex * ex + ey * ey);
      const double per = la + lb + le, hm = std::max({la, lb, le});
      const double Q = measures::shape_Q(la, lb, le, area2);
      if (s == 0) continue;
      const double r2 = (Q / s) * (Q / s), r4 = r2 * r2, term = r4 * r4;  // (Q / s)^8
      F += term;
      if (grad) {
        // d log Q = d per / per + d hmax / hmax - d area2 / area2.
        double gx = (-ux / la - wx / lb) / per + ey / area2;
        double gy = (-uy / la - wy / lb) / per - ex / area2;
        if (hm == la)
          gx -= ux / (la * hm), gy -= uy / (la * hm);
        else if (hm == lb)
          gx -= wx / (lb * hm), gy -= wy / (lb * hm);
        const Vec2 gp = ball_grad(k, {gx, gy});
        g.x += kPnorm * term * gp.x;
        g.y += kPnorm * term * gp.y;
      }
    }
    return F;
  };
  Vec2 g;
  // First call finds the scale: the worst Q of the ball.
  {
    double worst = 0;
    for (std::size_t k = 0; k < n; ++k) {
      Vec2 a, b, P;
      ball_tri(k, p, a, b, P);
      const double q = q_inv(P, a, b);
      if (!(q > 0)) return false;
      worst = std::max(worst, 1 / q);
    }
    s = worst;
  }
  double F = eval(p, true, g);
  bool moved = false;
  for (int it = 0; it < 4; ++it) {
    const double gn = std::sqrt(g.x * g.x + g.y * g.y);
    if (!(gn > 0)) break;
    const double ex = fr_[0].x - p.x, ey = fr_[0].y - p.y;
    double step = 0.05 * std::sqrt(ex * ex + ey * ey) / gn;
    bool took = false;
    for (int ls = 0; ls < 8; ++ls, step *= 0.5) {
      const Vec2 np{p.x - step * g.x, p.y - step * g.y};
      Vec2 ng;
      const double nF = eval(np, false, ng);
      if (nF < F && ball_valid(vf, np, vring)) {
        p = np;
        took = true;
        break;
      }
    }
    if (!took) break;
    moved = true;
    F = eval(p, true, g);
  }
  return moved;
}

bool Optimizer::pnorm_relocate(VertId v, std::vector<VertId>& ring) {
  if (ms.fixed[v] || !gather_ring(v, ring)) return false;
  const detail::MetricFrame f = frame_of(v);
  load_ring(f, ring, ms.vm[v]);
  Vec2 p = iso_uniform_ ? ms.tri.point(v) : f(ms.tri.point(v));
  if (!pnorm_core(p, f, ring)) return false;
  set_position(v, iso_uniform_ ? p : f.inv(p));
  return true;
}

bool Optimizer::ball_valid(const detail::MetricFrame& f, Vec2 fp,
                           const std::vector<VertId>& ring) const {
  const Vec2 q = iso_uniform_ ? fp : f.inv(fp);
  const auto& P = ms.tri.points();
  const std::size_t n = ring.size();
  for (std::size_t k = 0; k < n; ++k)
    if (!(pred::orient2d(&q.x, &P[ring[k]].x, &P[ring[k + 1 == n ? 0 : k + 1]].x) > 0))
      return false;
  return true;
}

// mv: the metric of the moving vertex, for the per-triangle frames of a varying field.
void Optimizer::load_ring(const detail::MetricFrame& f, const std::vector<VertId>& ring,
                          const Metric2& mv) {
  const std::size_t n = ring.size();
  fr_.resize(n);
  for (std::size_t k = 0; k < n; ++k)
    fr_[k] = iso_uniform_ ? ms.tri.point(ring[k]) : f(ms.tri.point(ring[k]));
  if (!multi_frame_) return;
  // Each ball triangle in its own frame, that of the mean of its vertex metrics (as
  // tri_q and the measure judge it): one frame for the whole ball misjudges a metric
  // that turns or grades across it (a ring-shaped boundary layer turns by degrees and
  // grades by percent from element to element). The map from the ball's frame f to triangle k's
  // frame R_k is R_k f^-1, upper triangular like both.
  bt_.resize(n);
  const auto& P = ms.tri.points();
  for (std::size_t k = 0; k < n; ++k) {
    const VertId ra = ring[k], rb = ring[k + 1 == n ? 0 : k + 1];
    const detail::MetricFrame r(detail::mean3(mv, ms.vm[ra], ms.vm[rb]));
    BallTri& t = bt_[k];
    t.a11 = r.l11 / f.l11;
    t.a12 = r.l12 / f.l22 - r.l11 * f.l12 / (f.l11 * f.l22);
    t.a22 = r.l22 / f.l22;
    t.a = r(P[ra]);
    t.b = r(P[rb]);
  }
}

void Optimizer::set_position(VertId v, Vec2 q) {
  ms.tri.set_point(v, q);
  if (!iso_uniform_) {
    ms.vm[v] = ms.metric(q.x, q.y);
    if (static_cast<std::size_t>(v) < ms.rs.size() && ms.rs[v] < 1)
      ms.vm[v] = detail::scaled(ms.vm[v], 1.0 / (ms.rs[v] * ms.rs[v]));
  }
}

bool Optimizer::maxmin_relocate(VertId v, std::vector<VertId>& ring, double qstop, int iters) {
  if (ms.fixed[v] || !gather_ring(v, ring)) return false;
  const detail::MetricFrame f = frame_of(v);
  load_ring(f, ring, ms.vm[v]);
  const Vec2 p0 = iso_uniform_ ? ms.tri.point(v) : f(ms.tri.point(v));
  Vec2 p = p0;
  maxmin_core(p, qstop, iters, f, ring);
  if (p.x == p0.x && p.y == p0.y) return false;
  set_position(v, iso_uniform_ ? p : f.inv(p));
  return true;
}

}  // namespace uvmesh::m2d::detail
