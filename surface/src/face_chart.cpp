// A face whose (u,v) boundary stays unusable -- pcurves that cross even after the repair
// of face_uv_repair.cpp, e.g. because they lie within a sloppy edge tolerance of their
// 3D edges, or because the surface's parametrization folds -- meshed in another chart:
// the least-squares plane of its boundary nodes, as Netgen falls back to plane space.
// The face must be a graph over that plane: the surface normals (at the boundary nodes'
// projections and on a grid of the face) stay within kMaxNormalAngle of the plane's
// normal, and the boundary loops, projected, neither cross nor touch (mesher2d's exact
// check of its PSLG). The PSLG is the boundary nodes' plane points (one point per global
// node, so the face conforms to its neighbours by index); mesher2d meshes it under the
// 3D size field pulled back to the plane (a grid of metrics J^T M3 J, J the derivative
// of the graph map plane -> surface, like the (u,v) metric grid of face_metric.h, §7.6.1);
// every new vertex is projected onto the surface (geom/project.h). The result is handed
// back in the face's (u,v) (the feet of the projections) for the usual finishing steps.
#include <cmath>
#include <limits>
#include <map>
#include <sstream>

#include "face_metric.h"
#include "face_stage.h"
#include "uvmesh/param/metric.h"

namespace uvmesh::surface::detail {

namespace {

constexpr double kMaxNormalAngle = 70.0;  // degrees; a graph well away from vertical
constexpr int kNormalGrid = 16;           // interior normal samples per direction of the uv box
constexpr int kMetricGrid = 24;           // cells of the chart's metric grid per direction
constexpr double kRadToDeg = 180.0 / 3.14159265358979323846;

struct Plane {
  geom::Vec3 o{0.0}, e1{0.0}, e2{0.0}, n{0.0};
  geom::Vec2 to2(const geom::Vec3& x) const { return {glm::dot(x - o, e1), glm::dot(x - o, e2)}; }
  geom::Vec3 to3(const geom::Vec2& q) const { return o + q.x * e1 + q.y * e2; }
};

// The boundary nodes, once each (a seam's node has two (u,v) points, one 3D point), with
// the feet of their projections onto the surface.
struct Boundary {
  std::vector<NodeId> g;
  std::vector<geom::Vec3> x;
  std::vector<geom::Vec2> uv;  ///< foot of x on the surface
  std::map<NodeId, std::size_t> index;
};

std::string fmt(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

double local_scale(const FaceInput& job) {
  return 1e-3 * job.m.bbox.diagonal();
}

// Each node's foot, seeded at its PSLG (u,v) and at the previous node's foot (the
// PSLG's (u,v) is what is in doubt); the nearer foot is kept.
bool project_boundary(const FaceInput& job, const FacePslg& pslg, Boundary& b, std::string& why) {
  geom::Vec2 prev{pslg.in.points[0].x, pslg.in.points[0].y};
  for (std::size_t i = 0; i < pslg.gid.size(); ++i) {
    const NodeId g = pslg.gid[i];
    if (b.index.count(g)) continue;
    const geom::Vec3& x = job.node_points[static_cast<std::size_t>(g)];
    const geom::Vec2 seed{pslg.in.points[i].x, pslg.in.points[i].y};
    Projection best = project_to_surface(job.s, x, seed, job.f.uv_box, local_scale(job));
    const Projection alt = project_to_surface(job.s, x, prev, job.f.uv_box, local_scale(job));
    if (alt.converged && (!best.converged || alt.distance < best.distance)) best = alt;
    if (!best.converged) {
      why = "boundary node " + std::to_string(g) + " does not project onto the surface";
      return false;
    }
    b.index[g] = b.g.size();
    b.g.push_back(g);
    b.x.push_back(x);
    b.uv.push_back(best.uv);
    prev = best.uv;
  }
  return b.g.size() >= 3;
}

// Least-squares plane of the boundary points: the normal is the covariance's smallest
// eigenvector, oriented with the surface's du x dv at the feet (so that a loop CCW in
// (u,v) stays CCW in the plane); e1 the largest.
Plane fit_plane(const FaceInput& job, const Boundary& b) {
  Plane P;
  for (const auto& x : b.x) P.o += x;
  P.o /= static_cast<double>(b.x.size());
  param::Metric3 cov;
  for (const auto& x : b.x) {
    const geom::Vec3 d = x - P.o;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) cov.m[i][j] += d[i] * d[j];
  }
  const param::Eigen<3> e = cov.eigen();
  P.n = e.vectors[0];
  geom::Vec3 sum{0.0};
  for (const auto& uv : b.uv) sum += job.s.eval_first(uv.x, uv.y).normal();
  if (glm::dot(sum, P.n) < 0) P.n = -P.n;
  P.e1 = e.vectors[2];
  P.e2 = glm::cross(P.n, P.e1);
  return P;
}

// Even-odd test of q against the projected boundary segments.
bool inside(const std::vector<geom::Vec2>& q, const std::vector<std::array<int, 2>>& segs,
            const geom::Vec2& p) {
  bool in = false;
  for (const auto& s : segs) {
    const geom::Vec2 &a = q[static_cast<std::size_t>(s[0])], &c = q[static_cast<std::size_t>(s[1])];
    if ((a.y > p.y) != (c.y > p.y) && p.x < a.x + (p.y - a.y) * (c.x - a.x) / (c.y - a.y)) in = !in;
  }
  return in;
}

// The largest angle (degrees) between the surface normal and the plane's, at the feet
// and at the points of a grid of the (u,v) box whose plane points lie inside the
// projected boundary; 180 where the normal is undefined.
double normal_deviation(const FaceInput& job, const Plane& P, const Boundary& b,
                        const std::vector<geom::Vec2>& q,
                        const std::vector<std::array<int, 2>>& segs) {
  double worst = 0;
  auto at = [&](const geom::Vec2& uv) {
    const geom::Vec3 nn = job.s.eval_first(uv.x, uv.y).normal();
    const double c = glm::length(nn) > 0 ? std::clamp(glm::dot(nn, P.n), -1.0, 1.0) : -1.0;
    worst = std::max(worst, std::acos(c) * kRadToDeg);
  };
  for (const auto& uv : b.uv) at(uv);
  const geom::Box2& box = job.f.uv_box;
  for (int i = 0; i <= kNormalGrid; ++i)
    for (int j = 0; j <= kNormalGrid; ++j) {
      const geom::Vec2 uv{box.u.lo + box.u.length() * i / kNormalGrid,
                          box.v.lo + box.v.length() * j / kNormalGrid};
      const geom::Vec3 x = job.s.point(uv.x, uv.y);
      if (std::isfinite(x.x) && inside(q, segs, P.to2(x))) at(uv);
    }
  return worst;
}

// The chart's PSLG: one point per boundary node, the face's segments between them (a
// pole's run of points is one node: its segments vanish). False when a segment is seen
// twice (a seam: the face wraps around, it is no disc over a plane).
bool plane_pslg(const FacePslg& pslg, const Plane& P, const Boundary& b, m2d::Pslg& in,
                std::vector<geom::Id>& sedge, std::vector<std::array<int, 2>>& segs,
                std::string& why) {
  for (const auto& x : b.x) {
    const geom::Vec2 q = P.to2(x);
    in.points.push_back({q.x, q.y});
  }
  std::map<std::pair<int, int>, int> seen;
  for (std::size_t k = 0; k < pslg.in.segments.size(); ++k) {
    const auto& s = pslg.in.segments[k];
    const int a = static_cast<int>(b.index.at(pslg.gid[static_cast<std::size_t>(s.a)]));
    const int c = static_cast<int>(b.index.at(pslg.gid[static_cast<std::size_t>(s.b)]));
    if (a == c) continue;
    if (seen[{std::min(a, c), std::max(a, c)}]++ > 0) {
      why = "edge " + std::to_string(pslg.sedge[k]) +
            " bounds the face twice (a seam): the face is no disc over a plane";
      return false;
    }
    in.segments.push_back({a, c, 0});
    sedge.push_back(pslg.sedge[k]);
    segs.push_back({a, c});
  }
  return true;
}

// The 3D size field pulled back to the plane on a grid over the projected boundary's
// box: at the surface point near each grid point (projected, seeded at the nearest
// boundary foot), M = J^T M3 J with J's columns the surface tangents over e1, e2 (the
// derivative of the graph map along the plane's normal).
class ChartMetric {
 public:
  ChartMetric(const FaceInput& job, const Plane& P, const Boundary& b, const m2d::Pslg& in) {
    lo_ = hi_ = {in.points[0].x, in.points[0].y};
    for (const auto& p : in.points)
      lo_ = glm::min(lo_, geom::Vec2{p.x, p.y}), hi_ = glm::max(hi_, geom::Vec2{p.x, p.y});
    const geom::Vec2 pad = 0.01 * (hi_ - lo_);
    lo_ -= pad, hi_ += pad;
    m_.resize((kMetricGrid + 1) * (kMetricGrid + 1));
    for (int i = 0; i <= kMetricGrid; ++i)
      for (int j = 0; j <= kMetricGrid; ++j) m_[idx(i, j)] = exact(job, P, b, in, node(i, j));
  }
  m2d::Metric2 operator()(double x, double y) const {
    const double fu = std::clamp((x - lo_.x) / (hi_.x - lo_.x), 0.0, 1.0) * kMetricGrid;
    const double fv = std::clamp((y - lo_.y) / (hi_.y - lo_.y), 0.0, 1.0) * kMetricGrid;
    const int i = std::min(static_cast<int>(fu), kMetricGrid - 1);
    const int j = std::min(static_cast<int>(fv), kMetricGrid - 1);
    const double tu = fu - i, tv = fv - j;
    const double w[4] = {(1 - tu) * (1 - tv), tu * (1 - tv), (1 - tu) * tv, tu * tv};
    const m2d::Metric2* c[4] = {&m_[idx(i, j)], &m_[idx(i + 1, j)], &m_[idx(i, j + 1)],
                                &m_[idx(i + 1, j + 1)]};
    m2d::Metric2 r{0, 0, 0};
    for (int k = 0; k < 4; ++k)
      r.m11 += w[k] * c[k]->m11, r.m12 += w[k] * c[k]->m12, r.m22 += w[k] * c[k]->m22;
    return r;
  }
  // The smallest size the metric asks for at (x, y).
  double min_size(double x, double y) const {
    const m2d::Metric2 m = (*this)(x, y);
    const double tr = 0.5 * (m.m11 + m.m22);
    const double det = m.m11 * m.m22 - m.m12 * m.m12;
    const double lmax = tr + std::sqrt(std::max(0.0, tr * tr - det));
    return 1.0 / std::sqrt(std::max(lmax, 1e-300));
  }

