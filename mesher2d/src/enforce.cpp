// Stage 3 of mesher2d: boundary enforcement by swaps (§7.2.2).
#include <algorithm>
#include <numeric>

#include "mesh_state.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d::detail {

namespace {

// The enforcement of a stack of segment records, and what it counted.
struct Enforcer {
  MeshState& ms;
  std::int64_t overlaps_merged = 0;  // segment pieces dropped as copies of another
  bool run(std::vector<std::int32_t>& work, bool split_crossings);
  bool overlaps_enforced(const SegRec& s, std::int32_t sid) const;
};

// The convex hull as segment records (no segments given).
bool add_hull(MeshState& ms) {
  // Andrew's monotone chain with exact orientation; collinear points are left out of
  // the hull and later split the hull edges through them (enforcement).
  // The (x, y) order of the unique input points is known from the duplicate merge.
  std::vector<VertId> v;
  v.reserve(ms.xy_order.size());
  for (const std::int32_t i : ms.xy_order)
    if (ms.rep[i] == i && ms.vid[i] != kNone) v.push_back(ms.vid[i]);
  const auto& P = ms.tri.points();
  std::vector<VertId> h(2 * v.size() + 2);
  std::size_t k = 0;
  for (std::size_t i = 0; i < v.size(); ++i) {
    while (k >= 2 && pred::orient2d(&P[h[k - 2]].x, &P[h[k - 1]].x, &P[v[i]].x) <= 0) --k;
    h[k++] = v[i];
  }
  for (std::size_t i = v.size() - 1, t = k + 1; i-- > 0;) {
    while (k >= t && pred::orient2d(&P[h[k - 2]].x, &P[h[k - 1]].x, &P[v[i]].x) <= 0) --k;
    h[k++] = v[i];
  }
  if (k < 4)
    return ms.fail(StatusCode::InvalidInput,
                   "all points are collinear: there is no triangle to make");
  for (std::size_t i = 0; i + 1 < k; ++i) ms.segs.push_back({h[i], h[i + 1], 1, -1});
  return true;
}

}  // namespace

bool enforce_boundary(MeshState& ms) {
  if (ms.segs.empty() && ms.opt.triangulate_hull_without_segments) {
    if (!add_hull(ms)) return false;
  }
  std::vector<std::int32_t> work(ms.segs.size());
  std::iota(work.begin(), work.end(), 0);
  std::reverse(work.begin(), work.end());
  Enforcer e{ms};
  if (!e.run(work, false)) return false;
  if (e.overlaps_merged > 0)
    ms.res.status.warnings.push_back(std::to_string(e.overlaps_merged) +
                                     " piece(s) of overlapping collinear segments merged");
  return true;
}

bool enforce_segments(MeshState& ms, std::vector<std::int32_t>& work, bool split_crossings) {
  Enforcer e{ms};
  return e.run(work, split_crossings);
}

