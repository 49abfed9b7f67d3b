// Domains with features narrower than the requested size, for Options::feature_size (the
// local feature size of the PSLG): the tests and bench_mesher2d's lfs rows mesh them.
//   thin_star(10, 1, 0.3)   10 spikes of radius 1 from a core of radius 0.3; a spike is
//                           0.19 wide at its base and 14.8 degrees at its tip
//   slotted_square(w)       the unit square with three slots of width w cut in from the
//                           bottom side, 0.6 deep
//   comb(n, w)              a 1 x 0.3 back with n teeth 0.6 long and w wide
#pragma once

#include <cmath>

#include "uvmesh/mesher2d/mesher2d.h"

namespace feature_domains {

using uvmesh::m2d::Pslg;
using uvmesh::m2d::Vec2;
using uvmesh::m2d::VertId;

// The polygon through pts (counter-clockwise), as one loop of segments with marker 1.
inline Pslg polygon(const std::vector<Vec2>& pts) {
  Pslg in;
  in.points = pts;
  const auto n = static_cast<VertId>(pts.size());
  for (VertId i = 0; i < n; ++i) in.segments.push_back({i, (i + 1) % n, 1});
  return in;
}

inline Pslg thin_star(int spikes, double r_out, double r_in) {
  const double pi = 3.14159265358979323846;
  std::vector<Vec2> p;
  for (int i = 0; i < 2 * spikes; ++i) {
    const double a = pi * i / spikes, r = i % 2 == 0 ? r_out : r_in;
    p.push_back({r * std::cos(a), r * std::sin(a)});
  }
  return polygon(p);
}

inline Pslg slotted_square(double w) {
  std::vector<Vec2> p{{0, 0}};
  for (double x : {0.25, 0.5, 0.75}) {
    p.push_back({x - w / 2, 0});
    p.push_back({x - w / 2, 0.6});
    p.push_back({x + w / 2, 0.6});
    p.push_back({x + w / 2, 0});
  }
  p.insert(p.end(), {{1, 0}, {1, 1}, {0, 1}});
  return polygon(p);
}

inline Pslg comb(int teeth, double w) {
  // Teeth spread evenly along the bottom of the back, hanging down from y = 0.
  std::vector<Vec2> p;
  const double gap = (1 - teeth * w) / (teeth - 1);
  for (int i = 0; i < teeth; ++i) {
    const double x = i * (w + gap);
    p.push_back({x, -0.6});
    p.push_back({x + w, -0.6});
    if (i + 1 < teeth) p.push_back({x + w, 0}), p.push_back({x + w + gap, 0});
  }
  p.insert(p.end(), {{1, 0.3}, {0, 0.3}});
  return polygon(p);
}

}  // namespace feature_domains
