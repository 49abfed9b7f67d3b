// mesh_model: the three stages of DESIGN.md's data flow -- curves first, faces in
// parallel, stitch by index -- with per-face failure isolation.
#include "uvmesh/surface/mesher.h"

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numbers>
#include <set>
#include <sstream>

#include "internal.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface {

param::SizeSpec default_size(const geom::Model& m) {
  const double D = m.bbox.diagonal() > 0 ? m.bbox.diagonal() : 1.0;
  param::SizeSpec s;
  s.hmax = D / 20;
  // D/1000: an assembly full of small fillets at D/5000 gave 13.5M triangles by default.
  s.hmin = D / 1000;
  s.angle_tol = 18.0 * std::numbers::pi / 180.0;  // 20 elements per 2 pi
  s.chordal_tol = D / 1000;
  s.gradation = 1.3;
  // Isotropic by default: the triangles are judged by their 3D shape (DESIGN.md Q_K), as
  // volume meshers need; anisotropic curvature sizes are an option.
  s.isotropic = true;
  return s;
}

namespace {

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// Gives the pages of freed heap memory back to the system. glibc keeps freed blocks
// (the face meshes are many small vectors, allocated in the worker threads' arenas), so
// without it the resident size never falls while stitching copies them into the output.
void release_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

template <class F>
void parallel_indices(tbb::task_arena& arena, std::size_t n, F&& f) {
  // grain 1: faces differ in cost by orders of magnitude.
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t i = r.begin(); i != r.end(); ++i) f(i);
                      });
  });
}

// Parameter of c in [lo, hi] closest to x: the best of 64 samples, then golden-section
// search between its two neighbours (the curves this is used on are within a fraction of
// a segment of x, so the distance is unimodal there).
double closest_param(const geom::Curve& c, double lo, double hi, const geom::Vec3& x) {
  constexpr int kSamples = 64;
  int best = 0;
  double dbest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kSamples; ++k) {
    const double d = glm::length(c.point(lo + (hi - lo) * k / kSamples) - x);
    if (d < dbest) dbest = d, best = k;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / kSamples,
         b = lo + (hi - lo) * std::min(kSamples, best + 1) / kSamples;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 60 && b - a > 1e-15 * std::max(1.0, std::abs(b)); ++it) {
    const double t1 = b - g * (b - a), t2 = a + g * (b - a);
    if (glm::length(c.point(t1) - x) < glm::length(c.point(t2) - x))
      b = t2;
    else
      a = t1;
  }
  return 0.5 * (a + b);
}

// Largest distance from points of a's curve to b's curve (33 samples, ends included).
double one_sided_distance(const geom::Edge& a, const geom::Edge& b) {
  double d = 0;
  for (int k = 0; k <= 32; ++k) {
    const geom::Vec3 x = a.curve->point(a.range.at(k / 32.0));
    d = std::max(
        d, glm::length(b.curve->point(closest_param(*b.curve, b.range.lo, b.range.hi, x)) - x));
  }
  return d;
}

}  // namespace

double MeshResult::unit_edge_share() const {
  std::int64_t e = 0, u = 0;
  for (const FaceStats& f : faces) e += f.edges, u += f.unit_edges;
  return e > 0 ? static_cast<double>(u) / static_cast<double>(e) : 0.0;
}

