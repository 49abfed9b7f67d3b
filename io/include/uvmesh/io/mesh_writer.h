// uvmesh::io mesh writers -- the whole-model surface mesh (surface::SurfaceMesh) to the
// files volume meshers and finite-element codes read.
//
//   io::WriteResult r = io::write_mesh(result.mesh, &model, "part.msh");
//   if (!r.ok) std::cerr << r.error << "\n";   // "part.msh: cannot write here: ..."
//
// The format comes from the extension (format_from_path) unless WriteOptions::format says
// otherwise:
//   .msh   Gmsh 4.1 ASCII with $Entities: one surface entity per CAD face (tag = face id+1),
//          one curve per model edge (edge id+1), one point per model vertex (vertex id+1),
//          one volume per solid (solid id+1); nodes in entity blocks, node tag = index+1;
//          point (type 15), 2-node line (type 1) and triangle (type 2) elements; no physical
//          groups, so that Gmsh keeps every element when it re-saves the file.
//   .mesh  Medit ASCII (MeshVersionFormatted 2: double coordinates), with the references
//          described at write_mesh.
//   .stl   binary STL (ASCII with Encoding::Ascii); normals from the triangle corners.
//   .obj   Wavefront OBJ: v lines, then one `g face_<id>` group of f lines per CAD face.
//   .vtk   legacy VTK UNSTRUCTURED_GRID, VTK_TRIANGLE cells, CELL_DATA int `face_id`;
//          ASCII, or big-endian binary with Encoding::Binary.
//
// Every ASCII number is written with std::to_chars (shortest form that reads back to the
// same double), so .msh, .mesh, .obj and .vtk round-trip coordinates bit for bit.
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

namespace uvmesh::io {

enum class MeshFormat { Msh41, Medit, Stl, Obj, Vtk };

/// The format for a file name's extension (case-insensitive): .msh .mesh .stl .obj .vtk.
/// nullopt for any other extension or none.
std::optional<MeshFormat> format_from_path(const std::string& path);

/// ".msh, .mesh, .stl, .obj, .vtk" -- for help texts and "unknown extension" messages.
std::string known_mesh_extensions();

/// Short name of a format: "msh41", "medit", "stl", "obj", "vtk".
std::string_view format_name(MeshFormat f);

enum class Encoding {
  Default,  ///< binary for STL, ASCII for the others
  Ascii,
  Binary,   ///< STL and VTK only; an error for the others
};

struct WriteOptions {
  std::optional<MeshFormat> format;  ///< overrides the extension when set
  Encoding encoding = Encoding::Default;
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
