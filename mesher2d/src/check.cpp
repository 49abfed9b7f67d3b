// Checker for 2D triangle meshes (see check.h). It works on the output Mesh and the
// input Pslg only, never on the mesher's internal structures, so that it can catch bugs
// in them. Every geometric decision uses the exact predicates of predicates.h: a valid
// mesh is never rejected because of round-off, and an invalid one is never accepted
// because of it (the one documented tolerance is for Steiner vertices on segments).
//
// Cost: O(n) for the edge adjacency (half-edges bucketed by their smaller vertex, a
// counting sort), O(n log n) for the coincident-vertex test, O(n + q) expected for the
// point queries (seeds, missing input points) through a uniform grid over the queries.
// About 0.5 s for 1e6 triangles on one core.
//
// Checks, in order (each error names the entities):
//   1. array sizes, vertex coordinates finite, no two vertices at the same place;
//   2. triangle indices in range, three distinct vertices, strictly counter-clockwise;
//   3. edges: each undirected edge in at most two triangles, then with opposite
//      orientations; an edge in one triangle (domain boundary) is constrained; every
//      constrained edge is an edge of a triangle; triangles on both sides of a
//      non-constrained edge are in the same region with the same attribute;
//      Delaunay (optional): incircle(opposite vertex) <= 0 across non-constrained edges;
//   4. no overlap around vertices: the angles of the triangles around an interior vertex
//      add up to 2*pi, around a boundary vertex to at most 2*pi (catches a mesh that
//      wraps around a vertex twice, which the edge checks cannot see);
//   5. input vertices: input_vertex maps to a vertex with the same coordinates; without
//      segments (the domain is the convex hull) every input point has a vertex;
//   6. segments: every input segment is covered by a chain of constrained edges from
//      one end to the other through vertices on the segment (exactly, or within the
//      rounding of a Steiner point: kSegmentTolUlps);
//   7. point queries: no triangle contains a hole seed; every region seed is in a
//      triangle whose attribute is the seed's; an input point without a mesh vertex is
//      not inside (or on the boundary of) the meshed domain.
// Not checked: two components overlapping without sharing a vertex (needs a sweep), and
// a vertex lying exactly on a segment without being on its chain.
#include "uvmesh/mesher2d/check.h"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numbers>
#include <sstream>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d {
namespace {

// A Steiner vertex placed on an input segment (boundary discretization, crossing split)
// is rounded to doubles, so in general it is not exactly on the segment's line. The chain
// covering a segment accepts a vertex whose distance to the line is at most
// kSegmentTolUlps * eps * (largest coordinate magnitude involved): rounding a point
// a + t (b - a) moves it by about 2 eps |coord|, a crossing point computed from four
// points by a few more operations; 64 leaves a wide margin while still rejecting any
// vertex that is visibly off the segment. Exactly collinear vertices are always accepted.
constexpr double kSegmentTolUlps = 64.0;

// The angles around a vertex are computed in floating point (atan2); a correct fan adds
// up to 2*pi within about degree * 1e-16, an overlapping one to 4*pi or more. 1e-6 rad
// separates the two with a wide margin on both sides.
constexpr double kAngleTol = 1e-6;

const double* ptr(const Vec2& p) {
  return &p.x;
}

double orient(const Vec2& a, const Vec2& b, const Vec2& c) {
  return pred::orient2d(ptr(a), ptr(b), ptr(c));
}

// Positions along a segment AB (A != B) and nearness to its line, as the segment checks
// use them. key: the coordinate of AB's dominant axis, then the other one (both signed to
// grow from A to B), compared lexicographically. Exact, and monotone for points on the
// line; the second coordinate orders a rounded Steiner vertex that shares the first one
// with its neighbour (a crossing point 1 ulp from an input point, moved along the minor
// axis only). near_line: on the line exactly, or within the rounding of a Steiner vertex
// (kSegmentTolUlps).
struct SegmentFrame {
  using Key = std::pair<double, double>;
  Vec2 A, B;
  bool use_x;
  double s1, s2, len, mag;
  SegmentFrame(const Vec2& a, const Vec2& b) : A(a), B(b) {
    use_x = std::abs(B.x - A.x) >= std::abs(B.y - A.y);
    const double dmaj = use_x ? B.x - A.x : B.y - A.y, dmin = use_x ? B.y - A.y : B.x - A.x;
    s1 = dmaj > 0 ? 1.0 : -1.0;
    s2 = dmin > 0 ? 1.0 : (dmin < 0 ? -1.0 : 0.0);
    len = std::hypot(B.x - A.x, B.y - A.y);
    mag = std::max({std::abs(A.x), std::abs(A.y), std::abs(B.x), std::abs(B.y)});
  }
  Key key(const Vec2& p) const {
    return Key{s1 * (use_x ? p.x : p.y), s2 == 0 ? 0.0 : s2 * (use_x ? p.y : p.x)};
  }
  bool near_line(const Vec2& P) const {
    const double o = orient(A, B, P);
    if (o == 0) return true;
    const double pm = std::max({mag, std::abs(P.x), std::abs(P.y)});
    return std::abs(o) / len <= kSegmentTolUlps * std::numeric_limits<double>::epsilon() * pm;
  }
  // P on the closed segment: near the line, between A and B.
  bool holds(const Vec2& P) const {
    const Key k = key(P);
    return k >= key(A) && k <= key(B) && near_line(P);
  }
};

std::string fmt(double v) {
  std::ostringstream os;
  os.precision(17);
  os << v;
  return os.str();
}

std::string pt(const Vec2& p) {
  // Appended piece by piece: GCC 12 warns falsely (-Wrestrict) on "(" + std::string&&.
  std::string s = "(";
  s += fmt(p.x);
  s += ", ";
  s += fmt(p.y);
  s += ")";
  return s;
}

std::string tri_str(TriId t, const std::array<VertId, 3>& v) {
  std::string s = "triangle ";
  s += std::to_string(t) + " (" + std::to_string(v[0]) + "," + std::to_string(v[1]) + "," +
       std::to_string(v[2]) + ")";
  return s;
}

std::string edge_str(VertId a, VertId b) {
  std::string s = "edge (";
  s += std::to_string(a) + "," + std::to_string(b) + ")";
  return s;
}

class Reporter {
 public:
  Reporter(CheckReport& rep, std::size_t max_errors)
      : rep_(rep), max_(std::max<std::size_t>(max_errors, 1)) {}  // 0 would hide every error
  bool full() const { return rep_.errors.size() >= max_; }
  void add(std::string msg) {
    if (!full()) rep_.errors.push_back(std::move(msg));
  }

