// Private to uvmesh::geom's OpenSubdiv back end: the surfaces and curves of a
// subdivision Model's patches, all evaluating OpenSubdiv's limit surface (Bfr::Surface).
// Model assembly (subd_model.cpp) builds them; see uvmesh/geom/subd.h for the layout.
#pragma once

#include <opensubdiv/bfr/surface.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

#include "subd_patch.h"
#include "uvmesh/geom/model.h"

namespace uvmesh::geom::subd_detail {

namespace Bfr = OpenSubdiv::Bfr;

// One base face's limit surface: the Bfr::Surface and its patch points. Shared (read
// only) by the sub-face patches of an n-gon.
struct BasePatch {
  Bfr::Surface<double> s;
  std::vector<double> points;  // patch points, xyz
  bool triangle = false;       // Loop: the domain is the triangle u, v >= 0, u + v <= 1
};

// A patch: base-face coordinates = origin + scale * (u,v) of the patch.
class SubdSurface final : public Surface {
 public:
  // diff_everywhere: tangents differenced on the whole patch, not only in the corner
  // squares (the sub-faces of n-gons, see eval()).
  SubdSurface(std::shared_ptr<const BasePatch> b, Vec2 origin, double scale,
              bool diff_everywhere = false)
      : b_(std::move(b)),
        o_(origin),
        k_(scale),
        regular_(b_->s.IsRegular()),
        diff_all_(diff_everywhere) {}

  SurfacePoint eval(double u, double v) const override { return evaluate(u, v, true); }
  // Without second derivatives Bfr combines three point sets instead of six (the induced
  // metric asks for this: most of the metric grids' evaluations).
  SurfacePoint eval_first(double u, double v) const override { return evaluate(u, v, false); }
  // Positions only (one Bfr combination instead of six): the mesher maps every new
  // (u,v) vertex, and the 3D smoothing and the projections try many, through point().
  Vec3 point(double u, double v) const override {
    const Vec2 c = clamp({u, v});
    if (c.x != u || c.y != v) return evaluate(u, v, false).p;  // the first-order extension outside
    return pos(c);
  }
  Box2 bounds() const override { return {{0.0, 1.0}, {0.0, 1.0}}; }
  SurfaceKind kind() const override { return SurfaceKind::Other; }
  unsigned singular_sides() const override { return sing_; }
  Vec2 origin() const { return o_; }
  double scale() const { return k_; }
  void set_singular_sides(unsigned s) { sing_ = s; }

