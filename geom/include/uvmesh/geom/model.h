// uvmesh::geom::Model -- the boundary representation the mesher works on.
//
// Built by a back end (OCC import: uvmesh/geom/occ.h, used by uvmesh::io's readers).
// Every topological entity appears once (shared edges are shared), ids are indices in
// file order (the order of OCC's TopExp::MapShapes). Seams, degenerate edges (poles),
// periodicity, face orientation and tolerances are explicit here so that later stages
// never rediscover them.
//
//   geom::Model m = ...;
//   for (const geom::Face& f : m.faces)
//     for (const geom::Loop& l : f.loops)
//       for (const geom::EdgeUse& use : l.uses) {
//         const geom::Edge& e = m.edges[use.edge];
//         geom::Vec2 uv = use.pcurve->point(use.range.lo);   // start of the use in (u,v)
//       }
//
// Orientation convention: loops are given for the face in its natural orientation (the
// one of its surface, normal = sigma_u x sigma_v); the outer loop then runs
// counter-clockwise in (u,v) and holes clockwise. `Face::reversed` says that the
// material side is the other one: the mesher must flip that face's triangles.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "uvmesh/geom/curve.h"
#include "uvmesh/geom/surface.h"

namespace uvmesh::geom {

struct Vertex {
  Vec3 p;
  double tol = 0.0;  ///< CAD tolerance (radius of the vertex's tolerance ball)
};

/// A vertex added by split_vertices_closing_open_edges(): `vertex` was split off `from`.
struct VertexSplit {
  Id vertex = kNone;
  Id from = kNone;
  std::string reason;
};

struct Edge {
  std::shared_ptr<const Curve> curve;  ///< null only for degenerate edges
  Interval range;                      ///< curve parameter range, v0 at lo, v1 at hi
  Id v0 = kNone;
  Id v1 = kNone;
  bool degenerate = false;  ///< collapses to one point (pole, cone apex); no 3D curve
  double tol = 0.0;
  double length = 0.0;  ///< arc length (0 for degenerate edges)
};

/// One use of an edge by a face's loop.
struct EdgeUse {
  Id edge = kNone;
  bool reversed = false;                 ///< traversed from v1 to v0 in the loop
  std::shared_ptr<const Curve2> pcurve;  ///< (u,v) curve of the edge on this face
  Interval range;                        ///< pcurve parameter range (same as the edge's)
  bool seam = false;  ///< the edge is used twice by this face (both sides of a seam)
  /// The edge is embedded in the face (OCC orientation INTERNAL: a crack tip, an imprinted
  /// curve), not part of its boundary: the mesh must conform to it, with the face on both
  /// sides. Not a step of the loop's cycle.
  bool internal = false;
};

struct Loop {
  std::vector<EdgeUse> uses;  ///< in traversal order
  bool outer = false;
};

struct Face {
  std::shared_ptr<const Surface> surface;  ///< null for a face without surface (kind other)
  SurfaceKind kind = SurfaceKind::Other;
  std::vector<Loop> loops;  ///< outer loop first (when there is one)
  bool reversed = false;
  double tol = 0.0;
  Box2 uv_box;        ///< box of the loops in (u,v)
  bool valid = true;  ///< CAD validity (OCC BRepCheck) when checked
  std::string invalid_reason;
  /// The face has no extent the model's own tolerances can resolve: its area is at most
  /// its boundary length times the largest tolerance of its boundary edges and vertices
  /// (it lies inside the tolerance tube of its boundary). Such a face is not meshed and is
  /// reported with `degenerate_reason` (surface::MeshResult::degenerate). Tested on faces
  /// with an open wire only: a closed wire around a sliver still closes its shell.
  bool degenerate = false;
  std::string degenerate_reason;
  Id shell = kNone;  ///< first shell containing the face, kNone for a loose face
  std::string name;  ///< the CAD system's name (STEP entity name), "" when it has none
};

struct Shell {
  std::vector<Id> faces;
  bool closed = false;
};

struct Solid {
  std::vector<Id> shells;
  std::string name;  ///< the CAD system's name (STEP entity name), "" when it has none
};

struct Model {
  std::string source;  ///< file the model was read from
  std::string format;  ///< "step", "iges", "brep", "analytic"
  std::string units;   ///< length unit of the coordinates, e.g. "mm"; "" when unknown
  std::vector<Vertex> vertices;
  std::vector<Edge> edges;
  std::vector<Face> faces;
  std::vector<Shell> shells;
  std::vector<Solid> solids;
  Box3 bbox;
  /// Vertices the import split (split_vertices_closing_open_edges()), in id order.
  std::vector<VertexSplit> vertex_splits;
};

/// What a person or a test wants to know about a model (`uvmesh info`).
struct ModelStats {
  int solids = 0, shells = 0, faces = 0, edges = 0, vertices = 0;
  std::map<std::string, int> surface_kinds;  ///< MANIFEST vocabulary -> face count
  std::map<std::string, int> curve_kinds;    ///< edges by 3D curve kind (degenerate excluded)
  int seam_edges = 0;                        ///< edges used twice by one face
  int faces_with_seams = 0;
  int degenerate_edges = 0;
  int free_edges = 0;          ///< non-degenerate, non-seam edges used by exactly one face
  int non_manifold_edges = 0;  ///< edges used by three or more distinct faces
  int short_edges = 0;         ///< non-degenerate edges shorter than short_edge_rel * diagonal
  double short_edge_threshold = 0.0;
  double min_edge_length = 0.0;
  int invalid_faces = 0;
  int open_shells = 0;
  /// Vertices farther than `gap_factor` times their tolerance from an end of an edge
  /// they bound (a sign of corrupted coordinates).
  int vertex_gaps = 0;
  double max_vertex_gap = 0.0;
};

struct StatsOptions {
  double short_edge_rel = 1e-3;  ///< the MANIFEST's "edges shorter than 1e-3*diag"
  double gap_factor = 1e3;       ///< vertex gap allowed, in units of the tolerances
};

ModelStats compute_stats(const Model& m, const StatsOptions& opt = {});

/// For every edge, the distinct faces that use it (seam uses counted once).
std::vector<std::vector<Id>> edge_faces(const Model& m);

/// An edge whose two ends are one vertex although its curve's ends are farther apart
/// than the edge's own tolerance is open: the file merged two distinct points into one
/// vertex and gave it a tolerance that covers both (e.g. 1 mm edges closed by a vertex of
/// tolerance 1 mm). Meshed as it is, that edge's last node is its first one,
/// and the edges and faces that really end at its other end are pulled to the vertex:
/// the faces fold there. Such a vertex is split: the two ends of each of these edges are
/// the seeds of separate vertices, every other edge end at the vertex goes to the seed
/// nearest its curve end, the seed nearest the vertex's point keeps the vertex (and its
/// id), the others become new vertices at their seed's point, appended and listed in
/// Model::vertex_splits. Each tolerance becomes the radius the vertex then needs: the
/// largest distance from its point to its edges' curve ends, at least their tolerances.
/// A vertex is left alone (and the edge stays closed) when the split is not clear-cut:
/// a degenerate edge at it, an edge end about as near to two seeds (not within half the
/// distance of the second nearest), or a loop of a face that would no longer chain
/// through it (two consecutive uses whose shared end would go to different vertices,
/// e.g. a loop made of that edge alone). Returns the number of vertices added.
int split_vertices_closing_open_edges(Model& m);

}  // namespace uvmesh::geom
