// Repair of a face's (u,v) boundary where a use's pcurve disagrees with its 3D edge
// (face.cpp's mesh_face). The PSLG takes each boundary node's (u,v) from the use's pcurve
// at the node's curve parameter (face_pslg.cpp), which is exact when the model is
// consistent: sigma(pcurve(t)) = curve(t) within the CAD tolerances. Files that fail
// BRepCheck break that: a pcurve bulging across the face, one shifted by a period, an
// approximation that strays from its edge. The 3D nodes are then right (the neighbouring
// faces share them) and only their (u,v) is wrong, so each node of such a use is given
// the (u,v) of its projection onto the surface (geom/project.h). The projections are a
// continuation: each seeded at the foot of the previous point, along the edge's 3D curve
// between nodes and from the previous use's last node into the first, inside a window
// of half a period in a periodic direction -- so the (u,v) boundary stays continuous
// across seams and no node jumps by a period. A use whose 3D nodes do not lie on the
// surface either (the 3D curve is the wrong one) keeps its pcurve.
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <sstream>

#include "face_stage.h"

namespace uvmesh::surface::detail {

namespace {

constexpr int kSubsteps = 4;  // projections per piece of the continuation
constexpr double kFloorShare = 0.01;

// The largest of the CAD tolerances that bound where the use may lie.
double use_tolerance(const FaceInput& job, const geom::EdgeUse& use) {
  const geom::Edge& e = job.m.edges[static_cast<std::size_t>(use.edge)];
  double t = std::max(e.tol, job.f.tol);
  for (geom::Id v : {e.v0, e.v1})
    if (v != geom::kNone) t = std::max(t, job.m.vertices[static_cast<std::size_t>(v)].tol);
  return t;
}

const geom::Vec3& node_point(const FaceInput& job, const FacePslg& pslg, std::size_t i) {
  return job.node_points[static_cast<std::size_t>(pslg.gid[i])];
}

// Largest distance between the span's nodes and sigma at their (u,v); infinite where
// sigma is not finite.
double disagreement(const FaceInput& job, const FacePslg& pslg, const FacePslg::UseSpan& sp) {
  double d = 0;
  for (std::size_t i = sp.first; i < sp.end; ++i) {
    const m2d::Vec2& p = pslg.in.points[i];
    const double di = glm::length(job.s.point(p.x, p.y) - node_point(job, pslg, i));
    d = std::isfinite(di) ? std::max(d, di) : std::numeric_limits<double>::infinity();
  }
  return d;
}

// The face's box, but half a period either side of the seed in a periodic direction.
geom::Box2 window(const FaceInput& job, const geom::Vec2& seed) {
  geom::Box2 b = job.f.uv_box;
  if (job.s.u_periodic() && job.s.u_period() > 0)
    b.u = {seed.x - 0.5 * job.s.u_period(), seed.x + 0.5 * job.s.u_period()};
  if (job.s.v_periodic() && job.s.v_period() > 0)
    b.v = {seed.y - 0.5 * job.s.v_period(), seed.y + 0.5 * job.s.v_period()};
  return b;
}

// One step of the continuation: the foot of x seeded at uv.
Projection step(const FaceInput& job, const geom::Vec2& uv, const geom::Vec3& x, double scale) {
  return project_to_surface(job.s, x, uv, window(job, uv), scale);
}

// New (u,v) of the span's points by continuation from `seed` (the (u,v) of the point
// before the span, at `x_prev`). False when a projection did not converge; `worst` is
// the largest distance of a node to its foot.
bool reproject_span(const FaceInput& job, const FacePslg& pslg, const FacePslg::UseSpan& sp,
                    geom::Vec2 seed, geom::Vec3 x_prev, std::vector<geom::Vec2>& uv,
                    double& worst) {
  const geom::Edge& e = job.m.edges[static_cast<std::size_t>(sp.use->edge)];
  uv.clear();
  worst = 0;
  for (std::size_t i = sp.first; i < sp.end; ++i) {
    const geom::Vec3& x = node_point(job, pslg, i);
    const double scale = std::max(glm::length(x - x_prev), 1e-9 * job.m.bbox.diagonal());
    for (int k = 1; k < kSubsteps; ++k) {
      const double w = double(k) / kSubsteps;
      // Between two nodes of the use: along its 3D curve; into its first node: along the
      // chord from the previous use's last node (one short piece).
      const auto& pc = pslg.piece[i - (i > sp.first ? 1 : 0)];
      const geom::Vec3 xk =
          i > sp.first ? e.curve->point(pc[0] + w * (pc[1] - pc[0])) : x_prev + w * (x - x_prev);
      const Projection pr = step(job, seed, xk, scale);
      if (pr.converged) seed = pr.uv;
    }
    const Projection pr = step(job, seed, x, scale);
    if (!pr.converged) return false;
    worst = std::max(worst, pr.distance);
    uv.push_back(pr.uv);
    seed = pr.uv;
    x_prev = x;
  }
  return true;
}

std::string fmt(double x) {
  std::ostringstream o;
  o.precision(3);
  o << x;
  return o.str();
}

// Repairs the wanted spans of one loop [lo, hi), in loop order from a span that is not
// wanted, so that every continuation starts from a (u,v) already final.
void repair_loop(const FaceInput& job, FacePslg& pslg, std::size_t lo, std::size_t hi,
                 const std::vector<double>& d, const std::vector<char>& want, UvRepair& rep) {
  std::size_t start = lo;
  while (start < hi && want[start]) ++start;
  const bool all = start == hi;
  if (all) start = lo;
  const std::size_t n = hi - lo;
  std::vector<geom::Vec2> uv;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t si = lo + (start - lo + k + (all ? 0 : 1)) % n;
    if (!want[si]) continue;
    const FacePslg::UseSpan& sp = pslg.spans[si];
    // The point before the span (the last of the previous use), or the span's own first
    // point when every use of the loop is repaired.
    const std::size_t loop_first = pslg.spans[lo].first, loop_end = pslg.spans[hi - 1].end;
    const std::size_t prev =
        all && si == lo ? sp.first : (sp.first > loop_first ? sp.first - 1 : loop_end - 1);
    const geom::Vec2 seed{pslg.in.points[prev].x, pslg.in.points[prev].y};
    double worst = 0;
    if (!reproject_span(job, pslg, sp, seed, node_point(job, pslg, prev), uv, worst)) continue;
    // Only a clear improvement: the 3D nodes lie on the surface, the pcurve did not.
    if (!(worst <= 0.1 * d[si])) continue;
    for (std::size_t i = sp.first; i < sp.end; ++i)
      pslg.in.points[i] = {uv[i - sp.first].x, uv[i - sp.first].y};
    rep.edges.push_back(sp.use->edge);
    rep.worst_before = std::max(rep.worst_before, d[si]);
    rep.worst_after = std::max(rep.worst_after, worst);
  }
}

// Where a use starts and ends in (u,v): its first point, and its pcurve's end.
std::array<geom::Vec2, 2> use_ends(const FacePslg& pslg, const FacePslg::UseSpan& sp) {
  const geom::EdgeUse& u = *sp.use;
  const m2d::Vec2& a = pslg.in.points[sp.first];
  return {geom::Vec2{a.x, a.y}, u.pcurve->point(u.reversed ? u.range.lo : u.range.hi)};
}

// Whole periods k (of period P > 0) that gap is away from 0, when it is within a
// thousandth of the period of them; 0 otherwise.
int periods_off(double gap, double P) {
  if (!(P > 0)) return 0;
  const double k = std::round(gap / P);
  return std::abs(gap - k * P) <= 1e-3 * P ? static_cast<int>(k) : 0;
}

// A use whose pcurve is a period away from both its neighbours' (sigma is the same
// there, so its nodes agree with the 3D edge): the loop jumps across the domain and back.
// Its points are moved by the period, in loop order, so that it chains in (u,v).
void unwrap_shifted_uses(const FaceInput& job, FacePslg& pslg, UvRepair& rep) {
  const double P[2] = {job.s.u_periodic() ? job.s.u_period() : 0.0,
                       job.s.v_periodic() ? job.s.v_period() : 0.0};
  if (!(P[0] > 0) && !(P[1] > 0)) return;
  for (const auto& [lo, hi] : pslg.loop_spans) {
    const std::size_t n = hi - lo;
    if (n < 2) continue;
    std::vector<std::array<geom::Vec2, 2>> ends(n);
    for (std::size_t k = 0; k < n; ++k) ends[k] = use_ends(pslg, pslg.spans[lo + k]);
    for (std::size_t k = 0; k < n; ++k) {
      const auto& prev = ends[(k + n - 1) % n];
      const auto& next = ends[(k + 1) % n];
      geom::Vec2 shift{0.0};
      for (int c = 0; c < 2; ++c) {
        const int kin = periods_off(ends[k][0][c] - prev[1][c], P[c]);
        const int kout = periods_off(next[0][c] - ends[k][1][c], P[c]);
        if (kin != 0 && kout == -kin) shift[c] = -kin * P[c];
      }
      if (shift == geom::Vec2{0.0}) continue;
      const FacePslg::UseSpan& sp = pslg.spans[lo + k];
      for (std::size_t i = sp.first; i < sp.end; ++i)
        pslg.in.points[i].x += shift.x, pslg.in.points[i].y += shift.y;
      ends[k][0] += shift, ends[k][1] += shift;
      rep.shifted.push_back(sp.use->edge);
    }
  }
}

std::string edge_list(const std::vector<geom::Id>& edges) {
  std::string s = edges.size() > 1 ? "edges" : "edge";
  for (std::size_t i = 0; i < edges.size(); ++i)
    s += (i == 0 ? " " : ", ") + std::to_string(edges[i]);
  return s;
}

}  // namespace