 private:
  SurfacePoint evaluate(double u, double v, bool second) const {
    // Bfr evaluates inside the face's domain only (irregular patches look the point up
    // in a quadtree of sub-patches). The mesher and the chordal projection may ask a
    // little outside (metric grids over the box, line searches): the point is then
    // extended to first order from the nearest domain point, which keeps sigma
    // continuous and exact inside.
    const Vec2 c = clamp({u, v});
    double P[3], Du[3], Dv[3], Duu[3] = {0, 0, 0}, Duv[3] = {0, 0, 0}, Dvv[3] = {0, 0, 0};
    const double uv[2] = {o_.x + k_ * c.x, o_.y + k_ * c.y};
    if (second)
      b_->s.Evaluate(uv, b_->points.data(), 3, P, Du, Dv, Duu, Duv, Dvv);
    else
      b_->s.Evaluate(uv, b_->points.data(), 3, P, Du, Dv);
    auto vec = [](const double* a) { return Vec3(a[0], a[1], a[2]); };
    SurfacePoint e{vec(P),
                   k_ * vec(Du),
                   k_ * vec(Dv),
                   k_ * k_ * vec(Duu),
                   k_ * k_ * vec(Duv),
                   k_ * k_ * vec(Dvv)};
    if (!regular_ && (b_->triangle || diff_all_ || near_corner(c))) {
      // Irregular faces end, around extraordinary vertices, in Gregory patches whose
      // first derivatives from Bfr ignore the rational weights (off by a fraction of a
      // percent of the patch size against differences of the positions).
      // Tangents must agree with sigma (Newton projections, unit lengths), so they are
      // differenced from positions, inside the domain; second derivatives only feed
      // curvature sizes and are kept.
      // Those patches lie in the corner squares of side 1/4 of a quad or sub-face (the
      // patch tree's smooth approximation level 2; sharp features go deeper, closer to
      // the corner). Sampled densely on irregular Catmull-Clark faces, Bfr's tangents are
      // off by several percent within Chebyshev distance 1/4 of a corner and agree with
      // the differences to their own truncation beyond it. So only there the four extra
      // evaluations are paid (they are a noticeable share of the meshing time). Loop
      // triangles keep them everywhere. The sub-faces of n-gons too: on thin triangles
      // next to a pole of high valence Bfr's tangents are off by more than 1% farther
      // from the centre corner (Chebyshev distance 0.34), where Newton projections on the
      // surface then stall.
      // eval_first (second == false: the induced metric, the 3D smoothing) takes
      // one-sided differences, one evaluation per direction (see forward_diff); eval keeps
      // the central ones, whose tangents vanish with sigma_u at a collapsed corner or fold
      // to 1e-12 (FaceSizeField's singular nodes, the curvature there).
      e.du = second ? diff(c, e.p, {1.0, 0.0}, e.du) : forward_diff(c, e.p, {1.0, 0.0}, e.du);
      e.dv = second ? diff(c, e.p, {0.0, 1.0}, e.dv) : forward_diff(c, e.p, {0.0, 1.0}, e.dv);
    }
    if (c.x != u || c.y != v) e.p += (u - c.x) * e.du + (v - c.y) * e.dv;
    return e;
  }
  bool inside(Vec2 c) const {
    if (b_->triangle) return c.x >= 0.0 && c.y >= 0.0 && c.x + c.y <= 1.0;
    return c.x >= 0.0 && c.y >= 0.0 && c.x <= 1.0 && c.y <= 1.0;
  }
  // Chebyshev distance below 0.3 (1/4 and a margin) from a corner of the unit square.
  static bool near_corner(Vec2 c) {
    const double dx = std::min(c.x, 1.0 - c.x), dy = std::min(c.y, 1.0 - c.y);
    return std::max(dx, dy) < 0.3;
  }
  Vec2 clamp(Vec2 c) const {
    if (!b_->triangle) return glm::clamp(c, Vec2(0.0), Vec2(1.0));
    c = glm::max(c, Vec2(0.0));
    if (c.x + c.y > 1.0)
      c = glm::min(glm::max(c - Vec2(0.5 * (c.x + c.y - 1.0)), Vec2(0.0)), Vec2(1.0));
    return c;
  }
  Vec3 pos(Vec2 c) const {
    const double uv[2] = {o_.x + k_ * c.x, o_.y + k_ * c.y};
    double P[3];
    b_->s.Evaluate(uv, b_->points.data(), 3, P);
    return {P[0], P[1], P[2]};
  }
  // Second-order difference along `dir` with a stencil inside the domain (central, else
  // one-sided); `fallback` where no stencil fits (the acute corners of a triangle).
  Vec3 diff(Vec2 c, const Vec3& p0, Vec2 dir, const Vec3& fallback) const {
    // 1e-6 of the unit domain: truncation ~1e-12, rounding ~1e-10 of the patch size.
    constexpr double h = 1e-6;
    const Vec2 a = c + h * dir, b = c - h * dir;
    if (inside(a) && inside(b)) return (pos(a) - pos(b)) / (2 * h);
    if (inside(a) && inside(c + 2 * h * dir))
      return (-3.0 * p0 + 4.0 * pos(a) - pos(c + 2 * h * dir)) / (2 * h);
    if (inside(b) && inside(c - 2 * h * dir))
      return (3.0 * p0 - 4.0 * pos(b) + pos(c - 2 * h * dir)) / (2 * h);
    return fallback;
  }

