// Principal curvatures from the fundamental forms.
#include "uvmesh/param/curvature.h"

#include <cmath>

namespace uvmesh::param {

Curvature principal_curvatures(const geom::SurfacePoint& e) {
  Curvature c;
  const double E = glm::dot(e.du, e.du), F = glm::dot(e.du, e.dv), G = glm::dot(e.dv, e.dv);
  const double det = E * G - F * F;
  const geom::Vec3 n = e.normal();
  // Singular when su x sv vanishes relative to |su||sv| (a pole; see SurfacePoint::normal).
  if (glm::length(n) == 0.0 || !(det > 0.0)) {
    c.singular = true;
    return c;
  }
  c.normal = n;
  const double L = glm::dot(e.duu, n), M = glm::dot(e.duv, n), N = glm::dot(e.dvv, n);
  const double H = (E * N - 2.0 * F * M + G * L) / (2.0 * det);
  const double K = (L * N - M * M) / det;
  const double disc = std::sqrt(std::max(0.0, H * H - K));
  double ka = H + disc, kb = H - disc;
  if (std::abs(kb) > std::abs(ka)) std::swap(ka, kb);
  c.k1 = ka;
  c.k2 = kb;
  // Direction w = (du, dv) of k1: (II - k I) w = 0. Take the better-conditioned row.
  const double a1 = L - ka * E, b1 = M - ka * F;  // row 1: a1 du + b1 dv = 0
  const double a2 = M - ka * F, b2 = N - ka * G;  // row 2
  geom::Vec2 w;
  const double s1 = a1 * a1 + b1 * b1, s2 = a2 * a2 + b2 * b2;
  const double scale =
      std::abs(L) + std::abs(M) + std::abs(N) + std::abs(ka) * (E + std::abs(F) + G);
  if (std::max(s1, s2) <= 1e-24 * scale * scale) {
    w = {1.0, 0.0};  // umbilic: every direction is principal
  } else if (s1 >= s2) {
    w = {-b1, a1};
  } else {
    w = {-b2, a2};
  }
  geom::Vec3 d1 = w.x * e.du + w.y * e.dv;
  d1 = glm::normalize(d1);
  const geom::Vec3 d2 = glm::cross(n, d1);
  c.dir1 = d1;
  c.dir2 = d2;
  // (u,v) coordinates of a 3D tangent t: solve I [a b]^T = [t.su t.sv]^T.
  auto to_uv = [&](const geom::Vec3& t) {
    const double p = glm::dot(t, e.du), q = glm::dot(t, e.dv);
    return geom::Vec2((G * p - F * q) / det, (E * q - F * p) / det);
  };
  c.uv1 = to_uv(d1);
  c.uv2 = to_uv(d2);
  return c;
}

}  // namespace uvmesh::param
