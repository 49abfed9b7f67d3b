// Stage 4 of mesher2d: the enforced segments split at unit metric length ("curves
// first", §7.3.5 preliminary requirements).
#include <algorithm>
#include <cmath>

#include "edge_sampling.h"
#include "mesh_state.h"

namespace uvmesh::m2d::detail {

// Curves first: every segment is split at unit length in the metric (eq. 7.10),
// computed on a piecewise subdivision fine enough (pieces of metric length <= 1/4) to
// follow a varying field.
bool split_boundary(MeshState& ms) {
  EdgeSampler es(ms);
  std::vector<std::int32_t> work;
  const std::size_t nseg = ms.segs.size();
  std::vector<VertId> chain;
  for (std::size_t sid = 0; sid < nseg; ++sid) {
    const SegRec s = ms.segs[sid];
    if (!s.alive) continue;
    const Vec2 a = ms.tri.point(s.a), b = ms.tri.point(s.b);
    const double L = es.sample(a, b, ms.metric(a.x, a.y), ms.metric(b.x, b.y));
    const int n = std::max(1, static_cast<int>(std::lround(L)));
    if (n == 1) continue;
    ms.tri.unconstrain(s.a, s.b);
    ms.segs[sid].alive = false;
    chain.assign(1, s.a);
    InsertParams prm;
    bool ok = true;
    es.split_params(n, [&](double t) {
      if (!ok) return;
      const Vec2 p{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)};
      // A split point is rounded off the segment's line; next to a nearly collinear
      // constrained neighbour it could land on the far side. Such a point is skipped
      // (the piece gets longer) rather than making a crossing.
      if (!ms.tri.segment_clear(chain.back(), p) || !ms.tri.segment_clear(s.b, p)) {
        ++ms.res.stats.boundary_points_skipped;
        return;
      }
      const auto r = ms.tri.insert_point(p, ms.tri.vertex_tri(chain.back()), prm);
      if (r.status == InsertStatus::Inserted) {
        ms.fixed.push_back(1);
        ms.vmark.push_back(s.marker);
        chain.push_back(r.v);
      } else if (r.status == InsertStatus::Duplicate) {
        if (r.v != chain.back()) chain.push_back(r.v);
      } else {
        ok = false;  // e.g. lands on another constrained edge: keep the segment whole
      }
    });
    chain.push_back(s.b);
    // Enforce the pieces now, so that the next segments' split points see them.
    work.clear();
    for (std::size_t k = chain.size() - 1; k-- > 0;)
      if (chain[k] != chain[k + 1])
        work.push_back(ms.add_seg({chain[k], chain[k + 1], s.marker, s.input}));
    if (!enforce_segments(ms, work, /*split_crossings=*/true)) return false;
  }
  return true;
}

}  // namespace uvmesh::m2d::detail
