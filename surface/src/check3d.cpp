// 3D checks and measures of a SurfaceMesh (see check3d.h for the definitions).
#include "uvmesh/surface/check3d.h"

#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>

#include "predicates3d.h"

namespace uvmesh::surface {

using geom::Vec2;
using geom::Vec3;

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kAlpha = 0.28867513459481287;  // sqrt(3)/6: Q = 1 for the equilateral

// Arena of `threads` workers (0: TBB's default, all cores).
tbb::task_arena make_arena(int threads) {
  return threads > 0 ? tbb::task_arena(threads) : tbb::task_arena();
}

enum TriState : std::int8_t { kValid = 0, kBadIndex = 1, kRepeated = 2 };

TriState tri_state(const SurfaceMesh& m, std::size_t t) {
  const auto& tr = m.triangles[t];
  const auto n = static_cast<NodeId>(m.points.size());
  for (NodeId i : tr)
    if (i < 0 || i >= n) return kBadIndex;
  if (tr[0] == tr[1] || tr[1] == tr[2] || tr[2] == tr[0]) return kRepeated;
  return kValid;
}

pred3::Tri corners(const SurfaceMesh& m, std::size_t t) {
  const auto& tr = m.triangles[t];
  return {m.points[tr[0]], m.points[tr[1]], m.points[tr[2]]};
}

geom::Id face_of(const SurfaceMesh& m, std::size_t t) {
  return t < m.triangle_face.size() ? m.triangle_face[t] : geom::kNone;
}

// Keeps the k smallest values pushed (a bounded max-heap), for capped sorted lists whose
// content does not depend on the order in which the values were found.
template <class T>
class SmallestK {
 public:
  explicit SmallestK(std::size_t k) : k_(k) {}
  void push(const T& v) {
    if (k_ == 0) return;
    if (heap_.size() < k_) {
      heap_.push(v);
    } else if (v < heap_.top()) {
      heap_.pop();
      heap_.push(v);
    }
  }
  void merge(SmallestK& o) {
    while (!o.heap_.empty()) {
      push(o.heap_.top());
      o.heap_.pop();
    }
  }
  std::vector<T> sorted() {
    std::vector<T> v;
    while (!heap_.empty()) {
      v.push_back(heap_.top());
      heap_.pop();
    }
    std::reverse(v.begin(), v.end());
    return v;
  }

 private:
  std::size_t k_;
  std::priority_queue<T> heap_;
};

}  // namespace

// =======================================================================================
// 1. Topology
// =======================================================================================

ClosePointsReport find_close_points(const std::vector<Vec3>& points, double rel_tol, int max_list) {
  ClosePointsReport r;
  const std::size_t n = points.size();
  if (n < 2) return r;
  geom::Box3 box;
  for (const Vec3& p : points) box.add(p);
  const double diag = box.diagonal();
  const double tol = std::max(rel_tol, 0.0) * diag;
  r.tolerance = tol;
  // Cells of size h > tol, so a close pair lies in the same or in neighbouring (x, y)
  // cells. The floor on h keeps cell indices below 1e12, where the rounding of
  // (x - lo) / h (about 1e-4 of a cell) stays inside the 0.1% margin of h over tol.
  double h = 1.001 * std::max({tol, 1e-12 * diag, std::numeric_limits<double>::min()});
  if (!(h > 0) || !std::isfinite(h)) h = 1.0;

  struct Rec {
    std::int64_t cx, cy;
    double z;
    NodeId id;
    bool operator<(const Rec& o) const {
      if (cx != o.cx) return cx < o.cx;
      if (cy != o.cy) return cy < o.cy;
      if (z != o.z) return z < o.z;
      return id < o.id;
    }
  };
  std::vector<Rec> rec(n);
  tbb::parallel_for(std::size_t(0), n, [&](std::size_t i) {
    const Vec3& p = points[i];
    rec[i] = {static_cast<std::int64_t>(std::floor((p.x - box.lo.x) / h)),
              static_cast<std::int64_t>(std::floor((p.y - box.lo.y) / h)), p.z,
              static_cast<NodeId>(i)};
  });
  tbb::parallel_sort(rec.begin(), rec.end());

  struct Group {
    std::int64_t cx, cy;
    std::size_t begin, end;
  };
  std::vector<Group> groups;
  for (std::size_t i = 0; i < n;) {
    std::size_t j = i + 1;
    while (j < n && rec[j].cx == rec[i].cx && rec[j].cy == rec[i].cy) ++j;
    groups.push_back({rec[i].cx, rec[i].cy, i, j});
    i = j;
  }
  auto find_group = [&](std::int64_t cx, std::int64_t cy) -> const Group* {
    auto it = std::lower_bound(groups.begin(), groups.end(), std::make_pair(cx, cy),
                               [](const Group& g, const std::pair<std::int64_t, std::int64_t>& k) {
                                 return g.cx != k.first ? g.cx < k.first : g.cy < k.second;
                               });
    return (it != groups.end() && it->cx == cx && it->cy == cy) ? &*it : nullptr;
  };

  SmallestK<std::pair<NodeId, NodeId>> smallest(static_cast<std::size_t>(std::max(max_list, 0)));
  double dmin = std::numeric_limits<double>::infinity();
  auto consider = [&](const Rec& p, const Rec& q) {
    const double d = glm::length(points[p.id] - points[q.id]);
    if (!(d < tol || d == 0)) return;
    ++r.pairs;
    dmin = std::min(dmin, d);
    const NodeId a = std::min(p.id, q.id), b = std::max(p.id, q.id);
    smallest.push({a, b});
  };
  for (const Group& g : groups) {
    // Within the cell column: a sweep along z.
    for (std::size_t i = g.begin; i < g.end; ++i)
      for (std::size_t j = i + 1; j < g.end && rec[j].z - rec[i].z <= tol; ++j)
        consider(rec[i], rec[j]);
    // The four forward neighbour columns (each unordered pair of neighbours once).
    const std::int64_t nb[4][2] = {{0, 1}, {1, -1}, {1, 0}, {1, 1}};
    for (const auto& o : nb) {
      const Group* q = find_group(g.cx + o[0], g.cy + o[1]);
      if (!q) continue;
      std::size_t s = q->begin;
      for (std::size_t i = g.begin; i < g.end; ++i) {
        while (s < q->end && rec[s].z < rec[i].z - tol) ++s;
        for (std::size_t j = s; j < q->end && rec[j].z <= rec[i].z + tol; ++j)
          consider(rec[i], rec[j]);
      }
    }
  }
  for (const auto& [a, b] : smallest.sorted())
    r.list.push_back({a, b, glm::length(points[a] - points[b])});
  r.min_distance = r.pairs ? dmin : 0.0;
  return r;
}

