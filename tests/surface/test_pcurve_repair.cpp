// Faces whose pcurves disagree with their 3D edges (BRepCheck-invalid files): a pcurve
// bulging across the face so that the (u,v) boundary crosses itself, a pcurve shifted
// by a period on a periodic surface, on planes, cylinders and a B-spline pipe swept
// along a multi-turn helix. Each model is a closed solid built with the OCC modeling API
// and corrupted with BRep_Builder::UpdateEdge; mesh_model must mesh every face,
// watertight, on the surfaces, and say which face and edges it repaired and how.
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepLib.hxx>
#include <BRepOffsetAPI_MakePipeShell.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <GC_MakeCircle.hxx>
#include <Geom2d_BSplineCurve.hxx>
#include <Geom2d_Line.hxx>
#include <Geom_CylindricalSurface.hxx>
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
template <class Make>
void corrupt_pcurve(const TopoDS_Shape& shape, int fi, int ei, Make&& make) {
  TopTools_IndexedMapOfShape faces, edges;
  TopExp::MapShapes(shape, TopAbs_FACE, faces);
  const TopoDS_Face face = TopoDS::Face(faces(fi));
  TopExp::MapShapes(face, TopAbs_EDGE, edges);
  const TopoDS_Edge edge = TopoDS::Edge(edges(ei));
  REQUIRE(!BRep_Tool::IsClosed(edge, face));  // a seam has two pcurves
  double f = 0, l = 0;
  const Handle(Geom2d_Curve) c = pcurve_of(edge, face, f, l);
  REQUIRE(!c.IsNull());
  BRep_Builder().UpdateEdge(edge, make(c, f, l), face, BRep_Tool::Tolerance(edge));
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
  for (const auto& f : x.r.failed) INFO("face " << f.face << ": " << f.reason);
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
  INFO("expected a warning containing: " << repair);
  for (const std::string& w : x.r.warnings) INFO("warning: " << w);
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