// Enforces the segments in work (a stack), splitting them at the vertices they pass
// through and, by option, at crossings.
bool Enforcer::run(std::vector<std::int32_t>& work, bool split_crossings) {
  std::int64_t budget = 16 * static_cast<std::int64_t>(ms.segs.size()) + 4096;
  while (!work.empty()) {
    const std::int32_t sid = work.back();
    work.pop_back();
    SegRec s = ms.segs[sid];
    if (!s.alive || s.a == s.b) continue;
    if (--budget < 0)
      return ms.fail(StatusCode::InternalError, "boundary enforcement did not converge");
    if (overlaps_enforced(s, sid)) {
      // Overlapping collinear segments, once split at each other's end points (the
      // ThroughVertex case below), give the same piece twice: it is kept once, as
      // Triangle keeps one subsegment. Two live records of one edge would each be split
      // at unit length in split_boundary, the second with points rounded off the
      // first one's chain (a constrained edge on no segment's chain).
      ms.segs[sid].alive = false;
      ++overlaps_merged;
      continue;
    }
    const auto r = ms.tri.enforce(s.a, s.b, sid);
    using ES = Triangulation::EnforceStatus;
    if (r.status == ES::Ok) continue;
    if (r.status == ES::ThroughVertex) {
      // A segment passing through a vertex is split there.
      ms.segs[sid].alive = false;
      ++ms.res.stats.segments_split_at_vertices;
      work.push_back(ms.add_seg({r.through, s.b, s.marker, s.input}));
      work.push_back(ms.add_seg({s.a, r.through, s.marker, s.input}));
      continue;
    }
    if (r.crossing_seg == kNone)
      return ms.fail(StatusCode::InternalError,
                     "boundary enforcement failed on segment " + ms.seg_name(s));
    const SegRec o = ms.segs[r.crossing_seg];
    if (!ms.opt.split_crossing_segments && !split_crossings)
      return ms.fail(StatusCode::CrossingSegments,
                     "segment " + ms.seg_name(s) + " crosses segment " + ms.seg_name(o),
                     {s.input, o.input});
    // Split both at their intersection point.
    const Vec2 pa = ms.tri.point(s.a), pb = ms.tri.point(s.b), pc = ms.tri.point(o.a),
               pd = ms.tri.point(o.b);
    // Parameters on both segments, clamped: for nearly parallel segments the line
    // intersection is ill-conditioned along the lines (not across them), so the point
    // is taken as the mean of the two clamped points, close to both segments.
    const double den = (pb.x - pa.x) * (pd.y - pc.y) - (pb.y - pa.y) * (pd.x - pc.x);
    double t = ((pc.x - pa.x) * (pd.y - pc.y) - (pc.y - pa.y) * (pd.x - pc.x)) / den;
    double u = ((pc.x - pa.x) * (pb.y - pa.y) - (pc.y - pa.y) * (pb.x - pa.x)) / den;
    t = std::isfinite(t) ? std::clamp(t, 0.0, 1.0) : 0.5;
    u = std::isfinite(u) ? std::clamp(u, 0.0, 1.0) : 0.5;
    const Vec2 x{0.5 * (pa.x + t * (pb.x - pa.x) + pc.x + u * (pd.x - pc.x)),
                 0.5 * (pa.y + t * (pb.y - pa.y) + pc.y + u * (pd.y - pc.y))};
    ms.tri.unconstrain(o.a, o.b);
    ms.segs[r.crossing_seg].alive = false;
    ms.segs[sid].alive = false;
    InsertParams prm;
    auto ir = ms.tri.insert_point(x, ms.tri.vertex_tri(s.a), prm);
    VertId xv;
    if (ir.status == InsertStatus::Inserted) {
      xv = ir.v;
      ms.fixed.push_back(1);
      ms.vmark.push_back(s.marker);
    } else if (ir.status == InsertStatus::Duplicate) {
      xv = ir.v;
    } else {
      return ms.fail(StatusCode::CrossingSegments,
                     "segment " + ms.seg_name(s) + " crosses segment " + ms.seg_name(o) +
                         " and the crossing point could not be inserted",
                     {s.input, o.input});
    }
    ++ms.res.stats.crossings_split;
    for (const SegRec& ns :
         {SegRec{o.a, xv, o.marker, o.input}, SegRec{xv, o.b, o.marker, o.input},
          SegRec{xv, s.b, s.marker, s.input}, SegRec{s.a, xv, s.marker, s.input}})
      if (ns.a != ns.b) work.push_back(ms.add_seg(ns));
  }
  return true;
}

// True when edge (s.a, s.b) is already in the triangulation, constrained by another
// live segment record with the same two ends.
bool Enforcer::overlaps_enforced(const SegRec& s, std::int32_t sid) const {
  std::int32_t h = ms.tri.find_half_edge(s.a, s.b);
  if (h == kNone) h = ms.tri.find_half_edge(s.b, s.a);
  if (h == kNone) return false;
  const std::int32_t o = ms.tri.constraint(h);
  if (o == kNone || o == sid || !ms.segs[o].alive) return false;
  const SegRec& so = ms.segs[o];
  return (so.a == s.a && so.b == s.b) || (so.a == s.b && so.b == s.a);
}

}  // namespace uvmesh::m2d::detail