  // First-order difference along `dir` from p0 = sigma(c): forward when that step stays
  // in the domain, else backward; `fallback` where neither does. One evaluation per
  // direction instead of diff()'s two, which cost a good share of the meshing time,
  // most of it for the metric grids. With h = 1e-7 of the unit domain the tangents differ
  // from the central differences by ~1e-7 of their length on average and ~1e-5 at worst
  // (random points in [0, 0.3]^2 of every patch of several cages; h = 1e-6 is worse by
  // truncation, 1e-8 by rounding) -- nothing a metric or a smoothing step notices. Not for
  // eval(): where sigma_u vanishes (the fold of a quad 'f a b a c', a collapsed corner)
  // the difference is h sigma_uu / 2 instead of ~0, the size field's nodes there no
  // longer count as singular, their curvature is noise, and the mesh gets more
  // triangles.
  Vec3 forward_diff(Vec2 c, const Vec3& p0, Vec2 dir, const Vec3& fallback) const {
    constexpr double h = 1e-7;
    const Vec2 a = c + h * dir, b = c - h * dir;
    if (inside(a)) return (pos(a) - p0) / h;
    if (inside(b)) return (p0 - pos(b)) / h;
    return fallback;
  }

  std::shared_ptr<const BasePatch> b_;
  Vec2 o_;
  double k_;
  bool regular_;
  bool diff_all_;
  unsigned sing_ = 0u;
};

// A Catmull-Clark n-gon (n != 4) as one patch. OpenSubdiv parameterizes it by n
// quadrangulated sub-faces meeting at the face centre; made into n model faces, the n
// spokes between them (edge midpoint -> centre) are mesh edges, and in a thin face they
// cut 5-16 degree corners and 170 degree angles that no triangle can fill well (around
// a pole of high valence the faces are triangles many times longer than wide, and the
// badly shaped triangles of the mesh all lie in those sub-faces). Here the domain is the face's
// own polygon: the cage face projected on its plane (Newell normal), scaled to extent
// 1, split as OpenSubdiv splits it into the quads (q_k, m_k, c, m_{k-1}) -- corner,
// edge midpoint, centre, previous midpoint -- each mapped bilinearly onto sub-face k's
// unit square. sigma is continuous across the spokes (both sides are linear on the
// shared side) and exact at every point; its first derivatives jump there (the
// induced metric is continuous, the meshing only needs that). The base edges stay
// straight lines in (u,v) with the same parameter as before, so the neighbours see the
// same curve.
class NgonSurface final : public Surface {
 public:
  NgonSurface(std::vector<std::shared_ptr<const SubdSurface>> sub, std::vector<Vec2> poly,
              Vec2 centre)
      : sub_(std::move(sub)), p_(std::move(poly)), c_(centre), n_(static_cast<int>(sub_.size())) {
    for (const Vec2& q : p_) {
      box_.u.lo = std::min(box_.u.lo, q.x), box_.u.hi = std::max(box_.u.hi, q.x);
      box_.v.lo = std::min(box_.v.lo, q.y), box_.v.hi = std::max(box_.v.hi, q.y);
    }
  }
  SurfacePoint eval(double u, double v) const override { return evaluate(u, v, true); }
  SurfacePoint eval_first(double u, double v) const override { return evaluate(u, v, false); }
  Vec3 point(double u, double v) const override {
    const Vec2 x{u, v};
    const int k = sector(x);
    const Vec2 st = ngon_subface_coords(p_, c_, k, x);
    return sub_[k]->point(st.x, st.y);
  }
  Box2 bounds() const override { return box_; }
  SurfaceKind kind() const override { return SurfaceKind::Other; }

