// Stage 1 of mesh_model: the 1D mesh of the model, every edge once -- discretized at
// unit length in the metric along the curve, then under size caps from the other edges
// of its faces, repaired against the chordal tolerance, and split so that every loop
// encloses something in (u,v).
#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "model_run.h"

namespace uvmesh::surface::detail {

namespace {

void discretize_edges(ModelRun& run, const EdgeDiscretizer& disc) {
  parallel_indices(run.arena, run.ne, [&](std::size_t e) {
    try {
      run.edges[e].t = disc.discretize(static_cast<geom::Id>(e));
    } catch (...) {
      const geom::Edge& ed = run.m.edges[e];
      run.edges[e].t = {ed.range.lo, ed.range.hi};
      run.edge_error[e] =
          "edge " + std::to_string(e) + ": its curve could not be evaluated; kept as one segment";
    }
  });
}

// Sizes from the other edges of each face (gradation across the face, proximity):
// each round caps every edge by the previous round's 1D mesh; a refined edge is a new
// source for its neighbours, hence more than one round.
//
// The caps of edge e read only the nodes of the other edges of the faces around e
// (BoundaryCaps::any_neighbour), so from the second round on an edge none of whose
// neighbours changed in the last round would be discretized exactly as before: it is
// skipped. (Where a thin strip refines two long edges, the rounds that rediscretized
// every edge were a third of the run.)
void boundary_size_rounds(ModelRun& run, const EdgeDiscretizer& disc) {
  const std::size_t ne = run.ne;
  std::vector<char> moved(ne, 1);  // the edge's nodes changed in the last round
  for (int round = 0; round < run.opt.boundary_size_rounds; ++round) {
    std::vector<std::vector<double>> ts(ne);
    for (std::size_t e = 0; e < ne; ++e) ts[e] = run.edges[e].t;
    const BoundaryCaps caps(run.m, ts, run.spec, run.feature, run.opt.feature_angle);
    std::atomic<int> changed{0};
    std::vector<char> now(ne, 0);
    parallel_indices(run.arena, ne, [&](std::size_t e) {
      if (!run.edge_error[e].empty()) return;
      if (round > 0 && !caps.any_neighbour(static_cast<geom::Id>(e), [&](geom::Id o) {
            return moved[static_cast<std::size_t>(o)] != 0;
          }))
        return;
      try {
        std::vector<double> nt = disc.discretize(static_cast<geom::Id>(e), &caps);
        if (nt.size() != run.edges[e].t.size()) ++changed;
        now[e] = nt != run.edges[e].t;
        run.edges[e].t = std::move(nt);
      } catch (...) {
        // Kept as discretized without caps: the curve evaluated there before.
      }
    });
    if (changed == 0) break;
    moved.swap(now);
  }
}

// Distance from the chord midpoint of the piece [t0, t1] of the curve to the curve: to
// the polyline through 9 samples of the piece (the nearest sample alone overestimates it
// where the parametrization is uneven).
double chord_midpoint_distance(const geom::Curve& c, double t0, double t1, const geom::Vec3& a,
                               const geom::Vec3& b) {
  const geom::Vec3 mid = 0.5 * (a + b);
  double d = std::numeric_limits<double>::infinity();
  geom::Vec3 prev = a;
  for (int k = 1; k <= 8; ++k) {
    const geom::Vec3 cur = k < 8 ? c.point(t0 + (t1 - t0) * k / 8.0) : b;
    const geom::Vec3 seg = cur - prev;
    const double l2 = glm::dot(seg, seg);
    const double w = l2 > 0 ? std::clamp(glm::dot(mid - prev, seg) / l2, 0.0, 1.0) : 0.0;
    d = std::min(d, glm::length(prev + w * seg - mid));
    prev = cur;
  }
  return d;
}

// Chordal repair along the curves (the 1D half of the one in the face mesher): a
// segment whose chord midpoint is farther than 0.9 tol from the curve -- the report
// measures it against the faces, on which the curve lies -- is split at its middle
// parameter. Sizes come from the curvature sampled at discrete parameters and graded;
// a semi-sharp crease of a subdivision surface turns faster than those samples see.
void repair_edge_chords(ModelRun& run) {
  const MeshOptions& opt = run.opt;
  if (!(opt.size.chordal_tol > 0 && opt.chordal_repair_rounds > 0)) return;
  const double lim = 0.9 * opt.size.chordal_tol;
  parallel_indices(run.arena, run.ne, [&](std::size_t e) {
    const geom::Edge& ed = run.m.edges[e];
    if (!run.edge_error[e].empty() || ed.degenerate || !ed.curve || !run.on_face[e]) return;
    auto& t = run.edges[e].t;
    for (int round = 0; round < opt.chordal_repair_rounds; ++round) {
      std::vector<double> nt;
      nt.reserve(t.size() * 2);
      bool split = false;
      for (std::size_t i = 0; i + 1 < t.size(); ++i) {
        nt.push_back(t[i]);
        const geom::Vec3 a = ed.curve->point(t[i]), b = ed.curve->point(t[i + 1]);
        if (chord_midpoint_distance(*ed.curve, t[i], t[i + 1], a, b) > lim)
          nt.push_back(0.5 * (t[i] + t[i + 1])), split = true;
      }
      nt.push_back(t.back());
      t.swap(nt);
      if (!split) break;
    }
  });
}

// Every loop needs at least 3 nodes to enclose anything in (u,v): a face bounded by
// two one-segment edges (a lens) gets its longest edge split.
void split_lens_edges(ModelRun& run) {
  const geom::Model& m = run.m;
  auto split_edge = [&](std::size_t e) {
    auto& t = run.edges[e].t;
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
          nodes += m.edges[e].degenerate ? 1 : run.edges[e].t.size() - 1;
          if (!m.edges[e].degenerate && m.edges[e].length > best)
            best = m.edges[e].length, longest = e;
        }
        if (nodes >= 3 || best < 0) break;
        split_edge(longest);
      }
    }
}

}  // namespace

void mesh_curves(ModelRun& run) {
  EdgeDiscretizer disc(run.m, run.spec, run.field_ptr);
  disc.set_min_closed(run.opt.min_segments_closed_edge);
  discretize_edges(run, disc);
  boundary_size_rounds(run, disc);
  repair_edge_chords(run);
  for (const auto& w : run.edge_error)
    if (!w.empty()) run.res.warnings.push_back(w);
  split_lens_edges(run);
}

}  // namespace uvmesh::surface::detail
