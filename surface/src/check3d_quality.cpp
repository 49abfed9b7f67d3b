// 3D measures of a SurfaceMesh, parts 3 and 4: shape quality and metric edge lengths
// (see check3d.h for the definitions).
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
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface {

using geom::Vec2;
using geom::Vec3;
using namespace check3d_impl;

// =======================================================================================
// 3. Shape quality
// =======================================================================================

double triangle_Q(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = glm::length(b - a), bc = glm::length(c - b), ca = glm::length(a - c);
  const double area2 = glm::length(glm::cross(b - a, c - a));  // twice the area
  if (!(area2 > 0)) return std::numeric_limits<double>::infinity();
  return measures::shape_Q(ab, bc, ca, area2);
}

namespace {

// Corner angle of each face at each model vertex its triangles touch: the sum of the
// triangles' angles there (a fan of the face around the vertex spans the CAD corner).
// Keyed by (node, face), sorted.
std::map<std::pair<NodeId, geom::Id>, double> corner_angles(const SurfaceMesh& m,
                                                            const std::vector<double>& Q) {
  std::map<std::pair<NodeId, geom::Id>, double> a;
  if (m.point_dim.empty()) return a;
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    if (Q[t] < 0) continue;
    const pred3::Tri c = corners(m, t);
    for (int k = 0; k < 3; ++k) {
      const NodeId i = m.triangles[t][k];
      if (m.point_dim[i] != 0) continue;
      const Vec3 e1 = c[(k + 1) % 3] - c[k], e2 = c[(k + 2) % 3] - c[k];
      a[{i, face_of(m, t)}] +=
          std::atan2(glm::length(glm::cross(e1, e2)), glm::dot(e1, e2)) * 180.0 / kPi;
    }
  }
  return a;
}

// The smallest corner angle of triangle t's face at the model vertices it touches
// (360 when it touches none).
double corner_angle_of(const SurfaceMesh& m, std::size_t t,
                       const std::map<std::pair<NodeId, geom::Id>, double>& angles) {
  double best = 360.0;
  for (NodeId i : m.triangles[t])
    if (m.point_dim[i] == 0)
      if (auto it = angles.find({i, face_of(m, t)}); it != angles.end())
        best = std::min(best, it->second);
  return best;
}

// A bad triangle away from corners spanning a gap of its face narrower than narrow_gap
// (or than its two edges' tolerance floor): all points on model edges or vertices, width
// (twice the area over the longest side) below the floor. Sets `width`.
bool in_narrow_gap(const SurfaceMesh& m, std::size_t t, double narrow_gap,
                   const std::vector<double>* edge_gap, double& width) {
  if (!(narrow_gap > 0) || m.point_dim.empty()) return false;
  bool gap = false;
  bool on_edges = true;
  for (NodeId i : m.triangles[t]) on_edges = on_edges && m.point_dim[i] <= 1 && m.point_dim[i] >= 0;
  if (on_edges) {
    const pred3::Tri c = corners(m, t);
    const double area2 = glm::length(glm::cross(c[1] - c[0], c[2] - c[0]));
    const double hmax =
        std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
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
  return gap;
}

}  // namespace

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
  const auto angles = corner_angles(m, Q);
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
    r.Q_over_10 += q > 10.0;
    if (q >= 3.0) {
      bool corner = false;
      if (!m.point_dim.empty())
        for (NodeId i : m.triangles[t]) corner = corner || m.point_dim[i] == 0;
      double width = 0.0;
      const bool gap = !corner && in_narrow_gap(m, t, narrow_gap, edge_gap, width);
      if (corner) {
        ++r.bad_at_corners;
        const double angle = corner_angle_of(m, t, angles);
        r.smallest_corner_deg = std::min(r.smallest_corner_deg, angle);
        r.bad_at_acute_corners += angle < kAcuteCornerDeg;
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
  measures::UnitEdges u;
  double sum = 0;
  r.min = std::numeric_limits<double>::infinity();
  r.max = -std::numeric_limits<double>::infinity();
  for (const auto& [a, b] : edges) {
    const double l = metric_length(a, b);
    sum += l;
    r.min = std::min(r.min, l);
    r.max = std::max(r.max, l);
    u.add(l);
    // Bin: the last lower bound <= l (bins 7 and 8 are [2^-1/2, 1) and [1, 2^1/2)).
    const auto it = std::upper_bound(r.bin_lo.begin(), r.bin_lo.end(), l);
    const auto bin = std::max<std::ptrdiff_t>(0, (it - r.bin_lo.begin()) - 1);
    ++r.bin_count[bin];
  }
  r.mean = sum / static_cast<double>(edges.size());
  r.unit = static_cast<std::size_t>(u.unit);
  r.short_edges = static_cast<std::size_t>(u.short_edges);
  r.long_edges = static_cast<std::size_t>(u.long_edges);
  r.unit_share = u.share();
  return r;
}

}  // namespace uvmesh::surface
