// Quality and size measures (reference chapter eq. 7.6-7.7 for shape, eq. 7.10 for size).
#include <algorithm>
#include <cmath>
#include <limits>
#include <unordered_set>

#include "metric_util.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::m2d {

namespace {
constexpr double kPi = 3.14159265358979323846;

struct Shape {
  double q;           // Q_K
  double cmin, cmax;  // cosines of the largest and the smallest angle
};

// Shape of abc with square roots only (no hypot, no acos: the extreme angles of a mesh
// are taken from the extreme cosines once at the end).
Shape shape(Vec2 a, Vec2 b, Vec2 c) {
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y, wx = a.x - c.x,
               wy = a.y - c.y;
  const double ab2 = ux * ux + uy * uy, bc2 = vx * vx + vy * vy, ca2 = wx * wx + wy * wy;
  const double ab = std::sqrt(ab2), bc = std::sqrt(bc2), ca = std::sqrt(ca2);
  const double area2 = ux * (c.y - a.y) - uy * (c.x - a.x);
  if (!(area2 > 0)) return {std::numeric_limits<double>::infinity(), -1, 1};
  Shape s;
  s.q = measures::shape_Q(ab, bc, ca, area2);
  // cos at a = -(u.w)/(|u||w|), at b = -(u.v)/(|u||v|), at c = -(v.w)/(|v||w|)
  const double ca_ = -(ux * wx + uy * wy) / (ab * ca);
  const double cb_ = -(ux * vx + uy * vy) / (ab * bc);
  const double cc_ = -(vx * wx + vy * wy) / (bc * ca);
  s.cmin = std::min({ca_, cb_, cc_});
  s.cmax = std::max({ca_, cb_, cc_});
  return s;
}
double deg(double cosine) {
  return std::acos(std::clamp(cosine, -1.0, 1.0)) * 180.0 / kPi;
}
}  // namespace

double triangle_quality(Vec2 a, Vec2 b, Vec2 c, const Metric2& m) {
  const detail::MetricFrame f(m);
  return shape(f(a), f(b), f(c)).q;
}

Quality measure(const std::vector<Vec2>& vertices, const std::vector<std::array<VertId, 3>>& tris,
                const SizeSpec& size) {
  return detail::measure_with_edges(vertices, tris, size, nullptr);
}

