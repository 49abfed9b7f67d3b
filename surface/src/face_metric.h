// The metric of one face as the face stage uses it (docs/ARCHITECTURE.md, "surface"):
// the one owner of the (u,v) metric grid, the v scaling of mesher2d's frame, the
// conversion from param::Metric2 to m2d::Metric2, the anisotropy caps and the boundary
// scale mesher2d applied. Not installed.
//
// Where the metric comes from: param::FaceSizeField holds the face's 3D size field M3
// (curvature sizes on a background grid, gradated there, §7.5.1) and gives the induced
// metric M_uv = J^T M3 J, capped in anisotropy (param::induced_metric). FaceMetric
// caches M_uv on a (u,v) grid, hands mesher2d the metric of its scaled frame, and gives
// the 3D metric each final vertex is measured in.
#pragma once

#include <algorithm>
#include <array>
#include <cstdint>
#include <unordered_map>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::surface::detail {

// The induced metric on a lazily filled (u,v) grid, interpolated bilinearly component
// by component (a convex combination of SPD tensors is SPD). mesher2d asks for the metric
// many times per vertex (edge sampling, eq. 7.10; relocation); each exact value costs a
// surface evaluation and two 3x3 eigen-decompositions, while the field behind it is
// itself a smooth background grid (§7.5.1). Only the cells the mesher visits are filled.
//
// The 3D field is smooth, but J need not be: where a spline patch's parametrization is
// strongly non-uniform (knots crowded in one corner, a nearly collapsed control row, a
// terrain patch whose (u,v) speed varies across it) J^T J changes by large factors
// inside one cell of the 64 x 64 grid. Interpolated there, the (u,v) metric is right at
// the nodes and wrong in between, and the mesh follows the wrong sizes. So a cell is
// checked against the exact metric at its centre when first visited, and split in four
// (recursively, a quadtree, down to kMaxDepth levels) while the interpolated metric
// measures some direction more than kTol off the exact one. Hanging nodes make the field
// slightly discontinuous across a split cell's side, which the mesher's edge sampling
// tolerates.
//
// The grid is a cache: every node is an exact induced metric (a surface evaluation with
// derivatives), and it pays only where the mesher's queries (every quarter of a unit
// length along each edge it measures, mesher2d's sample_edge) fall several to a cell.
// The top level therefore has about kCellsPerUnit cells per unit length in each
// direction (grid_cells in face_metric.cpp), not a fixed 64 x 64: on a face a few
// elements across (a subdivision patch of about 8 elements) 64 cells were a tenth of an
// element, and nearly every query filled new nodes, most of the meshing time. Cells of
// about one unit
// are far finer than the variation of the 3D field (sizes change by at most the
// gradation, 1.3, per unit), and where J varies faster the cells split as before.
class UvMetricGrid {
 public:
  // nu x nv cells at the top level (see grid_cells).
  UvMetricGrid(const param::FaceSizeField& field, const geom::Box2& box, unsigned singular_sides,
               int nu, int nv);
  m2d::Metric2 operator()(double u, double v);

 private:
  static constexpr int kMaxDepth = 8;
  static constexpr double kTol = 1.25;  // ratio of metric lengths, either way
  enum : std::int8_t { kUnknown = 0, kLeaf = 1, kSplit = 2 };

  static double frac(const geom::Interval& r, double x) {
    const double len = r.length() > 0 ? r.length() : 1.0;
    return std::clamp((x - r.lo) / len, 0.0, 1.0);
  }
  std::int8_t& state(int level, int i, int j) {
    if (level == 0) return state_[static_cast<std::size_t>(i * nv_ + j)];
    return deep_state_[key(level, i, j)];
  }
  static std::uint64_t key(int level, int i, int j) {
    return (static_cast<std::uint64_t>(level) << 56) | (static_cast<std::uint64_t>(i) << 28) |
           static_cast<std::uint64_t>(j);
  }
  const param::Metric2& node(int level, int i, int j);
  param::Metric2 exact(int level, double i, double j) const;
  param::Metric2 bilinear(int level, int i, int j, double tu, double tv);
  bool split_needed(int level, int i, int j);

