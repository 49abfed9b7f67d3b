// Stage 2 of mesh_model: curves and faces, repeated when a face's (u,v) boundary crossed
// itself. The edges named are refined (their (u,v) polylines then follow the pcurves more
// closely) and the model is meshed again -- edge nodes are shared, so every face must see
// them. What stays unusable after the rounds gets a last try: in the least-squares plane
// of its boundary (face_chart.cpp), else from its boundary nodes.
#include <algorithm>
#include <atomic>
#include <set>

#include "model_run.h"

namespace uvmesh::surface::detail {

namespace {

// Rounds of splitting edge pieces whose (u,v) polylines cross (each re-meshes the model).
constexpr int kCrossingRounds = 8;

NodeId add_point(SurfaceMesh& M, const geom::Vec3& p, int dim, geom::Id ent, double t) {
  M.points.push_back(p);
  M.point_dim.push_back(static_cast<std::int8_t>(dim));
  M.point_entity.push_back(ent);
  M.point_t.push_back(t);
  return static_cast<NodeId>(M.points.size() - 1);
}

// Edge e's nodes and segments (a collapsed strip's secondary: its ends only).
void number_edge(ModelRun& run, std::size_t e) {
  SurfaceMesh& M = run.res.mesh;
  const geom::Edge& ed = run.m.edges[e];
  auto& en = run.edges[e];
  const std::size_t n = en.t.size();
  en.node.resize(n);
  auto end_node = [&](geom::Id v, double t) {
    if (v != geom::kNone) return static_cast<NodeId>(v);
    // An edge without a vertex (rare CAD): its end becomes an edge node.
    return add_point(M, ed.curve ? ed.curve->point(t) : geom::Vec3(0.0), 1,
                     static_cast<geom::Id>(e), t);
  };
  en.node.front() = end_node(ed.v0, en.t.front());
  if (ed.degenerate) {
    for (auto& x : en.node) x = en.node.front();
    return;
  }
  if (!run.on_face[e]) {
    // A loose edge (wireframe geometry in a STEP file, not bounding any face) is not
    // part of the surface: no nodes, no segments; its vertices go if nothing uses them.
    en.node.back() = ed.v1 != geom::kNone ? static_cast<NodeId>(ed.v1) : en.node.front();
    return;
  }
  if (run.primary_of[e] != geom::kNone) return;  // its primary's nodes, number_nodes()
  for (std::size_t i = 1; i + 1 < n; ++i)
    en.node[i] = add_point(M, ed.curve->point(en.t[i]), 1, static_cast<geom::Id>(e), en.t[i]);
  en.node.back() =
      ed.v1 == ed.v0 && ed.v0 == geom::kNone ? en.node.front() : end_node(ed.v1, en.t.back());
  for (std::size_t i = 0; i + 1 < n; ++i)
    M.segments.push_back({en.node[i], en.node[i + 1], static_cast<geom::Id>(e)});
}

// Global numbering (surface_mesh.h): model vertices, then edge interiors in order.
void number_nodes(ModelRun& run) {
  run.res.mesh = {};
  for (std::size_t v = 0; v < run.nv; ++v)
    add_point(run.res.mesh, run.m.vertices[v].p, 0, static_cast<geom::Id>(v), 0.0);
  for (std::size_t e = 0; e < run.ne; ++e) number_edge(run, e);
  // A collapsed strip's secondary edge: the primary's nodes in its own direction, and no
  // segments of its own (they would be the primary's again).
  for (std::size_t e = 0; e < run.ne; ++e) {
    if (run.primary_of[e] == geom::kNone) continue;
    const auto pe = static_cast<std::size_t>(run.primary_of[e]);
    const std::vector<NodeId>& pn = run.edges[pe].node;
    auto& sn = run.edges[e].node;
    sn.assign(pn.begin(), pn.end());
    if (run.m.edges[pe].v0 != run.m.edges[e].v0) std::reverse(sn.begin(), sn.end());
  }
}

// Every face to mesh, in parallel; each face only touches its own surface and pcurves.
void mesh_all_faces(ModelRun& run) {
  run.fm.assign(run.nf, {});
  std::atomic<int> done{0};
  const std::vector<geom::Vec3>& node_points = run.res.mesh.points;
  parallel_indices(run.arena, run.nf, [&](std::size_t f) {
    if (!run.face_error[f].empty() || run.twin_of[f] != geom::kNone || run.m.faces[f].degenerate ||
        run.collapsed[f])
      return;
    const auto tf = Clock::now();
    // A face's size field lives while its face is meshed only (memory: one grid per face
    // of a model with thousands of faces); a later crossing round builds it again.
    if (!run.fields[f]) run.build_field(f);
    FaceMesh& F = run.fm[f];
    try {
      if (run.fields[f])
        F = mesh_face(run.m, static_cast<geom::Id>(f), run.edges, node_points, *run.fields[f],
                      run.opt);
    } catch (...) {
      F = {};
      F.error = "an exception was raised while evaluating the face's geometry";
    }
    run.fields[f].reset();
    F.stats.face = static_cast<geom::Id>(f);
    F.stats.seconds = seconds_since(tf);
    if (!F.error.empty()) run.face_error[f] = F.error;
    const int d = ++done;
    if (run.opt.progress) run.opt.progress(d, static_cast<int>(run.nf));
  });
}

// A secondary's piece is its primary's piece of the same index (counted from the other
// end when they run opposite ways): (e, t) becomes the primary and the piece's middle.
// False when t is outside the secondary's pieces.
bool to_primary_piece(const ModelRun& run, geom::Id& e, double& t) {
  const auto ei = static_cast<std::size_t>(e);
  const auto& st = run.edges[ei].t;
  const auto it = std::upper_bound(st.begin(), st.end(), t);
  if (it == st.begin() || it == st.end()) return false;
  const auto i = static_cast<std::size_t>(it - st.begin() - 1);
  const auto pe = static_cast<std::size_t>(run.primary_of[ei]);
  const auto& pt = run.edges[pe].t;
  const std::size_t k = run.m.edges[pe].v0 == run.m.edges[ei].v0 ? i : pt.size() - 2 - i;
  t = 0.5 * (pt[k] + pt[k + 1]);
  e = static_cast<geom::Id>(pe);
  return true;
}

// Only the crossing pieces are split (each round halves them), so that two pcurves
// meeting at a small angle get nodes close enough to the vertex to part before it
// without refining the whole edge 2^rounds times. (Splitting whole edges made new
// crossings elsewhere, although on some models it happened to clear faces that
// pieces alone do not.) Returns the edges split.
std::set<geom::Id> split_crossing_pieces(ModelRun& run,
                                         const std::set<std::pair<geom::Id, double>>& refine) {
  std::set<geom::Id> touched;
  for (auto [e, t] : refine) {
    if (run.m.edges[static_cast<std::size_t>(e)].degenerate) continue;
    if (run.primary_of[static_cast<std::size_t>(e)] != geom::kNone && !to_primary_piece(run, e, t))
      continue;  // sync_secondaries() follows
    auto& ts = run.edges[static_cast<std::size_t>(e)].t;
    const auto it = std::lower_bound(ts.begin(), ts.end(), t);
    if (it == ts.begin() || it == ts.end() || *it == t) continue;
    ts.insert(it, t);
    touched.insert(e);
  }
  return touched;
}

// Faces whose (u,v) boundary stayed unusable after the crossing rounds: a last try
// that may triangulate them from their boundary nodes (face.cpp,
// triangulate_from_boundary). The edges are final, so the nodes are the ones the
// neighbouring faces use.
void retry_from_boundary(ModelRun& run) {
  std::vector<std::size_t> retry;
  for (std::size_t f = 0; f < run.nf; ++f)
    // Only (u,v) boundary failures: any other (no surface, a time limit) would be
    // meshed again for nothing.
    if (run.fm[f].uv_defect && !run.fm[f].error.empty() && run.fm[f].error == run.face_error[f] &&
        run.twin_of[f] == geom::kNone)
      retry.push_back(f);
  const std::vector<geom::Vec3>& node_points = run.res.mesh.points;
  parallel_indices(run.arena, retry.size(), [&](std::size_t k) {
    const std::size_t f = retry[k];
    const auto tf = Clock::now();
    if (!run.fields[f]) run.build_field(f);
    FaceMesh r;
    try {
      if (run.fields[f])
        r = mesh_face(run.m, static_cast<geom::Id>(f), run.edges, node_points, *run.fields[f],
                      run.opt, true);
    } catch (...) {
      r = {};
      r.error = run.fm[f].error;
    }
    run.fields[f].reset();
    r.stats.face = static_cast<geom::Id>(f);
    r.stats.seconds = run.fm[f].stats.seconds + seconds_since(tf);
    if (r.error.empty())
      run.face_error[f].clear();
    else
      run.face_error[f] = r.error;
    run.fm[f] = std::move(r);
  });
  for (std::size_t f : retry)
    if (run.fm[f].from_boundary)
      run.res.warnings.push_back(
          "face " + std::to_string(f) +
          ": its (u,v) boundary is unusable (pcurves cross or coincide); triangulated from its " +
          std::to_string(run.fm[f].stats.boundary_nodes) +
          " boundary nodes, within the chordal tolerance" +
          (run.fm[f].repair.empty() ? "" : " (" + run.fm[f].repair + ")"));
}

}  // namespace

double mesh_faces(ModelRun& run, Clock::time_point t_curves) {
  const std::vector<std::string> pre_error = run.face_error;
  double t_faces = 0;
  for (int round = 0;; ++round) {
    run.face_error = pre_error;
    number_nodes(run);
    if (round == 0) run.res.stages.push_back({"curves", seconds_since(t_curves)});
    const auto t0 = Clock::now();
    mesh_all_faces(run);
    t_faces += seconds_since(t0);
    std::set<std::pair<geom::Id, double>> refine;
    for (const auto& F : run.fm) refine.insert(F.refine_at.begin(), F.refine_at.end());
    if (refine.empty() || round == kCrossingRounds) break;
    const std::set<geom::Id> touched = split_crossing_pieces(run, refine);
    if (touched.empty()) break;
    sync_secondaries(run);
    run.res.warnings.push_back("round " + std::to_string(round + 1) + ": " +
                               std::to_string(refine.size()) + " piece(s) of " +
                               std::to_string(touched.size()) +
                               " edge(s) split where (u,v) boundaries crossed; model meshed again");
  }
  const auto t0 = Clock::now();
  retry_from_boundary(run);
  // Faces meshed after their (u,v) boundary was repaired (face_uv_repair.cpp) or in a
  // plane chart (face_chart.cpp), once each, as the last round meshed them (a face
  // triangulated from its boundary said so above).
  for (std::size_t f = 0; f < run.nf; ++f)
    if (run.fm[f].error.empty() && !run.fm[f].repair.empty() && !run.fm[f].from_boundary)
      run.res.warnings.push_back("face " + std::to_string(f) + ": " + run.fm[f].repair);
  return t_faces + seconds_since(t0);
}

}  // namespace uvmesh::surface::detail
