// Internal pieces of the surface stage, shared by curves.cpp, face.cpp, improve3d.cpp
// and mesher.cpp. Not installed.
#pragma once

#include <array>
#include <string>
#include <unordered_map>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::surface::detail {

class BoundaryCaps;

/// Stage 1: the parameters of the nodes of each model edge (ends included).
class EdgeDiscretizer {
 public:
  EdgeDiscretizer(const geom::Model& m, const param::SizeSpec& spec,
                  const std::vector<const param::FaceSizeField*>& fields);
  void set_min_closed(int n) { min_closed_ = n; }
  /// Node parameters t_0 = lo < ... < t_n = hi on the edge's curve. With `caps`, the
  /// size along the edge is also bounded by caps->cap() (sizes from the other edges of
  /// the faces around it).
  std::vector<double> discretize(geom::Id edge, const BoundaryCaps* caps = nullptr) const;

 private:
  struct Adjacent {
    geom::Id face;
    const geom::Curve2* pcurve;
  };
  /// What density() needs from the curve and the faces at t, before the caps.
  struct Sample {
    geom::Vec3 p, d1;  ///< C(t), C'(t)
    double speed;      ///< |C'(t)|
    double f;          ///< unit edges per unit of parameter without caps
  };
  /// Unit edges per unit of parameter at t; `speed` receives |C'(t)|.
  double density(const geom::Edge& e, geom::Id eid, double t, double& speed,
                 const BoundaryCaps* caps) const;
  Sample sample(const geom::Edge& e, geom::Id eid, double t) const;
  const geom::Model& m_;
  const param::SizeSpec& spec_;
  const std::vector<const param::FaceSizeField*>& fields_;
  std::vector<std::vector<Adjacent>> adj_;
  /// Per edge, the samples at the parameters already seen: the rounds under caps
  /// (MeshOptions::boundary_size_rounds) sample the same parameters again, and the curve
  /// evaluation with second derivatives and the face metrics behind them are most of
  /// the cost. One edge is discretized by one thread at a time, so each list is only
  /// touched by that thread.
  mutable std::vector<std::unordered_map<double, Sample>> seen_;
  int min_closed_ = 3;
};

/// The 1D mesh of the whole model: global node ids of every edge's nodes.
struct EdgeNodes {
  std::vector<double> t;     ///< curve parameters, ends included
  std::vector<NodeId> node;  ///< global node ids, same length
};

/// Size caps along model edges from the 1D mesh of the other edges of the faces around
/// them, the 1D part of what the chapter's size field does over a face (§7.5.1):
///  - gradation across a face: a boundary node of size h(p) bounds the size at x, on any
///    edge of a face through p, by h(p) + (beta - 1) |x - p| (the H-correction of the
///    background field, eq. 7.11, applied between boundary nodes). Without it a long
///    straight edge keeps hmax next to a face interior that the small features on its
///    other edges made fine, and the triangles between the two are slivers.
///  - proximity: where another part of a face's boundary comes closer to x than the size
///    at x (a sliver face, a thin ligament between a hole and the outline, a sharp
///    corner), the size is bounded by that gap, so that the face gets about one element
///    across instead of triangles spanning the gap with edges many times longer.
/// Built from one discretization; the edges are then discretized again under the caps
/// (MeshOptions::boundary_size_rounds times, as a refined edge is a new source).
class BoundaryCaps {
 public:
  BoundaryCaps(const geom::Model& m, const std::vector<std::vector<double>>& t,
               const param::SizeSpec& spec, double feature,
               double feature_angle = MeshOptions{}.feature_angle);
  /// Bound of the size at x on edge e (tangent: unit tangent of e at x), at most h.
  double cap(geom::Id e, const geom::Vec3& x, const geom::Vec3& tangent, double h) const;
  /// True when cap(e, ...) reads edge o: o is another edge of a face around e. What it
  /// reads of o is o's nodes; nothing else of the 1D mesh.
  template <class Pred>
  bool any_neighbour(geom::Id e, Pred&& pred) const {
    for (const Neighbour& nb : nbrs_[static_cast<std::size_t>(e)])
      if (pred(nb.edge)) return true;
    return false;
  }

