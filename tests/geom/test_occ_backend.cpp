// OCC back end: exact curvature and point-by-point agreement with the analytic back end
// on OCC primitives; derivatives against finite differences and pcurve/curve/surface
// consistency on every surface kind of the corpus; poles and loop orientation.
#include <BRepPrimAPI_MakeCone.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepPrimAPI_MakeTorus.hxx>
#include <catch2/catch.hpp>
#include <cmath>
#include <gp_Ax2.hxx>
#include <map>
#include <numbers>
#include <random>
#include <set>

#include "fd_check.h"
#include "uvmesh/geom/analytic.h"
#include "uvmesh/geom/occ.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/param/curvature.h"

using namespace uvmesh;
using geom::Vec2;
using geom::Vec3;

namespace {

const std::string kData = UVMESH_SHARED_DATA;

geom::Model load(const std::string& rel) {
  io::ReadOptions opt;
  opt.heal = false;
  io::ReadResult r = io::read_cad(kData + "/" + rel, opt);
  INFO(r.error);
  REQUIRE(r.ok);
  return std::move(r.model);
}

// Signed area of a loop in (u,v), from its pcurves sampled in traversal order.
double loop_area(const geom::Loop& l) {
  std::vector<Vec2> pts;
  for (const geom::EdgeUse& u : l.uses) {
    if (!u.pcurve) return 0.0;
    for (int k = 0; k < 16; ++k) {
      const double s = double(k) / 16;
      const double t = u.reversed ? u.range.at(1.0 - s) : u.range.at(s);
      pts.push_back(u.pcurve->point(t));
    }
  }
  double a = 0.0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const Vec2& p = pts[i];
    const Vec2& q = pts[(i + 1) % pts.size()];
    a += p.x * q.y - q.x * p.y;
  }
  return 0.5 * a;
}

}  // namespace

TEST_CASE("occ: curvature is exact on OCC sphere, cylinder, cone and torus",
          "[geom][occ][curvature]") {
  const gp_Ax2 ax(gp_Pnt(1, 2, 3), gp_Dir(0.2, -0.3, 1.0));
  const double R1 = 3.0, R2 = 1.0, H = 4.0;
  const double half_angle = std::atan((R1 - R2) / H);
  struct Case {
    TopoDS_Shape shape;
    geom::SurfaceKind kind;
  };
  const std::vector<Case> cases = {
      {BRepPrimAPI_MakeSphere(ax, 2.5).Shape(), geom::SurfaceKind::Sphere},
      {BRepPrimAPI_MakeCylinder(ax, 1.5, 5.0).Shape(), geom::SurfaceKind::Cylinder},
      {BRepPrimAPI_MakeCone(ax, R1, R2, H).Shape(), geom::SurfaceKind::Cone},
      {BRepPrimAPI_MakeTorus(ax, 5.0, 1.25).Shape(), geom::SurfaceKind::Torus}};
  const Vec3 origin(1, 2, 3), axis = glm::normalize(Vec3(0.2, -0.3, 1.0));
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> U(0.05, 0.95);
  for (const Case& c : cases) {
    const geom::Model m = geom::model_from_occ(c.shape, {});
    int checked = 0;
    for (const geom::Face& f : m.faces) {
      if (f.kind != c.kind) continue;
      INFO(to_string(f.kind));
      for (int t = 0; t < 100; ++t) {
        const double u = f.uv_box.u.at(U(rng)), v = f.uv_box.v.at(U(rng));
        const geom::SurfacePoint e = f.surface->eval(u, v);
        const param::Curvature k = param::principal_curvatures(e);
        const Vec3 rel = e.p - origin;
        const double radius =
            glm::length(rel - glm::dot(rel, axis) * axis);  // distance to the axis
        switch (c.kind) {
          case geom::SurfaceKind::Sphere:
            CHECK(std::abs(k.k1) == Approx(1 / 2.5));
            CHECK(std::abs(k.k2) == Approx(1 / 2.5));
            break;
          case geom::SurfaceKind::Cylinder:
            CHECK(std::abs(k.k1) == Approx(1 / 1.5));
            CHECK(k.k2 == Approx(0).margin(1e-12));
            break;
          case geom::SurfaceKind::Cone:
            CHECK(std::abs(k.k1) == Approx(std::cos(half_angle) / radius));
            CHECK(k.k2 == Approx(0).margin(1e-12));
            break;
          default: {  // torus: 1/r across the tube, cos(v)/(R + r cos v) = (radius - R)/(r radius)
                      // along
            const double ka = 1 / 1.25, kb = (radius - 5.0) / (1.25 * radius);
            CHECK(std::abs(k.k1) == Approx(std::max(ka, std::abs(kb))));
            CHECK(std::abs(k.k2) == Approx(std::min(ka, std::abs(kb))).margin(1e-12));
          }
        }
        ++checked;
      }
    }
    CHECK(checked > 0);
  }
}

