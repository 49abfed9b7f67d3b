#include "uvmesh2d/locate.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uvmesh::cli2d {

namespace {

double cross(m2d::Vec2 a, m2d::Vec2 b, m2d::Vec2 c) {  // (b - a) x (c - a)
  return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
}

// Barycentric tolerance for "on the triangle": a point on an edge shared by two triangles
// must be found in one of them despite rounding. The weights are dimensionless, so a fixed
// tolerance is relative to the triangle's size; a point accepted this way lies at most
// ~1e-12 of that size outside, where interpolated values are continuous anyway.
constexpr double kInsideTolerance = 1e-12;

// Cap on grid cells per axis: bounds the grid's memory on degenerate inputs (all
// triangles in a thin strip) while keeping O(1) queries for meshes up to ~4e6 triangles.
constexpr double kMaxCellsPerAxis = 2048;

}  // namespace

bool TriangleLocator::build(const std::vector<m2d::Vec2>& vertices,
                            const std::vector<std::array<m2d::VertId, 3>>& triangles) {
  verts_ = vertices;
  tris_.clear();
  tri_index_.clear();
  double xmin = std::numeric_limits<double>::infinity(), ymin = xmin, xmax = -xmin, ymax = -xmin;
  const auto nv = static_cast<std::int64_t>(verts_.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto& tr = triangles[t];
    if (tr[0] < 0 || tr[1] < 0 || tr[2] < 0 || tr[0] >= nv || tr[1] >= nv || tr[2] >= nv) continue;
    const m2d::Vec2 a = verts_[static_cast<std::size_t>(tr[0])],
                    b = verts_[static_cast<std::size_t>(tr[1])],
                    c = verts_[static_cast<std::size_t>(tr[2])];
    if (!(cross(a, b, c) != 0)) continue;  // zero area (or NaN)
    tris_.push_back(tr);
    tri_index_.push_back(static_cast<std::int32_t>(t));
    for (const m2d::Vec2& v : {a, b, c}) {
      xmin = std::min(xmin, v.x);
      xmax = std::max(xmax, v.x);
      ymin = std::min(ymin, v.y);
      ymax = std::max(ymax, v.y);
    }
  }
  if (tris_.empty()) return false;

  const double w = xmax - xmin, h = ymax - ymin;  // > 0: some triangle has an area
  const double n = static_cast<double>(tris_.size());
  nx_ = static_cast<int>(std::clamp(std::round(std::sqrt(n * w / h)), 1.0, kMaxCellsPerAxis));
  ny_ = static_cast<int>(std::clamp(std::round(n / nx_), 1.0, kMaxCellsPerAxis));
  x0_ = xmin;
  y0_ = ymin;
  cw_ = w / nx_;
  ch_ = h / ny_;
  auto cx = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - x0_) / cw_)), 0, nx_ - 1);
  };
  auto cy = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - y0_) / ch_)), 0, ny_ - 1);
  };
  const std::size_t ncells = static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_);
  cell_start_.assign(ncells + 1, 0);
  auto for_cells = [&](std::size_t t, auto&& fn) {
    double bx0 = std::numeric_limits<double>::infinity(), by0 = bx0, bx1 = -bx0, by1 = -bx0;
    for (m2d::VertId v : tris_[t]) {
      const m2d::Vec2 p = verts_[static_cast<std::size_t>(v)];
      bx0 = std::min(bx0, p.x);
      bx1 = std::max(bx1, p.x);
      by0 = std::min(by0, p.y);
      by1 = std::max(by1, p.y);
    }
    for (int j = cy(by0); j <= cy(by1); ++j)
      for (int i = cx(bx0); i <= cx(bx1); ++i)
        fn(static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(i));
  };
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for_cells(t, [&](std::size_t c) { ++cell_start_[c + 1]; });
  for (std::size_t c = 0; c < ncells; ++c) cell_start_[c + 1] += cell_start_[c];
  cell_tris_.resize(static_cast<std::size_t>(cell_start_[ncells]));
  std::vector<std::int32_t> fill(cell_start_.begin(), cell_start_.end() - 1);
  for (std::size_t t = 0; t < tris_.size(); ++t)
    for_cells(t, [&](std::size_t c) {
      cell_tris_[static_cast<std::size_t>(fill[c]++)] = static_cast<std::int32_t>(t);
    });
  return true;
}