TopologyReport check_topology(const SurfaceMesh& m, const TopologyOptions& opt) {
  TopologyReport r;
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  const std::size_t cap = static_cast<std::size_t>(std::max(opt.max_list, 0));
  r.points = np;
  r.triangles = nt;

  // Per-triangle state; zero area decided exactly (all three projected areas are zero).
  std::vector<std::int8_t> state(nt), zero(nt, 0);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    state[t] = tri_state(m, t);
    if (state[t] == kValid) zero[t] = pred3::projection_axis(corners(m, t)) < 0;
  });
  for (std::size_t t = 0; t < nt; ++t) {
    const bool bad = state[t] != kValid || zero[t];
    r.bad_index_triangles += state[t] == kBadIndex;
    r.repeated_index_triangles += state[t] == kRepeated;
    r.zero_area_triangles += zero[t] != 0;
    if (bad && r.degenerate_list.size() < cap) r.degenerate_list.push_back(static_cast<TriId>(t));
  }
  r.degenerate_triangles =
      r.bad_index_triangles + r.repeated_index_triangles + r.zero_area_triangles;

  // Directed edges of the valid triangles, sorted by (undirected edge, triangle).
  struct EdgeRec {
    NodeId lo, hi;
    TriId t;
    bool forward;  // traversed lo -> hi
    bool operator<(const EdgeRec& o) const {
      if (lo != o.lo) return lo < o.lo;
      if (hi != o.hi) return hi < o.hi;
      return t < o.t;
    }
  };
  std::vector<EdgeRec> er;
  er.reserve(3 * nt);
  std::vector<char> used(np, 0);
  std::size_t valid_tris = 0;
  for (std::size_t t = 0; t < nt; ++t) {
    if (state[t] == kBadIndex) continue;
    const auto& tr = m.triangles[t];
    for (NodeId i : tr) used[i] = 1;
    if (state[t] != kValid) continue;
    ++valid_tris;
    for (int k = 0; k < 3; ++k) {
      const NodeId a = tr[k], b = tr[(k + 1) % 3];
      er.push_back({std::min(a, b), std::max(a, b), static_cast<TriId>(t), a < b});
    }
  }
  tbb::parallel_sort(er.begin(), er.end());
  auto issue = [&](std::size_t i, std::size_t j) {
    EdgeIssue e;
    e.a = er[i].lo;
    e.b = er[i].hi;
    for (std::size_t k = i; k < j; ++k) {
      e.triangles.push_back(er[k].t);
      e.faces.push_back(face_of(m, er[k].t));
    }
    return e;
  };
  for (std::size_t i = 0; i < er.size();) {
    std::size_t j = i + 1;
    while (j < er.size() && er[j].lo == er[i].lo && er[j].hi == er[i].hi) ++j;
    ++r.edges;
    const std::size_t c = j - i;
    if (c == 1) {
      if (r.free_list.size() < cap) r.free_list.push_back(issue(i, j));
      ++r.free_edges;
    } else if (c >= 3) {
      if (r.non_manifold_list.size() < cap) r.non_manifold_list.push_back(issue(i, j));
      ++r.non_manifold_edges;
    } else if (er[i].forward == er[i + 1].forward) {
      if (r.inconsistent_list.size() < cap) r.inconsistent_list.push_back(issue(i, j));
      ++r.inconsistent_edges;
    }
    i = j;
  }

  std::size_t referenced = 0;
  for (std::size_t i = 0; i < np; ++i) {
    if (used[i]) {
      ++referenced;
    } else {
      ++r.unreferenced_points;
      if (r.unreferenced_list.size() < cap) r.unreferenced_list.push_back(static_cast<NodeId>(i));
    }
  }
  r.euler_characteristic = static_cast<long long>(referenced) - static_cast<long long>(r.edges) +
                           static_cast<long long>(valid_tris);
  r.close_points = find_close_points(m.points, opt.close_rel_tol, opt.max_list);
  return r;
}

// =======================================================================================
// 2. Self-intersections
// =======================================================================================

