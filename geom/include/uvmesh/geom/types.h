// uvmesh::geom basic value types: points, parameter intervals and boxes.
//
//   geom::Box3 box;  box.add({0,0,0});  box.add({1,2,2});  box.diagonal() == 3
//
// Fixed core types: double coordinates (GLM vectors), int32 ids.
#pragma once

#include <cstdint>
#include <glm/geometric.hpp>
#include <glm/vec2.hpp>
#include <glm/vec3.hpp>
#include <limits>

namespace uvmesh::geom {

using Vec2 = glm::dvec2;
using Vec3 = glm::dvec3;

/// Index of a model entity (vertex, edge, face, shell, solid) in file order.
using Id = std::int32_t;
inline constexpr Id kNone = -1;

/// Closed parameter interval [lo, hi].
struct Interval {
  double lo = 0.0;
  double hi = 0.0;
  double length() const { return hi - lo; }
  double mid() const { return 0.5 * (lo + hi); }
  bool contains(double x) const { return x >= lo && x <= hi; }
  double at(double s) const { return lo + s * (hi - lo); }  ///< s in [0,1] -> parameter
};

/// Parameter box of a surface: u x v.
struct Box2 {
  Interval u;
  Interval v;
};

/// Axis-aligned 3D box; empty until the first add().
struct Box3 {
  Vec3 lo{std::numeric_limits<double>::infinity()};
  Vec3 hi{-std::numeric_limits<double>::infinity()};
  bool empty() const { return !(lo.x <= hi.x); }
  void add(const Vec3& p) {
    lo = glm::min(lo, p);
    hi = glm::max(hi, p);
  }
  void add(const Box3& b) {
    if (!b.empty()) {
      add(b.lo);
      add(b.hi);
    }
  }
  double diagonal() const { return empty() ? 0.0 : glm::length(hi - lo); }
};

}  // namespace uvmesh::geom
