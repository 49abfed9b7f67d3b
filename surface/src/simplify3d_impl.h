// Private to the simplification stage (simplify3d.cpp, simplify3d_repair.cpp): the
// Simplifier, the mesh being simplified with its adjacency, and the shape measures its
// operations are judged by. Not installed.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "simplify3d.h"
#include "uvmesh/geom/project.h"
#include "uvmesh/mesher2d/measures.h"

namespace uvmesh::surface::detail::simplify_impl {

using geom::Vec2;
using geom::Vec3;
using Tri = std::array<NodeId, 3>;
using TriUV = std::array<Vec2, 3>;
constexpr double kInf = std::numeric_limits<double>::infinity();
// A collapse or swap may turn no triangle by more than this (the fold guard of §7.3.6).
inline const double kMaxTurn = std::cos(60.0 * std::numbers::pi / 180.0);
constexpr int kRounds = 24;
// What a collapse of an edge shorter than L may leave even when it is worse than before.
constexpr double kFairShape = 2.0;
// How much worse than the needle it removes a collapse along a needle strip may leave.
constexpr double kStripStepSlack = 1.1;

inline std::string fmt(double x) {
  std::ostringstream s;
  s.precision(3);
  s << x;
  return s.str();
}

inline double shape(const Vec3& p, const Vec3& q, const Vec3& r) {
  const double area2 = glm::length(glm::cross(q - p, r - p));
  if (!(area2 > 0)) return kInf;
  return measures::shape_Q(glm::length(q - p), glm::length(r - q), glm::length(p - r), area2);
}

inline Vec3 unit_normal(const Vec3& p, const Vec3& q, const Vec3& r) {
  const Vec3 n = glm::cross(q - p, r - p);
  const double l = glm::length(n);
  return l > 0 ? n / l : Vec3(0.0);
}

// An operation, as the guard against crossings names it: its kind ('c' collapse of the
// first node onto the second, 'f' swap of the edge, 's' split of the edge, 'r'
// relocation of the first node) and its nodes.
using OpKey = std::tuple<char, NodeId, NodeId>;
inline OpKey edge_op(char kind, NodeId a, NodeId b) {
  return {kind, std::min(a, b), std::max(a, b)};
}

// A triangle about to be written: its corners, face and (u,v) on that face.
struct NewTri {
  int slot = -1;  ///< triangle index it replaces, -1: appended
  Tri v{};
  geom::Id face = geom::kNone;
  TriUV uv{};
};

struct Simplifier {
  const SimplifyInput& in;
  const geom::Model& m;
  SurfaceMesh& M;
  std::vector<Simplification> log;

  std::vector<char> tri_alive, node_alive, seg_alive;
  std::vector<std::vector<int>> vtris, nsegs, eseg;
  std::vector<std::vector<geom::Id>> efaces;
  std::vector<char> sharp, dissolved;
  std::vector<char> free_edge;   ///< per model edge: used by one face once (a sheet's border)
  std::vector<double> dihedral;  ///< per model edge, degrees (max along it)
  /// Per face: which solids it bounds (an index of the distinct sets). A triangle never
  /// moves to a face of another set: each solid's own triangles stay a closed surface.
  std::vector<int> solid_set;
  std::vector<int> touched;
  double start_worst = 0;  ///< the worst Q of the mesh the stage was given
  bool changed = false;
  std::vector<double> area0;  ///< per face: its triangles' area before the stage
  /// The guard against crossings (simplify_mesh): operations an earlier run found to
  /// make triangles intersect are not done; each operation done is listed, and each
  /// triangle knows the last one that changed it (written, or a corner moved; -1: none).
  const std::set<OpKey>& forbidden;
  std::vector<OpKey> ops;
  std::vector<int> writer;

  Simplifier(const SimplifyInput& i, SurfaceMesh& mesh, const std::set<OpKey>& no)
      : in(i), m(i.model), M(mesh), forbidden(no) {}