 private:
  CheckReport& rep_;
  std::size_t max_;
};

// One half-edge or constrained edge in the bucket of its smaller vertex.
struct EdgeEntry {
  VertId hi;
  std::int32_t code;  // >= 0: 3 * t + k, the edge v[k] -> v[(k+1)%3] of triangle t;
                      // < 0: -1 - e, constrained edge e of Mesh::boundary_edges
};

bool entry_less(const EdgeEntry& x, const EdgeEntry& y) {
  return x.hi != y.hi ? x.hi < y.hi : x.code < y.code;
}

void sort_bucket(EdgeEntry* first, EdgeEntry* last) {
  if (last - first > 24) {
    std::sort(first, last, entry_less);
    return;
  }
  for (EdgeEntry* i = first + 1; i < last; ++i) {  // buckets hold ~6 entries on average
    EdgeEntry x = *i;
    EdgeEntry* j = i;
    for (; j > first && entry_less(x, *(j - 1)); --j) *j = *(j - 1);
    *j = x;
  }
}

struct Query {
  enum Kind { Hole, Region, MissingInput } kind;
  std::int32_t index;  // seed index or input point index
  Vec2 p;
  TriId strict = kNone;  // first triangle containing p in its interior
  TriId closed = kNone;  // first triangle containing p in its closure
};

// The checks of check(), in the order they run, with the context they share: each check_*
// adds its errors to err and leaves what later checks need (valid and ccw triangles, the
// edge buckets, the input vertex map).
class Checker {
 public:
  Checker(const Mesh& m_, const Pslg& in_, const CheckOptions& opt_, CheckReport& rep_)
      : m(m_),
        in(in_),
        opt(opt_),
        rep(rep_),
        err(rep_, opt_.max_errors),
        V(m_.vertices),
        T(m_.triangles),
        E(m_.boundary_edges) {}
  void run();

 private:
  bool check_id_range();
  void check_arrays_and_vertices();
  void check_triangles();
  bool check_constrained_edge_ids();
  void bucket_edges();
  void check_edges();
  void check_edge(VertId lo, VertId hi, std::int32_t constrained,
                  const std::vector<std::int32_t>& halves);
  void check_vertex_angles();
  void map_input_vertices();
  void check_segments();
  void check_segment(std::size_t s);
  bool leaves_domain(const std::vector<VertId>& dead_ends, const Vec2& B);
  void accept_unmarked_on_segments();
  void check_point_queries();
  void collect_queries(std::vector<Query>& qs);
  void locate_queries(std::vector<Query>& qs) const;
  void report_queries(const std::vector<Query>& qs);

