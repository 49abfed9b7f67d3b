// uvmesh::cli2d -- Medit ASCII meshes (.mesh) and solutions (.sol) in 2D, as used by
// MMG2D, BAMG and FreeFem++ for background meshes and metric fields.
//
// Usage (background metric):
//   uvmesh::cli2d::MeditRead m = uvmesh::cli2d::read_medit_mesh("bg.mesh");
//   uvmesh::cli2d::SolRead s = uvmesh::cli2d::read_medit_sol("bg.sol", m.mesh.vertices.size());
//   if (!m.ok() || !s.ok()) ...;
// Usage (output):
//   uvmesh::cli2d::write_medit(out, result.mesh, triangle_refs(result.mesh, has_regions));
//
// Format: keyword-based, white-space separated, '#' comments. Keywords read:
// MeshVersionFormatted, Dimension (2, or 3 with z ignored), Vertices (x y [z] ref),
// Triangles (a b c ref, 1-based), Edges (a b ref), End; Corners, RequiredVertices, Ridges,
// RequiredEdges, Quadrilaterals are skipped. .sol: SolAtVertices, count, then
// "<#fields> <type>...", type 1 = scalar (a size h, M = I/h^2), 3 = symmetric tensor
// stored m11 m12 m22; the first field is used, further fields are skipped.
#pragma once

#include <array>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/diagnostic.h"

namespace uvmesh::cli2d {

struct MeditMesh2 {
  int version = 2;
  int dimension = 2;  // as written in the file; vertices keep x and y only
  std::vector<m2d::Vec2> vertices;
  std::vector<int> vertex_refs;
  std::vector<std::array<m2d::VertId, 3>> triangles;  // 0-based
  std::vector<int> triangle_refs;
  std::vector<std::array<m2d::VertId, 2>> edges;  // 0-based
  std::vector<int> edge_refs;
  std::vector<int> triangle_lines;  // line of each triangle record, for later messages
};

struct MeditRead {
  MeditMesh2 mesh;
  std::optional<Diagnostic> error;
  bool ok() const { return !error.has_value(); }
};

struct MeditSol {
  enum class Type { Scalar = 1, Vector = 2, Tensor = 3 };
  Type type = Type::Scalar;  // of the field kept (the first one)
  int dimension = 2;
  std::vector<double> values;  // 1 (scalar) or 3 (m11 m12 m22) values per vertex
  std::vector<int> lines;      // line of each vertex's values
};

struct SolRead {
  MeditSol sol;
  std::optional<Diagnostic> error;
  bool ok() const { return !error.has_value(); }
};

MeditRead read_medit_mesh(const std::string& path);
MeditRead parse_medit_mesh(std::istream& in, const std::string& name);

// expected_vertices: the vertex count of the mesh the solution belongs to (checked), or
// -1 not to check. Every scalar must be a finite size > 0 and every tensor finite and
// positive definite (m11 > 0, m11 m22 - m12^2 > 0): the message names the line.
SolRead read_medit_sol(const std::string& path, std::int64_t expected_vertices = -1);
SolRead parse_medit_sol(std::istream& in, const std::string& name,
                        std::int64_t expected_vertices = -1);

// Medit reference of every triangle: the regional attribute when the input had region
// seeds and every attribute is an integer, otherwise the connected component index + 1.
// When attributes had to be dropped, *warning (if given) says why.
std::vector<int> triangle_refs(const m2d::Mesh& m, bool has_regions,
                               std::string* warning = nullptr);

// MeshVersionFormatted 2, Dimension 2, Vertices (ref = vertex marker), Triangles (ref =
// tri_refs[i]), Edges (the boundary edges, ref = marker), End. Indices 1-based.
void write_medit(std::ostream& out, const m2d::Mesh& m, const std::vector<int>& tri_refs);

}  // namespace uvmesh::cli2d