TEST_CASE("occ: sphere face evaluates like the analytic sphere (same parametrisation)",
          "[geom][occ]") {
  const gp_Ax2 ax(gp_Pnt(0, 0, 0), gp_Dir(0, 0, 1), gp_Dir(1, 0, 0));
  const geom::Model m = geom::model_from_occ(BRepPrimAPI_MakeSphere(ax, 2.0).Shape(), {});
  auto ana = geom::make_sphere(geom::Frame{}, 2.0);
  REQUIRE(m.faces.size() == 1);
  const geom::Face& f = m.faces[0];
  CHECK(f.surface->u_periodic());
  CHECK(f.surface->u_period() == Approx(2 * std::numbers::pi));
  CHECK(f.surface->singular_sides() == (geom::kSideVMin | geom::kSideVMax));
  for (double u : {0.1, 1.0, 3.0, 5.5})
    for (double v : {-1.2, 0.0, 0.7}) {
      const auto a = f.surface->eval(u, v), b = ana->eval(u, v);
      CHECK(glm::length(a.p - b.p) < 1e-12);
      CHECK(glm::length(a.du - b.du) < 1e-12);
      CHECK(glm::length(a.dvv - b.dvv) < 1e-12);
    }
  // One seam edge used twice, two degenerate edges at the poles.
  const geom::ModelStats s = geom::compute_stats(m);
  CHECK(s.seam_edges == 1);
  CHECK(s.degenerate_edges == 2);
  CHECK(s.free_edges == 0);
}

TEST_CASE("occ: derivatives match finite differences on every corpus surface kind", "[geom][occ]") {
  // Together these cover planar, cylinder, cone, sphere, torus, bspline, bezier,
  // revolution, extrusion and offset surfaces.
  const std::vector<std::string> files = {
      "cad/occt_screw.step",     "cad/occt_spheres.stp",      "cad/gmsh_capot.brep",
      "cad/occt_cone_catia.igs", "cad/gmsh_t106_blade.step",  "cad/occt_offset_tube.igs",
      "cad/occt_bottle.brep",    "cad/gmsh_full_sphere.brep", "cad/occt_propeller.brep"};
  std::set<std::string> kinds;
  std::mt19937 rng(4);
  std::uniform_real_distribution<double> U(0.1, 0.9);
  for (const std::string& file : files) {
    const geom::Model m = load(file);
    const double diag = m.bbox.diagonal();
    for (std::size_t fi = 0; fi < m.faces.size(); ++fi) {
      const geom::Face& f = m.faces[fi];
      if (!f.surface) continue;
      kinds.insert(std::string(to_string(f.kind)));
      INFO(file << " face " << fi << " " << to_string(f.kind));
      for (int t = 0; t < 8; ++t) {
        const double u = f.uv_box.u.at(U(rng)), v = f.uv_box.v.at(U(rng));
        const double hu = 1e-5 * f.uv_box.u.length(), hv = 1e-5 * f.uv_box.v.length();
        // Errors relative to the model size; B-spline knots inside the stencil make the
        // second differences O(h) instead of O(h^2), hence 1e-7 rather than 1e-9.
        CHECK(test::surface_fd_error(*f.surface, u, v, hu, hv, diag) < 1e-7);
      }
    }
    for (std::size_t ei = 0; ei < m.edges.size(); ++ei) {
      const geom::Edge& e = m.edges[ei];
      if (e.degenerate) continue;
      INFO(file << " edge " << ei);
      const double t = e.range.at(0.37), h = 1e-5 * e.range.length();
      CHECK(test::curve_fd_error(*e.curve, t, h, diag) < 1e-7);
    }
  }
  for (const char* k : {"planar", "cylinder", "cone", "sphere", "torus", "bspline", "bezier",
                        "revolution", "extrusion", "offset"})
    CHECK(kinds.count(k) == 1);
}