namespace detail {

namespace {

// Running shape measures of a triangle set: the largest and summed Q_K, the counts under
// 1.5 and 2, and the extreme angle cosines.
struct ShapeSums {
  double q_max = 0, qsum = 0;
  std::int64_t n15 = 0, n2 = 0;
  double cmax = -1, cmin = 1;
};

// The Euclidean shape of abc as shape() computes it, with one division per triangle: the
// extreme cosines are compared as cross-multiplied fractions and divided out only when
// they beat the running extreme (a million-triangle mesh has a few such).
void add_euclidean_shape(ShapeSums& e, Vec2 a, Vec2 b, Vec2 c) {
  const double ux = b.x - a.x, uy = b.y - a.y, vx = c.x - b.x, vy = c.y - b.y, wx = a.x - c.x,
               wy = a.y - c.y;
  const double ab = std::sqrt(ux * ux + uy * uy), bc = std::sqrt(vx * vx + vy * vy),
               ca = std::sqrt(wx * wx + wy * wy);
  const double area2 = ux * (c.y - a.y) - uy * (c.x - a.x);
  if (!(area2 > 0)) {
    e.q_max = std::numeric_limits<double>::infinity();
    e.qsum = std::numeric_limits<double>::infinity();
    e.cmax = 1, e.cmin = -1;
    return;
  }
  const double q = measures::shape_Q(ab, bc, ca, area2);
  e.q_max = std::max(e.q_max, q);
  e.qsum += q;
  e.n15 += q < 1.5;
  e.n2 += q < 2;
  // cos at a = -(u.w)/(|u||w|), at b = -(u.v)/(|u||v|), at c = -(v.w)/(|v||w|)
  const double na = -(ux * wx + uy * wy), da = ab * ca;
  const double nb = -(ux * vx + uy * vy), db = ab * bc;
  const double nc = -(vx * wx + vy * wy), dc = bc * ca;
  if (na > e.cmax * da) e.cmax = std::max(e.cmax, na / da);
  if (nb > e.cmax * db) e.cmax = std::max(e.cmax, nb / db);
  if (nc > e.cmax * dc) e.cmax = std::max(e.cmax, nc / dc);
  if (na < e.cmin * da) e.cmin = std::min(e.cmin, na / da);
  if (nb < e.cmin * db) e.cmin = std::min(e.cmin, nb / db);
  if (nc < e.cmin * dc) e.cmin = std::min(e.cmin, nc / dc);
}

// Shape in the metric: the mean of the vertex metrics (a convex combination of SPD
// tensors is SPD) stands for the metric over K.
void add_metric_shape(ShapeSums& s, Vec2 a, Vec2 b, Vec2 c, const Metric2& ma, const Metric2& mb,
                      const Metric2& mc) {
  const detail::MetricFrame f(detail::mean3(ma, mb, mc));
  const Shape ms = shape(f(a), f(b), f(c));
  s.q_max = std::max(s.q_max, ms.q);
  s.qsum += ms.q;
  s.n15 += ms.q < 1.5;
  s.n2 += ms.q < 2;
  s.cmax = std::max(s.cmax, ms.cmax);
  s.cmin = std::min(s.cmin, ms.cmin);
}

// Unit-edge share and edge lengths: every undirected edge once, length in the metric by
// eq. 7.10 with Simpson's rule on the true field (endpoints and midpoint). known_edges:
// every undirected edge once, given by a caller that has the adjacency (else found here).
void measure_edges(Quality& out, const std::vector<Vec2>& vertices,
                   const std::vector<std::array<VertId, 3>>& tris, const SizeSpec& size,
                   const std::vector<Metric2>& vm, const Metric2& m_uniform,
                   const std::vector<std::uint64_t>* known_edges) {
  std::vector<std::uint64_t> own;
  if (!known_edges) {
    own.reserve(tris.size() * 3);
    for (const auto& t : tris)
      for (int i = 0; i < 3; ++i) {
        std::uint64_t a = static_cast<std::uint32_t>(t[i]),
                      b = static_cast<std::uint32_t>(t[(i + 1) % 3]);
        if (a > b) std::swap(a, b);
        own.push_back(a << 32 | b);
      }
    std::sort(own.begin(), own.end());
    own.erase(std::unique(own.begin(), own.end()), own.end());
  }
  const std::vector<std::uint64_t>& edges = known_edges ? *known_edges : own;
  std::int64_t unit = 0;
  double lsum = 0;
  out.edge_len_min = std::numeric_limits<double>::infinity();
  for (const std::uint64_t e : edges) {
    const VertId a = static_cast<VertId>(e >> 32), b = static_cast<VertId>(e & 0xFFFFFFFFu);
    const Vec2 pa = vertices[a], pb = vertices[b];
    const Vec2 d{pb.x - pa.x, pb.y - pa.y};
    // (A uniform field: one length, the rule is exact.)
    const double l =
        size.kind == SizeSpec::Kind::Uniform
            ? detail::length(m_uniform, d)
            : measures::edge_length(
                  detail::length(vm[a], d),
                  detail::length(detail::metric_at(size, 0.5 * (pa.x + pb.x), 0.5 * (pa.y + pb.y)),
                                 d),
                  detail::length(vm[b], d));
    unit += measures::is_unit(l);
    lsum += l;
    out.edge_len_min = std::min(out.edge_len_min, l);
    out.edge_len_max = std::max(out.edge_len_max, l);
  }
  out.edges = static_cast<std::int64_t>(edges.size());
  out.unit_edge_share = static_cast<double>(unit) / static_cast<double>(edges.size());
  out.edge_len_mean = lsum / static_cast<double>(edges.size());
}

}  // namespace

Quality measure_with_edges(const std::vector<Vec2>& vertices,
                           const std::vector<std::array<VertId, 3>>& tris, const SizeSpec& size,
                           std::vector<std::uint64_t>* known_edges) {
  Quality out;
  if (tris.empty()) return out;
  const bool has_metric = !(size.kind == SizeSpec::Kind::Uniform && size.h <= 0);
  std::vector<Metric2> vm;
  // A uniform field has one metric: no per-vertex copy (half a million on a 1e6 mesh).
  const Metric2 m_uniform = size.kind == SizeSpec::Kind::Uniform && has_metric
                                ? detail::metric_at(size, 0, 0)
                                : Metric2{};
  if (has_metric && size.kind != SizeSpec::Kind::Uniform) {
    vm.resize(vertices.size());
    for (std::size_t i = 0; i < vertices.size(); ++i)
      vm[i] = detail::metric_at(size, vertices[i].x, vertices[i].y);
  }
  ShapeSums e, ms;  // Euclidean and metric
  // A uniform field's metric is a scaling: the shape in it is the Euclidean one.
  const bool metric_shapes = has_metric && size.kind != SizeSpec::Kind::Uniform;
  for (const auto& t : tris) {
    const Vec2 a = vertices[t[0]], b = vertices[t[1]], c = vertices[t[2]];
    add_euclidean_shape(e, a, b, c);
    if (metric_shapes) add_metric_shape(ms, a, b, c, vm[t[0]], vm[t[1]], vm[t[2]]);
  }
  out.q_max = e.q_max;
  out.metric_q_max = ms.q_max;
  if (has_metric && !metric_shapes) ms = e;
  const double nt = static_cast<double>(tris.size());
  out.min_angle_deg = deg(e.cmax);
  out.max_angle_deg = deg(e.cmin);
  out.metric_min_angle_deg = deg(ms.cmax);
  out.metric_max_angle_deg = deg(ms.cmin);
  out.q_mean = e.qsum / nt;
  out.share_q_below_1_5 = e.n15 / nt;
  out.share_q_below_2 = e.n2 / nt;
  if (!has_metric) {
    out.metric_q_max = out.q_max;
    out.metric_q_mean = out.q_mean;
    out.metric_share_q_below_1_5 = out.share_q_below_1_5;
    out.metric_share_q_below_2 = out.share_q_below_2;
    out.metric_min_angle_deg = out.min_angle_deg;
    out.metric_max_angle_deg = out.max_angle_deg;
    return out;
  }
  out.metric_q_max = ms.q_max;
  out.metric_q_mean = ms.qsum / nt;
  out.metric_share_q_below_1_5 = ms.n15 / nt;
  out.metric_share_q_below_2 = ms.n2 / nt;
  measure_edges(out, vertices, tris, size, vm, m_uniform, known_edges);
  return out;
}

}  // namespace detail

}  // namespace uvmesh::m2d
