// The simplification stage (simplify3d.h): edge collapses, swaps and splits on the
// stitched mesh, judged by the 3D shape quality Q_K (eq. 7.6), with vertices kept on
// their model entities. Each operation is local and only the triangles it made are
// candidates of the next round, so a round costs O(k log k) in its k candidates after
// the first, O(n log n), scan.
#include "simplify3d.h"

#include <algorithm>
#include <map>
#include <tuple>

#include "check3d_internal.h"
#include "model_run.h"
#include "simplify3d_impl.h"

namespace uvmesh::surface::detail {

namespace simplify_impl {

void Simplifier::init() {
  const std::size_t nn = M.points.size(), nt = M.triangles.size();
  tri_alive.assign(nt, 1);
  node_alive.assign(nn, 1);
  seg_alive.assign(M.segments.size(), 1);
  vtris.assign(nn, {});
  nsegs.assign(nn, {});
  eseg.assign(m.edges.size(), {});
  for (std::size_t t = 0; t < nt; ++t)
    for (NodeId v : M.triangles[t])
      vtris[static_cast<std::size_t>(v)].push_back(static_cast<int>(t));
  for (std::size_t s = 0; s < M.segments.size(); ++s) {
    const auto& g = M.segments[s];
    nsegs[static_cast<std::size_t>(g.a)].push_back(static_cast<int>(s));
    nsegs[static_cast<std::size_t>(g.b)].push_back(static_cast<int>(s));
    if (g.edge >= 0) eseg[static_cast<std::size_t>(g.edge)].push_back(static_cast<int>(s));
  }
  writer.assign(nt, -1);
  efaces = geom::edge_faces(m);
  classify_edges();
  classify_faces();
}

void Simplifier::classify_faces() {
  std::vector<std::vector<geom::Id>> solids(m.faces.size());
  for (std::size_t so = 0; so < m.solids.size(); ++so)
    for (geom::Id sh : m.solids[so].shells)
      if (sh >= 0 && static_cast<std::size_t>(sh) < m.shells.size())
        for (geom::Id f : m.shells[static_cast<std::size_t>(sh)].faces)
          if (f >= 0 && static_cast<std::size_t>(f) < solids.size())
            solids[static_cast<std::size_t>(f)].push_back(static_cast<geom::Id>(so));
  std::map<std::vector<geom::Id>, int> index;
  solid_set.assign(m.faces.size(), 0);
  for (std::size_t f = 0; f < solids.size(); ++f) {
    std::sort(solids[f].begin(), solids[f].end());
    solids[f].erase(std::unique(solids[f].begin(), solids[f].end()), solids[f].end());
    solid_set[f] = index.emplace(solids[f], static_cast<int>(index.size())).first->second;
  }
}

// The largest angle between the material-side normals of the edge's two faces, at the
// edge's nodes (the CAD normals at the (u,v) the triangles give them).
double Simplifier::edge_dihedral(geom::Id e) const {
  const auto& fs = efaces[static_cast<std::size_t>(e)];
  double worst = -1;
  for (int s : eseg[static_cast<std::size_t>(e)]) {
    const auto& g = M.segments[static_cast<std::size_t>(s)];
    for (NodeId n : {g.a, g.b}) {
      Vec3 nrm[2];
      bool ok = true;
      for (int i = 0; i < 2 && ok; ++i) {
        const geom::Face& F = m.faces[static_cast<std::size_t>(fs[static_cast<std::size_t>(i)])];
        const auto uv = uv_on(n, fs[static_cast<std::size_t>(i)], nullptr);
        if (!uv || !F.surface) {
          ok = false;
          break;
        }
        nrm[i] = F.surface->eval_first(uv->x, uv->y).normal() * (F.reversed ? -1.0 : 1.0);
        ok = glm::length(nrm[i]) > 0.5;
      }
      if (!ok) continue;
      const double c = std::clamp(glm::dot(nrm[0], nrm[1]), -1.0, 1.0);
      worst = std::max(worst, std::acos(c) * 180.0 / std::numbers::pi);
    }
  }
  return worst;
}

// Sharp: kept as a chain of segments (simplify3d.h).
void Simplifier::classify_edges() {
  const std::size_t ne = m.edges.size();
  sharp.assign(ne, 1);
  dissolved.assign(ne, 0);
  std::vector<int> uses(ne, 0);
  for (const geom::Face& face : m.faces)
    for (const geom::Loop& l : face.loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.edge >= 0 && static_cast<std::size_t>(u.edge) < ne)
          ++uses[static_cast<std::size_t>(u.edge)];
  free_edge.assign(ne, 0);
  for (std::size_t e = 0; e < ne; ++e) free_edge[e] = uses[e] == 1;
  dihedral.assign(ne, 180.0);
  std::vector<geom::Id> solid_of_shell(m.shells.size(), geom::kNone);
  for (std::size_t s = 0; s < m.solids.size(); ++s)
    for (geom::Id sh : m.solids[s].shells)
      if (sh >= 0 && static_cast<std::size_t>(sh) < m.shells.size())
        solid_of_shell[static_cast<std::size_t>(sh)] = static_cast<geom::Id>(s);
  auto solid = [&](geom::Id f) {
    const geom::Id sh = m.faces[static_cast<std::size_t>(f)].shell;
    return sh >= 0 ? solid_of_shell[static_cast<std::size_t>(sh)] : geom::kNone;
  };
  for (std::size_t e = 0; e < ne; ++e) {
    const auto& fs = efaces[e];
    if (fs.size() != 2 || eseg[e].empty()) continue;  // free, non-manifold or seam
    const geom::Face &f0 = m.faces[static_cast<std::size_t>(fs[0])],
                     &f1 = m.faces[static_cast<std::size_t>(fs[1])];
    if (solid(fs[0]) != solid(fs[1])) continue;
    if (f0.name != f1.name && !(f0.name.empty() && f1.name.empty())) continue;
    if (kept(static_cast<geom::Id>(e))) continue;
    dihedral[e] = edge_dihedral(static_cast<geom::Id>(e));
    sharp[e] = !(dihedral[e] >= 0 && dihedral[e] < in.feature_angle * 180.0 / std::numbers::pi);
  }
}

// The face of a new triangle: among its old face and the faces of its corners, the one
// its centroid projects closest onto; its corners' (u,v) on that face. False when the
// centroid is farther than the chordal tolerance from it.
bool Simplifier::place(NewTri& nt, geom::Id f0, const TriUV& hint) const {
  std::vector<geom::Id> cand;
  for (NodeId v : nt.v) {
    if (dim(v) == 2) cand.push_back(ent(v));
    if (dim(v) == 1)
      for (geom::Id f : efaces[static_cast<std::size_t>(ent(v))]) cand.push_back(f);
  }
  std::sort(cand.begin(), cand.end());
  cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  double best = kInf;
  NewTri keep = nt;
  if (place_on(keep, f0, &hint, best)) nt = keep;
  for (geom::Id f : cand) {
    if (f == f0 ||
        solid_set[static_cast<std::size_t>(f)] != solid_set[static_cast<std::size_t>(f0)])
      continue;
    NewTri tr = nt;
    double d = kInf;
    if (place_on(tr, f, nullptr, d) && d < best) best = d, nt = tr;
  }
  if (best == kInf) return false;
  return in.chordal_tol <= 0 || best <= in.chordal_tol;
}

bool Simplifier::place_on(NewTri& nt, geom::Id f, const TriUV* hint, double& dist) const {
  const geom::Face& F = m.faces[static_cast<std::size_t>(f)];
  if (!F.surface) return false;
  std::array<std::optional<Vec2>, 3> uv;
  int known = -1;
  for (int k = 0; k < 3; ++k) {
    uv[k] = uv_on(nt.v[k], f, hint ? &(*hint)[k] : nullptr);
    if (uv[k] && known < 0) known = k;
  }
  if (known < 0 && !hint) return false;
  const Vec3 &a = P(nt.v[0]), &b = P(nt.v[1]), &c = P(nt.v[2]);
  const double h = std::max({glm::length(b - a), glm::length(c - b), glm::length(a - c)});
  for (int k = 0; k < 3; ++k)
    if (!uv[k]) {
      const Vec2 seed = hint ? (*hint)[k] : *uv[known];
      uv[k] = project(f, P(nt.v[k]), seed, h).uv;
    }
  // One period for the three corners: on a periodic surface a node on the seam has a
  // (u,v) on either side, and corners taken from different triangles may disagree.
  const geom::Surface& S = *F.surface;
  for (int k = 0; k < 3; ++k) {
    if (S.u_periodic() && S.u_period() > 0)
      uv[k]->x += std::round((uv[0]->x - uv[k]->x) / S.u_period()) * S.u_period();
    if (S.v_periodic() && S.v_period() > 0)
      uv[k]->y += std::round((uv[0]->y - uv[k]->y) / S.v_period()) * S.v_period();
  }
  nt.face = f;
  for (int k = 0; k < 3; ++k) nt.uv[k] = *uv[k];
  dist = deviation(nt);
  return true;
}

// The chordal deviation of a triangle as the report measures it (check3d_chordal.cpp):
// its chordal_samples() projected onto its face.
double Simplifier::deviation(const NewTri& nt) const {
  const std::array<Vec3, 3> c{P(nt.v[0]), P(nt.v[1]), P(nt.v[2])};
  const double h =
      std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
  const check3d_impl::ChordalSamples cs = check3d_impl::chordal_samples(c, nt.uv);
  double d = 0;
  for (int k = 0; k < 4; ++k) d = std::max(d, project(nt.face, cs.x[k], cs.uv[k], h).distance);
  return d;
}

// The rank rules of simplify3d.h: lower rank onto higher; along a sharp edge only; model
// vertices only along a model edge shorter than L. `dissolve`: a's smooth edge goes.
bool Simplifier::collapse_allowed(NodeId a, NodeId b, bool& dissolve) const {
  dissolve = false;
  if (rank(a) > rank(b)) return false;
  const int s = segment(a, b);
  if (dim(a) == 0) {
    if (dim(b) != 0) return false;
    // Two model vertices across a face (no model edge joins them) closer than L / 2: the two
    // corners of a sliver face that ends in a short side of no edge of its own. Merged
    // like the ends of a short edge, except on a sheet's border, whose gaps are its own
    // width.
    if (s < 0)
      return glm::length(P(a) - P(b)) < in.collapse_size && !(on_free_edge(a) && on_free_edge(b)) &&
             !on_kept_edge(a) && !on_kept_edge(b);
    const geom::Id e = M.segments[static_cast<std::size_t>(s)].edge;
    return e >= 0 && !kept(e) && m.edges[static_cast<std::size_t>(e)].length < in.collapse_size;
  }
  if (dim(a) == 1) {
    if (s >= 0 && M.segments[static_cast<std::size_t>(s)].edge == ent(a)) return true;
    // Two sharp edges closer than L / 2 (the two sides of a sliver face): one gives its
    // nodes to the other.
    // Not two free edges: their gap is a sheet's own width, which nothing absorbs (the
    // size field resolves it, boundary_caps.cpp).
    if (sharp[static_cast<std::size_t>(ent(a))]) {
      if (kept(ent(a)) || (dim(b) == 1 && kept(ent(b)))) return false;
      if (free_edge[static_cast<std::size_t>(ent(a))] && dim(b) == 1 &&
          free_edge[static_cast<std::size_t>(ent(b))])
        return false;
      return rank(b) >= 2 && glm::length(P(a) - P(b)) < in.collapse_size;
    }
    dissolve = true;
  }
  return true;
}

bool Simplifier::on_edge_where(NodeId n, const std::vector<char>& flag) const {
  for (int s : nsegs[static_cast<std::size_t>(n)])
    if (seg_alive[static_cast<std::size_t>(s)]) {
      const geom::Id e = M.segments[static_cast<std::size_t>(s)].edge;
      if (e >= 0 && static_cast<std::size_t>(e) < flag.size() && flag[static_cast<std::size_t>(e)])
        return true;
    }
  return false;
}

// Link condition: the common neighbours of a and b are the apexes of the triangles on a-b
// (else the collapse pinches the surface or duplicates a triangle).
bool Simplifier::link_ok(NodeId a, NodeId b, const std::vector<int>& removed) const {
  const auto na = neighbours(a), nb = neighbours(b);
  std::vector<NodeId> common, apex;
  std::set_intersection(na.begin(), na.end(), nb.begin(), nb.end(), std::back_inserter(common));
  for (int t : removed)
    for (NodeId v : T(t))
      if (v != a && v != b) apex.push_back(v);
  std::sort(apex.begin(), apex.end());
  apex.erase(std::unique(apex.begin(), apex.end()), apex.end());
  return common == apex && !removed.empty();
}

Simplifier::Plan Simplifier::plan_collapse(NodeId a, NodeId b) const {
  Plan p;
  if (!collapse_allowed(a, b, p.dissolve)) return p;
  p.removed = edge_tris(a, b);
  if (!link_ok(a, b, p.removed) || !allowed({'c', a, b})) return p;
  double old_worst = 0;
  for (int t : p.removed) old_worst = std::max(old_worst, Q(t));
  const double removed_worst = old_worst;
  bool ok = true;
  p.worst = 0;
  for_tris(a, [&](int t) {
    if (!ok || has(T(t), b)) return;
    old_worst = std::max(old_worst, Q(t));
    NewTri nt;
    nt.slot = t;
    nt.v = T(t);
    for (NodeId& v : nt.v)
      if (v == a) v = b;
    const Vec3 n0 = unit_normal(P(T(t)[0]), P(T(t)[1]), P(T(t)[2]));
    const Vec3 n1 = unit_normal(P(nt.v[0]), P(nt.v[1]), P(nt.v[2]));
    if (glm::dot(n0, n1) < kMaxTurn) ok = false;
    p.worst = std::max(p.worst, shape(P(nt.v[0]), P(nt.v[1]), P(nt.v[2])));
    p.tris.push_back(nt);
  });
  // Never worse than the worst triangle replaced, unless that one is removed for good.
  // An edge shorter than L may also go where the triangles it leaves stay fair, or where
  // it removes a needle and leaves about as bad a one: a strip narrower than L meshed as
  // a row of needles is absorbed one cross edge at a time, and only the last collapse
  // clears it.
  const bool short_edge = glm::length(P(a) - P(b)) < in.collapse_size;
  // Steps along a strip never go beyond the worst triangle the stage started from, so
  // that the slack cannot compound from one step to the next.
  const bool strip_step = short_edge && removed_worst > kPoorShape &&
                          p.worst <= kStripStepSlack * removed_worst && p.worst <= start_worst;
  if (!ok || !(p.worst <= old_worst || (old_worst > kBadShape && p.worst < kBadShape) ||
               (short_edge && p.worst < kFairShape) || strip_step))
    return p;
  for (NewTri& nt : p.tris)
    if (!place(nt, M.triangle_face[static_cast<std::size_t>(nt.slot)],
               M.triangle_uv[static_cast<std::size_t>(nt.slot)]))
      return p;
  p.ok = true;
  return p;
}

void Simplifier::write(const NewTri& nt) {
  int t = nt.slot;
  if (t < 0) {
    t = static_cast<int>(M.triangles.size());
    M.triangles.push_back(nt.v);
    M.triangle_face.push_back(nt.face);
    M.triangle_uv.push_back(nt.uv);
    tri_alive.push_back(1);
    writer.push_back(static_cast<int>(ops.size()) - 1);
  } else {
    writer[static_cast<std::size_t>(t)] = static_cast<int>(ops.size()) - 1;
    M.triangles[static_cast<std::size_t>(t)] = nt.v;
    M.triangle_face[static_cast<std::size_t>(t)] = nt.face;
    M.triangle_uv[static_cast<std::size_t>(t)] = nt.uv;
  }
  for (NodeId v : nt.v) {
    auto& l = vtris[static_cast<std::size_t>(v)];
    if (std::find(l.begin(), l.end(), t) == l.end()) l.push_back(t);
  }
  touched.push_back(t);
  changed = true;
}

// A smooth edge the mesh stops following: its segments go, its nodes become nodes of the
// face (the lower id) whose triangles they touch.
void Simplifier::dissolve(geom::Id e) {
  if (dissolved[static_cast<std::size_t>(e)]) return;
  dissolved[static_cast<std::size_t>(e)] = 1;
  for (int s : eseg[static_cast<std::size_t>(e)]) {
    if (!seg_alive[static_cast<std::size_t>(s)]) continue;
    seg_alive[static_cast<std::size_t>(s)] = 0;
    const auto& g = M.segments[static_cast<std::size_t>(s)];
    for (NodeId n : {g.a, g.b}) {
      if (dim(n) != 1 || ent(n) != e) continue;
      geom::Id f = std::numeric_limits<geom::Id>::max();
      for_tris(n, [&](int t) { f = std::min(f, M.triangle_face[static_cast<std::size_t>(t)]); });
      M.point_dim[static_cast<std::size_t>(n)] = 2;
      M.point_entity[static_cast<std::size_t>(n)] = f;
      M.point_t[static_cast<std::size_t>(n)] = 0.0;
    }
  }
  Simplification s;
  s.what = "edge dissolved";
  s.edges = {e};
  s.faces = efaces[static_cast<std::size_t>(e)];
  s.size = m.edges[static_cast<std::size_t>(e)].length;
  s.why = "dihedral " + fmt(dihedral[static_cast<std::size_t>(e)]) + " deg < feature angle " +
          fmt(in.feature_angle * 180.0 / std::numbers::pi) + " deg";
  log.push_back(std::move(s));
  changed = true;
}

// The log entry of two model vertices made one: the ends of a model edge shorter than L,
// or two corners closer than L / 2 across the faces of the triangles removed.
Simplification Simplifier::vertex_merge(NodeId a, NodeId b, const Plan& p) const {
  Simplification r;
  r.vertices = {ent(a), ent(b)};
  const int s = segment(a, b);
  if (s >= 0) {
    const geom::Id e = M.segments[static_cast<std::size_t>(s)].edge;
    r.what = "edge collapsed to a vertex";
    r.edges = {e};
    r.size = m.edges[static_cast<std::size_t>(e)].length;
    r.why = "length " + fmt(r.size) + " < L/2 = " + fmt(in.collapse_size);
    return r;
  }
  r.what = "vertices merged";
  for (int t : p.removed) r.faces.push_back(M.triangle_face[static_cast<std::size_t>(t)]);
  std::sort(r.faces.begin(), r.faces.end());
  r.faces.erase(std::unique(r.faces.begin(), r.faces.end()), r.faces.end());
  r.size = glm::length(P(a) - P(b));
  r.why = "distance " + fmt(r.size) + " across the face < L/2 = " + fmt(in.collapse_size);
  return r;
}

void Simplifier::apply_collapse(NodeId a, NodeId b, const Plan& p) {
  begin({'c', a, b});
  if (dim(a) == 0) log.push_back(vertex_merge(a, b, p));
  if (p.dissolve) dissolve(ent(a));
  for (int t : p.removed) tri_alive[static_cast<std::size_t>(t)] = 0;
  for (const NewTri& nt : p.tris) write(nt);
  for (int s : nsegs[static_cast<std::size_t>(a)]) {
    if (!seg_alive[static_cast<std::size_t>(s)]) continue;
    auto& g = M.segments[static_cast<std::size_t>(s)];
    if (g.a == b || g.b == b) {
      seg_alive[static_cast<std::size_t>(s)] = 0;
      continue;
    }
    (g.a == a ? g.a : g.b) = b;
    nsegs[static_cast<std::size_t>(b)].push_back(s);
  }
  node_alive[static_cast<std::size_t>(a)] = 0;
  vtris[static_cast<std::size_t>(a)].clear();
  changed = true;
}

bool Simplifier::try_collapse(NodeId a, NodeId b) {
  if (!node_alive[static_cast<std::size_t>(a)] || !node_alive[static_cast<std::size_t>(b)])
    return false;
  Plan ab = plan_collapse(a, b), ba = plan_collapse(b, a);
  if (ab.ok && ba.ok && rank(a) == rank(b) && dim(a) == 0) {
    // Two model vertices: the one on more sharp edges stays (a box corner, not the end
    // of a split line).
    auto sharp_edges = [&](NodeId n) {
      int c = 0;
      for (int s : nsegs[static_cast<std::size_t>(n)])
        c += seg_alive[static_cast<std::size_t>(s)] &&
             sharp[static_cast<std::size_t>(M.segments[static_cast<std::size_t>(s)].edge)];
      return c;
    };
    const int ca = sharp_edges(a), cb = sharp_edges(b);
    if (ca != cb) (ca > cb ? ab : ba).ok = false;
  }
  if (ab.ok && (!ba.ok || ab.worst <= ba.worst)) return apply_collapse(a, b, ab), true;
  if (ba.ok) return apply_collapse(b, a, ba), true;
  return false;
}

// Short edges (below L) and the short edges of needles, shortest first.
bool Simplifier::collapse_pass(const std::vector<int>& cand) {
  std::vector<std::tuple<double, NodeId, NodeId>> edges;
  for (int t : cand) {
    if (!tri_alive[static_cast<std::size_t>(t)]) continue;
    const Tri& v = T(t);
    const double q = Q(t);
    double len[3], longest = 0;
    for (int k = 0; k < 3; ++k)
      longest = std::max(longest, len[k] = glm::length(P(v[(k + 1) % 3]) - P(v[k])));
    for (int k = 0; k < 3; ++k) {
      const bool needle =
          (q > kBadShape && len[k] < 0.5 * longest) || (q > kPoorShape && len[k] < 0.25 * longest);
      if (len[k] < in.collapse_size || needle)
        edges.emplace_back(len[k], std::min(v[k], v[(k + 1) % 3]), std::max(v[k], v[(k + 1) % 3]));
    }
  }
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  bool any = false;
  for (const auto& [len, a, b] : edges)
    if (node_alive[static_cast<std::size_t>(a)] && node_alive[static_cast<std::size_t>(b)] &&
        !edge_tris(a, b).empty())
      any |= try_collapse(a, b);
  return any;
}

// Swap of the edge k of t (corners k, k+1) with the opposite triangle: accepted when the
// worst Q of the two falls below `limit` and below theirs, the two are nearly coplanar
// (a swap across a crease would cut the solid) and the new ones meet the chordal
// tolerance. A smooth model edge under it is dissolved; a sharp one is never swapped.
bool Simplifier::try_flip(int t, int k, double limit) {
  const Tri v = T(t);
  const NodeId b = v[k], c = v[(k + 1) % 3], a = v[(k + 2) % 3];
  const int s = segment(b, c);
  if (s >= 0 && (M.segments[static_cast<std::size_t>(s)].edge < 0 ||
                 sharp[static_cast<std::size_t>(M.segments[static_cast<std::size_t>(s)].edge)]))
    return false;
  const auto on = edge_tris(b, c);
  if (on.size() != 2) return false;
  const int t2 = on[0] == t ? on[1] : on[0];
  const Tri& w = T(t2);
  NodeId d = -1;
  for (NodeId x : w)
    if (x != b && x != c) d = x;
  if (d < 0 || d == a || !edge_tris(a, d).empty() || !allowed(edge_op('f', b, c))) return false;
  const Vec3 n0 = unit_normal(P(b), P(c), P(a)), n1 = unit_normal(P(c), P(b), P(d));
  if (glm::dot(n0, n1) < std::cos(in.feature_angle)) return false;
  const double old_worst = std::max(Q(t), Q(t2));
  NewTri x, y;
  x.slot = t, y.slot = t2;
  x.v = {a, b, d}, y.v = {d, c, a};
  const double nw = std::max(shape(P(a), P(b), P(d)), shape(P(d), P(c), P(a)));
  if (!(nw < old_worst) || !(nw < limit)) return false;
  for (const NewTri* nt : {&x, &y}) {
    const Vec3 n = unit_normal(P(nt->v[0]), P(nt->v[1]), P(nt->v[2]));
    if (glm::dot(n, n0) < kMaxTurn || glm::dot(n, n1) < kMaxTurn) return false;
  }
  // (u,v) hints: the corners' (u,v) in t, or in t2 for d.
  auto uv_in = [&](int tri, NodeId n) {
    const Tri& q = T(tri);
    const int i = q[0] == n ? 0 : (q[1] == n ? 1 : 2);
    return M.triangle_uv[static_cast<std::size_t>(tri)][static_cast<std::size_t>(i)];
  };
  const Vec2 ud =
      M.triangle_face[static_cast<std::size_t>(t)] == M.triangle_face[static_cast<std::size_t>(t2)]
          ? uv_in(t2, d)
          : uv_in(t, a);
  if (!place(x, M.triangle_face[static_cast<std::size_t>(t)], {uv_in(t, a), uv_in(t, b), ud}) ||
      !place(y, M.triangle_face[static_cast<std::size_t>(t)], {ud, uv_in(t, c), uv_in(t, a)}))
    return false;
  begin(edge_op('f', b, c));
  if (s >= 0) dissolve(M.segments[static_cast<std::size_t>(s)].edge);
  write(x);
  write(y);
  return true;
}
void Simplifier::run() {
  init();
  area0.assign(m.faces.size(), 0.0);
  std::vector<int> cand;
  for (std::size_t t = 0; t < M.triangles.size(); ++t) {
    const Tri& v = M.triangles[t];
    area0[static_cast<std::size_t>(M.triangle_face[t])] +=
        0.5 * glm::length(glm::cross(P(v[1]) - P(v[0]), P(v[2]) - P(v[0])));
    double shortest = kInf;
    for (int k = 0; k < 3; ++k)
      shortest = std::min(shortest, glm::length(P(v[(k + 1) % 3]) - P(v[k])));
    start_worst = std::max(start_worst, Q(static_cast<int>(t)));
    if (shortest < in.collapse_size || Q(static_cast<int>(t)) > kPoorShape)
      cand.push_back(static_cast<int>(t));
  }
  for (int round = 0; round < kRounds && !cand.empty(); ++round) {
    touched.clear();
    collapse_pass(cand);
    std::vector<int> next = touched;
    for (int t : cand) next.push_back(t);
    std::sort(next.begin(), next.end());
    next.erase(std::unique(next.begin(), next.end()), next.end());
    // The next round looks at what either pass made, nothing else.
    repair_pass(next);
    relocate_pass(next);
    cand.assign(touched.begin(), touched.end());
    std::sort(cand.begin(), cand.end());
    cand.erase(std::unique(cand.begin(), cand.end()), cand.end());
  }
}

const OpKey& Simplifier::culprit(int t0, int t1) const {
  const int w =
      std::max(writer[static_cast<std::size_t>(t0)], writer[static_cast<std::size_t>(t1)]);
  return ops[static_cast<std::size_t>(w)];
}

std::vector<std::pair<int, int>> Simplifier::crossings() const {
  if (!changed) return {};
  SurfaceMesh alive;
  alive.points = M.points;
  std::vector<int> slot;
  std::vector<char> subset;
  for (std::size_t t = 0; t < M.triangles.size(); ++t) {
    if (!tri_alive[t]) continue;
    slot.push_back(static_cast<int>(t));
    alive.triangles.push_back(M.triangles[t]);
    alive.triangle_face.push_back(M.triangle_face[t]);
    subset.push_back(writer[t] >= 0);
  }
  const IntersectionReport r =
      find_intersections_with(alive, subset, std::numeric_limits<int>::max(), in.threads);
  std::vector<std::pair<int, int>> out;
  for (const IntersectingPair& p : r.pairs)
    out.emplace_back(slot[static_cast<std::size_t>(p.t0)], slot[static_cast<std::size_t>(p.t1)]);
  return out;
}

void Simplifier::finish() {
  if (!changed) return;
  std::vector<char> has_tri(m.faces.size(), 0), has_seg(m.edges.size(), 0),
      logged(m.edges.size(), 0);
  for (std::size_t t = 0; t < M.triangles.size(); ++t)
    if (tri_alive[t]) has_tri[static_cast<std::size_t>(M.triangle_face[t])] = 1;
  for (std::size_t s = 0; s < M.segments.size(); ++s)
    if (seg_alive[s] && M.segments[s].edge >= 0)
      has_seg[static_cast<std::size_t>(M.segments[s].edge)] = 1;
  for (const Simplification& r : log)
    for (geom::Id e : r.edges) logged[static_cast<std::size_t>(e)] = 1;
  for (std::size_t e = 0; e < m.edges.size(); ++e)
    if (!eseg[e].empty() && !has_seg[e] && !logged[e]) {
      Simplification r;
      r.what = "edge collapsed to a vertex";
      r.edges = {static_cast<geom::Id>(e)};
      r.vertices = {m.edges[e].v0, m.edges[e].v1};
      r.size = m.edges[e].length;
      r.why = "its nodes merged with those of shorter edges around it (length " + fmt(r.size) + ")";
      log.push_back(std::move(r));
    }
  for (std::size_t f = 0; f < m.faces.size(); ++f) {
    if (!(area0[f] > 0) || has_tri[f]) continue;
    double perimeter = 0;
    for (const geom::Loop& l : m.faces[f].loops)
      for (const geom::EdgeUse& u : l.uses)
        perimeter += m.edges[static_cast<std::size_t>(u.edge)].length;
    Simplification r;
    r.what = "face absorbed";
    r.faces = {static_cast<geom::Id>(f)};
    r.size = perimeter > 0 ? 2 * area0[f] / perimeter : 0.0;
    r.why = "width " + fmt(r.size) +
            " (twice its area over its perimeter) against L/2 = " + fmt(in.collapse_size);
    log.push_back(std::move(r));
  }
  compact();
}

// Dead triangles, segments and nodes dropped; the order of surface_mesh.h kept: vertex
// nodes, edge nodes by edge and parameter, face nodes by face; triangles and segments
// by face and edge (stable: the order they had within one).
void Simplifier::compact() {
  const std::size_t nn = M.points.size();
  std::vector<char> used(nn, 0);
  for (std::size_t t = 0; t < M.triangles.size(); ++t)
    if (tri_alive[t])
      for (NodeId v : M.triangles[t]) used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t s = 0; s < M.segments.size(); ++s)
    if (seg_alive[s])
      used[static_cast<std::size_t>(M.segments[s].a)] =
          used[static_cast<std::size_t>(M.segments[s].b)] = 1;
  std::vector<NodeId> order;
  for (std::size_t i = 0; i < nn; ++i)
    if (used[i]) order.push_back(static_cast<NodeId>(i));
  std::stable_sort(order.begin(), order.end(), [&](NodeId x, NodeId y) {
    const auto kx =
        std::make_tuple(dim(x), ent(x), dim(x) == 1 ? M.point_t[static_cast<std::size_t>(x)] : 0.0);
    const auto ky =
        std::make_tuple(dim(y), ent(y), dim(y) == 1 ? M.point_t[static_cast<std::size_t>(y)] : 0.0);
    return kx < ky;
  });
  std::vector<NodeId> nid(nn, -1);
  SurfaceMesh out;
  for (NodeId o : order) {
    nid[static_cast<std::size_t>(o)] = static_cast<NodeId>(out.points.size());
    out.points.push_back(P(o));
    out.point_dim.push_back(static_cast<std::int8_t>(dim(o)));
    out.point_entity.push_back(ent(o));
    out.point_t.push_back(M.point_t[static_cast<std::size_t>(o)]);
  }
  std::vector<int> tris;
  for (std::size_t t = 0; t < M.triangles.size(); ++t)
    if (tri_alive[t]) tris.push_back(static_cast<int>(t));
  std::stable_sort(tris.begin(), tris.end(), [&](int x, int y) {
    return M.triangle_face[static_cast<std::size_t>(x)] <
           M.triangle_face[static_cast<std::size_t>(y)];
  });
  for (int t : tris) {
    Tri v = T(t);
    for (NodeId& x : v) x = nid[static_cast<std::size_t>(x)];
    out.triangles.push_back(v);
    out.triangle_face.push_back(M.triangle_face[static_cast<std::size_t>(t)]);
    out.triangle_uv.push_back(M.triangle_uv[static_cast<std::size_t>(t)]);
  }
  std::vector<std::pair<std::pair<geom::Id, double>, int>> segs;
  for (std::size_t s = 0; s < M.segments.size(); ++s) {
    if (!seg_alive[s]) continue;
    const auto& g = M.segments[s];
    double key = 0;
    if (g.edge >= 0 && m.edges[static_cast<std::size_t>(g.edge)].curve) {
      const double ta =
          node_param(g.a, g.edge, dim(g.b) == 1 ? M.point_t[static_cast<std::size_t>(g.b)] : 0.0);
      key = ta + node_param(g.b, g.edge, ta);
    }
    segs.push_back({{g.edge, key}, static_cast<int>(s)});
  }
  std::stable_sort(segs.begin(), segs.end(),
                   [](const auto& x, const auto& y) { return x.first < y.first; });
  for (const auto& [k, s] : segs) {
    auto g = M.segments[static_cast<std::size_t>(s)];
    g.a = nid[static_cast<std::size_t>(g.a)], g.b = nid[static_cast<std::size_t>(g.b)];
    out.segments.push_back(g);
  }
  M = std::move(out);
}

}  // namespace simplify_impl