namespace {

PairKind pair_kind(const std::array<NodeId, 3>& A, const std::array<NodeId, 3>& B) {
  int shared = 0;
  for (NodeId a : A)
    for (NodeId b : B) shared += a == b;
  return static_cast<PairKind>(shared);
}

// The pair test for two valid, non-degenerate triangles (see check3d.h for the rules).
bool pair_intersects(const SurfaceMesh& m, TriId t0, TriId t1, PairKind& kind) {
  const auto& A = m.triangles[t0];
  const auto& B = m.triangles[t1];
  const auto& P = m.points;
  kind = pair_kind(A, B);
  switch (kind) {
    case PairKind::Duplicate:
      return true;
    case PairKind::SharedEdge: {
      // Rotate A so that its corner 2 is the one not shared; B's unshared corner is d.
      int ia = 0;
      while (B[0] == A[(ia + 2) % 3] || B[1] == A[(ia + 2) % 3] || B[2] == A[(ia + 2) % 3]) ++ia;
      int ib = 0;
      while (A[0] == B[ib] || A[1] == B[ib] || A[2] == B[ib]) ++ib;
      return pred3::intersect_beyond_edge(P[A[ia]], P[A[(ia + 1) % 3]], P[A[(ia + 2) % 3]],
                                          P[B[ib]]);
    }
    case PairKind::SharedVertex: {
      int ia = 0, ib = 0;
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j)
          if (A[i] == B[j]) ia = i, ib = j;
      return pred3::intersect_beyond_vertex(P[A[ia]], P[A[(ia + 1) % 3]], P[A[(ia + 2) % 3]],
                                            P[B[(ib + 1) % 3]], P[B[(ib + 2) % 3]]);
    }
    case PairKind::Disjoint:
      return pred3::closed_triangles_intersect(corners(m, t0), corners(m, t1));
  }
  return false;
}

struct Aabb {
  Vec3 lo, hi;
  void add(const Aabb& b) {
    lo = glm::min(lo, b.lo);
    hi = glm::max(hi, b.hi);
  }
  // Closed boxes: touching triangles have touching boxes.
  bool overlaps(const Aabb& b) const {
    // Bitwise and: no unpredictable branches on the hot path of the traversal.
    return (lo.x <= b.hi.x) & (b.lo.x <= hi.x) & (lo.y <= b.hi.y) & (b.lo.y <= hi.y) &
           (lo.z <= b.hi.z) & (b.lo.z <= hi.z);
  }
};

// 21 bits of x spread to every third bit.
std::uint64_t spread3(std::uint64_t x) {
  x &= 0x1fffff;
  x = (x | x << 32) & 0x1f00000000ffffULL;
  x = (x | x << 16) & 0x1f0000ff0000ffULL;
  x = (x | x << 8) & 0x100f00f00f00f00fULL;
  x = (x | x << 4) & 0x10c30c30c30c30c3ULL;
  x = (x | x << 2) & 0x1249249249249249ULL;
  return x;
}

// Bounding-volume hierarchy over triangles: items in Morton (Z-curve) order of their box
// centres, then a median split by count, so that the tree's shape, and each node's index,
// depend on the item count alone (left child right after its parent, right child after
// the whole left subtree). Subtrees are built in parallel with an identical result for
// any thread count; boxes are unions of the children's, bottom-up.
class Bvh {
 public:
  static constexpr std::size_t kLeaf = 4;
  struct Node {
    Aabb box;
    std::int32_t right = 0;  // internal: index of the right child (left is this + 1)
    std::int32_t first = 0;  // leaf: first item
    std::int32_t count = 0;  // leaf: item count (0 for internal nodes)
  };

  Bvh(const std::vector<Aabb>& boxes, std::vector<TriId> items)
      : boxes_(boxes), items_(std::move(items)) {
    if (items_.empty()) return;
    morton_order();
    sorted_.resize(items_.size());
    for (std::size_t i = 0; i < items_.size(); ++i) sorted_[i] = boxes_[items_[i]];
    nodes_.resize(node_count(items_.size()));
    build(0, 0, items_.size());
  }
  const std::vector<Node>& nodes() const { return nodes_; }
  const std::vector<TriId>& items() const { return items_; }
  /// Boxes in item order (contiguous within a leaf).
  const std::vector<Aabb>& item_boxes() const { return sorted_; }

 private:
  void morton_order() {
    Aabb c{boxes_[items_[0]].lo + boxes_[items_[0]].hi,
           boxes_[items_[0]].lo + boxes_[items_[0]].hi};
    for (TriId t : items_) {
      const Vec3 m = boxes_[t].lo + boxes_[t].hi;  // twice the centre
      c.add({m, m});
    }
    const Vec3 ext = glm::max(c.hi - c.lo, Vec3(std::numeric_limits<double>::min()));
    std::vector<std::pair<std::uint64_t, TriId>> key(items_.size());
    tbb::parallel_for(std::size_t(0), items_.size(), [&](std::size_t i) {
      const TriId t = items_[i];
      const Vec3 f = (boxes_[t].lo + boxes_[t].hi - c.lo) / ext * 2097151.0;
      key[i] = {spread3(std::uint64_t(f.x)) | spread3(std::uint64_t(f.y)) << 1 |
                    spread3(std::uint64_t(f.z)) << 2,
                t};
    });
    tbb::parallel_sort(key.begin(), key.end());
    for (std::size_t i = 0; i < key.size(); ++i) items_[i] = key[i].second;
  }
  std::size_t node_count(std::size_t n) {
    // Sizes at one depth differ by at most one, so the memo stays tiny.
    if (n <= kLeaf) return 1;
    auto it = count_memo_.find(n);
    if (it != count_memo_.end()) return it->second;
    const std::size_t c = 1 + node_count(n / 2) + node_count(n - n / 2);
    count_memo_[n] = c;
    return c;
  }
  std::size_t nodes_in(std::size_t n) const {  // after node_count(): read-only
    return n <= kLeaf ? 1 : count_memo_.at(n);
  }
  void build(std::size_t node, std::size_t b, std::size_t e) {
    Node& nd = nodes_[node];
    if (e - b <= kLeaf) {
      nd.box = sorted_[b];
      for (std::size_t i = b + 1; i < e; ++i) nd.box.add(sorted_[i]);
      nd.first = static_cast<std::int32_t>(b);
      nd.count = static_cast<std::int32_t>(e - b);
      return;
    }
    const std::size_t mid = b + (e - b) / 2;
    const std::size_t left = node + 1;
    const std::size_t right = left + nodes_in(mid - b);
    nd.right = static_cast<std::int32_t>(right);
    if (e - b > 50000) {
      tbb::parallel_invoke([&] { build(left, b, mid); }, [&] { build(right, mid, e); });
    } else {
      build(left, b, mid);
      build(right, mid, e);
    }
    nd.box = nodes_[left].box;
    nd.box.add(nodes_[right].box);
  }

