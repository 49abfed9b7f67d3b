// The simplification stage (simplify3d.cpp): the stitched mesh cleared of the triangles
// that CAD artefacts smaller than the feature size L force on it (issue 21 of the
// project: edges of a micrometre, faces narrower than the size, gaps between two parts
// of a face's boundary). Not installed.
//
//   SimplifyInput in{model, L / 2, chordal_tol, feature_angle};
//   std::vector<Simplification> log = simplify_mesh(in, mesh);
//
// Every vertex stays on its model entity; the mesh only loses vertices (edge collapses),
// changes diagonals (3D edge swaps), gains vertices on model edges (splits at a point of
// the curve) or moves face nodes of poor triangles along their face (relocation,
// projected back onto the CAD surface). A model edge is sharp (kept as a chain of segments)
// when its faces meet at a dihedral angle of at least the feature angle, it is free or
// non-manifold, it separates two solids or two differently named faces, it is a seam, or the user
// gave it or a face it bounds a size (never merged with another entity either);
// any other edge is smooth and is dissolved (its segments dropped, its nodes classified
// on one of its faces) when an operation needs to cross it.
#pragma once

#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/surface/mesher.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::surface::detail {

struct SimplifyInput {
  const geom::Model& model;
  double collapse_size = 0;  ///< L / 2: what is shorter or narrower goes; 0: nothing
  double chordal_tol = 0;    ///< new triangles' centroids within it of their face; 0: unchecked
  double feature_angle = 0;  ///< radians
  /// Per model edge (empty: none): the user gave it, or a face it bounds, a size. Such an
  /// edge is sharp whatever its dihedral angle and is never merged with another entity.
  std::vector<char> kept_edges;
  int threads = 0;  ///< for the crossing checks (0: all cores); the result does not depend on it
};

/// kept_edges for the sizes `spec` gives (its edge_size and face_size entries).
std::vector<char> user_sized_edges(const geom::Model& m, const param::SizeSpec& spec);

/// Above this shape quality a triangle is a needle or a cap the stage removes.
inline constexpr double kBadShape = 10.0;
/// Above this one it tries swaps and needle collapses that strictly improve the worst Q.
inline constexpr double kPoorShape = 3.0;

/// Simplifies `mesh` in place (deterministically: candidates in sorted order) and returns
/// what it absorbed, in the order it was done. Leaves the mesh untouched when there is
/// nothing to do. Never makes two triangles intersect that did not: where its triangles
/// cross others (parts in near contact), the nodes of the crossing triangles are frozen
/// and the stage runs again from the given mesh (the log says where).
std::vector<Simplification> simplify_mesh(const SimplifyInput& in, SurfaceMesh& mesh);

}  // namespace uvmesh::surface::detail
