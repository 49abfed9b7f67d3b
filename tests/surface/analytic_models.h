// One-face (or two-face) B-Rep models on the analytic back end, built by hand, so that
// the surface stage's components are tested without OpenCASCADE on the cases every
// parametric surface meshing must get right: a plane, a cylinder with a seam, a sphere
// with two poles, a torus (periodic in u and v: two seams), a cone with an apex.
#pragma once

#include <cmath>
#include <numbers>

#include "uvmesh/geom/analytic.h"
#include "uvmesh/geom/model.h"

namespace analytic_models {

using namespace uvmesh;
inline constexpr double kPi = std::numbers::pi;
inline constexpr double kTol = 1e-7;

inline geom::Edge line_edge(const geom::Vec3& a, const geom::Vec3& b, geom::Id v0, geom::Id v1) {
  const double len = glm::length(b - a);
  return {geom::make_line(a, (b - a) / len, {0, len}), {0, len}, v0, v1, false, kTol, len};
}

inline geom::Edge circle_edge(const geom::Frame& f, double r, geom::Id v) {
  return {geom::make_circle(f, r), {0, 2 * kPi}, v, v, false, kTol, 2 * kPi * r};
}

/// A pole or an apex: no 3D curve, its pcurve runs along u at v.
inline geom::Edge degenerate_edge(geom::Id v) {
  return {nullptr, {0, 2 * kPi}, v, v, true, kTol, 0.0};
}

inline geom::EdgeUse use(geom::Id e, bool reversed, geom::Vec2 p, geom::Vec2 d, geom::Interval r,
                         bool seam = false) {
  return {e, reversed, geom::make_line2(p, d, r), r, seam};
}

inline void finish(geom::Model& m, geom::Face f, const geom::Box2& uv, bool closed) {
  f.uv_box = uv;
  f.loops.front().outer = true;
  f.shell = 0;
  m.format = "analytic";
  m.faces = {f};
  m.shells = {{{0}, closed}};
  m.solids.clear();
  if (closed) m.solids = {{{0}, ""}};
  for (double u = 0; u <= 1.0; u += 1.0 / 64)
    for (double v = 0; v <= 1.0; v += 1.0 / 64)
      m.bbox.add(m.faces[0].surface->eval(uv.u.at(u), uv.v.at(v)).p);
}

/// The square [0, a]^2 in the plane z = 0.
inline geom::Model plane_rectangle(double a, double b) {
  geom::Model m;
  const geom::Vec3 p[4] = {{0, 0, 0}, {a, 0, 0}, {a, b, 0}, {0, b, 0}};
  for (const auto& q : p) m.vertices.push_back({q, kTol});
  for (int i = 0; i < 4; ++i) m.edges.push_back(line_edge(p[i], p[(i + 1) % 4], i, (i + 1) % 4));
  geom::Face f;
  f.surface = geom::make_plane(geom::Frame{}, {{0, a}, {0, b}});
  f.kind = geom::SurfaceKind::Plane;
  geom::Loop l;
  l.uses = {use(0, false, {0, 0}, {1, 0}, {0, a}), use(1, false, {a, 0}, {0, 1}, {0, b}),
            use(2, false, {a, b}, {-1, 0}, {0, a}), use(3, false, {0, b}, {0, -1}, {0, b})};
  f.loops = {l};
  finish(m, f, {{0, a}, {0, b}}, false);
  return m;
}

/// The side of the cylinder of radius r and height h: one face, one seam at u = 0.
inline geom::Model cylinder_side(double r, double h) {
  geom::Model m;
  m.vertices = {{{r, 0, 0}, kTol}, {{r, 0, h}, kTol}};
  geom::Frame top;
  top.origin = {0, 0, h};
  m.edges = {circle_edge(geom::Frame{}, r, 0), circle_edge(top, r, 1),
             line_edge({r, 0, 0}, {r, 0, h}, 0, 1)};
  geom::Face f;
  f.surface = geom::make_cylinder(geom::Frame{}, r, {0, h});
  f.kind = geom::SurfaceKind::Cylinder;
  geom::Loop l;
  // The circles are parametrised by angle: their pcurves are u = t.
  l.uses = {use(0, false, {0, 0}, {1, 0}, {0, 2 * kPi}),
            use(2, false, {2 * kPi, 0}, {0, 1}, {0, h}, true),
            use(1, true, {0, h}, {1, 0}, {0, 2 * kPi}), use(2, true, {0, 0}, {0, 1}, {0, h}, true)};
  f.loops = {l};
  finish(m, f, {{0, 2 * kPi}, {0, h}}, false);
  return m;
}

/// The sphere of radius r: one face, poles at v = -pi/2 and pi/2 (degenerate edges), the
/// seam a meridian at u = 0. Closed.
inline geom::Model sphere(double r) {
  geom::Model m;
  m.vertices = {{{0, 0, -r}, kTol}, {{0, 0, r}, kTol}};
  geom::Frame meridian;  // (r cos t, 0, r sin t)
  meridian.x = {1, 0, 0};
  meridian.y = {0, 0, 1};
  meridian.z = {0, -1, 0};
  // As OCC gives a sphere's seam: the circle's parameter in [3pi/2, 5pi/2], v = t - 2pi.
  const double h = kPi / 2;
  const geom::Interval t{3 * h, 5 * h};
  geom::Edge seam{geom::make_circle(meridian, r), t, 0, 1, false, kTol, kPi * r};
  m.edges = {degenerate_edge(0), degenerate_edge(1), seam};
  geom::Face f;
  f.surface = geom::make_sphere(geom::Frame{}, r);
  f.kind = geom::SurfaceKind::Sphere;
  geom::Loop l;
  l.uses = {use(0, false, {0, -h}, {1, 0}, {0, 2 * kPi}),
            use(2, false, {2 * kPi, -4 * h}, {0, 1}, t, true),
            use(1, true, {0, h}, {1, 0}, {0, 2 * kPi}), use(2, true, {0, -4 * h}, {0, 1}, t, true)};
  f.loops = {l};
  finish(m, f, {{0, 2 * kPi}, {-h, h}}, true);
  return m;
}

/// The torus of radii R > r: one face periodic in u and v, two seams (the circles u = 0
/// and v = 0) meeting at one vertex. Closed.
inline geom::Model torus(double R, double r) {
  geom::Model m;
  m.vertices = {{{R + r, 0, 0}, kTol}};
  geom::Frame minor;  // (R + r cos t, 0, r sin t)
  minor.origin = {R, 0, 0};
  minor.x = {1, 0, 0};
  minor.y = {0, 0, 1};
  minor.z = {0, -1, 0};
  m.edges = {circle_edge(geom::Frame{}, R + r, 0), circle_edge(minor, r, 0)};
  geom::Face f;
  f.surface = geom::make_torus(geom::Frame{}, R, r);
  f.kind = geom::SurfaceKind::Torus;
  geom::Loop l;
  const double p = 2 * kPi;
  l.uses = {use(0, false, {0, 0}, {1, 0}, {0, p}, true),
            use(1, false, {p, 0}, {0, 1}, {0, p}, true), use(0, true, {0, p}, {1, 0}, {0, p}, true),
            use(1, true, {0, 0}, {0, 1}, {0, p}, true)};
  f.loops = {l};
  finish(m, f, {{0, p}, {0, p}}, true);
  return m;
}

/// The cone of base radius r at z = 0 and semi-angle a, from its apex (a degenerate edge at
/// v = -r / sin a) to the base circle (v = 0); the seam is the generatrix at u = 0.
inline geom::Model cone(double r, double a) {
  geom::Model m;
  const double va = -r / std::sin(a);
  const geom::Vec3 apex{0, 0, va * std::cos(a)};
  m.vertices = {{apex, kTol}, {{r, 0, 0}, kTol}};
  const geom::Vec3 dir{std::sin(a), 0, std::cos(a)};
  geom::Edge seam{geom::make_line({r, 0, 0}, dir, {va, 0}), {va, 0}, 0, 1, false, kTol, -va};
  m.edges = {degenerate_edge(0), circle_edge(geom::Frame{}, r, 1), seam};
  geom::Face f;
  f.surface = geom::make_cone(geom::Frame{}, r, a, {va, 0});
  f.kind = geom::SurfaceKind::Cone;
  geom::Loop l;
  l.uses = {use(0, false, {0, va}, {1, 0}, {0, 2 * kPi}),
            use(2, false, {2 * kPi, 0}, {0, 1}, {va, 0}, true),
            use(1, true, {0, 0}, {1, 0}, {0, 2 * kPi}),
            use(2, true, {0, 0}, {0, 1}, {va, 0}, true)};
  f.loops = {l};
  finish(m, f, {{0, 2 * kPi}, {va, 0}}, false);
  return m;
}

/// Distance of p from the analytic surface of the model's first face, by its implicit
/// equation (the models above are centred at the origin with axis z).
inline double distance_to_surface(const geom::Model& m, const geom::Vec3& p) {
  const geom::Face& f = m.faces[0];
  const double rho = std::hypot(p.x, p.y);
  switch (f.kind) {
    case geom::SurfaceKind::Plane:
      return std::abs(p.z);
    case geom::SurfaceKind::Cylinder:
      return std::abs(rho - m.vertices[0].p.x);
    case geom::SurfaceKind::Sphere:
      return std::abs(glm::length(p) - m.vertices[1].p.z);
    case geom::SurfaceKind::Torus: {
      const double r = m.edges[1].length / (2 * kPi), R = m.vertices[0].p.x - r;
      return std::abs(std::hypot(rho - R, p.z) - r);
    }
    case geom::SurfaceKind::Cone: {
      // The generatrix through the base point (r, 0, 0) with direction (sin a, 0, cos a).
      const geom::Vec3 d = glm::normalize(m.vertices[1].p - m.vertices[0].p);
      const double r = m.vertices[1].p.x;
      const double s = (rho - r) * d.x + p.z * d.z;
      return std::hypot(rho - (r + s * d.x), p.z - s * d.z);
    }
    default:
      return -1;
  }
}

}  // namespace analytic_models
