// Size caps along model edges from the other edges of the faces around them (gradation
// across a face, proximity). See BoundaryCaps in internal.h for what and why.
#include <algorithm>
#include <cmath>
#include <numbers>

#include "internal.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface::detail {

namespace {

double box_distance(const geom::Vec3& x, const geom::Vec3& lo, const geom::Vec3& hi) {
  const geom::Vec3 d = glm::max(glm::max(lo - x, x - hi), geom::Vec3(0.0));
  return glm::length(d);
}

// Closest point of segment [a,b] to x.
geom::Vec3 closest_on_segment(const geom::Vec3& x, const geom::Vec3& a, const geom::Vec3& b) {
  const geom::Vec3 ab = b - a;
  const double l2 = glm::dot(ab, ab);
  const double w = l2 > 0 ? std::clamp(glm::dot(x - a, ab) / l2, 0.0, 1.0) : 0.0;
  return a + w * ab;
}

}  // namespace

}  // namespace uvmesh::surface::detail

namespace uvmesh::surface {

double gap_tolerance(const geom::Model& m, geom::Id edge) {
  if (edge < 0 || static_cast<std::size_t>(edge) >= m.edges.size()) return 0.0;
  const geom::Edge& e = m.edges[static_cast<std::size_t>(edge)];
  double t = e.tol;
  for (geom::Id v : {e.v0, e.v1})
    if (v >= 0 && static_cast<std::size_t>(v) < m.vertices.size())
      t = std::max(t, m.vertices[static_cast<std::size_t>(v)].tol);
  return t;
}

std::vector<double> edge_gap_floors(const geom::Model& m) {
  std::vector<double> g(m.edges.size());
  for (std::size_t e = 0; e < g.size(); ++e)
    g[e] = kGapToleranceFactor * gap_tolerance(m, static_cast<geom::Id>(e));
  return g;
}

double proximity_floor(const param::SizeSpec& spec, double diagonal, double feature) {
  if (feature > 0) return feature;
  return 0.01 * (spec.hmin > 0 ? spec.hmin : 1e-3 * diagonal);
}

}  // namespace uvmesh::surface

