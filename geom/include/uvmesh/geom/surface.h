// uvmesh::geom surfaces: the map sigma(u,v) of a face with its first and second
// derivatives, its parameter box, periodicity and singular (pole) sides.
//
//   auto s = geom::make_sphere(geom::Frame{}, 1.0);
//   geom::SurfacePoint e = s->eval(0.3, 0.2);  // e.p, e.du, e.dv, e.duu, e.duv, e.dvv
//   bool pole = s->singular_sides() & geom::kSideVMin;       // true: south pole
//
// Contract (docs/ARCHITECTURE.md "Contracts between stages"): every back end satisfies the same
// tests (derivatives against finite differences, exact curvature on analytic kinds).
// Thread safety: as for Curve, one object per thread (OCC keeps evaluation caches).
#pragma once

#include <memory>
#include <string_view>

#include "uvmesh/geom/types.h"

namespace uvmesh::geom {

/// Surface types; the names printed by to_string() are the corpus MANIFEST's `kinds`
/// vocabulary (planar, cylinder, cone, sphere, torus, bspline, bezier, revolution,
/// extrusion, offset, other).
enum class SurfaceKind {
  Plane,
  Cylinder,
  Cone,
  Sphere,
  Torus,
  Bezier,
  BSpline,
  Revolution,
  Extrusion,
  Offset,
  Other
};
std::string_view to_string(SurfaceKind k);

struct SurfacePoint {
  Vec3 p;    ///< sigma(u,v)
  Vec3 du;   ///< d sigma / du
  Vec3 dv;   ///< d sigma / dv
  Vec3 duu;  ///< d2 sigma / du2
  Vec3 duv;  ///< d2 sigma / du dv
  Vec3 dvv;  ///< d2 sigma / dv2
  /// Unit normal du x dv / |du x dv|; zero vector where the map is singular
  /// (|du x dv| <= 1e-12 max(|du|, |dv|)^2: a pole, or parallel derivatives).
  Vec3 normal() const;
};

/// Sides of the parameter box, as bit flags for Surface::singular_sides().
enum SideBits : unsigned { kSideUMin = 1u, kSideUMax = 2u, kSideVMin = 4u, kSideVMax = 8u };

class Surface {
 public:
  virtual ~Surface() = default;
  virtual SurfacePoint eval(double u, double v) const = 0;
  /// Parameter box. For a trimmed CAD face this is the box of the face's loops.
  virtual Box2 bounds() const = 0;
  virtual SurfaceKind kind() const = 0;
  virtual bool u_periodic() const { return false; }
  virtual bool v_periodic() const { return false; }
  virtual double u_period() const { return 0.0; }
  virtual double v_period() const { return 0.0; }
  /// Sides of bounds() along which sigma collapses to a point (a pole: sigma_u = 0 on
  /// a v-side, or sigma_v = 0 on a u-side). Bit set of SideBits.
  virtual unsigned singular_sides() const { return 0u; }
  /// sigma(u,v) alone; back ends whose derivatives cost extra work override it.
  virtual Vec3 point(double u, double v) const { return eval(u, v).p; }
  /// sigma (equal to eval()'s) and its first derivatives (equal to eval()'s, or within
  /// 1e-4 of their length where a back end differences them more cheaply); the second
  /// derivatives may be left zero. The induced metric and the 3D smoothing need no
  /// more, and back ends whose derivatives cost extra work override it.
  virtual SurfacePoint eval_first(double u, double v) const { return eval(u, v); }
};

/// Finds the singular sides of s.bounds() by sampling: a side is singular when the
/// image of the whole side is shorter than rel_tol times the size of the image of the
/// box (measured along its two mid-lines). Back ends that know their poles
/// analytically do not need this; the OCC back end uses it for B-splines and
/// surfaces of revolution.
unsigned detect_singular_sides(const Surface& s, double rel_tol = 1e-9);

}  // namespace uvmesh::geom
