// Analytic back end: exact closed-form surfaces and curves, independent of OCC. Used by
// tests that must not need OCC, and as the reference the other back ends are checked
// against. Parametrisations follow OCC's (gp_Cylinder, gp_Cone, gp_Sphere, gp_Torus), so
// a test can compare both back ends point by point.
//
//   geom::Frame f;                        // origin 0, axes x, y, z
//   auto cyl = geom::make_cylinder(f, 2.0, {0.0, 5.0});
//   auto e = cyl->eval(M_PI / 2, 1.0);    // (0, 2, 1)
#pragma once

#include <memory>
#include <vector>

#include "uvmesh/geom/curve.h"
#include "uvmesh/geom/surface.h"

namespace uvmesh::geom {

/// Right-handed orthonormal frame (x, y, z = x cross y).
struct Frame {
  Vec3 origin{0.0, 0.0, 0.0};
  Vec3 x{1.0, 0.0, 0.0};
  Vec3 y{0.0, 1.0, 0.0};
  Vec3 z{0.0, 0.0, 1.0};
  /// Frame with the given origin and z axis; x is any unit vector normal to z.
  static Frame from_axis(const Vec3& origin, const Vec3& z);
};

/// sigma(u,v) = O + u X + v Y on the box `box`.
std::shared_ptr<Surface> make_plane(const Frame& f, const Box2& box);
/// sigma(u,v) = O + r (cos u X + sin u Y) + v Z, u in [0, 2pi) periodic.
std::shared_ptr<Surface> make_cylinder(const Frame& f, double r, const Interval& v);
/// sigma(u,v) = O + (r + v sin a)(cos u X + sin u Y) + v cos a Z, u periodic; the apex is
/// at v = -r / sin a (a pole when v.lo equals it).
std::shared_ptr<Surface> make_cone(const Frame& f, double r, double semi_angle, const Interval& v);
/// sigma(u,v) = O + r cos v (cos u X + sin u Y) + r sin v Z, u in [0,2pi) periodic,
/// v in [-pi/2, pi/2] with poles on both v sides.
std::shared_ptr<Surface> make_sphere(const Frame& f, double r);
/// sigma(u,v) = O + (R + r cos v)(cos u X + sin u Y) + r sin v Z, doubly periodic.
std::shared_ptr<Surface> make_torus(const Frame& f, double major_r, double minor_r);
/// Tensor-product B-spline patch of degree (p, q) with clamped uniform knots on [0,1]^2.
/// `ctrl` is row-major: ctrl[i * nv + j] is control point (i, j), i along u.
std::shared_ptr<Surface> make_bspline_patch(const std::vector<Vec3>& ctrl, int nu, int nv,
                                            int p = 3, int q = 3);

/// C(t) = P + t D on [range].
std::shared_ptr<Curve> make_line(const Vec3& p, const Vec3& d, const Interval& range);
/// C(t) = O + r (cos t X + sin t Y), t in [0, 2pi) periodic.
std::shared_ptr<Curve> make_circle(const Frame& f, double r);
/// 2D segment c(t) = P + t D on [range] (the pcurve of most edges on analytic faces).
std::shared_ptr<Curve2> make_line2(const Vec2& p, const Vec2& d, const Interval& range);

}  // namespace uvmesh::geom
