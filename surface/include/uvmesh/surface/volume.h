// uvmesh::volume -- tetrahedra filling every closed solid of a model, seeded by the surface
// mesh unchanged (target uvmesh::volume, built when Netgen's nglib is found; the surface
// library itself does not depend on it).
//
//   surface::MeshResult s = surface::mesh_model(model, opts);
//   surface::VolumeOptions vo;
//   vo.hmax = opts.size.hmax;
//   surface::VolumeResult v = surface::fill_solids(model, s.mesh, vo);
//   for (const auto& f : v.failed) log(f.message);     // "solid 3 (name): ..."
//   io::WriteOptions w;  w.volume = &v.mesh;  io::write_mesh(s.mesh, &model, "part.msh", w);
//
// Contract
//   * One region per solid: every tetrahedron carries its solid id (TetMesh::tet_solid).
//   * The boundary faces of each solid's tetrahedra are exactly that solid's triangles of
//     the surface mesh (same node indices), and the surface mesh's points keep their
//     indices and their coordinates bit for bit; interior points are appended. This is
//     verified after meshing, not assumed: a solid whose tetrahedra would change the
//     surface is reported as failed and left empty.
//   * A face shared by two solids (conforming assembly interface) bounds both: each solid
//     is filled separately from the same triangles, so the tetrahedra of the two solids
//     meet face to face there.
//   * A solid whose surface is not closed (surface::solid_surface(...).watertight() is
//     false: the one definition the report uses), or that the mesher cannot fill, gets a
//     failure naming it; the other solids are still filled.
//
// Netgen (nglib) keeps global state (its meshing parameters, its output streams, its
// debug stream) between Ng_Init and Ng_Exit, so calls into it are serialized by a mutex
// inside fill_solids: two threads may call fill_solids, they run one after the other.
// Netgen's own messages are silenced while it runs; nothing is printed.
#pragma once

#include <string>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/surface/surface_mesh.h"
#include "uvmesh/surface/tet_mesh.h"

namespace uvmesh::surface {

struct VolumeOptions {
  /// Largest tetrahedron edge wanted (0: no bound; the sizes grow from the surface mesh's
  /// edges with Netgen's grading). Usually the surface mesh's hmax.
  double hmax = 0.0;
  /// Netgen's grading, 0..1 (0: uniform, 1: aggressive); 0.3 is Netgen's default.
  double grading = 0.3;
  /// Netgen's 3D optimization steps (0: none). Interior points only: the surface is fixed.
  int optimize_steps = 3;
  /// Only these solids (model.solids indices); empty: all of them.
  std::vector<geom::Id> solids;
};

struct SolidFailure {
  geom::Id solid = geom::kNone;
  std::string name;     ///< the solid's CAD name, "" when it has none
  std::string message;  ///< "solid <id+1> "<name>": <reason>" -- names it for a person
};

struct SolidVolumeStats {
  geom::Id solid = geom::kNone;
  std::size_t triangles = 0;  ///< boundary triangles fed to the mesher
  std::size_t tets = 0;
  std::size_t interior_points = 0;
  double seconds = 0.0;
};

struct VolumeResult {
  TetMesh mesh;
  std::vector<SolidFailure> failed;
  std::vector<SolidVolumeStats> solids;  ///< the solids filled, in id order
  std::string mesher;                    ///< "netgen nglib"
  bool ok() const { return failed.empty(); }
};

/// Fills the closed solids of `model` (see the file comment). `mesh` must be the surface
/// mesh of `model` (triangle_face naming its faces).
VolumeResult fill_solids(const geom::Model& model, const SurfaceMesh& mesh,
                         const VolumeOptions& opts = {});

}  // namespace uvmesh::surface