 private:
  static std::size_t idx(int i, int j) {
    return static_cast<std::size_t>(i * (kMetricGrid + 1) + j);
  }
  geom::Vec2 node(int i, int j) const {
    return {lo_.x + (hi_.x - lo_.x) * i / kMetricGrid, lo_.y + (hi_.y - lo_.y) * j / kMetricGrid};
  }
  static m2d::Metric2 exact(const FaceInput& job, const Plane& P, const Boundary& b,
                            const m2d::Pslg& in, const geom::Vec2& q);
  geom::Vec2 lo_, hi_;
  std::vector<m2d::Metric2> m_;
};

// The boundary node whose plane point is nearest q.
std::size_t nearest_boundary(const m2d::Pslg& in, std::size_t nb, const geom::Vec2& q) {
  std::size_t best = 0;
  double bd = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < nb; ++k) {
    const double dx = in.points[k].x - q.x, dy = in.points[k].y - q.y;
    if (dx * dx + dy * dy < bd) bd = dx * dx + dy * dy, best = k;
  }
  return best;
}

// The surface point over plane point q along the plane's normal (the inverse of the
// orthogonal projection that made the boundary's plane points, so that new vertices and
// boundary nodes agree): the closest point of q (seeded at the nearest boundary foot),
// then Newton on to2(sigma(u,v)) = q, whose 2x2 derivative is invertible on a graph.
Projection foot_of(const FaceInput& job, const Plane& P, const Boundary& b, const m2d::Pslg& in,
                   const geom::Vec2& q) {
  const std::size_t k = nearest_boundary(in, b.g.size(), q);
  Projection pr = project_to_surface(job.s, P.to3(q), b.uv[k], job.f.uv_box, local_scale(job));
  if (!pr.converged) return pr;
  const double tol = 1e-10 * local_scale(job);
  pr.converged = false;
  for (int it = 0; it < 20 && !pr.converged; ++it) {
    const geom::SurfacePoint sp = job.s.eval_first(pr.uv.x, pr.uv.y);
    const geom::Vec2 r = P.to2(sp.p) - q;
    pr.point = sp.p;
    if (glm::length(r) <= tol) {
      pr.converged = true;
      break;
    }
    const double a = glm::dot(P.e1, sp.du), bb = glm::dot(P.e1, sp.dv);
    const double c = glm::dot(P.e2, sp.du), d = glm::dot(P.e2, sp.dv);
    const double det = a * d - bb * c;
    if (!(std::abs(det) > 0)) break;
    pr.uv -= geom::Vec2{(d * r.x - bb * r.y) / det, (a * r.y - c * r.x) / det};
  }
  pr.distance = glm::length(pr.point - P.to3(q));
  return pr;
}

m2d::Metric2 ChartMetric::exact(const FaceInput& job, const Plane& P, const Boundary& b,
                                const m2d::Pslg& in, const geom::Vec2& q) {
  Projection pr = foot_of(job, P, b, in, q);
  if (!pr.converged) pr.uv = b.uv[nearest_boundary(in, b.g.size(), q)];
  const geom::Vec3 nn = job.s.eval_first(pr.uv.x, pr.uv.y).normal();
  const double c = glm::dot(nn, P.n);
  // Outside the graph's range (a grid corner beyond the face) the tangents are the plane's.
  const geom::Vec3 j1 = c > 0.1 ? P.e1 - (glm::dot(nn, P.e1) / c) * P.n : P.e1;
  const geom::Vec3 j2 = c > 0.1 ? P.e2 - (glm::dot(nn, P.e2) / c) * P.n : P.e2;
  const param::Metric3 M = job.field.metric3(pr.uv.x, pr.uv.y);
  return {M.dot(j1, j1), M.dot(j1, j2), M.dot(j2, j2)};
}

// mesher2d on the chart's PSLG, with the options of the (u,v) path.
m2d::Result run_chart_mesher(const FaceInput& job, const m2d::Pslg& in, const ChartMetric& cm) {
  m2d::Options o;
  o.split_segments = false;
  o.domain_from_orientation = true;
  FaceMetric::mesher_options(job.opt, o);
  o.collapse_short_edges = false;
  o.time_limit = job.opt.face_time_limit;
  o.measure = false;
  return m2d::mesh(in, m2d::SizeSpec::aniso([&cm](double x, double y) { return cm(x, y); }), o);
}

// The unit 3D normal of triangle t of lm, and the surface's at its centroid's (u,v).
double normal_agreement(const LocalMesh& lm, const geom::Surface& s, const std::array<int, 3>& t) {
  const geom::Vec3 n = glm::cross(lm.p[t[1]] - lm.p[t[0]], lm.p[t[2]] - lm.p[t[0]]);
  const geom::Vec2 c = (lm.uv[t[0]] + lm.uv[t[1]] + lm.uv[t[2]]) / 3.0;
  const geom::Vec3 ns = s.eval_first(c.x, c.y).normal();
  const double len = glm::length(n);
  return len > 0 ? glm::dot(n, ns) / len : -1.0;
}

// A boundary chain that bends out of the plane (an arc seen edge-on) is straight in the
// chart, and rounding may leave a triangle of three consecutive boundary nodes there: in
// 3D it stands across the surface, between the arc and its chord. Each such triangle
// (its normal more than 60 degrees from the surface's) is flipped with the triangle
// across its one inner edge when both new triangles face the surface's way.
int flip_standing_triangles(LocalMesh& lm, const geom::Surface& s) {
  std::map<std::pair<int, int>, std::size_t> owner;  // directed edge -> triangle
  for (std::size_t k = 0; k < lm.tris.size(); ++k)
    for (int i = 0; i < 3; ++i) owner[{lm.tris[k][i], lm.tris[k][(i + 1) % 3]}] = k;
  int flips = 0;
  for (std::size_t k = 0; k < lm.tris.size(); ++k) {
    const std::array<int, 3> t = lm.tris[k];
    if (lm.global[t[0]] < 0 || lm.global[t[1]] < 0 || lm.global[t[2]] < 0) continue;
    if (normal_agreement(lm, s, t) > 0.5) continue;
    for (int i = 0; i < 3; ++i) {
      const int x = t[i], y = t[(i + 1) % 3], z = t[(i + 2) % 3];
      const auto it = owner.find({y, x});
      if (it == owner.end() || owner.count({z, y}) || owner.count({x, z})) continue;
      const std::array<int, 3>& n = lm.tris[it->second];
      int w = n[0];
      for (int c : n)
        if (c != x && c != y) w = c;
      const std::array<int, 3> a{x, w, z}, b{w, y, z};
      if (!(normal_agreement(lm, s, a) > 0) || !(normal_agreement(lm, s, b) > 0)) continue;
      const std::size_t j = it->second;
      lm.tris[k] = a, lm.tris[j] = b;
      for (std::size_t m : {k, j})
        for (int e = 0; e < 3; ++e) owner[{lm.tris[m][e], lm.tris[m][(e + 1) % 3]}] = m;
      owner.erase({x, y}), owner.erase({y, x});
      ++flips;
      break;
    }
  }
  return flips;
}

// mesher2d's mesh -> the face's local mesh: boundary vertices are the global nodes at
// their feet; every other vertex is projected onto the surface. False when a
// projection fails or lands farther than the local size from its plane point.
bool chart_to_surface(const FaceInput& job, const Plane& P, const Boundary& b, const m2d::Pslg& in,
                      const ChartMetric& cm, const m2d::Mesh& mm, LocalMesh& lm, std::string& why) {
  const std::size_t nv = mm.vertices.size();
  lm.uv.assign(nv, geom::Vec2{0.0});
  lm.p.assign(nv, geom::Vec3{0.0});
  lm.global.assign(nv, -1);
  lm.fixed.assign(nv, 0);
  lm.scale.assign(nv, 1.0);
  for (std::size_t i = 0; i < b.g.size(); ++i) {
    const m2d::VertId v = mm.input_vertex[i];
    if (v == m2d::kNone) {
      why = "boundary node " + std::to_string(b.g[i]) + " lost in the plane";
      return false;
    }
    const auto vi = static_cast<std::size_t>(v);
    lm.global[vi] = b.g[i], lm.fixed[vi] = 1, lm.uv[vi] = b.uv[i], lm.p[vi] = b.x[i];
  }
  double height = 0;
  for (const auto& x : b.x) height = std::max(height, std::abs(glm::dot(x - P.o, P.n)));
  for (std::size_t v = 0; v < nv; ++v) {
    if (v < mm.boundary_scale.size()) lm.scale[v] = mm.boundary_scale[v];
    if (lm.global[v] >= 0) continue;
    const geom::Vec2 q{mm.vertices[v].x, mm.vertices[v].y};
    const Projection pr = foot_of(job, P, b, in, q);
    // Farther from the plane than the boundary's own height plus the local size: on
    // another sheet of the surface.
    const double h = cm.min_size(q.x, q.y);
    if (!pr.converged || pr.distance > height + h) {
      why =
          "a chart point does not lift onto the surface within the boundary's height over "
          "the plane and the local size (" +
          (pr.converged ? fmt(pr.distance) : std::string("no convergence")) + ", size " + fmt(h) +
          ")";
      return false;
    }
    lm.uv[v] = pr.uv, lm.p[v] = pr.point;
  }
  for (const auto& t : mm.triangles) lm.tris.push_back({t[0], t[1], t[2]});
  flip_standing_triangles(lm, job.s);
  return true;
}

}  // namespace

