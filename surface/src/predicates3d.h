// Exact 3D orientation predicate and the exact triangle/triangle intersection tests built
// on it (used by check3d.cpp's self-intersection search; private to uvmesh::surface, the
// tests reach it through their include path).
//
//   double o = uvmesh::surface::pred3::orient3d(a, b, c, d);
//   // > 0: d lies below the plane through a, b, c, where "below" is the side from which
//   //      a, b, c appear clockwise (equivalently det[a-d; b-d; c-d] > 0);
//   // = 0: the four points are exactly coplanar.
//
// The sign is exact (adaptive precision: a floating-point filter, then exact expansion
// arithmetic; see predicates3d.cpp) for every finite input, subnormals included. The
// magnitude is only approximate. No global state: thread-safe.
#pragma once

#include <array>

#include "uvmesh/geom/types.h"

namespace uvmesh::surface::pred3 {

double orient3d(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c, const geom::Vec3& d);
/// Plain double evaluation of the same determinant (tests and benchmarks only).
double orient3d_fast(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                     const geom::Vec3& d);

/// Exact sign (-1, 0, +1) of orient3d.
int orient3d_sign(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                  const geom::Vec3& d);

using Tri = std::array<geom::Vec3, 3>;

/// Axis (0, 1, 2) along which the projection of the triangle keeps a nonzero exact area,
/// i.e. a coordinate whose normal component is nonzero; -1 when the three points are
/// exactly collinear (zero area, including coincident points).
int projection_axis(const Tri& t);

/// Do the two closed triangles (as point sets) have a common point? Exact. Both triangles
/// must be non-degenerate (projection_axis >= 0).
bool closed_triangles_intersect(const Tri& t0, const Tri& t1);

/// Triangles v a b and v c d share the vertex v (by index). True when their intersection
/// is more than the point v. Exact; both non-degenerate.
bool intersect_beyond_vertex(const geom::Vec3& v, const geom::Vec3& a, const geom::Vec3& b,
                             const geom::Vec3& c, const geom::Vec3& d);

/// Triangles a b c and a b d share the edge ab (by index). True when their intersection
/// is more than the segment ab: only when they are coplanar with c and d on the same side
/// of ab (the mesh folds over itself). Exact; both non-degenerate.
bool intersect_beyond_edge(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                           const geom::Vec3& d);

}  // namespace uvmesh::surface::pred3