 private:
  SurfacePoint evaluate(double u, double v, bool second_derivatives) const {
    const Vec2 x{u, v};
    const int k = sector(x);
    const Vec2 st = ngon_subface_coords(p_, c_, k, x);
    // Bilinear map P(s,t) = p00 + s e + t f + s t g of quad k and its inverse's
    // derivatives: D(s,t)/D(u,v) = J^-1, second derivatives -J^-1 g (s_a t_b + t_a s_b).
    const int m = 2 * n_;
    const Vec2 p00 = p_[2 * k], e = p_[2 * k + 1] - p00, f = p_[(2 * k + m - 1) % m] - p00;
    const Vec2 g = c_ - p_[2 * k + 1] - p_[(2 * k + m - 1) % m] + p00;
    const Vec2 Ps = e + st.y * g, Pt = f + st.x * g;
    const double det = Ps.x * Pt.y - Ps.y * Pt.x;
    const double su = Pt.y / det, sv = -Pt.x / det, tu = -Ps.y / det, tv = Ps.x / det;
    const SurfacePoint a =
        second_derivatives ? sub_[k]->eval(st.x, st.y) : sub_[k]->eval_first(st.x, st.y);
    SurfacePoint r;
    r.p = a.p;
    r.du = su * a.du + tu * a.dv;
    r.dv = sv * a.du + tv * a.dv;
    if (!second_derivatives) return r;
    auto second = [&](double sa, double ta, double sb, double tb) {
      const double w = sa * tb + ta * sb;
      return Vec2(-(su * g.x + sv * g.y) * w, -(tu * g.x + tv * g.y) * w);
    };
    const Vec2 uu = second(su, tu, su, tu), uv = second(su, tu, sv, tv),
               vv = second(sv, tv, sv, tv);
    auto d2 = [&](double sa, double ta, double sb, double tb, const Vec2& ab) {
      return sa * sb * a.duu + (sa * tb + ta * sb) * a.duv + ta * tb * a.dvv + ab.x * a.du +
             ab.y * a.dv;
    };
    r.duu = d2(su, tu, su, tu, uu);
    r.duv = d2(su, tu, sv, tv, uv);
    r.dvv = d2(sv, tv, sv, tv, vv);
    return r;
  }
  // The sub-face whose angular sector around the centre (from the ray to side point k-1
  // to the ray to side point k, CCW) holds x; outside the polygon the sectors extend.
  int sector(const Vec2& x) const {
    const Vec2 d = x - c_;
    const int m = 2 * n_;
    int best = 0;
    double best_score = -std::numeric_limits<double>::infinity();
    for (int k = 0; k < n_; ++k) {
      const Vec2 a = p_[(2 * k + m - 1) % m] - c_, b = p_[2 * k + 1] - c_;
      const double s0 = (a.x * d.y - a.y * d.x) / glm::length(a),
                   s1 = (d.x * b.y - d.y * b.x) / glm::length(b);
      const double score = std::min(s0, s1);
      if (score >= 0) return k;
      if (score > best_score) best_score = score, best = k;
    }
    return best;
  }
  std::vector<std::shared_ptr<const SubdSurface>> sub_;
  std::vector<Vec2> p_;
  Vec2 c_;
  int n_;
  Box2 box_{{std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()},
            {std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()}};
};

// The 3D curve of a model edge: the limit surface of one patch along a straight pcurve.
class CurveOnPatch final : public Curve {
 public:
  CurveOnPatch(std::shared_ptr<const Surface> s, std::shared_ptr<const Curve2> pc)
      : s_(std::move(s)), pc_(std::move(pc)) {}
  CurvePoint3 eval(double t) const override {
    const CurvePoint2 c = pc_->eval(t);
    const SurfacePoint e = s_->eval(c.p.x, c.p.y);
    const Vec3 d1 = c.d1.x * e.du + c.d1.y * e.dv;
    const Vec3 d2 = c.d1.x * c.d1.x * e.duu + 2.0 * c.d1.x * c.d1.y * e.duv +
                    c.d1.y * c.d1.y * e.dvv + c.d2.x * e.du + c.d2.y * e.dv;
    return {e.p, d1, d2};
  }
  Interval range() const override { return pc_->range(); }
  CurveKind kind() const override { return CurveKind::Other; }

