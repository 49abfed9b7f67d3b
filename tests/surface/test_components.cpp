// Unit tests of the surface stage's components on analytic surfaces (no OpenCASCADE):
// the edge discretizer (stage 1), the boundary caps (gradation and proximity along the
// boundary), the face metric (the (u,v) grid, v scaling and frame), the 3D improvement
// (stage 2b), and the whole pipeline on a plane, a cylinder
// with a seam, a sphere with poles, a torus and a cone with an apex.
#include <catch2/catch.hpp>
#include <cmath>
#include <memory>
#include <vector>

#include "analytic_models.h"
#include "face_metric.h"
#include "internal.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;
namespace am = analytic_models;

namespace {

param::SizeSpec uniform(double h) {
  param::SizeSpec s;
  s.hmax = h;
  s.hmin = h / 100;
  return s;
}

// What mesh_model gives the discretizer: one background field per face.
struct Fields {
  std::vector<std::unique_ptr<param::FaceSizeField>> own;
  std::vector<const param::FaceSizeField*> ptr;
  Fields(const geom::Model& m, const param::SizeSpec& spec) {
    for (std::size_t f = 0; f < m.faces.size(); ++f) {
      const geom::Face& face = m.faces[f];
      own.push_back(std::make_unique<param::FaceSizeField>(*face.surface, face.uv_box, spec,
                                                           static_cast<geom::Id>(f)));
      ptr.push_back(own.back().get());
    }
  }
};

// Arc length of edge e between parameters a < b (Simpson on |C'|, 16 panels).
double arc(const geom::Edge& e, double a, double b) {
  const int n = 16;
  double s = 0;
  for (int i = 0; i <= 2 * n; ++i) {
    const double t = a + (b - a) * i / (2 * n);
    const double w = (i == 0 || i == 2 * n) ? 1 : (i % 2 ? 4 : 2);
    s += w * glm::length(e.curve->eval(t).d1);
  }
  return s * (b - a) / (6 * n);
}

std::vector<geom::Model> all_models() {
  return {am::plane_rectangle(2, 1), am::cylinder_side(1, 2), am::sphere(1), am::torus(2, 0.5),
          am::cone(1, 0.5)};
}

}  // namespace

TEST_CASE("edge discretizer: unit segments in a uniform size on every analytic edge",
          "[surface][edges]") {
  for (const geom::Model& m : all_models()) {
    INFO("surface " << geom::to_string(m.faces[0].kind));
    const double h = 0.1;
    const param::SizeSpec spec = uniform(h);
    const Fields fields(m, spec);
    surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
    for (std::size_t e = 0; e < m.edges.size(); ++e) {
      const geom::Edge& ed = m.edges[e];
      if (ed.degenerate) continue;
      const std::vector<double> t = disc.discretize(static_cast<geom::Id>(e));
      INFO("edge " << e << " of length " << ed.length);
      REQUIRE(t.size() >= 2);
      CHECK(t.front() == ed.range.lo);
      CHECK(t.back() == ed.range.hi);
      // Unit segments; shorter ones only where the size grades down towards a pole or an
      // apex (the face metric is refined there, §7.6.2), never longer ones.
      const auto segments = static_cast<double>(t.size() - 1);
      CHECK(segments >= ed.length / h - 1.0);
      CHECK(segments <= 1.2 * ed.length / h + 1.0);
      uvmesh::measures::UnitEdges u;
      for (std::size_t i = 0; i + 1 < t.size(); ++i) {
        REQUIRE(t[i] < t[i + 1]);
        const double L = arc(ed, t[i], t[i + 1]) / h;
        CHECK(L <= uvmesh::measures::kUnitMax);
        u.add(L);
      }
      CHECK(u.share() >= 0.85);
    }
  }
}

TEST_CASE("edge discretizer: a closed edge gets at least its minimum number of segments",
          "[surface][edges]") {
  const geom::Model m = am::cylinder_side(1e-3, 2);  // circles far shorter than h
  const param::SizeSpec spec = uniform(0.5);
  const Fields fields(m, spec);
  surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
  for (int n : {3, 5}) {
    disc.set_min_closed(n);
    CHECK(disc.discretize(0).size() - 1 >= static_cast<std::size_t>(n));
    CHECK(disc.discretize(1).size() - 1 >= static_cast<std::size_t>(n));
  }
}

