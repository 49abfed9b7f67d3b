// 3D checks of a SurfaceMesh, part 1: topology and close points (see check3d.h for the
// definitions; the other parts: check3d_intersections.cpp, check3d_quality.cpp,
// check3d_chordal.cpp).
#include "uvmesh/surface/check3d.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>

#include "check3d_internal.h"

namespace uvmesh::surface {

using geom::Vec2;
using geom::Vec3;
using namespace check3d_impl;

// =======================================================================================
// 1. Topology
// =======================================================================================

ClosePointsReport find_close_points(const std::vector<Vec3>& points, double rel_tol, int max_list) {
  ClosePointsReport r;
  const std::size_t n = points.size();
  if (n < 2) return r;
  geom::Box3 box;
  for (const Vec3& p : points) box.add(p);
  const double diag = box.diagonal();
  const double tol = std::max(rel_tol, 0.0) * diag;
  r.tolerance = tol;
  // Cells of size h > tol, so a close pair lies in the same or in neighbouring (x, y)
  // cells. The floor on h keeps cell indices below 1e12, where the rounding of
  // (x - lo) / h (about 1e-4 of a cell) stays inside the 0.1% margin of h over tol.
  double h = 1.001 * std::max({tol, 1e-12 * diag, std::numeric_limits<double>::min()});
  if (!(h > 0) || !std::isfinite(h)) h = 1.0;

  struct Rec {
    std::int64_t cx, cy;
    double z;
    NodeId id;
    bool operator<(const Rec& o) const {
      if (cx != o.cx) return cx < o.cx;
      if (cy != o.cy) return cy < o.cy;
      if (z != o.z) return z < o.z;
      return id < o.id;
    }
  };
  std::vector<Rec> rec(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Vec3& p = points[i];
    rec[i] = {static_cast<std::int64_t>(std::floor((p.x - box.lo.x) / h)),
              static_cast<std::int64_t>(std::floor((p.y - box.lo.y) / h)), p.z,
              static_cast<NodeId>(i)};
  });
  tbb::parallel_sort(rec.begin(), rec.end());

  struct Group {
    std::int64_t cx, cy;
    std::size_t begin, end;
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && rec[j].cx == rec[i].cx && rec[j].cy == rec[i].cy) ++j;
    groups.push_back({rec[i].cx, rec[i].cy, i, j});
    i = j;
  }
  auto find_group = [&](std::int64_t cx, std::int64_t cy) -> const Group* {
    auto it = std::lower_bound(groups.begin(), groups.end(), std::make_pair(cx, cy),
                               [](const Group& g, const std::pair<std::int64_t, std::int64_t>& k) {
                                 return g.cx != k.first ? g.cx < k.first : g.cy < k.second;
                               });
    return (it != groups.end() && it->cx == cx && it->cy == cy) ? &*it : nullptr;
  };

  SmallestK<std::pair<NodeId, NodeId>> smallest(static_cast<std::size_t>(std::max(max_list, 0)));
  double dmin = std::numeric_limits<double>::infinity();
  auto consider = [&](const Rec& p, const Rec& q) {
    const double d = glm::length(points[p.id] - points[q.id]);
    if (!(d < tol || d == 0)) return;
    ++r.pairs;
    dmin = std::min(dmin, d);
    const NodeId a = std::min(p.id, q.id), b = std::max(p.id, q.id);
    smallest.push({a, b});
  };
  for (const Group& g : groups) {
    // Within the cell column: a sweep along z.
    for (std::size_t i = g.begin; i < g.end; ++i)
      for (std::size_t j = i + 1; j < g.end && rec[j].z - rec[i].z <= tol; ++j)
        consider(rec[i], rec[j]);
    // The four forward neighbour columns (each unordered pair of neighbours once).
    const std::int64_t nb[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    for (const auto& o : nb) {
      const Group* q = find_group(g.cx + o[0], g.cy + o[1]);
      if (!q) continue;
      std::size_t s = q->begin;
      for (std::size_t i = g.begin; i < g.end; ++i) {
        while (s < q->end && rec[s].z < rec[i].z - tol) ++s;
        for (std::size_t j = s; j < q->end && rec[j].z <= rec[i].z + tol; ++j)
          consider(rec[i], rec[j]);
      }
    }
  }
  for (const auto& [a, b] : smallest.sorted())
    r.list.push_back({a, b, glm::length(points[a] - points[b])});
  r.min_distance = r.pairs ? dmin : 0.0;
  return r;
}

