// Principal curvatures and directions of a parametric surface from its first and second
// fundamental forms.
//
//   geom::SurfacePoint e = surface.eval(u, v);
//   param::Curvature c = param::principal_curvatures(e);
//   // c.k1, c.k2 (|k1| >= |k2|), c.dir1, c.dir2 (3D, unit), c.uv1, c.uv2 ((u,v) directions)
//
// I = [E F; F G] (E = su.su, F = su.sv, G = sv.sv), II = [L M; M N] (L = suu.n, ...),
// n = su x sv / |su x sv|. The principal curvatures are the eigenvalues of the shape
// operator I^-1 II; their sign follows n (a sphere with outward n has k = -1/r).
#pragma once

#include "uvmesh/geom/surface.h"

namespace uvmesh::param {

struct Curvature {
  double k1 = 0.0;  ///< principal curvature of largest magnitude
  double k2 = 0.0;
  geom::Vec3 dir1{0.0}, dir2{0.0};  ///< unit tangent directions of k1, k2 (dir2 = n x dir1)
  geom::Vec2 uv1{0.0}, uv2{0.0};    ///< the same directions as (du, dv)
  geom::Vec3 normal{0.0};
  /// The map is singular here (pole, |su x sv| ~ 0): curvatures are not defined and are
  /// reported as 0.
  bool singular = false;
  double mean() const { return 0.5 * (k1 + k2); }
  double gauss() const { return k1 * k2; }
};

Curvature principal_curvatures(const geom::SurfacePoint& e);

}  // namespace uvmesh::param