  const Mesh& m;
  const Pslg& in;
  const CheckOptions& opt;
  CheckReport& rep;
  Reporter err;
  const std::vector<Vec2>& V;
  const std::vector<std::array<VertId, 3>>& T;
  const std::vector<BoundaryEdge>& E;
  VertId nv = 0;
  TriId nt = 0;
  std::int32_t ne = 0;
  std::size_t np = 0;
  bool have_region = false, have_attr = false;
  // valid: indices in range and distinct (usable for adjacency); ccw: also oriented.
  std::vector<std::uint8_t> valid, ccw;
  bool all_ccw = true;
  std::vector<std::uint8_t> evalid;  // constrained edge indices in range, not degenerate
  // Half-edges and constrained edges bucketed by their smaller vertex: bucket lo is
  // entries[start[lo], start[lo+1]).
  std::vector<std::int64_t> start;
  std::vector<EdgeEntry> entries;
  // canon[e]: the first constrained edge with the same two vertices as e (duplicates
  // in boundary_edges, e.g. from an input segment given twice, count as one).
  std::vector<std::int32_t> canon;
  std::vector<std::uint8_t> on_boundary;  // in a once-used edge
  bool manifold = true;
  std::vector<VertId> vmap;  // input point -> mesh vertex (kNone: none)
  // Segment checks: constrained-edge adjacency (both directions, CSR), which constrained
  // edges lie on a segment's chain, the segment that last reached each vertex, and the
  // vertex -> (3 t + k) incidence built on first need.
  std::vector<std::int32_t> cs, cedge;
  std::vector<VertId> cadj;
  std::vector<std::uint8_t> on_chain;
  std::vector<std::int64_t> visit;
  std::vector<VertId> stack, dead_ends;
  std::vector<std::int32_t> vstart, vtris;
};

void Checker::run() {
  if (!check_id_range()) return;
  check_arrays_and_vertices();
  check_triangles();
  if (!check_constrained_edge_ids()) return;
  bucket_edges();
  check_edges();
  check_vertex_angles();
  map_input_vertices();
  check_segments();
  check_point_queries();
}

bool Checker::check_id_range() {
  const std::int64_t nv64 = static_cast<std::int64_t>(V.size());
  const std::int64_t nt64 = static_cast<std::int64_t>(T.size());
  if (nv64 > std::numeric_limits<std::int32_t>::max() ||
      nt64 > std::numeric_limits<std::int32_t>::max() / 3) {
    err.add("mesh too large for 32-bit ids: " + std::to_string(nv64) + " vertices, " +
            std::to_string(nt64) + " triangles");
    return false;
  }
  nv = static_cast<VertId>(nv64);
  nt = static_cast<TriId>(nt64);
  rep.triangles_checked = nt;
  return true;
}

// 1. Array sizes, finite coordinates, no two vertices at the same place.
void Checker::check_arrays_and_vertices() {
  auto size_ok = [&](std::size_t got, std::size_t want, const char* what, const char* per) {
    if (got != 0 && got != want)
      err.add(std::string("mesh.") + what + " has " + std::to_string(got) + " entries for " +
              std::to_string(want) + " " + per);
  };
  size_ok(m.vertex_markers.size(), V.size(), "vertex_markers", "vertices");
  size_ok(m.triangle_region.size(), T.size(), "triangle_region", "triangles");
  size_ok(m.triangle_attribute.size(), T.size(), "triangle_attribute", "triangles");
  have_region = m.triangle_region.size() == T.size() && nt > 0;
  have_attr = m.triangle_attribute.size() == T.size() && nt > 0;

  bool all_finite = true;
  for (VertId i = 0; i < nv; ++i)
    if (!std::isfinite(V[i].x) || !std::isfinite(V[i].y)) {
      all_finite = false;
      err.add("vertex " + std::to_string(i) + " has a non-finite coordinate " + pt(V[i]));
    }
  if (!all_finite) return;  // (NaN would break the strict weak order of the sort)
  // Two mesh vertices at the same place would let two sheets of triangles overlap
  // without any edge or angle check noticing.
  std::vector<VertId> order(static_cast<std::size_t>(nv));
  for (VertId i = 0; i < nv; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](VertId a, VertId b) {
    return V[a].x != V[b].x ? V[a].x < V[b].x : (V[a].y != V[b].y ? V[a].y < V[b].y : a < b);
  });
  for (VertId i = 1; i < nv && !err.full(); ++i) {
    const Vec2 &p = V[order[i - 1]], &q = V[order[i]];
    if (p.x == q.x && p.y == q.y)
      err.add("vertices " + std::to_string(order[i - 1]) + " and " + std::to_string(order[i]) +
              " coincide at " + pt(p));
  }
}

// 2. Triangle indices in range, three distinct vertices, strictly counter-clockwise.
void Checker::check_triangles() {
  valid.assign(static_cast<std::size_t>(nt), 0);
  ccw.assign(static_cast<std::size_t>(nt), 0);
  for (TriId t = 0; t < nt; ++t) {
    const auto& v = T[t];
    if (v[0] < 0 || v[0] >= nv || v[1] < 0 || v[1] >= nv || v[2] < 0 || v[2] >= nv) {
      err.add(tri_str(t, v) + " has a vertex index out of range [0," + std::to_string(nv) + ")");
      all_ccw = false;
      continue;
    }
    if (v[0] == v[1] || v[1] == v[2] || v[2] == v[0]) {
      err.add(tri_str(t, v) + " has a repeated vertex");
      all_ccw = false;
      continue;
    }
    valid[t] = 1;
    const double o = orient(V[v[0]], V[v[1]], V[v[2]]);
    if (o > 0) {
      ccw[t] = 1;
    } else {
      all_ccw = false;
      err.add(tri_str(t, v) + " is not counter-clockwise (" +
              (o < 0 ? std::string("clockwise")
                     : std::string("degenerate: its vertices are collinear")) +
              ")");
    }
  }
}