TopologyReport check_topology(const SurfaceMesh& m, const TopologyOptions& opt) {
  TopologyReport r;
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  const std::size_t cap = static_cast<std::size_t>(std::max(opt.max_list, 0));
  r.points = np;
  r.triangles = nt;

  // Per-triangle state; zero area decided exactly (all three projected areas are zero).
  std::vector<std::int8_t> state(nt), zero(nt, 0);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    state[t] = tri_state(m, t);
    if (state[t] == kValid) zero[t] = pred3::projection_axis(corners(m, t)) < 0;
  });
  for (std::size_t t = 0; t < nt; ++t) {
    const bool bad = state[t] != kValid || zero[t];
    r.bad_index_triangles += state[t] == kBadIndex;
    r.repeated_index_triangles += state[t] == kRepeated;
    r.zero_area_triangles += zero[t] != 0;
    if (bad && r.degenerate_list.size() < cap) r.degenerate_list.push_back(static_cast<TriId>(t));
  }
  r.degenerate_triangles =
      r.bad_index_triangles + r.repeated_index_triangles + r.zero_area_triangles;

  // Directed edges of the valid triangles, sorted by (undirected edge, triangle).
  struct EdgeRec {
    NodeId lo, hi;
    TriId t;
    bool forward;  // traversed lo -> hi
    bool operator<(const EdgeRec& o) const {
      if (lo != o.lo) return lo < o.lo;
      if (hi != o.hi) return hi < o.hi;
      return t < o.t;
    }
  };
  std::vector<EdgeRec> er;
  er.reserve(3 * nt);
  std::vector<char> used(np, 0);
  std::size_t valid_tris = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (state[t] == kBadIndex) continue;
    const auto& tr = m.triangles[t];
    for (NodeId i : tr) used[i] = 1;
    if (state[t] != kValid) continue;
    ++valid_tris;
    for (int k = 0; k < 3; ++k) {
      const NodeId a = tr[k], b = tr[(k + 1) % 3];
      er.push_back({std::min(a, b), std::max(a, b), static_cast<TriId>(t), a < b});
    }
  }
  tbb::parallel_sort(er.begin(), er.end());
  auto issue = [&](std::size_t i, std::size_t j) {
    EdgeIssue e;
    e.a = er[i].lo;
    e.b = er[i].hi;
    for (std::size_t k = i; k < j; ++k) {
      e.triangles.push_back(er[k].t);
      e.faces.push_back(face_of(m, er[k].t));
    }
    return e;
  };
  for (std::size_t i = 0; i < er.size();) {
    std::size_t j = i + 1;
    while (j < er.size() && er[j].lo == er[i].lo && er[j].hi == er[i].hi) ++j;
    ++r.edges;
    const std::size_t c = j - i;
    if (c == 1) {
      if (r.free_list.size() < cap) r.free_list.push_back(issue(i, j));
      ++r.free_edges;
    } else if (c >= 3) {
      if (r.non_manifold_list.size() < cap) r.non_manifold_list.push_back(issue(i, j));
      ++r.non_manifold_edges;
    } else if (er[i].forward == er[i + 1].forward) {
      if (r.inconsistent_list.size() < cap) r.inconsistent_list.push_back(issue(i, j));
      ++r.inconsistent_edges;
    }
    i = j;
  }

  std::size_t referenced = 0;
  for (std::size_t i = 0; i < np; ++i) {
    if (used[i]) {
      ++referenced;
    } else {
      ++r.unreferenced_points;
      if (r.unreferenced_list.size() < cap) r.unreferenced_list.push_back(static_cast<NodeId>(i));
    }
  }
  r.euler_characteristic = static_cast<long long>(referenced) - static_cast<long long>(r.edges) +
                           static_cast<long long>(valid_tris);
  r.close_points = find_close_points(m.points, opt.close_rel_tol, opt.max_list);
  return r;
}

SolidSurface solid_surface(const SurfaceMesh& m, const geom::Model& model, geom::Id solid) {
  SolidSurface st;
  st.solid = solid;
  st.closed = true;
  std::vector<char> in(model.faces.size(), 0);
  for (geom::Id sh : model.solids[static_cast<std::size_t>(solid)].shells) {
    if (sh < 0 || static_cast<std::size_t>(sh) >= model.shells.size()) continue;
    st.closed = st.closed && model.shells[static_cast<std::size_t>(sh)].closed;
    for (geom::Id f : model.shells[static_cast<std::size_t>(sh)].faces)
      if (f >= 0 && static_cast<std::size_t>(f) < in.size()) in[static_cast<std::size_t>(f)] = 1;
  }
  for (std::size_t f = 0; f < in.size(); ++f)
    if (in[f]) st.faces.push_back(static_cast<geom::Id>(f));
  std::map<std::pair<NodeId, NodeId>, int> count;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const geom::Id f = t < m.triangle_face.size() ? m.triangle_face[t] : geom::kNone;
    if (f < 0 || static_cast<std::size_t>(f) >= in.size() || !in[static_cast<std::size_t>(f)])
      continue;
    st.triangles.push_back(static_cast<TriId>(t));
    const auto& tri = m.triangles[t];
    for (int i = 0; i < 3; ++i) {
      const NodeId a = tri[static_cast<std::size_t>(i)],
                   b = tri[static_cast<std::size_t>((i + 1) % 3)];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  }
  for (const auto& [k, c] : count) {
    if (c == 1) ++st.free_edges;
    if (c > 2) ++st.non_manifold_edges;
  }
  return st;
}

}  // namespace uvmesh::surface
