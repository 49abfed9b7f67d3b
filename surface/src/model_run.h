// The state that the steps of surface::mesh_model share (mesher.cpp), and the small
// tools they all use. Each step lives in its own file:
//   mesher.cpp          size fields, edge checks, the step list itself
//   twin_faces.cpp      coincident faces, meshed once
//   model_curves.cpp    stage 1: the 1D mesh (caps rounds, 1D chordal repair, lens split)
//   strip_collapse.cpp  strips narrower than the proximity floor, onto one curve
//   crossing_rounds.cpp stage 2: node numbering and the faces, again while (u,v)
//                       boundaries cross; the boundary triangulation of what is left
//   stitch.cpp          stage 3: one SurfaceMesh by global ids
//   simplify3d.cpp      needles and caps of entities below the feature size removed
// Not installed.
#pragma once

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include "internal.h"

namespace uvmesh::surface::detail {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

/// f(i) for i in [0, n) on the arena's threads.
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

/// What the steps of mesh_model read and write: the model and options, the sizes, the
/// per-face and per-edge state, and the result being built. Scratch of a single step
/// stays in that step.
struct ModelRun {
  ModelRun(const geom::Model& model, const MeshOptions& options);

  const geom::Model& m;
  const MeshOptions& opt;
  const std::size_t nf, ne, nv;  ///< faces, edges, vertices of m
  /// The feature size L (feature_size(opt, m.bbox); 0 under keep_topology).
  const double feature;
  tbb::task_arena arena;
  MeshResult res;               ///< res.size: the sizes elements are made for (meshing_size(opt))
  const param::SizeSpec& spec;  ///< = res.size

  /// Per face: non-empty = the face failed, with the reason.
  std::vector<std::string> face_error;
  /// Per face: its background size field (§7.5.1) while it is needed; freed after its
  /// face is meshed, built again (identical) when a crossing round meshes it again.
  std::vector<std::unique_ptr<param::FaceSizeField>> fields;
  /// The fields as the edge discretizer reads them (stage 1, before any is freed).
  std::vector<const param::FaceSizeField*> field_ptr;
  /// Per face: the face meshed in its place (twin_faces.cpp), or kNone.
  std::vector<geom::Id> twin_of;
  /// Per face: a strip collapsed onto one curve (strip_collapse.cpp), not meshed.
  std::vector<char> collapsed;

  /// Per edge: the edge bounds some face (else it is a loose wire: no nodes).
  std::vector<char> on_face;
  /// Per edge: its 1D mesh (parameters; global node ids once numbered).
  std::vector<EdgeNodes> edges;
  /// Per edge: non-empty = its curve could not be evaluated (kept as one segment).
  std::vector<std::string> edge_error;
  /// Per edge: the primary edge whose nodes a collapsed strip's secondary takes, or kNone.
  std::vector<geom::Id> primary_of;

  /// Per face: its mesh before stitching.
  std::vector<FaceMesh> fm;

  /// Builds fields[f] (or sets face_error[f] when the surface cannot be evaluated).
  void build_field(std::size_t f);
  /// The face is meshed by itself: no error, no twin, not degenerate, not collapsed.
  bool meshed(std::size_t f) const {
    return face_error[f].empty() && twin_of[f] == geom::kNone && !m.faces[f].degenerate &&
           !collapsed[f];
  }
};

/// Coincident faces (twin_faces.cpp): sets twin_of and res.twins.
void find_twin_faces(ModelRun& run);

/// Stage 1 (model_curves.cpp): every edge's node parameters, with the size caps rounds,
/// the 1D chordal repair and at least 3 nodes per loop.
void mesh_curves(ModelRun& run);

/// Strips narrower than the proximity floor (strip_collapse.cpp): sets primary_of,
/// collapsed and res.collapsed, then gives each secondary its primary's nodes.
void collapse_strips(ModelRun& run);
/// The secondaries' parameters from their primaries' nodes (after a primary changed).
void sync_secondaries(ModelRun& run);

/// Stage 2 (crossing_rounds.cpp): numbers the nodes, meshes the faces, and repeats while
/// (u,v) boundaries cross; then triangulates the faces left with an unusable (u,v)
/// boundary from their boundary nodes. `t_curves` is when stage 1 began (its time ends
/// with the first numbering). Returns the seconds spent meshing faces.
double mesh_faces(ModelRun& run, Clock::time_point t_curves);

/// Stage 3 (stitch.cpp): the face meshes into res.mesh by global ids, failures listed,
/// unused model vertices dropped.
void stitch(ModelRun& run);

/// After stitching (simplify3d.cpp): triangles forced by entities smaller than the
/// feature size (feature_size()) collapsed, swapped or split away, each absorbed entity
/// listed in res.simplified. Does nothing under keep_topology.
void simplify(ModelRun& run);

}  // namespace uvmesh::surface::detail