// 3a. Constrained edges: indices in range, not degenerate.
bool Checker::check_constrained_edge_ids() {
  const std::int64_t ne64 = static_cast<std::int64_t>(E.size());
  if (ne64 > std::numeric_limits<std::int32_t>::max() - 1) {
    err.add("too many boundary edges: " + std::to_string(ne64));
    return false;
  }
  ne = static_cast<std::int32_t>(ne64);
  evalid.assign(static_cast<std::size_t>(ne), 0);
  for (std::int32_t e = 0; e < ne; ++e) {
    const VertId a = E[e].a, b = E[e].b;
    if (a < 0 || a >= nv || b < 0 || b >= nv)
      err.add("constrained edge " + std::to_string(e) + " " + edge_str(a, b) +
              " has a vertex index out of range [0," + std::to_string(nv) + ")");
    else if (a == b)
      err.add("constrained edge " + std::to_string(e) + " " + edge_str(a, b) + " is degenerate");
    else
      evalid[e] = 1;
  }
  return true;
}

// 3b. Counting sort of half-edges and constrained edges by their smaller vertex.
void Checker::bucket_edges() {
  start.assign(static_cast<std::size_t>(nv) + 2, 0);
  for (TriId t = 0; t < nt; ++t)
    if (valid[t])
      for (int k = 0; k < 3; ++k) ++start[std::min(T[t][k], T[t][(k + 1) % 3]) + 2];
  for (std::int32_t e = 0; e < ne; ++e)
    if (evalid[e]) ++start[std::min(E[e].a, E[e].b) + 2];
  for (std::size_t i = 2; i < start.size(); ++i) start[i] += start[i - 1];
  entries.resize(static_cast<std::size_t>(start.back()));
  for (TriId t = 0; t < nt; ++t)
    if (valid[t])
      for (int k = 0; k < 3; ++k) {
        const VertId a = T[t][k], b = T[t][(k + 1) % 3];
        entries[start[std::min(a, b) + 1]++] = {std::max(a, b), 3 * t + k};
      }
  for (std::int32_t e = 0; e < ne; ++e)
    if (evalid[e])
      entries[start[std::min(E[e].a, E[e].b) + 1]++] = {std::max(E[e].a, E[e].b), -1 - e};
}

// 3c. Each undirected edge in at most two triangles, then with opposite orientations; an
// edge in one triangle (domain boundary) is constrained; every constrained edge is an
// edge of a triangle.
void Checker::check_edges() {
  canon.assign(static_cast<std::size_t>(ne), -1);
  on_boundary.assign(static_cast<std::size_t>(nv), 0);
  std::int64_t nedges = 0;
  std::vector<std::int32_t> halves;
  for (VertId lo = 0; lo < nv; ++lo) {
    EdgeEntry* b0 = entries.data() + start[lo];
    EdgeEntry* b1 = entries.data() + start[lo + 1];
    sort_bucket(b0, b1);
    for (EdgeEntry* g = b0; g < b1;) {
      EdgeEntry* h = g;
      while (h < b1 && h->hi == g->hi) ++h;
      const VertId hi = g->hi;
      // Constrained entries sort first (negative codes).
      std::int32_t constrained = -1;
      halves.clear();
      for (EdgeEntry* x = g; x < h; ++x) {
        if (x->code < 0) {
          if (constrained < 0) constrained = -1 - x->code;
          canon[-1 - x->code] = constrained;
        } else {
          halves.push_back(x->code);
        }
      }
      g = h;
      if (halves.empty()) {
        err.add("constrained edge " + std::to_string(constrained) + " " + edge_str(lo, hi) +
                " is not an edge of any triangle");
        continue;
      }
      ++nedges;
      check_edge(lo, hi, constrained, halves);
    }
  }
  rep.edges_checked = nedges;
}

// One edge (lo, hi) and its half-edges: manifold, consistently oriented, constrained on
// the boundary; triangles on both sides of a non-constrained edge are in the same region
// with the same attribute; Delaunay (optional): incircle(opposite vertex) <= 0.
void Checker::check_edge(VertId lo, VertId hi, std::int32_t constrained,
                         const std::vector<std::int32_t>& halves) {
  auto tri_of = [](std::int32_t code) { return code / 3; };
  // Direction of a half-edge: true when it runs lo -> hi.
  auto forward = [&](std::int32_t code) { return T[code / 3][code % 3] == lo; };
  if (halves.size() == 1) {
    on_boundary[lo] = on_boundary[hi] = 1;
    if (constrained < 0) {
      const TriId t = tri_of(halves[0]);
      err.add(edge_str(lo, hi) + " is on the domain boundary but is not a constrained edge (" +
              tri_str(t, T[t]) + ")");
    }
    return;
  }
  if (halves.size() > 2) {
    manifold = false;
    on_boundary[lo] = on_boundary[hi] = 1;
    std::string list;
    for (std::size_t i = 0; i < halves.size(); ++i) {
      if (i) list += ", ";
      list += tri_str(tri_of(halves[i]), T[tri_of(halves[i])]);
    }
    err.add(edge_str(lo, hi) + " is non-manifold: shared by " + std::to_string(halves.size()) +
            " triangles: " + list);
    return;
  }
  const TriId t1 = tri_of(halves[0]), t2 = tri_of(halves[1]);
  if (forward(halves[0]) == forward(halves[1])) {
    manifold = false;
    on_boundary[lo] = on_boundary[hi] = 1;
    err.add(edge_str(lo, hi) + " has inconsistent orientation: " + tri_str(t1, T[t1]) + " and " +
            tri_str(t2, T[t2]) + " both use it in the same direction " +
            (forward(halves[0]) ? edge_str(lo, hi) : edge_str(hi, lo)));
    return;
  }
  if (constrained >= 0) return;
  if (have_region && m.triangle_region[t1] != m.triangle_region[t2])
    err.add(edge_str(lo, hi) + " is not constrained but separates regions: " + tri_str(t1, T[t1]) +
            " is in region " + std::to_string(m.triangle_region[t1]) + ", " + tri_str(t2, T[t2]) +
            " in region " + std::to_string(m.triangle_region[t2]));
  if (have_attr && !(m.triangle_attribute[t1] == m.triangle_attribute[t2]))
    err.add(edge_str(lo, hi) + " is not constrained but separates attributes: " +
            tri_str(t1, T[t1]) + " has attribute " + fmt(m.triangle_attribute[t1]) + ", " +
            tri_str(t2, T[t2]) + " has " + fmt(m.triangle_attribute[t2]));
  if (opt.delaunay && ccw[t1] && ccw[t2]) {
    const auto& v1 = T[t1];
    const VertId d = T[t2][(halves[1] % 3 + 2) % 3];  // vertex of t2 opposite the shared edge
    const double ic = pred::incircle(ptr(V[v1[0]]), ptr(V[v1[1]]), ptr(V[v1[2]]), ptr(V[d]));
    if (ic > 0)
      err.add(edge_str(lo, hi) + " is not Delaunay: vertex " + std::to_string(d) + " of " +
              tri_str(t2, T[t2]) + " is inside the circumcircle of " + tri_str(t1, v1));
  }
}

