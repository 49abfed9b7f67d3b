// uvmesh::cli2d -- size field from a background mesh (reference chapter §7.5.1, "Using a
// background mesh"): sizes or metrics known at the vertices of a triangle mesh,
// interpolated inside the triangle that contains the query point.
//
// Usage:
//   uvmesh::cli2d::BackgroundLoad bg = uvmesh::cli2d::load_background("bg.mesh", "bg.sol");
//   if (!bg.ok()) ...;                       // bg.error names file and line
//   uvmesh::m2d::Result r = uvmesh::m2d::mesh(pslg, bg.spec);
//
// Location: TriangleLocator (locate.h), a uniform grid of buckets, O(1) per query. Points
// outside the background mesh (or in its holes) take the value at the nearest point of the
// nearest triangle.
//
// Interpolation: log-Euclidean, M(P) = exp(sum_i w_i log M_i) with w the barycentric
// coordinates of P. Why: it keeps the result SPD; it interpolates sizes geometrically
// (a size going from h0 to h1 passes through sqrt(h0 h1) at the middle, the same along every
// principal direction), which is invariant under a change of unit; it commutes with
// inversion and scaling; and, unlike interpolating M^{-1/2} componentwise, it does not
// shrink the determinant when neighbouring metrics have rotated principal axes (the
// "swelling" effect of linear interpolation). Scalar fields (type 1) are treated the same
// way: h(P) = exp(sum_i w_i log h_i), i.e. M = I/h^2 interpolated log-Euclidean, so a
// scalar field and the equivalent isotropic tensor field give the same sizes.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/diagnostic.h"
#include "uvmesh2d/locate.h"
#include "uvmesh2d/medit.h"

namespace uvmesh::cli2d {

// Matrix log / exp of a symmetric 2x2 matrix (closed-form eigen decomposition). spd_log
// requires M SPD; spd_exp accepts any symmetric matrix and returns an SPD one.
m2d::Metric2 spd_log(const m2d::Metric2& m);
m2d::Metric2 spd_exp(const m2d::Metric2& l);
// Intersection of M with the isotropic metric I / hmax^2 (eigenvalues raised to at least
// 1 / hmax^2): the size in every direction becomes at most hmax. Exact because I commutes
// with M, so the simultaneous reduction basis is M's eigenbasis.
m2d::Metric2 spd_bound_size(const m2d::Metric2& m, double hmax);

class BackgroundField {
 public:
  // Fails (file-level diagnostic naming mesh_name) when no triangle has a non-zero area or
  // when the value count does not match the vertex count.
  static std::optional<Diagnostic> create(const MeditMesh2& mesh, const MeditSol& sol,
                                          const std::string& mesh_name,
                                          std::shared_ptr<const BackgroundField>& out);

  TriangleLocator::Location locate(m2d::Vec2 p) const { return locator_.locate(p); }
  m2d::Metric2 metric(double x, double y) const;
  // Size: h for scalar fields; det(M)^(-1/4) (the geometric mean of the principal sizes)
  // for tensor fields.
  double size(double x, double y) const;
  bool isotropic() const { return scalar_; }

 private:
  TriangleLocator locator_;
  std::vector<std::array<m2d::VertId, 3>> tris_;
  bool scalar_ = true;
  std::vector<double> log_h_;        // scalar: log h per vertex
  std::vector<m2d::Metric2> log_m_;  // tensor: log M per vertex
};

struct BackgroundLoad {
  m2d::SizeSpec spec;  // Scalar for a type-1 field, Metric for a type-3 field
  std::shared_ptr<const BackgroundField> field;
  std::optional<Diagnostic> error;
  bool ok() const { return !error.has_value(); }
};

BackgroundLoad load_background(const std::string& mesh_path, const std::string& sol_path);
// Same, from already-parsed files (tests, fuzzers).
BackgroundLoad make_background(const MeditMesh2& mesh, const MeditSol& sol,
                               const std::string& mesh_name);

}  // namespace uvmesh::cli2d
