// Size field: curvature sizes, local sizes, induced metric, gradation, background grid.
#include "uvmesh/param/size_field.h"

#include <algorithm>
#include <cmath>
#include <deque>

namespace uvmesh::param {

double chordal_size(double rho, double eps) {
  if (!(eps > 0.0) || !std::isfinite(rho) || eps >= rho)
    return std::numeric_limits<double>::infinity();
  return 2.0 * std::sqrt(eps * (2.0 * rho - eps));
}

double angle_size(double rho, double theta) {
  if (!(theta > 0.0) || !std::isfinite(rho)) return std::numeric_limits<double>::infinity();
  return 2.0 * rho * std::sin(0.5 * std::min(theta, 3.14159265358979));
}

namespace {

double curvature_size(double k, const SizeSpec& spec) {
  const double rho =
      std::abs(k) > 0.0 ? 1.0 / std::abs(k) : std::numeric_limits<double>::infinity();
  return std::min(
      {spec.hmax, chordal_size(rho, spec.chordal_tol), angle_size(rho, spec.angle_tol)});
}

double clamp_size(double h, const SizeSpec& spec) {
  return std::clamp(h, spec.hmin > 0.0 ? spec.hmin : 0.0, spec.hmax);
}

}  // namespace

Metric3 curvature_metric(const Curvature& c, const SizeSpec& spec) {
  if (c.singular) return Metric3::isotropic(clamp_size(spec.hmax, spec));
  double h1 = clamp_size(curvature_size(c.k1, spec), spec);
  double h2 = clamp_size(curvature_size(c.k2, spec), spec);
  if (spec.isotropic) h1 = h2 = std::min(h1, h2);
  const double hn = std::min(h1, h2);
  Metric3 m = Metric3::from_sizes({c.dir1, c.dir2, c.normal}, {h1, h2, hn});
  return m.capped(spec.max_anisotropy);
}

Metric3 surface_metric(const geom::Surface& s, double u, double v, const SizeSpec& spec,
                       geom::Id face) {
  return surface_metric(s.eval(u, v), spec, face);
}

Metric3 surface_metric(const geom::SurfacePoint& e, const SizeSpec& spec, geom::Id face) {
  Metric3 m = curvature_metric(principal_curvatures(e), spec);
  if (face != geom::kNone) {
    if (auto it = spec.face_size.find(face); it != spec.face_size.end())
      m = intersect(m, Metric3::isotropic(clamp_size(it->second, spec)));
  }
  for (const PointSize& ps : spec.point_size)
    if (glm::length(e.p - ps.p) <= ps.radius)
      m = intersect(m, Metric3::isotropic(clamp_size(ps.h, spec)));
  return m;
}

Metric2 induced_metric(const Metric3& m3, const geom::SurfacePoint& e, const SizeSpec& spec) {
  const geom::Vec3 mu = m3.apply(e.du), mv = m3.apply(e.dv);
  Metric2 r;
  r.m[0][0] = glm::dot(e.du, mu);
  r.m[0][1] = r.m[1][0] = 0.5 * (glm::dot(e.du, mv) + glm::dot(e.dv, mu));
  r.m[1][1] = glm::dot(e.dv, mv);
  // Within the anisotropy cap (lambda_min / lambda_max >= 1 / A^2) M_uv is returned as
  // it is; that is decided from the trace and the determinant without the Jacobi
  // eigen-decomposition (the metric is asked for at every grid node and sample):
  // det / tr^2 = r / (1 + r)^2 grows with r = lambda_min / lambda_max on (0, 1].
  {
    const double tr = r.m[0][0] + r.m[1][1], det = r.determinant();
    const double a2 = spec.max_uv_anisotropy * spec.max_uv_anisotropy;
    if (tr > 0 && det > 0 && std::isfinite(tr) && det * (a2 + 1) * (a2 + 1) >= tr * tr * a2)
      return r;
  }
  Eigen<2> eg = r.eigen();
  if (!(eg.values[1] > 0.0)) {
    const Eigen<3> e3 = m3.eigen();
    return Metric2::diagonal(e3.values[2]);
  }
  const double floor = eg.values[1] / (spec.max_uv_anisotropy * spec.max_uv_anisotropy);
  if (eg.values[0] < floor) {
    eg.values[0] = floor;
    return Metric2::from_eigen(eg.vectors, eg.values);
  }
  return r;
}

namespace {
// True when a - b is positive definite (all leading principal minors > 0).
bool dominates(const Metric3& a, const Metric3& b) {
  const Metric3 d = a + b * -1.0;
  const auto& x = d.m;
  return x[0][0] > 0 && x[0][0] * x[1][1] - x[0][1] * x[1][0] > 0 && d.determinant() > 0;
}
}  // namespace

int gradate(std::vector<Metric3>& metrics, const std::vector<geom::Vec3>& points,
            const std::vector<std::pair<int, int>>& edges, double beta) {
  const std::size_t n = metrics.size();
  std::vector<std::vector<int>> adj(n);
  for (const auto& [a, b] : edges) {
    adj[static_cast<std::size_t>(a)].push_back(b);
    adj[static_cast<std::size_t>(b)].push_back(a);
  }
  std::deque<int> work;
  std::vector<char> queued(n, 1);
  for (std::size_t i = 0; i < n; ++i) work.push_back(static_cast<int>(i));
  int updates = 0;
  // Relative change below which a metric is considered unchanged (keeps the worklist
  // from cycling on rounding; 1e-9 is far below any size that matters).
  constexpr double kRel = 1e-9;
  while (!work.empty()) {
    const int i = work.front();
    work.pop_front();
    queued[static_cast<std::size_t>(i)] = 0;
    const Metric3& mi = metrics[static_cast<std::size_t>(i)];
    for (int j : adj[static_cast<std::size_t>(i)]) {
      const geom::Vec3 d =
          points[static_cast<std::size_t>(j)] - points[static_cast<std::size_t>(i)];
      const double eta = 1.0 + (beta - 1.0) * mi.length(d);
      const Metric3 grown = mi * (1.0 / (eta * eta));
      Metric3& mj = metrics[static_cast<std::size_t>(j)];
      // Most edges of a gradated grid ask for nothing: M_j - grown positive definite means
      // the unit ball of M_j lies inside grown's, so intersect(M_j, grown) = M_j. Tested
      // by the leading principal minors (Sylvester), which costs a few products, while the
      // intersection takes three eigen-decompositions (and a grid has far more edges than
      // updates).
      if (dominates(mj, grown)) continue;
      const Metric3 next = intersect(mj, grown);
      double diff = 0.0, ref = 0.0;
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) {
          diff = std::max(diff, std::abs(next.m[a][b] - mj.m[a][b]));
          ref = std::max(ref, std::abs(mj.m[a][b]));
        }
      if (diff > kRel * ref) {
        mj = next;
        ++updates;
        if (!queued[static_cast<std::size_t>(j)]) {
          queued[static_cast<std::size_t>(j)] = 1;
          work.push_back(j);
        }
      }
    }
  }
  return updates;
}