namespace uvmesh::surface::detail {

BoundaryCaps::BoundaryCaps(const geom::Model& m, const std::vector<std::vector<double>>& t,
                           const param::SizeSpec& spec, double feature)
    : poly_(m.edges.size()) {
  beta_ = std::max(1.0, spec.gradation);
  const double D = std::max(m.bbox.diagonal(), 1e-300);
  // hmin bounds the curvature and gradation sizes. A face narrower than hmin (a chamfer
  // band of a micrometre on a millimetre part) gets elements down to the feature size,
  // no smaller: below it the entity is the CAD system's artefact, not the user's shape,
  // and the simplify stage absorbs it (with keep_topology, down to hmin / 100).
  floor_ = spec.hmin > 0 ? spec.hmin : 1e-3 * D;
  prox_floor_ = proximity_floor(spec, D, feature);
  sheet_floor_ = proximity_floor(spec, D, 0.0);
  sized_at_floor_ = feature > 0;
  eps_ = 1e-12 * D;
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const geom::Edge& ed = m.edges[e];
    if (ed.degenerate || !ed.curve || t[e].size() < 2) continue;
    EdgePoly& P = poly_[e];
    P.tol = gap_tolerance(m, static_cast<geom::Id>(e));
    for (double s : t[e]) P.p.push_back(ed.curve->point(s));
    const std::size_t n = P.p.size();
    P.h.assign(n, std::numeric_limits<double>::infinity());
    P.len.assign(n - 1, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double l = glm::length(P.p[i + 1] - P.p[i]);
      P.len[i] = l;
      P.h[i] = std::min(P.h[i], l);
      P.h[i + 1] = std::min(P.h[i + 1], l);
    }
    P.lo = P.hi = P.p[0];
    for (const auto& q : P.p) P.lo = glm::min(P.lo, q), P.hi = glm::max(P.hi, q);
    P.hmin = *std::min_element(P.h.begin(), P.h.end());
    for (std::size_t a = 0; a + 1 < n; a += kChunk) {
      const std::size_t b = std::min(n - 1, a + kChunk);  // nodes a..b, segments a..b-1
      EdgePoly::Chunk c{P.p[a], P.p[a], P.h[a]};
      for (std::size_t i = a; i <= b; ++i)
        c.lo = glm::min(c.lo, P.p[i]), c.hi = glm::max(c.hi, P.p[i]),
        c.hmin = std::min(c.hmin, P.h[i]);
      P.chunks.push_back(c);
    }
    for (std::size_t a = 0; a < P.chunks.size(); a += kChunk) {
      EdgePoly::Chunk g = P.chunks[a];
      for (std::size_t i = a; i < std::min(P.chunks.size(), a + kChunk); ++i)
        g.lo = glm::min(g.lo, P.chunks[i].lo), g.hi = glm::max(g.hi, P.chunks[i].hi),
        g.hmin = std::min(g.hmin, P.chunks[i].hmin);
      P.groups.push_back(g);
    }
  }
  std::vector<std::vector<geom::Id>> face_edges(
      m.faces.size());  // distinct non-degenerate edges per face
  std::vector<std::vector<geom::Id>> edge_faces(m.edges.size());  // distinct faces per edge
  std::vector<int> uses(m.edges.size(), 0);
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    for (const geom::Loop& l : m.faces[f].loops)
      for (const geom::EdgeUse& u : l.uses) {
        if (u.edge < 0 || poly_[static_cast<std::size_t>(u.edge)].p.empty()) continue;
        ++uses[static_cast<std::size_t>(u.edge)];
        auto& fe = face_edges[f];
        if (std::find(fe.begin(), fe.end(), u.edge) == fe.end()) fe.push_back(u.edge);
        auto& ef = edge_faces[static_cast<std::size_t>(u.edge)];
        if (std::find(ef.begin(), ef.end(), static_cast<geom::Id>(f)) == ef.end())
          ef.push_back(static_cast<geom::Id>(f));
      }
  // What cap() needs of each other edge of the faces around an edge that does not depend
  // on the query point: the gap floor of the pair, and which ends of the other edge are
  // ends of this one (two square roots per end and query before).
  nbrs_.resize(m.edges.size());
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const EdgePoly& self = poly_[e];
    for (geom::Id f : edge_faces[e])
      for (geom::Id oe : face_edges[static_cast<std::size_t>(f)]) {
        if (static_cast<std::size_t>(oe) == e) continue;
        const EdgePoly& P = poly_[static_cast<std::size_t>(oe)];
        // A gap within the two edges' CAD tolerances is no gap (kGapToleranceFactor).
        // With a feature size L, a gap below L is sized at L, not resolved and not
        // ignored: ignored, the face across it took the size beside it and its triangles
        // were caps of Q ~ h / width (where it is narrower than L/2 the simplify stage
        // then collapses across it; where it is wider, elements of L fit it fairly).
        // Between two free edges the gap is a sheet's own width, nothing is there to
        // absorb it, and it is resolved down to hmin / 100 as before; so is every gap
        // under keep_topology, where one below hmin / 100 is ignored.
        const bool sheet = uses[e] == 1 && uses[static_cast<std::size_t>(oe)] == 1;
        const double tol_floor = kGapToleranceFactor * (self.tol + P.tol);
        const double floor = std::max(sheet ? sheet_floor_ : prox_floor_, tol_floor);
        const double from = sheet || !sized_at_floor_ ? floor : tol_floor;
        Neighbour nb{
            oe, floor, std::min(from, floor), std::max(sheet_floor_, tol_floor), {false, false}};
        if (!self.p.empty())
          for (int k = 0; k < 2; ++k) {
            const geom::Vec3& q = k == 0 ? P.p.front() : P.p.back();
            nb.shares_end[k] =
                glm::length(q - self.p.front()) <= eps_ || glm::length(q - self.p.back()) <= eps_;
          }
        nbrs_[e].push_back(nb);
      }
  }
}

namespace {

// sin(kAcuteCornerDeg): a gap d at distance r from the vertex two edges share belongs to
// the tip of an acute corner when d <= r sin(theta) with theta below this angle.
const double kAcuteWedgeSin = std::sin(kAcuteCornerDeg * std::numbers::pi / 180.0);
// A wedge narrower than this many degrees is a lens or a sliver between two edges that
// run along each other (a CAD artefact the feature size absorbs), not a corner of the
// part's shape: resolving it would take ln(L / floor) / theta nodes along each edge.
const double kMinWedgeSin = std::sin(2.0 * std::numbers::pi / 180.0);

}  // namespace

// The tip of an acute corner (two edges of a face meeting at a vertex at an angle below
// kAcuteCornerDeg) is narrower than the feature size L over a length L / sin(theta).
// Sized at L there, its triangles are caps of Q ~ L / (r sin theta), one row after the
// other, and only the one touching the vertex is a corner's (the report's exemption).
// The corner is the part's shape, not a CAD artefact: sizes follow the gap d = r sin
// theta down to the wedge floor, which grades geometrically towards the vertex (ratio
// 1 + sin theta per element) and leaves one poor triangle, at the vertex. A gap that
// does not open linearly from the shared vertex (a strip, a lens, a sliver face: d much
// less than r sin of the angle between the edges there) keeps the feature-size rules.
bool BoundaryCaps::in_acute_wedge(const geom::Vec3& x, const EdgePoly& P, const Neighbour& nb,
                                  double d) const {
  for (int k = 0; k < 2; ++k) {
    if (!nb.shares_end[k]) continue;
    const geom::Vec3& vtx = k == 0 ? P.p.front() : P.p.back();
    const double r = glm::length(x - vtx);
    if (!(r > 0) || d > kAcuteWedgeSin * r || d < kMinWedgeSin * r) continue;
    return true;
  }
  return false;
}