  const std::vector<Aabb>& boxes_;
  std::vector<TriId> items_;
  std::vector<Aabb> sorted_;
  std::vector<Node> nodes_;
  std::map<std::size_t, std::size_t> count_memo_;
};

// All pairs of items with overlapping boxes, each once, by a self-join of the tree: a
// node against itself is its two children against themselves and against each other;
// two distinct nodes whose boxes overlap are split on the larger one. Iterative (explicit
// stack of node pairs); the top of the recursion is expanded breadth-first into
// independent tasks that run in parallel. sink_of_thread() gives the calling thread's
// sink (fetched once per block of tasks); sink(t, u) is called with t < u.
template <class SinkOfThread>
void for_each_overlapping_pair(const Bvh& bvh, SinkOfThread&& sink_of_thread) {
  const auto& nodes = bvh.nodes();
  const auto& items = bvh.items();
  const auto& boxes = bvh.item_boxes();
  if (nodes.empty()) return;
  struct Job {
    std::int32_t a, b;
  };
  auto leaf = [&](std::int32_t n) { return nodes[n].count > 0; };
  // Children of a pair; returns false for a leaf/leaf pair (handled directly).
  auto split = [&](const Job& j, auto&& push) {
    if (j.a == j.b) {
      if (leaf(j.a)) return false;
      const std::int32_t l = j.a + 1, r = nodes[j.a].right;
      push(Job{l, l});
      push(Job{r, r});
      push(Job{l, r});
      return true;
    }
    if (!nodes[j.a].box.overlaps(nodes[j.b].box)) return true;  // nothing below
    if (leaf(j.a) && leaf(j.b)) return false;
    // Split the node that is not a leaf; of two internal nodes, the one that comes first
    // in the layout (the larger or equal subtree: siblings are balanced).
    if (!leaf(j.a) && (leaf(j.b) || j.a <= j.b)) {
      push(Job{j.a + 1, j.b});
      push(Job{nodes[j.a].right, j.b});
    } else {
      push(Job{j.a, j.b + 1});
      push(Job{j.a, nodes[j.b].right});
    }
    return true;
  };
  auto leaf_pairs = [&](const Job& j, auto& sink) {
    const Bvh::Node& A = nodes[j.a];
    const Bvh::Node& B = nodes[j.b];
    for (std::int32_t i = A.first; i < A.first + A.count; ++i) {
      const TriId t = items[i];
      const std::int32_t k0 = j.a == j.b ? i + 1 : B.first;
      for (std::int32_t k = k0; k < B.first + B.count; ++k) {
        if (!boxes[i].overlaps(boxes[k])) continue;
        const TriId u = items[k];
        sink(std::min(t, u), std::max(t, u));
      }
    }
  };
  // Breadth-first seeding of independent jobs.
  std::vector<Job> frontier{{0, 0}}, leafjobs;
  while (frontier.size() < 512) {
    std::vector<Job> next;
    bool grew = false;
    for (const Job& j : frontier) {
      const std::size_t before = next.size();
      if (!split(j, [&](const Job& c) { next.push_back(c); })) leafjobs.push_back(j);
      grew = grew || next.size() > before;
    }
    frontier.swap(next);
    if (!grew) break;
  }
  if (!leafjobs.empty()) {
    auto& sink = sink_of_thread();
    for (const Job& j : leafjobs) leaf_pairs(j, sink);
  }
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, frontier.size(), 1),
                    [&](const tbb::blocked_range<std::size_t>& rg) {
                      auto& sink = sink_of_thread();
                      std::vector<Job> stack;
                      for (std::size_t q = rg.begin(); q < rg.end(); ++q) {
                        stack.push_back(frontier[q]);
                        while (!stack.empty()) {
                          const Job j = stack.back();
                          stack.pop_back();
                          if (!split(j, [&](const Job& c) { stack.push_back(c); }))
                            leaf_pairs(j, sink);
                        }
                      }
                    });
}

}  // namespace

bool triangles_intersect(const SurfaceMesh& m, TriId t0, TriId t1) {
  const auto nt = static_cast<TriId>(m.triangles.size());
  if (t0 == t1 || t0 < 0 || t1 < 0 || t0 >= nt || t1 >= nt) return false;
  if (tri_state(m, t0) != kValid || tri_state(m, t1) != kValid) return false;
  if (pred3::projection_axis(corners(m, t0)) < 0 || pred3::projection_axis(corners(m, t1)) < 0)
    return false;
  PairKind kind;
  return pair_intersects(m, t0, t1, kind);
}

