// Stage 2, one face (reference chapter §7.6.2): the (u,v) PSLG is built from the edge
// nodes through each use's pcurve at the same curve parameters (never by projection,
// face_pslg.cpp); mesher2d meshes it under the induced metric M_uv = J^T M3 J (the face
// metric, face_metric.h); the vertices are mapped back through sigma and the mesh is
// improved in 3D and repaired (face_repair.cpp). Uses whose pcurves disagree with their
// 3D edges -- before meshing, or where mesher2d finds two (u,v) curves crossing -- get the
// (u,v) of their nodes' projections instead (face_uv_repair.cpp). A face whose (u,v)
// boundary is still unusable may be triangulated from its boundary nodes
// (face_from_boundary.cpp), but first, where the face is a graph over the least-squares
// plane of its boundary nodes, it is meshed in that plane (face_chart.cpp).
#include <cmath>
#include <sstream>

#include "face_metric.h"
#include "face_stage.h"
#include "uvmesh/mesher2d/measures.h"

namespace uvmesh::surface::detail {

namespace {

std::string fmt_uv(const geom::Vec2& p) {
  std::ostringstream o;
  o.precision(9);
  o << "(" << p.x << ", " << p.y << ")";
  return o.str();
}

void improve_and_repair(const FaceInput& job, bool has_pole, LocalMesh& lm, FaceStats& stats);
void count_unit_edges(const LocalMesh& lm, std::size_t nvf, const FaceMetric& metric,
                      FaceStats& stats);
void write_face_mesh(const LocalMesh& lm, std::size_t nvf, bool reversed, FaceMesh& out);

// Triangles of lm that are not CCW in (u,v).
int inverted_in_uv(const LocalMesh& lm) {
  int n = 0;
  for (const auto& t : lm.tris) {
    const geom::Vec2 &a = lm.uv[t[0]], &b = lm.uv[t[1]], &c = lm.uv[t[2]];
    n += !((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0);
  }
  return n;
}

// The plane chart (face_chart.cpp) on the last try; true: out is the face's mesh, with
// the warning in FaceMesh::repair. The 3D improvement and the repairs move and split
// vertices in (u,v), keeping triangles CCW there: they run only when every chart
// triangle is CCW at the (u,v) of its corners' feet.
bool mesh_by_chart(const FaceInput& job, const FacePslg& pslg, FaceMesh& out,
                   const std::string& msg, std::string& why) {
  LocalMesh lm;
  double dev = 0;
  if (!mesh_in_plane_chart(job, pslg, lm, dev, why)) return false;
  FaceMesh res;
  res.stats.face = job.fid;
  res.stats.boundary_nodes = out.stats.boundary_nodes;
  const bool has_pole = face_has_pole(job.m, job.f);
  const int inverted = inverted_in_uv(lm);
  if (inverted == 0) improve_and_repair(job, has_pole, lm, res.stats);
  const std::size_t nvf = lm.uv.size();
  if (inverted == 0) remove_folds(lm);
  const FaceMetric metric(job.field, job.f, has_pole);
  count_unit_edges(lm, nvf, metric, res.stats);
  write_face_mesh(lm, nvf, job.f.reversed, res);
  std::ostringstream o;
  o.precision(3);
  o << "its (u,v) boundary is unusable (" << msg
    << "); meshed in a least-squares plane chart (surface normals within " << dev
    << " degrees of the plane's normal)";
  if (inverted > 0)
    o << "; 3D improvement skipped (" << inverted << " triangles inverted in (u,v))";
  res.repair = o.str();
  out = std::move(res);
  return true;
}

// An unusable (u,v) boundary, on the last try (mesher.cpp): the face is meshed in the
// least-squares plane of its boundary (mesh_by_chart) or else, with one loop,
// triangulated from its boundary nodes when that is a manifold disc within the chordal
// tolerance (triangulate_from_boundary); else the reasons are added to the failure.
void fail_on_uv(const FaceInput& job, const FacePslg& pslg, FaceMesh& out, std::string msg) {
  if (job.boundary_fallback) {
    std::string why;
    if (mesh_by_chart(job, pslg, out, msg, why)) return;
    msg += "; not meshed in a least-squares plane chart: " + why;
  }
  if (job.boundary_fallback && pslg.one_loop) {
    std::vector<geom::Vec2> uv_raw(pslg.in.points.size());
    for (std::size_t i = 0; i < uv_raw.size(); ++i)
      uv_raw[i] = {pslg.in.points[i].x, pslg.in.points[i].y};
    std::string why;
    if (triangulate_from_boundary(out, job.f, job.s, pslg.gid, uv_raw, job.node_points,
                                  job.opt.size.chordal_tol, &why)) {
      out.repair = msg.substr(msg.find("not meshed in a least-squares plane chart"));
      out.stats.face = job.fid;
      out.error.clear();
      out.refine_at.clear();
      return;
    }
    msg += "; not triangulated from its boundary either: " + why;
  }
  out.error = std::move(msg);
  out.uv_defect = true;  // worth the last try (mesher.cpp) when it was not this one
}

// mesher2d failed: the message names the model edges; crossing (u,v) curves also name
// the pieces of edges to split (FaceMesh::refine_at). A defect of the (u,v) boundary may
// still be triangulated from the boundary (fail_on_uv).
void fail_in_mesher2d(const FaceInput& job, const FacePslg& pslg, const m2d::Result& r,
                      FaceMesh& out) {
  std::string msg = r.status.message;
  if (r.status.code == m2d::StatusCode::CrossingSegments && r.status.entities.size() >= 2) {
    const auto e0 = pslg.sedge[static_cast<std::size_t>(r.status.entities[0])];
    const auto e1 = pslg.sedge[static_cast<std::size_t>(r.status.entities[1])];
    msg = "the (u,v) curves of edges " + std::to_string(e0) + " and " + std::to_string(e1) +
          " cross (" + msg + ")";
    for (int k = 0; k < 2; ++k) {
      const auto sg = static_cast<std::size_t>(r.status.entities[static_cast<std::size_t>(k)]);
      if (std::isfinite(pslg.spiece[sg][0]) && std::isfinite(pslg.spiece[sg][1]))
        out.refine_at.push_back({pslg.sedge[sg], 0.5 * (pslg.spiece[sg][0] + pslg.spiece[sg][1])});
    }
  }
  msg = "2D mesher: " + msg;
  if (r.status.code == m2d::StatusCode::CrossingSegments ||
      r.status.code == m2d::StatusCode::OpenBoundary ||
      r.status.code == m2d::StatusCode::InvalidInput)
    return fail_on_uv(job, pslg, out, std::move(msg));
  out.error = std::move(msg);
}

// Retries of mesher2d after a crossing of (u,v) curves was repaired: each failure names
// one pair of crossing segments.
constexpr int kCrossingRepairs = 8;

// A use whose nodes lie farther than this many CAD tolerances from sigma at their (u,v)
// has its (u,v) recomputed before meshing (face_uv_repair.cpp); a use whose (u,v)
// polyline crosses another's, beyond its tolerance at all.
constexpr double kDisagreeFactor = 100.0;
constexpr double kCrossingFactor = 1.0;

// mesher2d under the face metric, in its v-scaled frame.
m2d::Result run_mesher2d(const FaceInput& job, const FacePslg& pslg, FaceMetric& metric) {
  m2d::Pslg in = pslg.in;
  for (auto& p : in.points) p = metric.to_mesher(p);
  m2d::Options o;
  o.split_segments = false;          // edge nodes are owned by the model edges
  o.domain_from_orientation = true;  // outer loop CCW, holes CW in (u,v)
  FaceMetric::mesher_options(job.opt, o);
  // The (u,v) metric is a sampled lower bound on the density the chordal tolerance needs
  // (the chordal repair below only adds points): mesher2d's size pass may split long
  // edges but must not collapse short ones.
  o.collapse_short_edges = false;
  o.time_limit = job.opt.face_time_limit;
  o.measure = false;  // the face's quality is measured in 3D below, not in the (u,v) metric
  return m2d::mesh(in, metric.mesher_size(), o);
}

// The model edges of the two crossing segments mesher2d named, or none.
std::vector<geom::Id> crossing_edges(const FacePslg& pslg, const m2d::Result& r) {
  if (r.status.code != m2d::StatusCode::CrossingSegments || r.status.entities.size() < 2) return {};
  return {pslg.sedge[static_cast<std::size_t>(r.status.entities[0])],
          pslg.sedge[static_cast<std::size_t>(r.status.entities[1])]};
}

// ---- mesher2d; where two (u,v) curves cross, their uses' (u,v) are repaired from the
// 3D nodes when they disagree with them (repair_uv_boundary) and the face is meshed
// again. False: the face failed (out says why).
bool mesh_in_uv(const FaceInput& job, FacePslg& pslg, FaceMetric& metric, UvRepair& rep,
                m2d::Result& r, FaceMesh& out) {
  r = run_mesher2d(job, pslg, metric);
  for (int k = 0; k < kCrossingRepairs && !r.ok(); ++k) {
    const std::vector<geom::Id> pair = crossing_edges(pslg, r);
    if (pair.empty() || repair_uv_boundary(job, pslg, pair, kCrossingFactor, rep) == 0) break;
    rep.crossing = true;
    r = run_mesher2d(job, pslg, metric);
  }
  if (!r.ok()) {
    fail_in_mesher2d(job, pslg, r, out);
    return false;
  }
  if (r.stats.segments_split_at_vertices > 0) {
    fail_on_uv(job, pslg, out,
               "a boundary node lies on another edge's (u,v) segment; the face would not conform");
    return false;
  }
  return true;
}

// Boundary vertices of mesher2d's mesh are global nodes, fixed. False (out says why) when
// an input point was lost or two nodes fell on one vertex.
bool bind_boundary_nodes(const FaceInput& job, const FacePslg& pslg, const m2d::Mesh& mm,
                         LocalMesh& lm, FaceMesh& out) {
  const std::vector<m2d::Vec2>& uv_in = pslg.in.points;
  for (std::size_t i = 0; i < uv_in.size(); ++i) {
    const m2d::VertId v = mm.input_vertex[i];
    if (v == m2d::kNone) {
      fail_on_uv(job, pslg, out,
                 "boundary node at " + fmt_uv({uv_in[i].x, uv_in[i].y}) + " of edge " +
                     std::to_string(pslg.pedge[i]) +
                     " lies outside the face's (u,v) domain (loop orientation?)");
      return false;
    }
    const auto vi = static_cast<std::size_t>(v);
    if (lm.global[vi] >= 0 && lm.global[vi] != pslg.gid[i]) {
      fail_on_uv(job, pslg, out,
                 "nodes " + std::to_string(lm.global[vi]) + " and " + std::to_string(pslg.gid[i]) +
                     " (edges " + std::to_string(pslg.pedge[i]) + ") coincide in (u,v) at " +
                     fmt_uv({uv_in[i].x, uv_in[i].y}));
      return false;
    }
    lm.global[vi] = pslg.gid[i];
    lm.fixed[vi] = 1;
  }
  return true;
}

// ---- map back: boundary vertices are global nodes; the others are new points on sigma.
// Each vertex keeps the scale mesher2d applied to the field there (Mesh::boundary_scale).
bool map_back(const FaceInput& job, const FacePslg& pslg, const FaceMetric& metric,
              const m2d::Mesh& mm, LocalMesh& lm, FaceMesh& out) {
  const std::size_t nv = mm.vertices.size();
  lm.uv.resize(nv);
  lm.p.resize(nv);
  lm.global.assign(nv, -1);
  lm.fixed.assign(nv, 0);
  if (!bind_boundary_nodes(job, pslg, mm, lm, out)) return false;
  lm.scale.assign(nv, 1.0);
  for (std::size_t v = 0; v < nv; ++v) {
    lm.uv[v] = metric.from_mesher(mm.vertices[v]);
    if (v < mm.boundary_scale.size()) lm.scale[v] = mm.boundary_scale[v];
    lm.p[v] = lm.global[v] >= 0 ? job.node_points[static_cast<std::size_t>(lm.global[v])]
                                : job.s.point(lm.uv[v].x, lm.uv[v].y);
  }
  // Boundary nodes keep their exact (u,v), not the round trip through the v scaling.
  const std::vector<m2d::Vec2>& uv_in = pslg.in.points;
  for (std::size_t i = 0; i < uv_in.size(); ++i)
    lm.uv[static_cast<std::size_t>(mm.input_vertex[i])] = {uv_in[i].x, uv_in[i].y};
  lm.tris.reserve(mm.triangles.size());
  for (const auto& t : mm.triangles) {
    // At a pole two (u,v) points are one node: that triangle is an edge in 3D.
    const NodeId g0 = lm.global[static_cast<std::size_t>(t[0])],
                 g1 = lm.global[static_cast<std::size_t>(t[1])],
                 g2 = lm.global[static_cast<std::size_t>(t[2])];
    if (g0 >= 0 && (g0 == g1 || g0 == g2)) continue;
    if (g1 >= 0 && g1 == g2) continue;
    lm.tris.push_back({t[0], t[1], t[2]});
  }
  return true;
}

// ---- 3D improvement, then the repairs (face_repair.cpp).
void improve_and_repair(const FaceInput& job, bool has_pole, LocalMesh& lm, FaceStats& stats) {
  if (job.opt.optimize3d) {
    const auto [sw, mv] = improve3d(lm, job.s, job.opt.optimize3d_passes);
    stats.swaps3d = sw;
    stats.moves3d = mv;
  }
  repair_chordal(job, lm, stats);
  if (has_pole) repair_flat_apex(job, lm, stats);
}

// ---- unit edges, measured in this face's metric (the field scaled as mesher2d did),
// over the first nvf vertices (those of the repairs included).
void count_unit_edges(const LocalMesh& lm, std::size_t nvf, const FaceMetric& metric,
                      FaceStats& stats) {
  std::vector<param::Metric3> m3(nvf);
  std::vector<char> has(nvf, 0);
  auto metric_at = [&](int v) -> const param::Metric3& {
    if (!has[v]) m3[v] = metric.metric3(lm.uv[v], lm.scale[v]), has[v] = 1;
    return m3[v];
  };
  // Each edge once. An edge of two triangles is seen from both: counted from the one
  // where it runs a < b; an edge of one triangle (on the face's boundary) always. Both
  // ends on the boundary does not make an edge a boundary edge: a chord across a
  // narrow face joins two boundary nodes and has two triangles (counted twice before,
  // which weighed a strip of chords double).
  const EdgeUses uses(lm);
  measures::UnitEdges u;
  for (const auto& t : lm.tris)
    for (int i = 0; i < 3; ++i) {
      const int a = t[i], b = t[(i + 1) % 3];
      if (a > b) {
        const auto [lo, hi] = uses.of(a, b);
        if (hi - lo > 1) continue;
      }
      const geom::Vec3 d = lm.p[b] - lm.p[a];
      u.add(measures::edge_length(metric_at(a).length(d), metric_at(b).length(d)));
    }
  stats.edges += u.edges;
  stats.unit_edges += u.unit;
  stats.short_edges += u.short_edges;
  stats.long_edges += u.long_edges;
}

// ---- the face's contribution: interior points renumbered -(k+1) in local order.
void write_face_mesh(const LocalMesh& lm, std::size_t nvf, bool reversed, FaceMesh& out) {
  std::vector<NodeId> ref(nvf, 0);
  std::vector<char> used(nvf, 0);
  for (const auto& t : lm.tris)
    for (int v : t) used[static_cast<std::size_t>(v)] = 1;
  for (std::size_t v = 0; v < nvf; ++v) {
    if (!used[v]) continue;  // e.g. the tip of a removed fold
    if (lm.global[v] >= 0) {
      ref[v] = lm.global[v];
    } else {
      ref[v] = -static_cast<NodeId>(out.points.size()) - 1;
      out.points.push_back(lm.p[v]);
    }
  }
  out.tris.reserve(lm.tris.size());
  out.tri_uv.reserve(lm.tris.size());
  for (const auto& t : lm.tris) {
    // Triangles are CCW in (u,v), so their normal is sigma_u x sigma_v; a reversed face
    // has its material on the other side.
    std::array<int, 3> c = t;
    if (reversed) std::swap(c[1], c[2]);
    out.tris.push_back({ref[c[0]], ref[c[1]], ref[c[2]]});
    out.tri_uv.push_back({lm.uv[c[0]], lm.uv[c[1]], lm.uv[c[2]]});
  }
  out.stats.triangles = static_cast<int>(out.tris.size());
}

}  // namespace

FaceMesh mesh_face(const geom::Model& m, geom::Id fid, const std::vector<EdgeNodes>& edges,
                   const std::vector<geom::Vec3>& node_points, const param::FaceSizeField& field,
                   const MeshOptions& opt, bool boundary_fallback) {
  FaceMesh out;
  out.stats.face = fid;
  const geom::Face& f = m.faces[static_cast<std::size_t>(fid)];
  const FaceInput job{m, fid, f, *f.surface, edges, node_points, field, opt, boundary_fallback};

  FacePslg pslg;
  if (!build_face_pslg(job, pslg, out.error)) return out;
  out.stats.boundary_nodes = static_cast<int>(pslg.in.points.size());
  if (!check_face_pslg(pslg, out.error)) return out;

  const bool has_pole = face_has_pole(m, f);
  UvRepair rep;
  repair_uv_boundary(job, pslg, {}, kDisagreeFactor, rep);
  FaceMetric metric(field, f, has_pole);
  m2d::Result r;
  if (!mesh_in_uv(job, pslg, metric, rep, r, out)) return out;
  if (!rep.edges.empty() || !rep.shifted.empty()) out.repair = rep.describe();
  LocalMesh lm;
  if (!map_back(job, pslg, metric, r.mesh, lm, out)) return out;

  improve_and_repair(job, has_pole, lm, out.stats);
  const std::size_t nvf = lm.uv.size();  // with the points of the chordal repair
  remove_folds(lm);
  count_unit_edges(lm, nvf, metric, out.stats);
  write_face_mesh(lm, nvf, f.reversed, out);
  return out;
}

}  // namespace uvmesh::surface::detail