bool mesh_in_plane_chart(const FaceInput& job, const FacePslg& pslg, LocalMesh& lm,
                         double& max_normal_deg, std::string& why) {
  Boundary b;
  if (!project_boundary(job, pslg, b, why)) {
    if (why.empty()) why = "fewer than 3 boundary nodes";
    return false;
  }
  const Plane P = fit_plane(job, b);
  m2d::Pslg in;
  std::vector<geom::Id> sedge;
  std::vector<std::array<int, 2>> segs;
  if (!plane_pslg(pslg, P, b, in, sedge, segs, why)) return false;
  std::vector<geom::Vec2> q(in.points.size());
  for (std::size_t i = 0; i < q.size(); ++i) q[i] = {in.points[i].x, in.points[i].y};
  max_normal_deg = normal_deviation(job, P, b, q, segs);
  if (max_normal_deg > kMaxNormalAngle) {
    why = "the surface normal turns " + fmt(max_normal_deg) +
          " degrees from the least-squares plane's (at most " + fmt(kMaxNormalAngle) +
          "): the face is no graph over a plane";
    return false;
  }
  const ChartMetric cm(job, P, b, in);
  const m2d::Result r = run_chart_mesher(job, in, cm);
  if (!r.ok()) {
    why = "in the least-squares plane: " + r.status.message;
    if (r.status.code == m2d::StatusCode::CrossingSegments && r.status.entities.size() >= 2)
      why = "the boundary loops cross in the least-squares plane (edges " +
            std::to_string(sedge[static_cast<std::size_t>(r.status.entities[0])]) + " and " +
            std::to_string(sedge[static_cast<std::size_t>(r.status.entities[1])]) + ")";
    return false;
  }
  if (r.stats.segments_split_at_vertices > 0) {
    why = "a boundary node lies on another edge's segment in the least-squares plane";
    return false;
  }
  return chart_to_surface(job, P, b, in, cm, r.mesh, lm, why);
}

}  // namespace uvmesh::surface::detail
