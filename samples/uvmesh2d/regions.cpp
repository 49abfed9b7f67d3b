#include "uvmesh2d/regions.h"

#include <cmath>
#include <limits>
#include <memory>

#include "uvmesh2d/background.h"
#include "uvmesh2d/locate.h"

namespace uvmesh::cli2d {

namespace {

struct ComponentSizes {
  TriangleLocator locator;
  std::vector<int> tri_component;
  std::vector<double> h;  // per component; +inf when unconstrained

  double at(double x, double y) const {
    const auto loc = locator.locate({x, y});
    const int c = tri_component[static_cast<std::size_t>(loc.triangle)];
    return c >= 0 && static_cast<std::size_t>(c) < h.size()
               ? h[static_cast<std::size_t>(c)]
               : std::numeric_limits<double>::infinity();
  }
};

}  // namespace

RegionSize apply_region_max_area(const PolyData& poly, const m2d::SizeSpec& base,
                                 const m2d::Options& opt) {
  RegionSize rs;
  rs.spec = base;
  bool any = false;
  for (double a : poly.region_max_area) any = any || a > 0;
  if (!any) return rs;

  m2d::Options cdt = opt;
  cdt.refine = false;
  cdt.optimize = false;
  cdt.split_segments = false;
  const m2d::Result r = m2d::mesh(poly.pslg, m2d::SizeSpec::uniform(0), cdt);
  if (!r.usable()) return rs;  // the real run reports the problem
  auto cs = std::make_shared<ComponentSizes>();
  if (!cs->locator.build(r.mesh.vertices, r.mesh.triangles)) return rs;
  cs->tri_component = r.mesh.triangle_region;
  cs->tri_component.resize(r.mesh.triangles.size(), -1);
  int ncomp = 0;
  for (int c : cs->tri_component) ncomp = std::max(ncomp, c + 1);
  cs->h.assign(static_cast<std::size_t>(ncomp), std::numeric_limits<double>::infinity());

  for (std::size_t i = 0; i < poly.pslg.regions.size(); ++i) {
    const double area = i < poly.region_max_area.size() ? poly.region_max_area[i] : -1;
    if (!(area > 0)) continue;
    const std::string where =
        "region " + std::to_string(static_cast<std::int64_t>(i) + poly.first_index) +
        (i < poly.region_lines.size()
             ? " (" + poly.file + ":" + std::to_string(poly.region_lines[i]) + ")"
             : "");
    const auto loc = cs->locator.locate(poly.pslg.regions[i].seed);
    if (!loc.inside) {
      rs.notes.push_back(where +
                         ": the seed is outside the meshed domain; its maximum area is ignored");
      continue;
    }
    const int c = cs->tri_component[static_cast<std::size_t>(loc.triangle)];
    if (c < 0) continue;
    const double h = std::sqrt(4.0 * area / std::sqrt(3.0));
    double& hc = cs->h[static_cast<std::size_t>(c)];
    hc = std::min(hc, h);
    ++rs.constrained_regions;
  }
  if (rs.constrained_regions == 0) return rs;

  std::shared_ptr<const ComponentSizes> sizes = cs;
  switch (base.kind) {
    case m2d::SizeSpec::Kind::Uniform: {
      double h0 = base.h;
      if (!(h0 > 0)) {  // "from the boundary": the mean input segment length
        double sum = 0;
        for (const auto& s : poly.pslg.segments) {
          const m2d::Vec2 a = poly.pslg.points[static_cast<std::size_t>(s.a)],
                          b = poly.pslg.points[static_cast<std::size_t>(s.b)];
          sum += std::hypot(b.x - a.x, b.y - a.y);
        }
        h0 = poly.pslg.segments.empty() ? std::numeric_limits<double>::infinity()
                                        : sum / static_cast<double>(poly.pslg.segments.size());
        if (!std::isfinite(h0)) {  // no segments: the bounding box diagonal
          double x0 = std::numeric_limits<double>::infinity(), y0 = x0, x1 = -x0, y1 = -x0;
          for (const auto& p : poly.pslg.points) {
            x0 = std::min(x0, p.x), x1 = std::max(x1, p.x), y0 = std::min(y0, p.y),
            y1 = std::max(y1, p.y);
          }
          h0 = std::hypot(x1 - x0, y1 - y0);
        }
      }
      rs.spec = m2d::SizeSpec::scalar(
          [sizes, h0](double x, double y) { return std::min(h0, sizes->at(x, y)); });
      break;
    }
    case m2d::SizeSpec::Kind::Scalar: {
      auto f = base.size;
      rs.spec = m2d::SizeSpec::scalar(
          [sizes, f](double x, double y) { return std::min(f(x, y), sizes->at(x, y)); });
      break;
    }
    case m2d::SizeSpec::Kind::Metric: {
      auto f = base.metric;
      rs.spec = m2d::SizeSpec::aniso([sizes, f](double x, double y) {
        const double h = sizes->at(x, y);
        const m2d::Metric2 m = f(x, y);
        return std::isfinite(h) ? spd_bound_size(m, h) : m;
      });
      break;
    }
  }
  return rs;
}

}  // namespace uvmesh::cli2d