  // ---- accessors
  const Vec3& P(NodeId n) const { return M.points[static_cast<std::size_t>(n)]; }
  int dim(NodeId n) const { return M.point_dim[static_cast<std::size_t>(n)]; }
  geom::Id ent(NodeId n) const { return M.point_entity[static_cast<std::size_t>(n)]; }
  const Tri& T(int t) const { return M.triangles[static_cast<std::size_t>(t)]; }
  double Q(int t) const { return shape(P(T(t)[0]), P(T(t)[1]), P(T(t)[2])); }
  /// face interior < smooth model edge < sharp model edge < model vertex
  int rank(NodeId n) const {
    if (dim(n) == 2) return 0;
    if (dim(n) == 0) return 3;
    return sharp[static_cast<std::size_t>(ent(n))] ? 2 : 1;
  }
  template <class F>
  void for_tris(NodeId n, F&& f) const {
    for (int t : vtris[static_cast<std::size_t>(n)])
      if (tri_alive[static_cast<std::size_t>(t)] && has(T(t), n)) f(t);
  }
  bool allowed(const OpKey& k) const { return !forbidden.count(k); }
  /// The operation k starts: what it writes from now on is its doing.
  void begin(const OpKey& k) { ops.push_back(k); }
  static bool has(const Tri& v, NodeId n) { return v[0] == n || v[1] == n || v[2] == n; }
  /// The corner (0, 1, 2) of triangle t at node n (a corner of it).
  int corner(int t, NodeId n) const { return T(t)[0] == n ? 0 : (T(t)[1] == n ? 1 : 2); }
  /// The alive segment a-b, or -1.
  int segment(NodeId a, NodeId b) const {
    for (int s : nsegs[static_cast<std::size_t>(a)]) {
      const auto& g = M.segments[static_cast<std::size_t>(s)];
      if (seg_alive[static_cast<std::size_t>(s)] && (g.a == b || g.b == b)) return s;
    }
    return -1;
  }
  std::vector<int> edge_tris(NodeId a, NodeId b) const {
    std::vector<int> r;
    for_tris(a, [&](int t) {
      if (has(T(t), b)) r.push_back(t);
    });
    return r;
  }
  std::vector<NodeId> neighbours(NodeId a) const {
    std::vector<NodeId> r;
    for_tris(a, [&](int t) {
      for (NodeId v : T(t))
        if (v != a) r.push_back(v);
    });
    std::sort(r.begin(), r.end());
    r.erase(std::unique(r.begin(), r.end()), r.end());
    return r;
  }
  /// (u,v) of node n on face f from a triangle of f around it, the one nearest `ref`.
  std::optional<Vec2> uv_on(NodeId n, geom::Id f, const Vec2* ref) const {
    std::optional<Vec2> best;
    double bd = kInf;
    for_tris(n, [&](int t) {
      if (M.triangle_face[static_cast<std::size_t>(t)] != f) return;
      const Vec2 uv =
          M.triangle_uv[static_cast<std::size_t>(t)][static_cast<std::size_t>(corner(t, n))];
      const double d = ref ? glm::length(uv - *ref) : 0.0;
      if (d < bd) bd = d, best = uv;
    });
    return best;
  }
  geom::Projection project(geom::Id f, const Vec3& x, const Vec2& seed, double scale) const {
    const geom::Face& F = m.faces[static_cast<std::size_t>(f)];
    return geom::project_to_surface(*F.surface, x, seed, F.uv_box, scale);
  }

  void init();
  void classify_edges();
  void classify_faces();
  double edge_dihedral(geom::Id e) const;
  bool place(NewTri& nt, geom::Id f0, const TriUV& hint) const;
  bool place_on(NewTri& nt, geom::Id f, const TriUV* hint, double& dist) const;
  double deviation(const NewTri& nt) const;
  struct Plan {
    bool ok = false;
    double worst = kInf;
    bool dissolve = false;
    std::vector<NewTri> tris;
    std::vector<int> removed;
  };
  Plan plan_collapse(NodeId a, NodeId b) const;
  bool collapse_allowed(NodeId a, NodeId b, bool& dissolve) const;
  /// On an alive segment of an edge e with flag[e] set.
  bool on_edge_where(NodeId n, const std::vector<char>& flag) const;
  bool on_free_edge(NodeId n) const { return on_edge_where(n, free_edge); }
  bool on_kept_edge(NodeId n) const { return on_edge_where(n, in.kept_edges); }
  bool kept(geom::Id e) const {
    return e >= 0 && static_cast<std::size_t>(e) < in.kept_edges.size() &&
           in.kept_edges[static_cast<std::size_t>(e)];
  }
  Simplification vertex_merge(NodeId a, NodeId b, const Plan& p) const;
  bool link_ok(NodeId a, NodeId b, const std::vector<int>& removed) const;
  void apply_collapse(NodeId a, NodeId b, const Plan& p);
  void write(const NewTri& nt);
  void dissolve(geom::Id e);
  bool try_collapse(NodeId a, NodeId b);
  bool collapse_pass(const std::vector<int>& cand);
  bool try_flip(int t, int k, double limit);
  bool try_split(int t, int k, double max_height);
  std::vector<int> poor_first(const std::vector<int>& cand) const;
  /// op(t) on each candidate still alive and poor (Q > kPoorShape) when its turn comes,
  /// worst first; whether any op returned true.
  template <class Op>
  bool for_each_poor(const std::vector<int>& cand, Op&& op) {
    bool any = false;
    for (int t : poor_first(cand))
      if (tri_alive[static_cast<std::size_t>(t)] && Q(t) > kPoorShape) any |= op(t);
    return any;
  }
  bool repair_pass(const std::vector<int>& cand);
  bool try_relocate(NodeId n);
  bool relocate_pass(const std::vector<int>& cand);
  double node_param(NodeId n, geom::Id e, double hint) const;
  NodeId add_edge_node(geom::Id e, double t);
  void run();
  /// Pairs of alive triangles (t0 < t1, at least one changed) that intersect.
  std::vector<std::pair<int, int>> crossings() const;
  /// Of a crossing pair, the operation that made it: the later of the two triangles' last.
  const OpKey& culprit(int t0, int t1) const;
  void finish();
  void compact();
};

}  // namespace uvmesh::surface::detail::simplify_impl