using simplify_impl::OpKey;
using simplify_impl::Simplifier;

std::vector<char> user_sized_edges(const geom::Model& m, const param::SizeSpec& spec) {
  std::vector<char> kept(m.edges.size(), 0);
  for (const auto& [e, h] : spec.edge_size)
    if (e >= 0 && static_cast<std::size_t>(e) < kept.size()) kept[static_cast<std::size_t>(e)] = 1;
  for (const auto& [f, h] : spec.face_size)
    if (f >= 0 && static_cast<std::size_t>(f) < m.faces.size())
      for (const geom::Loop& l : m.faces[static_cast<std::size_t>(f)].loops)
        for (const geom::EdgeUse& u : l.uses)
          if (u.edge >= 0 && static_cast<std::size_t>(u.edge) < kept.size())
            kept[static_cast<std::size_t>(u.edge)] = 1;
  return kept;
}

namespace {

constexpr int kGuardRuns = 8;

// The log entry of a run redone because its triangles crossed others.
Simplification crossing_entry(const SurfaceMesh& mesh, const std::vector<std::pair<int, int>>& x,
                              const std::set<OpKey>& refused) {
  Simplification r;
  r.what = "operations refused";
  for (const auto& [a, b] : x)
    for (int t : {a, b}) r.faces.push_back(mesh.triangle_face[static_cast<std::size_t>(t)]);
  std::sort(r.faces.begin(), r.faces.end());
  r.faces.erase(std::unique(r.faces.begin(), r.faces.end()), r.faces.end());
  r.size = static_cast<double>(x.size());
  std::map<char, int> kinds;
  for (const OpKey& k : refused) ++kinds[std::get<0>(k)];
  const std::map<char, const char*> name{
      {'c', "collapses"}, {'f', "swaps"}, {'s', "splits"}, {'r', "relocations"}};
  r.why = std::to_string(x.size()) +
          " pairs of triangles would intersect (parts closer than the feature size); not done:";
  for (const auto& [k, n] : kinds) r.why += " " + std::to_string(n) + " " + name.at(k);
  return r;
}

}  // namespace

