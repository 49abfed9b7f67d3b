// The (u,v) PSLG of one face (reference chapter §7.6.2): the edge nodes through each
// use's pcurve at the same curve parameters (never by projection), in loop order.
#include <algorithm>
#include <cmath>
#include <limits>

#include "face_stage.h"

namespace uvmesh::surface::detail {

namespace {

const double kNan = std::numeric_limits<double>::quiet_NaN();

// Parameter of a use's pcurve for the curve parameter t: the same when the use's range is
// the edge's (OCC's SameParameter), otherwise the affine map between the two ranges.
double pcurve_param(const geom::Edge& e, const geom::EdgeUse& u, double t) {
  if (u.range.lo == e.range.lo && u.range.hi == e.range.hi) return t;
  const double L = e.range.length();
  const double s = L != 0 ? (t - e.range.lo) / L : 0.0;
  return u.range.lo + s * u.range.length();
}

// A degenerate edge (pole, cone apex) is a run of (u,v) points mapping to one 3D vertex.
// How many: as many as the first ring of triangles around the pole will have, estimated
// as the metric length of the pole side moved inward until sigma moves by about one
// local size (on the side itself the induced metric is singular and capped).
int pole_segments(const geom::EdgeUse& use, const geom::Surface& s,
                  const param::FaceSizeField& field, const geom::Box2& box) {
  const geom::Vec2 a = use.pcurve->point(use.range.lo), b = use.pcurve->point(use.range.hi);
  const geom::Vec2 mid = 0.5 * (a + b);
  const geom::Vec2 centre{box.u.mid(), box.v.mid()};
  const geom::Vec3 pole = s.point(mid.x, mid.y);
  const param::Metric3 m3 = field.metric3(mid.x, mid.y);
  const auto sz = m3.sizes();
  const double h = *std::min_element(sz.begin(), sz.end());
  double frac = 1e-3;
  geom::Vec2 shift{0.0};
  for (; frac < 0.5; frac *= 2) {
    shift = frac * (centre - mid);
    if (glm::length(s.point(mid.x + shift.x, mid.y + shift.y) - pole) >= 0.5 * h) break;
  }
  double L = 0;
  const int n = 32;
  geom::Vec2 prev = a + shift;
  for (int k = 1; k <= n; ++k) {
    const geom::Vec2 q = use.pcurve->point(use.range.at(double(k) / n)) + shift;
    const param::Metric2 mm = field.metric_uv(0.5 * (prev.x + q.x), 0.5 * (prev.y + q.y));
    L += mm.length(q - prev);
    prev = q;
  }
  return std::clamp(static_cast<int>(std::lround(L)), 1, 512);
}

// The points of one (not embedded) use: the pole's run, or the edge's nodes but the last
// in the use's direction (the next use starts there).
void add_use_points(const FaceInput& job, const geom::EdgeUse& use, FacePslg& pslg) {
  const geom::Edge& e = job.m.edges[static_cast<std::size_t>(use.edge)];
  m2d::Pslg& in = pslg.in;
  const std::size_t first = in.points.size();
  if (e.degenerate) {
    const int k = pole_segments(use, job.s, job.field, job.f.uv_box);
    const NodeId node = job.edges[static_cast<std::size_t>(use.edge)].node.front();
    for (int i = 0; i < k; ++i) {
      const double w = use.reversed ? 1.0 - double(i) / k : double(i) / k;
      const geom::Vec2 p = use.pcurve->point(use.range.at(w));
      in.points.push_back({p.x, p.y});
      pslg.gid.push_back(node);
      pslg.piece.push_back({kNan, kNan});
    }
  } else {
    const EdgeNodes& en = job.edges[static_cast<std::size_t>(use.edge)];
    const std::size_t n = en.t.size();
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const std::size_t k = use.reversed ? n - 1 - i : i;
      const geom::Vec2 p = use.pcurve->point(pcurve_param(e, use, en.t[k]));
      in.points.push_back({p.x, p.y});
      pslg.gid.push_back(en.node[k]);
      pslg.piece.push_back({en.t[k], en.t[use.reversed ? k - 1 : k + 1]});
    }
  }
  for (std::size_t i = first; i < in.points.size(); ++i) pslg.pedge.push_back(use.edge);
}

// The closed chain of segments over the points [start, end) of one loop.
// The segments of a CAD edge shorter than the proximity floor (seg_floor) are the
// artefact's, not the user's sizes: the edges beside them are not graded below the floor
// (proximity_floor()). Their length is no size to grade the interior from either: it
// refined the interior around them down to their length, against boundary segments at
// the floor, and fans of needles joined the two. With a feature size the test is on the
// CAD edge's length, so that segments refined below the floor on purpose (a sheet's free
// edges, a local edge size) still size the interior; with keep_topology it is on the
// segment's length, as before feature sizes.
void close_loop(const FaceInput& job, m2d::VertId start, m2d::VertId end, double seg_floor,
                FacePslg& pslg) {
  const bool by_edge = feature_size(job.opt, job.m.bbox) > 0;
  for (m2d::VertId i = start; i < end; ++i) {
    const m2d::VertId j = i + 1 < end ? i + 1 : start;
    // Marker edge id + 1; negative on a pole's collapsed side, which must not impose
    // its (u,v) length as a size (Options::boundary_gradation), and on a segment
    // shorter than the proximity floor (seg_floor).
    const geom::Id ei = pslg.pedge[static_cast<std::size_t>(i)];
    const geom::Edge& edge = job.m.edges[static_cast<std::size_t>(ei)];
    const bool pole = edge.degenerate;
    const bool sub_floor =
        by_edge
            ? edge.length < seg_floor
            : glm::length(
                  job.node_points[static_cast<std::size_t>(pslg.gid[static_cast<std::size_t>(j)])] -
                  job.node_points[static_cast<std::size_t>(
                      pslg.gid[static_cast<std::size_t>(i)])]) < seg_floor;
    pslg.in.segments.push_back(
        {i, j, pole || sub_floor ? -(static_cast<int>(ei) + 1) : static_cast<int>(ei) + 1});
    pslg.sedge.push_back(ei);
    pslg.spiece.push_back(pslg.piece[static_cast<std::size_t>(i)]);
  }
}

// Embedded edges: every node, ends included, and a segment per piece (no closing
// segment). Both sides of such a segment lie in the face, so its two half-edges cancel
// in mesher2d's orientation vote; an end on the boundary is the same node as the
// boundary's occurrence and merges with it (snap_node_copies).
void add_embedded(const FaceInput& job, FacePslg& pslg) {
  m2d::Pslg& in = pslg.in;
  for (const geom::EdgeUse* use : pslg.embedded) {
    const geom::Edge& e = job.m.edges[static_cast<std::size_t>(use->edge)];
    if (!use->pcurve || e.degenerate) continue;
    const EdgeNodes& en = job.edges[static_cast<std::size_t>(use->edge)];
    const auto first = static_cast<m2d::VertId>(in.points.size());
    for (std::size_t k = 0; k < en.t.size(); ++k) {
      const geom::Vec2 p = use->pcurve->point(pcurve_param(e, *use, en.t[k]));
      in.points.push_back({p.x, p.y});
      pslg.gid.push_back(en.node[k]);
      pslg.pedge.push_back(use->edge);
      pslg.piece.push_back({en.t[k], k + 1 < en.t.size() ? en.t[k + 1] : kNan});
    }
    for (m2d::VertId i = first; i + 1 < static_cast<m2d::VertId>(in.points.size()); ++i)
      in.segments.push_back({i, i + 1, static_cast<int>(use->edge) + 1}),
          pslg.sedge.push_back(use->edge),
          pslg.spiece.push_back(pslg.piece[static_cast<std::size_t>(i)]);
  }
}

// One closed loop (the boundary triangulation's case): nothing embedded, every point on
// a closing chain, and a single loop with a use that is not embedded.
bool is_one_loop(const geom::Face& f, const FacePslg& pslg) {
  return pslg.embedded.empty() && pslg.in.segments.size() == pslg.in.points.size() &&
         std::count_if(f.loops.begin(), f.loops.end(), [](const geom::Loop& l) {
           return std::any_of(l.uses.begin(), l.uses.end(),
                              [](const geom::EdgeUse& u) { return !u.internal; });
         }) == 1;
}

}  // namespace

