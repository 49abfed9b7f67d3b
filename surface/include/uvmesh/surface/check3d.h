// uvmesh::surface 3D checks and measures of a SurfaceMesh (docs/ARCHITECTURE.md "Quality
// and size measures": topology, self-intersections, shape, metric edge lengths, chordal
// deviation). Everything returns data; nothing prints.
//
//   surface::TopologyReport t = surface::check_topology(mesh);
//   bool watertight = t.free_edges == 0 && t.non_manifold_edges == 0;
//   surface::IntersectionReport x = surface::find_self_intersections(mesh);
//   surface::QualityReport q = surface::measure_quality(mesh);   // q.Q_max,
//   q.bad_away_from_corners surface::ChordalReport c = surface::measure_chordal(mesh, model,
//   /*threads=*/0);
//
// Conventions
//   * Triangles whose indices repeat (a a b) or are out of range are "degenerate by
//     index": counted, and left out of the edge analysis and of the intersection search.
//     Exactly collinear triangles (zero area, decided with exact predicates) are counted
//     as degenerate too and left out of the intersection search (reported in
//     IntersectionReport::skipped_degenerate), but keep their edges.
//   * Lists are capped (max_list / max_report) and sorted, so that every report is
//     deterministic and independent of the thread count.
//   * An empty SurfaceMesh::point_dim means "no classification": no point counts as a
//     model vertex.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::surface {

using TriId = std::int32_t;

// ---------------------------------------------------------------------------------------
// 1. Topology
// ---------------------------------------------------------------------------------------

/// An edge (a < b) and the triangles using it, with their face ids (same order).
struct EdgeIssue {
  NodeId a = 0, b = 0;
  std::vector<TriId> triangles;
  std::vector<geom::Id> faces;
};

struct ClosePair {
  NodeId a = 0, b = 0;  ///< a < b
  double distance = 0;
};

struct ClosePointsReport {
  double tolerance = 0;         ///< absolute: rel_tol * bounding-box diagonal
  std::size_t pairs = 0;        ///< pairs of distinct points with distance < tolerance (or == 0)
  std::vector<ClosePair> list;  ///< the first max_list pairs in (a, b) order
  double min_distance = 0;      ///< smallest distance among all close pairs (0 when none)
};

/// Pairs of distinct points closer than rel_tol times the bounding-box diagonal of
/// `points` (exact duplicates always count). Grid sort, O(n log n). TetGen's -pY rejects
/// such surfaces ("duplicated facets") at about rel_tol = 1e-8 (docs/ARCHITECTURE.md).
ClosePointsReport find_close_points(const std::vector<geom::Vec3>& points, double rel_tol = 1e-8,
                                    int max_list = 20);

struct TopologyOptions {
  double close_rel_tol = 1e-8;
  int max_list = 20;
};

struct TopologyReport {
  std::size_t points = 0, triangles = 0;
  std::size_t edges = 0;               ///< unique undirected edges of the valid triangles
  std::size_t free_edges = 0;          ///< used by one triangle
  std::size_t non_manifold_edges = 0;  ///< used by three or more triangles
  /// Used by exactly two triangles that traverse it in the same direction.
  std::size_t inconsistent_edges = 0;
  std::size_t degenerate_triangles = 0;  ///< repeated_index + zero_area (+ bad_index)
  std::size_t repeated_index_triangles = 0;
  std::size_t bad_index_triangles = 0;  ///< an index outside [0, points)
  std::size_t zero_area_triangles = 0;  ///< exactly collinear corners (exact predicate)
  std::size_t unreferenced_points = 0;
  /// V - E + F over referenced points, edges and valid triangles (2 for a sphere).
  long long euler_characteristic = 0;

  std::vector<EdgeIssue> free_list, non_manifold_list, inconsistent_list;  // capped
  std::vector<TriId> degenerate_list;                                      // capped
  std::vector<NodeId> unreferenced_list;                                   // capped
  ClosePointsReport close_points;