// 4. No overlap around vertices: the angles of the triangles around an interior vertex
// add up to 2*pi, around a boundary vertex to at most 2*pi (catches a mesh that wraps
// around a vertex twice, which the edge checks cannot see).
void Checker::check_vertex_angles() {
  if (!all_ccw || !manifold) return;
  std::vector<double> angle(static_cast<std::size_t>(nv), 0.0);
  std::vector<std::uint8_t> used(static_cast<std::size_t>(nv), 0);
  for (TriId t = 0; t < nt; ++t) {
    const auto& v = T[t];
    for (int k = 0; k < 3; ++k) {
      const Vec2 &a = V[v[k]], &b = V[v[(k + 1) % 3]], &c = V[v[(k + 2) % 3]];
      // Edge vectors scaled to unit max-norm (differences of tiny or denormal
      // coordinates would underflow in the products), and |cross|: the triangle is
      // CCW (exact), so each angle is in (0, pi) even when round-off flips the sign of
      // a nearly zero cross product.
      double ux = b.x - a.x, uy = b.y - a.y, wx = c.x - a.x, wy = c.y - a.y;
      const double su = std::max(std::abs(ux), std::abs(uy)),
                   sw = std::max(std::abs(wx), std::abs(wy));
      ux /= su, uy /= su, wx /= sw, wy /= sw;
      angle[v[k]] += std::atan2(std::abs(ux * wy - uy * wx), ux * wx + uy * wy);
      used[v[k]] = 1;
    }
  }
  constexpr double two_pi = 2.0 * std::numbers::pi;
  for (VertId i = 0; i < nv && !err.full(); ++i) {
    if (!used[i]) continue;
    const double deg = angle[i] * 180.0 / std::numbers::pi;
    if (!on_boundary[i] && std::abs(angle[i] - two_pi) > kAngleTol)
      err.add("vertex " + std::to_string(i) + " " + pt(V[i]) +
              ": the triangles around this interior vertex overlap (their angles add up to " +
              fmt(deg) + " degrees, not 360)");
    else if (on_boundary[i] && angle[i] > two_pi + kAngleTol)
      err.add("vertex " + std::to_string(i) + " " + pt(V[i]) +
              ": the triangles around this boundary vertex overlap (their angles add up to " +
              fmt(deg) + " degrees)");
  }
}

// 5. Input vertices: input_vertex maps to a vertex with the same coordinates (without a
// map, the input points are found by their exact coordinates).
void Checker::map_input_vertices() {
  np = in.points.size();
  vmap.assign(np, kNone);
  if (m.input_vertex.size() == np) {
    for (std::size_t i = 0; i < np; ++i) {
      const VertId v = m.input_vertex[i];
      if (v == kNone) continue;
      if (v < 0 || v >= nv) {
        err.add("input point " + std::to_string(i) + " maps to vertex " + std::to_string(v) +
                ", out of range [0," + std::to_string(nv) + ")");
        continue;
      }
      if (!(V[v].x == in.points[i].x && V[v].y == in.points[i].y)) {
        err.add("input point " + std::to_string(i) + " " + pt(in.points[i]) + " maps to vertex " +
                std::to_string(v) + " at a different place " + pt(V[v]));
        continue;
      }
      vmap[i] = v;
    }
  } else if (m.input_vertex.empty()) {
    // No map given: find the input points by their exact coordinates.
    struct H {
      std::size_t operator()(const std::pair<double, double>& p) const {
        return std::hash<double>()(p.first) * 0x9E3779B97F4A7C15ull ^ std::hash<double>()(p.second);
      }
    };
    std::unordered_map<std::pair<double, double>, VertId, H> at;
    at.reserve(static_cast<std::size_t>(nv));
    for (VertId i = 0; i < nv; ++i) at.emplace(std::make_pair(V[i].x, V[i].y), i);
    for (std::size_t i = 0; i < np; ++i) {
      auto it = at.find({in.points[i].x, in.points[i].y});
      if (it != at.end()) vmap[i] = it->second;
    }
  } else {
    err.add("mesh.input_vertex has " + std::to_string(m.input_vertex.size()) + " entries for " +
            std::to_string(np) + " input points");
  }
}

