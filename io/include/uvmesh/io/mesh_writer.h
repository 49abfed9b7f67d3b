// uvmesh::io mesh writers -- the whole-model surface mesh (surface::SurfaceMesh) to the
// files volume meshers and finite-element codes read.
//
//   io::WriteResult r = io::write_mesh(result.mesh, &model, "part.msh");
//   if (!r.ok) std::cerr << r.error << "\n";   // "part.msh: cannot write here: ..."
//
// The format comes from the extension (format_from_path) unless WriteOptions::format says
// otherwise:
//   .msh   Gmsh 4.1 (ASCII, or binary with Encoding::Binary) with $Entities: one surface
//          entity per CAD face (tag = face id+1), one curve per model edge (edge id+1), one
//          point per model vertex (vertex id+1), one volume per solid (solid id+1); nodes in
//          entity blocks, node tag = index+1; point (type 15), 2-node line (type 1) and
//          triangle (type 2) elements. Physical groups (WriteOptions::physical_groups, with
//          a model): one volume group per solid (named after the solid, else "solid_<id+1>")
//          and one surface group per distinct face name; when faces are named, the others
//          form "unnamed_faces" and the model edges and vertices "model_edges" and
//          "model_vertices" (Gmsh re-saves only grouped elements, meshio rejects a file
//          where only some elements are grouped). Without face names Gmsh re-saves the
//          file's elements only when told -save_all.
//   msh22  Gmsh 2.2 ASCII (format "msh22"): elementary tag = entity tag as above, physical
//          tag = the groups above but the solids' (0 when none).
//   .mesh  Medit ASCII (MeshVersionFormatted 2: double coordinates), with the references
//          described at write_mesh. .meshb: the same, binary (libMeshb version 3: double
//          reals, 32-bit integers, 64-bit keyword positions).
//   .stl   binary STL (ASCII with Encoding::Ascii); normals from the triangle corners.
//   .obj   Wavefront OBJ: v lines, then one `g face_<id>` group of f lines per CAD face.
//   .ply   PLY binary little-endian: double x y z; faces with int vertex_indices (ASCII with
//          Encoding::Ascii, whose faces also carry an int face_id property).
//   .vtk   legacy VTK UNSTRUCTURED_GRID, VTK_TRIANGLE cells, CELL_DATA int `face_id`;
//          ASCII, or big-endian binary with Encoding::Binary.
//   .vtu   VTK XML UnstructuredGrid, inline base64 binary arrays (ASCII arrays with
//          Encoding::Ascii), Int32 cell data `face_id`.
//   .poly  TetGen piecewise linear complex: the nodes, one single-triangle facet per
//   .smesh triangle with boundary marker = face id+1, no holes, no regions.
//   .drc   Draco mesh: positions, per-vertex normals, per-vertex generic attribute face_id
//          (vertices on face boundaries are split, one copy per face); quantization bits
//          and compression level from WriteOptions (draco_io.cpp).
//   .glb   glTF 2.0 binary, geometry compressed with KHR_draco_mesh_compression by Draco's
//          own glTF encoder; one mesh per solid (or per face with GlbGroups::Face).
//
// Every ASCII number is written with std::to_chars (shortest form that reads back to the
// same double), so .msh, .mesh, .obj, .ply and .vtk/.vtu round-trip coordinates bit for bit.
//
// Writes are atomic: the file is written beside the target under a temporary name and
// renamed over it only when every byte has been written and the file is closed. A failed
// write returns ok = false, removes the temporary file and leaves any previous file at
// the path untouched. Library code: nothing is printed, diagnostics are returned.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "uvmesh/geom/model.h"
#include "uvmesh/surface/surface_mesh.h"
#include "uvmesh/surface/tet_mesh.h"