// The guard against crossings: a run whose triangles intersect others (two solids in near
// contact, a fold of the surface) is done again from the given mesh without the
// operations that made those triangles. A run repeats the earlier one exactly up to the
// first operation refused (the stage is deterministic), so every run refuses at least one
// operation more than the last.
std::vector<Simplification> simplify_mesh(const SimplifyInput& in, SurfaceMesh& mesh) {
  if (!(in.collapse_size > 0) || mesh.triangles.empty()) return {};
  const SurfaceMesh given = mesh;
  std::set<OpKey> forbidden;
  std::vector<Simplification> log;
  for (int run = 0;; ++run) {
    Simplifier s(in, mesh, forbidden);
    s.run();
    const auto x = s.crossings();
    if (x.empty()) {
      s.finish();
      for (auto& r : s.log) log.push_back(std::move(r));
      return log;
    }
    std::set<OpKey> refused;
    for (const auto& [a, b] : x) refused.insert(s.culprit(a, b));
    log.push_back(crossing_entry(mesh, x, refused));
    forbidden.insert(refused.begin(), refused.end());
    mesh = given;
    if (run + 1 == kGuardRuns) {
      log.back().why +=
          "; still crossing after " + std::to_string(kGuardRuns) + " runs: the stage is undone";
      return log;
    }
  }
}

void simplify(ModelRun& run) {
  // Entities shorter than half the feature size are collapsed. Between half and the whole
  // of it they set no size but are kept: a mesh at the smallest size hmin (= L by
  // default) has unit edges down to hmin / sqrt2, which are the user's elements, not
  // artefacts, and a sliver face half as wide as its elements are long is fairly shaped.
  const double half = 0.5 * feature_size(run.opt, run.m.bbox);
  const SimplifyInput in{run.m,
                         half,
                         run.spec.chordal_tol,
                         run.opt.feature_angle,
                         user_sized_edges(run.m, run.spec),
                         run.opt.threads};
  auto log = simplify_mesh(in, run.res.mesh);
  for (auto& r : log) run.res.simplified.push_back(std::move(r));
}

}  // namespace uvmesh::surface::detail
