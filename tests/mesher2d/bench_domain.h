// bench_mesher2d's isotropic domain, for the tests that pin its numbers: the unit square
// with a hole of radius 0.25 at the centre, every boundary piece shorter than h
// (ceil(1/h) per side of the square, ceil(2 pi r / h) on the circle), so that the boundary
// spacing is not h and the corners' 90-degree angles meet pieces of 1/ceil(1/h).
#pragma once

#include <cmath>

#include "uvmesh/mesher2d/mesher2d.h"

inline uvmesh::m2d::Pslg bench_square_with_hole(double h) {
  using uvmesh::m2d::Vec2;
  const double pi = 3.14159265358979323846;
  uvmesh::m2d::Pslg in;
  const int ns = static_cast<int>(std::ceil(1.0 / h));
  const Vec2 c[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int k = 0; k < 4; ++k)
    for (int i = 0; i < ns; ++i) {
      const double t = static_cast<double>(i) / ns;
      in.points.push_back(
          {c[k].x + t * (c[(k + 1) % 4].x - c[k].x), c[k].y + t * (c[(k + 1) % 4].y - c[k].y)});
    }
  const int n0 = static_cast<int>(in.points.size());
  for (int i = 0; i < n0; ++i) in.segments.push_back({i, (i + 1) % n0, 1});
  const int nc = static_cast<int>(std::ceil(2 * pi * 0.25 / h));
  for (int i = 0; i < nc; ++i)
    in.points.push_back(
        {0.5 + 0.25 * std::cos(2 * pi * i / nc), 0.5 + 0.25 * std::sin(2 * pi * i / nc)});
  for (int i = 0; i < nc; ++i) in.segments.push_back({n0 + i, n0 + (i + 1) % nc, 2});
  in.holes.push_back({0.5, 0.5});
  return in;
}
