// The last stage of mesher2d: the triangles of the domain written to the result.
#include <algorithm>

#include "huge_pages.h"
#include "mesh_state.h"

namespace uvmesh::m2d::detail {

void output_mesh(MeshState& ms, std::vector<std::uint64_t>& edges) {
  Mesh& M = ms.res.mesh;
  const VertId nv = ms.tri.num_verts();
  std::vector<VertId> newid(nv, kNone);
  const std::size_t n = ms.in.points.size();
  // Input points keep their relative order first, then every created vertex.
  std::vector<char> used(nv, 0);
  const TriId nt = ms.tri.num_tris();
  std::size_t ndom = 0;
  for (TriId t = 0; t < nt; ++t)
    if (ms.in_domain(t)) {
      ++ndom;
      for (int i = 0; i < 3; ++i) used[ms.tri.vertex(t, i)] = 1;
    }
  // Sized once: a million-triangle mesh otherwise grows every array by doubling.
  detail::reserve_huge(M.vertices, M.vertices.size() + static_cast<std::size_t>(nv));
  detail::reserve_huge(M.vertex_markers, M.vertex_markers.size() + static_cast<std::size_t>(nv));
  const bool metrics = ms.vm.size() == ms.tri.points().size();
  if (metrics) {
    M.vertex_metric.reserve(M.vertex_metric.size() + static_cast<std::size_t>(nv));
    M.boundary_scale.reserve(M.boundary_scale.size() + static_cast<std::size_t>(nv));
  }
  detail::reserve_huge(M.triangles, M.triangles.size() + ndom);
  detail::reserve_huge(M.triangle_region, M.triangle_region.size() + ndom);
  detail::reserve_huge(M.triangle_attribute, M.triangle_attribute.size() + ndom);
  if (ms.opt.measure) edges.reserve(edges.size() + 3 * ndom / 2 + static_cast<std::size_t>(nv));
  auto take = [&](VertId v) {
    if (v == kNone || !used[v] || newid[v] != kNone) return;
    newid[v] = static_cast<VertId>(M.vertices.size());
    M.vertices.push_back(ms.tri.point(v));
    M.vertex_markers.push_back(ms.vmark[v]);
    if (metrics) {
      M.vertex_metric.push_back(ms.vm[v]);
      // The factor the metric was scaled by: 1 / rs^2 where the boundary made it finer
      // (detail::scaled, as field_points.cpp and the optimizer apply it), else 1.
      M.boundary_scale.push_back(ms.rs[v] < 1 ? 1.0 / (ms.rs[v] * ms.rs[v]) : 1.0);
    }
  };
  for (std::size_t i = 0; i < n; ++i) take(ms.vid[i]);
  for (VertId v = 4; v < nv; ++v) take(v);
  M.input_vertex.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    M.input_vertex[i] = ms.vid[i] == kNone ? kNone : newid[ms.vid[i]];
  std::vector<std::int32_t> region_id(ms.removed.size(), -1);
  std::int32_t nreg = 0;
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    const std::int32_t c = ms.tri.tag(t);
    if (region_id[c] < 0) region_id[c] = nreg++;
    M.triangles.push_back(
        {newid[ms.tri.vertex(t, 0)], newid[ms.tri.vertex(t, 1)], newid[ms.tri.vertex(t, 2)]});
    M.triangle_region.push_back(region_id[c]);
    M.triangle_attribute.push_back(ms.attr[c]);
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i;
      if (ms.opt.measure) {
        // Every undirected edge once, for the measures.
        const std::int32_t g = ms.tri.twin(h);
        if (g == kNone || !ms.in_domain(g / 3) || g > h) {
          const auto a = static_cast<std::uint32_t>(newid[ms.tri.vertex(t, detail::next3(i))]);
          const auto b = static_cast<std::uint32_t>(newid[ms.tri.vertex(t, detail::prev3(i))]);
          edges.push_back(static_cast<std::uint64_t>(std::min(a, b)) << 32 | std::max(a, b));
        }
      }
      const std::int32_t s = ms.tri.constraint(h);
      if (s == kNone) continue;
      const std::int32_t g = ms.tri.twin(h);
      if (g != kNone && ms.in_domain(g / 3) && g / 3 < t) continue;  // once per edge
      M.boundary_edges.push_back({newid[ms.tri.vertex(t, detail::next3(i))],
                                  newid[ms.tri.vertex(t, detail::prev3(i))], ms.segs[s].marker});
    }
  }
}

}  // namespace uvmesh::m2d::detail
