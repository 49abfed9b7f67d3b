// A face whose (u,v) boundary is unusable -- its pcurves cross, two nodes coincide, the
// loop runs clockwise -- after the crossing rounds of the mesher (mesher.cpp). In CAD
// models these are slivers: a face between two curves a few micrometres apart, whose
// pcurves, approximations both, cross each other, orders of magnitude below hmin. The
// face is triangulated from its boundary nodes alone, in 3D: the triangulation of the
// closed polygon that minimizes the sum of the triangles' perimeters (each diagonal
// counts twice, so it is the minimum-weight triangulation; on a strip it joins the two
// sides by their shortest rungs), by the O(n^3) dynamic programme over sub-polygons. The
// result is kept only if it is a manifold disc (no edge used three times, no triangle
// with a repeated node) and lies within the chordal tolerance at every centroid and edge
// midpoint (measured by Newton projection, as the report measures); otherwise the face
// stays failed. Triangles are turned to agree with sigma_u x sigma_v, as the (u,v)-CCW
// triangles of a meshed face are.
#include <algorithm>
#include <cstdint>
#include <limits>
#include <map>
#include <sstream>

#include "face_stage.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface::detail {

namespace {

constexpr std::size_t kMaxBoundaryTriangulation = 400;  // nodes; O(n^3) work

using Tri = std::array<std::size_t, 3>;  // corners: indices of the polygon

// The polygon: consecutive repeats of a node (a pole's run of (u,v) points) are one corner.
void boundary_polygon(const std::vector<NodeId>& gid_in, const std::vector<geom::Vec2>& uv_in,
                      std::vector<NodeId>& g, std::vector<geom::Vec2>& uv) {
  for (std::size_t i = 0; i < gid_in.size(); ++i)
    if (g.empty() || g.back() != gid_in[i]) g.push_back(gid_in[i]), uv.push_back(uv_in[i]);
  while (g.size() > 1 && g.back() == g.front()) g.pop_back(), uv.pop_back();
}

// The minimum-perimeter triangulation of the polygon p (nodes g) by the dynamic
// programme over sub-polygons [i, j]; false when every one repeats a node.
bool min_perimeter_triangulation(const std::vector<NodeId>& g, const std::vector<geom::Vec3>& p,
                                 std::vector<Tri>& tris) {
  const std::size_t n = g.size();
  const double inf = std::numeric_limits<double>::infinity();
  std::vector<double> W(n * n, 0.0);
  std::vector<std::uint16_t> K(n * n, 0);
  auto cost = [&](std::size_t i, std::size_t k, std::size_t j) {
    if (g[i] == g[k] || g[k] == g[j] || g[i] == g[j]) return inf;  // a seam node seen twice
    return glm::length(p[k] - p[i]) + glm::length(p[j] - p[k]) + glm::length(p[i] - p[j]);
  };
  for (std::size_t len = 2; len < n; ++len)
    for (std::size_t i = 0; i + len < n; ++i) {
      const std::size_t j = i + len;
      double best = inf;
      std::size_t bk = i + 1;
      for (std::size_t k = i + 1; k < j; ++k) {
        const double c = W[i * n + k] + W[k * n + j] + cost(i, k, j);
        if (c < best) best = c, bk = k;
      }
      W[i * n + j] = best;
      K[i * n + j] = static_cast<std::uint16_t>(bk);
    }
  if (!(W[n - 1] < inf)) return false;
  std::vector<std::pair<std::size_t, std::size_t>> stack{{0, n - 1}};
  while (!stack.empty()) {
    const auto [i, j] = stack.back();
    stack.pop_back();
    if (j < i + 2) continue;
    const std::size_t k = K[i * n + j];
    tris.push_back({i, k, j});
    stack.push_back({i, k});
    stack.push_back({k, j});
  }
  return true;
}

// A manifold disc: every edge between two nodes in at most two triangles, a boundary
// edge in one (a diagonal may join two nodes that are already neighbours elsewhere).
bool is_manifold(const std::vector<NodeId>& g, const std::vector<Tri>& tris) {
  std::map<std::pair<NodeId, NodeId>, int> use;
  for (const auto& t : tris)
    for (int e = 0; e < 3; ++e) {
      const NodeId a = g[t[e]], b = g[t[(e + 1) % 3]];
      ++use[{std::min(a, b), std::max(a, b)}];
    }
  for (const auto& [e, c] : use)
    if (c > 2) return false;
  return true;
}

// Where the two sides of a strip cross in space (a circle and a B-spline copy of it,
// crossing several times), every triangulation of the polygon folds through itself: two
// triangles without a common node must not meet. The report's own pair test (exact;
// pairs sharing a node count when they overlap beyond it), on the face's triangles
// numbered by their global nodes.
bool intersects_itself(const std::vector<NodeId>& g, const std::vector<geom::Vec3>& p,
                       const std::vector<Tri>& tris) {
  SurfaceMesh sm;
  std::map<NodeId, NodeId> local;
  for (std::size_t i = 0; i < g.size(); ++i)
    if (local.emplace(g[i], static_cast<NodeId>(sm.points.size())).second)
      sm.points.push_back(p[i]);
  for (const auto& t : tris)
    sm.triangles.push_back({local[g[t[0]]], local[g[t[1]]], local[g[t[2]]]});
  for (std::size_t x = 0; x < tris.size(); ++x)
    for (std::size_t y = x + 1; y < tris.size(); ++y)
      if (triangles_intersect(sm, static_cast<TriId>(x), static_cast<TriId>(y))) return true;
  return false;
}

// Orientation: by area-weighted agreement with the surface normal at the centroids.
void orient_with_surface(const geom::Surface& s, const std::vector<geom::Vec3>& p,
                         const std::vector<geom::Vec2>& uv, std::vector<Tri>& tris) {
  double agree = 0;
  for (const auto& t : tris) {
    const geom::Vec3 nt = glm::cross(p[t[1]] - p[t[0]], p[t[2]] - p[t[0]]);
    const geom::Vec2 c = (uv[t[0]] + uv[t[1]] + uv[t[2]]) / 3.0;
    const geom::SurfacePoint sp = s.eval(c.x, c.y);
    agree += glm::dot(nt, sp.normal());
  }
  if (agree < 0)
    for (auto& t : tris) std::swap(t[1], t[2]);
}

// The largest distance to the surface of the triangles' centroids and edge midpoints.
double worst_deviation(const geom::Face& f, const geom::Surface& s,
                       const std::vector<geom::Vec3>& p, const std::vector<geom::Vec2>& uv,
                       const std::vector<Tri>& tris) {
  double worst = 0;
  for (const auto& t : tris) {
    const geom::Vec3 x[4] = {(p[t[0]] + p[t[1]] + p[t[2]]) / 3.0, 0.5 * (p[t[0]] + p[t[1]]),
                             0.5 * (p[t[1]] + p[t[2]]), 0.5 * (p[t[2]] + p[t[0]])};
    const geom::Vec2 u[4] = {(uv[t[0]] + uv[t[1]] + uv[t[2]]) / 3.0, 0.5 * (uv[t[0]] + uv[t[1]]),
                             0.5 * (uv[t[1]] + uv[t[2]]), 0.5 * (uv[t[2]] + uv[t[0]])};
    const double scale = std::max({glm::length(p[t[1]] - p[t[0]]), glm::length(p[t[2]] - p[t[1]]),
                                   glm::length(p[t[0]] - p[t[2]])});
    for (int k = 0; k < 4; ++k) {
      const Projection pr = project_to_surface(s, x[k], u[k], f.uv_box, scale);
      if (pr.converged) worst = std::max(worst, pr.distance);
    }
  }
  return worst;
}

}  // namespace