// 6. Segments: every input segment is covered by a chain of constrained edges from one
// end to the other through vertices on the segment (exactly, or within the rounding of a
// Steiner point: kSegmentTolUlps), and every constrained edge lies on such a chain.
void Checker::check_segments() {
  if (!opt.segments_present || in.segments.empty()) return;
  // Constrained-edge adjacency (both directions), CSR.
  cs.assign(static_cast<std::size_t>(nv) + 2, 0);
  for (std::int32_t e = 0; e < ne; ++e)
    if (evalid[e]) ++cs[E[e].a + 2], ++cs[E[e].b + 2];
  for (std::size_t i = 2; i < cs.size(); ++i) cs[i] += cs[i - 1];
  cadj.resize(static_cast<std::size_t>(cs.back()));
  cedge.resize(static_cast<std::size_t>(cs.back()));
  for (std::int32_t e = 0; e < ne; ++e)
    if (evalid[e]) {
      cedge[cs[E[e].a + 1]] = e, cadj[cs[E[e].a + 1]++] = E[e].b;
      cedge[cs[E[e].b + 1]] = e, cadj[cs[E[e].b + 1]++] = E[e].a;
    }
  // The converse: every constrained edge must lie on the chain of some input segment.
  // This catches a chain bent away from its segment (a misplaced Steiner vertex) when
  // the segment itself is accepted as leaving the domain (below).
  on_chain.assign(static_cast<std::size_t>(ne), 0);
  visit.assign(static_cast<std::size_t>(nv), -1);  // segment that reached a vertex
  for (std::size_t s = 0; s < in.segments.size() && !err.full(); ++s) check_segment(s);
  accept_unmarked_on_segments();
  for (std::int32_t e = 0; e < ne && !err.full(); ++e)
    if (evalid[e] && canon[e] == e && !on_chain[e])
      err.add("constrained edge " + std::to_string(e) + " " + edge_str(E[e].a, E[e].b) + " " +
              pt(V[E[e].a]) + "-" + pt(V[E[e].b]) + " is not on the chain of any input segment");
}

// The chain of input segment s, marking the constrained edges on it (on_chain).
void Checker::check_segment(std::size_t s) {
  const auto& sg = in.segments[s];
  const std::string sname = "segment " + std::to_string(s) + " (input " + std::to_string(sg.a) +
                            "-" + std::to_string(sg.b) + ")";
  if (sg.a < 0 || sg.b < 0 || static_cast<std::size_t>(sg.a) >= np ||
      static_cast<std::size_t>(sg.b) >= np) {
    err.add(sname + " references a point out of range [0," + std::to_string(np) + ")");
    return;
  }
  VertId va = vmap[sg.a], vb = vmap[sg.b];
  // Both ends outside the domain: the segment went with the exterior or a hole.
  // One end outside: walk from the other one; the chain must leave the domain.
  if (va == kNone && vb == kNone) return;
  Vec2 A, B;
  if (va == kNone) {
    va = vb;
    vb = kNone;
    A = V[va], B = in.points[sg.a];
  } else {
    A = V[va], B = vb == kNone ? in.points[sg.b] : V[vb];
  }
  if (va == vb || (A.x == B.x && A.y == B.y)) return;
  const SegmentFrame sf(A, B);
  using Key = SegmentFrame::Key;
  auto key = [&](const Vec2& p) { return sf.key(p); };
  // Search along constrained edges whose far vertex advances toward B and lies on
  // the segment (exactly, or within rounding). The whole reachable set is explored,
  // not one greedy path: two input segments from one point may be nearly collinear
  // (a grid scaled by 0.1), so both chains are within rounding of both lines and
  // either may lead on; every edge met this way lies on the segment and is marked.
  const Key kb = key(B);
  stack.clear();
  dead_ends.clear();
  stack.push_back(va);
  visit[va] = static_cast<std::int64_t>(s);
  VertId furthest = va;
  bool reached = false;
  while (!stack.empty()) {
    const VertId cur = stack.back();
    stack.pop_back();
    const Key kc = key(V[cur]);
    if (kc > key(V[furthest])) furthest = cur;
    bool onward = false;
    for (std::int32_t j = cs[cur]; j < cs[cur + 1]; ++j) {
      const VertId n = cadj[j];
      if (n != vb) {
        const Vec2& P = V[n];
        const Key kp = key(P);
        if (!(kp > kc && kp < kb)) continue;
        if (!sf.near_line(P)) continue;
      }
      onward = true;
      on_chain[canon[cedge[j]]] = 1;
      if (n == vb) {
        reached = true;
      } else if (visit[n] != static_cast<std::int64_t>(s)) {
        visit[n] = static_cast<std::int64_t>(s);
        stack.push_back(n);
      }
    }
    if (!onward) dead_ends.push_back(cur);
  }
  if (reached || leaves_domain(dead_ends, B)) return;
  err.add(sname + " is not covered by constrained edges: the chain from vertex " +
          std::to_string(va) + " toward " +
          (vb == kNone ? "input point " + pt(B) : "vertex " + std::to_string(vb)) +
          " stops at vertex " + std::to_string(furthest) + " " + pt(V[furthest]) +
          ", where the segment goes on into the domain");
}

