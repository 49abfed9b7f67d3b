// The face metric: the (u,v) metric grid, the v scaling, the conversion to mesher2d's
// type and the boundary scale (face_metric.h).
#include "face_metric.h"

#include <cmath>

namespace uvmesh::surface::detail {

UvMetricGrid::UvMetricGrid(const param::FaceSizeField& field, const geom::Box2& box,
                           unsigned singular_sides, int nu, int nv)
    : field_(field),
      box_(box),
      singular_(singular_sides),
      nu_(nu),
      nv_(nv),
      vals_(static_cast<std::size_t>((nu + 1) * (nv + 1))),
      has_(vals_.size(), 0),
      state_(static_cast<std::size_t>(nu * nv), kUnknown) {}

m2d::Metric2 UvMetricGrid::operator()(double u, double v) {
  const double fu = frac(box_.u, u), fv = frac(box_.v, v);
  int level = 0;
  for (;;) {
    const int cu = nu_ << level, cv = nv_ << level;
    const int i = std::min(static_cast<int>(fu * cu), cu - 1);
    const int j = std::min(static_cast<int>(fv * cv), cv - 1);
    const double tu = fu * cu - i, tv = fv * cv - j;
    std::int8_t& st = state(level, i, j);
    if (st == kUnknown) st = split_needed(level, i, j) ? kSplit : kLeaf;
    if (st == kLeaf) {
      const param::Metric2 m = bilinear(level, i, j, tu, tv);
      return {m(0, 0), m(0, 1), m(1, 1)};
    }
    ++level;
  }
}

// Node (i, j) of level `level`: nodes shared with a coarser level are stored once, at
// the coarsest level that has them.
const param::Metric2& UvMetricGrid::node(int level, int i, int j) {
  while (level > 0 && i % 2 == 0 && j % 2 == 0) i /= 2, j /= 2, --level;
  if (level == 0) {
    const auto k = static_cast<std::size_t>(i * (nv_ + 1) + j);
    if (!has_[k]) {
      vals_[k] = exact(0, i, j);
      has_[k] = 1;
    }
    return vals_[k];
  }
  const std::uint64_t k = key(level, i, j);
  auto it = deep_vals_.find(k);
  if (it == deep_vals_.end()) it = deep_vals_.emplace(k, exact(level, i, j)).first;
  return it->second;
}

param::Metric2 UvMetricGrid::exact(int level, double i, double j) const {
  return field_.metric_uv(box_.u.at(i / static_cast<double>(nu_ << level)),
                          box_.v.at(j / static_cast<double>(nv_ << level)));
}

param::Metric2 UvMetricGrid::bilinear(int level, int i, int j, double tu, double tv) {
  const param::Metric2 &a = node(level, i, j), &b = node(level, i + 1, j),
                       &c = node(level, i, j + 1), &d = node(level, i + 1, j + 1);
  const double w00 = (1 - tu) * (1 - tv), w10 = tu * (1 - tv), w01 = (1 - tu) * tv, w11 = tu * tv;
  param::Metric2 m = a;
  for (int r = 0; r < 2; ++r)
    for (int k = r; k < 2; ++k) {
      m.m[r][k] = w00 * a(r, k) + w10 * b(r, k) + w01 * c(r, k) + w11 * d(r, k);
      m.m[k][r] = m.m[r][k];
    }
  return m;
}

// The interpolated metric at the cell's centre against the exact one, along the two
// axes and the two diagonals of the cell.
bool UvMetricGrid::split_needed(int level, int i, int j) {
  if (level >= kMaxDepth) return false;
  // Cells on a singular side (a pole: a cone's apex, a sphere's) stay as they are: J
  // is singular there by construction and the mesher's pole handling expects the
  // smoothed field (splitting them made a fold at a cone's apex).
  if (((singular_ & geom::kSideUMin) && i == 0) ||
      ((singular_ & geom::kSideUMax) && i == (nu_ << level) - 1) ||
      ((singular_ & geom::kSideVMin) && j == 0) ||
      ((singular_ & geom::kSideVMax) && j == (nv_ << level) - 1))
    return false;
  const param::Metric2 mi = bilinear(level, i, j, 0.5, 0.5);
  const param::Metric2 me = exact(level, i + 0.5, j + 0.5);
  const double du = box_.u.length(), dv = box_.v.length();
  const double dirs[4][2] = {{du, 0}, {0, dv}, {du, dv}, {du, -dv}};
  for (const auto& d : dirs) {
    const double li = mi(0, 0) * d[0] * d[0] + 2 * mi(0, 1) * d[0] * d[1] + mi(1, 1) * d[1] * d[1];
    const double le = me(0, 0) * d[0] * d[0] + 2 * me(0, 1) * d[0] * d[1] + me(1, 1) * d[1] * d[1];
    if (!(le > 0) || !(li > 0)) continue;  // a degenerate point: nothing to compare
    const double r = li / le;              // squared ratio of lengths
    if (r > kTol * kTol || r < 1 / (kTol * kTol)) return true;
  }
  return false;
}

namespace {

// Top-level cells of a face's UvMetricGrid along u and v, from its metric length across
// the box in each direction (the largest metric speed of the samples times the side):
// kCellsPerUnit cells per unit length, as a power of two between 16 (the size field's own
// grid, FaceSizeField's 17 x 17 nodes, whose lines then are grid lines) and 64 (the fixed
// size before; a face more than 32 units across keeps it). Finer top cells fill more
// exact metrics for the same mesh quality; coarser ones (down to 8 x 8) save little and
// put the size field's grid lines inside cells.
// A face with a pole keeps 64 x 64: the cells along a singular side are never split
// (UvMetricGrid::split_needed), so their size is the width of the smoothed field the
// pole handling sees; 16 cells there left poor triangles (test "caps wedged between
// sub-hmin features"). CAD surfaces keep 64 x 64 too: on CAD parts the counts from the
// metric speed gave self-intersecting pairs and poor triangles. A subdivision
// patch (SurfaceKind::Other) is one smooth polynomial piece a few elements across, where
// the count from the speed is what saves the time.
constexpr double kCellsPerUnit = 1.0;
std::array<int, 2> grid_cells(const std::vector<param::Metric2>& samples, const geom::Box2& box,
                              unsigned singular_sides, geom::SurfaceKind kind) {
  if (singular_sides != 0u || kind != geom::SurfaceKind::Other) return {64, 64};
  double su = 0, sv = 0;
  for (const param::Metric2& g : samples) {
    if (std::isfinite(g(0, 0)) && g(0, 0) > 0) su = std::max(su, std::sqrt(g(0, 0)));
    if (std::isfinite(g(1, 1)) && g(1, 1) > 0) sv = std::max(sv, std::sqrt(g(1, 1)));
  }
  auto cells = [](double units) {
    int n = 16;
    while (n < 64 && n < kCellsPerUnit * units) n *= 2;
    return n;
  };
  return {cells(su * box.u.length()), cells(sv * box.v.length())};
}

UvMetricGrid make_grid(const param::FaceSizeField& field, const geom::Face& f,
                       const std::vector<param::Metric2>& samples) {
  const geom::Surface& s = *f.surface;
  const auto [cells_u, cells_v] = grid_cells(samples, f.uv_box, s.singular_sides(), s.kind());
  return UvMetricGrid(field, f.uv_box, s.singular_sides(), cells_u, cells_v);
}

}  // namespace

std::vector<param::Metric2> FaceMetric::samples(const param::FaceSizeField& field,
                                                const geom::Box2& box) {
  std::vector<param::Metric2> samples;
  samples.reserve(81);
  for (int i = 0; i <= 8; ++i)
    for (int j = 0; j <= 8; ++j)
      samples.push_back(field.metric_uv(box.u.at((i + 0.5) / 9.5), box.v.at((j + 0.5) / 9.5)));
  return samples;
}

FaceMetric::FaceMetric(const param::FaceSizeField& field, const geom::Face& f, bool has_pole,
                       const std::vector<param::Metric2>& samples)
    : field_(field), grid_(make_grid(field, f, samples)), vscale_(v_scaling(samples, has_pole)) {}

// k = exp(mean(log sqrt m22) - mean(log sqrt m11)) over the samples (face_metric.h);
// 1 on a face with a pole, or when k is within a factor 1.5 of 1.
double FaceMetric::v_scaling(const std::vector<param::Metric2>& samples, bool has_pole) {
  if (has_pole) return 1.0;
  double lu = 0, lv = 0;
  int n = 0;
  for (const param::Metric2& g : samples) {
    if (!(g(0, 0) > 0) || !(g(1, 1) > 0) || !std::isfinite(g(0, 0)) || !std::isfinite(g(1, 1)))
      continue;
    lu += 0.5 * std::log(g(0, 0)), lv += 0.5 * std::log(g(1, 1)), ++n;
  }
  if (n > 0) {
    const double k = std::exp((lv - lu) / n);
    if (std::isfinite(k) && std::abs(std::log(k)) > std::log(1.5)) return std::clamp(k, 1e-6, 1e6);
  }
  return 1.0;
}

m2d::SizeSpec FaceMetric::mesher_size() {
  const double vscale = vscale_;
  return m2d::SizeSpec::aniso([this, vscale](double u, double v) {
    const m2d::Metric2 g = grid_(u, v / vscale);
    return m2d::Metric2{g.m11, g.m12 / vscale, g.m22 / (vscale * vscale)};
  });
}

// The second anisotropy cap: mesher2d caps every metric it reads at max_anisotropy, in
// its own (scaled) frame, on top of induced_metric's cap in the unscaled frame. With
// vscale = 1 both frames are one and the second cap only sees metrics already within
// the bound (a convex combination of metrics within it stays within it), up to
// rounding; with vscale = k the scaled metric's anisotropy can exceed the bound by up
// to a factor k, and mesher2d raises its small eigenvalue there.
//
// Gradation from the boundary: mesher2d grows the boundary's sizes into the face at the
// spec's gradation rate (the H-correction, eq. 7.11), taken as at least 1.05.
//
// Field points: saturation or frontal placement, as MeshOptions::frontal says.
void FaceMetric::mesher_options(const MeshOptions& opt, m2d::Options& o) {
  o.max_anisotropy = opt.size.max_uv_anisotropy;
  o.boundary_gradation = std::max(opt.size.gradation, 1.05);
  o.field_points = opt.frontal ? m2d::FieldPointMethod::Frontal : m2d::FieldPointMethod::Saturation;
}

}  // namespace uvmesh::surface::detail
