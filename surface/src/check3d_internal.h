// Helpers shared by the files that implement check3d.h (check3d.cpp: topology,
// check3d_intersections.cpp, check3d_quality.cpp: shape and edge lengths,
// check3d_chordal.cpp). Not installed.
#pragma once

#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <queue>
#include <vector>

#include "predicates3d.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface::check3d_impl {

using geom::Vec2;
using geom::Vec3;

inline constexpr double kPi = 3.14159265358979323846;

// Arena of `threads` workers (0: TBB's default, all cores).
inline tbb::task_arena make_arena(int threads) {
  return threads > 0 ? tbb::task_arena(threads) : tbb::task_arena();
}

// Where a triangle's chordal deviation is measured (measure_chordal, and the simplify
// stage holding the tolerance): its centroid and edge midpoints, with the matching (u,v)
// as the seeds of their projections onto its face.
struct ChordalSamples {
  Vec3 x[4];
  Vec2 uv[4];
};
inline ChordalSamples chordal_samples(const std::array<Vec3, 3>& c, const std::array<Vec2, 3>& uv) {
  return {
      {(c[0] + c[1] + c[2]) / 3.0, 0.5 * (c[0] + c[1]), 0.5 * (c[1] + c[2]), 0.5 * (c[2] + c[0])},
      {(uv[0] + uv[1] + uv[2]) / 3.0, 0.5 * (uv[0] + uv[1]), 0.5 * (uv[1] + uv[2]),
       0.5 * (uv[2] + uv[0])}};
}

enum TriState : std::int8_t { kValid = 0, kBadIndex = 1, kRepeated = 2 };

inline TriState tri_state(const SurfaceMesh& m, std::size_t t) {
  const auto& tr = m.triangles[t];
  const auto n = static_cast<NodeId>(m.points.size());
  for (NodeId i : tr)
    if (i < 0 || i >= n) return kBadIndex;
  if (tr[0] == tr[1] || tr[1] == tr[2] || tr[2] == tr[0]) return kRepeated;
  return kValid;
}

inline pred3::Tri corners(const SurfaceMesh& m, std::size_t t) {
  const auto& tr = m.triangles[t];
  return {m.points[tr[0]], m.points[tr[1]], m.points[tr[2]]};
}

inline geom::Id face_of(const SurfaceMesh& m, std::size_t t) {
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

}  // namespace uvmesh::surface::check3d_impl