std::string UvRepair::describe() const {
  std::string s;
  if (!shifted.empty())
    s = edge_list(shifted) + ": (u,v) curves a period away from their neighbours', moved by it";
  if (!edges.empty())
    s += (s.empty() ? "" : "; ") + edge_list(edges) + ": (u,v) curves " +
         (crossing ? "crossing, " : "") + fmt(worst_before) +
         " from their 3D edges, the boundary nodes' (u,v) recomputed by projecting the 3D edge "
         "nodes onto the surface (now within " +
         fmt(worst_after) + ")";
  return s;
}

int repair_uv_boundary(const FaceInput& job, FacePslg& pslg, const std::vector<geom::Id>& only,
                       double tol_factor, UvRepair& rep) {
  const std::size_t before = rep.edges.size();
  if (only.empty()) unwrap_shifted_uses(job, pslg, rep);
  const std::size_t shifted = rep.shifted.size();
  std::vector<double> d(pslg.spans.size(), 0.0);
  std::vector<char> want(pslg.spans.size(), 0);
  // A (u,v) error that moves sigma by less than a hundredth of the narrowest gap the sizes
  // resolve (proximity_floor) changes no element that matters: left alone.
  const double floor = kFloorShare * proximity_floor(job.opt.size, job.m.bbox.diagonal(), 0.0);
  for (std::size_t si = 0; si < pslg.spans.size(); ++si) {
    const geom::EdgeUse& use = *pslg.spans[si].use;
    const geom::Edge& e = job.m.edges[static_cast<std::size_t>(use.edge)];
    if (e.degenerate || !e.curve) continue;  // a pole has no 3D nodes to project
    if (!only.empty() && std::find(only.begin(), only.end(), use.edge) == only.end()) continue;
    if (std::find(rep.edges.begin(), rep.edges.end(), use.edge) != rep.edges.end()) continue;
    d[si] = disagreement(job, pslg, pslg.spans[si]);
    want[si] = d[si] > std::max(tol_factor * use_tolerance(job, use), floor);
  }
  if (std::find(want.begin(), want.end(), 1) != want.end())
    for (const auto& [lo, hi] : pslg.loop_spans) repair_loop(job, pslg, lo, hi, d, want, rep);
  const auto changed = static_cast<int>(rep.edges.size() - before + shifted);
  if (changed > 0) snap_node_copies(job.f.uv_box, pslg);
  return changed;
}

}  // namespace uvmesh::surface::detail