// A segment without a chain to B is right when it leaves the domain where the chain
// stops: the rest of it was removed with the exterior or a hole (a dangling segment
// outside the outer boundary, one end outside). It is wrong when the segment goes on into
// a triangle there. At a dead end F, the direction F->B is in the closed angular sector
// of a triangle (F, P, Q) iff orient(F,P,B) >= 0 and orient(F,B,Q) >= 0 (the angle at F
// is below pi). True when at some dead end no triangle contains the direction. (A segment
// leaving a hole's boundary through a vertex and re-entering the domain later is accepted
// without checking the rest.)
bool Checker::leaves_domain(const std::vector<VertId>& ends, const Vec2& B) {
  if (vstart.empty()) {
    vstart.assign(static_cast<std::size_t>(nv) + 2, 0);
    for (TriId t = 0; t < nt; ++t)
      if (ccw[t])
        for (int k = 0; k < 3; ++k) ++vstart[T[t][k] + 2];
    for (std::size_t i = 2; i < vstart.size(); ++i) vstart[i] += vstart[i - 1];
    vtris.resize(static_cast<std::size_t>(vstart.back()));
    for (TriId t = 0; t < nt; ++t)
      if (ccw[t])
        for (int k = 0; k < 3; ++k) vtris[vstart[T[t][k] + 1]++] = 3 * t + k;
  }
  for (const VertId f : ends) {
    bool inside = false;
    for (std::int32_t j = vstart[f]; j < vstart[f + 1] && !inside; ++j) {
      const auto& v = T[vtris[j] / 3];
      const int k = vtris[j] % 3;
      const Vec2 &F = V[v[k]], &P = V[v[(k + 1) % 3]], &Q = V[v[(k + 2) % 3]];
      inside = orient(F, P, B) >= 0 && orient(F, B, Q) >= 0;
    }
    if (!inside) return true;
  }
  return false;
}

// A segment accepted as leaving the domain may come back into it (its middle runs
// between a hole and the exterior): the walk from its first end stops at the gap and
// never marks the pieces beyond it. An edge left unmarked is therefore accepted when it
// lies on some input segment (both ends on the closed segment). Only unmarked edges are
// searched, so a valid mesh pays for its few re-entering pieces only.
void Checker::accept_unmarked_on_segments() {
  for (std::int32_t e = 0; e < ne && !err.full(); ++e) {
    if (!evalid[e] || canon[e] != e || on_chain[e]) continue;
    for (const auto& sg : in.segments) {
      if (sg.a < 0 || sg.b < 0 || static_cast<std::size_t>(sg.a) >= np ||
          static_cast<std::size_t>(sg.b) >= np)
        continue;
      const Vec2 &A = in.points[sg.a], &B = in.points[sg.b];
      if (A.x == B.x && A.y == B.y) continue;
      const SegmentFrame sf(A, B);
      if (sf.holds(V[E[e].a]) && sf.holds(V[E[e].b])) {
        on_chain[e] = 1;
        break;
      }
    }
  }
}

// 7. Point queries: no triangle contains a hole seed; every region seed is in a triangle
// whose attribute is the seed's; an input point without a mesh vertex is not inside (or
// on the boundary of) the meshed domain.
void Checker::check_point_queries() {
  std::vector<Query> qs;
  collect_queries(qs);
  if (qs.empty()) return;
  locate_queries(qs);
  report_queries(qs);
}

void Checker::collect_queries(std::vector<Query>& qs) {
  if (opt.seeds) {
    for (std::size_t i = 0; i < in.holes.size(); ++i)
      qs.push_back({Query::Hole, static_cast<std::int32_t>(i), in.holes[i]});
    for (std::size_t i = 0; i < in.regions.size(); ++i)
      qs.push_back({Query::Region, static_cast<std::int32_t>(i), in.regions[i].seed});
  }
  if (m.input_vertex.size() == np) {
    // Without segments the domain is the convex hull of all input points: each of them
    // must be a vertex. (A point on the hull dropped by the mesher is outside every
    // triangle, so the point query below could not see it.)
    const bool hull_domain = in.segments.empty() && nt > 0;
    for (std::size_t i = 0; i < np; ++i) {
      if (m.input_vertex[i] != kNone) continue;
      if (hull_domain)
        err.add("input point " + std::to_string(i) + " " + pt(in.points[i]) +
                " has no mesh vertex, but without segments the domain is the convex hull of all "
                "input points");
      else
        qs.push_back({Query::MissingInput, static_cast<std::int32_t>(i), in.points[i]});
    }
  }
  // Drop non-finite query points (they cannot be located; the mesher rejects them).
  std::erase_if(qs, [](const Query& q) { return !std::isfinite(q.p.x) || !std::isfinite(q.p.y); });
}