bool triangulate_from_boundary(FaceMesh& out, const geom::Face& f, const geom::Surface& s,
                               const std::vector<NodeId>& gid_in,
                               const std::vector<geom::Vec2>& uv_in,
                               const std::vector<geom::Vec3>& node_points, double chordal_tol,
                               std::string* why) {
  std::vector<NodeId> g;
  std::vector<geom::Vec2> uv;
  boundary_polygon(gid_in, uv_in, g, uv);
  const std::size_t n = g.size();
  if (n < 3 || n > kMaxBoundaryTriangulation) {
    *why = std::to_string(n) + " boundary nodes";
    return false;
  }
  std::vector<geom::Vec3> p(n);
  for (std::size_t i = 0; i < n; ++i) p[i] = node_points[static_cast<std::size_t>(g[i])];
  std::vector<Tri> tris;
  if (!min_perimeter_triangulation(g, p, tris)) {
    *why = "no triangulation without a repeated node";
    return false;
  }
  if (!is_manifold(g, tris)) {
    *why = "the triangulation is not a manifold";
    return false;
  }
  if (intersects_itself(g, p, tris)) {
    *why = "its boundary triangulation intersects itself (the sides of the strip cross in space)";
    return false;
  }
  orient_with_surface(s, p, uv, tris);
  if (chordal_tol > 0) {
    const double worst = worst_deviation(f, s, p, uv, tris);
    if (worst > chordal_tol) {
      std::ostringstream o;
      o << "its boundary triangulation deviates " << worst << " from the surface (tolerance "
        << chordal_tol << ")";
      *why = o.str();
      return false;
    }
  }
  out = {};
  for (auto t : tris) {
    if (f.reversed) std::swap(t[1], t[2]);
    out.tris.push_back({g[t[0]], g[t[1]], g[t[2]]});
    out.tri_uv.push_back({uv[t[0]], uv[t[1]], uv[t[2]]});
  }
  out.stats.boundary_nodes = static_cast<int>(n);
  out.stats.triangles = static_cast<int>(out.tris.size());
  out.from_boundary = true;
  return true;
}

}  // namespace uvmesh::surface::detail