  /// Closed 2-manifold, consistently oriented, nothing degenerate.
  bool watertight() const {
    return free_edges == 0 && non_manifold_edges == 0 && inconsistent_edges == 0 &&
           degenerate_triangles == 0;
  }
};

TopologyReport check_topology(const SurfaceMesh& m, const TopologyOptions& opt = {});

/// One solid's own surface: the triangles of the faces of its shells, checked on their
/// own. In a conforming assembly an interface face bounds two solids and its edges are
/// non-manifold in the whole mesh, yet every solid must be closed and manifold by itself
/// (what a volume mesher filling it needs). The one definition of a "closed solid" used by
/// the report (io::CheckData::solids) and the volume stage (volume.h).
struct SolidSurface {
  geom::Id solid = geom::kNone;
  bool closed = false;                 ///< every shell of the solid is closed in the model
  std::vector<geom::Id> faces;         ///< the faces of its shells, ascending
  std::vector<TriId> triangles;        ///< the mesh's triangles on those faces, ascending
  std::size_t free_edges = 0;          ///< edges used by one of those triangles
  std::size_t non_manifold_edges = 0;  ///< edges used by three or more of them
  /// Closed in the model and in the mesh: what a volume mesher can fill.
  bool watertight() const {
    return closed && !triangles.empty() && free_edges == 0 && non_manifold_edges == 0;
  }
};

SolidSurface solid_surface(const SurfaceMesh& m, const geom::Model& model, geom::Id solid);

// ---------------------------------------------------------------------------------------
// 2. Self-intersections
// ---------------------------------------------------------------------------------------
//
// Two triangles of a conforming mesh may only meet in what they share by index: nothing,
// one vertex or one edge. A pair intersects when their closed point sets meet anywhere
// else. Decided with exact predicates (orient3d / orient2d), so touching, coplanar and
// 1-ulp cases are classified exactly:
//   * no shared index: any common point (touching counts);
//   * one shared vertex: a common point other than that vertex;
//   * a shared edge: only when the two are coplanar with their third vertices on the
//     same side of the edge (the mesh folds onto itself); a dihedral angle of exactly 0
//     is a fold, any other angle is not;
//   * the same three indices (a duplicated triangle): always.
// Two distinct points at the same coordinates are distinct vertices: triangles touching
// there intersect (find such points with find_close_points).

enum class PairKind : std::int8_t { Disjoint = 0, SharedVertex = 1, SharedEdge = 2, Duplicate = 3 };

struct IntersectingPair {
  TriId t0 = 0, t1 = 0;  ///< t0 < t1
  geom::Id f0 = geom::kNone, f1 = geom::kNone;
  PairKind kind = PairKind::Disjoint;  ///< what the two share by index
};

struct IntersectionReport {
  std::size_t triangles = 0;
  std::size_t skipped_degenerate = 0;  ///< zero-area or bad-index triangles not tested
  std::size_t candidate_pairs = 0;     ///< pairs whose bounding boxes overlap
  std::size_t intersecting_pairs = 0;
  std::vector<IntersectingPair> pairs;  ///< the first max_report in (t0, t1) order
};

/// AABB tree over the triangles (median split), parallel traversal (threads: 0 = all
/// cores), exact pair test. Deterministic.
IntersectionReport find_self_intersections(const SurfaceMesh& m, int max_report = 20,
                                           int threads = 0);

/// The same test for the pairs with at least one triangle t where subset[t] is set (a
/// subset shorter than the mesh counts as unset beyond its end): a tree over the subset,
/// queried by every triangle's box, so that a few changed triangles are checked against
/// a large mesh in O(n log k). Pairs, counts and order as above, restricted to those.
IntersectionReport find_intersections_with(const SurfaceMesh& m, const std::vector<char>& subset,
                                           int max_report = 20, int threads = 0);

/// The pair test used above, for two triangles of m (tests compare it with brute force).
/// Degenerate triangles (repeated index, zero area) never intersect by this definition.
bool triangles_intersect(const SurfaceMesh& m, TriId t0, TriId t1);