 private:
  std::shared_ptr<const Surface> s_;
  std::shared_ptr<const Curve2> pc_;
};

// A patch at a high-valence vertex re-parameterized by the projection of its limit
// surface on its plane: sigma(w) = inner(z) where P(inner(z)) = w, P the orthogonal
// projection on the plane (SubdPlane), found by Newton's method.
//
// Why (bench/subd/results.md): OpenSubdiv's parameterization of a face at
// an extraordinary vertex of valence n squeezes the face's 90-degree (sub-face) corner
// into the 360/n-degree corner of the limit surface, and not uniformly: along a line
// s + t = c of a sub-face at the valence-64 pole the 3D spacing of equal steps is 0.0070
// at the sides and 0.0011 in the middle. The induced metric M_uv = J^T M3 J (docs/ARCHITECTURE.md)
// then varies 6x across one element, and mesher2d, which measures an edge by
// integrating M_uv along its straight (u,v) segment (chapter eq. 7.10), measures the
// length of a curve that bends toward the pole (1.8 units for a 3D chord of 0.2) and
// splits every edge across the thin strips next to the pole. In the projected domain
// the distance in (u,v) is the distance of the projected points: where the patch is
// nearly flat over its plane (a thin face around a pole is), (u,v) distances are 3D
// distances up to the slope, and M_uv is smooth.
//
// The patch's boundary is the projection of its limit boundary curves (ProjectedCurve2);
// used only when the projection is one-to-one on the patch (checked on samples at
// construction, see make_projected).
class ProjectedSurface final : public Surface {
 public:
  // sub: OpenSubdiv's sub-faces of the n-gon, k = 0..n-1 CCW (sub-face k's side s = 1
  // is sub-face k+1's side t = 1: the spoke from side point k to the centre), each on
  // its unit square. Samples (k, st) covering them start the Newton iterations.
  ProjectedSurface(std::vector<std::shared_ptr<const SubdSurface>> sub, const SubdPlane& pl,
                   const std::vector<std::pair<int, Vec2>>& samples, Box2 box)
      : sub_(std::move(sub)), pl_(pl), box_(box) {
    for (const auto& [k, z] : samples) {
      const SurfacePoint e = sub_[static_cast<std::size_t>(k)]->eval(z.x, z.y);
      const Vec2 a0 = pl_.dir(e.du), a1 = pl_.dir(e.dv);
      const double det = a0.x * a1.y - a0.y * a1.x;
      samples_.push_back(
          {k, z, pl_.map(e.p), Vec2(a1.y, -a0.y) / det, Vec2(-a1.x, a0.x) / det, to_w(e)});
    }
  }

  SurfacePoint eval(double u, double v) const override {
    bool far = false;
    const SurfacePoint e = solve({u, v}, far);
    return far ? e : to_w(e);
  }
  Vec3 point(double u, double v) const override {
    bool far = false;
    return solve({u, v}, far).p;
  }
  Box2 bounds() const override { return box_; }
  SurfaceKind kind() const override { return SurfaceKind::Other; }
  const SubdPlane& plane() const { return pl_; }

 private:
  // Derivatives in sub-face coordinates -> in w by the chain rule through z(w):
  // Dz/Dw = A^-1 with A = P [sigma_s sigma_t]; differentiating P(sigma(z(w))) = w twice
  // gives z_ab = -A^-1 P(D2 sigma[z_a, z_b]).
  SurfacePoint to_w(const SurfacePoint& e) const {
    const Vec2 a0 = pl_.dir(e.du), a1 = pl_.dir(e.dv);
    const double det = a0.x * a1.y - a0.y * a1.x;
    const Vec2 zu(a1.y / det, -a0.y / det), zv(-a1.x / det, a0.x / det);  // columns of A^-1
    auto second = [&](const Vec2& p, const Vec2& q) {
      const Vec3 h = p.x * q.x * e.duu + (p.x * q.y + p.y * q.x) * e.duv + p.y * q.y * e.dvv;
      const Vec2 ph = pl_.dir(h);
      const Vec2 zab = -(ph.x * zu + ph.y * zv);
      return h + zab.x * e.du + zab.y * e.dv;
    };
    SurfacePoint r;
    r.p = e.p;
    r.du = zu.x * e.du + zu.y * e.dv;
    r.dv = zv.x * e.du + zv.y * e.dv;
    r.duu = second(zu, zu);
    r.duv = second(zu, zv);
    r.dvv = second(zv, zv);
    return r;
  }

