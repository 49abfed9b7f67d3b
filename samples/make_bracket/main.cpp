// make_bracket OUT.step -- builds the bundled sample model samples/data/bracket.step.
//
// An L-shaped mounting bracket in millimetres, one solid, built with OpenCASCADE's
// modeling API and written as STEP AP214 (length unit mm):
//   - base plate 100 x 60 x 8 lying on z = 0, upright plate 8 x 60 x 70 standing at x = 0;
//   - the bend filleted inside (R6) and outside (R14 = R6 + thickness, concentric);
//   - the free corners of both plates rounded (R12);
//   - base plate: one plain through hole (d 9) and one counterbored hole (d 9, counterbore
//     d 16 x 4 deep) -- vertical cylinders, a flat annulus;
//   - upright plate: an obround slot (width 10, 30 long) and two through holes (d 8) whose
//     outer rims are broken by an R1 fillet (tori).
// Planes, cylinders and tori, 26 faces, bounding-box diagonal ~136 mm.
//
// Errors: one line on stderr, exit status 1, and no output file (the model is written to
// a temporary file beside OUT, which is renamed only once complete). The STEP header has a
// fixed time stamp, so the output is the same on every run.
#include <unistd.h>

#include <APIHeaderSection_MakeHeader.hxx>
#include <BRepAdaptor_Curve.hxx>
#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeEdge.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_MakeWire.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakePrism.hxx>
#include <BRep_Tool.hxx>
#include <GC_MakeArcOfCircle.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <STEPControl_Controller.hxx>
#include <STEPControl_Writer.hxx>
#include <Standard_Failure.hxx>
#include <StepData_StepModel.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Shell.hxx>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <functional>
#include <gp_Ax2.hxx>
#include <gp_Circ.hxx>
#include <gp_Pnt.hxx>
#include <gp_Vec.hxx>
#include <iostream>
#include <stdexcept>
#include <string>
#include <system_error>
#include <vector>

namespace {

// Dimensions (mm).
constexpr double kT = 8.0;             // plate thickness
constexpr double kBaseLength = 100.0;  // base plate along x
constexpr double kWidth = 60.0;        // both plates along y
constexpr double kHeight = 70.0;       // upright plate along z
constexpr double kBendInner = 6.0;     // inner bend radius; the outer one is kBendInner + kT
constexpr double kCorner = 12.0;       // rounded free corners
constexpr double kHoleD = 9.0;         // base plate holes (M8 clearance)
constexpr double kCboreD = 16.0, kCboreDepth = 4.0;
constexpr double kUprightHoleD = 8.0;  // upright plate holes
constexpr double kRimBreak = 1.0;      // fillet on the upright holes' outer rims
constexpr double kSlotW = 10.0, kSlotZ0 = 25.0,
                 kSlotZ1 = 55.0;  // slot: width, extent in z (ends included)
constexpr double kTol = 1e-6;

bool near(double a, double b) {
  return std::abs(a - b) < kTol;
}

using EdgeTest = std::function<bool(const TopoDS_Edge&)>;

// The distinct edges of `s` that pass `test`; exactly `expected` of them, else an error
// naming `what` (a model change that moves an edge must not silently skip a fillet).
std::vector<TopoDS_Edge> edges_where(const TopoDS_Shape& s, const EdgeTest& test,
                                     std::size_t expected, const char* what) {
  TopTools_IndexedMapOfShape map;
  TopExp::MapShapes(s, TopAbs_EDGE, map);
  std::vector<TopoDS_Edge> out;
  for (int i = 1; i <= map.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(map(i));
    if (!BRep_Tool::Degenerated(e) && test(e)) out.push_back(e);
  }
  if (out.size() != expected)
    throw std::runtime_error(std::string("found ") + std::to_string(out.size()) + " edges for " +
                             what + ", expected " + std::to_string(expected));
  return out;
}

// A straight edge parallel to axis `along` (0 x, 1 y, 2 z) whose other two coordinates are
// `a` and `b` (in axis order, e.g. x and z for an edge along y).
EdgeTest line_along(int along, double a, double b) {
  return [=](const TopoDS_Edge& e) {
    BRepAdaptor_Curve c(e);
    if (c.GetType() != GeomAbs_Line) return false;
    const gp_Pnt p = c.Value(c.FirstParameter()), q = c.Value(c.LastParameter());
    double other[2];
    int k = 0;
    for (int axis = 0; axis < 3; ++axis) {
      if (axis == along) continue;
      if (!near(p.Coord(axis + 1), q.Coord(axis + 1))) return false;
      other[k++] = p.Coord(axis + 1);
    }
    return near(other[0], a) && near(other[1], b);
  };
}

// A circular edge of radius r centred at `centre`.
EdgeTest circle_at(const gp_Pnt& centre, double r) {
  return [=](const TopoDS_Edge& e) {
    BRepAdaptor_Curve c(e);
    if (c.GetType() != GeomAbs_Circle) return false;
    const gp_Circ circ = c.Circle();
    return near(circ.Radius(), r) && circ.Location().Distance(centre) < kTol;
  };
}

TopoDS_Shape checked(BRepAlgoAPI_BooleanOperation& op, const char* what) {
  op.Build();
  if (!op.IsDone() || op.HasErrors())
    throw std::runtime_error(std::string("boolean operation failed: ") + what);
  return op.Shape();
}

TopoDS_Shape fuse(const TopoDS_Shape& a, const TopoDS_Shape& b, const char* what) {
  BRepAlgoAPI_Fuse op(a, b);
  TopoDS_Shape s = checked(op, what);
  // The two plates share the face strip x in [0, 8]: merge the coplanar faces they leave.
  op.SimplifyResult();
  return op.Shape().IsNull() ? s : op.Shape();
}

TopoDS_Shape cut(const TopoDS_Shape& a, const TopoDS_Shape& tool, const char* what) {
  BRepAlgoAPI_Cut op(a, tool);
  return checked(op, what);
}

TopoDS_Shape fillet(const TopoDS_Shape& s,
                    const std::vector<std::pair<double, std::vector<TopoDS_Edge>>>& sets,
                    const char* what) {
  BRepFilletAPI_MakeFillet mk(s);
  for (const auto& [r, edges] : sets)
    for (const TopoDS_Edge& e : edges) mk.Add(r, e);
  mk.Build();
  if (!mk.IsDone()) throw std::runtime_error(std::string("fillet failed: ") + what);
  return mk.Shape();
}

// Vertical through cylinder (axis +z) at (x, y) from z0 to z1.
TopoDS_Shape z_cylinder(double x, double y, double d, double z0, double z1) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(x, y, z0), gp::DZ()), d / 2, z1 - z0).Shape();
}