TEST_CASE("edge discretizer: the angle tolerance bounds the arc per segment on a circle",
          "[surface][edges]") {
  const geom::Model m = am::cylinder_side(1, 2);
  param::SizeSpec spec = uniform(10.0);  // the size alone would give 3 segments
  spec.angle_tol = am::kPi / 12;         // 24 segments per turn
  const Fields fields(m, spec);
  surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
  const std::vector<double> t = disc.discretize(0);
  CHECK(t.size() - 1 >= 22);
  CHECK(t.size() - 1 <= 40);
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
    CHECK(t[i + 1] - t[i] <= std::sqrt(2.0) * spec.angle_tol * 1.05);
}

TEST_CASE("boundary caps: a narrow strip sizes its long edges by its width", "[surface][caps]") {
  // Proximity: the two long edges of a 4 x 0.02 rectangle are 0.02 apart, far less than
  // h = 0.5: capped, their segments follow the gap instead of spanning it 25 times over.
  const double w = 0.02, h = 0.5;
  const geom::Model m = am::plane_rectangle(4, w);
  const param::SizeSpec spec = uniform(h);
  const Fields fields(m, spec);
  surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
  std::vector<std::vector<double>> t(m.edges.size());
  for (std::size_t e = 0; e < m.edges.size(); ++e) t[e] = disc.discretize(static_cast<geom::Id>(e));
  CHECK(t[0].size() - 1 <= 10);  // without caps: about 4 / h
  const surface::detail::BoundaryCaps caps(m, t, spec, 0.0);
  const geom::Vec3 mid{2, 0, 0}, tangent{1, 0, 0};
  const double c = caps.cap(0, mid, tangent, h);
  CHECK(c <= 2 * w);
  CHECK(c >= w / 4);
  // Capped, the edge is discretized at about the gap, and never above h.
  const std::vector<double> capped = disc.discretize(0, &caps);
  CHECK(capped.size() - 1 >= static_cast<std::size_t>(4 / (2 * w)));
  for (std::size_t i = 0; i + 1 < capped.size(); ++i) CHECK(capped[i + 1] - capped[i] <= h);
}

TEST_CASE("boundary caps: a sheet narrower than the feature size is still resolved",
          "[surface][caps][feature]") {
  // The same 4 x 0.02 strip with a feature size of 0.05. Its long edges are free (used by
  // this face alone): the gap is the sheet's own width, not an artefact another face could
  // absorb, so proximity refines along it as without a feature size (the case above).
  const double w = 0.02, h = 0.5, feature = 0.05;
  const geom::Model m = am::plane_rectangle(4, w);
  const param::SizeSpec spec = uniform(h);
  const Fields fields(m, spec);
  surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
  std::vector<std::vector<double>> t(m.edges.size());
  for (std::size_t e = 0; e < m.edges.size(); ++e) t[e] = disc.discretize(static_cast<geom::Id>(e));
  const surface::detail::BoundaryCaps caps(m, t, spec, feature);
  const geom::Vec3 mid{2, 0, 0}, tangent{1, 0, 0};
  CHECK(caps.cap(0, mid, tangent, h) <= 2 * w);
  const std::vector<double> capped = disc.discretize(0, &caps);
  CHECK(capped.size() - 1 >= static_cast<std::size_t>(4 / (2 * w)));
}

TEST_CASE("boundary caps: sizes grade away from a small edge at the gradation rate",
          "[surface][caps]") {
  // A 1 x 4 rectangle whose short edge 3 (x = 0) is given a size of h / 50: along the long
  // edge 0 the cap at distance d from it is at most h_s + (beta - 1) d (eq. 7.11).
  const double h = 0.5, hs = h / 50;
  const geom::Model m = am::plane_rectangle(4, 1);
  param::SizeSpec spec = uniform(h);
  spec.edge_size[3] = hs;
  const Fields fields(m, spec);
  surface::detail::EdgeDiscretizer disc(m, spec, fields.ptr);
  std::vector<std::vector<double>> t(m.edges.size());
  for (std::size_t e = 0; e < m.edges.size(); ++e) t[e] = disc.discretize(static_cast<geom::Id>(e));
  const surface::detail::BoundaryCaps caps(m, t, spec, 0.0);
  for (double d : {0.05, 0.2, 0.5, 1.0}) {
    INFO("distance " << d);
    const double c = caps.cap(0, {d, 0, 0}, {1, 0, 0}, h);
    CHECK(c <= hs + (spec.gradation - 1) * d + 1e-9);
    CHECK(c > 0);
  }
  // Far from the small edge the cap lets the size return to h.
  CHECK(caps.cap(0, {3.9, 0, 0}, {1, 0, 0}, h) == Approx(h));
}

