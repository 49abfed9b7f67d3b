// Size caps along model edges from the other edges of the faces around them (gradation
// across a face, proximity). See BoundaryCaps in internal.h for what and why.
#include <algorithm>
#include <array>
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

namespace {

// Unit chord from the first (at_front) or last node of a curve to its point at a distance
// of about `scale` (halving the parameter step from the whole range); zero when unknown.
geom::Vec3 corner_chord(const geom::Curve& c, const std::vector<double>& t, bool at_front,
                        double scale) {
  const double t0 = at_front ? t.front() : t.back(), t1 = at_front ? t.back() : t.front();
  const geom::Vec3 v = c.point(t0);
  geom::Vec3 d(0.0);
  for (int j = 0; j < 40; ++j) {
    d = c.point(t0 + (t1 - t0) * std::ldexp(1.0, -j)) - v;
    if (glm::length(d) <= scale) break;
  }
  const double n = glm::length(d);
  return n > 0 ? d / n : geom::Vec3(0.0);
}

// How much farther than L the corner's angle is measured a second time: a corner whose
// sides curve towards each other (two curves tangent at the vertex, a cusp: the gap grows
// as r^2) opens more than twice as wide there, and is no straight wedge.
constexpr double kWedgeReach = 4.0;
// The tip of a wedge is graded down to this share of L; inside that, one triangle spans
// it at the vertex. Each factor of 10 costs ln(10) / sin(theta) more nodes along each
// side (100 at 1.3 degrees) and grades the face around: a tenth holds the caps off the
// rows beside the tip triangle at a few dozen nodes.
constexpr double kWedgeFloorShare = 0.1;

// sin of the angle between two unit directions leaving one vertex; 1 when it is 90
// degrees or more (not acute) or either is unknown (a zero tangent).
double corner_sin(const geom::Vec3& a, const geom::Vec3& b) {
  if (glm::dot(a, b) <= 0 || glm::length(a) < 0.5 || glm::length(b) < 0.5) return 1.0;
  return std::min(1.0, glm::length(glm::cross(a, b)));
}

// Per edge: whether it is sharp, its faces meeting at a dihedral angle of at least
// `feature_angle` (radians) somewhere along it (at the nodes between its ends, where the
// simplify stage measures it too: simplify3d.cpp), or it is free or non-manifold. A
// smooth edge or a seam is no side of a corner: the simplify stage dissolves it, and the
// faces across it are one surface there.
std::vector<char> sharp_edges(const geom::Model& m, const std::vector<std::vector<double>>& t,
                              double feature_angle) {
  std::vector<std::vector<std::pair<const geom::Face*, const geom::EdgeUse*>>> uses(m.edges.size());
  for (const geom::Face& f : m.faces)
    for (const geom::Loop& l : f.loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.edge >= 0 && !u.internal) uses[static_cast<std::size_t>(u.edge)].push_back({&f, &u});
  std::vector<char> sharp(m.edges.size(), 1);
  const double cos_limit = std::cos(feature_angle);
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const auto& us = uses[e];
    if (us.size() != 2 || t[e].size() < 2) continue;
    sharp[e] = 0;
    if (us[0].first == us[1].first) continue;  // a seam
    std::vector<double> at(t[e].begin() + 1, t[e].end() - 1);
    if (at.empty()) at.push_back(0.5 * (t[e].front() + t[e].back()));
    for (double s : at) {
      geom::Vec3 n[2];
      for (int i = 0; i < 2; ++i) {
        const auto& [f, u] = us[static_cast<std::size_t>(i)];
        if (!f->surface || !u->pcurve) break;
        const geom::Vec2 uv = u->pcurve->point(s);
        n[i] = f->surface->eval_first(uv.x, uv.y).normal() * (f->reversed ? -1.0 : 1.0);
      }
      const double l0 = glm::length(n[0]), l1 = glm::length(n[1]);
      if (l0 > 0.5 && l1 > 0.5 && glm::dot(n[0], n[1]) / (l0 * l1) <= cos_limit) {
        sharp[e] = 1;
        break;
      }
    }
  }
  return sharp;
}

}  // namespace

