// Shared helpers of uvmesh::geom: kind names, normals, arc length, pole detection.
#include <algorithm>
#include <array>
#include <cmath>

#include "uvmesh/geom/curve.h"
#include "uvmesh/geom/surface.h"

namespace uvmesh::geom {

std::string_view to_string(CurveKind k) {
  switch (k) {
    case CurveKind::Line:
      return "line";
    case CurveKind::Circle:
      return "circle";
    case CurveKind::Ellipse:
      return "ellipse";
    case CurveKind::Hyperbola:
      return "hyperbola";
    case CurveKind::Parabola:
      return "parabola";
    case CurveKind::Bezier:
      return "bezier";
    case CurveKind::BSpline:
      return "bspline";
    case CurveKind::Offset:
      return "offset";
    case CurveKind::Other:
      return "other";
  }
  return "other";
}

std::string_view to_string(SurfaceKind k) {
  switch (k) {
    case SurfaceKind::Plane:
      return "planar";
    case SurfaceKind::Cylinder:
      return "cylinder";
    case SurfaceKind::Cone:
      return "cone";
    case SurfaceKind::Sphere:
      return "sphere";
    case SurfaceKind::Torus:
      return "torus";
    case SurfaceKind::Bezier:
      return "bezier";
    case SurfaceKind::BSpline:
      return "bspline";
    case SurfaceKind::Revolution:
      return "revolution";
    case SurfaceKind::Extrusion:
      return "extrusion";
    case SurfaceKind::Offset:
      return "offset";
    case SurfaceKind::Other:
      return "other";
  }
  return "other";
}

Vec3 SurfacePoint::normal() const {
  const Vec3 n = glm::cross(du, dv);
  const double l = glm::length(n);
  // Singular where |du x dv| vanishes relative to max(|du|, |dv|)^2: one derivative
  // collapsed (a pole: |sigma_u| ~ 1e-16 |sigma_v| at a sphere's pole) or both parallel.
  // 1e-12 ~ the smallest area ratio evaluated derivatives resolve in double precision.
  const double ref = std::max(glm::dot(du, du), glm::dot(dv, dv));
  if (!(l > 1e-12 * ref)) return Vec3(0.0);
  return n / l;
}

double arc_length(const Curve& c, double a, double b, int pieces) {
  // 5-point Gauss-Legendre nodes and weights on [-1, 1].
  static constexpr std::array<double, 5> x{0.0, -0.5384693101056831, 0.5384693101056831,
                                           -0.9061798459386640, 0.9061798459386640};
  static constexpr std::array<double, 5> w{0.5688888888888889, 0.4786286704993665,
                                           0.4786286704993665, 0.2369268850561891,
                                           0.2369268850561891};
  pieces = std::max(pieces, 1);
  const double h = (b - a) / pieces;
  double sum = 0.0;
  for (int i = 0; i < pieces; ++i) {
    const double m = a + (i + 0.5) * h;
    for (int k = 0; k < 5; ++k) sum += w[k] * glm::length(c.eval(m + 0.5 * h * x[k]).d1);
  }
  return std::abs(0.5 * h * sum);
}

unsigned detect_singular_sides(const Surface& s, double rel_tol) {
  const Box2 b = s.bounds();
  constexpr int n = 16;  // samples per side: enough to see a non-collapsed side
  auto image_length = [&](bool along_u, double fixed) {
    double len = 0.0;
    Vec3 prev{};
    for (int i = 0; i <= n; ++i) {
      const double t = double(i) / n;
      const Vec3 p = along_u ? s.point(b.u.at(t), fixed) : s.point(fixed, b.v.at(t));
      if (i > 0) len += glm::length(p - prev);
      prev = p;
    }
    return len;
  };
  const double size = std::max(image_length(true, b.v.mid()), image_length(false, b.u.mid()));
  if (!(size > 0.0)) return 0u;
  const double tol = rel_tol * size;
  unsigned sides = 0u;
  if (image_length(true, b.v.lo) <= tol) sides |= kSideVMin;
  if (image_length(true, b.v.hi) <= tol) sides |= kSideVMax;
  if (image_length(false, b.u.lo) <= tol) sides |= kSideUMin;
  if (image_length(false, b.u.hi) <= tol) sides |= kSideUMax;
  return sides;
}

}  // namespace uvmesh::geom