TEST_CASE("3D improvement: vertices stay on the surface, boundary fixed, worst triangle better",
          "[surface][improve3d]") {
  // A grid on the cylinder side, interior (u,v) vertices pushed off their places: the
  // improvement may only move interior vertices, in (u,v), mapped through sigma.
  const geom::Model m = am::cylinder_side(1, 2);
  const geom::Surface& s = *m.faces[0].surface;
  surface::detail::LocalMesh lm;
  const int nu = 24, nv = 8;
  auto id = [&](int i, int j) { return j * (nu + 1) + i; };
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) {
      const bool boundary = i == 0 || j == 0 || i == nu || j == nv;
      geom::Vec2 uv{2 * am::kPi * i / nu, 2.0 * j / nv};
      if (!boundary)
        uv += geom::Vec2(0.08 * std::sin(7.0 * i + 3 * j), 0.07 * std::cos(5.0 * j + i));
      lm.uv.push_back(uv);
      lm.p.push_back(s.point(uv.x, uv.y));
      lm.global.push_back(boundary ? id(i, j) : -1);
      lm.fixed.push_back(boundary);
      lm.scale.push_back(1.0);
    }
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      lm.tris.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      lm.tris.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  auto worst = [&] {
    double q = 1;
    for (const auto& t : lm.tris)
      q = std::min(q, surface::detail::q3(lm.p[t[0]], lm.p[t[1]], lm.p[t[2]]));
    return q;
  };
  const double before = worst();
  const auto boundary_uv = lm.uv;
  surface::detail::improve3d(lm, s, 4, /*collapse=*/false);
  CHECK(worst() >= before);
  for (std::size_t v = 0; v < lm.uv.size(); ++v) {
    const geom::Vec3 on = s.point(lm.uv[v].x, lm.uv[v].y);
    CHECK(glm::length(on - lm.p[v]) <= 1e-12);
    if (lm.fixed[v]) CHECK(lm.uv[v] == boundary_uv[v]);
  }
  for (const auto& t : lm.tris) {
    const geom::Vec2 a = lm.uv[t[0]], b = lm.uv[t[1]], c = lm.uv[t[2]];
    CHECK((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0);
  }
}

TEST_CASE("surface pipeline: every analytic model meshes on its surface, closed where it is",
          "[surface][pipeline]") {
  for (const geom::Model& m : all_models()) {
    INFO("surface " << geom::to_string(m.faces[0].kind));
    surface::MeshOptions o;
    o.size = surface::default_size(m);
    o.threads = 1;
    const surface::MeshResult r = surface::mesh_model(m, o);
    REQUIRE(r.failed.empty());
    REQUIRE(!r.mesh.triangles.empty());
    const double D = m.bbox.diagonal();
    double far = 0;
    for (const geom::Vec3& p : r.mesh.points) far = std::max(far, am::distance_to_surface(m, p));
    CHECK(far <= 1e-9 * D);
    const surface::TopologyReport t = surface::check_topology(r.mesh);
    CHECK(t.non_manifold_edges == 0);
    CHECK(t.inconsistent_edges == 0);
    if (m.shells[0].closed) CHECK(t.free_edges == 0);
    CHECK(r.unit_edge_share() >= 0.9);
    const surface::QualityReport q = surface::measure_quality(r.mesh);
    CHECK(q.share_Q_lt_1_5 >= 0.95);
  }
}

// ---- the face metric (surface/src/face_metric.h) -----------------------------------------

namespace {
// The exact (u,v) metric the face metric caches, in mesher2d's frame (v scaled by k:
// M' = S^-T M S^-1 with S = diag(1, k)).
uvmesh::m2d::Metric2 exact_in_mesher_frame(const param::FaceSizeField& field, double u, double v,
                                           double k) {
  const param::Metric2 m = field.metric_uv(u, v);
  return {m(0, 0), m(0, 1) / k, m(1, 1) / (k * k)};
}
}  // namespace

