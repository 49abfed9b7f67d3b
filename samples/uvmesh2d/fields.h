// uvmesh::cli2d::fields -- analytic size fields on the unit square, for the uvmesh2d
// program (--metric-fn NAME:ARGS), the tests and the benchmark. Header only.
//
// Usage:
//   uvmesh::m2d::SizeSpec s = uvmesh::cli2d::fields::ring(0.002, 0.05);
//   auto p = uvmesh::cli2d::fields::parse("bl:0.001,0.1");   // p.ok(), p.spec, p.error
//
// Fields (x, y in the unit square; outside it the formulas are clamped to the square, as
// noted, so that sizes stay positive and bounded everywhere):
//   uniform:h      h(x, y) = h                                          (SizeSpec::Uniform)
//   linear:h0,h1   h(x, y) = h0 + (h1 - h0) x, x clamped to [0, 1]      (isotropic, Scalar)
//   bl:h0,hmax     boundary layer along y = 0.5 (anisotropic, Metric):
//                  h_x = hmax, h_y = h0 + 2 (hmax - h0) |y - 0.5|, |y - 0.5| clamped to 0.5,
//                  M = diag(1/h_x^2, 1/h_y^2)
//   ring:h0,hmax   layer on the circle of radius 0.25 centred at (0.5, 0.5) (Metric):
//                  r = |(x, y) - (0.5, 0.5)|, d = |r - 0.25|, n = radial unit vector,
//                  t = tangent unit vector, h_n = min(hmax, h0 + 4 (hmax - h0) d), h_t = hmax,
//                  M = n n^T / h_n^2 + t t^T / h_t^2; M = I / hmax^2 at r = 0 (where h_n = hmax
//                  already, so M is continuous there)
// Constraints: every size > 0 and finite; bl and ring need h0 <= hmax.
#pragma once

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::cli2d::fields {

inline constexpr const char* kHelp =
    "Built-in size fields for --metric-fn NAME:ARGS (x, y on the unit square; clamped outside "
    "it):\n"
    "  uniform:h      h = h\n"
    "  linear:h0,h1   isotropic, h = h0 + (h1 - h0) * x\n"
    "  bl:h0,hmax     anisotropic boundary layer on y = 0.5: h_x = hmax,\n"
    "                 h_y = h0 + 2 (hmax - h0) |y - 0.5|, M = diag(1/h_x^2, 1/h_y^2)\n"
    "  ring:h0,hmax   anisotropic layer on the circle r = 0.25 around (0.5, 0.5): d = |r - 0.25|,\n"
    "                 h_n = min(hmax, h0 + 4 (hmax - h0) d) along the radius n, h_t = hmax along\n"
    "                 the tangent t, M = n n^T / h_n^2 + t t^T / h_t^2 (M = I / hmax^2 at r = 0)\n"
    "  Sizes must be > 0; bl and ring need h0 <= hmax.";

inline double linear_size(double h0, double h1, double x) {
  return h0 + (h1 - h0) * std::clamp(x, 0.0, 1.0);
}

inline m2d::Metric2 bl_metric(double h0, double hmax, double /*x*/, double y) {
  const double hx = hmax;
  const double hy = h0 + 2.0 * (hmax - h0) * std::min(std::fabs(y - 0.5), 0.5);
  return {1.0 / (hx * hx), 0.0, 1.0 / (hy * hy)};
}

inline m2d::Metric2 ring_metric(double h0, double hmax, double x, double y) {
  const double dx = x - 0.5, dy = y - 0.5;
  const double r = std::hypot(dx, dy);
  if (r == 0) return m2d::Metric2::iso(hmax);
  const double nx = dx / r, ny = dy / r;  // radial unit vector n; tangent t = (-ny, nx)
  const double d = std::fabs(r - 0.25);
  const double hn = std::min(hmax, h0 + 4.0 * (hmax - h0) * d), ht = hmax;
  const double an = 1.0 / (hn * hn), at = 1.0 / (ht * ht);
  return {an * nx * nx + at * ny * ny, (an - at) * nx * ny, an * ny * ny + at * nx * nx};
}

inline m2d::SizeSpec uniform(double h) {
  return m2d::SizeSpec::uniform(h);
}
inline m2d::SizeSpec linear(double h0, double h1) {
  return m2d::SizeSpec::scalar([h0, h1](double x, double) { return linear_size(h0, h1, x); });
}
inline m2d::SizeSpec bl(double h0, double hmax) {
  return m2d::SizeSpec::aniso([h0, hmax](double x, double y) { return bl_metric(h0, hmax, x, y); });
}
inline m2d::SizeSpec ring(double h0, double hmax) {
  return m2d::SizeSpec::aniso(
      [h0, hmax](double x, double y) { return ring_metric(h0, hmax, x, y); });
}

struct Parsed {
  m2d::SizeSpec spec;
  std::string name;
  std::vector<double> args;
  std::string error;  // empty on success; otherwise one sentence naming the problem
  bool ok() const { return error.empty(); }
};

// "NAME:a,b" -> the field; error for unknown names, wrong argument counts, numbers that do
// not parse, non-positive or non-finite sizes, and h0 > hmax.
inline Parsed parse(std::string_view text) {
  Parsed p;
  const std::size_t colon = text.find(':');
  p.name = std::string(text.substr(0, colon));
  const std::string_view rest =
      colon == std::string_view::npos ? std::string_view{} : text.substr(colon + 1);
  std::size_t expected = 0;
  if (p.name == "uniform")
    expected = 1;
  else if (p.name == "linear" || p.name == "bl" || p.name == "ring")
    expected = 2;
  else {
    p.error = "unknown size field '" + p.name +
              "' (known: uniform:h, linear:h0,h1, bl:h0,hmax, ring:h0,hmax)";
    return p;
  }
  const std::string usage = p.name == "uniform"  ? "uniform:h"
                            : p.name == "linear" ? "linear:h0,h1"
                                                 : p.name + ":h0,hmax";
  std::size_t pos = 0;
  while (colon != std::string_view::npos && pos <= rest.size()) {
    std::size_t comma = rest.find(',', pos);
    std::string_view tok =
        rest.substr(pos, comma == std::string_view::npos ? std::string_view::npos : comma - pos);
    double v = 0;
    const char* b = tok.data();
    const char* e = tok.data() + tok.size();
    if (!tok.empty() && *b == '+') ++b;
    auto [ptr, ec] = std::from_chars(b, e, v);
    if (tok.empty() || ec != std::errc() || ptr != e) {
      p.error = "size field '" + std::string(text) + "': '" + std::string(tok) +
                "' is not a number (expected " + usage + ")";
      return p;
    }
    p.args.push_back(v);
    if (comma == std::string_view::npos) break;
    pos = comma + 1;
  }
  if (p.args.size() != expected) {
    p.error = "size field '" + std::string(text) + "': expected " + std::to_string(expected) +
              (expected == 1 ? " number" : " numbers") + " (" + usage + "), found " +
              std::to_string(p.args.size());
    return p;
  }
  for (double v : p.args) {
    if (!std::isfinite(v) || !(v > 0)) {
      p.error = "size field '" + std::string(text) + "': sizes must be finite and > 0";
      return p;
    }
  }
  if ((p.name == "bl" || p.name == "ring") && p.args[0] > p.args[1]) {
    p.error = "size field '" + std::string(text) + "': h0 must not exceed hmax";
    return p;
  }
  if (p.name == "uniform")
    p.spec = uniform(p.args[0]);
  else if (p.name == "linear")
    p.spec = linear(p.args[0], p.args[1]);
  else if (p.name == "bl")
    p.spec = bl(p.args[0], p.args[1]);
  else
    p.spec = ring(p.args[0], p.args[1]);
  return p;
}

}  // namespace uvmesh::cli2d::fields