  const param::FaceSizeField& field_;
  geom::Box2 box_;
  unsigned singular_;  ///< geom::SideBits of the surface's poles
  int nu_, nv_;
  std::vector<param::Metric2> vals_;
  std::vector<char> has_;
  std::vector<std::int8_t> state_;
  std::unordered_map<std::uint64_t, std::int8_t> deep_state_;
  std::unordered_map<std::uint64_t, param::Metric2> deep_vals_;
};

/// The face's metric, from the (u,v) grid to mesher2d's frame and back.
///
/// mesher2d starts from the Delaunay triangulation of the boundary in its own
/// coordinates and refines under the metric from there (§7.6.1). Where the (u,v) metric
/// is strongly anisotropic as a whole -- an angle parameter times a radius against a
/// length, a thin band of a cylinder -- that first triangulation is made of fans of long
/// edges running along the boundary, every point sampled on them is too close to the
/// boundary, and the fans stay. So v is scaled by
/// k = mean(sqrt m22) / mean(sqrt m11) over the face, which makes the metric isotropic
/// on average; the metric is transformed accordingly (M' = S^-T M S^-1, S = diag(1, k))
/// and the vertices are scaled back.
/// Not on faces with a pole: there the metric is singular (sqrt m11 -> 0 at a cone's
/// apex), the mean says little, and the fans at the pole's run of (u,v) points are what
/// the pole handling expects (scaled, a cone's apex got a fold).
///
/// The anisotropy cap is applied twice today, with the same bound
/// param::SizeSpec::max_uv_anisotropy: by param::induced_metric in the unscaled (u,v)
/// frame (every grid node), and by mesher2d (Options::max_anisotropy, set here by
/// mesher_options) in the scaled frame. Both are kept so that meshes stay as they are;
/// see mesher_options.
class FaceMetric {
 public:
  /// has_pole: the face has a degenerate edge (no v scaling).
  FaceMetric(const param::FaceSizeField& field, const geom::Face& f, bool has_pole)
      : FaceMetric(field, f, has_pole, samples(field, f.uv_box)) {}

  double vscale() const { return vscale_; }
  /// (u,v) -> mesher2d's frame (v scaled) and back.
  m2d::Vec2 to_mesher(const m2d::Vec2& uv) const { return {uv.x, uv.y * vscale_}; }
  geom::Vec2 from_mesher(const m2d::Vec2& p) const { return {p.x, p.y / vscale_}; }

  /// The metric mesher2d meshes under: the grid's M_uv in the scaled frame, as an
  /// m2d::Metric2. Refers to this object (and its grid): keep it alive while meshing.
  m2d::SizeSpec mesher_size();
  /// The options of mesher2d that belong to the metric: the second anisotropy cap and
  /// the gradation from the boundary sizes.
  static void mesher_options(const MeshOptions& opt, m2d::Options& o);

  /// The 3D metric at uv, scaled as mesher2d scaled it there (m2d::Mesh::boundary_scale): what the
  /// face's unit edges are measured in.
  param::Metric3 metric3(const geom::Vec2& uv, double scale) const {
    return field_.metric3(uv.x, uv.y) * scale;
  }

 private:
  /// 9 x 9 exact samples over the face: the grid's cell counts and the v scaling.
  static std::vector<param::Metric2> samples(const param::FaceSizeField& field,
                                             const geom::Box2& box);
  FaceMetric(const param::FaceSizeField& field, const geom::Face& f, bool has_pole,
             const std::vector<param::Metric2>& samples);
  static double v_scaling(const std::vector<param::Metric2>& samples, bool has_pole);

  const param::FaceSizeField& field_;
  UvMetricGrid grid_;
  double vscale_ = 1.0;
};

}  // namespace uvmesh::surface::detail