namespace uvmesh::io {

enum class MeshFormat {
  Msh41,
  Msh22,
  Medit,
  Meshb,
  Stl,
  Obj,
  Ply,
  Vtk,
  Vtu,
  Poly,
  Smesh,
  Drc,
  Glb
};

/// The format for a file name's extension (case-insensitive): .msh .mesh .meshb .stl .obj
/// .ply .vtk .vtu .poly .smesh .drc .glb. nullopt for any other extension or none.
std::optional<MeshFormat> format_from_path(const std::string& path);

/// True for the formats that carry tetrahedra (WriteOptions::volume): .msh 4.1 and 2.2,
/// Medit .mesh, .vtu.
bool carries_tetrahedra(MeshFormat f);

/// The format of a short name (format_name), e.g. "msh22"; nullopt when unknown.
std::optional<MeshFormat> format_from_name(std::string_view name);

/// ".msh, .mesh, ..." -- for help texts and "unknown extension" messages.
std::string known_mesh_extensions();

/// "msh41, msh22, ..." -- every short name, for help texts.
std::string known_format_names();

/// Short name of a format: "msh41", "msh22", "medit", "meshb", "stl", "obj", "ply", "vtk",
/// "vtu", "poly", "smesh", "drc", "glb".
std::string_view format_name(MeshFormat f);

enum class Encoding {
  Default,  ///< binary for STL, PLY, VTU, .meshb, .drc and .glb; ASCII for the others
  Ascii,    ///< an error for .meshb, .drc and .glb
  Binary,   ///< .msh 4.1, STL, PLY, VTK, VTU (and the binary-only formats)
};

/// What one glTF mesh holds.
enum class GlbGroups { Solid, Face };

struct WriteOptions {
  std::optional<MeshFormat> format;  ///< overrides the extension when set
  Encoding encoding = Encoding::Default;
  /// .msh: physical groups per solid and per face name (needs a model; Gmsh then keeps only
  /// grouped elements when it re-saves, see above).
  bool physical_groups = true;
  /// Draco (.drc, .glb): position quantization bits (1..30) and compression level 0..10
  /// (Draco's speed is 10 - level: 10 compresses most). Normals use normal_bits.
  int draco_bits = 14;
  int draco_level = 7;
  int draco_normal_bits = 10;
  GlbGroups glb_groups = GlbGroups::Solid;
  /// Tetrahedra to write with the surface mesh (surface::fill_solids; its points start
  /// with the surface mesh's, unchanged). Only .msh (4.1 and 2.2), .mesh and .vtu carry
  /// them; any other format is then an error. Null: the surface mesh alone, byte for byte
  /// what it is without this option.
  ///   .msh 4.1: interior nodes in one block per volume entity (dim 3, tag solid id+1),
  ///             4-node tetrahedra (type 4) in one block per volume; the solid's physical
  ///             volume group as for the surface mesh.
  ///   .msh 2.2: tetrahedra with physical = elementary = solid id+1 (the volume groups are
  ///             then named in $PhysicalNames).
  ///   .mesh:    Tetrahedra with reference solid id+1; interior vertices carry solid id+1.
  ///   .vtu:     VTK_TETRA cells (type 10) after the triangles; cell data face_id (-1 on
  ///             tetrahedra) and solid_id (-1 on triangles).
  const surface::TetMesh* volume = nullptr;
};

struct WriteResult {
  bool ok = false;
  std::string error;  ///< "<path>: <reason>" when !ok
};

/// Writes `m` to `path`. `model` may be null: the .msh entities are then derived from the
/// mesh's classification alone (no bounding curves of surfaces, no volumes); with a model,
/// surfaces list their bounding curves with the orientation of their loops and solids
/// become volumes. Only entities that carry mesh nodes or elements are written, so every
/// entity tag a file mentions is defined in it.
///
/// Medit references: triangles carry face id + 1, edges carry edge id + 1, vertices carry
/// the id + 1 of the entity they are classified on (model vertex, edge or face, as Gmsh's
/// own Medit export writes its nodes' entity tags) -- read them together with the
/// dimension, which Medit has no field for.
///
/// The mesh is validated first (array sizes agree, node indices in range, classification
/// dimensions 0..2 and non-negative entity ids): a malformed mesh is an error, not a
/// malformed file.
WriteResult write_mesh(const surface::SurfaceMesh& m, const geom::Model* model,
                       const std::string& path, const WriteOptions& opts = {});

}  // namespace uvmesh::io
