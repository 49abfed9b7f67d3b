// The optimization stage of mesher2d (§7.3.6, §7.5.2) and its scratch (internal).
//
// One Optimizer runs the whole stage (optimize_mesh): its methods are spread over
// optimize.cpp (the passes and their order), relocation.cpp (relocation of one vertex in
// its ball) and repair.cpp (the targeted repair and the size pass), which share the
// ball and ring scratch below.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "mesh_state.h"
#include "uvmesh/mesher2d/measures.h"

namespace uvmesh::m2d::detail {

// 1 / Q_K (eq. 7.6) = rho / (alpha hmax): 1 for the equilateral, 0 for flat.
inline double q_inv(Vec2 a, Vec2 b, Vec2 c) {
  const double ab2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
  const double bc2 = (c.x - b.x) * (c.x - b.x) + (c.y - b.y) * (c.y - b.y);
  const double ca2 = (a.x - c.x) * (a.x - c.x) + (a.y - c.y) * (a.y - c.y);
  const double area2 = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
  if (!(area2 > 0)) return area2 == 0 ? 0.0 : -1.0;
  // sqrt is correctly rounded and monotone: the longest edge's length is the largest of
  // the three roots, bit for bit what sqrt(max(ab2, bc2, ca2)) gave, one sqrt fewer.
  const double ab = std::sqrt(ab2), bc = std::sqrt(bc2), ca = std::sqrt(ca2);
  return measures::shape_q(ab, bc, ca, area2);
}

class Optimizer {
 public:
  explicit Optimizer(MeshState& ms_) : ms(ms_) {}
  void run();

 private:
  // ---- optimize.cpp: the passes
  std::int64_t swap_pass();
  std::int64_t swap_pass_varying();
  Metric2 quad_metric(VertId a, VertId b, VertId c, VertId d) const;
  std::int64_t smooth_pass();
  std::int64_t maxmin_pass(double qstop, int iters);
  std::int64_t valence_pass();

  // ---- relocation.cpp: one vertex in its ball
  bool gather_ring(VertId v, std::vector<VertId>& ring) const;
  // The ball is the ring loaded by load_ring; valid positions keep every triangle
  // (p, vring[k], vring[k+1]) counter-clockwise, p in the frame vf (ball_valid).
  double maxmin_core(Vec2& p, double qstop, int iters, const MetricFrame& vf,
                     const std::vector<VertId>& vring);
  bool pnorm_core(Vec2& p, const MetricFrame& vf, const std::vector<VertId>& vring);
  bool pnorm_relocate(VertId v, std::vector<VertId>& ring);
  bool ball_valid(const MetricFrame& f, Vec2 fp, const std::vector<VertId>& ring) const;
  void load_ring(const MetricFrame& f, const std::vector<VertId>& ring, const Metric2& mv);
  void set_position(VertId v, Vec2 q);
  bool maxmin_relocate(VertId v, std::vector<VertId>& ring, double qstop, int iters);

  // ---- repair.cpp: targeted repair and size pass
  double ball_min(VertId v, const std::vector<VertId>& ring) const;
  bool has_constrained_edge(VertId v) const;
  bool try_swap(TriId t);
  bool try_collapse(TriId t);
  bool collapse_into(VertId v, VertId u, double floor, bool size_check);
  bool try_split(TriId t);
  bool split_at(std::int32_t h, double floor, bool size_check);
  double q_of_point(Vec2 p, const Metric2& mp, VertId a, VertId b) const;
  Metric2 point_metric(Vec2 p, double r);
  double true_len(Vec2 p, const Metric2& mp, double rp, VertId w);
  double rank_len2(VertId a, VertId b) const;
  void touch_around(TriId t, std::vector<VertId>& out) const;
  void bad_in_balls(const std::vector<VertId>& vs, double q, std::vector<TriId>& out);
  std::vector<VertId> targeted_pass(double qstop, int rounds);
  void repair(double qbad, int rounds, const std::vector<VertId>* first = nullptr);
  std::int64_t size_pass(double floor);