MeshResult mesh_model(const geom::Model& m, const MeshOptions& opt) {
  // Rounds of splitting edge pieces whose (u,v) polylines cross (each re-meshes the model).
  constexpr int kCrossingRounds = 8;
  MeshResult res;
  const auto t_all = Clock::now();
  const int threads = opt.threads > 0 ? opt.threads : tbb::this_task_arena::max_concurrency();
  tbb::task_arena arena(threads);

  // The chordal tolerance sizes elements with a safety factor (MeshOptions doc); the
  // report measures the deviation against the tolerance the user asked for.
  param::SizeSpec spec = opt.size;
  if (spec.chordal_tol > 0 && opt.chordal_safety > 1) spec.chordal_tol /= opt.chordal_safety;

  const std::size_t nf = m.faces.size(), ne = m.edges.size(), nv = m.vertices.size();
  std::vector<std::string> face_error(nf);

  // ---- 0. per-face background size fields (§7.5.1), gradated on their grids.
  auto t0 = Clock::now();
  std::vector<std::unique_ptr<param::FaceSizeField>> fields(nf);
  // Deterministic: a field freed after its face is meshed is built again, identical, when
  // a crossing round meshes the faces again (stage 2).
  auto build_field = [&](std::size_t f) {
    const geom::Face& face = m.faces[f];
    if (face.degenerate) return;  // not meshed (geom::Face::degenerate); no field, no error
    if (!face.surface) {
      face_error[f] =
          "the face has no surface (kind " + std::string(geom::to_string(face.kind)) + ")";
      return;
    }
    try {
      fields[f] = std::make_unique<param::FaceSizeField>(*face.surface, face.uv_box, spec,
                                                         static_cast<geom::Id>(f));
    } catch (...) {
      face_error[f] = "the surface could not be evaluated on its parameter box";
    }
  };
  parallel_indices(arena, nf, build_field);
  // Coincident faces: an assembly written without imprinting often gives the interface
  // between two solids twice, as two faces on the same edges and the same surface. Both
  // meshed would put two different triangulations on one surface (intersecting, and
  // rejected by TetGen as duplicated facets); the interface is meshed once, as the first
  // face, which then bounds both solids (as Gmsh's conformal fragments do).
  std::vector<geom::Id> twin_of(nf, geom::kNone);
  {
    std::map<std::vector<geom::Id>, std::vector<std::size_t>> by_edges;
    for (std::size_t f = 0; f < nf; ++f) {
      if (!face_error[f].empty() || m.faces[f].degenerate) continue;
      std::vector<geom::Id> k;
      for (const geom::Loop& l : m.faces[f].loops)
        for (const geom::EdgeUse& u : l.uses) k.push_back(u.edge);
      std::sort(k.begin(), k.end());
      k.erase(std::unique(k.begin(), k.end()), k.end());
      if (!k.empty()) by_edges[k].push_back(f);
    }
    const double tol = 1e-6 * std::max(m.bbox.diagonal(), 1e-300);
    for (const auto& [k, fs] : by_edges)
      for (std::size_t i = 1; i < fs.size(); ++i)
        for (std::size_t j = 0; j < i; ++j) {
          const geom::Face &a = m.faces[fs[j]], &b = m.faces[fs[i]];
          if (twin_of[fs[j]] != geom::kNone) continue;
          bool same = a.kind == geom::SurfaceKind::Plane && b.kind == geom::SurfaceKind::Plane;
          if (!same) {
            // Same edges but two different surfaces (a lens): compare an inside point.
            try {
              const geom::Vec3 p = a.surface->point(a.uv_box.u.mid(), a.uv_box.v.mid());
              const Projection pr =
                  project_to_surface(*b.surface, p, {b.uv_box.u.mid(), b.uv_box.v.mid()}, b.uv_box,
                                     std::max(a.tol, tol));
              same = pr.converged && pr.distance <= std::max(10 * std::max(a.tol, b.tol), tol);
            } catch (...) {
              same = false;
            }
          }
          if (same) {
            twin_of[fs[i]] = static_cast<geom::Id>(fs[j]);
            res.twins.push_back({static_cast<geom::Id>(fs[i]), static_cast<geom::Id>(fs[j])});
            break;
          }
        }
  }
  std::vector<const param::FaceSizeField*> field_ptr(nf);
  for (std::size_t f = 0; f < nf; ++f) field_ptr[f] = fields[f].get();
  res.stages.push_back({"size fields", seconds_since(t0)});

  std::vector<char> on_face(ne, 0);
  for (const geom::Face& face : m.faces)
    for (const geom::Loop& l : face.loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.edge >= 0 && static_cast<std::size_t>(u.edge) < ne)
          on_face[static_cast<std::size_t>(u.edge)] = 1;

  // An edge whose two ends are one model vertex although its curve's ends are farther
  // apart than the edge's own tolerance is closed by the vertex's tolerance alone: its
  // last node is that vertex, and the faces along it fold at the scale of the gap
  // (occt_caxif_k1: edges of 1 mm whose vertex got OCC's largest tolerance, 1 mm; 19
  // self-intersecting pairs in each of two solids). The OCC import splits such a vertex
  // in two (geom::split_vertices_closing_open_edges); one it could not split (the split
  // would open a loop, or an edge end is about as near to both ends of the curve) is
  // still closed here, and the mesh cannot follow both: say so.
  for (std::size_t e = 0; e < ne; ++e) {
    const geom::Edge& ed = m.edges[e];
    if (!on_face[e] || ed.degenerate || !ed.curve || ed.v0 != ed.v1 || ed.v0 == geom::kNone)
      continue;
    try {
      const double gap = glm::length(ed.curve->point(ed.range.hi) - ed.curve->point(ed.range.lo));
      if (!(gap > ed.tol)) continue;
      std::ostringstream os;
      os << "edge " << e << ": both ends are vertex " << ed.v0 << " (tolerance "
         << m.vertices[static_cast<std::size_t>(ed.v0)].tol << ") but its curve's ends are " << gap
         << " apart (edge length " << ed.length << ", tolerance " << ed.tol
         << "): the mesh closes it at the vertex, and the faces along it may fold there";
      res.warnings.push_back(os.str());
    } catch (...) {
      // An edge whose curve cannot be evaluated fails in the discretization below.
    }
  }

  // ---- 1. curves: every edge once.
  t0 = Clock::now();
  detail::EdgeDiscretizer disc(m, spec, field_ptr);
  disc.set_min_closed(opt.min_segments_closed_edge);
  std::vector<detail::EdgeNodes> edges(ne);
  std::vector<std::string> edge_error(ne);
  parallel_indices(arena, ne, [&](std::size_t e) {
    try {
      edges[e].t = disc.discretize(static_cast<geom::Id>(e));
    } catch (...) {
      const geom::Edge& ed = m.edges[e];
      edges[e].t = {ed.range.lo, ed.range.hi};
      edge_error[e] =
          "edge " + std::to_string(e) + ": its curve could not be evaluated; kept as one segment";
    }
  });
  // Sizes from the other edges of each face (gradation across the face, proximity):
  // each round caps every edge by the previous round's 1D mesh; a refined edge is a new
  // source for its neighbours, hence more than one round.
  //
  // The caps of edge e read only the nodes of the other edges of the faces around e
  // (BoundaryCaps::any_neighbour), so from the second round on an edge none of whose
  // neighbours changed in the last round would be discretized exactly as before: it is
  // skipped. (On kicad_tantalum_c, whose 1 um strip refines two long edges, the rounds
  // were a third of the run.)
  std::vector<char> moved(ne, 1);  // the edge's nodes changed in the last round
  for (int round = 0; round < opt.boundary_size_rounds; ++round) {
    std::vector<std::vector<double>> ts(ne);
    for (std::size_t e = 0; e < ne; ++e) ts[e] = edges[e].t;
    const detail::BoundaryCaps caps(m, ts, spec);
    std::atomic<int> changed{0};
    std::vector<char> now(ne, 0);
    parallel_indices(arena, ne, [&](std::size_t e) {
      if (!edge_error[e].empty()) return;
      if (round > 0 && !caps.any_neighbour(static_cast<geom::Id>(e), [&](geom::Id o) {
            return moved[static_cast<std::size_t>(o)] != 0;
          }))
        return;
      try {
        std::vector<double> nt = disc.discretize(static_cast<geom::Id>(e), &caps);
        if (nt.size() != edges[e].t.size()) ++changed;
        now[e] = nt != edges[e].t;
        edges[e].t = std::move(nt);
      } catch (...) {
        // Kept as discretized without caps: the curve evaluated there before.
      }
    });
    if (changed == 0) break;
    moved.swap(now);
  }
  // Chordal repair along the curves (the 1D half of the one in the face mesher): a
  // segment whose chord midpoint is farther than 0.9 tol from the curve -- the report
  // measures it against the faces, on which the curve lies -- is split at its middle
  // parameter. Sizes come from the curvature sampled at discrete parameters and graded;
  // a semi-sharp crease of a subdivision surface turns faster than those samples see.
  if (opt.size.chordal_tol > 0 && opt.chordal_repair_rounds > 0) {
    const double lim = 0.9 * opt.size.chordal_tol;
    parallel_indices(arena, ne, [&](std::size_t e) {
      const geom::Edge& ed = m.edges[e];
      if (!edge_error[e].empty() || ed.degenerate || !ed.curve || !on_face[e]) return;
      auto& t = edges[e].t;
      for (int round = 0; round < opt.chordal_repair_rounds; ++round) {
        std::vector<double> nt;
        nt.reserve(t.size() * 2);
        bool split = false;
        for (std::size_t i = 0; i + 1 < t.size(); ++i) {
          nt.push_back(t[i]);
          const geom::Vec3 a = ed.curve->point(t[i]), b = ed.curve->point(t[i + 1]);
          const geom::Vec3 mid = 0.5 * (a + b);
          // Distance to the curve: to the polyline through 9 samples of the piece (the
          // nearest sample alone overestimates it where the parametrization is uneven).
          double d = std::numeric_limits<double>::infinity();
          geom::Vec3 prev = a;
          for (int k = 1; k <= 8; ++k) {
            const geom::Vec3 cur = k < 8 ? ed.curve->point(t[i] + (t[i + 1] - t[i]) * k / 8.0) : b;
            const geom::Vec3 seg = cur - prev;
            const double l2 = glm::dot(seg, seg);
            const double w = l2 > 0 ? std::clamp(glm::dot(mid - prev, seg) / l2, 0.0, 1.0) : 0.0;
            d = std::min(d, glm::length(prev + w * seg - mid));
            prev = cur;
          }
          if (d > lim) nt.push_back(0.5 * (t[i] + t[i + 1])), split = true;
        }
        nt.push_back(t.back());
        t.swap(nt);
        if (!split) break;
      }
    });
  }
  for (const auto& w : edge_error)
    if (!w.empty()) res.warnings.push_back(w);

  // Every loop needs at least 3 nodes to enclose anything in (u,v): a face bounded by
  // two one-segment edges (a lens) gets its longest edge split.
  auto split_edge = [&](std::size_t e) {
    auto& t = edges[e].t;
    std::vector<double> nt;
    for (std::size_t i = 0; i + 1 < t.size(); ++i)
      nt.push_back(t[i]), nt.push_back(0.5 * (t[i] + t[i + 1]));
    nt.push_back(t.back());
    t.swap(nt);
  };
  for (const geom::Face& face : m.faces)
    for (const geom::Loop& l : face.loops) {
      for (int guard = 0; guard < 4; ++guard) {
        std::size_t nodes = 0, longest = 0;
        double best = -1;
        for (const geom::EdgeUse& u : l.uses) {
          const auto e = static_cast<std::size_t>(u.edge);
          nodes += m.edges[e].degenerate ? 1 : edges[e].t.size() - 1;
          if (!m.edges[e].degenerate && m.edges[e].length > best)
            best = m.edges[e].length, longest = e;
        }
        if (nodes >= 3 || best < 0) break;
        split_edge(longest);
      }
    }

  // Strips narrower than the proximity floor, collapsed onto one curve. A face bounded by
  // two edges between the same two vertices (a lens), no more than proximity_floor() --
  // or the two edges' tolerance floor, when larger -- apart anywhere, is narrower than
  // any gap the sizes resolve (BoundaryCaps::cap): meshed, it can only be
  // a row of slivers across its width (occt_mesh_artifact: face 2, a planar step 7.9e-6
  // wide and 0.029 long, and face 6, at most 9.7e-6 wide, against a floor of 5.1e-5; 20
  // triangles of Q up to 580, 2.5% of the mesh). Resolving it instead would need
  // elements as small as the width along the whole strip, graded over both faces beside
  // it: tens of thousands of triangles for a feature the sizes were told to ignore. So
  // the strip is not meshed, and its two edges become one polyline: the edge with more
  // nodes keeps them (primary), the other (secondary) takes the same global nodes at
  // the parameters of its own curve closest to them, so the faces on either side meet
  // along it by index and the solid stays closed. The geometric error is the strip's
  // width, below hmin / 100 and a tenth of the chordal tolerance. Only a two-edge strip
  // whose edges each bound one other face, two different ones, is collapsed: a strip
  // with end edges, or a slit of one face, would need more than one edge identified.
  std::vector<geom::Id> primary_of(ne, geom::kNone);  // secondary edge -> its primary
  std::vector<char> collapsed(nf, 0);
  {
    const double floor = proximity_floor(spec, std::max(m.bbox.diagonal(), 1e-300));
    std::vector<std::vector<geom::Id>> faces_of(ne);
    for (std::size_t f = 0; f < nf; ++f)
      for (const geom::Loop& l : m.faces[f].loops)
        for (const geom::EdgeUse& u : l.uses)
          if (u.edge >= 0)
            faces_of[static_cast<std::size_t>(u.edge)].push_back(static_cast<geom::Id>(f));
    std::vector<char> involved(ne, 0);
    for (std::size_t f = 0; f < nf; ++f) {
      const geom::Face& face = m.faces[f];
      if (face.degenerate || !face_error[f].empty() || twin_of[f] != geom::kNone ||
          face.loops.size() != 1)
        continue;
      const auto& uses = face.loops[0].uses;
      if (uses.size() != 2 || uses[0].internal || uses[1].internal) continue;
      const auto ea = static_cast<std::size_t>(uses[0].edge),
                 eb = static_cast<std::size_t>(uses[1].edge);
      if (ea == eb || involved[ea] || involved[eb] || !edge_error[ea].empty() ||
          !edge_error[eb].empty())
        continue;
      const geom::Edge &a = m.edges[ea], &b = m.edges[eb];
      if (a.degenerate || b.degenerate || !a.curve || !b.curve || a.v0 == geom::kNone ||
          a.v1 == geom::kNone || a.v0 == a.v1 ||
          !((a.v0 == b.v0 && a.v1 == b.v1) || (a.v0 == b.v1 && a.v1 == b.v0)))
        continue;
      // Each edge: this face and exactly one other, and the two others differ.
      auto other = [&](std::size_t e) {
        geom::Id o = geom::kNone;
        int n = 0;
        for (geom::Id g : faces_of[e])
          if (g != static_cast<geom::Id>(f)) o = g, ++n;
        return std::pair{o, n + 1 == static_cast<int>(faces_of[e].size()) ? n : -1};
      };
      const auto [oa, na] = other(ea);
      const auto [ob, nb] = other(eb);
      if (na != 1 || nb != 1 || oa == ob || collapsed[static_cast<std::size_t>(oa)] ||
          collapsed[static_cast<std::size_t>(ob)])
        continue;
      double width = 0;
      try {
        width = std::max(one_sided_distance(a, b), one_sided_distance(b, a));
      } catch (...) {
        continue;
      }
      // The narrowest gap the sizes resolve between these two edges is BoundaryCaps' gap
      // floor: the proximity floor, or the two edges' tolerance floor when that is larger
      // (a gap inside the tolerance tubes is not refined at all, kGapToleranceFactor).
      const double gap_floor =
          std::max(floor, kGapToleranceFactor * (gap_tolerance(m, static_cast<geom::Id>(ea)) +
                                                 gap_tolerance(m, static_cast<geom::Id>(eb))));
      // The faces beside the strip then meet at its primary edge, up to `width` off the
      // secondary's face: with a chordal tolerance, only a strip much narrower than it
      // (a tenth: the chords along the primary may use 0.9 of it, see the 1D repair).
      if (!(width <= gap_floor) ||
          (opt.size.chordal_tol > 0 && !(width <= 0.1 * opt.size.chordal_tol)))
        continue;
      const bool a_first = edges[ea].t.size() > edges[eb].t.size() ||
                           (edges[ea].t.size() == edges[eb].t.size() && ea < eb);
      const std::size_t pe = a_first ? ea : eb, se = a_first ? eb : ea;
      primary_of[se] = static_cast<geom::Id>(pe);
      involved[ea] = involved[eb] = 1;
      collapsed[f] = 1;
      std::ostringstream os;
      os << "a strip between edges " << pe << " and " << se << " at most " << width
         << " wide, narrower than the proximity floor " << gap_floor
         << (gap_floor > floor ? " (the edges' tolerances)" : " (hmin / 100)") << ": edge " << se
         << " takes the nodes of edge " << pe << ", faces " << (a_first ? ob : oa) << " and "
         << (a_first ? oa : ob) << " meet there";
      res.collapsed.push_back({static_cast<geom::Id>(f), os.str()});
    }
  }
  // The secondary's parameters: those of its curve closest to the primary's nodes, in
  // its own direction (again after a crossing round refined the primary).
  auto sync_secondaries = [&] {
    for (std::size_t se = 0; se < ne; ++se) {
      if (primary_of[se] == geom::kNone) continue;
      const auto pe = static_cast<std::size_t>(primary_of[se]);
      const geom::Edge &P = m.edges[pe], &S = m.edges[se];
      const bool same = P.v0 == S.v0;
      const std::vector<double>& tp = edges[pe].t;
      const std::size_t n = tp.size();
      std::vector<double> ts(n);
      ts.front() = S.range.lo;
      ts.back() = S.range.hi;
      double lo = S.range.lo;
      for (std::size_t i = 1; i + 1 < n; ++i) {
        const geom::Vec3 x = P.curve->point(tp[same ? i : n - 1 - i]);
        // Searched beyond the previous node only, so the parameters increase.
        ts[i] = closest_param(*S.curve, lo, S.range.hi, x);
        lo = ts[i];
      }
      edges[se].t = std::move(ts);
    }
  };
  sync_secondaries();

  // Curves and faces, repeated when a face's (u,v) boundary crossed itself: the edges
  // named are refined (their (u,v) polylines then follow the pcurves more closely) and
  // the model is meshed again -- edge nodes are shared, so every face must see them.
  const std::vector<std::string> pre_error = face_error;
  std::vector<detail::FaceMesh> fm(nf);
  double t_faces = 0;
  SurfaceMesh& M = res.mesh;
  for (int round = 0;; ++round) {
    face_error = pre_error;
    M = {};
    // Global numbering (surface_mesh.h): model vertices, then edge interiors in order.
    auto add_point = [&](const geom::Vec3& p, int dim, geom::Id ent, double t) {
      M.points.push_back(p);
      M.point_dim.push_back(static_cast<std::int8_t>(dim));
      M.point_entity.push_back(ent);
      M.point_t.push_back(t);
      return static_cast<NodeId>(M.points.size() - 1);
    };
    for (std::size_t v = 0; v < nv; ++v)
      add_point(m.vertices[v].p, 0, static_cast<geom::Id>(v), 0.0);
    for (std::size_t e = 0; e < ne; ++e) {
      const geom::Edge& ed = m.edges[e];
      auto& en = edges[e];
      const std::size_t n = en.t.size();
      en.node.resize(n);
      auto end_node = [&](geom::Id v, double t) {
        if (v != geom::kNone) return static_cast<NodeId>(v);
        // An edge without a vertex (rare CAD): its end becomes an edge node.
        return add_point(ed.curve ? ed.curve->point(t) : geom::Vec3(0.0), 1,
                         static_cast<geom::Id>(e), t);
      };
      en.node.front() = end_node(ed.v0, en.t.front());
      if (ed.degenerate) {
        for (auto& x : en.node) x = en.node.front();
        continue;
      }
      if (!on_face[e]) {
        // A loose edge (wireframe geometry in a STEP file, not bounding any face) is not
        // part of the surface: no nodes, no segments; its vertices go if nothing uses them.
        en.node.back() = ed.v1 != geom::kNone ? static_cast<NodeId>(ed.v1) : en.node.front();
        continue;
      }
      if (primary_of[e] != geom::kNone) continue;  // its primary's nodes, below
      for (std::size_t i = 1; i + 1 < n; ++i)
        en.node[i] = add_point(ed.curve->point(en.t[i]), 1, static_cast<geom::Id>(e), en.t[i]);
      en.node.back() =
          ed.v1 == ed.v0 && ed.v0 == geom::kNone ? en.node.front() : end_node(ed.v1, en.t.back());
      for (std::size_t i = 0; i + 1 < n; ++i)
        M.segments.push_back({en.node[i], en.node[i + 1], static_cast<geom::Id>(e)});
    }
    // A collapsed strip's secondary edge: the primary's nodes in its own direction, and no
    // segments of its own (they would be the primary's again).
    for (std::size_t e = 0; e < ne; ++e) {
      if (primary_of[e] == geom::kNone) continue;
      const auto pe = static_cast<std::size_t>(primary_of[e]);
      const std::vector<NodeId>& pn = edges[pe].node;
      auto& sn = edges[e].node;
      sn.assign(pn.begin(), pn.end());
      if (m.edges[pe].v0 != m.edges[e].v0) std::reverse(sn.begin(), sn.end());
    }
    if (round == 0) res.stages.push_back({"curves", seconds_since(t0)});

    // ---- 2. faces, in parallel; each face only touches its own surface and pcurves.
    t0 = Clock::now();
    fm.assign(nf, {});
    std::atomic<int> done{0};
    const std::vector<geom::Vec3>& node_points = M.points;
    parallel_indices(arena, nf, [&](std::size_t f) {
      if (!face_error[f].empty() || twin_of[f] != geom::kNone || m.faces[f].degenerate ||
          collapsed[f])
        return;
      const auto tf = Clock::now();
      // A face's size field lives while its face is meshed only (memory: one grid per face
      // of a model with thousands of faces); a later crossing round builds it again.
      if (!fields[f]) build_field(f);
      try {
        if (fields[f])
          fm[f] =
              detail::mesh_face(m, static_cast<geom::Id>(f), edges, node_points, *fields[f], opt);
      } catch (...) {
        fm[f] = {};
        fm[f].error = "an exception was raised while evaluating the face's geometry";
      }
      fields[f].reset();
      fm[f].stats.face = static_cast<geom::Id>(f);
      fm[f].stats.seconds = seconds_since(tf);
      if (!fm[f].error.empty()) face_error[f] = fm[f].error;
      const int d = ++done;
      if (opt.progress) opt.progress(d, static_cast<int>(nf));
    });
    t_faces += seconds_since(t0);
    // Only the crossing pieces are split (each round halves them), so that two pcurves
    // meeting at a small angle get nodes close enough to the vertex to part before it
    // without refining the whole edge 2^rounds times. (Splitting whole edges, as before,
    // made new crossings elsewhere on occt_turbine; on occt_caxif_b1 it happened to clear
    // two faces that pieces alone do not.)
    std::set<std::pair<geom::Id, double>> refine;
    for (const auto& F : fm) refine.insert(F.refine_at.begin(), F.refine_at.end());
    if (refine.empty() || round == kCrossingRounds) break;
    std::set<geom::Id> touched;
    for (auto [e, t] : refine) {
      auto ei = static_cast<std::size_t>(e);
      if (m.edges[ei].degenerate) continue;
      if (primary_of[ei] != geom::kNone) {
        // A secondary's piece is its primary's piece of the same index (counted from the
        // other end when they run opposite ways); sync_secondaries() follows.
        const auto& st = edges[ei].t;
        const auto it = std::upper_bound(st.begin(), st.end(), t);
        if (it == st.begin() || it == st.end()) continue;
        const auto i = static_cast<std::size_t>(it - st.begin() - 1);
        const auto pe = static_cast<std::size_t>(primary_of[ei]);
        const auto& pt = edges[pe].t;
        const std::size_t k = m.edges[pe].v0 == m.edges[ei].v0 ? i : pt.size() - 2 - i;
        t = 0.5 * (pt[k] + pt[k + 1]);
        ei = pe;
        e = static_cast<geom::Id>(pe);
      }
      auto& ts = edges[ei].t;
      const auto it = std::lower_bound(ts.begin(), ts.end(), t);
      if (it == ts.begin() || it == ts.end() || *it == t) continue;
      ts.insert(it, t);
      touched.insert(e);
    }
    if (touched.empty()) break;
    sync_secondaries();
    res.warnings.push_back("round " + std::to_string(round + 1) + ": " +
                           std::to_string(refine.size()) + " piece(s) of " +
                           std::to_string(touched.size()) +
                           " edge(s) split where (u,v) boundaries crossed; model meshed again");
  }
  // Faces whose (u,v) boundary stayed unusable after the crossing rounds: a last try
  // that may triangulate them from their boundary nodes (face.cpp,
  // triangulate_from_boundary). The edges are final, so the nodes are the ones the
  // neighbouring faces use.
  {
    const auto tf0 = Clock::now();
    std::vector<std::size_t> retry;
    for (std::size_t f = 0; f < nf; ++f)
      // Only (u,v) boundary failures: any other (no surface, a time limit) would be
      // meshed again for nothing.
      if (fm[f].uv_defect && !fm[f].error.empty() && fm[f].error == face_error[f] &&
          twin_of[f] == geom::kNone)
        retry.push_back(f);
    const std::vector<geom::Vec3>& node_points = M.points;
    parallel_indices(arena, retry.size(), [&](std::size_t k) {
      const std::size_t f = retry[k];
      const auto tf = Clock::now();
      if (!fields[f]) build_field(f);
      detail::FaceMesh r;
      try {
        if (fields[f])
          r = detail::mesh_face(m, static_cast<geom::Id>(f), edges, node_points, *fields[f], opt,
                                true);
      } catch (...) {
        r = {};
        r.error = fm[f].error;
      }
      fields[f].reset();
      r.stats.face = static_cast<geom::Id>(f);
      r.stats.seconds = fm[f].stats.seconds + seconds_since(tf);
      if (r.error.empty())
        face_error[f].clear();
      else
        face_error[f] = r.error;
      fm[f] = std::move(r);
    });
    for (std::size_t f : retry)
      if (fm[f].from_boundary)
        res.warnings.push_back(
            "face " + std::to_string(f) +
            ": its (u,v) boundary is unusable (pcurves cross or coincide); triangulated from its " +
            std::to_string(fm[f].stats.boundary_nodes) +
            " boundary nodes, within the chordal tolerance");
    t_faces += seconds_since(tf0);
  }
  res.stages.push_back({"faces", t_faces});
  // Peak memory (issue 7, bench/memory): the face meshes and the whole output coexist
  // while stitching. The output arrays are sized once instead of doubling as they grow
  // (a doubling holds 1.5-3x the final array; a reservation is not resident until
  // written), and the memory of the face meshes and of the meshers' working sets is
  // given back as they are freed. Measured by bench/memory/run.sh.
  release_freed_memory();
  {
    std::size_t add_points = 0, add_tris = 0;
    for (std::size_t f = 0; f < nf; ++f)
      if (face_error[f].empty() && twin_of[f] == geom::kNone && !m.faces[f].degenerate &&
          !collapsed[f])
        add_points += fm[f].points.size(), add_tris += fm[f].tris.size();
    M.points.reserve(M.points.size() + add_points);
    M.point_dim.reserve(M.points.capacity());
    M.point_entity.reserve(M.points.capacity());
    M.point_t.reserve(M.points.capacity());
    M.triangles.reserve(add_tris);
    M.triangle_face.reserve(add_tris);
    M.triangle_uv.reserve(add_tris);
  }

  // ---- 3. stitch: face points appended in face order; triangles refer to global ids.
  t0 = Clock::now();
  std::size_t freed = 0;  // bytes of face meshes freed since the last release
  for (std::size_t f = 0; f < nf; ++f) {
    if (!face_error[f].empty()) {
      res.failed.push_back({static_cast<geom::Id>(f), face_error[f]});
      fm[f] = {};
      continue;
    }
    if (m.faces[f].degenerate) {
      res.degenerate.push_back({static_cast<geom::Id>(f), m.faces[f].degenerate_reason});
      continue;
    }
    if (twin_of[f] != geom::kNone || collapsed[f]) continue;
    detail::FaceMesh& F = fm[f];
    const auto base = static_cast<NodeId>(M.points.size());
    for (std::size_t k = 0; k < F.points.size(); ++k) {
      M.points.push_back(F.points[k]);
      M.point_dim.push_back(2);
      M.point_entity.push_back(static_cast<geom::Id>(f));
      M.point_t.push_back(0.0);
    }
    for (std::size_t t = 0; t < F.tris.size(); ++t) {
      std::array<NodeId, 3> g{};
      for (int i = 0; i < 3; ++i)
        g[i] = F.tris[t][i] >= 0 ? F.tris[t][i] : base + (-F.tris[t][i] - 1);
      M.triangles.push_back(g);
      M.triangle_face.push_back(static_cast<geom::Id>(f));
      M.triangle_uv.push_back(F.tri_uv[t]);
    }
    res.faces.push_back(F.stats);
    freed += F.points.capacity() * sizeof(F.points[0]) + F.tris.capacity() * sizeof(F.tris[0]) +
             F.tri_uv.capacity() * sizeof(F.tri_uv[0]);
    F = {};
    if (freed >= (std::size_t{4} << 20)) release_freed_memory(), freed = 0;
  }
  // Model vertices used by nothing (isolated CAD vertices) are dropped so that the mesh
  // has no unreferenced points; ids are compacted in order.
  std::vector<char> used(M.points.size(), 0);
  for (const auto& t : M.triangles)
    for (NodeId v : t) used[static_cast<std::size_t>(v)] = 1;
  for (const auto& s : M.segments)
    used[static_cast<std::size_t>(s.a)] = used[static_cast<std::size_t>(s.b)] = 1;
  if (std::find(used.begin(), used.end(), 0) != used.end()) {
    std::vector<NodeId> nid(M.points.size(), -1);
    NodeId k = 0;
    for (std::size_t i = 0; i < used.size(); ++i)
      if (used[i]) {
        nid[i] = k;
        M.points[static_cast<std::size_t>(k)] = M.points[i];
        M.point_dim[static_cast<std::size_t>(k)] = M.point_dim[i];
        M.point_entity[static_cast<std::size_t>(k)] = M.point_entity[i];
        M.point_t[static_cast<std::size_t>(k)] = M.point_t[i];
        ++k;
      }
    M.points.resize(static_cast<std::size_t>(k));
    M.point_dim.resize(static_cast<std::size_t>(k));
    M.point_entity.resize(static_cast<std::size_t>(k));
    M.point_t.resize(static_cast<std::size_t>(k));
    for (auto& t : M.triangles)
      for (NodeId& v : t) v = nid[static_cast<std::size_t>(v)];
    for (auto& s : M.segments)
      s.a = nid[static_cast<std::size_t>(s.a)], s.b = nid[static_cast<std::size_t>(s.b)];
  }
  res.stages.push_back({"stitch", seconds_since(t0)});
  res.stages.push_back({"total", seconds_since(t_all)});
  return res;
}

}  // namespace uvmesh::surface