std::vector<std::size_t> pairs_intersecting_in_model(const SurfaceMesh& m, const geom::Model& model,
                                                     const std::vector<IntersectingPair>& pairs,
                                                     int k) {
  std::vector<std::size_t> out;
  if (m.triangle_uv.size() != m.triangles.size() || k < 1) return out;
  // The surface piece under triangle t: (k+1)(k+2)/2 points of a barycentric grid of its
  // (u,v) triangle mapped through sigma, k^2 triangles, appended to `pc`.
  auto piece = [&](TriId t, SurfaceMesh& pc, int skip_corner) {
    const auto f = static_cast<std::size_t>(m.triangle_face[static_cast<std::size_t>(t)]);
    if (f >= model.faces.size() || !model.faces[f].surface) return false;
    const geom::Surface& s = *model.faces[f].surface;
    const auto& uv = m.triangle_uv[static_cast<std::size_t>(t)];
    const auto base = static_cast<NodeId>(pc.points.size());
    auto id = [&](int i, int j) {
      return base + static_cast<NodeId>(i * (k + 1) - i * (i - 1) / 2 + j);
    };
    for (int i = 0; i <= k; ++i)
      for (int j = 0; i + j <= k; ++j) {
        const geom::Vec2 p =
            uv[0] + (uv[1] - uv[0]) * (double(i) / k) + (uv[2] - uv[0]) * (double(j) / k);
        const geom::Vec3 x = s.point(p.x, p.y);
        if (!std::isfinite(x.x + x.y + x.z)) return false;
        pc.points.push_back(x);
      }
    // Pieces touching the corner the two triangles share meet there by construction.
    const NodeId skip = skip_corner == 0   ? id(0, 0)
                        : skip_corner == 1 ? id(k, 0)
                        : skip_corner == 2 ? id(0, k)
                                           : -1;
    auto add = [&](std::array<NodeId, 3> T) {
      if (T[0] != skip && T[1] != skip && T[2] != skip) pc.triangles.push_back(T);
    };
    for (int i = 0; i < k; ++i)
      for (int j = 0; i + j < k; ++j) {
        add({id(i, j), id(i + 1, j), id(i, j + 1)});
        if (i + j + 1 < k) add({id(i + 1, j), id(i + 1, j + 1), id(i, j + 1)});
      }
    return true;
  };
  for (std::size_t n = 0; n < pairs.size(); ++n) {
    const IntersectingPair& p = pairs[n];
    if (p.kind != PairKind::Disjoint && p.kind != PairKind::SharedVertex) continue;
    int c0 = -1, c1 = -1;
    if (p.kind == PairKind::SharedVertex) {
      const auto &A = m.triangles[static_cast<std::size_t>(p.t0)],
                 &B = m.triangles[static_cast<std::size_t>(p.t1)];
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b)
          if (A[a] == B[b]) c0 = a, c1 = b;
    }
    SurfaceMesh pc;
    if (!piece(p.t0, pc, c0)) continue;
    const auto split = static_cast<TriId>(pc.triangles.size());
    if (!piece(p.t1, pc, c1)) continue;
    bool hit = false;
    for (TriId a = 0; a < split && !hit; ++a)
      for (TriId b = split; b < static_cast<TriId>(pc.triangles.size()) && !hit; ++b)
        hit = triangles_intersect(pc, a, b);
    if (hit) out.push_back(n);
  }
  return out;
}

IntersectionReport find_self_intersections(const SurfaceMesh& m, int max_report, int threads) {
  IntersectionReport r;
  const std::size_t nt = m.triangles.size();
  r.triangles = nt;
  if (nt == 0) return r;
  tbb::task_arena arena = make_arena(threads);
  arena.execute([&] {
    std::vector<Aabb> boxes(nt);
    std::vector<char> ok(nt, 0);
    tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
      if (tri_state(m, t) != kValid) return;
      const pred3::Tri c = corners(m, t);
      if (pred3::projection_axis(c) < 0) return;
      ok[t] = 1;
      boxes[t] = {glm::min(c[0], glm::min(c[1], c[2])), glm::max(c[0], glm::max(c[1], c[2]))};
    });
    std::vector<TriId> items;
    items.reserve(nt);
    for (std::size_t t = 0; t < nt; ++t) {
      if (ok[t])
        items.push_back(static_cast<TriId>(t));
      else
        ++r.skipped_degenerate;
    }
    const Bvh bvh(boxes, std::move(items));

    const std::size_t cap = static_cast<std::size_t>(std::max(max_report, 0));
    struct Local {
      const SurfaceMesh* m;
      std::size_t candidates = 0, hits = 0;
      SmallestK<std::pair<TriId, TriId>> first;
      Local(const SurfaceMesh* mesh, std::size_t k) : m(mesh), first(k) {}
      void operator()(TriId t, TriId u) {
        ++candidates;
        PairKind kind;
        if (pair_intersects(*m, t, u, kind)) {
          ++hits;
          first.push({t, u});
        }
      }
    };
    tbb::enumerable_thread_specific<Local> tls([&m, cap] { return Local(&m, cap); });
    for_each_overlapping_pair(bvh, [&]() -> Local& { return tls.local(); });
    SmallestK<std::pair<TriId, TriId>> first(cap);
    for (Local& L : tls) {
      r.candidate_pairs += L.candidates;
      r.intersecting_pairs += L.hits;
      first.merge(L.first);
    }
    for (const auto& [a, b] : first.sorted())
      r.pairs.push_back(
          {a, b, face_of(m, a), face_of(m, b), pair_kind(m.triangles[a], m.triangles[b])});
  });
  return r;
}

// =======================================================================================
// 3. Shape quality
// =======================================================================================

double triangle_Q(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  const double area2 = glm::length(glm::cross(b - a, c - a));  // twice the area
  if (!(area2 > 0)) return std::numeric_limits<double>::infinity();
  // rho = 2 area / perimeter  =>  Q = alpha hmax perimeter / (2 area)
  return kAlpha * std::max({ab, bc, ca}) * (ab + bc + ca) / area2;
}