  // The limit point (with its derivatives in sub-face coordinates) whose projection is
  // w. Newton's method in one sub-face's (s,t), where sigma is smooth (its derivatives
  // jump across the spokes between sub-faces), from a linear step off the nearest
  // sample; a solution beyond a spoke moves to the sub-face there and starts again.
  // Near the patch (within a quarter of a sub-face) the sub-faces' first-order
  // extension is inverted the same way; farther out (`far`: only the metric grids over
  // the box of a thin patch ask there) sigma is the second-order Taylor extension from
  // the nearest sample, derivatives in w.
  SurfacePoint solve(Vec2 w, bool& far) const {
    std::size_t best = 0;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t i = 0; i < samples_.size(); ++i) {
      const Vec2 d = samples_[i].w - w;
      const double dd = glm::dot(d, d);
      if (dd < bd) bd = dd, best = i;
    }
    const Sample& sm = samples_[best];
    const Vec2 dw = w - sm.w;
    int k = sm.k;
    Vec2 z = sm.z + dw.x * sm.iu + dw.y * sm.iv;
    constexpr double kNear = 0.25;
    far = !(z.x >= -kNear && z.y >= -kNear && z.x <= 1.0 + kNear && z.y <= 1.0 + kNear);
    if (far) {
      const SurfacePoint& a = sm.ew;
      SurfacePoint r = a;
      r.du = a.du + dw.x * a.duu + dw.y * a.duv;
      r.dv = a.dv + dw.x * a.duv + dw.y * a.dvv;
      r.p = a.p + dw.x * a.du + dw.y * a.dv +
            0.5 * (dw.x * dw.x * a.duu + 2.0 * dw.x * dw.y * a.duv + dw.y * dw.y * a.dvv);
      return r;
    }
    const int n = static_cast<int>(sub_.size());
    SurfacePoint e;
    for (int pass = 0;; ++pass) {
      newton(*sub_[static_cast<std::size_t>(k)], w, z, e);
      // Across a spoke (a little beyond it: on it both sides agree to rounding)?
      constexpr double kOver = 1e-9;
      if (pass >= 3 || (z.x <= 1.0 + kOver && z.y <= 1.0 + kOver)) break;
      if (z.x - 1.0 >= z.y - 1.0)
        k = (k + 1) % n, z = Vec2(z.y, 2.0 - z.x);
      else
        k = (k + n - 1) % n, z = Vec2(2.0 - z.y, z.x);
    }
    return e;
  }
  void newton(const SubdSurface& s, Vec2 w, Vec2& z, SurfacePoint& e) const {
    e = s.eval(z.x, z.y);
    Vec2 r = pl_.map(e.p) - w;
    double rn = glm::length(r);
    // 1e-14 of the unit domain: sigma(w) is exact at a point within 1e-14 of w, far below
    // the acceptance's 1e-9 D; rounding of the projected coordinates is ~1e-16.
    for (int it = 0; it < 12 && rn > 1e-14; ++it) {
      // Outside the unit square SubdSurface extends sigma to first order from the
      // clamped point c: p = P(c) + (z - c) . D(c), whose derivative along a side also
      // has the cross term (z - c) D_uv(c), which eval() leaves out; with it Newton
      // converges quadratically there too.
      const double ox = z.x - std::clamp(z.x, 0.0, 1.0), oy = z.y - std::clamp(z.y, 0.0, 1.0);
      const Vec3 ju = oy != 0.0 && ox == 0.0 ? e.du + oy * e.duv : e.du;
      const Vec3 jv = ox != 0.0 && oy == 0.0 ? e.dv + ox * e.duv : e.dv;
      const Vec2 a0 = pl_.dir(ju), a1 = pl_.dir(jv);
      const double det = a0.x * a1.y - a0.y * a1.x;
      if (!(std::abs(det) > 0)) break;
      const Vec2 dz(-(a1.y * r.x - a1.x * r.y) / det, -(-a0.y * r.x + a0.x * r.y) / det);
      double step = 1.0;
      bool moved = false;
      for (int h = 0; h < 8; ++h, step *= 0.5) {
        const Vec2 zn = z + step * dz;
        const SurfacePoint en = s.eval(zn.x, zn.y);
        const Vec2 rr = pl_.map(en.p) - w;
        const double rnn = glm::length(rr);
        if (rnn < rn) {
          z = zn, e = en, r = rr, rn = rnn, moved = true;
          break;
        }
        // Close to the solution a step that does not reduce the residual meets the
        // rounding of the evaluation (~1e-11 outside the patch, in the extension): stop
        // there rather than search along the step.
        if (rn < 1e-10) break;
      }
      if (!moved) break;
    }
  }

