// uvmesh::mesher2d -- anisotropic 2D Delaunay mesher (reference chapter §7.1-7.3,
// 7.5, 7.6.1). Depends on nothing but the standard library.
//
// Usage:
//   uvmesh::m2d::Pslg in;
//   in.points = {{0,0},{1,0},{1,1},{0,1}};
//   in.segments = {{0,1,1},{1,2,1},{2,3,1},{3,0,1}};
//   uvmesh::m2d::Result r = uvmesh::m2d::mesh(in, uvmesh::m2d::SizeSpec::uniform(0.05));
//   if (!r.ok()) { /* r.status.message names what failed and where */ }
//   for (auto& t : r.mesh.triangles) { /* t[0], t[1], t[2] index r.mesh.vertices, CCW */ }
//
// Pipeline (each stage timed in Result::stats):
//   1. input check, duplicate merge          (exact comparison; reported)
//   2. boundary discretization               (segments split at unit metric length, eq. 7.10;
//                                             off when Options::split_segments is false)
//   3. Delaunay triangulation in a box       (§7.3.2, kernel T(i+1) = T(i) - C(P) + B(P))
//   4. boundary enforcement by swaps         (§7.2.2); the size capped by the local
//                                            feature size (Options::feature_size)
//   5. domain coloring                       (§7.3.4): exterior and holes removed, regions
//   6. field points (Options::field_points)  anisotropic kernel (§7.6.1) for a metric field.
//                                            Saturation: edge saturation (§7.3.5, 7.5.2);
//                                            a uniform field first gets corner bisector
//                                            points, the boundary edges' optimal points
//                                            (§7.4.3) and the equilateral lattice of side h.
//                                            Frontal: waves of optimal points on the front
//                                            between accepted and unaccepted triangles
//                                            (§7.4.3, combined advancing-front-Delaunay);
//                                            saturation waves then close what it left
//   7. optimization                          (§7.3.6): quality swaps, relocation in the metric;
//                                            max-min relocation and a repair of bad
//                                            triangles (swaps, edge collapse and split:
//                                            Q > 1.18 for a uniform field, Q > 1.4 for a
//                                            varying one, each triangle judged in the mean
//                                            of its vertex metrics); a varying field then
//                                            gets a size pass (§7.5.2: split edges longer
//                                            than sqrt2, collapse those under 1/sqrt2)
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace uvmesh::m2d {

using VertId = std::int32_t;
using TriId = std::int32_t;
inline constexpr std::int32_t kNone = -1;

struct Vec2 {
  double x = 0, y = 0;
};

// Symmetric positive definite 2x2 tensor [[m11 m12][m12 m22]]; the length of a vector e
// is sqrt(e^T M e) (eq. 7.10). A size h gives M = I / h^2 (eq. 7.9).
struct Metric2 {
  double m11 = 1, m12 = 0, m22 = 1;
  static Metric2 iso(double h) { return {1.0 / (h * h), 0.0, 1.0 / (h * h)}; }
};

// Planar straight line graph, as in Triangle's .poly format.
struct Pslg {
  struct Segment {
    VertId a = 0, b = 0;
    int marker = 0;
  };
  struct Region {
    Vec2 seed;
    double attribute = 0;
  };
  std::vector<Vec2> points;
  std::vector<int> point_markers;  // optional: empty, or one per point
  std::vector<Segment> segments;
  std::vector<Vec2> holes;      // seeds: the connected component containing them is removed
  std::vector<Region> regions;  // seeds: the component containing them gets the attribute
};

// Size specification: the control space of §7.5.1.
struct SizeSpec {
  enum class Kind { Uniform, Scalar, Metric };
  Kind kind = Kind::Uniform;
  double h = 0;                                   // Uniform; <= 0 means "from the boundary"
  std::function<double(double, double)> size;     // Scalar: h(x, y) > 0
  std::function<Metric2(double, double)> metric;  // Metric: M(x, y) SPD

  static SizeSpec uniform(double h) {
    SizeSpec s;
    s.kind = Kind::Uniform;
    s.h = h;
    return s;
  }
  static SizeSpec scalar(std::function<double(double, double)> f) {
    SizeSpec s;
    s.kind = Kind::Scalar;
    s.size = std::move(f);
    return s;
  }
  static SizeSpec aniso(std::function<Metric2(double, double)> f) {
    SizeSpec s;
    s.kind = Kind::Metric;
    s.metric = std::move(f);
    return s;
  }
};

// How field points are placed (stage 6).
//   Saturation: points at unit spacing along the edges of the current mesh, wave after wave
//     (§7.3.5, §7.5.2); a uniform field starts from the equilateral lattice.
//   Frontal: the combined advancing-front-Delaunay method of §7.4.3. A triangle is accepted
//     when its circumradius in the metric is that of a unit triangle within a margin; the
//     front is the edges between an accepted triangle (or the boundary) and an unaccepted
//     one, and each front edge gets the point that makes a unit equilateral triangle with
//     it in the metric at the edge, kept inside the unaccepted triangle's circumdisk,
//     corrected once with the metric at the point and filtered by distance. Waves run
//     until no front point can be inserted; saturation waves then split what is still
//     too long (narrow gaps where fronts met).
// The default is Saturation, because Frontal is not at least as good everywhere it was
// measured (bench/results.md, the field-point modes section). Frontal gives the higher
// median shape quality on the anisotropic fields and is faster on the boundary layer,
// but with a uniform size the lattice that saturation starts from is already equilateral
// (the same median and Q_M under 1.2 in both modes) and builds it in about half the time
// of the front waves; on a fine anisotropic ring frontal's metric Q_M is slightly higher
// and it is slower, and on a steep ring (its tangent size a good fraction of its radius)
// neither mode is ahead on the unit share. The surface stage keeps the default.
enum class FieldPointMethod { Saturation, Frontal };

struct Options {
  bool refine = true;                    // false: constrained Delaunay triangulation only
  bool split_segments = true;            // discretize input segments at unit length first;
                                         // false keeps boundary vertices exactly (surface stage)
  bool split_crossing_segments = false;  // false: crossing segments are an error naming both
  bool triangulate_hull_without_segments = true;  // no segments: mesh the convex hull
  // Domain by orientation (CAD loops: the outer loop counter-clockwise, holes clockwise):
  // a component is kept only when it lies to the left of most of its bounding segments
  // (taken a -> b). Needs no hole seeds; seeds still apply on top.
  bool domain_from_orientation = false;
  // Size from the boundary (what Gmsh calls "extend from boundary"): where the boundary
  // segments are shorter than the field asks, the field is scaled down around them and
  // the scale grows back with this gradation ratio (> 1) into the domain, so that short
  // boundary edges do not meet large interior triangles. 0: off (the field alone).
  // Segments with a negative marker impose nothing (e.g. the collapsed side of a pole,
  // short in the plane but not a size anyone asked for).
  double boundary_gradation = 0;
  // Local feature size (the lfs of Ruppert's and Shewchuk's refinement): the size at a
  // boundary point never exceeds its distance to the nearest boundary feature apart from
  // it (a segment sharing no vertex with its own; across an angle under 30 degrees also
  // the other side, down to 1/64 of the side from the apex, so that a thin spike gets
  // triangles as wide as it is), and that cap grows into the domain at the
  // boundary_gradation ratio (1.3 when it is off). A slot or a spike narrower than the
  // requested size then gets a layer of triangles per width instead of needles across
  // it. It only ever makes the size smaller; a uniform size the features never bind
  // stays uniform (the same mesh as without it). Off by default: the surface stage
  // has its own proximity rule; uvmesh2d turns it on.
  bool feature_size = false;
  FieldPointMethod field_points = FieldPointMethod::Saturation;
  bool optimize = true;
  // Size optimization of a varying field (§7.5.2): edges longer than sqrt2 in the metric
  // are split, and with this on, edges shorter than 1/sqrt2 are collapsed. Off where the
  // field is a lower bound on the density rather than the target (the surface stage: its
  // sizes come from curvature sampled on a grid and its chordal repair only adds points;
  // a subdivision crease cube went 1.3x over the chordal tolerance with collapses).
  bool collapse_short_edges = true;
  int optimize_passes = 8;
  bool anisotropic_kernel = true;           // §7.6.1 cavity criterion under M(P) when kind==Metric
  double max_anisotropy = 1e6;              // cap on the ratio of metric eigenvalues' square roots
  std::int64_t max_vertices = 200'000'000;  // refinement stops (status Incomplete) beyond this
  // Wall-clock seconds for refinement and optimization (0: no limit). Beyond it the mesher
  // stops with status TimeLimit, so that a caller meshing many domains (CAD faces) can
  // report the one that would run away instead of never finishing.
  double time_limit = 0;
  bool check = false;  // run the checker after each stage (debug builds: on)
  // Compute Stats::quality (a pass over the output mesh; with a varying field it samples
  // the field at every vertex and edge midpoint). Off for callers that do not read it
  // (the surface stage; a benchmark that measures the mesh itself): Stats::quality then
  // stays zero and the "measure" stage is not listed.
  bool measure = true;
};

struct Triangle3 {
  std::array<VertId, 3> v;
};

struct BoundaryEdge {
  VertId a = 0, b = 0;
  int marker = 0;
};

struct Mesh {
  std::vector<Vec2> vertices;       // the mesher's order: find input point i at
                                    // input_vertex[i] (no segments, holes, regions or
                                    // refinement: the kernel's spatial insertion order)
  std::vector<int> vertex_markers;  // input markers; boundary splits inherit the
                                    // segment marker; interior vertices 0
  std::vector<std::array<VertId, 3>> triangles;  // counter-clockwise
  std::vector<int> triangle_region;              // connected component index (0..)
  std::vector<double> triangle_attribute;        // regional attribute (0 when no seed)
  std::vector<BoundaryEdge> boundary_edges;      // every constrained edge left in the mesh
  std::vector<VertId> input_vertex;              // input point i -> output vertex (kNone if
                                                 // it lies outside the domain)
  std::vector<Metric2> vertex_metric;            // the metric each vertex was placed for (the
                                                 // field capped by Options::feature_size,
                                                 // scaled by Options::boundary_gradation);
                                                 // empty when not refined
  // Per vertex (as vertex_metric): the factor s >= 1 by which Options::boundary_gradation
  // scaled the field's metric there, vertex_metric[v] = s * M(x_v) with M the field after
  // the anisotropy cap (Options::max_anisotropy); s = 1 / r^2 for the size ratio r < 1
  // that the boundary imposed, 1 where it imposed nothing. Callers that build their own
  // metrics from the field at the output vertices multiply them by s to get the metric
  // the vertex was placed for. Empty when vertex_metric is.
  std::vector<double> boundary_scale;
};

struct Quality {
  // Q_K = alpha * h_max / rho_K, alpha = sqrt(3)/6 (eq. 7.6); q_K = 1 / Q_K.
  double q_max = 0, q_mean = 0;  // Q_M (eq. 7.7) and the mean Q_K
  double share_q_below_1_5 = 0, share_q_below_2 = 0;
  double min_angle_deg = 0, max_angle_deg = 0;
  double metric_q_max = 0, metric_q_mean = 0;
  double metric_share_q_below_1_5 = 0, metric_share_q_below_2 = 0;
  double metric_min_angle_deg = 0, metric_max_angle_deg = 0;
  double unit_edge_share = 0;  // metric length in [1/sqrt2, sqrt2]
  double edge_len_min = 0, edge_len_max = 0, edge_len_mean = 0;  // in the metric
  std::int64_t edges = 0;
};

struct Stats {
  struct Stage {
    std::string name;
    double seconds = 0;
  };
  std::vector<Stage> stages;
  std::int64_t duplicates_merged = 0;
  std::int64_t segments_split_at_vertices = 0;
  std::int64_t crossings_split = 0;
  std::int64_t boundary_points_skipped = 0;  // split points that would cross a neighbour
  std::int64_t field_points_inserted = 0;
  std::int64_t field_points_rejected = 0;
  int saturation_waves = 0;
  int frontal_waves = 0;  // Options::field_points == Frontal: front waves run
  std::int64_t swaps = 0, relocations = 0;
  Quality quality;
};

enum class StatusCode {
  Ok,
  InvalidInput,      // NaN/Inf, bad index, empty PSLG, degenerate segment
  CrossingSegments,  // two segments cross (and Options::split_crossing_segments is false)
  OpenBoundary,      // a hole or the exterior leaks into every triangle: nothing left
  Incomplete,        // refinement stopped early (max_vertices); the mesh is valid
  InternalError,     // the checker found an invalid triangulation (a bug: please report)
  TimeLimit,         // Options::time_limit was reached during refinement or optimization
};

struct Status {
  StatusCode code = StatusCode::Ok;
  std::string message;  // names the entities: "segment 12 (3-7) crosses segment 40 ..."
  std::vector<std::int64_t> entities;  // ids of the entities named in message
  std::vector<std::string> warnings;   // duplicates merged etc.; the mesh is still valid
};

struct Result {
  Mesh mesh;
  Stats stats;
  Status status;
  bool ok() const { return status.code == StatusCode::Ok; }
  // The mesh is valid (possibly incomplete) and can be written.
  bool usable() const {
    return status.code == StatusCode::Ok || status.code == StatusCode::Incomplete;
  }
};

Result mesh(const Pslg& in, const SizeSpec& size, const Options& opt = {});

// Quality and size measures of any 2D triangle mesh under a size spec (kind Uniform with
// h <= 0 means "Euclidean only").
Quality measure(const std::vector<Vec2>& vertices, const std::vector<std::array<VertId, 3>>& tris,
                const SizeSpec& size);

// Q_K (eq. 7.6) of triangle abc in the metric M (identity for Euclidean).
double triangle_quality(Vec2 a, Vec2 b, Vec2 c, const Metric2& m = {});

}  // namespace uvmesh::m2d