FaceSizeField::FaceSizeField(const geom::Surface& s, const geom::Box2& box, const SizeSpec& spec,
                             geom::Id face, int n)
    : s_(s), box_(box), spec_(spec), n_(std::max(n, 2)) {
  // The gradated grid itself is not kept: only its M^{-1/2} is interpolated, and a model
  // holds one field per face until its faces are meshed (bench/memory).
  std::vector<Metric3> grid;
  std::vector<geom::Vec3> pts;
  pts.reserve(static_cast<std::size_t>(n_ * n_));
  grid.reserve(static_cast<std::size_t>(n_ * n_));
  // One evaluation per node gives its point, its metric and whether it is singular
  // (instead of three evaluations of sigma; building the fields is a visible share of
  // the meshing time on models of many small faces).
  std::vector<char> singular(static_cast<std::size_t>(n_ * n_), 0);
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) {
      const double u = box_.u.at(double(i) / (n_ - 1)), v = box_.v.at(double(j) / (n_ - 1));
      const geom::SurfacePoint e = s_.eval(u, v);
      singular[pts.size()] = e.normal() == geom::Vec3(0.0);
      pts.push_back(e.p);
      grid.push_back(surface_metric(e, spec_, face));
    }
  auto id = [&](int i, int j) { return i * n_ + j; };
  // At a singular node (pole, cone apex) the curvature is undefined and surface_metric
  // falls back to hmax. A pole of a smooth surface has the curvature of its
  // neighbourhood, while a cone's apex is a true singularity where the curvature radius
  // goes to 0: the node takes the metric of its neighbour toward the box centre, halved
  // in size, so the fan of triangles around the apex stays close to the surface.
  {
    const int c = (n_ - 1) / 2;
    for (int i = 0; i < n_; ++i)
      for (int j = 0; j < n_; ++j) {
        if (!singular[static_cast<std::size_t>(id(i, j))]) continue;
        int a = i, b = j;
        for (int step = 0; step < n_ && singular[static_cast<std::size_t>(id(a, b))]; ++step) {
          a += (c > a) - (c < a);
          b += (c > b) - (c < b);
        }
        if (!singular[static_cast<std::size_t>(id(a, b))])
          grid[static_cast<std::size_t>(id(i, j))] = grid[static_cast<std::size_t>(id(a, b))] * 4.0;
      }
  }
  std::vector<std::pair<int, int>> edges;
  for (int i = 0; i < n_; ++i)
    for (int j = 0; j < n_; ++j) {
      if (i + 1 < n_) edges.emplace_back(id(i, j), id(i + 1, j));
      if (j + 1 < n_) edges.emplace_back(id(i, j), id(i, j + 1));
      if (i + 1 < n_ && j + 1 < n_) edges.emplace_back(id(i, j), id(i + 1, j + 1));
    }
  corrections_ = gradate(grid, pts, edges, spec_.gradation);
  grid_inv_sqrt_.reserve(grid.size());
  for (const Metric3& m : grid) grid_inv_sqrt_.push_back(m.power(-0.5));
}

