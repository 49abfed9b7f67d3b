// Analytic surfaces and curves (closed-form derivatives). Parametrisations as in OCC's gp
// elementary surfaces so both back ends can be compared point by point.
#include "uvmesh/geom/analytic.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace uvmesh::geom {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

class Plane final : public Surface {
 public:
  Plane(const Frame& f, const Box2& b) : f_(f), b_(b) {}
  SurfacePoint eval(double u, double v) const override {
    return {f_.origin + u * f_.x + v * f_.y, f_.x, f_.y, Vec3(0.0), Vec3(0.0), Vec3(0.0)};
  }
  Box2 bounds() const override { return b_; }
  SurfaceKind kind() const override { return SurfaceKind::Plane; }

 private:
  Frame f_;
  Box2 b_;
};

class Cylinder final : public Surface {
 public:
  Cylinder(const Frame& f, double r, const Interval& v) : f_(f), r_(r), v_(v) {}
  SurfacePoint eval(double u, double v) const override {
    const Vec3 c = std::cos(u) * f_.x + std::sin(u) * f_.y;    // radial
    const Vec3 dc = -std::sin(u) * f_.x + std::cos(u) * f_.y;  // d radial / du
    return {f_.origin + r_ * c + v * f_.z, r_ * dc, f_.z, -r_ * c, Vec3(0.0), Vec3(0.0)};
  }
  Box2 bounds() const override { return {{0.0, kTwoPi}, v_}; }
  SurfaceKind kind() const override { return SurfaceKind::Cylinder; }
  bool u_periodic() const override { return true; }
  double u_period() const override { return kTwoPi; }

 private:
  Frame f_;
  double r_;
  Interval v_;
};

class Cone final : public Surface {
 public:
  Cone(const Frame& f, double r, double a, const Interval& v) : f_(f), r_(r), a_(a), v_(v) {}
  SurfacePoint eval(double u, double v) const override {
    const Vec3 c = std::cos(u) * f_.x + std::sin(u) * f_.y;
    const Vec3 dc = -std::sin(u) * f_.x + std::cos(u) * f_.y;
    const double s = std::sin(a_), k = std::cos(a_);
    const double rad = r_ + v * s;
    return {f_.origin + rad * c + v * k * f_.z,
            rad * dc,
            s * c + k * f_.z,
            -rad * c,
            s * dc,
            Vec3(0.0)};
  }
  Box2 bounds() const override { return {{0.0, kTwoPi}, v_}; }
  SurfaceKind kind() const override { return SurfaceKind::Cone; }
  bool u_periodic() const override { return true; }
  double u_period() const override { return kTwoPi; }
  unsigned singular_sides() const override {
    // The apex (radius 0) is a pole when it is on a v side of the box.
    const double apex = -r_ / std::sin(a_);
    const double tol = 1e-12 * (std::abs(v_.lo) + std::abs(v_.hi) + std::abs(r_));
    unsigned s = 0u;
    if (std::abs(v_.lo - apex) <= tol) s |= kSideVMin;
    if (std::abs(v_.hi - apex) <= tol) s |= kSideVMax;
    return s;
  }

 private:
  Frame f_;
  double r_, a_;
  Interval v_;
};

class Sphere final : public Surface {
 public:
  Sphere(const Frame& f, double r) : f_(f), r_(r) {}
  SurfacePoint eval(double u, double v) const override {
    const Vec3 c = std::cos(u) * f_.x + std::sin(u) * f_.y;
    const Vec3 dc = -std::sin(u) * f_.x + std::cos(u) * f_.y;
    const double cv = std::cos(v), sv = std::sin(v);
    SurfacePoint e;
    e.p = f_.origin + r_ * cv * c + r_ * sv * f_.z;
    e.du = r_ * cv * dc;
    e.dv = -r_ * sv * c + r_ * cv * f_.z;
    e.duu = -r_ * cv * c;
    e.duv = -r_ * sv * dc;
    e.dvv = -r_ * cv * c - r_ * sv * f_.z;
    return e;
  }
  Box2 bounds() const override {
    return {{0.0, kTwoPi}, {-0.5 * std::numbers::pi, 0.5 * std::numbers::pi}};
  }
  SurfaceKind kind() const override { return SurfaceKind::Sphere; }
  bool u_periodic() const override { return true; }
  double u_period() const override { return kTwoPi; }
  unsigned singular_sides() const override { return kSideVMin | kSideVMax; }

 private:
  Frame f_;
  double r_;
};

