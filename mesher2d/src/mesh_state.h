// The state every stage of the mesher2d pipeline shares (internal, not a public header).
//
// m2d::mesh builds one MeshState and hands it to the stages in order (mesher.cpp): input
// and validation (input.cpp), Delaunay triangulation in a box (delaunay.cpp) or the
// convex-hull fast path (hull_path.cpp), boundary enforcement (enforce.cpp), boundary
// splitting (boundary_split.cpp), coloring (coloring.cpp), field points (field_points.cpp,
// lattice.cpp), optimization and repair (optimizer.h) and output (output.cpp). A stage's
// scratch belongs to the stage (a local, or a struct the stage owns), not to this struct:
// what is here is read or written by more than one stage.
#pragma once

#include <chrono>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "metric_util.h"
#include "triangulation.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::m2d::detail {

// Unit mesh bounds (§7.5.2): an edge conforms when its metric length is in
// [measures::kUnitMin, measures::kUnitMax] = [1/sqrt2, sqrt2].
// Field-point filter (§7.3.5): a candidate closer than this (metric length) to an existing
// vertex is dropped. Just above 1/sqrt2, so that no edge shorter than the unit-mesh lower
// bound is created by refinement.
constexpr double kFilterDist = 0.74;

// A deterministic pseudo-random number in [-1, 1) from z (a 64-bit mix): the offsets by
// which the lattice and the front points leave degenerate (collinear, cocircular)
// positions, so that the floating-point filter of the predicates decides their tests.
inline double unit_jitter(std::uint64_t z) {
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
  z ^= z >> 31;
  return static_cast<double>(z >> 11) * 0x1.0p-52 - 1;
}

// "(x, y)" with every digit, for messages.
std::string fmt_pt(Vec2 p);

// A segment record: an input segment, a piece of one (split at a vertex, at a crossing or
// at unit length) or a convex hull edge. Enforced records are the constraints of the
// triangulation (Triangulation::constraint gives the record id).
struct SegRec {
  VertId a, b;
  int marker;
  std::int32_t input;  // input segment index; -1 for convex hull edges
  bool alive = true;
};

struct MeshState {
  using Clock = std::chrono::steady_clock;
  MeshState(const Pslg& in_, const SizeSpec& size_, const Options& opt_, Result& res_)
      : in(in_), field(size_), size(field), opt(opt_), res(res_) {}

  const Pslg& in;
  // The size specification in effect: the caller's, capped by the local feature size
  // (feature_size.cpp, Options::feature_size). Stages read it through size.
  SizeSpec field;
  const SizeSpec& size;
  const Options& opt;
  Result& res;
  Clock::time_point t_start = Clock::now();  // for Options::time_limit

  Triangulation tri;
  // Input (input.cpp).
  std::vector<std::int32_t> rep;       // input point -> representative input point
  std::vector<std::int32_t> xy_order;  // input points sorted by (x, y)
  std::vector<VertId> vid;             // input point -> triangulation vertex
  std::vector<SegRec> segs;            // segment records; the constraint ids of tri
  double h_uniform = 0;                // the uniform size (from the boundary when h <= 0)
  Metric2 m_uniform;                   // Metric2::iso(h_uniform)
  bool refine_ok = true;               // false: no size to refine to (no segment length)
  // Per triangulation vertex.
  std::vector<char> fixed;  // not movable (box corners, input and boundary vertices)
  std::vector<int> vmark;   // marker
  std::vector<Metric2> vm;  // metric it was placed for (field points on)
  std::vector<double> rs;   // boundary size ratio (<= 1; Options::boundary_gradation); the
                            // metric is the field's scaled by 1 / rs^2
  // Per domain component (coloring.cpp).
  std::vector<char> removed;  // exterior or hole
  std::vector<double> attr;   // region attribute
  bool field_error = false;   // the size field returned an invalid value (status set)
  bool lattice_used = false;  // lattice_points placed the field points
  bool fronts_used = false;   // front waves (frontal.cpp) placed the field points

  bool fail(StatusCode c, std::string msg, std::vector<std::int64_t> ent = {});
  // Reports an invalid field value once (status InvalidInput) and sets field_error.
  void field_fail(std::string msg);
  // Options::time_limit: true (and the status set) once it is exceeded.
  bool over_time(const char* stage);

