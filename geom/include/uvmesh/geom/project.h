// uvmesh::geom::project_to_surface -- the closest point of a surface to a point in space,
// near a starting (u,v). Used wherever a 3D point has to be put back on its surface: the
// chordal deviation of a mesh (surface/check3d.h), the (u,v) of the nodes of a mesh read
// from a file (io/report.h, attach_uv), coincident-face detection and the face mesher.
//
//   geom::Projection p = geom::project_to_surface(s, x, uv0, face.uv_box, h);
//   if (p.converged) use(p.uv, p.point, p.distance);
#pragma once

#include "uvmesh/geom/surface.h"
#include "uvmesh/geom/types.h"

namespace uvmesh::geom {

struct Projection {
  Vec2 uv{0.0, 0.0};
  Vec3 point{0.0, 0.0, 0.0};  ///< sigma(uv)
  double distance = 0;
  int iterations = 0;
  bool converged = false;
};

/// Closest point of s to x near uv0: Newton on |sigma(u,v) - x|^2 (second derivatives;
/// Levenberg-Marquardt damping on the first fundamental form where the Hessian is not
/// positive definite, e.g. at poles), backtracking line search, bound constraints on
/// `box` (active set). `scale` is a length of the problem (e.g. the triangle size), tol =
/// 1e-10 scale. Converged: the distance is below tol, or a full Newton step moves sigma
/// by less than tol, or along every free direction (one not blocked by a bound) the
/// residual's tangential component is below 1e-6 |residual| + tol.
Projection project_to_surface(const Surface& s, const Vec3& x, Vec2 uv0, const Box2& box,
                              double scale, int max_iter = 30);

}  // namespace uvmesh::geom
