// uvmesh::cli2d -- Triangle's regional maximum areas (.poly region lines
// "<id> <x> <y> <attribute> <maximum area>") turned into a size bound for m2d::mesh().
//
// Usage:
//   uvmesh::cli2d::RegionSize rs = uvmesh::cli2d::apply_region_max_area(poly, spec, options);
//   uvmesh::m2d::Result r = uvmesh::m2d::mesh(poly.pslg, rs.spec, options);
//
// The mesher's API takes one size field and knows regions only after coloring, so this
// runs a first, cheap pass: the constrained Delaunay triangulation (Options::refine =
// false), in which each region seed is located to find its connected component. A maximum
// area A becomes the size bound h_A = sqrt(4 A / sqrt 3), the side of the equilateral
// triangle of area A (a unit mesh has triangles of about that area; the bound is thus
// approximate, where Triangle enforces it strictly). Inside a constrained component the
// size is min(h, h_A) (scalar sizes) or the metric intersected with I / h_A^2 (metrics).
// When the size comes "from the boundary" (SizeSpec::uniform(0)), unconstrained
// components get the mean length of the input segments, as a scalar field cannot defer to
// the mesher's own boundary sizes.
#pragma once

#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/poly.h"

namespace uvmesh::cli2d {

struct RegionSize {
  m2d::SizeSpec spec;              // the base spec when no maximum area applies
  int constrained_regions = 0;     // regions whose maximum area was applied
  std::vector<std::string> notes;  // e.g. "region 2 (file:57): seed outside the domain"
};

RegionSize apply_region_max_area(const PolyData& poly, const m2d::SizeSpec& base,
                                 const m2d::Options& opt);

}  // namespace uvmesh::cli2d