bool TriangleLocator::barycentric(std::int32_t t, m2d::Vec2 p, std::array<double, 3>& w) const {
  const auto& tr = tris_[static_cast<std::size_t>(t)];
  const m2d::Vec2 a = verts_[static_cast<std::size_t>(tr[0])],
                  b = verts_[static_cast<std::size_t>(tr[1])],
                  c = verts_[static_cast<std::size_t>(tr[2])];
  const double det = cross(a, b, c);
  w[0] = cross(p, b, c) / det;
  w[1] = cross(a, p, c) / det;
  w[2] = 1.0 - w[0] - w[1];
  return w[0] >= -kInsideTolerance && w[1] >= -kInsideTolerance && w[2] >= -kInsideTolerance;
}

double TriangleLocator::nearest_on(std::int32_t t, m2d::Vec2 p, std::array<double, 3>& w) const {
  if (barycentric(t, p, w)) return 0.0;
  const auto& tr = tris_[static_cast<std::size_t>(t)];
  double best = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < 3; ++i) {
    const std::size_t j = (i + 1) % 3, k = (i + 2) % 3;
    const m2d::Vec2 a = verts_[static_cast<std::size_t>(tr[i])],
                    b = verts_[static_cast<std::size_t>(tr[j])];
    const double ex = b.x - a.x, ey = b.y - a.y, len2 = ex * ex + ey * ey;
    const double s =
        std::clamp(len2 > 0 ? ((p.x - a.x) * ex + (p.y - a.y) * ey) / len2 : 0.0, 0.0, 1.0);
    const double dx = a.x + s * ex - p.x, dy = a.y + s * ey - p.y, d2 = dx * dx + dy * dy;
    if (d2 < best) {
      best = d2;
      w[i] = 1.0 - s;
      w[j] = s;
      w[k] = 0.0;
    }
  }
  return std::sqrt(best);
}

TriangleLocator::Location TriangleLocator::locate(m2d::Vec2 p) const {
  Location loc;
  if (tris_.empty()) return loc;
  const int ci = std::clamp(static_cast<int>(std::floor((p.x - x0_) / cw_)), 0, nx_ - 1);
  const int cj = std::clamp(static_cast<int>(std::floor((p.y - y0_) / ch_)), 0, ny_ - 1);
  auto cell = [&](int i, int j) {
    const std::size_t c =
        static_cast<std::size_t>(j) * static_cast<std::size_t>(nx_) + static_cast<std::size_t>(i);
    return std::pair{cell_start_[c], cell_start_[c + 1]};
  };
  {
    auto [b, e] = cell(ci, cj);
    for (std::int32_t k = b; k < e; ++k) {
      const std::int32_t t = cell_tris_[static_cast<std::size_t>(k)];
      if (barycentric(t, p, loc.w)) {
        loc.triangle = tri_index_[static_cast<std::size_t>(t)];
        loc.inside = true;
        return loc;
      }
    }
  }
  // Outside every triangle: nearest triangle by rings of cells around the cell of p', the
  // projection of p onto the grid box. A triangle point q in a cell of ring r + 1 is at
  // least r * min(cw, ch) from p', and |q - p| >= |q - p'| (projecting onto a convex set
  // does not increase distances), so the search stops once the best distance found is
  // within that bound.
  double best = std::numeric_limits<double>::infinity();
  std::int32_t best_t = -1;
  std::array<double, 3> w{};
  const double step = std::min(cw_, ch_);
  const int rmax = std::max(nx_, ny_);
  for (int r = 0; r <= rmax; ++r) {
    for (int j = cj - r; j <= cj + r; ++j) {
      if (j < 0 || j >= ny_) continue;
      const bool full_row = r == 0 || j == cj - r || j == cj + r;
      for (int i = ci - r; i <= ci + r; i += full_row ? 1 : 2 * r) {
        if (i < 0 || i >= nx_) continue;
        auto [b, e] = cell(i, j);
        for (std::int32_t k = b; k < e; ++k) {
          const std::int32_t t = cell_tris_[static_cast<std::size_t>(k)];
          const double d = nearest_on(t, p, w);
          if (d < best) {
            best = d;
            best_t = t;
            loc.w = w;
          }
        }
      }
    }
    if (best_t >= 0 && best <= r * step) break;
  }
  loc.triangle = tri_index_[static_cast<std::size_t>(best_t)];
  loc.inside = best == 0.0;
  return loc;
}

}  // namespace uvmesh::cli2d