double BoundaryCaps::cap(geom::Id e, const geom::Vec3& x, const geom::Vec3& tangent,
                         double h) const {
  double best = h, prox = h, at_vertex = h, wedge = h;
  const double g = beta_ - 1.0;
  // The other edges of the faces around e. The edge itself is not among them: its own 1D
  // gradation already holds along it, and its nodes near x lie along the tangent
  // (proximity would reject them anyway).
  for (const Neighbour& nb : nbrs_[static_cast<std::size_t>(e)]) {
    const EdgePoly& P = poly_[static_cast<std::size_t>(nb.edge)];
    const double gap_floor = nb.gap_floor;
    // Below hmin, gradation comes only through a vertex the two edges share. An edge
    // refined below hmin by proximity (a narrow gap) that ends on a coarse edge makes a
    // jump of 50x there, and the triangles at the joint are caps. Graded from the shared
    // node, the coarse edge takes O(log) extra nodes. Graded from every sub-hmin node
    // (of the face, or even of the adjacent edges only), the small sizes spread into
    // tangential contacts and acute corners, where they only multiply the slivers across
    // sub-floor gaps (measured: four times as many triangles of Q > 3 on parts with such
    // contacts).
    if (g > 0)
      for (int k = 0; k < 2; ++k)
        if (nb.shares_end[k]) {
          const std::size_t i = k == 0 ? 0 : P.p.size() - 1;
          at_vertex = std::min(at_vertex, P.h[i] + g * glm::length(x - P.p[i]));
        }
    // A node p can lower the size at x only if h(p) + g |x - p| < best; a segment only
    // if it is closer than best.
    const double reach = std::max(prox, g > 0 ? (best - P.hmin) / g : 0.0);
    if (box_distance(x, P.lo, P.hi) >= reach) continue;
    const std::size_t n = P.p.size();
    auto far = [&](const EdgePoly::Chunk& ch) {
      return box_distance(x, ch.lo, ch.hi) >= std::max(prox, g > 0 ? (best - ch.hmin) / g : 0.0);
    };
    // The nearest group first: the caps it gives shrink the reach for all the others.
    std::size_t first = 0;
    double dmin = std::numeric_limits<double>::infinity();
    for (std::size_t k = 0; k < P.groups.size(); ++k)
      if (const double d = box_distance(x, P.groups[k].lo, P.groups[k].hi); d < dmin)
        dmin = d, first = k;
    for (std::size_t step = 0; step < P.chunks.size() + kChunk; ++step) {
      // step 0..kChunk-1 visit the chunks of the nearest group, then every other chunk.
      std::size_t c;
      if (step < kChunk) {
        c = first * kChunk + step;
        if (c >= P.chunks.size()) continue;
      } else {
        c = step - kChunk;
        if (c / kChunk == first) continue;
        if (c >= P.chunks.size()) break;
        if (c % kChunk == 0 && far(P.groups[c / kChunk])) {
          step += kChunk - 1;
          continue;
        }
      }
      if (far(P.chunks[c])) continue;
      const std::size_t a = c * kChunk, b = std::min(n - 1, a + kChunk);
      for (std::size_t i = a; i <= b; ++i) {
        const double di = glm::length(x - P.p[i]);
        if (g > 0) best = std::min(best, P.h[i] + g * di);
        if (i == b) continue;
        // |x - p_i| - |p_i p_i+1| bounds the distance to the segment from below: when it
        // is beyond prox (with a margin far above the rounding of the two lengths), the
        // test below would reject the segment anyway, and its closest point is skipped.
        if (di - P.len[i] > prox * (1 + 1e-9)) continue;
        // Proximity: the gap counts when it is across the face, not along the boundary:
        // the direction to the closest point must be more than 60 degrees from the
        // tangent at x. At a corner of angle theta this holds only for theta < 30
        // degrees, where the sizes then shrink towards the corner.
        const geom::Vec3 v = closest_on_segment(x, P.p[i], P.p[i + 1]) - x;
        const double d = glm::length(v);
        // A gap below resolve_from (a face narrower than the two edges' CAD
        // tolerances, or under keep_topology than hmin / 100: a defect rather than a
        // feature) cannot be resolved; refining along it would only multiply the
        // slivers across it, so it is left to the other caps. One between it and the
        // gap floor is sized at the floor.
        if (d >= prox || d < nb.resolve_from) continue;
        if (std::abs(glm::dot(v, tangent)) > 0.5 * d) continue;
        prox = std::min(prox, std::max(d, gap_floor));
        if (d < gap_floor && in_acute_wedge(x, P, nb, d))
          wedge = std::min(wedge, std::max(d, nb.wedge_floor));
      }
    }
  }
  // The gradation cap stops at hmin, the proximity cap at the feature size (hmin / 100
  // between two free edges; never above h), except in the tip of an acute wedge.
  return std::min({h, std::max(best, floor_), std::max(at_vertex, prox_floor_),
                   std::max(prox, std::min(prox_floor_, sheet_floor_)), wedge});
}

}  // namespace uvmesh::surface::detail
