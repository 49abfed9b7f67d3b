// Edge sampling in the metric (eq. 7.10), shared by the boundary split and the field
// points (internal).
#pragma once

#include <algorithm>
#include <vector>

#include "mesh_state.h"

namespace uvmesh::m2d::detail {

// One sampler per stage: the vectors are its scratch, reused from edge to edge.
struct EdgeSampler {
  explicit EdgeSampler(MeshState& ms_) : ms(ms_) {}

  // Boundary size ratio at parameter t of an edge whose ends have ratios ra, rb (<= 1):
  // the growth at the gradation rate from the nearer end (the H-correction, eq. 7.11);
  // l is the edge's length in the unscaled metric (Options::boundary_gradation). Not an
  // interpolation between the ends: the first waves' edges cross the whole domain between
  // two boundary vertices, and interpolating would keep the small boundary ratio all the
  // way across (a face bounded by tiny segments everywhere was meshed uniformly fine).
  double ratio_at(double ra, double rb, double t, double l) const {
    const double g = ms.opt.boundary_gradation - 1;
    const double r = std::min({1.0, ra + g * t * l, rb + g * (1 - t) * l});
    return std::max(r, 1e-6);
  }

  // Metric length of the straight edge a -> b (eq. 7.10) by a piecewise-linear rule on a
  // sampling refined until every piece is shorter than kPiece in the metric, so that a
  // size feature between the endpoints (a boundary layer, a ring) is not missed; and the
  // parameters of n - 1 points splitting it in n pieces of equal metric length.
  // ra, rb: the boundary size ratios of the ends (Options::boundary_gradation; ma and mb
  // are already scaled by them). Returns the metric length; the pieces stay in the sampler.
  double sample(Vec2 a, Vec2 b, const Metric2& ma, const Metric2& mb, double ra = 1, double rb = 1);

  // Parameters of the points splitting the sampled edge into n equal metric pieces.
  template <class F>
  void split_params(int n, F&& emit) const {
    const double L = cum.back();
    std::size_t k = 0;
    for (int j = 1; j < n; ++j) {
      const double target = L * j / n;
      while (k + 2 < cum.size() && cum[k + 1] < target) ++k;
      const double f = (target - cum[k]) / std::max(cum[k + 1] - cum[k], 1e-300);
      emit(ts[k] + f * (ts[k + 1] - ts[k]));
    }
  }

  MeshState& ms;
  std::vector<double> ts, len, cum, nts, nl;
};

}  // namespace uvmesh::m2d::detail