  // The metric at (x, y), validated (SPD, finite) and capped in anisotropy.
  Metric2 metric(double x, double y);

  bool in_domain(TriId t) const { return !tri.dead(t) && !removed[tri.tag(t)]; }

  double edge_length(VertId a, VertId b) const {
    // eq. 7.10 with the length of AB varying geometrically between its values in the
    // metrics of A and B (exact for a geometric size progression; the log-mean).
    const Vec2 d{tri.point(b).x - tri.point(a).x, tri.point(b).y - tri.point(a).y};
    const double la = length(vm[a], d), lb = length(vm[b], d);
    const double r = lb / la;
    if (std::abs(r - 1) < 1e-3) return 0.5 * (la + lb);
    return (lb - la) / std::log(r);
  }

  // Calls fn(t) for every triangle around vertex v (the star of a non-box vertex is
  // closed in the triangulation of the box).
  template <class F>
  void for_ball(VertId v, F&& fn) const {
    const TriId t0 = tri.vertex_tri(v);
    if (t0 == kNone) return;
    TriId t = t0;
    int guard = 0;
    do {
      fn(t);
      int k = 0;
      while (tri.vertex(t, k) != v) ++k;
      const std::int32_t h = tri.twin(3 * t + next3(k));
      if (h == kNone || ++guard > 256) return;
      t = h / 3;
    } while (t != t0);
  }

  std::int32_t add_seg(SegRec s) {
    segs.push_back(s);
    return static_cast<std::int32_t>(segs.size() - 1);
  }
  // "12 (points 3-7)" or "convex hull edge", for messages.
  std::string seg_name(const SegRec& s) const;
};

// ---------------------------------------------------------------- the stages, in order
// Each returns false when it failed (the status names what and where).

// input.cpp: the input checked (finite, indices in range, a field function), exact
// duplicates merged (reported), segment records built (zero-length and repeated ones
// dropped) and the uniform size settled.
bool validate_input(MeshState& ms);
void merge_duplicates(MeshState& ms);
void build_segments(MeshState& ms);

// hull_path.cpp: no segments, holes, regions or refinement: the Delaunay triangulation of
// the convex hull, built directly (HullDelaunay) and written to the result.
bool hull_fast_path(const MeshState& ms);
void output_hull(MeshState& ms, HullDelaunay& dh);

// delaunay.cpp: the Delaunay triangulation of the distinct input points in a box (§7.3.2).
bool triangulate_box(MeshState& ms);

// enforce.cpp: every segment record (or the convex hull) made an edge (§7.2.2), split at the
// vertices it passes through and, by option, at crossings.
bool enforce_boundary(MeshState& ms);
// Enforces the records in work (a stack); split_crossings splits crossing segments even
// when Options::split_crossing_segments is off (the boundary split's rounded points).
bool enforce_segments(MeshState& ms, std::vector<std::int32_t>& work, bool split_crossings);

// feature_size.cpp: Options::feature_size: the size field capped by the local feature size
// of the enforced segments, graded into the domain (a uniform size may become a scalar
// field; it stays uniform where the features never bind).
void apply_feature_size(MeshState& ms);

// boundary_split.cpp: the enforced segments split at unit metric length (eq. 7.10).
bool split_boundary(MeshState& ms);

// coloring.cpp: connected components, exterior and holes removed, region attributes (§7.3.4).
bool color_domain(MeshState& ms);

// field_points.cpp, lattice.cpp, frontal.cpp: field points by edge saturation (§7.3.5,
// 7.5.2; a uniform field first gets the equilateral lattice) or by front waves (§7.4.3,
// Options::field_points), then saturation.
void insert_field_points(MeshState& ms);
void lattice_points(MeshState& ms, bool aniso);

// optimize.cpp: §7.3.6 / §7.5.2 optimization and the targeted repair.
void optimize_mesh(MeshState& ms);

// output.cpp: the triangles of the domain written to the result; with Options::measure,
// edges gets every undirected output edge once (a << 32 | b), for the measure.
void output_mesh(MeshState& ms, std::vector<std::uint64_t>& edges);

}  // namespace uvmesh::m2d::detail
