// uvmesh::cli2d -- point location in a 2D triangle mesh with a uniform bucket grid.
//
// Usage:
//   uvmesh::cli2d::TriangleLocator loc;
//   if (!loc.build(mesh.vertices, mesh.triangles)) ...;   // no triangle with an area
//   auto l = loc.locate({x, y});   // l.triangle, l.w (barycentric), l.inside
//
// The grid has about one triangle per cell, cells shaped like the bounding box, and each
// cell lists the triangles whose bounding box overlaps it, so a query costs O(1) on
// reasonable meshes. Points outside the mesh (or in its holes) get the nearest triangle
// and the barycentric coordinates of the nearest point on it, found by searching rings of
// cells outward. Queries are const and keep no state: safe to call from several threads.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::cli2d {

class TriangleLocator {
 public:
  struct Location {
    std::int32_t triangle = -1;  // index into the triangles given to build()
    std::array<double, 3> w{};   // barycentric weights (of the nearest point if outside)
    bool inside = false;         // the query point is in (or on) that triangle
  };

  // Triangles with zero area are kept out of the grid (they cover nothing and have no
  // barycentric coordinates). Returns false when no triangle is left.
  bool build(const std::vector<m2d::Vec2>& vertices,
             const std::vector<std::array<m2d::VertId, 3>>& triangles);
  Location locate(m2d::Vec2 p) const;
  std::size_t triangles_used() const { return tris_.size(); }

 private:
  std::vector<m2d::Vec2> verts_;
  std::vector<std::array<m2d::VertId, 3>> tris_;  // non-degenerate triangles only
  std::vector<std::int32_t> tri_index_;           // -> index given to build()
  double x0_ = 0, y0_ = 0, cw_ = 1, ch_ = 1;
  int nx_ = 1, ny_ = 1;
  std::vector<std::int32_t> cell_start_, cell_tris_;

  bool barycentric(std::int32_t t, m2d::Vec2 p, std::array<double, 3>& w) const;
  double nearest_on(std::int32_t t, m2d::Vec2 p, std::array<double, 3>& w) const;
};

}  // namespace uvmesh::cli2d