  struct Sample {
    int k;
    Vec2 z, w;
    Vec2 iu, iv;      // columns of the inverse Jacobian of P o sigma at z
    SurfacePoint ew;  // sigma and its derivatives in w there
  };
  std::vector<std::shared_ptr<const SubdSurface>> sub_;
  SubdPlane pl_;
  std::vector<Sample> samples_;
  Box2 box_;
};

// The pcurve of an edge use on a projected patch: the projection of the limit curve,
// i.e. P(inner(line(t))) for the straight inner pcurve; sigma(pcurve(t)) is then the
// edge's point at t, as on every other side.
class ProjectedCurve2 final : public Curve2 {
 public:
  ProjectedCurve2(std::shared_ptr<const Surface> inner, SubdPlane pl,
                  std::shared_ptr<const Curve2> line)
      : c_(std::move(inner), std::move(line)), pl_(pl) {}
  CurvePoint2 eval(double t) const override {
    const CurvePoint3 c = c_.eval(t);
    return {pl_.map(c.p), pl_.dir(c.d1), pl_.dir(c.d2)};
  }
  Interval range() const override { return c_.range(); }
  CurveKind kind() const override { return CurveKind::Other; }

 private:
  CurveOnPatch c_;  // the limit curve along the straight pcurve of the inner domain
  SubdPlane pl_;
};

// The domain of an n-gon patch (NgonSurface) from the limit points of its sub-faces:
// corners, side points (sub-face corner (1,0)) and centre, projected on the plane of the
// boundary's Newell normal, corner 0 at the origin, side 0 along +u, scaled to extent 1.
// Shaped after the limit surface rather than the cage, each bilinear quad is close to an
// isometry of its piece, so sigma's derivatives agree across the spokes (with the cage
// polygon of a thin triangle next to a valence-64 pole, sigma_u turned by 120 degrees
// across a spoke and Newton projections stalled on it). Empty (sub-face patches are used)
// when a vertex repeats or a quad is not strictly convex (the bilinear maps would not be
// one-to-one) or the quads do not turn once around the centre.
bool flatten_ngon(const std::vector<Vec3>& bnd, const Vec3& centre, std::vector<Vec2>& out,
                  Vec2& c2, SubdPlane& plane);

// Valence from which the n-gon patches at a vertex are projected (ProjectedSurface). The
// corner squeeze of OpenSubdiv's parameterization grows with the valence n (a 90-degree
// sub-face corner onto about 360/n degrees: 2x at n = 8, 16x at n = 64).
constexpr int kProjectValence = 8;

// The projected version of an n-gon patch (ProjectedSurface), or null when the
// projection is not one-to-one on it: the Jacobian of P o inner must keep its sign
// (positive: the polygon is CCW in the same plane) on 9 x 9 samples of every quad, and
// stay above 1e-3 of its median (a fold or a cusp of the projection would make the
// inversion ill-conditioned).
std::shared_ptr<const ProjectedSurface> make_projected(
    const std::vector<std::shared_ptr<const SubdSurface>>& sub, const SubdPlane& pl);

}  // namespace uvmesh::geom::subd_detail
