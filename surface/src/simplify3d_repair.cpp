// The repair operations of the simplification stage (simplify3d_impl.h): points on model
// edges (a cap split under its apex), swaps of poor triangles and relocation of face nodes
// on the CAD surface.
#include "simplify3d_impl.h"

namespace uvmesh::surface::detail::simplify_impl {

namespace {

// Golden-section search of the parameter in [lo, hi] of the edge's curve nearest x (one
// minimum there: the interval is a segment of the 1D mesh or of a sampling).
double nearest_on(const geom::Edge& E, const Vec3& x, double lo, double hi) {
  auto d = [&](double t) { return glm::length(E.curve->point(t) - x); };
  for (int i = 0; i < 60; ++i) {
    const double m1 = lo + (hi - lo) * 0.381966, m2 = hi - (hi - lo) * 0.381966;
    if (d(m1) < d(m2))
      hi = m2;
    else
      lo = m1;
  }
  return 0.5 * (lo + hi);
}

// Parameter of the point of the edge's curve nearest x: the best of 64 samples, refined
// by golden-section search between its neighbours (a node another edge gave this one).
double closest_param(const geom::Edge& E, const Vec3& x) {
  const int n = 64;
  auto d = [&](double t) { return glm::length(E.curve->point(t) - x); };
  int best = 0;
  for (int i = 1; i <= n; ++i)
    if (d(E.range.at(double(i) / n)) < d(E.range.at(double(best) / n))) best = i;
  double lo = E.range.at(std::max(0, best - 1) / double(n)),
         hi = E.range.at(std::min(n, best + 1) / double(n));
  return nearest_on(E, x, lo, hi);
}

}  // namespace

// Parameter of node n on edge e's curve (a model vertex: the end nearest `hint`).
double Simplifier::node_param(NodeId n, geom::Id e, double hint) const {
  const geom::Edge& E = m.edges[static_cast<std::size_t>(e)];
  if (dim(n) == 1 && ent(n) == e) return M.point_t[static_cast<std::size_t>(n)];
  if (dim(n) == 1) return closest_param(E, P(n));
  const double dl = glm::length(E.curve->point(E.range.lo) - P(n)),
               dh = glm::length(E.curve->point(E.range.hi) - P(n));
  if (std::abs(dl - dh) > 1e-12 * (1 + dl + dh)) return dl < dh ? E.range.lo : E.range.hi;
  return std::abs(hint - E.range.lo) < std::abs(hint - E.range.hi) ? E.range.lo : E.range.hi;
}

NodeId Simplifier::add_edge_node(geom::Id e, double t) {
  const auto n = static_cast<NodeId>(M.points.size());
  M.points.push_back(m.edges[static_cast<std::size_t>(e)].curve->point(t));
  M.point_dim.push_back(1);
  M.point_entity.push_back(e);
  M.point_t.push_back(t);
  node_alive.push_back(1);
  vtris.emplace_back();
  nsegs.emplace_back();
  return n;
}

// A cap whose long edge lies on a sharp model edge: the edge split at the point of its
// curve nearest the apex (when that point is closer than max_height to the apex), then
// the apex collapsed onto it when it may be.
bool Simplifier::try_split(int t, int k, double max_height) {
  const Tri v = T(t);
  const NodeId b = v[k], c = v[(k + 1) % 3], a = v[(k + 2) % 3];
  const int s = segment(b, c);
  if (s < 0) return false;
  const geom::Id e = M.segments[static_cast<std::size_t>(s)].edge;
  const geom::Edge& E = m.edges[static_cast<std::size_t>(e)];
  const auto on = edge_tris(b, c);
  if (!E.curve || on.size() > 2 || !allowed(edge_op('s', b, c))) return false;
  double t0 = node_param(b, e, dim(c) == 1 ? M.point_t[static_cast<std::size_t>(c)] : E.range.lo);
  double t1 = node_param(c, e, t0);
  const double tm = nearest_on(E, P(a), std::min(t0, t1), std::max(t0, t1));
  const double span = std::abs(t1 - t0);
  if (!(std::abs(tm - t0) > 0.05 * span && std::abs(tm - t1) > 0.05 * span)) return false;
  const Vec3 x = E.curve->point(tm);
  if (!(glm::length(P(a) - x) < max_height)) return false;
  double old_worst = 0, new_worst = 0;
  std::vector<NewTri> nts;
  for (int tri : on) {
    const Tri q = T(tri);
    const int i = q[0] == b && q[1] == c
                      ? 0
                      : (q[1] == b && q[2] == c ? 1 : (q[2] == b && q[0] == c ? 2 : -1));
    const int j = i >= 0 ? i : (q[0] == c && q[1] == b ? 0 : (q[1] == c && q[2] == b ? 1 : 2));
    const NodeId p0 = q[j], p1 = q[(j + 1) % 3], p2 = q[(j + 2) % 3];
    old_worst = std::max(old_worst, Q(tri));
    new_worst = std::max({new_worst, shape(P(p0), x, P(p2)), shape(x, P(p1), P(p2))});
    NewTri h0, h1;
    h0.slot = tri;
    h0.v = {p0, -1, p2}, h1.v = {-1, p1, p2};
    const TriUV& uv = M.triangle_uv[static_cast<std::size_t>(tri)];
    const Vec2 mid =
        0.5 * (uv[static_cast<std::size_t>(j)] + uv[static_cast<std::size_t>((j + 1) % 3)]);
    h0.face = h1.face = M.triangle_face[static_cast<std::size_t>(tri)];
    const Vec2 um = project(h0.face, x, mid, glm::length(P(p1) - P(p0))).uv;
    h0.uv = {uv[static_cast<std::size_t>(j)], um, uv[static_cast<std::size_t>((j + 2) % 3)]};
    h1.uv = {um, uv[static_cast<std::size_t>((j + 1) % 3)],
             uv[static_cast<std::size_t>((j + 2) % 3)]};
    nts.push_back(h0);
    nts.push_back(h1);
  }
  if (!(new_worst < old_worst)) return false;
  begin(edge_op('s', b, c));
  const NodeId n = add_edge_node(e, tm);
  for (NewTri& nt : nts) {
    for (NodeId& w : nt.v)
      if (w < 0) w = n;
    write(nt);
  }
  auto& g = M.segments[static_cast<std::size_t>(s)];
  const NodeId gb = g.b;
  g.b = n;
  nsegs[static_cast<std::size_t>(n)].push_back(s);
  std::erase(nsegs[static_cast<std::size_t>(gb)], s);
  M.segments.push_back({n, gb, e});
  seg_alive.push_back(1);
  const int s2 = static_cast<int>(M.segments.size()) - 1;
  nsegs[static_cast<std::size_t>(n)].push_back(s2);
  nsegs[static_cast<std::size_t>(gb)].push_back(s2);
  eseg[static_cast<std::size_t>(e)].push_back(s2);
  if (glm::length(P(a) - x) <= std::max(in.chordal_tol, in.collapse_size)) try_collapse(a, n);
  return true;
}

// The candidates with Q > kPoorShape, worst first.
std::vector<int> Simplifier::poor_first(const std::vector<int>& cand) const {
  std::vector<std::pair<double, int>> bad;
  for (int t : cand)
    if (tri_alive[static_cast<std::size_t>(t)] && Q(t) > kPoorShape) bad.emplace_back(-Q(t), t);
  std::sort(bad.begin(), bad.end());
  std::vector<int> r;
  for (const auto& b : bad) r.push_back(b.second);
  return r;
}

// Triangles still poor after the collapses: swaps of their edges, longest first; caps on
// a sharp edge split.
bool Simplifier::repair_pass(const std::vector<int>& cand) {
  return for_each_poor(cand, [&](int t) {
    const Tri v = T(t);
    std::array<std::pair<double, int>, 3> ks;
    for (int k = 0; k < 3; ++k) ks[k] = {-glm::length(P(v[(k + 1) % 3]) - P(v[k])), k};
    std::sort(ks.begin(), ks.end());
    bool done = false;
    for (const auto& [nl, k] : ks)
      if (!done) done = try_flip(t, k, Q(t));
    // A cap of Q above kBadShape is split whatever its height; a poor one only when its
    // apex lies closer than L / 2 to the edge (a strip narrower than that meshed as caps
    // along it, which the apex collapses onto the split points absorb).
    if (!done) done = try_split(t, ks[0].second, Q(t) > kBadShape ? kInf : in.collapse_size);
    return done;
  });
}

// Relocation (the point smoothing of the chapter's optimization step, done on the CAD
// surface): a face node of a poor triangle moved toward the centroid of its ring and
// projected back onto its face, at the largest of a few step fractions that lowers the
// worst Q of the ring without turning a triangle past the fold guard. Only nodes whose
// triangles all lie on their own face with one (u,v) (not on a seam) move, so every
// vertex stays on its CAD face and each triangle keeps its face.
bool Simplifier::try_relocate(NodeId n) {
  if (dim(n) != 2) return false;
  const geom::Id f = ent(n);
  // The ring; the node's (u,v) on its face from a triangle of that face. Triangles on
  // other faces (a dissolved edge's neighbours) or on the far side of a seam are placed
  // again after the move, as a collapse places the triangles it makes.
  std::vector<int> ring;
  std::vector<char> own;
  std::optional<Vec2> uv0;
  for_tris(n, [&](int t) {
    ring.push_back(t);
    own.push_back(0);
    if (M.triangle_face[static_cast<std::size_t>(t)] != f) return;
    const Vec2 uv =
        M.triangle_uv[static_cast<std::size_t>(t)][static_cast<std::size_t>(corner(t, n))];
    if (!uv0) uv0 = uv;
    own.back() = glm::length(uv - *uv0) == 0;
  });
  if (ring.size() < 3 || !uv0 || !allowed({'r', n, -1})) return false;
  double old_worst = 0, area = 0, h = 0;
  Vec3 target(0.0);
  for (int t : ring) {
    const Tri& v = T(t);
    old_worst = std::max(old_worst, Q(t));
    const double a = 0.5 * glm::length(glm::cross(P(v[1]) - P(v[0]), P(v[2]) - P(v[0])));
    target += a * (P(v[0]) + P(v[1]) + P(v[2])) / 3.0;
    area += a;
    for (int k = 0; k < 3; ++k) h = std::max(h, glm::length(P(v[(k + 1) % 3]) - P(v[k])));
  }
  if (!(area > 0)) return false;
  target /= area;
  const Vec3 x0 = P(n);
  for (double step : {1.0, 0.5, 0.25}) {
    const geom::Projection pr = project(f, x0 + step * (target - x0), *uv0, h);
    if (!pr.converged) continue;
    double worst = 0;
    bool fold = false;
    for (int t : ring) {
      std::array<Vec3, 3> c{P(T(t)[0]), P(T(t)[1]), P(T(t)[2])};
      const Vec3 n0 = unit_normal(c[0], c[1], c[2]);
      for (auto& x : c)
        if (x == x0) x = pr.point;
      if (glm::dot(n0, unit_normal(c[0], c[1], c[2])) < kMaxTurn) fold = true;
      worst = std::max(worst, shape(c[0], c[1], c[2]));
    }
    if (fold || !(worst < old_worst)) continue;
    M.points[static_cast<std::size_t>(n)] = pr.point;
    std::vector<NewTri> others;
    bool placed = true;
    for (std::size_t i = 0; i < ring.size() && placed; ++i) {
      NewTri nt;
      nt.slot = ring[i];
      nt.v = T(ring[i]);
      if (own[i]) {  // same face and (u,v): only the chordal tolerance to hold
        nt.face = f;
        nt.uv = M.triangle_uv[static_cast<std::size_t>(nt.slot)];
        nt.uv[static_cast<std::size_t>(corner(nt.slot, n))] = pr.uv;
        placed = in.chordal_tol <= 0 || deviation(nt) <= in.chordal_tol;
        continue;
      }
      placed = place(nt, M.triangle_face[static_cast<std::size_t>(nt.slot)],
                     M.triangle_uv[static_cast<std::size_t>(nt.slot)]);
      others.push_back(nt);
    }
    if (!placed) {
      M.points[static_cast<std::size_t>(n)] = x0;
      continue;
    }
    for (std::size_t i = 0; i < ring.size(); ++i)
      if (own[i])
        M.triangle_uv[static_cast<std::size_t>(ring[i])]
                     [static_cast<std::size_t>(corner(ring[i], n))] = pr.uv;
    begin({'r', n, -1});
    for (const NewTri& nt : others) write(nt);
    for (int t : ring)
      touched.push_back(t), writer[static_cast<std::size_t>(t)] = static_cast<int>(ops.size()) - 1;
    changed = true;
    return true;
  }
  return false;
}

// The face nodes of triangles still poor after the swaps, worst triangle first.
bool Simplifier::relocate_pass(const std::vector<int>& cand) {
  return for_each_poor(cand, [&](int t) {
    bool any = false;
    for (NodeId n : Tri(T(t))) any |= try_relocate(n);
    return any;
  });
}

}  // namespace uvmesh::surface::detail::simplify_impl
