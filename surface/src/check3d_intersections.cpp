// 3D checks of a SurfaceMesh, part 2: self-intersections (see check3d.h for the rules).
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

#include "check3d_internal.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface {

using geom::Vec2;
using geom::Vec3;
using namespace check3d_impl;

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

namespace {

// Each valid, non-degenerate triangle's box (ok[t] = 1); the rest counted as skipped.
struct TriangleBoxes {
  std::vector<Aabb> boxes;
  std::vector<char> ok;
};
TriangleBoxes triangle_boxes(const SurfaceMesh& m, IntersectionReport& r) {
  const std::size_t nt = m.triangles.size();
  TriangleBoxes b{std::vector<Aabb>(nt), std::vector<char>(nt, 0)};
  tbb::parallel_for(std::size_t(0), nt, [&](std::size_t t) {
    if (tri_state(m, t) != kValid) return;
    const pred3::Tri c = corners(m, t);
    if (pred3::projection_axis(c) < 0) return;
    b.ok[t] = 1;
    b.boxes[t] = {glm::min(c[0], glm::min(c[1], c[2])), glm::max(c[0], glm::max(c[1], c[2]))};
  });
  for (std::size_t t = 0; t < nt; ++t) r.skipped_degenerate += !b.ok[t];
  return b;
}

// A thread's share of the pair tests: counts and the first pairs that intersect.
struct PairTests {
  const SurfaceMesh* m;
  std::size_t candidates = 0, hits = 0;
  SmallestK<std::pair<TriId, TriId>> first;
  PairTests(const SurfaceMesh* mesh, std::size_t k) : m(mesh), first(k) {}
  void operator()(TriId t, TriId u) {
    ++candidates;
    PairKind kind;
    if (pair_intersects(*m, t, u, kind)) {
      ++hits;
      first.push({t, u});
    }
  }
};

void add_pairs(const SurfaceMesh& m, tbb::enumerable_thread_specific<PairTests>& tls,
               std::size_t cap, IntersectionReport& r) {
  SmallestK<std::pair<TriId, TriId>> first(cap);
  for (PairTests& L : tls) {
    r.candidate_pairs += L.candidates;
    r.intersecting_pairs += L.hits;
    first.merge(L.first);
  }
  for (const auto& [a, b] : first.sorted())
    r.pairs.push_back(
        {a, b, face_of(m, a), face_of(m, b), pair_kind(m.triangles[a], m.triangles[b])});
}

// The items of `bvh` whose boxes overlap `box`.
template <class F>
void for_each_overlapping_item(const Bvh& bvh, const Aabb& box, F&& f) {
  const auto& nodes = bvh.nodes();
  if (nodes.empty()) return;
  std::int32_t stack[64];
  int top = 0;
  stack[top++] = 0;
  while (top > 0) {
    const Bvh::Node& n = nodes[stack[--top]];
    if (!n.box.overlaps(box)) continue;
    if (n.count > 0) {
      for (std::int32_t i = n.first; i < n.first + n.count; ++i)
        if (bvh.item_boxes()[i].overlaps(box)) f(bvh.items()[i]);
      continue;
    }
    // Balanced median splits: depth at most log2(2^31 / kLeaf) < 64.
    stack[top++] = n.right;
    stack[top++] = static_cast<std::int32_t>(&n - nodes.data()) + 1;
  }
}

}  // namespace

IntersectionReport find_self_intersections(const SurfaceMesh& m, int max_report, int threads) {
  IntersectionReport r;
  const std::size_t nt = m.triangles.size();
  r.triangles = nt;
  if (nt == 0) return r;
  tbb::task_arena arena = make_arena(threads);
  arena.execute([&] {
    const TriangleBoxes tb = triangle_boxes(m, r);
    std::vector<TriId> items;
    items.reserve(nt);
    for (std::size_t t = 0; t < nt; ++t)
      if (tb.ok[t]) items.push_back(static_cast<TriId>(t));
    const Bvh bvh(tb.boxes, std::move(items));
    const std::size_t cap = static_cast<std::size_t>(std::max(max_report, 0));
    tbb::enumerable_thread_specific<PairTests> tls([&m, cap] { return PairTests(&m, cap); });
    for_each_overlapping_pair(bvh, [&]() -> PairTests& { return tls.local(); });
    add_pairs(m, tls, cap, r);
  });
  return r;
}

IntersectionReport find_intersections_with(const SurfaceMesh& m, const std::vector<char>& subset,
                                           int max_report, int threads) {
  IntersectionReport r;
  const std::size_t nt = m.triangles.size();
  r.triangles = nt;
  if (nt == 0) return r;
  auto in_subset = [&](std::size_t t) { return t < subset.size() && subset[t]; };
  tbb::task_arena arena = make_arena(threads);
  arena.execute([&] {
    const TriangleBoxes tb = triangle_boxes(m, r);
    // A tree over the subset only: the rest of the mesh queries it box by box.
    std::vector<TriId> items;
    for (std::size_t t = 0; t < nt; ++t)
      if (tb.ok[t] && in_subset(t)) items.push_back(static_cast<TriId>(t));
    const Bvh bvh(tb.boxes, std::move(items));
    const std::size_t cap = static_cast<std::size_t>(std::max(max_report, 0));
    tbb::enumerable_thread_specific<PairTests> tls([&m, cap] { return PairTests(&m, cap); });
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, nt, 1024),
                      [&](const tbb::blocked_range<std::size_t>& rg) {
                        PairTests& L = tls.local();
                        for (std::size_t t = rg.begin(); t < rg.end(); ++t) {
                          if (!tb.ok[t]) continue;
                          const auto ti = static_cast<TriId>(t);
                          // Two of the subset: once, from the lower index.
                          for_each_overlapping_item(bvh, tb.boxes[t], [&](TriId u) {
                            if (u != ti && !(in_subset(t) && u < ti))
                              L(std::min(ti, u), std::max(ti, u));
                          });
                        }
                      });
    add_pairs(m, tls, cap, r);
  });
  return r;
}

}  // namespace uvmesh::surface