/// Of the given intersecting pairs, those where the model itself intersects: the two
/// triangles share no node (or one node: then the pieces at that corner are left out),
/// and the images through sigma of their (u,v) triangles (each cut into k^2 pieces,
/// mapped onto its face's surface) intersect as well. There no mesh
/// that follows the CAD surfaces can avoid the intersection: a swept surface folding over
/// itself (a swept tube whose normal reverses across lines where sigma_u x sigma_v
/// vanishes), two faces overlapping in the file. Pairs on faces without a surface
/// are not counted. A lower bound: two flat triangles can cross next to a line where the
/// surfaces cross while the finer pieces under them pass each other (a spindle torus: 74%
/// of its pairs found with k = 4, 85% with k = 8). Returns the indices into `pairs`.
std::vector<std::size_t> pairs_intersecting_in_model(const SurfaceMesh& m, const geom::Model& model,
                                                     const std::vector<IntersectingPair>& pairs,
                                                     int k = 4);

// ---------------------------------------------------------------------------------------
// 3. Shape quality (3D): Q = alpha h_max / rho, alpha = sqrt(3)/6; q = 1/Q
// ---------------------------------------------------------------------------------------

struct BadTriangle {
  TriId triangle = 0;
  geom::Id face = geom::kNone;
  double Q = 0;
};

struct QualityReport {
  std::size_t triangles = 0;
  std::size_t flat = 0;  ///< zero computed area: Q = inf, q = 0
  /// Shares (0..1) of triangles with Q below 1.5, 2 and 3.
  double share_Q_lt_1_5 = 0, share_Q_lt_2 = 0, share_Q_lt_3 = 0;
  /// Percentiles are nearest-rank: p5 of q is the smallest value with at least 5% of the
  /// triangles at or below it.
  double q_min = 0, q_p1 = 0, q_p5 = 0, q_p50 = 0, q_mean = 0;
  double Q_p50 = 0, Q_p95 = 0, Q_p99 = 0, Q_max = 0;
  double min_angle_deg = 0, max_angle_deg = 0;
  /// Triangles with Q >= 3 that touch a model vertex (point_dim == 0) / that do not.
  std::size_t bad_at_corners = 0;
  std::size_t bad_away_from_corners = 0;
  /// Of the bad triangles away from model vertices, those spanning a gap of the CAD face
  /// narrower than the mesher's proximity floor (`narrow_gap` of measure_quality): all
  /// three points on model edges or vertices (point_dim <= 1) and a width (twice the area
  /// over the longest side) below the floor. The face itself is narrower there than any
  /// element the sizes allow -- in practice the last micrometres before two model edges
  /// meet tangentially at a vertex -- so the triangles across it cannot be well shaped.
  /// With edge_gap given, a gap between two model edges narrower than the pair's
  /// tolerance floor (kGapToleranceFactor times the sum of their gap_tolerance()s, the
  /// floor below which the mesher's proximity sees no gap) counts too: the CAD model
  /// does not resolve it.
  /// Counted here and NOT in bad_away_from_corners; 0 unless narrow_gap > 0.
  std::size_t bad_in_narrow_gaps = 0;
  /// The widest of those gaps (largest width of a triangle counted there; 0 if none), so
  /// that a reader sees how much the exception excuses.
  double widest_narrow_gap = 0.0;
  /// Of bad_at_corners, those at a model vertex where the CAD face they lie on has a
  /// corner angle below kAcuteCornerDeg (the sum of the angles at that vertex of the face's
  /// triangles around it): no triangle there can be well shaped, whatever the sizes.
  /// The only exemption of the acceptance. smallest_corner_deg: the smallest corner angle
  /// at any bad triangle of bad_at_corners, so a reader sees what the exemption excuses.
  std::size_t bad_at_acute_corners = 0;
  double smallest_corner_deg = 360.0;
  /// Triangles with Q > 10 anywhere (slivers a volume mesher or a solver cannot use).
  std::size_t Q_over_10 = 0;
  /// The bad triangles away from corners, worst first (ties by id), capped at max_list.
  std::vector<BadTriangle> bad_list;
};

