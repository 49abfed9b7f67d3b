// Checker for the output of uvmesh::m2d::mesh (and for any 2D triangle mesh): returns a
// report, never prints. Tests and debug builds call it.
//
// Usage:
//   auto r = uvmesh::m2d::mesh(pslg, size);
//   uvmesh::m2d::CheckReport rep = uvmesh::m2d::check(r.mesh, pslg, {.delaunay = true});
//   if (!rep.ok()) { for (auto& e : rep.errors) ...; }
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::m2d {

struct CheckOptions {
  // Every non-constrained interior edge must be locally (constrained-)Delaunay: exact
  // incircle of the opposite vertex <= 0. Holds before refinement and after refinement
  // with the isotropic kernel when no optimization ran.
  bool delaunay = false;
  // Every input segment must be covered by a chain of boundary edges of the mesh.
  bool segments_present = true;
  // No triangle may contain a hole seed; every region seed must lie in a triangle.
  bool seeds = true;
  std::size_t max_errors = 20;  // stop collecting after this many
};

struct CheckReport {
  std::vector<std::string> errors;  // each names the entities: "triangle 12 (4,9,17) is not CCW"
  std::int64_t triangles_checked = 0;
  std::int64_t edges_checked = 0;
  bool ok() const { return errors.empty(); }
};

// Checks: vertex indices in range; every triangle strictly counter-clockwise (exact
// orient2d); every edge shared by at most two triangles with opposite orientations
// (neighbour symmetry); boundary edges of the triangle set are exactly constrained
// edges; segments present; seeds respected; Delaunay when asked.
CheckReport check(const Mesh& m, const Pslg& in, const CheckOptions& opt = {});

}  // namespace uvmesh::m2d
