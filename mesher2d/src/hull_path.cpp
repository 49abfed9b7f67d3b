// The convex-hull fast path of mesher2d: no segments, holes, regions or refinement.
#include <algorithm>

#include "huge_pages.h"
#include "mesh_state.h"

namespace uvmesh::m2d::detail {

// No segments, holes, regions or refinement: the result is the Delaunay triangulation
// of the convex hull of the distinct input points, which HullDelaunay builds directly
// (ghost triangles instead of box, hull enforcement and coloring). Same exact
// predicates, same Result: vertices in input order, hull edges as boundary edges
// (marker 1, split at collinear points), duplicates merged and reported.
bool hull_fast_path(const MeshState& ms) {
  return ms.in.segments.empty() && ms.in.holes.empty() && ms.in.regions.empty() &&
         ms.in.points.size() <= detail::HullDelaunay::kMaxPoints &&
         ms.opt.triangulate_hull_without_segments && !ms.opt.domain_from_orientation &&
         (!ms.opt.refine || (ms.size.kind == SizeSpec::Kind::Uniform && !(ms.size.h > 0)));
}

void output_hull(MeshState& ms, HullDelaunay& dh) {
  Mesh& M = ms.res.mesh;
  const std::size_t n = ms.in.points.size();
  const std::size_t nv = n;  // vertices 0..n-1; dh.ghost_id == n
  // Output vertices in the kernel's insertion order (spatially coherent: BRIO rounds
  // in Hilbert order), so that every later pass over the mesh, ours or the caller's,
  // reads its vertices nearly in sequence; input_vertex maps input points to them.
  // An exact duplicate's vertex is left out; its input point maps to the equal vertex.
  std::vector<VertId> out;
  const bool compact = !dh.dups.empty();
  std::vector<char> dead;
  if (compact) {
    dead.assign(nv, 0);
    for (const auto& d : dh.dups) dead[d.first] = 1;
    out.assign(nv, kNone);
  }
  const std::size_t nout = nv - dh.dups.size();
  detail::assign_huge(M.vertex_markers, nout, 0);
  // Without duplicates input point i is vertex vert_of[i] as it is (the kernel's
  // inverse of its insertion order, made while it gathered the points).
  if (compact)
    M.input_vertex.resize(n);
  else
    M.input_vertex = std::move(dh.vert_of);
  // The marker of a merged vertex is that of its first input point (as in
  // merge_duplicates): msrc = the smallest input index among equal points.
  std::vector<std::int32_t> msrc;
  if (compact) {
    msrc.assign(dh.src.begin(), dh.src.end());
    for (const auto& [d, k] : dh.dups) msrc[k] = std::min(msrc[k], dh.src[d]);
    M.vertices.resize(nout);
  }
  VertId w = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    if (compact) {
      if (dead[v]) continue;
      out[v] = w;
      M.vertices[w] = dh.pts[v];
    }
    if (compact) M.input_vertex[dh.src[v]] = w;
    if (!ms.in.point_markers.empty())
      M.vertex_markers[w] = ms.in.point_markers[compact ? msrc[v] : dh.src[v]];
    ++w;
  }
  if (compact) {
    std::int64_t dup_first = -1, dup_of = -1;
    for (const auto& [d, k] : dh.dups) {
      M.input_vertex[dh.src[d]] = out[k];
      for (const std::int32_t i : {dh.src[d], dh.src[k]})
        if (i != msrc[k] && (dup_first < 0 || i < dup_first)) dup_first = i, dup_of = msrc[k];
    }
    const auto dup = static_cast<std::int64_t>(dh.dups.size());
    ms.res.stats.duplicates_merged = dup;
    ms.res.status.warnings.push_back(
        std::to_string(dup) + " duplicate point(s) merged (first: point " +
        std::to_string(dup_first) + " duplicates point " + std::to_string(dup_of) + ")");
  } else {
    // Every vertex is output as it is: the kernel's coordinate array, without G.
    M.vertices = std::move(dh.pts);
    M.vertices.pop_back();
  }
  // Triangles and hull edges in one pass; a ghost (a, b, G) stands for the hull edge
  // b -> a of the triangle inside.
  const std::size_t nt = dh.tris.size();
  detail::reserve_huge(M.triangles, nt);
  auto emit = [&](auto id) {
    for (std::size_t t = 0; t < nt; ++t) {
      const auto& r = dh.tris[t];
      if (dh.ghost(r)) [[unlikely]] {
        const int g = dh.ghost_corner(r);
        M.boundary_edges.push_back({id(r.v[detail::prev3(g)]), id(r.v[detail::next3(g)]), 1});
        continue;
      }
      M.triangles.push_back({id(r.v[0]), id(r.v[1]), id(r.v[2])});
    }
  };
  if (compact)
    emit([&](VertId v) { return out[v]; });
  else
    emit([](VertId v) { return v; });
  const std::size_t k = M.triangles.size();
  detail::assign_huge(M.triangle_region, k, 0);
  detail::assign_huge(M.triangle_attribute, k, 0.0);
}

}  // namespace uvmesh::m2d::detail