TEST_CASE("occ: pcurves map onto their edges through the surface; loops are oriented",
          "[geom][occ][seam]") {
  const std::vector<std::string> files = {"cad/occt_engine_block.brep", "cad/nist_ctc_01.stp",
                                          "cad/occt_screw.step",        "cad/gmsh_torus1.brep",
                                          "cad/gmsh_cone1.brep",        "cad/occt_spheres.stp",
                                          "cad/gmsh_cyl_loop_seam.brep"};
  for (const std::string& file : files) {
    const geom::Model m = load(file);
    const double diag = m.bbox.diagonal();
    for (std::size_t fi = 0; fi < m.faces.size(); ++fi) {
      const geom::Face& f = m.faces[fi];
      INFO(file << " face " << fi);
      for (const geom::Loop& l : f.loops) {
        for (const geom::EdgeUse& u : l.uses) {
          const geom::Edge& e = m.edges[u.edge];
          REQUIRE(u.pcurve);
          for (double s : {0.0, 0.3, 0.5, 1.0}) {
            const double t = u.range.at(s);
            const Vec2 uv = u.pcurve->point(t);
            const Vec3 on_surface = f.surface->point(uv.x, uv.y);
            const Vec3 on_curve = e.degenerate ? m.vertices[e.v0].p : e.curve->point(t);
            CHECK(glm::length(on_surface - on_curve) <= std::max(10 * e.tol, 1e-7 * diag));
          }
        }
        // Outer loops run counter-clockwise in (u,v), holes clockwise (faces taken in
        // their natural orientation; Face::reversed carries the material side).
        if (f.loops.size() > 1 || !f.surface->u_periodic()) {
          const double a = loop_area(l);
          if (l.outer)
            CHECK(a > 0.0);
          else
            CHECK(a < 0.0);
        }
      }
    }
  }
}

TEST_CASE("occ: poles are explicit -- degenerate edges lie on singular sides",
          "[geom][occ][pole]") {
  for (const std::string file :
       {"cad/gmsh_full_sphere.brep", "cad/occt_spheres.stp", "cad/gmsh_cone1.brep"}) {
    const geom::Model m = load(file);
    int poles = 0;
    for (const geom::Face& f : m.faces)
      for (const geom::Loop& l : f.loops)
        for (const geom::EdgeUse& u : l.uses) {
          if (!m.edges[u.edge].degenerate) continue;
          ++poles;
          INFO(file);
          CHECK(f.surface->singular_sides() != 0u);
          // The pcurve of a pole runs along a side of the parameter box.
          const Vec2 a = u.pcurve->point(u.range.lo), b = u.pcurve->point(u.range.hi);
          const geom::Box2 bx = f.uv_box;
          const double tu = 1e-9 * bx.u.length() + 1e-12, tv = 1e-9 * bx.v.length() + 1e-12;
          const bool on_v_side = std::abs(a.y - b.y) <= tv &&
                                 (std::abs(a.y - bx.v.lo) <= tv || std::abs(a.y - bx.v.hi) <= tv);
          const bool on_u_side = std::abs(a.x - b.x) <= tu &&
                                 (std::abs(a.x - bx.u.lo) <= tu || std::abs(a.x - bx.u.hi) <= tu);
          CHECK((on_u_side || on_v_side));
        }
    CHECK(poles > 0);
  }
}
