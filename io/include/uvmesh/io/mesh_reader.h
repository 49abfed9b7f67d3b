// uvmesh::io mesh readers -- surface meshes written by uvmesh or by other tools, read
// back into a surface::SurfaceMesh so that `uvmesh check` can grade any mesh and the
// tests can round-trip every format.
//
//   io::MeshReadResult r = io::read_mesh("part.msh");
//   if (!r.ok) std::cerr << r.error << "\n";   // "part.msh: line 12: expected a node tag, found
//   'x'"
//
// Formats (by extension, or MeshReadOptions::format):
//   .msh   Gmsh 4.1 ASCII and binary, Gmsh 2.2 ASCII
//   .mesh  Medit ASCII; .meshb Medit binary (libMeshb versions 1 to 4)
//   .stl   ASCII or binary (decided by content: a binary file's size is 84 + 50 n)
//   .obj   Wavefront (v and f statements; polygons are fanned into triangles)
//   .ply   ASCII, binary little- and big-endian
//   .drc   Draco (draco_io.cpp)
//
// Errors name the file and where: "line N" in text, "byte offset N" in binary data, and
// what was expected. A truncated file is an error, never a short mesh.
//
// What the mesh holds:
//   * points, triangles; segments from line elements (.msh lines, Medit Edges);
//   * triangle_face from the file's face ids when it has them (has_face_ids): .msh entity
//     tag - 1, Medit reference - 1, PLY/Draco face_id, OBJ groups "face_<id>" (other
//     groups are numbered in order of appearance), ASCII STL solids in order;
//     else 0 for every triangle;
//   * point_dim / point_entity: from .msh 4.1 node blocks (classified = true); otherwise
//     derived from the elements: a node of a point element (.msh 2.2 type 15) is a
//     model vertex, a node of a segment lies on that segment's edge, any other node on
//     the face of the first triangle using it (classified = false). Either way the mesh
//     can be written again with io::write_mesh.
//   * STL repeats coordinates per facet: corners at bit-identical coordinates are merged
//     into one point (as meshio and Gmsh do). Draco corners are merged the same way.
//   * Elements other than points, lines and triangles (quadrangles, tetrahedra, ...) are
//     skipped and counted in skipped_elements.
#pragma once

#include <array>
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::io {

struct MeshReadOptions {
  std::optional<MeshFormat> format;  ///< overrides the extension (Msh41 reads any .msh)
};

struct MeshReadResult {
  bool ok = false;
  std::string error;  ///< "<path>: <where>: <problem>" when !ok
  surface::SurfaceMesh mesh;
  MeshFormat format = MeshFormat::Msh41;  ///< what was read (Msh22 for a 2.2 file)
  bool binary = false;
  bool classified = false;    ///< point_dim / point_entity come from the file
  bool has_face_ids = false;  ///< triangle_face comes from the file
  /// .msh 4.1: entities declared in $Entities (points, curves, surfaces, volumes).
  std::array<std::size_t, 4> entities{0, 0, 0, 0};
  /// .msh: physical groups as (dim, tag, name), in file order.
  struct Physical {
    int dim = 0, tag = 0;
    std::string name;
  };
  std::vector<Physical> physicals;
  std::size_t skipped_elements = 0;
  std::vector<std::string> warnings;
};

MeshReadResult read_mesh(const std::string& path, const MeshReadOptions& opts = {});

/// The parser of read_mesh on a file's contents already in memory (the fuzzers feed it
/// bytes without a file); `name` stands for the path in messages. A format read_mesh
/// does not read is an error.
MeshReadResult read_mesh_data(const std::string& data, MeshFormat format, const std::string& name);

/// ".msh, .mesh, .meshb, .stl, .obj, .ply, .drc"
std::string readable_mesh_extensions();

}  // namespace uvmesh::io
