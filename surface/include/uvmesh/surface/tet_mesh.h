// uvmesh::surface::TetMesh -- the tetrahedral mesh of a model's solids, the product of the
// volume stage (uvmesh/surface/volume.h, target uvmesh::volume) and an input of the writers
// and the report. Plain data and measures only: this header and its measures are part of
// uvmesh::surface, so that io can write and report tetrahedra without depending on the
// volume mesher's library.
//
//   surface::TetMesh v = surface::fill_solids(model, mesh, {}).mesh;
//   // v.points[i] == mesh.points[i] for i < mesh.points.size(): the surface mesh's points
//   // first, unchanged, then the interior points the volume mesher added.
//   for (std::size_t t = 0; t < v.tets.size(); ++t) {
//     auto [a, b, c, d] = v.tets[t];        // positive volume: (b-a).((c-a)x(d-a)) > 0
//     geom::Id solid = v.tet_solid[t];      // model.solids index
//   }
//
// Quality measures (one definition each, used by the report, the tests and the benchmark):
//   * minimum dihedral angle: the smallest of the six interior dihedral angles, in degrees
//     (70.53 for the regular tetrahedron, 0 for a flat one);
//   * radius-edge ratio: circumradius over the shortest edge (sqrt(6)/4 = 0.612 for the
//     regular tetrahedron, infinite for a flat one). TetGen's -q bound is on this ratio.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "uvmesh/geom/types.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::surface {

struct TetMesh {
  /// The surface mesh's points (same indices, same coordinates), then interior points.
  std::vector<geom::Vec3> points;
  std::size_t surface_points = 0;  ///< how many of `points` are the surface mesh's
  /// Solid each interior point lies in (points[surface_points + i]).
  std::vector<geom::Id> interior_point_solid;
  std::vector<std::array<NodeId, 4>> tets;  ///< positively oriented
  std::vector<geom::Id> tet_solid;

  std::size_t num_tets() const { return tets.size(); }
};

/// Signed volume of (a, b, c, d): positive when d is on the side of (a, b, c) that the
/// right-hand normal (b-a)x(c-a) points to.
double tet_volume(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                  const geom::Vec3& d);

/// Smallest interior dihedral angle in degrees (0 for a flat tetrahedron).
double tet_min_dihedral_deg(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                            const geom::Vec3& d);

/// Circumradius over shortest edge (infinity for a flat tetrahedron).
double tet_radius_edge(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c,
                       const geom::Vec3& d);

/// Distribution of the two measures over a set of tetrahedra. Percentiles are nearest-rank,
/// like QualityReport's: p1 of the dihedral angle is the smallest value with at least 1% of
/// the tetrahedra at or below it; p99 of the radius-edge ratio the largest with at least 1%
/// at or above it (the bad tail of each measure).
struct TetQualityReport {
  std::size_t tets = 0;
  std::size_t inverted = 0;  ///< volume <= 0 (should be 0)
  double volume = 0;         ///< sum of the signed volumes
  double dihedral_min = 0, dihedral_p1 = 0, dihedral_p50 = 0;
  double radius_edge_max = 0, radius_edge_p99 = 0, radius_edge_p50 = 0;
};

/// The measures over the tetrahedra of `solid`, or over all of them with solid == kNone.
TetQualityReport measure_tet_quality(const TetMesh& m, geom::Id solid = geom::kNone);

}  // namespace uvmesh::surface
