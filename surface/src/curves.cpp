// Stage 1, curves first (reference chapter §7.5.2, §7.6.2): every model edge is
// discretized once, at unit length in the 3D metric along the curve. The metric along
// an edge is the intersection of the curve's own curvature size and the metrics of the
// faces around it, read through each use's pcurve at the same curve parameter.
#include <algorithm>
#include <cmath>

#include "internal.h"

namespace uvmesh::surface::detail {

namespace {

// Size asked by the curvature of the curve itself: a circle of radius rho needs
// h = 2 sqrt(eps (2 rho - eps)) for a sagitta eps, and h = 2 rho sin(theta/2) for an arc
// of theta (the same rules as param's surface sizes).
double curve_size(const geom::CurvePoint3& c, const param::SizeSpec& spec) {
  const double s = glm::length(c.d1);
  const double k = s > 0 ? glm::length(glm::cross(c.d1, c.d2)) / (s * s * s) : 0.0;
  const double rho = k > 0 ? 1.0 / k : std::numeric_limits<double>::infinity();
  return std::min({spec.hmax, param::chordal_size(rho, spec.chordal_tol),
                   param::angle_size(rho, spec.angle_tol)});
}

}  // namespace

// Scalar density f(t) = metric length of dC/dt: the number of unit edges per unit of
// parameter. The largest over the curve's own size and every adjacent face's metric.
double EdgeDiscretizer::density(const geom::Edge& e, geom::Id eid, double t, double& speed,
                                const BoundaryCaps* caps) const {
  auto& seen = seen_[static_cast<std::size_t>(eid)];
  auto it = seen.find(t);
  if (it == seen.end()) it = seen.emplace(t, sample(e, eid, t)).first;
  const Sample& x = it->second;
  speed = x.speed;
  if (!(speed > 0)) return 0.0;
  double f = x.f;
  if (caps && f > 0) {
    const double hc = caps->cap(eid, x.p, x.d1 / speed, speed / f);
    f = std::max(f, speed / hc);
  }
  return f;
}

EdgeDiscretizer::Sample EdgeDiscretizer::sample(const geom::Edge& e, geom::Id eid, double t) const {
  const geom::CurvePoint3 c = e.curve->eval(t);
  Sample x{c.p, c.d1, glm::length(c.d1), 0.0};
  if (!(x.speed > 0)) return x;
  double h = curve_size(c, spec_);
  if (auto it = spec_.edge_size.find(eid); it != spec_.edge_size.end()) h = std::min(h, it->second);
  h = std::clamp(h, spec_.hmin > 0 ? spec_.hmin : 0.0, spec_.hmax);
  x.f = x.speed / h;
  for (const Adjacent& a : adj_[static_cast<std::size_t>(eid)]) {
    const param::FaceSizeField* fld = fields_[static_cast<std::size_t>(a.face)];
    if (!fld) continue;
    const geom::Vec2 uv = a.pcurve->point(t);
    const param::Metric3 m = fld->metric3(uv.x, uv.y);
    x.f = std::max(x.f, m.length(c.d1));
  }
  return x;
}

EdgeDiscretizer::EdgeDiscretizer(const geom::Model& m, const param::SizeSpec& spec,
                                 const std::vector<const param::FaceSizeField*>& fields)
    : m_(m), spec_(spec), fields_(fields), adj_(m.edges.size()), seen_(m.edges.size()) {
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (const geom::Loop& l : m.faces[f].loops)
      for (const geom::EdgeUse& u : l.uses) {
        if (u.edge < 0 || !u.pcurve) continue;
        auto& list = adj_[static_cast<std::size_t>(u.edge)];
        const bool seen = std::any_of(list.begin(), list.end(), [&](const Adjacent& a) {
          return a.face == static_cast<geom::Id>(f);
        });
        if (!seen) list.push_back({static_cast<geom::Id>(f), u.pcurve.get()});
      }
}

std::vector<double> EdgeDiscretizer::discretize(geom::Id eid, const BoundaryCaps* caps) const {
  const geom::Edge& e = m_.edges[static_cast<std::size_t>(eid)];
  const double lo = e.range.lo, hi = e.range.hi;
  if (e.degenerate || !e.curve || !(hi > lo)) return {lo, hi};
  // Adaptive sampling of the density: pieces are split until each carries at most a
  // quarter of a unit edge and its end densities differ by less than 2x, so a face
  // feature between samples is not missed (the 1D analogue of eq. 7.10's sampling).
  struct Sample {
    double t, f;
    double speed;  // |C'(t)|: converts parameter steps to arc length for the gradation
  };
  auto sample = [&](double t) {
    Sample x{t, 0.0, 0.0};
    x.f = density(e, eid, t, x.speed, caps);
    return x;
  };
  std::vector<Sample> s;
  const int n0 = 16;
  for (int i = 0; i <= n0; ++i) {
    const double t = lo + (hi - lo) * i / n0;
    s.push_back(sample(t));
  }
  const std::size_t cap = 20000;
  for (int pass = 0; pass < 12 && s.size() < cap; ++pass) {
    std::vector<Sample> next;
    next.reserve(s.size() * 2);
    bool split = false;
    for (std::size_t i = 0; i + 1 < s.size(); ++i) {
      next.push_back(s[i]);
      const double dt = s[i + 1].t - s[i].t;
      const double piece = 0.5 * (s[i].f + s[i + 1].f) * dt;
      const double fa = std::max(s[i].f, 1e-300), fb = std::max(s[i + 1].f, 1e-300);
      if ((piece > 0.25 || std::max(fa / fb, fb / fa) > 2.0) && dt > (hi - lo) * 1e-9 &&
          next.size() + s.size() < cap) {
        const double t = 0.5 * (s[i].t + s[i + 1].t);
        next.push_back(sample(t));
        split = true;
      }
    }
    next.push_back(s.back());
    s.swap(next);
    if (!split) break;
  }
  // Gradation along the curve (H-correction in 1D): the size h = speed / f may grow by
  // at most (beta - 1) per unit of arc length; two sweeps make it hold both ways.
  const double beta = std::max(1.0, spec_.gradation);
  if (beta > 1.0) {
    std::vector<double> h(s.size()), ds(s.size(), 0.0);
    for (std::size_t i = 0; i < s.size(); ++i)
      h[i] = s[i].f > 0 ? 1.0 / s[i].f : 0.0;  // parameter units
    for (std::size_t i = 1; i < s.size(); ++i) ds[i] = s[i].t - s[i - 1].t;
    // In parameter units a unit of arc is 1/speed; use the local speed at each sample.
    std::vector<double> speed(s.size());
    for (std::size_t i = 0; i < s.size(); ++i) speed[i] = std::max(s[i].speed, 1e-300);
    for (std::size_t i = 1; i < s.size(); ++i)
      if (h[i - 1] > 0 && h[i] > 0)
        h[i] = std::min(h[i], (h[i - 1] * speed[i - 1] + (beta - 1) * ds[i] * speed[i]) / speed[i]);
    for (std::size_t i = s.size() - 1; i-- > 0;)
      if (h[i + 1] > 0 && h[i] > 0)
        h[i] = std::min(h[i],
                        (h[i + 1] * speed[i + 1] + (beta - 1) * ds[i + 1] * speed[i]) / speed[i]);
    for (std::size_t i = 0; i < s.size(); ++i)
      if (h[i] > 0) s[i].f = 1.0 / h[i];
  }
  // Cumulative metric length; trapezoid per piece.
  std::vector<double> cum(s.size(), 0.0);
  for (std::size_t i = 1; i < s.size(); ++i)
    cum[i] = cum[i - 1] + 0.5 * (s[i - 1].f + s[i].f) * (s[i].t - s[i - 1].t);
  const double L = cum.back();
  int n = std::max(1, static_cast<int>(std::lround(L)));
  const bool closed = e.v0 == e.v1 && e.v0 != geom::kNone;
  if (closed) n = std::max(n, min_closed_);
  std::vector<double> out;
  out.reserve(static_cast<std::size_t>(n) + 1);
  out.push_back(lo);
  std::size_t j = 1;
  for (int k = 1; k < n; ++k) {
    const double target = L > 0 ? L * k / n : 0.0;
    while (j + 1 < s.size() && cum[j] < target) ++j;
    double t;
    if (L > 0) {
      const double a = cum[j - 1], b = cum[j];
      const double w = b > a ? (target - a) / (b - a) : 0.5;
      t = s[j - 1].t + w * (s[j].t - s[j - 1].t);
    } else {
      t = lo + (hi - lo) * k / n;
    }
    out.push_back(t);
  }
  out.push_back(hi);
  return out;
}

}  // namespace uvmesh::surface::detail