class Torus final : public Surface {
 public:
  Torus(const Frame& f, double R, double r) : f_(f), R_(R), r_(r) {}
  SurfacePoint eval(double u, double v) const override {
    const Vec3 c = std::cos(u) * f_.x + std::sin(u) * f_.y;
    const Vec3 dc = -std::sin(u) * f_.x + std::cos(u) * f_.y;
    const double cv = std::cos(v), sv = std::sin(v);
    const double rad = R_ + r_ * cv;
    SurfacePoint e;
    e.p = f_.origin + rad * c + r_ * sv * f_.z;
    e.du = rad * dc;
    e.dv = -r_ * sv * c + r_ * cv * f_.z;
    e.duu = -rad * c;
    e.duv = -r_ * sv * dc;
    e.dvv = -r_ * cv * c - r_ * sv * f_.z;
    return e;
  }
  Box2 bounds() const override { return {{0.0, kTwoPi}, {0.0, kTwoPi}}; }
  SurfaceKind kind() const override { return SurfaceKind::Torus; }
  bool u_periodic() const override { return true; }
  bool v_periodic() const override { return true; }
  double u_period() const override { return kTwoPi; }
  double v_period() const override { return kTwoPi; }

 private:
  Frame f_;
  double R_, r_;
};

// Clamped uniform knot vector on [0,1] for n control points of degree p.
std::vector<double> clamped_knots(int n, int p) {
  std::vector<double> k(static_cast<std::size_t>(n + p + 1));
  const int inner = n - p;  // number of spans
  for (int i = 0; i < n + p + 1; ++i) {
    if (i <= p)
      k[i] = 0.0;
    else if (i >= n)
      k[i] = 1.0;
    else
      k[i] = double(i - p) / inner;
  }
  return k;
}

// Span index s with knots[s] <= t < knots[s+1] (last span for t == 1).
int find_span(const std::vector<double>& k, int n, int p, double t) {
  if (t >= k[n]) return n - 1;
  if (t <= k[p]) return p;
  int lo = p, hi = n;
  while (hi - lo > 1) {
    const int mid = (lo + hi) / 2;
    if (t < k[mid])
      hi = mid;
    else
      lo = mid;
  }
  return lo;
}

// Values and first two derivatives of the p+1 basis functions non-zero on span s
// (out[d][j] is the d-th derivative of N_{s-p+j,p}). Cox-de Boor triangle for the values
// of every degree, then N'_{i,d} = d/(k_{i+d}-k_i) N_{i,d-1} - d/(k_{i+d+1}-k_{i+1}) N_{i+1,d-1}
// applied once or twice (0/0 terms of repeated knots are zero).
void basis_ders(const std::vector<double>& k, int s, int p, double t, double out[3][8]) {
  double table[8][8] = {};  // table[d][m] = N_{s-d+m, d}(t), m = 0..d
  table[0][0] = 1.0;
  auto val = [&](int d, int i) {  // N_{i,d}(t), zero off the span's support
    const int m = i - (s - d);
    return (d >= 0 && m >= 0 && m <= d) ? table[d][m] : 0.0;
  };
  for (int d = 1; d <= p; ++d)
    for (int m = 0; m <= d; ++m) {
      const int i = s - d + m;
      double v = 0.0;
      const double a = k[i + d] - k[i], b = k[i + d + 1] - k[i + 1];
      if (a > 0.0) v += (t - k[i]) / a * val(d - 1, i);
      if (b > 0.0) v += (k[i + d + 1] - t) / b * val(d - 1, i + 1);
      table[d][m] = v;
    }
  auto d1 = [&](int d, int i) {
    if (d < 1) return 0.0;
    const double a = k[i + d] - k[i], b = k[i + d + 1] - k[i + 1];
    double r = 0.0;
    if (a > 0.0) r += d / a * val(d - 1, i);
    if (b > 0.0) r -= d / b * val(d - 1, i + 1);
    return r;
  };
  auto d2 = [&](int d, int i) {
    if (d < 2) return 0.0;
    const double a = k[i + d] - k[i], b = k[i + d + 1] - k[i + 1];
    double r = 0.0;
    if (a > 0.0) r += d / a * d1(d - 1, i);
    if (b > 0.0) r -= d / b * d1(d - 1, i + 1);
    return r;
  };
  for (int j = 0; j <= p; ++j) {
    const int i = s - p + j;
    out[0][j] = table[p][j];
    out[1][j] = d1(p, i);
    out[2][j] = d2(p, i);
  }
}

