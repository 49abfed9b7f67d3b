// uvmesh::surface::mesh_model -- the main job: a geom::Model in, one conforming,
// watertight surface mesh out (docs/ARCHITECTURE.md data flow; reference chapter
// §7.5-7.6.2).
//
//   surface::MeshOptions o;
//   o.size = surface::default_size(model);      // hmax = D/20 ... (see default_size)
//   o.size.hmax = model.bbox.diagonal() / 40;
//   surface::MeshResult r = surface::mesh_model(model, o);
//   for (const auto& f : r.failed) std::cerr << "face " << f.face << ": " << f.reason;
//   write(r.mesh);
//
// Stages (each timed in MeshResult::stages):
//   1. curves: every model edge discretized once at unit length in the 3D metric along
//      the curve (curve curvature and the metrics of the faces around it).
//   2. faces (parallel, TBB): (u,v) PSLG from the edge nodes through each use's pcurve,
//      mesher2d under M_uv = J^T M3 J, map back through sigma, 3D improvement.
//   3. stitch: global numbering by model entity, orientation with the face.
// A face that fails is listed in MeshResult::failed with the reason and left out; the
// rest of the model is meshed.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::surface {

struct MeshOptions {
  param::SizeSpec size;
  int threads = 0;         ///< 0: all cores
  bool optimize3d = true;  ///< swaps and smoothing judged by 3D quality
  int optimize3d_passes = 4;
  /// Field points of each face's 2D mesh placed frontally (mesher2d's
  /// FieldPointMethod::Frontal, §7.4.3) instead of by edge saturation (§7.5.2). Off by
  /// default: on the corpus at hmax D/40 it raises the median triangle shape on 50 of 53
  /// models but worsens the largest Q on 13 and makes 5-12% more triangles
  /// (bench/surface/results.md, Session 24).
  bool frontal = false;
  /// The chordal tolerance the user asked for is divided by this before it sizes
  /// elements: a unit edge may be sqrt(2) long, and the sagitta grows with h^2.
  double chordal_safety = 4.0;
  /// Rounds of chordal repair (0 = off): edge segments whose chord midpoint is farther
  /// than 0.9 chordal tolerance from the curve are split (1D stage), and so are the
  /// triangles whose centroid deviates that much from the surface (after the 3D
  /// improvement).
  int chordal_repair_rounds = 8;
  int min_segments_closed_edge = 3;
  /// Rounds of size caps on the edges from the other edges of their faces (gradation
  /// across a face and proximity of another part of its boundary); 0 = off.
  int boundary_size_rounds = 3;
  /// Wall-clock seconds the 2D mesher may spend on one face (0: no limit). A face that
  /// exceeds it fails with that reason, like any other failed face, and the run goes on.
  double face_time_limit = 120.0;
  /// Feature size L (`--min-feature`; 0: feature_size() derives it). Model entities smaller
  /// than L -- edges shorter, faces narrower, two parts of a face's boundary closer -- are
  /// CAD artefacts at the user's scale: they set no size below L and are absorbed into
  /// their neighbours (MeshResult::simplified lists each absorption).
  double min_feature = 0.0;
  /// Dihedral angle (radians) below which a model edge is smooth: the faces on either
  /// side may be meshed as one domain, so mesh edges need not follow it.
  double feature_angle = 20.0 * 3.14159265358979323846 / 180.0;
  /// Every model entity stays a mesh entity, proximity resolves down to hmin / 100 and
  /// nothing is absorbed (`--keep-topology`: the meshes of before feature sizes).
  bool keep_topology = false;
  /// Called after each face, from the worker thread that meshed it (so it must be
  /// thread-safe): faces done so far, total faces.
  std::function<void(int, int)> progress;
};

/// Defaults relative to the bounding-box diagonal D: hmax = D/20, hmin = D/1000,
/// curvature angle 18 degrees (20 elements per 2 pi), chordal tolerance D/1000,
/// gradation 1.3.
param::SizeSpec default_size(const geom::Model& m);

/// The options mesh_model runs `m` with: `opt`, except that a subdivision cage keeps its
/// topology (its patches and creases are the user's control net, not CAD artefacts).
MeshOptions effective_options(const geom::Model& m, const MeshOptions& opt);

/// The sizes mesh_model makes elements for: opt.size with its chordal tolerance divided
/// by opt.chordal_safety (MeshResult::size holds them after a run). What a check of the
/// mesh measures unit edges against; the chordal deviation is still compared with the
/// tolerance the user asked for, opt.size.chordal_tol.
param::SizeSpec meshing_size(const MeshOptions& opt);

/// The narrowest gap the sizes resolve: proximity (two edges of a face closer than the
/// size) refines down to the feature size `feature` (feature_size()), no further; with
/// no feature size (keep_topology: 0) down to hmin / 100 (hmin = D/1000 when unset). A
/// face narrower than that -- a CAD sliver, the last micrometres of a tangential contact
/// -- gets elements as long as the floor across a narrower width, and the simplify
/// stage absorbs them. Boundary segments shorter than it set no size either.
double proximity_floor(const param::SizeSpec& spec, double diagonal, double feature);