 private:
  struct EdgePoly {
    std::vector<geom::Vec3> p;  ///< node points
    std::vector<double> h;      ///< size at each node: the shorter adjacent segment
    std::vector<double> len;    ///< length of each segment (p[i], p[i+1])
    double length = 0.0;        ///< of the polyline
    /// Unit directions in which the curve leaves its first and last node, at the scale of
    /// the feature size (boundary_caps.cpp, corner_chord(); zero where unknown).
    geom::Vec3 end_dir[2] = {geom::Vec3(0.0), geom::Vec3(0.0)};
    geom::Vec3 end_dir_far[2] = {geom::Vec3(0.0), geom::Vec3(0.0)};  ///< the same, farther
    geom::Vec3 lo{0.0}, hi{0.0};
    double hmin = 0.0;
    double tol = 0.0;  ///< the CAD edge's tolerance (largest of the edge's and its vertices')
    /// Runs of kChunk segments with their boxes and smallest node size, so that a query
    /// skips the far parts of a long edge (a slender face has two edges of 10^4 nodes
    /// side by side).
    struct Chunk {
      geom::Vec3 lo, hi;
      double hmin;
    };
    std::vector<Chunk> chunks;
    std::vector<Chunk> groups;  ///< boxes of kChunk consecutive chunks
  };
  static constexpr std::size_t kChunk = 16;
  std::vector<EdgePoly> poly_;
  struct Neighbour {
    geom::Id edge;     ///< another edge of a face around this one
    double gap_floor;  ///< a gap below this is none (proximity floor, the two CAD tolerances)
    /// A gap in [resolve_from, gap_floor) is sized at gap_floor (with a feature size:
    /// every gap above the CAD tolerances gets elements of at least L; boundary_caps.cpp).
    double resolve_from;
    /// A gap closing towards a vertex the two edges share at an acute corner (a wedge)
    /// is resolved down to this (L / 10, or the two CAD tolerances): boundary_caps.cpp,
    /// cap().
    double wedge_floor;
    bool shares_end[2];  ///< its first / last node is an end of this edge
    /// At a shared end: sin of the angle between the two edges' tangents there (the
    /// corner's angle in the tangent plane), 1 when it is not acute or when either edge is
    /// smooth there (no corner of the part's shape: sharp_edges() in boundary_caps.cpp).
    double corner_sin[2];
  };
  std::vector<std::vector<Neighbour>> nbrs_;  ///< per edge, in the order cap() visits them
  /// sin of the corner between edge a's end ka and edge b's end kb (one vertex), 1 when it
  /// is no straight acute wedge.
  static double wedge_sin(const EdgePoly& a, int ka, const EdgePoly& b, int kb);
  /// x (at gap d from nb's edge P) lies in the tip of an acute corner the two edges share.
  bool in_acute_wedge(const geom::Vec3& x, const EdgePoly& P, const Neighbour& nb, double d) const;
  double beta_ = 1.3, floor_ = 0.0, prox_floor_ = 0.0, eps_ = 0.0;
  /// The proximity floor between two free edges (each used once): hmin / 100.
  double sheet_floor_ = 0.0;
  bool sized_at_floor_ = false;  ///< a feature size is set: gaps below it sized at it
};

/// A face's contribution before stitching. Corners of triangles are global node ids
/// (>= 0) for boundary nodes, or -(k + 1) for the face's own k-th interior point.
struct FaceMesh {
  std::vector<geom::Vec3> points;  ///< interior points
  std::vector<std::array<NodeId, 3>> tris;
  std::vector<std::array<geom::Vec2, 3>> tri_uv;  ///< (u,v) of the corners (of interior points too)
  std::string error;                              ///< non-empty: the face failed, with the reason
  /// Pieces of edges whose (u,v) polylines crossed: {edge, curve parameter of the
  /// piece's midpoint}. Splitting them lets the polylines follow the pcurves closer.
  std::vector<std::pair<geom::Id, double>> refine_at;
  /// Triangulated from its boundary nodes only (its (u,v) boundary was unusable; see
  /// mesh_face's boundary_fallback).
  bool from_boundary = false;
  /// Non-empty: the face's (u,v) boundary was repaired, and how (a warning of the run).
  std::string repair;
  /// Failed on its (u,v) boundary: the plane chart (face_chart.cpp) and, with one loop,
  /// the boundary triangulation may apply.
  bool uv_defect = false;
  FaceStats stats;
};

/// Local (u,v) mesh of one face handed to the 3D improvement: vertex positions in both
/// spaces, the global id of each vertex (for boundary vertices; -1 inside), and which
/// vertices may move.
struct LocalMesh {
  std::vector<geom::Vec2> uv;
  std::vector<geom::Vec3> p;
  std::vector<NodeId> global;            ///< >= 0 boundary node; -1 interior
  std::vector<std::array<int, 3>> tris;  ///< CCW in (u,v)
  std::vector<char> fixed;
  std::vector<double> scale;  ///< metric scale used by mesher2d (see FaceMesh::scale)
};

/// Stage 2b: swaps and smoothing judged by 3D quality, moving vertices in (u,v) so they
/// stay on the surface. Returns {swaps, moves}.
/// collapse = false: swaps and smoothing only (after the chordal repair, whose added
/// points a collapse would take away again).
std::array<int, 2> improve3d(LocalMesh& lm, const geom::Surface& s, int passes,
                             bool collapse = true);

/// Q_K = alpha h_max / rho (eq. 7.6) of a 3D triangle, as 1/Q in [0, 1] (0: flat).
double q3(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c);

/// Stage 2: one face.
FaceMesh mesh_face(const geom::Model& m, geom::Id face, const std::vector<EdgeNodes>& edges,
                   const std::vector<geom::Vec3>& node_points, const param::FaceSizeField& field,
                   const MeshOptions& opt, bool boundary_fallback = false);

}  // namespace uvmesh::surface::detail

// ---- The closest point of a surface, which lives in geom (uvmesh/geom/project.h), under
// the names the surface stage has always called it by.
#include "uvmesh/geom/project.h"

namespace uvmesh::surface::detail {

using geom::project_to_surface;
using geom::Projection;

}  // namespace uvmesh::surface::detail
