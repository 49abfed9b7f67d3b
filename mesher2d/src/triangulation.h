// Internal triangulation store and the Delaunay kernel of mesher2d (not a public header).
//
// Flat, index-based store (STYLE.md): per triangle three vertex ids, three "opposite
// half-edge" ids and three constraint ids, as parallel int32 arrays; per vertex one
// incident triangle. kNone means "nothing".
//
// Local numbering, drawn once:
//
//                 v2
//                /  \  .
//        e1     /    \     e0          edge i is opposite vertex i:
//   (v2 -> v0) /      \ (v1 -> v2)        e0 = (v1, v2), e1 = (v2, v0), e2 = (v0, v1)
//             /        \               half-edge id h = 3 * t + i
//           v0 -------- v1             opp[h] = half-edge id of the same edge seen from the
//               e2 (v0 -> v1)                   neighbour across it (kNone on the box border)
//                                      seg[h] = input segment id if edge i is constrained
//
// All triangles are counter-clockwise. The triangulation always covers the enclosing box
// (§7.3.2): every vertex that is not a box corner is strictly inside it, so every
// inserted point falls in some triangle.
#pragma once

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <vector>

#include "predicates_filter.h"
#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::m2d::detail {

// Branch-free (two-bit tables 0b00'10'01 and 0b01'00'10 indexed by 2i): the local index
// depends on data (the edge a walk or a cavity enters by), so a conditional is
// mispredicted about every other time; cachegrind counted these two as 46% of the
// mispredicted branches of the Delaunay kernel.
inline int next3(int i) {
  return (0x09 >> (2 * i)) & 3;
}
inline int prev3(int i) {
  return (0x12 >> (2 * i)) & 3;
}

// What the cavity criterion of one insertion uses (§7.3.2 isotropic, §7.6.1 anisotropic).
struct InsertParams {
  bool use_metric = false;  // anisotropic criterion alpha_M(P)(P,K) < 1 (eq. 7.15-7.16)
  Metric2 m;                // M(P), the metric of the point being inserted
  // Field-point filter: reject P when a cavity vertex lies closer than this in M(P)
  // (in Delaunay the nearest vertex of P is always a cavity vertex). <= 0: off.
  double min_dist = 0;
  // Per-vertex metrics (index < num_vertex_metrics) for the filter: the distance to a
  // vertex V is then measured along PV with the metric varying from M(P) to M(V) (the
  // log-mean of eq. 7.10), not in M(P) alone. Where sizes grade from a finely split
  // boundary, a point with a coarser metric than its fine neighbour V is not "too close"
  // to V by V's own measure. nullptr: M(P) alone.
  const Metric2* vertex_metrics = nullptr;
  std::size_t num_vertex_metrics = 0;
  bool allow_on_constraint = false;  // false: a point exactly on a constrained edge is rejected
};

// The field-point filter of InsertParams (min_dist, vertex_metrics): true when vertex a at
// q is too close to the point p being inserted.
inline bool filter_too_close(const InsertParams& prm, VertId a, const Vec2& q, const Vec2& p) {
  const double lim = prm.min_dist * prm.min_dist;
  const double dx = q.x - p.x, dy = q.y - p.y;
  double d2 = prm.m.m11 * dx * dx + 2 * prm.m.m12 * dx * dy + prm.m.m22 * dy * dy;
  if (d2 < lim && prm.vertex_metrics && static_cast<std::size_t>(a) < prm.num_vertex_metrics) {
    const Metric2& mv = prm.vertex_metrics[a];
    const double lv2 = mv.m11 * dx * dx + 2 * mv.m12 * dx * dy + mv.m22 * dy * dy;
    if (lv2 > d2) {
      const double lp = std::sqrt(d2), lv = std::sqrt(lv2);
      const double l = lv / lp - 1 < 1e-3 ? 0.5 * (lp + lv) : (lv - lp) / std::log(lv / lp);
      d2 = l * l;
    }
  }
  return d2 < lim;
}

enum class InsertStatus { Inserted, Duplicate, TooClose, OnConstraint, Outside, BadCavity };

struct InsertResult {
  InsertStatus status;
  VertId v;  // the new vertex (Inserted) or the existing one (Duplicate)
};

class Triangulation {
 public:
  // Box corners are vertices 0..3.
  void init_box(double xmin, double ymin, double xmax, double ymax, std::size_t reserve_pts);

