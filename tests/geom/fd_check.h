// Finite-difference checks of surface and curve derivatives, shared by the back-end tests.
#pragma once

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "uvmesh/geom/curve.h"
#include "uvmesh/geom/surface.h"

namespace uvmesh::test {

/// Central differences of sigma and its first derivatives at (u,v) with steps h_u, h_v;
/// returns the largest error relative to `scale` (a length of the patch's image, so the
/// check is unit-free). Exact derivatives give O(h^2) errors.
inline double surface_fd_error(const geom::Surface& s, double u, double v, double hu, double hv,
                               double scale) {
  const geom::SurfacePoint e = s.eval(u, v);
  const auto pu = s.eval(u + hu, v), mu = s.eval(u - hu, v), pv = s.eval(u, v + hv),
             mv = s.eval(u, v - hv);
  // First derivatives scaled by the step (lengths), second by the step squared.
  double err = 0.0;
  auto upd = [&](const geom::Vec3& fd, const geom::Vec3& an, double step) {
    err = std::max(err, glm::length(fd - an) * step / scale);
  };
  upd((pu.p - mu.p) / (2 * hu), e.du, hu);
  upd((pv.p - mv.p) / (2 * hv), e.dv, hv);
  upd((pu.du - mu.du) / (2 * hu), e.duu, hu * hu);
  upd((pv.dv - mv.dv) / (2 * hv), e.dvv, hv * hv);
  upd((pv.du - mv.du) / (2 * hv), e.duv, hu * hv);
  upd((pu.dv - mu.dv) / (2 * hu), e.duv, hu * hv);
  return err;
}

inline double curve_fd_error(const geom::Curve& c, double t, double h, double scale) {
  const auto e = c.eval(t), p = c.eval(t + h), m = c.eval(t - h);
  return std::max(glm::length((p.p - m.p) / (2 * h) - e.d1) * h / scale,
                  glm::length((p.d1 - m.d1) / (2 * h) - e.d2) * h * h / scale);
}

}  // namespace uvmesh::test