// One node, one (u,v) point per side: the pcurves of two edges meeting at a vertex end
// a few ulps apart, and a loop touching the seam at a vertex would then put a point a
// hair off the seam's segment. Occurrences of a node closer than a millionth of the
// (u,v) box are snapped together (mesher2d merges exact duplicates); the copies of a
// node on the two sides of a seam are a period apart and stay distinct.
void snap_node_copies(const geom::Box2& box, FacePslg& pslg) {
  m2d::Pslg& in = pslg.in;
  const std::vector<NodeId>& gid = pslg.gid;
  const double ext = std::max(box.u.length(), box.v.length());
  const double tol = 1e-6 * (ext > 0 ? ext : 1.0);
  std::vector<std::size_t> order(in.points.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::stable_sort(order.begin(), order.end(),
                   [&](std::size_t a, std::size_t b) { return gid[a] < gid[b]; });
  for (std::size_t k = 0; k < order.size();) {
    std::size_t e = k;
    while (e < order.size() && gid[order[e]] == gid[order[k]]) ++e;
    for (std::size_t i = k + 1; i < e; ++i)
      for (std::size_t j = k; j < i; ++j) {
        auto& p = in.points[order[i]];
        const auto& q = in.points[order[j]];
        if (std::abs(p.x - q.x) <= tol && std::abs(p.y - q.y) <= tol) {
          p = q;
          break;
        }
      }
    k = e;
  }
}

bool face_has_pole(const geom::Model& m, const geom::Face& f) {
  bool has_pole = false;
  for (const geom::Loop& loop : f.loops)
    for (const geom::EdgeUse& use : loop.uses)
      has_pole =
          has_pole || (use.edge >= 0 && m.edges[static_cast<std::size_t>(use.edge)].degenerate);
  return has_pole;
}

bool build_face_pslg(const FaceInput& job, FacePslg& pslg, std::string& error) {
  const double D = job.m.bbox.diagonal();
  const double seg_floor = proximity_floor(job.opt.size, D, feature_size(job.opt, job.m.bbox));
  for (const geom::Loop& loop : job.f.loops) {
    const auto start = static_cast<m2d::VertId>(pslg.in.points.size());
    const std::size_t span_lo = pslg.spans.size();
    for (const geom::EdgeUse& use : loop.uses) {
      if (use.internal) {
        pslg.embedded.push_back(&use);
        continue;
      }
      if (!use.pcurve) {
        error = "edge " + std::to_string(use.edge) + " has no (u,v) curve on this face";
        return false;
      }
      const std::size_t first = pslg.in.points.size();
      add_use_points(job, use, pslg);
      pslg.spans.push_back({&use, first, pslg.in.points.size()});
    }
    const auto end = static_cast<m2d::VertId>(pslg.in.points.size());
    if (end == start) continue;  // a wire holding only embedded edges
    pslg.loop_spans.push_back({span_lo, pslg.spans.size()});
    close_loop(job, start, end, seg_floor, pslg);
  }
  add_embedded(job, pslg);
  snap_node_copies(job.f.uv_box, pslg);
  pslg.one_loop = is_one_loop(job.f, pslg);
  return true;
}

bool check_face_pslg(const FacePslg& pslg, std::string& error) {
  if (pslg.in.segments.size() < 3) {
    error = "the face's loops have fewer than 3 boundary nodes in (u,v)";
    return false;
  }
  for (const auto& p : pslg.in.points)
    if (!std::isfinite(p.x) || !std::isfinite(p.y)) {
      error = "a (u,v) curve gives a non-finite point";
      return false;
    }
  return true;
}

}  // namespace uvmesh::surface::detail
