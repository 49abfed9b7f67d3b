// Faces whose pcurves disagree with their 3D edges (BRepCheck-invalid files): a pcurve
// bulging across the face so that the (u,v) boundary crosses itself, a pcurve shifted
// by a period on a periodic surface, on planes, cylinders and a B-spline pipe swept
// along a multi-turn helix. Each model is a closed solid built with the OCC modeling API
// and corrupted with BRep_Builder::UpdateEdge; mesh_model must mesh every face,
// watertight, on the surfaces, and say which face and edges it repaired and how.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepLib.hxx>
#include <BRepOffsetAPI_MakePipeShell.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GC_MakeCircle.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_Circle.hxx>
#include <Geom_CylindricalSurface.hxx>
#include <Geom_Plane.hxx>
#include <Geom_Surface.hxx>
#include <TColStd_Array1OfInteger.hxx>
#include <TColStd_Array1OfReal.hxx>
#include <TColgp_Array1OfPnt2d.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Solid.hxx>
#include <catch2/catch.hpp>
#include <cmath>
#include <gp_Circ.hxx>
#include <numbers>
#include <string>

#include "uvmesh/geom/occ.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;

namespace {

constexpr double kPi = std::numbers::pi;

// The pcurve of `edge` on `face`, and its range.
Handle(Geom2d_Curve)
    pcurve_of(const TopoDS_Edge& edge, const TopoDS_Face& face, double& f, double& l) {
  return BRep_Tool::CurveOnSurface(edge, face, f, l);
}

// A quadratic B-spline over [f, l] with the pcurve's ends, whose middle is pushed by
// `bulge` (in (u,v)) from the chord's middle: the same ends, so the loop still closes in
// (u,v), but its interior strays from the 3D edge.
Handle(Geom2d_Curve)
    bulging(const Handle(Geom2d_Curve) & c, double f, double l, const gp_Vec2d& bulge) {
  const gp_Pnt2d a = c->Value(f), b = c->Value(l);
  const gp_Pnt2d m((a.X() + b.X()) / 2 + 2 * bulge.X(), (a.Y() + b.Y()) / 2 + 2 * bulge.Y());
  TColgp_Array1OfPnt2d poles(1, 3);
  poles(1) = a, poles(2) = m, poles(3) = b;
  TColStd_Array1OfReal knots(1, 2);
  knots(1) = f, knots(2) = l;
  TColStd_Array1OfInteger mults(1, 2);
  mults(1) = 3, mults(2) = 3;
  return new Geom2d_BSplineCurve(poles, knots, mults, 2);
}

// Replaces the pcurve of edge number `ei` (TopExp map of the face's edges, from 1) on
// face number `fi` (map of the shape's faces, from 1) by make(old pcurve, f, l).
// tol > 0: the edge's tolerance becomes tol (a sloppy edge, within whose tolerance the
// corrupted pcurve still lies).
template <class Make>
void corrupt_pcurve(const TopoDS_Shape& shape, int fi, int ei, Make&& make, double tol = 0) {
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  const TopoDS_Face face = TopoDS::Face(faces(fi));
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  const TopoDS_Edge edge = TopoDS::Edge(edges(ei));
  REQUIRE(!BRep_Tool::IsClosed(edge, face));  // a seam has two pcurves
  double f = 0, l = 0;
  const Handle(Geom2d_Curve) c = pcurve_of(edge, face, f, l);
  REQUIRE(!c.IsNull());
  BRep_Builder().UpdateEdge(edge, make(c, f, l), face, tol > 0 ? tol : BRep_Tool::Tolerance(edge));
}

struct Meshed {
  surface::MeshResult r;
  geom::Model m;
};

Meshed mesh(const TopoDS_Shape& shape) {
  Meshed out{{}, geom::model_from_occ(shape, {})};
  surface::MeshOptions o;
  o.size = surface::default_size(out.m);
  o.threads = 1;
  out.r = surface::mesh_model(out.m, o);
  return out;
}

// Every face meshed, closed, on the surfaces within the chordal tolerance, and a
// warning that names the repair.
void check_meshed_and_repaired(const Meshed& x, const std::string& repair) {
  std::string failed;
  for (const auto& f : x.r.failed)
    failed += "face " + std::to_string(f.face) + ": " + f.reason + "\n";
  INFO(failed);
  REQUIRE(x.r.failed.empty());
  const surface::TopologyReport t = surface::check_topology(x.r.mesh);
  CHECK(t.free_edges == 0);
  CHECK(t.non_manifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(surface::find_self_intersections(x.r.mesh, 20, 1).intersecting_pairs == 0);
  const surface::ChordalReport c = surface::measure_chordal(x.r.mesh, x.m, 1);
  CHECK(c.not_converged == 0);
  CHECK(c.max <= surface::default_size(x.m).chordal_tol);
  bool named = false;
  for (const std::string& w : x.r.warnings) named = named || w.find(repair) != std::string::npos;
  std::string warnings;
  for (const std::string& w : x.r.warnings) warnings += "warning: " + w + "\n";
  INFO("expected a warning containing: " << repair << "\n" << warnings);
  CHECK(named);
}

}  // namespace

TEST_CASE("pcurve repair: a box face whose edge's pcurve bulges across the face",
          "[surface][pcurve_repair]") {
  // The bulge is 1.5 face widths toward the inside of the face: the pcurve crosses the
  // opposite edge's.
  for (int side : {-1, 1}) {
    TopoDS_Shape s = BRepPrimAPI_MakeBox(10, 10, 10).Shape();
    corrupt_pcurve(s, 1, 1, [&](const Handle(Geom2d_Curve) & c, double f, double l) {
      const gp_Vec2d d(c->Value(f), c->Value(l));
      const gp_Vec2d n(-d.Y() / d.Magnitude(), d.X() / d.Magnitude());
      return bulging(c, f, l, n * (15.0 * side));
    });
    INFO("bulge side " << side);
    const Meshed x = mesh(s);
    CHECK(!x.m.faces[0].valid);
    check_meshed_and_repaired(x, "face 0: edge");
    check_meshed_and_repaired(x, "recomputed by projecting the 3D edge nodes onto the surface");
  }
}

TEST_CASE("pcurve repair: a cylinder's side whose bottom circle's pcurve bulges past the top",
          "[surface][pcurve_repair]") {
  TopoDS_Shape s = BRepPrimAPI_MakeCylinder(3, 4).Shape();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  // Face 1 is the side; its edges: the seam, the two circles.
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(faces(1), TopAbs_EDGE, edges);
  int circle = 0;
  for (int i = 1; i <= edges.Extent() && circle == 0; ++i)
    if (!BRep_Tool::IsClosed(TopoDS::Edge(edges(i)), TopoDS::Face(faces(1)))) circle = i;
  REQUIRE(circle > 0);
  corrupt_pcurve(s, 1, circle, [](const Handle(Geom2d_Curve) & c, double f, double l) {
    return bulging(c, f, l, gp_Vec2d(0.0, c->Value(f).Y() < 2 ? 6.0 : -6.0));
  });
  const Meshed x = mesh(s);
  check_meshed_and_repaired(x, "face 0: edge");
}

TEST_CASE("pcurve repair: a cylinder's side whose circle's pcurve is shifted by a period",
          "[surface][pcurve_repair]") {
  TopoDS_Shape s = BRepPrimAPI_MakeCylinder(3, 4).Shape();
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  TopExp::MapShapes(faces(1), TopAbs_EDGE, edges);
  int circle = 0;
  for (int i = 1; i <= edges.Extent() && circle == 0; ++i)
    if (!BRep_Tool::IsClosed(TopoDS::Edge(edges(i)), TopoDS::Face(faces(1)))) circle = i;
  corrupt_pcurve(s, 1, circle, [](const Handle(Geom2d_Curve) & c, double, double) {
    return Handle(Geom2d_Curve)::DownCast(c->Translated(gp_Vec2d(2 * kPi, 0.0)));
  });
  const Meshed x = mesh(s);
  check_meshed_and_repaired(x, "face 0: edge");
}

namespace {

// A solid tube of radius r swept along a helix of radius R, pitch p and `turns` turns
// (the helix is a Geom2d_Line on a cylinder): one B-spline face winding around the
// axis, two planar end caps.
TopoDS_Shape helical_spring(double R, double r, double p, double turns) {
  const Handle(Geom_CylindricalSurface) cyl = new Geom_CylindricalSurface(gp_Ax3(), R);
  const gp_Dir2d dir(2 * kPi, p);
  const Handle(Geom2d_Line) line = new Geom2d_Line(gp_Pnt2d(0, 0), dir);
  const double len = turns * std::hypot(2 * kPi, p);
  TopoDS_Edge helix = BRepBuilderAPI_MakeEdge(line, cyl, 0.0, len);
  BRepLib::BuildCurves3d(helix);
  const TopoDS_Wire spine = BRepBuilderAPI_MakeWire(helix);
  // The profile: a circle at the helix's start, in the plane normal to its tangent.
  gp_Pnt p0;
  gp_Vec t0;
  double f = 0, l = 0;
  BRep_Tool::Curve(helix, f, l)->D1(f, p0, t0);
  const TopoDS_Edge ce = BRepBuilderAPI_MakeEdge(GC_MakeCircle(gp_Ax2(p0, gp_Dir(t0)), r).Value());
  const TopoDS_Wire profile = BRepBuilderAPI_MakeWire(ce);
  BRepOffsetAPI_MakePipeShell pipe(spine);
  pipe.SetMode(Standard_True);  // Frenet: the profile turns with the helix
  pipe.Add(profile);
  pipe.Build();
  REQUIRE(pipe.IsDone());
  REQUIRE(pipe.MakeSolid());
  return pipe.Shape();
}

}  // namespace

TEST_CASE("pcurve repair: a spring swept along a multi-turn helix with a corrupted pcurve",
          "[surface][pcurve_repair]") {
  TopoDS_Shape s = helical_spring(10, 1.5, 5, 3);
  {
    // Consistent first: the swept face meshes without a repair.
    const Meshed x = mesh(s);
    REQUIRE(x.r.failed.empty());
    CHECK(surface::check_topology(x.r.mesh).free_edges == 0);
    for (const std::string& w : x.r.warnings) CHECK(w.find("projecting") == std::string::npos);
  }
  // The swept face is the one with the most edges (seam, two end circles); the end
  // circle's pcurve on it is pushed across the whole strip.
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  int swept = 0, most = 0;
  for (int i = 1; i <= faces.Extent(); ++i) {
    TopTools_IndexedMapOfShape e;
    TopExp::MapShapes(faces(i), TopAbs_EDGE, e);
    if (e.Extent() > most) most = e.Extent(), swept = i;
  }
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(faces(swept), TopAbs_EDGE, edges);
  int circle = 0;
  for (int i = 1; i <= edges.Extent() && circle == 0; ++i)
    if (!BRep_Tool::IsClosed(TopoDS::Edge(edges(i)), TopoDS::Face(faces(swept)))) circle = i;
  REQUIRE(circle > 0);
  double u0 = 0, u1 = 0, v0 = 0, v1 = 0;
  BRep_Tool::Surface(TopoDS::Face(faces(swept)))->Bounds(u0, u1, v0, v1);
  corrupt_pcurve(s, swept, circle, [&](const Handle(Geom2d_Curve) & c, double f, double l) {
    // Across the strip, in the direction along the spine (the longer side of (u,v)).
    const gp_Pnt2d a = c->Value(f), b = c->Value(l);
    const gp_Vec2d along = std::abs(b.X() - a.X()) > std::abs(b.Y() - a.Y())
                               ? gp_Vec2d(0.0, 0.3 * (v1 - v0))
                               : gp_Vec2d(0.3 * (u1 - u0), 0.0);
    const double inward =
        (std::abs(b.X() - a.X()) > std::abs(b.Y() - a.Y()) ? (a.Y() < 0.5 * (v0 + v1) ? 1 : -1)
                                                           : (a.X() < 0.5 * (u0 + u1) ? 1 : -1));
    return bulging(c, f, l, along * inward);
  });
  const Meshed x = mesh(s);
  check_meshed_and_repaired(x, "recomputed by projecting the 3D edge nodes onto the surface");
}

// ---- Faces whose (u,v) boundary stays unusable after the repair: meshed in the
// least-squares plane of their boundary nodes (face_chart.cpp), or refused with a reason.

namespace {

// The index (TopExp map, from 1) of the first edge of face fi whose 3D curve is a circle
// (or an arc of one).
int circle_edge(const TopoDS_Shape& shape, int fi) {
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  TopExp::MapShapes(faces(fi), TopAbs_EDGE, edges);
  for (int i = 1; i <= edges.Extent(); ++i) {
    double f = 0, l = 0;
    const Handle(Geom_Curve) c = BRep_Tool::Curve(TopoDS::Edge(edges(i)), f, l);
    if (!c.IsNull() && !Handle(Geom_Circle)::DownCast(c).IsNull()) return i;
  }
  return 0;
}

// The face (map index) of a planar face at height z.
int plane_face_at(const TopoDS_Shape& shape, double z) {
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  for (int i = 1; i <= faces.Extent(); ++i) {
    const Handle(Geom_Plane) pl =
        Handle(Geom_Plane)::DownCast(BRep_Tool::Surface(TopoDS::Face(faces(i))));
    if (!pl.IsNull() && std::abs(pl->Location().Z() - z) < 1e-9 &&
        std::abs(std::abs(pl->Axis().Direction().Z()) - 1) < 1e-9)
      return i;
  }
  return 0;
}

bool warned(const Meshed& x, const std::string& what) {
  for (const std::string& w : x.r.warnings)
    if (w.find(what) != std::string::npos) return true;
  return false;
}

}  // namespace

TEST_CASE(
    "plane chart: a planar face with a hole whose pcurve crosses the outline within "
    "its edge's tolerance",
    "[surface][pcurve_repair][plane_chart]") {
  // A 10 x 10 x 2 slab with a hole of radius 2 whose wall is 0.3 from one side. On the top
  // face the hole circle's pcurve is moved 0.5 toward that side, across the outline, and
  // the circle's tolerance set to 0.6: the pcurve lies within the edge's tolerance, so the
  // (u,v) repair rightly leaves it (it is not wrong by the model's own measure), splitting
  // the crossing pieces cannot part the two (u,v) curves, and the face has two loops, so
  // no boundary-only triangulation applies: only another chart can mesh it.
  const double hx = 2.3, r = 2.0;
  TopoDS_Wire outer =
      BRepBuilderAPI_MakeWire(BRepBuilderAPI_MakeEdge(gp_Pnt(0, 0, 0), gp_Pnt(10, 0, 0)),
                              BRepBuilderAPI_MakeEdge(gp_Pnt(10, 0, 0), gp_Pnt(10, 10, 0)),
                              BRepBuilderAPI_MakeEdge(gp_Pnt(10, 10, 0), gp_Pnt(0, 10, 0)),
                              BRepBuilderAPI_MakeEdge(gp_Pnt(0, 10, 0), gp_Pnt(0, 0, 0)));
  const TopoDS_Edge ce =
      BRepBuilderAPI_MakeEdge(gp_Circ(gp_Ax2(gp_Pnt(hx, 5, 0), gp_Dir(0, 0, 1)), r));
  TopoDS_Wire hole = BRepBuilderAPI_MakeWire(ce);
  hole.Reverse();
  BRepBuilderAPI_MakeFace mf(outer, Standard_True);
  mf.Add(hole);
  REQUIRE(mf.IsDone());
  const TopoDS_Shape s = BRepPrimAPI_MakePrism(mf.Face(), gp_Vec(0, 0, 2)).Shape();
  const int top = plane_face_at(s, 2.0);
  REQUIRE(top > 0);
  const int circle = circle_edge(s, top);
  REQUIRE(circle > 0);
  {
    const Meshed x = mesh(s);  // consistent: no chart
    REQUIRE(x.r.failed.empty());
    CHECK(!warned(x, "plane chart"));
  }
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  const Handle(Geom_Plane) pl =
      Handle(Geom_Plane)::DownCast(BRep_Tool::Surface(TopoDS::Face(faces(top))));
  const gp_Vec shift(-0.5, 0, 0);  // toward the side x = 0, in (u,v) of the top plane
  const gp_Vec2d duv(shift.Dot(gp_Vec(pl->Position().XDirection())),
                     shift.Dot(gp_Vec(pl->Position().YDirection())));
  corrupt_pcurve(
      s, top, circle,
      [&](const Handle(Geom2d_Curve) & c, double, double) {
        return Handle(Geom2d_Curve)::DownCast(c->Translated(duv));
      },
      0.6);
  const Meshed x = mesh(s);
  check_meshed_and_repaired(x, "meshed in a least-squares plane chart (surface normals within 0");
  CHECK(warned(x, "cross"));
}

namespace {

// A cylinder sector (radius R, height h, angle a) whose bottom arc's pcurve on the side
// is moved by `lift` in v, past the top, with the arc's tolerance set to tol (a sloppy
// edge within whose tolerance the pcurve lies, so that the (u,v) repair leaves it).
TopoDS_Shape sector_with_lifted_arc(double R, double h, double a, double lift, double tol) {
  TopoDS_Shape s = BRepPrimAPI_MakeCylinder(R, h, a).Shape();
  TopTools_IndexedMapOfShape faces;
  TopExp::MapShapes(s, TopAbs_FACE, faces);
  int side = 0;
  for (int i = 1; i <= faces.Extent() && side == 0; ++i)
    if (!Handle(Geom_CylindricalSurface)::DownCast(BRep_Tool::Surface(TopoDS::Face(faces(i))))
             .IsNull())
      side = i;
  REQUIRE(side > 0);
  TopTools_IndexedMapOfShape edges;
  TopExp::MapShapes(faces(side), TopAbs_EDGE, edges);
  int bottom = 0;
  for (int i = 1; i <= edges.Extent() && bottom == 0; ++i) {
    double f = 0, l = 0;
    const Handle(Geom_Curve) c = BRep_Tool::Curve(TopoDS::Edge(edges(i)), f, l);
    if (!Handle(Geom_Circle)::DownCast(c).IsNull() && std::abs(c->Value(f).Z()) < 1e-9) bottom = i;
  }
  REQUIRE(bottom > 0);
  corrupt_pcurve(
      s, side, bottom,
      [&](const Handle(Geom2d_Curve) & c, double, double) {
        return Handle(Geom2d_Curve)::DownCast(c->Translated(gp_Vec2d(0.0, lift)));
      },
      tol);
  return s;
}

}  // namespace

TEST_CASE("plane chart: a slightly curved face whose pcurves cross within a sloppy tolerance",
          "[surface][pcurve_repair][plane_chart]") {
  // A 0.5 rad sector of a cylinder of radius 20 (the side's normal turns 14 degrees either
  // way from the middle): the bottom arc's pcurve lifted 1.2 heights, past the top.
  const Meshed x = mesh(sector_with_lifted_arc(20, 1, 0.5, 1.2, 1.5));
  check_meshed_and_repaired(x, "; meshed in a least-squares plane chart (surface normals within 1");
}

TEST_CASE("plane chart: refused on most of a cylinder whose pcurves cross",
          "[surface][pcurve_repair][plane_chart]") {
  // A 286-degree sector, its bottom arc's pcurve lifted past the top. The side is no
  // graph over any plane: the chart is refused, naming the normal's turn, and the last
  // fallback (the boundary triangulation of the one-loop side) is tried as before.
  const Meshed x = mesh(sector_with_lifted_arc(5, 2, 5.0, 2.5, 3.0));
  std::string said;
  for (const auto& f : x.r.failed) said += f.reason + "\n";
  for (const std::string& w : x.r.warnings) said += w + "\n";
  INFO(said);
  CHECK(said.find("not meshed in a least-squares plane chart: the surface normal turns") !=
        std::string::npos);
  CHECK(said.find("degrees from the least-squares plane's") != std::string::npos);
  CHECK(said.find("not triangulated from its boundary either") != std::string::npos);
  CHECK(!warned(x, "; meshed in a least-squares plane chart"));
}
