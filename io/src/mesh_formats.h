// Private to uvmesh::io: the format writers of the whole-model surface mesh, each filling
// a Sink (mesh_sink.h); write_mesh (mesh_writer.cpp) validates, picks one and commits the
// file. Gmsh in mesh_writer_gmsh.cpp, the other formats in mesh_writer_formats.cpp.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "mesh_sink.h"
#include "uvmesh/geom/model.h"
#include "uvmesh/surface/surface_mesh.h"
#include "uvmesh/surface/tet_mesh.h"

namespace uvmesh::io::detail {

// Physical groups: a solver addresses boundary conditions and materials through them.
// Volume group per solid (tag = solid id + 1); surface groups per distinct face name
// (tags 1.. in order of first appearance), so that faces a CAD user named alike (e.g.
// "inlet") form one group. Once the file has any physical group, every element must be
// in one: Gmsh re-saves only grouped elements (Mesh.SaveAll off, its default), and meshio
// rejects a file where some element blocks have physical tags and others not. So with
// named faces or a solid, the unnamed faces form "unnamed_faces", and the model edges
// and vertices one group each. (A solid's volume group alone left every triangle
// ungrouped: `gmsh part.msh -0 -o copy.msh` wrote an empty mesh.)
struct Physicals {
  std::vector<std::int64_t> face_group;           ///< per face: its surface group tag, 0 for none
  std::vector<std::string> face_names;            ///< surface group tag - 1 -> name
  std::int64_t curve_group = 0, point_group = 0;  ///< the catch-all tags (0: none)
  bool solids = false;                            ///< one volume group per written volume
  std::vector<std::string> solid_names;           ///< per solid id
};

Physicals physicals(const geom::Model* model, const Counts& c, bool on);

// `vol` (may be null): tetrahedra written with the surface mesh (WriteOptions::volume).
void write_msh41(Sink& out, const surface::SurfaceMesh& m, const geom::Model* model,
                 const Counts& c, const Physicals& phys, bool binary, const surface::TetMesh* vol);
void write_msh22(Sink& out, const surface::SurfaceMesh& m, Physicals phys,
                 const surface::TetMesh* vol);
void write_medit(Sink& out, const surface::SurfaceMesh& m, const surface::TetMesh* vol);
void write_meshb(Sink& out, const surface::SurfaceMesh& m);
void write_tetgen(Sink& out, const surface::SurfaceMesh& m, bool smesh);
void write_ply(Sink& out, const surface::SurfaceMesh& m, bool binary);
void write_stl_binary(Sink& out, const surface::SurfaceMesh& m);
void write_stl_ascii(Sink& out, const surface::SurfaceMesh& m);
void write_obj(Sink& out, const surface::SurfaceMesh& m, const Counts& c);
void write_vtk(Sink& out, const surface::SurfaceMesh& m, bool binary);
void write_vtu(Sink& out, const surface::SurfaceMesh& m, bool binary, const surface::TetMesh* vol);

}  // namespace uvmesh::io::detail
