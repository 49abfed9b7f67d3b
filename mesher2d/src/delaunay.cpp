// Stage 2 of mesher2d: the Delaunay triangulation of the distinct input points in an
// enclosing box (§7.3.2), inserted in Hilbert order.
#include <algorithm>
#include <limits>
#include <utility>

#include "mesh_state.h"

namespace uvmesh::m2d::detail {

// Hilbert index of (x, y) in [0, 2^16)^2: the spatial order of batch insertion (§7.3.2).
static std::uint32_t hilbert_d(std::uint32_t x, std::uint32_t y) {
  std::uint32_t d = 0;
  for (std::uint32_t s = 1u << 15; s > 0; s >>= 1) {
    const std::uint32_t rx = (x & s) ? 1 : 0;
    const std::uint32_t ry = (y & s) ? 1 : 0;
    d += s * s * ((3 * rx) ^ ry);
    if (ry == 0) {  // rotate the quadrant
      if (rx == 1) {
        x = s - 1 - x;
        y = s - 1 - y;
      }
      std::swap(x, y);
    }
  }
  return d;
}

bool triangulate_box(MeshState& ms) {
  auto point = [&](VertId i) { return ms.in.points[i]; };
  const std::size_t n = ms.in.points.size();
  const std::size_t ntot = n;
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  for (std::size_t i = 0; i < ntot; ++i) {
    const Vec2 p = point(static_cast<VertId>(i));
    xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x);
    ymin = std::min(ymin, p.y), ymax = std::max(ymax, p.y);
  }
  double ext = std::max(xmax - xmin, ymax - ymin);
  if (!(ext > 0)) ext = std::max(1.0, std::abs(xmin) + std::abs(ymin));
  // The box (§7.3.2): far enough that box corners never matter inside the domain.
  const double m = 2.0 * ext;
  ms.tri.init_box(xmin - m, ymin - m, xmax + m, ymax + m, ntot + 16);
  ms.vid.assign(ntot, kNone);
  // Batch insertion in Hilbert order.
  std::vector<std::pair<std::uint32_t, VertId>> order;
  order.reserve(ntot);
  const double sx = 65535.0 / std::max(xmax - xmin, 1e-300),
               sy = 65535.0 / std::max(ymax - ymin, 1e-300);
  for (std::size_t i = 0; i < ntot; ++i) {
    if (i < n && ms.rep[i] != static_cast<std::int32_t>(i)) continue;
    const Vec2 p = point(static_cast<VertId>(i));
    const auto qx = static_cast<std::uint32_t>(std::clamp((p.x - xmin) * sx, 0.0, 65535.0));
    const auto qy = static_cast<std::uint32_t>(std::clamp((p.y - ymin) * sy, 0.0, 65535.0));
    order.push_back({hilbert_d(qx, qy), static_cast<VertId>(i)});
  }
  std::sort(order.begin(), order.end());
  ms.fixed.assign(4, 1);
  ms.vmark.assign(4, 0);
  InsertParams prm;
  TriId hint = 0;
  for (const auto& [key, i] : order) {
    const VertId v = ms.tri.add_vertex(point(i));
    const auto r = ms.tri.insert(v, hint, prm);
    if (r.status == InsertStatus::Duplicate) {
      // A boundary split point landing exactly on another point: use that one.
      ms.tri.remove_last_vertex();
      ms.vid[i] = r.v;
      continue;
    }
    if (r.status != InsertStatus::Inserted)
      return ms.fail(StatusCode::InternalError,
                     "could not insert point " + std::to_string(i) + " " + fmt_pt(point(i)));
    ms.vid[i] = v;
    ms.fixed.push_back(1);
    ms.vmark.push_back(ms.in.point_markers.empty() ? 0 : ms.in.point_markers[i]);
    hint = ms.tri.vertex_tri(v);
  }
  for (std::size_t i = 0; i < n; ++i) ms.vid[i] = ms.vid[ms.rep[i]];
  for (auto& s : ms.segs) {
    s.a = ms.vid[s.a];
    s.b = ms.vid[s.b];
  }
  return true;
}

}  // namespace uvmesh::m2d::detail