class BSplinePatch final : public Surface {
 public:
  BSplinePatch(std::vector<Vec3> ctrl, int nu, int nv, int p, int q)
      : c_(std::move(ctrl)),
        nu_(nu),
        nv_(nv),
        p_(p),
        q_(q),
        ku_(clamped_knots(nu, p)),
        kv_(clamped_knots(nv, q)) {}
  SurfacePoint eval(double u, double v) const override {
    double bu[3][8], bv[3][8];
    const int su = find_span(ku_, nu_, p_, u), sv = find_span(kv_, nv_, q_, v);
    basis_ders(ku_, su, p_, u, bu);
    basis_ders(kv_, sv, q_, v, bv);
    SurfacePoint e{Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0), Vec3(0.0)};
    for (int a = 0; a <= p_; ++a)
      for (int b = 0; b <= q_; ++b) {
        const Vec3& P = c_[static_cast<std::size_t>((su - p_ + a) * nv_ + (sv - q_ + b))];
        e.p += bu[0][a] * bv[0][b] * P;
        e.du += bu[1][a] * bv[0][b] * P;
        e.dv += bu[0][a] * bv[1][b] * P;
        e.duu += bu[2][a] * bv[0][b] * P;
        e.duv += bu[1][a] * bv[1][b] * P;
        e.dvv += bu[0][a] * bv[2][b] * P;
      }
    return e;
  }
  Box2 bounds() const override { return {{0.0, 1.0}, {0.0, 1.0}}; }
  SurfaceKind kind() const override { return SurfaceKind::BSpline; }
  unsigned singular_sides() const override { return detect_singular_sides(*this); }

 private:
  std::vector<Vec3> c_;
  int nu_, nv_, p_, q_;
  std::vector<double> ku_, kv_;
};

class Line final : public Curve {
 public:
  Line(const Vec3& p, const Vec3& d, const Interval& r) : p_(p), d_(d), r_(r) {}
  CurvePoint3 eval(double t) const override { return {p_ + t * d_, d_, Vec3(0.0)}; }
  Interval range() const override { return r_; }
  CurveKind kind() const override { return CurveKind::Line; }

 private:
  Vec3 p_, d_;
  Interval r_;
};

class Circle final : public Curve {
 public:
  Circle(const Frame& f, double r) : f_(f), r_(r) {}
  CurvePoint3 eval(double t) const override {
    const Vec3 c = std::cos(t) * f_.x + std::sin(t) * f_.y;
    const Vec3 dc = -std::sin(t) * f_.x + std::cos(t) * f_.y;
    return {f_.origin + r_ * c, r_ * dc, -r_ * c};
  }
  Interval range() const override { return {0.0, kTwoPi}; }
  CurveKind kind() const override { return CurveKind::Circle; }
  bool periodic() const override { return true; }
  double period() const override { return kTwoPi; }

 private:
  Frame f_;
  double r_;
};

class Line2 final : public Curve2 {
 public:
  Line2(const Vec2& p, const Vec2& d, const Interval& r) : p_(p), d_(d), r_(r) {}
  CurvePoint2 eval(double t) const override { return {p_ + t * d_, d_, Vec2(0.0)}; }
  Interval range() const override { return r_; }
  CurveKind kind() const override { return CurveKind::Line; }

 private:
  Vec2 p_, d_;
  Interval r_;
};

}  // namespace

Frame Frame::from_axis(const Vec3& origin, const Vec3& z) {
  Frame f;
  f.origin = origin;
  f.z = glm::normalize(z);
  // Any vector not parallel to z: pick the coordinate axis least aligned with it.
  const Vec3 a = std::abs(f.z.x) < 0.9 ? Vec3(1, 0, 0) : Vec3(0, 1, 0);
  f.x = glm::normalize(a - glm::dot(a, f.z) * f.z);
  f.y = glm::cross(f.z, f.x);
  return f;
}

std::shared_ptr<Surface> make_plane(const Frame& f, const Box2& box) {
  return std::make_shared<Plane>(f, box);
}
std::shared_ptr<Surface> make_cylinder(const Frame& f, double r, const Interval& v) {
  return std::make_shared<Cylinder>(f, r, v);
}
std::shared_ptr<Surface> make_cone(const Frame& f, double r, double a, const Interval& v) {
  return std::make_shared<Cone>(f, r, a, v);
}
std::shared_ptr<Surface> make_sphere(const Frame& f, double r) {
  return std::make_shared<Sphere>(f, r);
}
std::shared_ptr<Surface> make_torus(const Frame& f, double R, double r) {
  return std::make_shared<Torus>(f, R, r);
}
std::shared_ptr<Surface> make_bspline_patch(const std::vector<Vec3>& ctrl, int nu, int nv, int p,
                                            int q) {
  if (p < 1 || q < 1 || p > 7 || q > 7 || nu <= p || nv <= q ||
      ctrl.size() != static_cast<std::size_t>(nu) * static_cast<std::size_t>(nv))
    throw std::invalid_argument(
        "make_bspline_patch: need nu > p, nv > q, degrees 1..7, nu*nv points");
  return std::make_shared<BSplinePatch>(ctrl, nu, nv, p, q);
}
std::shared_ptr<Curve> make_line(const Vec3& p, const Vec3& d, const Interval& range) {
  return std::make_shared<Line>(p, d, range);
}
std::shared_ptr<Curve> make_circle(const Frame& f, double r) {
  return std::make_shared<Circle>(f, r);
}
std::shared_ptr<Curve2> make_line2(const Vec2& p, const Vec2& d, const Interval& range) {
  return std::make_shared<Line2>(p, d, range);
}

}  // namespace uvmesh::geom
