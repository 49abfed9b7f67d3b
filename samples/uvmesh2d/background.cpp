#include "uvmesh2d/background.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace uvmesh::cli2d {

namespace {

// f(M) for symmetric M = [[a b][b c]] through its eigen decomposition
// M = l1 v v^T + l2 (I - v v^T): f(M) = f(l2) I + (f(l1) - f(l2)) v v^T, with
// v v^T = [[(1 + cos 2t)/2, sin 2t / 2][sin 2t / 2, (1 - cos 2t)/2]], t the angle of v.
template <class F>
m2d::Metric2 apply(const m2d::Metric2& m, F f, bool spd) {
  const double mean = 0.5 * (m.m11 + m.m22), half = 0.5 * (m.m11 - m.m22);
  const double d = std::hypot(half, m.m12);
  if (d == 0) {
    const double fm = f(mean);
    return {fm, 0.0, fm};
  }
  const double l1 = mean + d;
  // For SPD input the small eigenvalue is computed as det / l1: mean - d cancels
  // catastrophically for strongly anisotropic metrics (eigenvalues 1e12 and 1e-12 give 0).
  double l2 = mean - d;
  if (spd) l2 = std::max((m.m11 * m.m22 - m.m12 * m.m12) / l1, std::numeric_limits<double>::min());
  const double c2 = half / d, s2 = m.m12 / d;
  const double f1 = f(l1), f2 = f(l2), df = f1 - f2;
  return {f2 + 0.5 * df * (1 + c2), 0.5 * df * s2, f2 + 0.5 * df * (1 - c2)};
}

}  // namespace

m2d::Metric2 spd_log(const m2d::Metric2& m) {
  return apply(
      m, [](double l) { return std::log(l); }, true);
}

m2d::Metric2 spd_exp(const m2d::Metric2& l) {
  return apply(
      l, [](double x) { return std::exp(x); }, false);
}

m2d::Metric2 spd_bound_size(const m2d::Metric2& m, double hmax) {
  const double lmin = 1.0 / (hmax * hmax);
  return apply(
      m, [lmin](double l) { return std::max(l, lmin); }, true);
}

std::optional<Diagnostic> BackgroundField::create(const MeditMesh2& mesh, const MeditSol& sol,
                                                  const std::string& mesh_name,
                                                  std::shared_ptr<const BackgroundField>& out) {
  if (sol.type == MeditSol::Type::Vector)
    return Diagnostic{mesh_name, 0, "a vector field is not a size field"};
  auto f = std::make_shared<BackgroundField>();
  f->scalar_ = sol.type == MeditSol::Type::Scalar;
  const std::size_t width = f->scalar_ ? 1 : 3;
  const std::size_t nv = mesh.vertices.size();
  if (sol.values.size() != nv * width)
    return Diagnostic{mesh_name, 0,
                      "the mesh has " + std::to_string(nv) +
                          " vertices, but the solution has values for " +
                          std::to_string(sol.values.size() / width)};
  if (f->scalar_) {
    f->log_h_.resize(nv);
    for (std::size_t i = 0; i < nv; ++i) f->log_h_[i] = std::log(sol.values[i]);
  } else {
    f->log_m_.resize(nv);
    for (std::size_t i = 0; i < nv; ++i)
      f->log_m_[i] = spd_log({sol.values[3 * i], sol.values[3 * i + 1], sol.values[3 * i + 2]});
  }
  f->tris_ = mesh.triangles;
  if (!f->locator_.build(mesh.vertices, mesh.triangles)) {
    return Diagnostic{mesh_name, 0,
                      mesh.triangles.empty()
                          ? "the background mesh has no triangles"
                          : "the background mesh has no triangle with a non-zero area"};
  }
  out = std::move(f);
  return std::nullopt;
}

m2d::Metric2 BackgroundField::metric(double x, double y) const {
  const TriangleLocator::Location loc = locator_.locate({x, y});
  const auto& tr = tris_[static_cast<std::size_t>(loc.triangle)];
  if (scalar_) {
    double lh = 0;
    for (std::size_t k = 0; k < 3; ++k) lh += loc.w[k] * log_h_[static_cast<std::size_t>(tr[k])];
    return m2d::Metric2::iso(std::exp(lh));
  }
  m2d::Metric2 l{0, 0, 0};
  for (std::size_t k = 0; k < 3; ++k) {
    const m2d::Metric2& lk = log_m_[static_cast<std::size_t>(tr[k])];
    l.m11 += loc.w[k] * lk.m11;
    l.m12 += loc.w[k] * lk.m12;
    l.m22 += loc.w[k] * lk.m22;
  }
  return spd_exp(l);
}

double BackgroundField::size(double x, double y) const {
  const m2d::Metric2 m = metric(x, y);
  if (scalar_) return 1.0 / std::sqrt(m.m11);
  return std::pow(m.m11 * m.m22 - m.m12 * m.m12, -0.25);
}

BackgroundLoad make_background(const MeditMesh2& mesh, const MeditSol& sol,
                               const std::string& mesh_name) {
  BackgroundLoad r;
  if (auto e = BackgroundField::create(mesh, sol, mesh_name, r.field)) {
    r.error = e;
    return r;
  }
  std::shared_ptr<const BackgroundField> f = r.field;
  if (f->isotropic())
    r.spec = m2d::SizeSpec::scalar([f](double x, double y) { return f->size(x, y); });
  else
    r.spec = m2d::SizeSpec::aniso([f](double x, double y) { return f->metric(x, y); });
  return r;
}

BackgroundLoad load_background(const std::string& mesh_path, const std::string& sol_path) {
  BackgroundLoad r;
  MeditRead m = read_medit_mesh(mesh_path);
  if (!m.ok()) {
    r.error = m.error;
    return r;
  }
  SolRead s = read_medit_sol(sol_path, static_cast<std::int64_t>(m.mesh.vertices.size()));
  if (!s.ok()) {
    r.error = s.error;
    return r;
  }
  return make_background(m.mesh, s.sol, mesh_path);
}

}  // namespace uvmesh::cli2d
