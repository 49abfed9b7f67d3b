// EdgeSampler::sample: the metric length of a straight edge on a piecewise sampling.
#include "edge_sampling.h"

namespace uvmesh::m2d::detail {

namespace {
// Pieces of the sampling are refined until each is shorter than this in the metric.
constexpr double kPiece = 0.25;
}  // namespace

double EdgeSampler::sample(Vec2 a, Vec2 b, const Metric2& ma, const Metric2& mb, double ra,
                           double rb) {
  const Vec2 d{b.x - a.x, b.y - a.y};
  const bool scaled = ra < 1 || rb < 1;
  ts.assign({0.0, 1.0});
  len.assign({detail::length(ma, d), detail::length(mb, d)});
  for (int it = 0; it < 40; ++it) {
    nts.assign(1, 0.0);
    nl.assign(1, len[0]);
    bool split = false;
    for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
      const double piece = (ts[k + 1] - ts[k]) * 0.5 * (len[k] + len[k + 1]);
      if (piece > kPiece && nts.size() < 1'000'000) {
        const double tm = 0.5 * (ts[k] + ts[k + 1]);
        nts.push_back(tm);
        nl.push_back(detail::length(ms.metric(a.x + tm * d.x, a.y + tm * d.y), d));
        split = true;
      }
      nts.push_back(ts[k + 1]);
      nl.push_back(len[k + 1]);
    }
    ts.swap(nts);
    len.swap(nl);
    if (!split) break;
  }
  if (scaled) {
    // The boundary scale is known in closed form (ratio_at), so it needs no field
    // evaluations: the field's lengths are interpolated on the pieces, divided by the
    // ratio, and pieces are split until each is short in the scaled metric too.
    const double lu = 0.5 * (len.front() * ra + len.back() * rb);
    // The metrics at the ends (ma, mb) are already scaled: undo it so that all samples are field
    // lengths.
    len.front() *= ra;
    len.back() *= rb;
    for (int it = 0; it < 40; ++it) {
      nts.assign(1, 0.0);
      nl.assign(1, len[0]);
      bool split = false;
      for (std::size_t k = 0; k + 1 < ts.size(); ++k) {
        const double t0 = ts[k], t1 = ts[k + 1];
        const double piece =
            (t1 - t0) * 0.5 *
            (len[k] / ratio_at(ra, rb, t0, lu) + len[k + 1] / ratio_at(ra, rb, t1, lu));
        if (piece > kPiece && nts.size() < 1'000'000) {
          nts.push_back(0.5 * (t0 + t1));
          nl.push_back(0.5 * (len[k] + len[k + 1]));
          split = true;
        }
        nts.push_back(t1);
        nl.push_back(len[k + 1]);
      }
      ts.swap(nts);
      len.swap(nl);
      if (!split) break;
    }
    for (std::size_t k = 0; k < ts.size(); ++k) len[k] /= ratio_at(ra, rb, ts[k], lu);
  }
  cum.assign(ts.size(), 0.0);
  for (std::size_t k = 1; k < ts.size(); ++k)
    cum[k] = cum[k - 1] + (ts[k] - ts[k - 1]) * 0.5 * (len[k - 1] + len[k]);
  return cum.back();
}

}  // namespace uvmesh::m2d::detail
