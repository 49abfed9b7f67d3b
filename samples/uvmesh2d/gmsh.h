// uvmesh::cli2d -- Gmsh MSH 2.2 ASCII writer for 2D meshes.
//
// Usage:
//   uvmesh::cli2d::write_gmsh22(out, result.mesh, uvmesh::cli2d::triangle_refs(result.mesh,
//   has_regions));
//
// Nodes are written with z = 0. Elements: first one 2-node line (type 1) per boundary edge,
// physical tag = the edge's marker; then one 3-node triangle (type 2) per triangle,
// physical tag = tri_refs[i] (the same references as the Medit writer). Elementary tags:
// lines use the marker (1 when the marker is not positive), triangles the connected
// component index + 1, so that Gmsh sees one discrete surface per component.
#pragma once

#include <ostream>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::cli2d {

void write_gmsh22(std::ostream& out, const m2d::Mesh& m, const std::vector<int>& tri_refs);

}  // namespace uvmesh::cli2d
