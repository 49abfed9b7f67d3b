// Stage 5 of mesher2d: domain coloring (§7.3.4). Color 0 is the component of the box
// corners (the exterior); every other connected component (bounded by constrained edges)
// gets its own color. The exterior, the components a hole seed lies in and, by option,
// those on the wrong side of their loops are removed; region seeds give attributes.
#include "mesh_state.h"

namespace uvmesh::m2d::detail {

namespace {

// Tags every live triangle with its component; returns the number of components.
std::int32_t flood_components(Triangulation& tri) {
  const TriId nt = tri.num_tris();
  tri.fill_tags(-1);
  std::vector<TriId> stack;
  std::int32_t ncomp = 0;
  auto flood = [&](TriId s, std::int32_t c) {
    tri.set_tag(s, c);
    stack.push_back(s);
    while (!stack.empty()) {
      const TriId t = stack.back();
      stack.pop_back();
      for (int i = 0; i < 3; ++i) {
        if (tri.constraint(3 * t + i) != kNone) continue;
        const std::int32_t h = tri.twin(3 * t + i);
        if (h != kNone && tri.tag(h / 3) == -1) {
          tri.set_tag(h / 3, c);
          stack.push_back(h / 3);
        }
      }
    }
  };
  flood(tri.vertex_tri(0), ncomp++);
  for (TriId t = 0; t < nt; ++t)
    if (!tri.dead(t) && tri.tag(t) == -1) flood(t, ncomp++);
  return ncomp;
}

// Options::domain_from_orientation. Vote per component: a constrained half-edge of a CCW
// triangle runs from vertex next3(i) to vertex prev3(i), so the triangle is on the left
// of its segment when that half-edge runs a -> b. A majority (not unanimity) tolerates a
// loop that touches itself at a vertex.
void remove_by_orientation(MeshState& ms, std::int32_t ncomp) {
  const TriId nt = ms.tri.num_tris();
  std::vector<std::int64_t> vote(ncomp, 0);
  for (TriId t = 0; t < nt; ++t) {
    if (ms.tri.dead(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t s = ms.tri.constraint(3 * t + i);
      if (s == kNone || ms.segs[s].input < 0) continue;
      const VertId from = ms.tri.vertex(t, next3(i));
      vote[ms.tri.tag(t)] += from == ms.segs[s].a ? 1 : -1;
    }
  }
  for (std::int32_t c = 1; c < ncomp; ++c)
    if (vote[c] <= 0) ms.removed[c] = 1;
}

// Hole seeds remove their component, region seeds give theirs an attribute; a seed outside
// the domain is a warning. Returns the last hole seed that removed a component (-1: none).
std::int32_t apply_seeds(MeshState& ms) {
  std::int32_t last_hole = -1;
  for (std::size_t i = 0; i < ms.in.holes.size(); ++i) {
    const TriId t =
        ms.tri.locate(ms.in.holes[i], ms.tri.vertex_tri(4 < ms.tri.num_verts() ? 4 : 0));
    if (t == kNone || ms.tri.tag(t) == 0) {
      ms.res.status.warnings.push_back("hole " + std::to_string(i) + " at " +
                                       fmt_pt(ms.in.holes[i]) +
                                       " lies outside the domain and was ignored");
      continue;
    }
    ms.removed[ms.tri.tag(t)] = 1;
    last_hole = static_cast<std::int32_t>(i);
  }
  for (std::size_t i = 0; i < ms.in.regions.size(); ++i) {
    const TriId t =
        ms.tri.locate(ms.in.regions[i].seed, ms.tri.vertex_tri(4 < ms.tri.num_verts() ? 4 : 0));
    if (t == kNone || ms.removed[ms.tri.tag(t)]) {
      ms.res.status.warnings.push_back("region " + std::to_string(i) + " seed " +
                                       fmt_pt(ms.in.regions[i].seed) +
                                       " lies outside the domain and was ignored");
      continue;
    }
    ms.attr[ms.tri.tag(t)] = ms.in.regions[i].attribute;
  }
  return last_hole;
}

// Nothing left: the status says why (open boundary, wrong orientation, a leaking hole).
bool fail_empty(MeshState& ms, bool had_domain, std::int32_t last_hole) {
  if (!had_domain)
    return ms.fail(StatusCode::OpenBoundary,
                   "the segments enclose no region: the boundary is open (every triangle is "
                   "connected to the outside)");
  // Removed by the orientation vote alone (no hole did it): the loops run the
  // wrong way round, or cross themselves so that no region is on their left.
  if (last_hole < 0)
    return ms.fail(StatusCode::OpenBoundary,
                   "no region lies to the left of its boundary segments (domain_from_orientation): "
                   "the loops are clockwise or cross themselves");
  return ms.fail(StatusCode::OpenBoundary,
                 "hole " + std::to_string(last_hole) + " at " + fmt_pt(ms.in.holes[last_hole]) +
                     " removes the whole domain: the boundary around it is open",
                 {last_hole});
}

}  // namespace

bool color_domain(MeshState& ms) {
  const std::int32_t ncomp = flood_components(ms.tri);
  ms.removed.assign(ncomp, 0);
  ms.removed[0] = 1;
  ms.attr.assign(ncomp, 0.0);
  const bool had_domain = ncomp > 1;
  if (ms.opt.domain_from_orientation) remove_by_orientation(ms, ncomp);
  const std::int32_t last_hole = apply_seeds(ms);
  bool any = false;
  for (std::int32_t c = 1; c < ncomp; ++c) any |= !ms.removed[c];
  return any || fail_empty(ms, had_domain, last_hole);
}

}  // namespace uvmesh::m2d::detail