// Horizontal through cylinder (axis +x) at (y, z) through the upright plate.
TopoDS_Shape x_cylinder(double y, double z, double d) {
  return BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(-1.0, y, z), gp::DX()), d / 2, kT + 2.0).Shape();
}

// The slot cutter: an obround (two straight sides, two half circles) in the plane
// x = -1, centred on y = yc, from z0 to z1 (ends included), extruded through the plate.
TopoDS_Shape slot_cutter(double yc, double z0, double z1, double w) {
  const double r = w / 2, x = -1.0;
  const gp_Pnt a(x, yc - r, z0 + r), b(x, yc - r, z1 - r), c(x, yc + r, z1 - r),
      d(x, yc + r, z0 + r);
  const Handle(Geom_TrimmedCurve) top = GC_MakeArcOfCircle(b, gp_Pnt(x, yc, z1), c).Value();
  const Handle(Geom_TrimmedCurve) bottom = GC_MakeArcOfCircle(d, gp_Pnt(x, yc, z0), a).Value();
  BRepBuilderAPI_MakeWire wire(
      BRepBuilderAPI_MakeEdge(a, b).Edge(), BRepBuilderAPI_MakeEdge(top).Edge(),
      BRepBuilderAPI_MakeEdge(c, d).Edge(), BRepBuilderAPI_MakeEdge(bottom).Edge());
  if (!wire.IsDone()) throw std::runtime_error("slot outline is not a closed wire");
  BRepBuilderAPI_MakeFace face(wire.Wire(), /*OnlyPlane=*/true);
  if (!face.IsDone()) throw std::runtime_error("slot outline is not a planar face");
  return BRepPrimAPI_MakePrism(face.Face(), gp_Vec(kT + 2.0, 0, 0)).Shape();
}

TopoDS_Shape build_bracket() {
  // The L: base plate and upright plate, fused into one solid.
  const TopoDS_Shape base =
      BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(kBaseLength, kWidth, kT)).Shape();
  const TopoDS_Shape upright =
      BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), gp_Pnt(kT, kWidth, kHeight)).Shape();
  TopoDS_Shape s = fuse(base, upright, "base plate + upright plate");

  // Bend (inside and outside, concentric) and the free corners of both plates.
  s = fillet(s,
             {{kBendInner, edges_where(s, line_along(1, kT, kT), 1, "the inner bend")},
              {kBendInner + kT, edges_where(s, line_along(1, 0, 0), 1, "the outer bend")},
              {kCorner, edges_where(s, line_along(2, kBaseLength, 0), 1, "base corner y=0")},
              {kCorner, edges_where(s, line_along(2, kBaseLength, kWidth), 1, "base corner y=60")},
              {kCorner, edges_where(s, line_along(0, 0, kHeight), 1, "upright corner y=0")},
              {kCorner, edges_where(s, line_along(0, kWidth, kHeight), 1, "upright corner y=60")}},
             "bend and corners");

  // Base plate: a plain hole and a counterbored one (counterbore from the top face).
  s = cut(s, z_cylinder(70, 15, kHoleD, -1, kT + 1), "plain hole");
  s = cut(s, z_cylinder(70, 45, kHoleD, -1, kT + 1), "counterbored hole");
  s = cut(s, z_cylinder(70, 45, kCboreD, kT - kCboreDepth, kT + 1), "counterbore");

  // Upright plate: a slot and two holes, the holes' outer rims (x = 0) broken.
  s = cut(s, slot_cutter(kWidth / 2, kSlotZ0, kSlotZ1, kSlotW), "slot");
  const double hy0 = 14, hy1 = kWidth - 14, hz = 52;
  s = cut(s, x_cylinder(hy0, hz, kUprightHoleD), "upright hole y=14");
  s = cut(s, x_cylinder(hy1, hz, kUprightHoleD), "upright hole y=46");
  s = fillet(
      s,
      {{kRimBreak, edges_where(s, circle_at(gp_Pnt(0, hy0, hz), kUprightHoleD / 2), 1, "rim y=14")},
       {kRimBreak,
        edges_where(s, circle_at(gp_Pnt(0, hy1, hz), kUprightHoleD / 2), 1, "rim y=46")}},
      "upright hole rims");
  return s;
}