/// How far apart two model edges of a face must be for proximity to see a gap between
/// them: kGapToleranceFactor (1: the two tolerance tubes touch) times the sum of their
/// gap_tolerance()s. Closer than that, the CAD model itself does not know on which side of the
/// other either curve lies: OCC's tolerances say a curve may be anywhere within its tolerance of
/// where it is drawn. Refining such a "gap" meshed the model's noise: pcurves ending a
/// hundredth of a millimetre from their 3D vertex had their edges graded down to segments
/// some forty times shorter than that gap, and needles formed between the curve's nodes and the
/// surface's image of the pcurve.
inline constexpr double kGapToleranceFactor = 1.0;
/// An edge's tolerance for that purpose: the largest of its own and its end vertices'.
double gap_tolerance(const geom::Model& m, geom::Id edge);
/// kGapToleranceFactor * gap_tolerance(e) for every edge e: measure_quality's edge_gap.
std::vector<double> edge_gap_floors(const geom::Model& m);

/// Share of the model's thinnest extent below which an entity may be an artefact: the
/// default feature size is at most that extent / kFeatureShare.
inline constexpr double kFeatureShare = 50.0;
/// The feature size L of a run: opt.min_feature, else the smallest size hmin (D/1000
/// when unset, as default_size()) but no more than the model box's thinnest side /
/// kFeatureShare; 0 under keep_topology.
double feature_size(const MeshOptions& opt, const geom::Box3& bbox);

struct FaceFailure {
  geom::Id face = geom::kNone;
  std::string reason;
};

struct FaceStats {
  geom::Id face = geom::kNone;
  int boundary_nodes = 0;
  int triangles = 0;
  double seconds = 0;
  int swaps3d = 0, moves3d = 0;
  int chordal_splits = 0;  ///< triangles split by the chordal repair
  /// Edges of the face's triangles and how many have a metric length in
  /// [1/sqrt2, sqrt2], shorter, longer -- measured in this face's metric (edges on the
  /// face's boundary are counted by each face around them).
  std::int64_t edges = 0, unit_edges = 0, short_edges = 0, long_edges = 0;
};

/// One absorption of a model entity smaller than the feature size, or one smooth model
/// edge the mesh no longer follows: what, which entities, how large, and why.
struct Simplification {
  std::string what;  ///< e.g. "edge collapsed to a vertex", "face absorbed", "edge dissolved"
  std::vector<geom::Id> vertices, edges, faces;
  double size = 0;  ///< the entity's length or width
  std::string why;
};

struct Stage {
  std::string name;
  double seconds = 0;
};

struct MeshResult {
  SurfaceMesh mesh;
  /// The sizes the elements were made for: meshing_size(options), so that a report of
  /// the mesh measures against what was used instead of deriving it again.
  param::SizeSpec size;
  std::vector<FaceFailure> failed;
  std::vector<FaceStats> faces;
  std::vector<Stage> stages;
  std::vector<std::string> warnings;
  /// Coincident faces (same edges, same surface): {face, the face meshed for it}. The
  /// first is not meshed; the second's triangles stand for both.
  std::vector<std::pair<geom::Id, geom::Id>> twins;
  /// Faces not meshed because they lie within the tolerance tube of their own boundary
  /// (geom::Face::degenerate), with the measurements that say so. Not failures: by the
  /// model's own tolerances such a face is a curve, not a surface.
  std::vector<FaceFailure> degenerate;
  /// Strips not meshed because they are narrower than proximity_floor(): a face of two
  /// edges between the same two vertices, nowhere farther apart than the floor, or than
  /// kGapToleranceFactor times the sum of their gap_tolerance()s when that is larger (nor
  /// than a tenth of the chordal tolerance, when one is set). Its two edges share one set of
  /// nodes (the faces on either side meet along it; the solid stays closed); its
  /// triangles could only have been slivers. Not failures; the reason gives the edges,
  /// the width and the floor.
  std::vector<FaceFailure> collapsed;
  /// Entities absorbed because they are smaller than the feature size, and smooth edges
  /// dissolved (MeshOptions::min_feature, feature_angle), in the order they were made.
  std::vector<Simplification> simplified;
  bool ok() const { return failed.empty(); }
  /// Share of unit edges over all faces (FaceStats::unit_edges / edges).
  /// Measured in each face's meshing metric (kFaceMetricName).
  double unit_edge_share() const;
};

/// What MeshResult::unit_edge_share() and FaceStats' edge counts measure against: the
/// metric each face was meshed for, i.e. the size field of MeshResult::size on the face
/// times the boundary scale mesher2d applied there (m2d::Mesh::boundary_scale: sizes
/// imposed by the face's boundary discretization). The report's metric_edge_lengths
/// measures against the size field alone (io::kSizeFieldMetricName).
inline constexpr const char* kFaceMetricName =
    "face meshing metric: size field of the meshing size times mesher2d's boundary scale";

MeshResult mesh_model(const geom::Model& m, const MeshOptions& opt);

}  // namespace uvmesh::surface