Metric3 FaceSizeField::metric3(double u, double v) const {
  auto cell = [&](const geom::Interval& r, double x, int& k, double& t) {
    const double s =
        std::clamp((x - r.lo) / (r.length() > 0 ? r.length() : 1.0), 0.0, 1.0) * (n_ - 1);
    k = std::min(static_cast<int>(s), n_ - 2);
    t = s - k;
  };
  int i, j;
  double tu, tv;
  cell(box_.u, u, i, tu);
  cell(box_.v, v, j, tv);
  auto g = [&](int a, int b) -> const Metric3& {
    return grid_inv_sqrt_[static_cast<std::size_t>(a * n_ + b)];
  };
  // Bilinear interpolation of M^{-1/2} (sizes), as in interpolate().
  const Metric3 s = g(i, j) * ((1 - tu) * (1 - tv)) + g(i + 1, j) * (tu * (1 - tv)) +
                    g(i, j + 1) * ((1 - tu) * tv) + g(i + 1, j + 1) * (tu * tv);
  // M = S^-2 = (S^-1)^2, S symmetric positive definite (a convex combination of such):
  // the inverse by cofactors, squared, instead of an eigen-decomposition and three
  // powers (metric3 is asked for at every node of every (u,v) metric grid).
  const auto& a = s.m;
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1],
               c01 = a[0][2] * a[2][1] - a[0][1] * a[2][2],
               c02 = a[0][1] * a[1][2] - a[0][2] * a[1][1],
               c11 = a[0][0] * a[2][2] - a[0][2] * a[2][0],
               c12 = a[0][2] * a[1][0] - a[0][0] * a[1][2],
               c22 = a[0][0] * a[1][1] - a[0][1] * a[1][0];
  const double det = s.determinant();
  if (!(det > 0) || !std::isfinite(det)) return s.power(-2.0);
  const double inv[3][3] = {{c00 / det, c01 / det, c02 / det},
                            {c01 / det, c11 / det, c12 / det},
                            {c02 / det, c12 / det, c22 / det}};
  Metric3 r;
  for (int x = 0; x < 3; ++x)
    for (int y = 0; y < 3; ++y)
      r.m[x][y] = inv[x][0] * inv[0][y] + inv[x][1] * inv[1][y] + inv[x][2] * inv[2][y];
  r.symmetrize();
  return r;
}

Metric2 FaceSizeField::metric_uv(double u, double v) const {
  return induced_metric(metric3(u, v), s_.eval_first(u, v), spec_);
}

}  // namespace uvmesh::param