// One valid closed solid with a plausible face count and volume, or an error.
void check_model(const TopoDS_Shape& s) {
  int solids = 0, shells = 0, faces = 0;
  for (TopExp_Explorer e(s, TopAbs_SOLID); e.More(); e.Next()) ++solids;
  for (TopExp_Explorer e(s, TopAbs_SHELL); e.More(); e.Next()) {
    ++shells;
    if (!BRep_Tool::IsClosed(e.Current())) throw std::runtime_error("the shell is not closed");
  }
  TopTools_IndexedMapOfShape fmap;
  TopExp::MapShapes(s, TopAbs_FACE, fmap);
  faces = fmap.Extent();
  if (solids != 1 || shells != 1)
    throw std::runtime_error("expected 1 solid with 1 shell, got " + std::to_string(solids) +
                             " solids, " + std::to_string(shells) + " shells");
  if (faces < 20 || faces > 60)
    throw std::runtime_error("unexpected face count " + std::to_string(faces));
  if (!BRepCheck_Analyzer(s).IsValid())
    throw std::runtime_error("BRepCheck reports an invalid shape");
  GProp_GProps props;
  BRepGProp::VolumeProperties(s, props);
  const double plates = kBaseLength * kWidth * kT + kT * kWidth * (kHeight - kT);
  if (!(props.Mass() > 0.8 * plates && props.Mass() < plates))
    throw std::runtime_error("implausible volume " + std::to_string(props.Mass()) + " mm^3");
}

// Writes to `path`; errors name `shown` (the file the user asked for).
void write_step(const TopoDS_Shape& s, const std::string& path, const std::string& shown) {
  STEPControl_Controller::Init();
  if (!Interface_Static::SetCVal("write.step.schema", "AP214IS") ||
      !Interface_Static::SetCVal("write.step.unit", "MM") ||
      !Interface_Static::SetCVal("xstep.cascade.unit", "MM") ||
      !Interface_Static::SetCVal("write.step.product.name", "bracket"))
    throw std::runtime_error("cannot set the STEP writer parameters");
  STEPControl_Writer writer;
  if (writer.Transfer(s, STEPControl_AsIs) != IFSelect_RetDone)
    throw std::runtime_error("STEP transfer failed");
  APIHeaderSection_MakeHeader header(writer.Model());
  header.SetName(new TCollection_HAsciiString("bracket"));
  header.SetTimeStamp(new TCollection_HAsciiString("2024-01-01T00:00:00"));
  header.SetOriginatingSystem(new TCollection_HAsciiString("uvmesh make_bracket"));
  if (writer.Write(path.c_str()) != IFSelect_RetDone)
    throw std::runtime_error("cannot write " + shown + " (missing folder or no permission?)");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2 || std::string(argv[1]).empty() || argv[1][0] == '-') {
    std::cerr << "usage: make_bracket OUT.step   (writes the sample L-bracket as STEP AP214, mm)\n";
    return 1;
  }
  const std::filesystem::path out = argv[1];
  std::filesystem::path tmp = out;
  tmp += ".tmp" + std::to_string(::getpid());
  // OCC's messenger prints progress and warnings on stdout: keep stdout and stderr clean.
  Message::DefaultMessenger()->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  try {
    const TopoDS_Shape bracket = build_bracket();
    check_model(bracket);
    write_step(bracket, tmp.string(), out.string());
    std::filesystem::rename(tmp, out);
  } catch (const Standard_Failure& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    std::cerr << "make_bracket: error: OpenCASCADE: " << e.GetMessageString() << "\n";
    return 1;
  } catch (const std::exception& e) {
    std::error_code ec;
    std::filesystem::remove(tmp, ec);
    std::cerr << "make_bracket: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