TEST_CASE("face metric: a cylinder band is scaled to isotropic, and the metric follows J^T M3 J",
          "[surface][face_metric]") {
  // Uniform size h on a cylinder of radius r: M_uv = diag(r^2, 1) / h^2, so v is scaled by
  // 1/r and mesher2d sees the isotropic metric I r^2 / h^2.
  const double r = 0.2, h = 0.05;
  const geom::Model m = am::cylinder_side(r, 2);
  const param::SizeSpec spec = uniform(h);
  const param::FaceSizeField field(*m.faces[0].surface, m.faces[0].uv_box, spec, 0);
  surface::detail::FaceMetric fm(field, m.faces[0], /*has_pole=*/false);
  CHECK(fm.vscale() == Approx(1 / r).epsilon(1e-6));
  const uvmesh::m2d::SizeSpec ms = fm.mesher_size();
  REQUIRE(ms.kind == uvmesh::m2d::SizeSpec::Kind::Metric);
  for (double u : {0.1, 1.7, 4.0, 6.2})
    for (double v : {0.05, 0.9, 1.95}) {
      const uvmesh::m2d::Vec2 p = fm.to_mesher({u, v});
      const geom::Vec2 back = fm.from_mesher(p);
      CHECK(back.x == Approx(u).epsilon(1e-15));
      CHECK(back.y == Approx(v).epsilon(1e-15));
      const uvmesh::m2d::Metric2 got = ms.metric(p.x, p.y);
      const uvmesh::m2d::Metric2 want = exact_in_mesher_frame(field, u, v, fm.vscale());
      CHECK(got.m11 == Approx(r * r / (h * h)).epsilon(1e-3));
      CHECK(got.m22 == Approx(r * r / (h * h)).epsilon(1e-3));
      CHECK(std::abs(got.m12) <= 1e-6 * got.m11);
      CHECK(got.m11 == Approx(want.m11).epsilon(1e-3));
      CHECK(got.m22 == Approx(want.m22).epsilon(1e-3));
    }
  // The 3D metric a vertex is measured in: the field's, times mesher2d's boundary scale.
  const param::Metric3 a = fm.metric3({1.0, 1.0}, 1.0), b = fm.metric3({1.0, 1.0}, 4.0);
  const geom::Vec3 e{0.01, 0.02, 0.03};
  CHECK(b.length(e) == Approx(2 * a.length(e)).epsilon(1e-12));
}

TEST_CASE("face metric: a torus's grid follows the exact induced metric; poles are not scaled",
          "[surface][face_metric]") {
  const geom::Model t = am::torus(2, 0.5);
  param::SizeSpec spec = uniform(0.3);
  spec.angle_tol = am::kPi / 10;  // curvature sizes: the metric varies over the face
  const param::FaceSizeField field(*t.faces[0].surface, t.faces[0].uv_box, spec, 0);
  surface::detail::FaceMetric fm(field, t.faces[0], false);
  const uvmesh::m2d::SizeSpec ms = fm.mesher_size();
  for (double u = 0.05; u < 2 * am::kPi; u += 0.77)
    for (double v = 0.05; v < 2 * am::kPi; v += 0.61) {
      INFO("u " << u << " v " << v);
      const uvmesh::m2d::Vec2 p = fm.to_mesher({u, v});
      const uvmesh::m2d::Metric2 got = ms.metric(p.x, p.y);
      const uvmesh::m2d::Metric2 want = exact_in_mesher_frame(field, u, v, fm.vscale());
      // The grid interpolates between exact nodes, refined where it is off (kTol).
      CHECK(got.m11 == Approx(want.m11).epsilon(0.1));
      CHECK(got.m22 == Approx(want.m22).epsilon(0.1));
    }
  // A face with a pole keeps its (u,v) frame.
  const geom::Model s = am::sphere(1);
  const param::FaceSizeField sf(*s.faces[0].surface, s.faces[0].uv_box, uniform(0.2), 0);
  surface::detail::FaceMetric sm(sf, s.faces[0], /*has_pole=*/true);
  CHECK(sm.vscale() == 1.0);
}