  VertId add_vertex(Vec2 p);  // a vertex not yet in any triangle
  InsertResult insert(VertId v, TriId hint, const InsertParams& prm);
  InsertResult insert_point(Vec2 p, TriId hint, const InsertParams& prm);
  // The same with the point already located: t0 contains it, o0 are its orientations
  // against t0's edges, as locate(p, hint, o0) returns them.
  InsertResult insert_located(VertId v, TriId t0, const double* o0, const InsertParams& prm);
  InsertResult insert_point_located(Vec2 p, TriId t0, const double* o0, const InsertParams& prm);

  // Locate: a triangle containing p (closed), walking from hint. kNone if outside the box.
  TriId locate(Vec2 p, TriId hint) const;
  // Same, and the orientations of p against the edges of the triangle found (edge i).
  TriId locate(Vec2 p, TriId hint, double* orients) const;

  // Boundary enforcement (§7.2.2) of segment (a, b) with id sid. Returns false and fills
  // crossing_seg (the constrained edge's segment id) when a constrained edge is crossed.
  // Vertices lying exactly on the open segment are reported in through (in order from a).
  enum class EnforceStatus { Ok, Crossing, ThroughVertex };
  struct EnforceResult {
    EnforceStatus status = EnforceStatus::Ok;
    VertId through = kNone;                         // ThroughVertex: the vertex on (a, b)
    std::int32_t crossing_seg = kNone;              // Crossing: the segment id crossed
    VertId crossing_a = kNone, crossing_b = kNone;  // Crossing: the constrained edge
  };
  EnforceResult enforce(VertId a, VertId b, std::int32_t sid);
  // Removes the constraint of edge (a, b) (both sides). Returns false if there is no such edge.
  bool unconstrain(VertId a, VertId b);
  // True when the open segment from vertex a to point p crosses no constrained edge and
  // meets no vertex, and p lies strictly inside a triangle reached that way.
  bool segment_clear(VertId a, Vec2 p) const;

  // The triangle t = (a, u, w) around vertex a whose angle at a holds the direction of q,
  // or, when a neighbour of a lies on the ray a -> q, that vertex (ray) and the half-edge
  // of edge (a, ray) (ray_edge). t == kNone and ray == kNone: not found (bug guard).
  struct Wedge {
    TriId t = kNone;
    VertId u = kNone, w = kNone;
    VertId ray = kNone;
    std::int32_t ray_edge = kNone;
  };
  Wedge find_wedge(VertId a, Vec2 q) const;

  // Half-edge from a to b (a triangle containing the directed edge a -> b), or kNone.
  std::int32_t find_half_edge(VertId a, VertId b) const;
  // Flips the edge of half-edge h; the quad must be strictly convex.
  void flip(std::int32_t h);
  bool flippable(std::int32_t h) const;  // strictly convex quad, not on the box border
  // Local operators for optimization (triangulation_local_ops.cpp, §7.3.6):
  // collapse_edge merges v into u and puts u at p (v has no constrained edge; the link
  // condition holds; every remaining triangle stays CCW), else returns false and changes
  // nothing. split_edge splits the unconstrained edge of half-edge h at p (inside the
  // quad of its two triangles) into four triangles; returns the new vertex or kNone.
  bool collapse_edge(VertId v, VertId u, Vec2 p);
  VertId split_edge(std::int32_t h, Vec2 p);
  // Lawson flips (constrained Delaunay) starting from the given edges (as half-edges).
  void restore_delaunay(std::vector<std::pair<VertId, VertId>>& stack);

