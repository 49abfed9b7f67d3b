// geom::project_to_surface (project.h): Newton with bounds, line search and a
// Levenberg-Marquardt fallback.
#include "uvmesh/geom/project.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uvmesh::geom {

Projection project_to_surface(const Surface& s, const Vec3& x, Vec2 uv0, const Box2& box,
                              double scale, int max_iter) {
  auto clampuv = [&](Vec2 p) {
    return Vec2(std::clamp(p.x, box.u.lo, box.u.hi), std::clamp(p.y, box.v.lo, box.v.hi));
  };
  Projection out;
  Vec2 uv = clampuv(uv0);
  SurfacePoint e = s.eval(uv.x, uv.y);
  Vec3 r = e.p - x;
  double f = glm::dot(r, r);
  if (!(scale > 0)) scale = std::max(glm::length(x), 1.0);
  const double tol = 1e-10 * scale;

  // Converged: the point is on the surface to within tol, or first-order optimality with
  // the bounds: along every free tangent direction the residual's component is below
  // 1e-6 |r| + tol (the distance is then exact to about 1e-12 relative; the absolute
  // part absorbs the rounding noise of sigma and of tiny residuals).
  auto stationary = [&](const SurfacePoint& ep, const Vec3& res, Vec2 p) {
    const double rl = glm::length(res);
    if (rl <= tol) return true;
    const double gu = glm::dot(ep.du, res), gv = glm::dot(ep.dv, res);
    const bool fu = (p.x <= box.u.lo && gu > 0) || (p.x >= box.u.hi && gu < 0);
    const bool fv = (p.y <= box.v.lo && gv > 0) || (p.y >= box.v.hi && gv < 0);
    const double lim = 1e-6 * rl + tol;
    return (fu || std::fabs(gu) <= lim * glm::length(ep.du)) &&
           (fv || std::fabs(gv) <= lim * glm::length(ep.dv));
  };

  int it = 0;
  bool converged = f <= tol * tol;  // already on the surface
  for (; it < max_iter && !converged; ++it) {
    const double gu = glm::dot(e.du, r), gv = glm::dot(e.dv, r);
    const double E = glm::dot(e.du, e.du), F = glm::dot(e.du, e.dv), G = glm::dot(e.dv, e.dv);
    // Active set: a variable sitting on a bound whose descent direction (-g) points out.
    const bool fixu = (uv.x <= box.u.lo && gu > 0) || (uv.x >= box.u.hi && gu < 0);
    const bool fixv = (uv.y <= box.v.lo && gv > 0) || (uv.y >= box.v.hi && gv < 0);
    if (fixu && fixv) {
      converged = true;
      break;
    }
    // Newton matrix (Hessian of f/2); where it is not positive definite, the first
    // fundamental form with a small Levenberg-Marquardt shift (poles: E = 0).
    double huu = E + glm::dot(e.duu, r), huv = F + glm::dot(e.duv, r), hvv = G + glm::dot(e.dvv, r);
    const double shift = 1e-12 * (E + G) + std::numeric_limits<double>::min();
    const bool pd = huu > 0 && hvv > 0 && huu * hvv - huv * huv > 1e-12 * huu * hvv;
    if (!pd) {
      huu = E + shift;
      huv = F;
      hvv = G + shift;
    }
    Vec2 d(0.0, 0.0);
    if (fixu) {
      d.y = gv / hvv;
    } else if (fixv) {
      d.x = gu / huu;
    } else {
      const double det = huu * hvv - huv * huv;
      if (!(det > 0)) break;
      d = Vec2((hvv * gu - huv * gv) / det, (huu * gv - huv * gu) / det);
    }
    if (!std::isfinite(d.x) || !std::isfinite(d.y)) break;
    // Backtracking: accept the first step that does not increase the distance by more
    // than tol. Near the solution the gain of a Newton step (the square of a tangential
    // residual) drops below the rounding noise of |sigma - x|^2 long before the
    // tangential residual itself is small, so "strictly no increase" would stall there.
    const double accept = (std::sqrt(f) + tol) * (std::sqrt(f) + tol);
    double t = 1.0;
    bool accepted = false;
    Vec2 uvn;
    SurfacePoint en;
    Vec3 rn;
    double fn = f;
    for (int ls = 0; ls < 40; ++ls, t *= 0.5) {
      uvn = clampuv(uv - t * d);
      en = s.eval(uvn.x, uvn.y);
      rn = en.p - x;
      fn = glm::dot(rn, rn);
      if (fn <= accept) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      // No decrease along the step: a minimum to rounding, if the gradient says so.
      converged = stationary(e, r, uv);
      break;
    }
    const double moved = glm::length(en.p - e.p);
    uv = uvn;
    e = en;
    r = rn;
    f = fn;
    if (moved <= tol) {
      // A full Newton step this small is convergence; a tiny damped one may be a stall.
      converged = t == 1.0 || stationary(e, r, uv);
      ++it;
      break;
    }
  }
  if (!converged) converged = stationary(e, r, uv);
  out.uv = uv;
  out.point = e.p;
  out.distance = std::sqrt(f);
  out.iterations = it;
  out.converged = converged;
  return out;
}

}  // namespace uvmesh::geom