BoundaryCaps::BoundaryCaps(const geom::Model& m, const std::vector<std::vector<double>>& t,
                           const param::SizeSpec& spec, double feature, double feature_angle)
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
    // The directions in which the corner at each end opens, at the scale the wedge rule
    // works at (prox_floor_, the feature size): the chord from the end to the curve's
    // point about that far along it. Not the end segment of this discretization (an
    // arc's first segment may turn tens of degrees away from it), nor the tangent (a
    // curve turning within a micrometre of its end: the corner the mesh sees is the one
    // at the element's scale).
    for (int k = 0; k < 2; ++k) {
      P.end_dir[k] = corner_chord(*ed.curve, t[e], k == 0, prox_floor_);
      P.end_dir_far[k] = corner_chord(*ed.curve, t[e], k == 0, kWedgeReach * prox_floor_);
    }
    const std::size_t n = P.p.size();
    P.h.assign(n, std::numeric_limits<double>::infinity());
    P.len.assign(n - 1, 0.0);
    for (std::size_t i = 0; i + 1 < n; ++i) {
      const double l = glm::length(P.p[i + 1] - P.p[i]);
      P.len[i] = l;
      P.length += l;
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
  const std::vector<char> sharp = sharp_edges(m, t, feature_angle);
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
        Neighbour nb{oe,
                     floor,
                     std::min(from, floor),
                     std::max(kWedgeFloorShare * prox_floor_, tol_floor),
                     {false, false},
                     {1.0, 1.0}};
        if (!self.p.empty())
          for (int k = 0; k < 2; ++k) {
            const bool first = k == 0;
            const geom::Vec3& q = first ? P.p.front() : P.p.back();
            const bool at_front = glm::length(q - self.p.front()) <= eps_;
            nb.shares_end[k] = at_front || glm::length(q - self.p.back()) <= eps_;
            const bool corner = sharp[e] && sharp[static_cast<std::size_t>(oe)];
            // An edge shorter than the feature size is absorbed (collapsed to a vertex or
            // merged into a composite edge): no side of a corner either.
            const bool sides = self.length >= prox_floor_ && P.length >= prox_floor_;
            if (nb.shares_end[k] && corner && sides)
              nb.corner_sin[k] = wedge_sin(self, at_front ? 0 : 1, P, first ? 0 : 1);
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

// The tip of an acute corner (two sharp edges of a face leaving a vertex at an angle below
// kAcuteCornerDeg between their tangents) is narrower than the feature size L over a
// length L / sin(theta). Sized at L there, its triangles are caps of Q ~ L / (r sin
// theta), one row after the other, and only the one touching the vertex is a corner's
// (the report's exemption). The corner is the part's shape, not a CAD artefact: sizes
// follow the gap d = r sin theta down to the wedge floor, which grades geometrically
// towards the vertex (ratio 1 + sin theta per element), and one triangle spans the rest,
// at the vertex. A gap that does not open linearly from the shared vertex at the
// corner's angle (an edge curving back towards the other far from the vertex), a corner
// below kMinWedgeSin (a lens, a sliver face) and one with a smooth side keep the
// feature-size rules.
double BoundaryCaps::wedge_sin(const EdgePoly& a, int ka, const EdgePoly& b, int kb) {
  const double near = corner_sin(a.end_dir[ka], b.end_dir[kb]);
  const double far = corner_sin(a.end_dir_far[ka], b.end_dir_far[kb]);
  return far <= 2.0 * near ? near : 1.0;
}

bool BoundaryCaps::in_acute_wedge(const geom::Vec3& x, const EdgePoly& P, const Neighbour& nb,
                                  double d) const {
  for (int k = 0; k < 2; ++k) {
    const double s = nb.corner_sin[k];
    if (!nb.shares_end[k] || s > kAcuteWedgeSin || s < kMinWedgeSin) continue;
    // Within the straight part of the wedge the gap is r sin(theta); a gap much smaller or
    // larger belongs to another part of the edges (one curving back towards the other).
    const double r = glm::length(x - (k == 0 ? P.p.front() : P.p.back()));
    if (d >= 0.5 * r * s && d <= 1.5 * r * s) return true;
  }
  return false;
}

double BoundaryCaps::cap(geom::Id e, const geom::Vec3& x, const geom::Vec3& tangent,
                         double h) const {
  double best = h, prox = h, at_vertex = h, wedge = h, at_wedge = h;
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
    // An edge at least L long refined below L at its end, or an edge shorter than L cut
    // into several segments (sizes above L would leave it one), was refined there on
    // purpose (the tip of an acute wedge, a sheet's width, a user size), not by being an
    // artefact: the other edges at that vertex grade down to it too, else the faces on
    // its other side meet a jump of L / h at the vertex (caps at corners of 90 degrees).
    // Not the other edge of the wedge itself: inside the tip, where the gap is below the
    // wedge floor, its sizes would put several nodes along a gap narrower than them.
    if (g > 0)
      for (int k = 0; k < 2; ++k)
        if (nb.shares_end[k]) {
          const std::size_t i = k == 0 ? 0 : P.p.size() - 1;
          const double hv = P.h[i] + g * glm::length(x - P.p[i]);
          at_vertex = std::min(at_vertex, hv);
          if ((P.length >= prox_floor_ || P.p.size() > 2) && nb.corner_sin[k] >= kAcuteWedgeSin)
            at_wedge = std::min(at_wedge, std::max(hv, nb.wedge_floor));
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
        // Inside the very tip, narrower than the wedge floor, no size: nodes there at the
        // floor would be needles; one triangle spans it, at the vertex.
        if (d < gap_floor && d >= nb.wedge_floor && in_acute_wedge(x, P, nb, d))
          wedge = std::min(wedge, d);
      }
    }
  }
  // The gradation cap stops at hmin, the proximity cap at the feature size (hmin / 100
  // between two free edges; never above h), except in the tip of an acute wedge.
  return std::min({h, std::max(best, floor_), std::max(at_vertex, prox_floor_),
                   std::max(prox, std::min(prox_floor_, sheet_floor_)), wedge, at_wedge});
}

}  // namespace uvmesh::surface::detail
