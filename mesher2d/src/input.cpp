// Stage 1 of mesher2d: the input checked, exact duplicates merged, segment records built.
#include <algorithm>
#include <cmath>
#include <unordered_set>

#include "mesh_state.h"

namespace uvmesh::m2d::detail {

namespace {
// Coordinates beyond this magnitude could overflow the exact predicates' products.
constexpr double kMaxCoord = 1e100;
}  // namespace

bool validate_input(MeshState& ms) {
  const std::size_t n = ms.in.points.size();
  if (n == 0) return ms.fail(StatusCode::InvalidInput, "empty PSLG: no points");
  if (!ms.in.point_markers.empty() && ms.in.point_markers.size() != n)
    return ms.fail(StatusCode::InvalidInput, "point_markers has " +
                                                 std::to_string(ms.in.point_markers.size()) +
                                                 " entries for " + std::to_string(n) + " points");
  auto bad = [](Vec2 p) {
    return !std::isfinite(p.x) || !std::isfinite(p.y) || std::abs(p.x) > kMaxCoord ||
           std::abs(p.y) > kMaxCoord;
  };
  for (std::size_t i = 0; i < n; ++i)
    if (bad(ms.in.points[i]))
      return ms.fail(StatusCode::InvalidInput,
                     "point " + std::to_string(i) +
                         " has a non-finite or out-of-range coordinate " + fmt_pt(ms.in.points[i]),
                     {static_cast<std::int64_t>(i)});
  for (std::size_t i = 0; i < ms.in.segments.size(); ++i) {
    const auto& s = ms.in.segments[i];
    for (VertId v : {s.a, s.b})
      if (v < 0 || static_cast<std::size_t>(v) >= n)
        return ms.fail(StatusCode::InvalidInput,
                       "segment " + std::to_string(i) + " references point " + std::to_string(v) +
                           ", but there are " + std::to_string(n) + " points",
                       {static_cast<std::int64_t>(i)});
  }
  for (std::size_t i = 0; i < ms.in.holes.size(); ++i)
    if (bad(ms.in.holes[i]))
      return ms.fail(StatusCode::InvalidInput,
                     "hole " + std::to_string(i) + " has a non-finite coordinate",
                     {static_cast<std::int64_t>(i)});
  for (std::size_t i = 0; i < ms.in.regions.size(); ++i)
    if (bad(ms.in.regions[i].seed) || !std::isfinite(ms.in.regions[i].attribute))
      return ms.fail(StatusCode::InvalidInput,
                     "region " + std::to_string(i) + " has a non-finite value",
                     {static_cast<std::int64_t>(i)});
  switch (ms.size.kind) {
    case SizeSpec::Kind::Uniform:
      if (!std::isfinite(ms.size.h))
        return ms.fail(StatusCode::InvalidInput, "uniform size is not finite");
      break;
    case SizeSpec::Kind::Scalar:
      if (!ms.size.size)
        return ms.fail(StatusCode::InvalidInput, "scalar size field without a function");
      break;
    case SizeSpec::Kind::Metric:
      if (!ms.size.metric)
        return ms.fail(StatusCode::InvalidInput, "metric size field without a function");
      break;
  }
  if (!(ms.opt.max_anisotropy >= 1))
    return ms.fail(StatusCode::InvalidInput, "max_anisotropy must be >= 1");
  return true;
}

void merge_duplicates(MeshState& ms) {
  const std::size_t n = ms.in.points.size();
  // Sort (x, y, index) records directly: an index sort with an indirect comparator is
  // several times slower on a million points (cache misses on every comparison).
  struct Rec {
    double x, y;
    std::int32_t i;
  };
  std::vector<Rec> recs(n);
  for (std::size_t i = 0; i < n; ++i)
    recs[i] = {ms.in.points[i].x, ms.in.points[i].y, static_cast<std::int32_t>(i)};
  std::sort(recs.begin(), recs.end(), [](const Rec& p, const Rec& q) {
    if (p.x != q.x) return p.x < q.x;
    if (p.y != q.y) return p.y < q.y;
    return p.i < q.i;
  });
  std::vector<std::int32_t>& order = ms.xy_order;
  order.resize(n);
  for (std::size_t k = 0; k < n; ++k) order[k] = recs[k].i;
  ms.rep.assign(n, -1);
  for (std::size_t k = 0; k < n; ++k) {
    const std::int32_t i = order[k];
    if (k > 0) {
      const std::int32_t j = order[k - 1];
      if (ms.in.points[i].x == ms.in.points[j].x && ms.in.points[i].y == ms.in.points[j].y) {
        ms.rep[i] = ms.rep[j];
        continue;
      }
    }
    ms.rep[i] = i;
  }
  std::int64_t dup = 0;
  for (std::size_t i = 0; i < n; ++i) dup += ms.rep[i] != static_cast<std::int32_t>(i);
  ms.res.stats.duplicates_merged = dup;
  if (dup > 0) {
    for (std::size_t i = 0; i < n; ++i)
      if (ms.rep[i] != static_cast<std::int32_t>(i)) {
        ms.res.status.warnings.push_back(
            std::to_string(dup) + " duplicate point(s) merged (first: point " + std::to_string(i) +
            " duplicates point " + std::to_string(ms.rep[i]) + ")");
        break;
      }
  }
}

void build_segments(MeshState& ms) {
  std::unordered_set<std::uint64_t> seen;
  std::int64_t degenerate = 0, repeated = 0;
  for (std::size_t i = 0; i < ms.in.segments.size(); ++i) {
    const auto& s = ms.in.segments[i];
    const VertId a = ms.rep[s.a], b = ms.rep[s.b];
    if (a == b) {
      ++degenerate;
      continue;
    }
    const std::uint64_t key = static_cast<std::uint64_t>(std::min(a, b)) << 32 |
                              static_cast<std::uint32_t>(std::max(a, b));
    if (!seen.insert(key).second) {
      ++repeated;
      continue;
    }
    ms.segs.push_back({a, b, s.marker, static_cast<std::int32_t>(i)});
  }
  if (degenerate)
    ms.res.status.warnings.push_back(std::to_string(degenerate) +
                                     " zero-length segment(s) ignored");
  if (repeated)
    ms.res.status.warnings.push_back(std::to_string(repeated) + " repeated segment(s) ignored");
  // Size for "uniform, h <= 0": the mean input segment length (the chapter's step size
  // from the boundary, §7.3.5 preliminary requirements).
  ms.h_uniform = ms.size.h;
  if (ms.size.kind == SizeSpec::Kind::Uniform && !(ms.h_uniform > 0)) {
    double sum = 0;
    for (const auto& s : ms.segs) {
      const Vec2 a = ms.in.points[s.a], b = ms.in.points[s.b];
      sum += std::hypot(b.x - a.x, b.y - a.y);
    }
    if (ms.segs.empty() || !(sum > 0)) {
      ms.refine_ok = false;
      ms.h_uniform = 1;
    } else {
      ms.h_uniform = sum / static_cast<double>(ms.segs.size());
    }
  }
  ms.m_uniform = Metric2::iso(ms.h_uniform);
}

}  // namespace uvmesh::m2d::detail
