// uvmesh::geom curves: 3D curves of model edges and 2D parameter curves (pcurves) of
// edge uses on a face. Every back end (OCC, analytic) gives the point and the first two
// derivatives at a parameter t.
//
//   auto c = geom::make_circle(geom::Frame{}, 2.0);
//   geom::CurvePoint3 e = c->eval(0.5);   // e.p, e.d1 = dC/dt, e.d2 = d2C/dt2
//
// Thread safety: eval() is const but a back end may keep a mutable evaluation cache
// (OCC B-splines do); use one Curve object from one thread at a time.
#pragma once

#include <memory>
#include <string_view>

#include "uvmesh/geom/types.h"

namespace uvmesh::geom {

/// Curve types; names follow OCC's GeomAbs_CurveType.
enum class CurveKind { Line, Circle, Ellipse, Hyperbola, Parabola, Bezier, BSpline, Offset, Other };
std::string_view to_string(CurveKind k);

struct CurvePoint3 {
  Vec3 p;   ///< C(t)
  Vec3 d1;  ///< C'(t)
  Vec3 d2;  ///< C''(t)
};

struct CurvePoint2 {
  Vec2 p;
  Vec2 d1;
  Vec2 d2;
};

/// A 3D curve C: [range.lo, range.hi] -> R^3.
class Curve {
 public:
  virtual ~Curve() = default;
  virtual CurvePoint3 eval(double t) const = 0;
  virtual Interval range() const = 0;
  virtual CurveKind kind() const = 0;
  virtual bool periodic() const { return false; }
  virtual double period() const { return 0.0; }
  Vec3 point(double t) const { return eval(t).p; }
};

/// A 2D curve in a surface's (u,v) plane.
class Curve2 {
 public:
  virtual ~Curve2() = default;
  virtual CurvePoint2 eval(double t) const = 0;
  virtual Interval range() const = 0;
  virtual CurveKind kind() const = 0;
  Vec2 point(double t) const { return eval(t).p; }
};

/// Arc length of c over [a,b] by composite 5-point Gauss-Legendre quadrature on
/// `pieces` equal sub-intervals (exact for lines, 1e-10 relative on circles for
/// pieces >= 8).
double arc_length(const Curve& c, double a, double b, int pieces = 16);

}  // namespace uvmesh::geom