QualityReport measure_quality(const SurfaceMesh& m, int max_list, double narrow_gap,
                              const std::vector<double>* edge_gap) {
  QualityReport r;
  const std::size_t nt = m.triangles.size();
  std::vector<double> Q(nt, -1.0), amin(nt, 180.0), amax(nt, 0.0);
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    if (tri_state(m, t) == kBadIndex) return;
    const pred3::Tri c = corners(m, t);
    Q[t] = triangle_Q(c[0], c[1], c[2]);
    for (int k = 0; k < 3; ++k) {
      const Vec3 e1 = c[(k + 1) % 3] - c[k], e2 = c[(k + 2) % 3] - c[k];
      // atan2 of |cross| and dot: accurate for angles near 0 and 180 degrees alike.
      const double ang =
          std::atan2(glm::length(glm::cross(e1, e2)), glm::dot(e1, e2)) * 180.0 / kPi;
      amin[t] = std::min(amin[t], ang);
      amax[t] = std::max(amax[t], ang);
    }
  });
  std::vector<double> sorted;
  sorted.reserve(nt);
  double qsum = 0;
  std::size_t n15 = 0, n2 = 0, n3 = 0;
  r.min_angle_deg = 180.0;
  r.max_angle_deg = 0.0;
  std::vector<BadTriangle> bad;
  for (std::size_t t = 0; t < nt; ++t) {
    if (Q[t] < 0) continue;
    const double q = Q[t];
    sorted.push_back(q);
    qsum += 1.0 / q;
    r.flat += std::isinf(q);
    n15 += q < 1.5;
    n2 += q < 2.0;
    n3 += q < 3.0;
    r.min_angle_deg = std::min(r.min_angle_deg, amin[t]);
    r.max_angle_deg = std::max(r.max_angle_deg, amax[t]);
    if (q >= 3.0) {
      bool corner = false;
      if (!m.point_dim.empty())
        for (NodeId i : m.triangles[t]) corner = corner || m.point_dim[i] == 0;
      bool gap = false;
      double width = 0.0;
      if (!corner && narrow_gap > 0 && !m.point_dim.empty()) {
        bool on_edges = true;
        for (NodeId i : m.triangles[t])
          on_edges = on_edges && m.point_dim[i] <= 1 && m.point_dim[i] >= 0;
        if (on_edges) {
          const pred3::Tri c = corners(m, t);
          const double area2 = glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
          const double hmax = std::max(
              {glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
          double floor = narrow_gap;
          if (edge_gap && !m.point_entity.empty()) {
            // The two distinct edges the points lie on with the largest floor between them.
            std::array<double, 3> g{0, 0, 0};
            std::array<geom::Id, 3> e{geom::kNone, geom::kNone, geom::kNone};
            for (int k = 0; k < 3; ++k) {
              const NodeId i = m.triangles[t][k];
              if (m.point_dim[i] != 1) continue;
              e[k] = m.point_entity[i];
              if (e[k] >= 0 && static_cast<std::size_t>(e[k]) < edge_gap->size())
                g[k] = (*edge_gap)[static_cast<std::size_t>(e[k])];
            }
            for (int a = 0; a < 3; ++a)
              for (int b = a + 1; b < 3; ++b)
                if (e[a] != geom::kNone && e[b] != geom::kNone && e[a] != e[b])
                  floor = std::max(floor, g[a] + g[b]);
          }
          width = area2 / hmax;
          gap = area2 < floor * hmax;
        }
      }
      if (corner) {
        ++r.bad_at_corners;
      } else if (gap) {
        ++r.bad_in_narrow_gaps;
        r.widest_narrow_gap = std::max(r.widest_narrow_gap, width);
      } else {
        ++r.bad_away_from_corners;
        bad.push_back({static_cast<TriId>(t), face_of(m, t), q});
      }
    }
  }
  const std::size_t n = sorted.size();
  r.triangles = n;
  if (n == 0) {
    r.min_angle_deg = r.max_angle_deg = 0;
    return r;
  }
  std::sort(sorted.begin(), sorted.end());
  const double dn = static_cast<double>(n);
  r.share_Q_lt_1_5 = n15 / dn;
  r.share_Q_lt_2 = n2 / dn;
  r.share_Q_lt_3 = n3 / dn;
  // Nearest rank; q = 1/Q is decreasing in Q, so q's low percentiles are Q's high ones.
  auto rank = [&](double pct) {
    return std::clamp<std::size_t>(static_cast<std::size_t>(std::ceil(pct / 100.0 * dn)), 1, n);
  };
  auto Qp = [&](double pct) { return sorted[rank(pct) - 1]; };
  auto qp = [&](double pct) { return 1.0 / sorted[n - rank(pct)]; };
  r.q_min = 1.0 / sorted.back();
  r.q_p1 = qp(1);
  r.q_p5 = qp(5);
  r.q_p50 = qp(50);
  r.q_mean = qsum / dn;
  r.Q_p50 = Qp(50);
  r.Q_p95 = Qp(95);
  r.Q_p99 = Qp(99);
  r.Q_max = sorted.back();
  std::sort(bad.begin(), bad.end(), [](const BadTriangle& a, const BadTriangle& b) {
    return a.Q != b.Q ? a.Q > b.Q : a.triangle < b.triangle;
  });
  if (bad.size() > static_cast<std::size_t>(std::max(max_list, 0)))
    bad.resize(std::max(max_list, 0));
  r.bad_list = std::move(bad);
  return r;
}

// =======================================================================================
// 4. Metric edge lengths
// =======================================================================================

EdgeLengthReport measure_edge_lengths(const SurfaceMesh& m,
                                      const std::function<double(NodeId, NodeId)>& metric_length) {
  EdgeLengthReport r;
  constexpr int kBins = 17;
  r.bin_lo.resize(kBins);
  r.bin_count.assign(kBins, 0);
  r.bin_lo[0] = 0.0;
  for (int i = 1; i < kBins; ++i) r.bin_lo[i] = std::exp2((i - 8) / 2.0);

  std::vector<std::pair<NodeId, NodeId>> edges;
  edges.reserve(3 * m.triangles.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (tri_state(m, t) != kValid) continue;
    const auto& tr = m.triangles[t];
    for (int k = 0; k < 3; ++k)
      edges.emplace_back(std::min(tr[k], tr[(k + 1) % 3]), std::max(tr[k], tr[(k + 1) % 3]));
  }
  tbb::parallel_sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  r.edges = edges.size();
  if (edges.empty()) return r;
  const double lo = std::sqrt(0.5), hi = std::sqrt(2.0);
  double sum = 0;
  r.min = std::numeric_limits<double>::infinity();
  r.max = -std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : edges) {
    const double l = metric_length(a, b);
    sum += l;
    r.min = std::min(r.min, l);
    r.max = std::max(r.max, l);
    if (l < lo)
      ++r.short_edges;
    else if (l > hi)
      ++r.long_edges;
    else
      ++r.unit;
    // Bin: the last lower bound <= l (bins 7 and 8 are [2^-1/2, 1) and [1, 2^1/2)).
    const auto it = std::upper_bound(r.bin_lo.begin(), r.bin_lo.end(), l);
    const auto bin = std::max<std::ptrdiff_t>(0, (it - r.bin_lo.begin()) - 1);
    ++r.bin_count[bin];
  }
  r.mean = sum / static_cast<double>(edges.size());
  r.unit_share = static_cast<double>(r.unit) / static_cast<double>(edges.size());
  return r;
}

