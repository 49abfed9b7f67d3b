// uvmesh::cli2d -- SVG picture of a 2D mesh: triangles filled by their quality Q_K
// (eq. 7.6 of the reference chapter; 1 = equilateral, in the metric when there is one),
// boundary edges drawn thick, y axis pointing up, viewBox fitted to the mesh.
//
// Usage:
//   uvmesh::cli2d::SvgOptions o;
//   o.quality = q;               // one Q_K per triangle (the caller picks the metric)
//   uvmesh::cli2d::write_svg(out, result.mesh, o);
//
// Size: triangles of one colour class go into one <path> ("Mx y x y x yZ" per triangle)
// and coordinates are rounded to 0.1 or 0.01 picture units (the picture is 1000 units
// wide), so a 1e5-triangle mesh is a few MB. Above max_wireframe_triangles the edges are
// not stroked; above max_filled_triangles only the boundary is drawn.
#pragma once

#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::cli2d {

struct SvgOptions {
  std::vector<double> quality;  // Q_K per triangle; empty: uniform grey fill, no legend
  std::string title;            // caption under the picture (escaped)
  double size = 1000;           // length of the longer side of the picture, in SVG units
  std::size_t max_wireframe_triangles = 200'000;
  std::size_t max_filled_triangles = 2'000'000;
};

// Colour classes of Q_K: class k holds Q in [bounds[k-1], bounds[k]).
inline constexpr double kSvgQualityBounds[] = {1.15, 1.3, 1.5, 2.0, 3.0, 5.0};

void write_svg(std::ostream& out, const m2d::Mesh& m, const SvgOptions& opt = {});

}  // namespace uvmesh::cli2d
