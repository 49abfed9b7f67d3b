// 3D size field and the induced (u,v) metric (docs/ARCHITECTURE.md: "param").
//
//   param::SizeSpec spec;
//   spec.hmax = diag / 20;  spec.hmin = diag / 2000;  spec.chordal_tol = diag * 1e-3;
//   param::Metric3 m3 = param::surface_metric(*face.surface, u, v, spec, face_id);
//   param::Metric2 muv = param::induced_metric(m3, face.surface->eval(u, v), spec);
//
//   // Per face, a background grid (7.5.1) gradated with ratio spec.gradation:
//   param::FaceSizeField field(*face.surface, face.uv_box, spec, face_id);
//   param::Metric2 m = field.metric_uv(u, v);
//
// Size from curvature (chordal tolerance eps on a radius rho): the chord whose sagitta
// is eps has length h = 2 sqrt(eps (2 rho - eps)); applied per principal direction
// (anisotropic) or with the smaller radius in all directions (isotropic option). Angle
// tolerance theta: h = 2 rho sin(theta / 2). Every size is clamped to [hmin, hmax].
#pragma once

#include <limits>
#include <map>
#include <utility>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/param/curvature.h"
#include "uvmesh/param/metric.h"

namespace uvmesh::param {

/// A size imposed near a point: h within `radius` of `p`.
struct PointSize {
  geom::Vec3 p{0.0};
  double h = 0.0;
  double radius = 0.0;
};

struct SizeSpec {
  double hmin = 0.0;                                      ///< smallest size anywhere
  double hmax = std::numeric_limits<double>::infinity();  ///< largest size anywhere
  double chordal_tol = 0.0;                               ///< eps (length); 0 = off
  double angle_tol = 0.0;                                 ///< radians of arc per element; 0 = off
  bool isotropic = false;  ///< curvature size from the smaller radius in every direction
  /// Cap of h_max / h_min for the 3D metric (flat directions of a thin cylinder would
  /// otherwise ask for hmax along the axis and a tiny size around it).
  double max_anisotropy = 100.0;
  /// Cap of the (u,v) metric's anisotropy: bounds the degenerate direction at poles and
  /// the stretch of badly parametrised patches (see induced_metric).
  double max_uv_anisotropy = 1e4;
  /// Gradation ratio beta >= 1: sizes grow by at most (beta - 1) per unit length of
  /// metric distance (H-correction), so neighbouring unit edges differ by <= beta.
  double gradation = 1.3;
  std::map<geom::Id, double> face_size;  ///< local size per face id
  std::map<geom::Id, double> edge_size;  ///< local size per edge id (used by the 1D stage)
  std::vector<PointSize> point_size;
};

/// h = 2 sqrt(eps (2 rho - eps)); +inf when rho is infinite or eps >= rho (the whole
/// circle is within the tolerance).
double chordal_size(double rho, double eps);
/// h = 2 rho sin(theta / 2).
double angle_size(double rho, double theta);

/// Curvature metric: sizes from the spec's curvature tolerances along the principal
/// directions, hmax along flat ones, min(h1, h2) along the normal; clamped and capped.
Metric3 curvature_metric(const Curvature& c, const SizeSpec& spec);

/// Metric of the spec at the surface point sigma(u,v) of face `face` (kNone: no face
/// size): curvature metric intersected with the face size and the point sizes.
Metric3 surface_metric(const geom::Surface& s, double u, double v, const SizeSpec& spec,
                       geom::Id face = geom::kNone);
/// The same at an evaluated point e = s.eval(u, v) (its second derivatives are needed).
Metric3 surface_metric(const geom::SurfacePoint& e, const SizeSpec& spec,
                       geom::Id face = geom::kNone);

/// Induced (u,v) metric M_uv = J^T M3 J, J = [sigma_u sigma_v]: the (u,v) step d has the
/// metric length of the 3D step J d to first order. At a pole J is singular (sigma_u = 0)
/// and M_uv has a null direction (moving along u does not move in space); there, and
/// wherever the ratio exceeds spec.max_uv_anisotropy, the small eigenvalue is raised to
/// lambda_max / max_uv_anisotropy^2, which asks for *more* points along the collapsed
/// direction than strictly needed -- safe, and finite for the 2D mesher. If J vanishes
/// altogether (a surface collapsed to a point) the result is lambda_max(M3) times the
/// identity: finite, but such a face has nothing to mesh.
/// On a seam the metric is that of sigma, which is periodic: M_uv(u + period, v) =
/// M_uv(u, v), so both sides of a seam see the same metric.
Metric2 induced_metric(const Metric3& m3, const geom::SurfacePoint& e, const SizeSpec& spec);

/// H-correction on a graph: after the call, for every edge (i, j), M_j <= M_i / eta^2
/// with eta = 1 + (beta - 1) |p_j - p_i|_{M_i} (and symmetrically), i.e. isotropic sizes
/// satisfy h_j <= h_i + (beta - 1) |p_j - p_i|. Metrics only get finer. Returns the number
/// of metric updates made.
int gradate(std::vector<Metric3>& metrics, const std::vector<geom::Vec3>& points,
            const std::vector<std::pair<int, int>>& edges, double beta);

/// Per-face background grid of 3D metrics (7.5.1): sampled on an n x n (u,v) grid,
/// gradated over the grid graph, interpolated bilinearly (size interpolation).
class FaceSizeField {
 public:
  FaceSizeField(const geom::Surface& s, const geom::Box2& box, const SizeSpec& spec,
                geom::Id face = geom::kNone, int n = 17);
  Metric3 metric3(double u, double v) const;
  /// Induced metric at (u,v): J from the surface (Surface::eval_first), M3 from the
  /// background.
  Metric2 metric_uv(double u, double v) const;
  int corrections() const { return corrections_; }

 private:
  const geom::Surface& s_;
  geom::Box2 box_;
  SizeSpec spec_;
  int n_;
  std::vector<Metric3> grid_inv_sqrt_;  ///< M^{-1/2} per node: what is interpolated
  int corrections_ = 0;
};

}  // namespace uvmesh::param