/// A CAD corner narrower than this (degrees) excuses the bad triangles at it
/// (QualityReport::bad_at_acute_corners).
inline constexpr double kAcuteCornerDeg = 20.0;

/// Q of one triangle (inf when its computed area is zero).
double triangle_Q(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c);

/// narrow_gap > 0: bad triangles in faces narrower than that are counted apart
/// (QualityReport::bad_in_narrow_gaps); surface::proximity_floor gives the mesher's own.
/// edge_gap (optional, indexed by model edge id): each edge's share of the tolerance
/// floor, kGapToleranceFactor * gap_tolerance(edge); a triangle whose points lie on two
/// edges a and b uses max(narrow_gap, edge_gap[a] + edge_gap[b]).
QualityReport measure_quality(const SurfaceMesh& m, int max_list = 100, double narrow_gap = 0.0,
                              const std::vector<double>* edge_gap = nullptr);

// ---------------------------------------------------------------------------------------
// 4. Metric edge lengths (unit mesh: length in [1/sqrt2, sqrt2])
// ---------------------------------------------------------------------------------------

struct EdgeLengthReport {
  std::size_t edges = 0;                        ///< unique edges of the valid triangles
  std::size_t unit = 0;                         ///< with length in [1/sqrt2, sqrt2]
  double unit_share = 0;                        ///< unit / edges
  std::size_t short_edges = 0, long_edges = 0;  ///< below / above that interval
  double min = 0, max = 0, mean = 0;
  /// Histogram on a log2 scale, bins of half an octave: bin i covers
  /// [bin_lo[i], bin_lo[i+1]); bin_lo[i] = 2^((i - 8)/2) for i = 1..16, bin 0 starts at
  /// 0 and the last one ends at infinity. The unit interval is exactly bins 7 and 8.
  std::vector<double> bin_lo;
  std::vector<std::size_t> bin_count;
};

/// metric_length(a, b) is called once per unique edge (a < b), sequentially, in edge
/// order (it need not be thread-safe).
EdgeLengthReport measure_edge_lengths(const SurfaceMesh& m,
                                      const std::function<double(NodeId, NodeId)>& metric_length);

// ---------------------------------------------------------------------------------------
// 5. Chordal deviation against the exact surfaces
// ---------------------------------------------------------------------------------------

struct ChordalSample {
  TriId triangle = -1;
  geom::Id face = geom::kNone;
  int which = 0;                   ///< 0: centroid, 1: midpoint of corners 0-1, 2: 1-2, 3: 2-0
  geom::Vec3 x{0.0, 0.0, 0.0};     ///< the sample on the flat triangle
  geom::Vec3 foot{0.0, 0.0, 0.0};  ///< its projection on the surface
  geom::Vec2 uv{0.0, 0.0};
  double distance = 0;
};

struct ChordalReport {
  std::size_t triangles = 0;  ///< triangles sampled
  std::size_t samples = 0;
  /// Triangles not sampled: face id out of range, face without surface, or no
  /// triangle_uv in the mesh.
  std::size_t skipped_triangles = 0;
  std::size_t not_converged = 0;  ///< samples whose projection did not converge
  double max = 0, mean = 0;
  std::vector<double> face_max;  ///< indexed by face id (model.faces.size()); 0 if unsampled
  ChordalSample worst;           ///< the sample of largest distance (smallest id on ties)
};

/// Samples the centroid and the three edge midpoints of every triangle, with the (u,v)
/// interpolated from triangle_uv as the starting point, and projects them
/// (geom::project_to_surface) on their
/// face's surface (box: Face::uv_box, or Surface::bounds() if uv_box is empty, extended
/// by half a period in periodic directions). Faces run in parallel in a task arena of
/// `threads` (0 = all cores); faces sharing one Surface object run in the same task
/// (geom surfaces are one-object-per-thread). Deterministic.
ChordalReport measure_chordal(const SurfaceMesh& m, const geom::Model& model, int threads = 0);

}  // namespace uvmesh::surface