// =======================================================================================
// 5. Chordal deviation
// =======================================================================================

Projection project_to_surface(const geom::Surface& s, const Vec3& x, Vec2 uv0,
                              const geom::Box2& box, double scale, int max_iter) {
  auto clampuv = [&](Vec2 p) {
    return Vec2(std::clamp(p.x, box.u.lo, box.u.hi), std::clamp(p.y, box.v.lo, box.v.hi));
  };
  Projection out;
  Vec2 uv = clampuv(uv0);
  geom::SurfacePoint e = s.eval(uv.x, uv.y);
  Vec3 r = e.p - x;
  double f = glm::dot(r, r);
  if (!(scale > 0)) scale = std::max(glm::length(x), 1.0);
  const double tol = 1e-10 * scale;

  // Converged: the point is on the surface to within tol, or first-order optimality with
  // the bounds: along every free tangent direction the residual's component is below
  // 1e-6 |r| + tol (the distance is then exact to about 1e-12 relative; the absolute
  // part absorbs the rounding noise of sigma and of tiny residuals).
  auto stationary = [&](const geom::SurfacePoint& ep, const Vec3& res, Vec2 p) {
    const double rl = glm::length(res);
    if (rl <= tol) return true;
    const double gu = glm::dot(ep.du, res), gv = glm::dot(ep.dv, res);
    const bool fu = (p.x <= box.u.lo && gu > 0) || (p.x >= box.u.hi && gu < 0);
    const bool fv = (p.y <= box.v.lo && gv > 0) || (p.y >= box.v.hi && gv < 0);
    const double lim = 1e-6 * rl + tol;
    return (fu || std::fabs(gu) <= lim * glm::length(ep.du)) &&
           (fv || std::fabs(gv) <= lim * glm::length(ep.dv));
  };

  int it = 0;
  bool converged = f <= tol * tol;  // already on the surface
  for (; it < max_iter && !converged; ++it) {
    const double gu = glm::dot(e.du, r), gv = glm::dot(e.dv, r);
    const double E = glm::dot(e.du, e.du), F = glm::dot(e.du, e.dv), G = glm::dot(e.dv, e.dv);
    // Active set: a variable sitting on a bound whose descent direction (-g) points out.
    const bool fixu = (uv.x <= box.u.lo && gu > 0) || (uv.x >= box.u.hi && gu < 0);
    const bool fixv = (uv.y <= box.v.lo && gv > 0) || (uv.y >= box.v.hi && gv < 0);
    if (fixu && fixv) {
      converged = true;
      break;
    }
    // Newton matrix (Hessian of f/2); where it is not positive definite, the first
    // fundamental form with a small Levenberg-Marquardt shift (poles: E = 0).
    double huu = E + glm::dot(e.duu, r), huv = F + glm::dot(e.duv, r), hvv = G + glm::dot(e.dvv, r);
    const double shift = 1e-12 * (E + G) + std::numeric_limits<double>::min();
    const bool pd = huu > 0 && hvv > 0 && huu * hvv - huv * huv > 1e-12 * huu * hvv;
    if (!pd) {
      huu = E + shift;
      huv = F;
      hvv = G + shift;
    }
    Vec2 d(0.0, 0.0);
    if (fixu) {
      d.y = gv / hvv;
    } else if (fixv) {
      d.x = gu / huu;
    } else {
      const double det = huu * hvv - huv * huv;
      if (!(det > 0)) break;
      d = Vec2((hvv * gu - huv * gv) / det, (huu * gv - huv * gu) / det);
    }
    if (!std::isfinite(d.x) || !std::isfinite(d.y)) break;
    // Backtracking: accept the first step that does not increase the distance by more
    // than tol. Near the solution the gain of a Newton step (the square of a tangential
    // residual) drops below the rounding noise of |sigma - x|^2 long before the
    // tangential residual itself is small, so "strictly no increase" would stall there.
    const double accept = (std::sqrt(f) + tol) * (std::sqrt(f) + tol);
    double t = 1.0;
    bool accepted = false;
    Vec2 uvn;
    geom::SurfacePoint en;
    Vec3 rn;
    double fn = f;
    for (int ls = 0; ls < 40; ++ls, t *= 0.5) {
      uvn = clampuv(uv - t * d);
      en = s.eval(uvn.x, uvn.y);
      rn = en.p - x;
      fn = glm::dot(rn, rn);
      if (fn <= accept) {
        accepted = true;
        break;
      }
    }
    if (!accepted) {
      // No decrease along the step: a minimum to rounding, if the gradient says so.
      converged = stationary(e, r, uv);
      break;
    }
    const double moved = glm::length(en.p - e.p);
    uv = uvn;
    e = en;
    r = rn;
    f = fn;
    if (moved <= tol) {
      // A full Newton step this small is convergence; a tiny damped one may be a stall.
      converged = t == 1.0 || stationary(e, r, uv);
      ++it;
      break;
    }
  }
  if (!converged) converged = stationary(e, r, uv);
  out.uv = uv;
  out.point = e.p;
  out.distance = std::sqrt(f);
  out.iterations = it;
  out.converged = converged;
  return out;
}