  // ---- small measures, inline (the innermost operations of the passes)
  // §7.3.6 / §7.5.2 optimizations: topological (edge swaps judged by the metric quality)
  // then metric (vertex relocation toward the ideal point of its ball), boundary fixed.
  double quality_in(const Metric2& m, Vec2 a, Vec2 b, Vec2 c) const {
    if (iso_uniform_) return q_inv(a, b, c);
    const detail::MetricFrame f(m);
    return q_inv(f(a), f(b), f(c));
  }

  double tri_q(VertId a, VertId b, VertId c) const {
    const auto& P = ms.tri.points();
    if (iso_uniform_) return q_inv(P[a], P[b], P[c]);
    const detail::MetricFrame f(detail::mean3(ms.vm[a], ms.vm[b], ms.vm[c]));
    return q_inv(f(P[a]), f(P[b]), f(P[c]));
  }

  double tri_q(TriId t) const {
    return tri_q(ms.tri.vertex(t, 0), ms.tri.vertex(t, 1), ms.tri.vertex(t, 2));
  }

  // A topological change is taken when the worst 1/Q_K of the triangles it makes beats
  // that of the triangles it replaces, or (floor > 0: the size pass) stays >= floor.
  static bool accept_q(double q_new, double q_old, double floor) {
    return q_new > q_old * (1 + 1e-9) || (floor > 0 && q_new >= floor);
  }

  // Frame of vertex v's metric (identity for a uniform field) and the exact validity of
  // a ball (p, ring[k], ring[k+1]) with p given in that frame.
  detail::MetricFrame frame_of(VertId v) const {
    return detail::MetricFrame(iso_uniform_ ? Metric2{} : ms.vm[v]);
  }

  // Triangle k of the loaded ball with its free vertex at pp (ball frame): its three
  // corners in the frame the triangle is judged in.
  void ball_tri(std::size_t k, Vec2 pp, Vec2& a, Vec2& b, Vec2& p) const {
    if (multi_frame_) {
      const BallTri& t = bt_[k];
      a = t.a, b = t.b, p = {t.a11 * pp.x + t.a12 * pp.y, t.a22 * pp.y};
      return;
    }
    const std::size_t n = fr_.size();
    a = fr_[k], b = fr_[k + 1 == n ? 0 : k + 1], p = pp;
  }

  // A gradient in triangle k's frame, as a gradient in the ball frame (A^T g).
  Vec2 ball_grad(std::size_t k, Vec2 g) const {
    if (!multi_frame_) return g;
    const BallTri& t = bt_[k];
    return {t.a11 * g.x, t.a12 * g.x + t.a22 * g.y};
  }

  MeshState& ms;
  bool iso_uniform_ = false;   // uniform field: Euclidean frames, no metric updates
  bool multi_frame_ = false;   // the field varies: each ball triangle in its own frame
  std::vector<Vec2> fr_, gk_;  // maxmin_relocate scratch: ring in the frame, gradients
  struct BallTri {
    double a11, a12, a22;  // ball frame -> this triangle's frame (upper triangular)
    Vec2 a, b;             // its ring edge in its frame
  };
  std::vector<BallTri> bt_;                           // per-triangle frames (multi_frame_)
  std::vector<double> tq_;                            // swap_pass_varying: 1/Q_K per triangle
  std::vector<double> qk_;                            // maxmin_core: 1/Q_K per ball triangle
  std::vector<VertId> rv_, ru_, merged_, nbr_, srt_;  // repair scratch: rings
  std::vector<std::pair<VertId, Vec2>> saved_;
  std::vector<std::pair<VertId, VertId>> absorbed_;
  std::int64_t work_ = 0;             // triangle evaluations of maxmin_core / pnorm_core
  std::vector<std::uint32_t> tmark_;  // bad_in_balls: triangle marks
  std::uint32_t tepoch_ = 0;
};

}  // namespace uvmesh::m2d::detail
