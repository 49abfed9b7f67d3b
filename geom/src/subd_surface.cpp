// Domains of the n-gon patches of a subdivision Model: the flattened polygon of an n-gon
// (NgonSurface) and the projected re-parameterization at high-valence vertices
// (ProjectedSurface), with the checks that make them one-to-one.
#include "subd_surface.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <vector>

namespace uvmesh::geom::subd_detail {

// The domain of an n-gon patch (NgonSurface) from the limit points of its sub-faces:
// corners, side points (sub-face corner (1,0)) and centre, projected on the plane of the
// boundary's Newell normal, corner 0 at the origin, side 0 along +u, scaled to extent 1.
// Shaped after the limit surface rather than the cage, each bilinear quad is close to an
// isometry of its piece, so sigma's derivatives agree across the spokes (with the cage
// polygon of a thin triangle next to a valence-64 pole, sigma_u turned by 120 degrees
// across a spoke and Newton projections stalled on it). Empty (sub-face patches are used)
// when a vertex repeats or a quad is not strictly convex (the bilinear maps would not be
// one-to-one) or the quads do not turn once around the centre.
bool flatten_ngon(const std::vector<Vec3>& bnd, const Vec3& centre, std::vector<Vec2>& out,
                  Vec2& c2, SubdPlane& plane) {
  const int m = static_cast<int>(bnd.size()), n = m / 2;
  Vec3 N{0.0};
  for (int i = 0; i < m; ++i) N += glm::cross(bnd[i] - centre, bnd[(i + 1) % m] - centre);
  const double ln = glm::length(N);
  if (!(ln > 0) || !std::isfinite(ln)) return false;
  N /= ln;
  Vec3 x = (bnd[1] - bnd[0]) - glm::dot(bnd[1] - bnd[0], N) * N;
  if (!(glm::length(x) > 0)) return false;
  x = glm::normalize(x);
  const Vec3 y = glm::cross(N, x);
  std::vector<Vec2> q;
  double ext = 0;
  for (const Vec3& a : bnd) {
    q.push_back({glm::dot(a - bnd[0], x), glm::dot(a - bnd[0], y)});
    ext = std::max({ext, std::abs(q.back().x), std::abs(q.back().y)});
  }
  if (!(ext > 0)) return false;
  for (Vec2& a : q) a /= ext;
  const Vec2 c{glm::dot(centre - bnd[0], x) / ext, glm::dot(centre - bnd[0], y) / ext};
  double turn = 0;
  for (int k = 0; k < n; ++k) {
    const Vec2 quad[4] = {q[2 * k], q[2 * k + 1], c, q[(2 * k + m - 1) % m]};
    for (int i = 0; i < 4; ++i) {
      const Vec2 a = quad[(i + 1) % 4] - quad[i], b = quad[(i + 2) % 4] - quad[(i + 1) % 4];
      if (!(a.x * b.y - a.y * b.x > 1e-6 * glm::length(a) * glm::length(b))) return false;
    }
    const Vec2 a = quad[3] - c, b = quad[1] - c;
    turn += std::atan2(a.x * b.y - a.y * b.x, glm::dot(a, b));
  }
  if (std::abs(turn - 2 * std::acos(-1.0)) > 1e-6) return false;
  out = std::move(q);
  c2 = c;
  plane = {bnd[0], x, y, ext};
  return true;
}

// The projected version of an n-gon patch (ProjectedSurface), or null when the
// projection is not one-to-one on it: the Jacobian of P o inner must keep its sign
// (positive: the polygon is CCW in the same plane) on 9 x 9 samples of every quad, and
// stay above 1e-3 of its median (a fold or a cusp of the projection would make the
// inversion ill-conditioned).
std::shared_ptr<const ProjectedSurface> make_projected(
    const std::vector<std::shared_ptr<const SubdSurface>>& sub, const SubdPlane& pl) {
  constexpr int ns = 8;
  std::vector<std::pair<int, Vec2>> zs;
  std::vector<double> dets;
  Box2 box{{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
           {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
  for (int k = 0; k < static_cast<int>(sub.size()); ++k)
    for (int i = 0; i <= ns; ++i)
      for (int j = 0; j <= ns; ++j) {
        const Vec2 z{double(i) / ns, double(j) / ns};
        const SurfacePoint e = sub[static_cast<std::size_t>(k)]->eval(z.x, z.y);
        const Vec2 w = pl.map(e.p), a0 = pl.dir(e.du), a1 = pl.dir(e.dv);
        zs.push_back({k, z});
        dets.push_back(a0.x * a1.y - a0.y * a1.x);
        box.u.lo = std::min(box.u.lo, w.x), box.u.hi = std::max(box.u.hi, w.x);
        box.v.lo = std::min(box.v.lo, w.y), box.v.hi = std::max(box.v.hi, w.y);
      }
  std::vector<double> sorted = dets;
  std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
  const double med = sorted[sorted.size() / 2];
  if (!(med > 0)) return nullptr;
  for (double d : dets)
    if (!(d > 1e-3 * med)) return nullptr;
  // The boundary curves bulge between samples; the box only bounds the metric grids.
  const double mu = 0.02 * box.u.length(), mv = 0.02 * box.v.length();
  box.u.lo -= mu, box.u.hi += mu, box.v.lo -= mv, box.v.hi += mv;
  return std::make_shared<ProjectedSurface>(sub, pl, zs, box);
}

}  // namespace uvmesh::geom::subd_detail