// The first triangle holding each query point (strictly and in its closure): a uniform
// grid over the query points, ~1 query per cell; every oriented triangle is tested
// against the queries in the cells its bounding box overlaps.
void Checker::locate_queries(std::vector<Query>& qs) const {
  double x0 = qs[0].p.x, x1 = x0, y0 = qs[0].p.y, y1 = y0;
  for (const auto& q : qs)
    x0 = std::min(x0, q.p.x), x1 = std::max(x1, q.p.x), y0 = std::min(y0, q.p.y),
    y1 = std::max(y1, q.p.y);
  const int G =
      std::clamp(static_cast<int>(std::ceil(std::sqrt(static_cast<double>(qs.size())))), 1, 1024);
  const double dx = x1 > x0 ? (x1 - x0) / G : 1.0, dy = y1 > y0 ? (y1 - y0) / G : 1.0;
  // floor((x - x0) / dx) is monotone in x, so a triangle's cell range covers every cell
  // of a query inside its bounding box.
  auto cx = [&](double x) {
    return std::clamp(static_cast<int>(std::floor((x - x0) / dx)), 0, G - 1);
  };
  auto cy = [&](double y) {
    return std::clamp(static_cast<int>(std::floor((y - y0) / dy)), 0, G - 1);
  };
  std::vector<std::int32_t> cstart(static_cast<std::size_t>(G) * G + 1, 0), cq(qs.size());
  for (const auto& q : qs) ++cstart[cy(q.p.y) * G + cx(q.p.x) + 1];
  for (std::size_t i = 1; i < cstart.size(); ++i) cstart[i] += cstart[i - 1];
  {
    std::vector<std::int32_t> fill(cstart.begin(), cstart.end() - 1);
    for (std::size_t i = 0; i < qs.size(); ++i)
      cq[fill[cy(qs[i].p.y) * G + cx(qs[i].p.x)]++] = static_cast<std::int32_t>(i);
  }
  for (TriId t = 0; t < nt; ++t) {
    if (!ccw[t]) continue;
    const Vec2 &a = V[T[t][0]], &b = V[T[t][1]], &c = V[T[t][2]];
    const double tx0 = std::min({a.x, b.x, c.x}), tx1 = std::max({a.x, b.x, c.x});
    const double ty0 = std::min({a.y, b.y, c.y}), ty1 = std::max({a.y, b.y, c.y});
    if (tx1 < x0 || tx0 > x1 || ty1 < y0 || ty0 > y1) continue;
    const int i0 = cx(tx0), i1 = cx(tx1), j0 = cy(ty0), j1 = cy(ty1);
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i)
        for (std::int32_t k = cstart[j * G + i]; k < cstart[j * G + i + 1]; ++k) {
          Query& q = qs[cq[k]];
          if (q.strict != kNone) continue;
          if (q.p.x < tx0 || q.p.x > tx1 || q.p.y < ty0 || q.p.y > ty1) continue;
          const double o1 = orient(a, b, q.p), o2 = orient(b, c, q.p), o3 = orient(c, a, q.p);
          if (o1 < 0 || o2 < 0 || o3 < 0) continue;
          if (q.closed == kNone) q.closed = t;
          if (o1 > 0 && o2 > 0 && o3 > 0) q.strict = t;
        }
  }
}

void Checker::report_queries(const std::vector<Query>& qs) {
  // Region seeds: group by the region of their triangle; when seeds of one region
  // disagree, any of their attributes is accepted (the input is ambiguous).
  std::unordered_map<std::int64_t, std::vector<double>> seeds_of_region;
  auto where = [](const Query& q) { return q.strict != kNone ? q.strict : q.closed; };
  for (const auto& q : qs)
    if (q.kind == Query::Region && where(q) != kNone)
      seeds_of_region[have_region ? m.triangle_region[where(q)] : where(q)].push_back(
          in.regions[q.index].attribute);
  for (const auto& q : qs) {
    const TriId t = where(q);
    switch (q.kind) {
      case Query::Hole:
        if (t != kNone)
          err.add("hole seed " + std::to_string(q.index) + " " + pt(q.p) + " lies in " +
                  tri_str(t, T[t]));
        break;
      case Query::MissingInput:
        if (t != kNone)
          err.add("input point " + std::to_string(q.index) + " " + pt(q.p) +
                  " has no mesh vertex but lies in the domain, in " + tri_str(t, T[t]));
        break;
      case Query::Region: {
        if (t == kNone) {
          err.add("region seed " + std::to_string(q.index) + " " + pt(q.p) +
                  " lies in no triangle");
          break;
        }
        if (!have_attr) break;
        const double got = m.triangle_attribute[t];
        const auto& cand = seeds_of_region[have_region ? m.triangle_region[t] : t];
        if (std::find(cand.begin(), cand.end(), got) == cand.end())
          err.add("region seed " + std::to_string(q.index) + " " + pt(q.p) + " with attribute " +
                  fmt(in.regions[q.index].attribute) + " lies in " + tri_str(t, T[t]) +
                  " whose attribute is " + fmt(got));
        break;
      }
    }
  }
}

}  // namespace

CheckReport check(const Mesh& m, const Pslg& in, const CheckOptions& opt) {
  CheckReport rep;
  Checker(m, in, opt, rep).run();
  return rep;
}

}  // namespace uvmesh::m2d