  // Accessors, the only way the mesher stages read and write the store (the arrays are
  // private; the kernel's own code indexes them). They assert their indices in debug
  // builds; in release builds they compile to the plain array access.
  std::int32_t num_tris() const { return static_cast<std::int32_t>(tv_.size() / 3); }
  std::int32_t num_verts() const { return static_cast<std::int32_t>(pts_.size()); }
  bool dead(TriId t) const { return tv_[3 * check_tri(t)] == kNone; }
  bool is_box_vertex(VertId v) const { return v < 4; }
  // Vertex i (0..2, counter-clockwise) of triangle t.
  VertId vertex(TriId t, int i) const {
    assert(i >= 0 && i < 3);
    return tv_[3 * check_tri(t) + i];
  }
  // The vertex opposite the edge of half-edge h = 3t + i (vertex i of t).
  VertId apex(std::int32_t h) const { return tv_[check_half_edge(h)]; }
  // The half-edge of the same edge seen from the neighbour across it (kNone on the box
  // border).
  std::int32_t twin(std::int32_t h) const { return opp_[check_half_edge(h)]; }
  // The input segment id constraining the edge of half-edge h, or kNone.
  std::int32_t constraint(std::int32_t h) const { return seg_[check_half_edge(h)]; }
  // The domain component of triangle t (coloring, §7.3.4).
  std::int32_t tag(TriId t) const { return tag_[check_tri(t)]; }
  void set_tag(TriId t, std::int32_t c) { tag_[check_tri(t)] = c; }
  void fill_tags(std::int32_t c) { std::fill(tag_.begin(), tag_.end(), c); }
  // Vertex coordinates and one incident triangle per vertex (kNone if not inserted).
  const Vec2& point(VertId v) const { return pts_[check_vertex(v)]; }
  const std::vector<Vec2>& points() const { return pts_; }
  void set_point(VertId v, Vec2 p) { pts_[check_vertex(v)] = p; }
  TriId vertex_tri(VertId v) const { return vtri_[check_vertex(v)]; }
  // Drops the last vertex added by add_vertex, which is in no triangle (a duplicate).
  void remove_last_vertex() {
    assert(!pts_.empty() && vtri_.back() == kNone);
    pts_.pop_back();
    vtri_.pop_back();
  }
  // Room for nv vertices and their triangles, in huge pages where the kernel allows them
  // (huge_pages.h: fewer TLB misses and page faults).
  void reserve_huge(std::size_t nv);

  // Statistics of the kernel.
  std::int64_t bad_cavities = 0;
  std::int64_t star_corrections = 0;

 private:
  TriId check_tri(TriId t) const {
    assert(t >= 0 && static_cast<std::size_t>(t) < tag_.size());
    return t;
  }
  std::int32_t check_half_edge(std::int32_t h) const {
    assert(h >= 0 && static_cast<std::size_t>(h) < tv_.size());
    return h;
  }
  VertId check_vertex(VertId v) const {
    assert(v >= 0 && static_cast<std::size_t>(v) < pts_.size());
    return v;
  }

  std::vector<Vec2> pts_;
  std::vector<TriId> vtri_;        // one incident triangle per vertex (kNone if not inserted)
  std::vector<VertId> tv_;         // 3 per triangle; tv_[3t] == kNone marks a dead slot
  std::vector<std::int32_t> opp_;  // 3 per triangle
  std::vector<std::int32_t> seg_;  // 3 per triangle: input segment id or kNone
  std::vector<std::int32_t> tag_;  // 1 per triangle: domain component (new triangles inherit
                                   // the tag of the base; flips keep it)

  // The cavity criterion for triangle t (inline: the isotropic test is the kernel's
  // innermost operation).
  bool in_cavity(TriId t, Vec2 p, const InsertParams& prm) const {
    if (prm.use_metric) return in_cavity_metric(t, p, prm);
    const Vec2& a = pts_[tv_[3 * t]];
    const Vec2& b = pts_[tv_[3 * t + 1]];
    const Vec2& c = pts_[tv_[3 * t + 2]];
    return pred::detail::incircle_filtered(&a.x, &b.x, &c.x, &p.x) > 0;
  }
  bool in_cavity_metric(TriId t, Vec2 p, const InsertParams& prm) const;
  std::array<double, 3> frame_{1, 0, 1};  // the insertion's R (M(P) = R^T R), see insert_located
  struct BoundaryEdge {
    VertId a, b;
    std::int32_t out, s;
  };
  bool cavity_unmarked(TriId t0, Vec2 p, const InsertParams& prm);
  InsertResult make_ball(VertId v, TriId t0, const InsertParams& prm, const TriId* cav,
                         std::size_t nc, const BoundaryEdge* bd, std::size_t m);
  void link(std::int32_t h1, std::int32_t h2) {
    opp_[h1] = h2;
    if (h2 != kNone) opp_[h2] = h1;
  }
  TriId new_tri();
  bool star_correct(Vec2 p, std::size_t nbase, std::uint32_t IN, std::uint32_t OUT,
                    std::uint32_t CAND);

  // Scratch, reused between insertions (epoch marks avoid clearing).
  mutable std::vector<std::uint32_t> mark_;
  mutable std::uint32_t epoch_ = 0;
  std::vector<TriId> cav_, stack_, free_;
  std::vector<std::int32_t> bnd_;  // boundary half-edges of the cavity (inside side)
  // cavity_unmarked's cavity, the half-edge each of its triangles was entered by, its
  // boundary edges, and their counts.
  static constexpr std::size_t kMaxFastCavity = 96;
  std::array<TriId, kMaxFastCavity> fcav_;
  std::array<std::int32_t, kMaxFastCavity> fpar_;
  std::array<BoundaryEdge, kMaxFastCavity + 2> fbd_;
  std::size_t fnc_ = 0, fm_ = 0;
  std::vector<std::int32_t> vstart_;  // vertex -> index in bnd_ of the edge starting there
  std::vector<BoundaryEdge> bd_;
  std::vector<TriId> nt_;
  std::vector<VertId> nb_scratch_;  // collapse_edge
  mutable std::uint64_t rng_ = 0x9E3779B97F4A7C15ull;
};