ChordalReport measure_chordal(const SurfaceMesh& m, const geom::Model& model, int threads) {
  ChordalReport r;
  const std::size_t nf = model.faces.size(), nt = m.triangles.size();
  r.face_max.assign(nf, 0.0);
  const bool have_uv = m.triangle_uv.size() == nt;

  // Triangles of each face, in id order.
  std::vector<std::vector<TriId>> by_face(nf);
  for (std::size_t t = 0; t < nt; ++t) {
    const geom::Id f = face_of(m, t);
    if (!have_uv || f < 0 || static_cast<std::size_t>(f) >= nf || !model.faces[f].surface ||
        tri_state(m, t) == kBadIndex) {
      ++r.skipped_triangles;
      continue;
    }
    by_face[f].push_back(static_cast<TriId>(t));
  }
  // Faces sharing one Surface object must run in the same task.
  std::vector<std::vector<geom::Id>> groups;
  {
    std::map<const geom::Surface*, std::size_t> gi;
    for (std::size_t f = 0; f < nf; ++f) {
      if (by_face[f].empty()) continue;
      const geom::Surface* s = model.faces[f].surface.get();
      auto [it, fresh] = gi.emplace(s, groups.size());
      if (fresh) groups.emplace_back();
      groups[it->second].push_back(static_cast<geom::Id>(f));
    }
  }

  struct FaceResult {
    std::size_t samples = 0, not_converged = 0;
    double sum = 0, max = 0;
    ChordalSample worst;
  };
  std::vector<FaceResult> fr(nf);
  auto run_face = [&](geom::Id f) {
    const geom::Face& face = model.faces[f];
    const geom::Surface& s = *face.surface;
    geom::Box2 box = face.uv_box;
    if (!(box.u.hi > box.u.lo && box.v.hi > box.v.lo)) box = s.bounds();
    if (s.u_periodic() && s.u_period() > 0) {
      box.u.lo -= 0.5 * s.u_period();
      box.u.hi += 0.5 * s.u_period();
    }
    if (s.v_periodic() && s.v_period() > 0) {
      box.v.lo -= 0.5 * s.v_period();
      box.v.hi += 0.5 * s.v_period();
    }
    FaceResult& out = fr[f];
    for (TriId t : by_face[f]) {
      const pred3::Tri c = corners(m, t);
      const auto& uv = m.triangle_uv[t];
      const double h =
          std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
      const Vec3 xs[4] = {(c[0] + c[1] + c[2]) / 3.0, 0.5 * (c[0] + c[1]), 0.5 * (c[1] + c[2]),
                          0.5 * (c[2] + c[0])};
      const Vec2 us[4] = {(uv[0] + uv[1] + uv[2]) / 3.0, 0.5 * (uv[0] + uv[1]),
                          0.5 * (uv[1] + uv[2]), 0.5 * (uv[2] + uv[0])};
      for (int k = 0; k < 4; ++k) {
        const Projection p = project_to_surface(s, xs[k], us[k], box, h);
        ++out.samples;
        out.not_converged += !p.converged;
        out.sum += p.distance;
        if (p.distance > out.max || out.worst.triangle < 0) {
          out.max = std::max(out.max, p.distance);
          out.worst = {t, f, k, xs[k], p.point, p.uv, p.distance};
        }
      }
    }
  };
  tbb::task_arena arena = make_arena(threads);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), groups.size(), [&](std::size_t g) {
      for (geom::Id f : groups[g]) run_face(f);
    });
  });

  // Reduction in face order: deterministic sums and ties (smallest face, then triangle).
  double sum = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    const FaceResult& x = fr[f];
    if (x.samples == 0) continue;
    r.samples += x.samples;
    r.triangles += by_face[f].size();
    r.not_converged += x.not_converged;
    sum += x.sum;
    r.face_max[f] = x.max;
    if (r.worst.triangle < 0 || x.max > r.max ||
        (x.max == r.max && x.worst.triangle < r.worst.triangle)) {
      r.max = x.max;
      r.worst = x.worst;
    }
  }
  r.mean = r.samples ? sum / static_cast<double>(r.samples) : 0.0;
  return r;
}

}  // namespace uvmesh::surface