// Insertion order of a point set for the Delaunay kernel (hull_delaunay.cpp): BRIO rounds,
// Hilbert order inside every round. rec[k] = (key << 32 | input index) of the k-th point
// to insert; the low 32 bits are the index (n < 2^32).
void brio_order(const std::vector<Vec2>& in, std::vector<std::uint64_t>& rec);

// Delaunay triangulation of the convex hull of a point set, without constraints: the
// fast path of m2d::mesh for unconstrained input without refinement (the Delaunay
// triangulation of N points). Same kernel idea as Triangulation
// (T(i+1) = T(i) - C(P) + B(P), §7.1.3, exact predicates), but instead of the enclosing
// box of §7.3.2 the outside of the hull is covered by "ghost" triangles (a, b, G) that
// join every hull edge to one vertex G at infinity. A ghost triangle's circumdisk is the
// open half-plane beyond its hull edge plus the open edge itself, so a point outside the
// current hull is inserted by the same cavity rule, the triangulation always is the
// Delaunay triangulation of the convex hull of the points inserted so far, and no box
// corners, hull recovery (enforcement of hull edges) or coloring are needed.
//
// Storage: per triangle three vertex ids and three twin half-edges; half-edge h = 4t + i
// is edge i, opposite vertex i, as in Triangulation (4t rather than 3t: shifts instead of
// divisions on the hot path; limits the fast path to 2^28 points). Vertex k is the k-th
// input point in insertion order (biased randomized insertion order, BRIO, with a
// Hilbert order inside every round), so that consecutive insertions touch coordinates
// and triangles close in memory as well as in the plane. Cavity triangles are reused for
// the ball, so no slot ever dies: every triangle is live. Exact duplicates are found by
// point location (a point on two edges of its triangle is their common vertex): their
// vertex stays unused and is listed in dups. G is vertex n (after the input points), so
// that without duplicates pts minus its last entry is the output vertex array as it is.
class HullDelaunay {
 public:
  struct Tri {
    VertId v[3];
    std::int32_t n[3];
  };
  enum class Status { Ok, Collinear, Internal };
  // in: finite coordinates (m2d::mesh validates them). Collinear: fewer than three
  // distinct points, or all on one line (no triangle). Internal: a bug guard fired.
  Status build(const std::vector<Vec2>& in);

  bool ghost(const Tri& r) const {
    return r.v[0] == ghost_id || r.v[1] == ghost_id || r.v[2] == ghost_id;
  }
  int ghost_corner(const Tri& r) const {
    return r.v[0] == ghost_id ? 0 : r.v[1] == ghost_id ? 1 : 2;
  }

  VertId ghost_id = 0;            // G: the vertex after the last input point
  std::vector<Vec2> pts;          // vertex -> point (pts[ghost_id]: G, NaN coordinates)
  std::vector<std::int32_t> src;  // vertex -> input point index
  std::vector<VertId> vert_of;    // input point index -> vertex (src's inverse)
  std::vector<std::pair<VertId, VertId>> dups;  // (unused vertex, the equal vertex kept)
  std::vector<Tri> tris;                        // real and ghost triangles, all live
  static constexpr std::size_t kMaxPoints = (std::size_t{1} << 28) - 16;

 private:
  bool insert(VertId pv);
  std::int32_t walk(Vec2 p, double* o) const;
  bool grow_cavity(std::int32_t t, Vec2 p, std::size_t& nc, std::size_t& m);
  bool make_ball(VertId pv, std::size_t nc, std::size_t m);
  bool conflict_slow(const Tri& r, Vec2 p) const;
  std::int32_t last_ = 0;  // a real triangle at the last inserted vertex: the walk's start
  struct NewTri {
    VertId a, b;
    std::int32_t out;  // the twin half-edge outside the cavity
  };
  std::vector<std::int32_t> cav_, stack_;  // scratch, sized on demand
  std::vector<NewTri> ball_;
};

}  // namespace uvmesh::m2d::detail
