// OCC side of the CAD readers: STEP / IGES / BREP import, healing (ShapeFix, sewing,
// general fuse), and the geom::Model build. The only io translation unit with OCCT.
#define OCC_CONVERT_SIGNALS 1
#include <tbb/task_arena.h>

#include <BOPAlgo_GlueEnum.hxx>
#include <BRepAlgoAPI_BuilderAlgo.hxx>
#include <BRepBndLib.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRep_Builder.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <IFSelect_ReturnStatus.hxx>
#include <IGESControl_Reader.hxx>
#include <IGESData_GlobalSection.hxx>
#include <IGESData_IGESModel.hxx>
#include <Interface_Static.hxx>
#include <Message.hxx>
#include <Message_Messenger.hxx>
#include <Message_PrinterOStream.hxx>
#include <OSD.hxx>
#include <STEPControl_Reader.hxx>
#include <ShapeBuild_ReShape.hxx>
#include <ShapeFix_Shape.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <StepRepr_RepresentationItem.hxx>
#include <TColStd_SequenceOfAsciiString.hxx>
#include <TCollection_HAsciiString.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedDataMapOfShapeListOfShape.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopTools_ListOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shape.hxx>
#include <TransferBRep.hxx>
#include <Transfer_TransientProcess.hxx>
#include <XSControl_TransferReader.hxx>
#include <XSControl_WorkSession.hxx>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <unordered_map>
#include <vector>

#include "uvmesh/geom/occ.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/prescan.h"
#include "uvmesh/io/units.h"

namespace uvmesh::io {
namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string occ_message(const Standard_Failure& f) {
  std::string s = f.DynamicType()->Name();
  const char* m = f.GetMessageString();
  if (m && *m) s += std::string(": ") + m;
  return s;
}

// OCC's readers and Interface_Static parameters are process-wide: serialise imports.
std::mutex g_occ_mutex;

void prepare_occ(const ReadOptions& opt) {
  static std::once_flag once;
  std::call_once(once, [&] {
    if (opt.install_signal_handlers) OSD::SetSignal(Standard_False);  // no FP traps
    // Library code does not print: drop OCC's console printers (STEP / IGES readers
    // write progress and checks to stdout otherwise).
    const Handle(Message_Messenger)& msg = Message::DefaultMessenger();
    msg->RemovePrinters(STANDARD_TYPE(Message_PrinterOStream));
  });
}

struct Counts {
  int faces = 0, edges = 0, solids = 0, free_edges = 0;
};

Counts count(const TopoDS_Shape& s) {
  Counts c;
  TopTools_IndexedMapOfShape m;
  TopExp::MapShapes(s, TopAbs_FACE, m);
  c.faces = m.Extent();
  m.Clear();
  TopExp::MapShapes(s, TopAbs_SOLID, m);
  c.solids = m.Extent();
  m.Clear();
  TopExp::MapShapes(s, TopAbs_EDGE, m);
  c.edges = m.Extent();
  TopTools_IndexedDataMapOfShapeListOfShape ef;
  TopExp::MapShapesAndUniqueAncestors(s, TopAbs_EDGE, TopAbs_FACE, ef);
  for (int i = 1; i <= ef.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(ef.FindKey(i));
    if (BRep_Tool::Degenerated(e) || ef(i).Extent() != 1) continue;
    if (BRep_Tool::IsClosed(e, TopoDS::Face(ef(i).First()))) continue;  // seam
    ++c.free_edges;
  }
  return c;
}

// The pieces of a model the `conform` step sees: the solids (compsolids as one), which are
// fused, and the faces that are in no solid, which are kept (as their shell when no face
// of the shell is in a solid or already taken, else one by one). A file may list a solid's
// shell or faces again next to it (some files list dozens): those
// are the solid's, not loose. Wires, edges and vertices carry nothing to mesh.
void collect_conform_pieces(const TopoDS_Shape& shape, TopTools_ListOfShape& solids,
                            TopTools_ListOfShape& loose) {
  std::vector<TopoDS_Shape> others;
  std::function<void(const TopoDS_Shape&)> walk = [&](const TopoDS_Shape& s) {
    switch (s.ShapeType()) {
      case TopAbs_COMPOUND:
        for (TopoDS_Iterator it(s); it.More(); it.Next()) walk(it.Value());
        break;
      case TopAbs_COMPSOLID:
      case TopAbs_SOLID:
        solids.Append(s);
        break;
      case TopAbs_SHELL:
      case TopAbs_FACE:
        others.push_back(s);
        break;
      default:
        break;
    }
  };
  walk(shape);
  TopTools_IndexedMapOfShape taken;  // faces of the solids, then of the loose pieces kept
  for (const TopoDS_Shape& so : solids) TopExp::MapShapes(so, TopAbs_FACE, taken);
  for (const TopoDS_Shape& o : others) {
    TopTools_IndexedMapOfShape faces;
    TopExp::MapShapes(o, TopAbs_FACE, faces);
    int free_faces = 0;
    for (int i = 1; i <= faces.Extent(); ++i)
      if (!taken.Contains(faces(i))) ++free_faces;
    if (free_faces == faces.Extent()) {
      if (free_faces > 0) loose.Append(o);
    } else {
      for (int i = 1; i <= faces.Extent(); ++i)
        if (!taken.Contains(faces(i))) loose.Append(faces(i));
    }
    for (int i = 1; i <= faces.Extent(); ++i) taken.Add(faces(i));
  }
}

// Solids with a free edge: an edge (not degenerate) that the faces of the solid use once
// in all, as FORWARD or REVERSED. A seam is used twice by its face; INTERNAL and EXTERNAL
// uses (an imprint inside a face) bound nothing and are not counted.
int count_open_solids(const TopoDS_Shape& s) {
  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(s, TopAbs_SOLID, solids);
  int open = 0;
  for (int i = 1; i <= solids.Extent(); ++i) {
    TopTools_IndexedMapOfShape edges;
    std::vector<int> uses;
    for (TopExp_Explorer fx(solids(i), TopAbs_FACE); fx.More(); fx.Next())
      for (TopExp_Explorer ex(fx.Current(), TopAbs_EDGE); ex.More(); ex.Next()) {
        const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
        if (BRep_Tool::Degenerated(e)) continue;
        if (e.Orientation() != TopAbs_FORWARD && e.Orientation() != TopAbs_REVERSED) continue;
        const int k = edges.Add(e);
        if (k > static_cast<int>(uses.size())) uses.resize(static_cast<std::size_t>(k), 0);
        ++uses[static_cast<std::size_t>(k - 1)];
      }
    if (std::find(uses.begin(), uses.end(), 1) != uses.end()) ++open;
  }
  return open;
}

// The distinct alerts (warnings and errors) of a boolean operation, by type name with
// their counts: "BOPAlgo_AlertTooSmallEdge x44, ...".
std::string fuse_alerts(const BRepAlgoAPI_BuilderAlgo& op) {
  std::ostringstream dump;
  op.DumpErrors(dump);
  op.DumpWarnings(dump);
  std::vector<std::pair<std::string, int>> seen;
  std::istringstream in(dump.str());
  for (std::string line; std::getline(in, line);) {
    if (line.empty()) continue;
    auto it =
        std::find_if(seen.begin(), seen.end(), [&](const auto& p) { return p.first == line; });
    if (it == seen.end())
      seen.emplace_back(line, 1);
    else
      ++it->second;
  }
  std::string out;
  for (const auto& [name, n] : seen)
    out += (out.empty() ? "" : ", ") + name + " x" + std::to_string(n);
  return out;
}

// Length of the shortest non-degenerate edge (the sewing tolerance stays well below it).
double shortest_edge_length(const TopoDS_Shape& s) {
  TopTools_IndexedMapOfShape m;
  TopExp::MapShapes(s, TopAbs_EDGE, m);
  double best = std::numeric_limits<double>::infinity();
  for (int i = 1; i <= m.Extent(); ++i) {
    const TopoDS_Edge& e = TopoDS::Edge(m(i));
    if (BRep_Tool::Degenerated(e)) continue;
    GProp_GProps g;
    BRepGProp::LinearProperties(e, g);
    best = std::min(best, g.Mass());
  }
  return best;
}

double diagonal(const TopoDS_Shape& s) {
  Bnd_Box b;
  BRepBndLib::Add(s, b, Standard_False);
  if (b.IsVoid()) return 0.0;
  return std::sqrt(b.SquareExtent());
}

HealStep make_step(const char* name, const Counts& a, const Counts& b) {
  HealStep h;
  h.name = name;
  h.faces_before = a.faces;
  h.faces_after = b.faces;
  h.edges_before = a.edges;
  h.edges_after = b.edges;
  h.solids_before = a.solids;
  h.solids_after = b.solids;
  h.free_edges_before = a.free_edges;
  h.free_edges_after = b.free_edges;
  return h;
}

std::string counts_text(const HealStep& h) {
  std::ostringstream os;
  os << "faces " << h.faces_before << "->" << h.faces_after << ", edges " << h.edges_before << "->"
     << h.edges_after << ", solids " << h.solids_before << "->" << h.solids_after << ", free edges "
     << h.free_edges_before << "->" << h.free_edges_after;
  return os.str();
}

const char* iges_unit_name(int flag) {
  switch (flag) {
    case 1:
      return "inch";
    case 2:
      return "mm";
    case 4:
      return "ft";
    case 5:
      return "mi";
    case 6:
      return "m";
    case 7:
      return "km";
    case 8:
      return "mil";
    case 9:
      return "um";
    case 10:
      return "cm";
    case 11:
      return "uin";
    default:
      return "";
  }
}

// OCC's tolerance parameters are expressed in the transfer's (system) length unit, not in
// mm: read.maxprecision.val (largest tolerance a shape may get, default 1) and
// read.precision.val (used when a file gives no uncertainty, default 1e-4). A transfer into
// another unit gets them rescaled, so that a model read in inches or metres gets the same
// tolerances as its mm reading; the defaults are restored afterwards (the statics are
// process-wide; imports are serialised by g_occ_mutex).
class ScopedTransferTolerances {
 public:
  explicit ScopedTransferTolerances(double mm_per_unit) {
    max_ = Interface_Static::RVal("read.maxprecision.val");
    prec_ = Interface_Static::RVal("read.precision.val");
    if (mm_per_unit > 0.0 && mm_per_unit != 1.0) {
      Interface_Static::SetRVal("read.maxprecision.val", max_ / mm_per_unit);
      Interface_Static::SetRVal("read.precision.val", prec_ / mm_per_unit);
      set_ = true;
    }
  }
  ~ScopedTransferTolerances() {
    if (!set_) return;
    Interface_Static::SetRVal("read.maxprecision.val", max_);
    Interface_Static::SetRVal("read.precision.val", prec_);
  }
  ScopedTransferTolerances(const ScopedTransferTolerances&) = delete;
  ScopedTransferTolerances& operator=(const ScopedTransferTolerances&) = delete;

 private:
  double max_ = 1.0, prec_ = 1e-4;
  bool set_ = false;
};

// The unit the coordinates come out in: the requested one, else the file's; a file that
// declares no unit or one not known here is left to OCC's default conversion to mm.
std::string target_unit(const std::string& requested, const std::string& declared,
                        ReadReport& rep) {
  if (!requested.empty()) return requested;
  if (!rep.file_units.empty()) return rep.file_units;
  rep.warnings.push_back(
      declared.empty() ? "the file declares no length unit: coordinates taken as mm (OCC's default)"
                       : "the file's length unit '" + declared +
                             "' is not one uvmesh knows: coordinates converted to mm by OCC");
  return "mm";
}

// Names the CAD system gave faces and solids (STEP entity names), attached to the shapes
// they became, and carried through healing so that the model's faces and solids get them
// (io::write_mesh turns them into physical groups).
struct ShapeNames {
  std::vector<std::pair<TopoDS_Shape, std::string>> items;

  // Every transferred STEP entity whose result is a face or a solid and whose name is not
  // empty: one pass over the transfer map, no per-shape search.
  void collect(const STEPControl_Reader& reader) {
    const Handle(XSControl_TransferReader) tr = reader.WS()->TransferReader();
    if (tr.IsNull()) return;
    const Handle(Transfer_TransientProcess) tp = tr->TransientProcess();
    if (tp.IsNull()) return;
    for (int i = 1; i <= tp->NbMapped(); ++i) {
      const Handle(StepRepr_RepresentationItem) item =
          Handle(StepRepr_RepresentationItem)::DownCast(tp->Mapped(i));
      // "NONE" is the placeholder several CAD systems write for "no name".
      if (item.IsNull() || item->Name().IsNull() || item->Name()->Length() == 0 ||
          item->Name()->IsSameString(new TCollection_HAsciiString("NONE")))
        continue;
      const Handle(Transfer_Binder) binder = tp->MapItem(i);
      if (binder.IsNull()) continue;
      const TopoDS_Shape sh = TransferBRep::ShapeResult(binder);
      if (sh.IsNull() || (sh.ShapeType() != TopAbs_FACE && sh.ShapeType() != TopAbs_SOLID))
        continue;
      items.emplace_back(sh, item->Name()->ToCString());
    }
  }
  // After a healing step: each named shape becomes what the step made of it (a split
  // face passes its name to every piece; a removed one loses it).
  template <class Map>
  void follow(Map&& image_of) {
    std::vector<std::pair<TopoDS_Shape, std::string>> next;
    for (const auto& [sh, name] : items)
      for (const TopoDS_Shape& im : image_of(sh)) next.emplace_back(im, name);
    items = std::move(next);
  }
  void apply(const TopoDS_Shape& shape, geom::Model& model) const {
    if (items.empty()) return;
    // Matched by TShape: an assembly places one part's faces several times (other
    // locations, same TShape), and every instance carries the part's names.
    std::unordered_map<const TopoDS_TShape*, const std::string*> name_of;
    for (const auto& [sh, name] : items) name_of.emplace(sh.TShape().get(), &name);
    TopTools_IndexedMapOfShape faces, solids;
    // The same maps (same order) as geom::model_from_occ numbers faces and solids with.
    TopExp::MapShapes(shape, TopAbs_FACE, faces);
    TopExp::MapShapes(shape, TopAbs_SOLID, solids);
    for (int i = 1; i <= faces.Extent() && i <= static_cast<int>(model.faces.size()); ++i)
      if (auto it = name_of.find(faces(i).TShape().get()); it != name_of.end())
        model.faces[static_cast<std::size_t>(i - 1)].name = *it->second;
    for (int i = 1; i <= solids.Extent() && i <= static_cast<int>(model.solids.size()); ++i)
      if (auto it = name_of.find(solids(i).TShape().get()); it != name_of.end())
        model.solids[static_cast<std::size_t>(i - 1)].name = *it->second;
  }
};

// Loads a STEP file into the reader. OCCT 7.6's STEP parser rejects a file that begins with
// a UTF-8 byte-order mark (measured: ReadFile fails, status IFSelect_RetFail); such a file
// is parsed from a stream of the file positioned after the mark (no copy, no temp file).
IFSelect_ReturnStatus load_step(STEPControl_Reader& reader, const std::string& path,
                                bool utf8_bom) {
  if (!utf8_bom) return reader.ReadFile(path.c_str());
  std::ifstream in(path, std::ios::binary);
  in.seekg(3);
  if (!in) return IFSelect_RetError;
  return reader.ReadStream(path.c_str(), in);
}

// Reads the file into a shape, with coordinates in `units` (set here: the requested unit,
// else the file's); sets report.format / file_units / mm_per_unit. Throws Standard_Failure
// or returns an error message.
//
// Units go through OCC's own mechanism, before the transfer: STEPControl_Reader's system
// length unit and the IGES global section's cascade unit (both in mm) are set to the target
// unit, so OCC converts file -> target in one factor, which is exactly 1 when the target is
// the file's unit (the coordinates are the file's numbers; no after-the-fact gp_Trsf
// rescaling, which would round every coordinate and leave tolerances in the wrong unit).
// OCCT 7.6 ignores Interface_Static "xstep.cascade.unit" in these readers (checked: a STEP
// file in cm still comes out in mm with it set to CM).
std::string read_shape(const std::string& path, const PrescanResult& pre,
                       const std::string& requested, TopoDS_Shape& shape, ReadReport& rep,
                       std::string& units, ShapeNames& shape_names) {
  const CadFormat fmt = pre.content;
  rep.format = std::string(to_string(fmt));
  if (fmt == CadFormat::Step) {
    STEPControl_Reader reader;
    if (load_step(reader, path, pre.utf8_bom) != IFSelect_RetDone)
      return "the STEP reader rejected the file";
    TColStd_SequenceOfAsciiString lu, au, su;
    reader.FileUnits(lu, au, su);
    std::vector<std::string> names;  // distinct length units of the shape representations
    for (int i = 1; i <= lu.Length(); ++i) {
      const std::string n = lu(i).ToCString();
      if (std::find(names.begin(), names.end(), n) == names.end()) names.push_back(n);
    }
    const std::string declared = names.empty() ? "" : names.front();
    rep.file_units_declared = declared;
    rep.file_units = canonical_length_unit(declared);
    if (names.size() > 1) {
      std::string all;
      for (const std::string& n : names) all += (all.empty() ? "" : ", ") + n;
      rep.warnings.push_back("the file's shape representations use several length units (" + all +
                             "): OCC converts all of them to the model's unit");
    }
    units = target_unit(requested, declared, rep);
    rep.mm_per_unit = length_unit_mm(units);
    rep.units_converted = !rep.file_units.empty() ? units != rep.file_units : !declared.empty();
    reader.SetSystemLengthUnit(rep.mm_per_unit);
    ScopedTransferTolerances tol(rep.mm_per_unit);
    reader.TransferRoots();
    shape = reader.OneShape();
    shape_names.collect(reader);
  } else if (fmt == CadFormat::Iges) {
    IGESControl_Reader reader;
    if (reader.ReadFile(path.c_str()) != IFSelect_RetDone)
      return "the IGES reader rejected the file";
    const Handle(IGESData_IGESModel) model = reader.IGESModel();
    if (model.IsNull()) return "the IGES reader produced no model";
    IGESData_GlobalSection gs = model->GlobalSection();
    const int flag = gs.UnitFlag();
    const Handle(TCollection_HAsciiString) uname = gs.UnitName();
    const std::string name = uname.IsNull() ? "" : uname->ToCString();
    std::string declared = !name.empty() ? name : iges_unit_name(flag);
    // Flag 3: the unit is the one named; otherwise the flag decides.
    rep.file_units = canonical_length_unit(flag == 3 ? name : std::string(iges_unit_name(flag)));
    rep.file_units_declared = declared + " (unit flag " + std::to_string(flag) + ")";
    if (declared.empty()) declared = "unit flag " + std::to_string(flag);
    units = target_unit(requested, declared, rep);
    rep.mm_per_unit = length_unit_mm(units);
    rep.units_converted = units != rep.file_units;
    // OCC's factor is UnitValue() / CascadeUnit(), both in mm: for the file's own unit use
    // OCC's UnitValue itself, so that the factor is exactly 1.
    const bool native = units == rep.file_units && gs.UnitValue() > 0.0;
    gs.SetCascadeUnit(native ? gs.UnitValue() : rep.mm_per_unit);
    model->SetGlobalSection(gs);
    ScopedTransferTolerances tol(rep.mm_per_unit);
    reader.TransferRoots();
    shape = reader.OneShape();
  } else {
    BRep_Builder b;
    if (!BRepTools::Read(shape, path.c_str(), b)) return "the BREP reader rejected the file";
    units.clear();  // BREP files carry no unit
    rep.mm_per_unit = 0.0;
    if (!requested.empty())
      rep.warnings.push_back("BREP files carry no length unit: the requested unit (" + requested +
                             ") is ignored, coordinates are as stored");
  }
  return {};
}

// The state the steps of read_cad share once the shape is read: the shape, its counts,
// the names following it through healing, and the stage (for a message if OCC fails).
struct CadRead {
  TopoDS_Shape shape;
  Counts c0;
  ShapeNames names;
  std::string stage = "reading";
};

// 1. Text pre-scan: nothing malformed reaches OCC. "" or the reason to refuse the file.
std::string prescan_step(const std::string& path, const ReadOptions& opt, PrescanResult& pre,
                         ReadReport& report) {
  PrescanOptions po;
  po.max_abs_coordinate = opt.max_abs_coordinate;
  po.allow_dangling_references = opt.allow_partial;
  pre = prescan_file(path, po);
  const CadFormat ext = format_from_extension(path);
  if (pre.content != CadFormat::Unknown && ext != CadFormat::Unknown && ext != pre.content &&
      !opt.trust_content)
    return "wrong extension: the name says " + std::string(to_string(ext)) +
           " but the content is " + std::string(to_string(pre.content)) +
           " (rename the file, or allow reading by content)";
  if (!pre.ok) return pre.error;
  for (const std::string& w : pre.warnings) report.warnings.push_back(w);
  if (ext != CadFormat::Unknown && ext != pre.content)
    report.warnings.push_back("extension says " + std::string(to_string(ext)) + ", read as " +
                              std::string(to_string(pre.content)));
  return {};
}

// Why a file whose shape has no face cannot be meshed.
std::string no_faces_reason(const PrescanResult& pre, const TopoDS_Shape& shape) {
  if (pre.step_tessellated_faces > 0)
    return "no B-rep faces: the file carries only tessellated geometry (" +
           std::to_string(pre.step_tessellated_faces) + " triangulated faces), nothing to mesh";
  return shape.IsNull() ? "no shape could be transferred from the file (empty result)"
                        : "the file contains no faces (empty or wire-only result)";
}

// 2a. ShapeFix_Shape, kept unless it loses entities.
void heal_shapefix(CadRead& cr, ReadReport& report) {
  cr.stage = "healing (ShapeFix)";
  const auto ts = Clock::now();
  ShapeFix_Shape fix(cr.shape);
  fix.Perform();
  const TopoDS_Shape fixed = fix.Shape();
  const Counts c1 = count(fixed);
  HealStep h = make_step("shapefix", cr.c0, c1);
  const bool changed = fix.Status(ShapeExtend_DONE) && !fixed.IsNull();
  // Healing must not drop anything (docs/ARCHITECTURE.md: nothing is dropped silently): a
  // fix that loses faces or solids (ShapeFix can discard a solid whose shell it deems open)
  // is reported and not kept.
  const bool loses = c1.faces < cr.c0.faces || c1.solids < cr.c0.solids;
  h.applied = changed && !loses;
  h.detail = !changed ? "ShapeFix_Shape found nothing to fix"
             : loses  ? "ShapeFix_Shape result not kept, it would lose entities: " + counts_text(h)
                      : "ShapeFix_Shape modified the shape: " + counts_text(h);
  if (changed && loses) report.warnings.push_back(h.detail);
  if (h.applied) {
    cr.shape = fixed;
    cr.c0 = c1;
    const Handle(ShapeBuild_ReShape) ctx = fix.Context();
    if (!ctx.IsNull())
      cr.names.follow([&](const TopoDS_Shape& s) {
        const TopoDS_Shape v = ctx->Value(s);
        return v.IsNull() ? std::vector<TopoDS_Shape>{} : std::vector<TopoDS_Shape>{v};
      });
  }
  h.seconds = seconds_since(ts);
  report.healing.push_back(h);
}

// One sewing of the shape at one tolerance.
struct SewAttempt {
  double tol = 0.0;
  std::unique_ptr<BRepBuilderAPI_Sewing> sew;
  TopoDS_Shape sewn;
  Counts counts;
  bool usable = false;
};

// Sew at the base tolerance; while free edges remain, try tenfold larger ones up to
// sew_max_rel_tol (see ReadOptions), each on the ShapeFix result. A tolerance is tried
// only below a tenth of the shortest edge, so no real edge collapses.
std::vector<SewAttempt> sew_attempts(const CadRead& cr, const ReadOptions& opt, double diag) {
  std::vector<SewAttempt> tries;
  const double max_tol = std::max(opt.sew_rel_tol, opt.sew_max_rel_tol) * diag;
  double shortest = -1.0;  // computed only if an escalation is needed
  for (double tol = opt.sew_rel_tol * diag; tol <= max_tol * (1 + 1e-9); tol *= 10) {
    if (!tries.empty()) {
      if (shortest < 0) shortest = shortest_edge_length(cr.shape);
      if (tol > 0.1 * shortest) break;
    }
    SewAttempt t;
    t.tol = tol;
    t.sew = std::make_unique<BRepBuilderAPI_Sewing>(tol);
    t.sew->Add(cr.shape);
    t.sew->Perform();
    t.sewn = t.sew->SewedShape();
    if (!t.sewn.IsNull()) {
      t.counts = count(t.sewn);
      // Keep a result only when it closed gaps without losing faces or solids
      // (sewing returns shells: solids of the input would be dissolved).
      t.usable = t.counts.free_edges < cr.c0.free_edges && t.counts.faces >= cr.c0.faces &&
                 t.counts.solids >= cr.c0.solids;
    }
    const bool done = t.usable && t.counts.free_edges == 0;
    tries.push_back(std::move(t));
    if (done) break;
  }
  return tries;
}

// The report line of the sewing attempts.
std::string sewing_detail(const CadRead& cr, const std::vector<SewAttempt>& tries,
                          const SewAttempt* best, const HealStep& h) {
  const Counts& c0 = cr.c0;
  std::ostringstream os;
  os << "BRepBuilderAPI_Sewing";
  for (const SewAttempt& t : tries) {
    os << (&t == &tries.front() ? ", tolerance " : "; tolerance ") << t.tol << ": ";
    if (t.sewn.IsNull()) {
      os << "no shape";
      continue;
    }
    os << "free edges " << c0.free_edges << "->" << t.counts.free_edges;
    if (t.counts.faces < c0.faces || t.counts.solids < c0.solids)
      os << " (would lose faces or solids)";
    if (&t == best) os << " [kept]";
  }
  if (tries.size() == 1 && tries.front().sewn.IsNull())
    return "sewing produced no shape (not kept)";
  return os.str() + (best ? " -- " + counts_text(h) : " (not kept: no free edge closed)");
}

// 2b. Sewing: the attempt that closes the most free edges (the smallest tolerance among
// equals) is kept.
void heal_sewing(CadRead& cr, const ReadOptions& opt, ReadReport& report) {
  cr.stage = "healing (sewing)";
  const auto ts = Clock::now();
  const double diag = diagonal(cr.shape);
  const std::vector<SewAttempt> tries = sew_attempts(cr, opt, diag);
  const SewAttempt* best = nullptr;
  for (const SewAttempt& t : tries)
    if (t.usable && (!best || t.counts.free_edges < best->counts.free_edges)) best = &t;
  HealStep h = make_step("sewing", cr.c0, best ? best->counts : cr.c0);
  h.applied = best != nullptr;
  h.detail = sewing_detail(cr, tries, best, h);
  if (best) {
    cr.shape = best->sewn;
    cr.c0 = best->counts;
    const BRepBuilderAPI_Sewing& sew = *best->sew;
    cr.names.follow([&](const TopoDS_Shape& s) {
      return std::vector<TopoDS_Shape>{sew.IsModified(s) ? sew.Modified(s) : s};
    });
  }
  h.seconds = seconds_since(ts);
  report.healing.push_back(h);
}

// The general fuse of the solids `args`, in a TBB arena bounded by opt.threads; its
// result with the `loose` shells and faces beside it, or null when it failed.
TopoDS_Shape run_fuse(BRepAlgoAPI_BuilderAlgo& fuse, const TopTools_ListOfShape& args,
                      const TopTools_ListOfShape& loose, const TopoDS_Shape& shape,
                      const ReadOptions& opt) {
  fuse.SetArguments(args);
  fuse.SetRunParallel(opt.threads != 1 ? Standard_True : Standard_False);
  fuse.SetNonDestructive(Standard_True);
  // Fuzzy value: solids of an assembly touch within their tolerances, not exactly.
  fuse.SetFuzzyValue(1e-7 * diagonal(shape));
  if (opt.threads != 1) {
    // OCC's parallel loops are TBB loops (Debian's OCCT is built with TBB): the arena
    // bounds them by the requested thread count.
    tbb::task_arena arena(opt.threads > 0 ? opt.threads : tbb::task_arena::automatic);
    arena.execute([&] { fuse.Build(); });
  } else {
    fuse.Build();
  }
  TopoDS_Shape out;
  if (fuse.IsDone() && !fuse.HasErrors()) {
    out = fuse.Shape();
    if (!loose.IsEmpty()) {
      TopoDS_Compound all;
      BRep_Builder b;
      b.MakeCompound(all);
      b.Add(all, out);
      for (const TopoDS_Shape& l : loose) b.Add(all, l);
      out = all;
    }
  }
  return out;
}

// 2c. Conforming assembly (general fuse of the solids), kept unless it opens a solid.
void make_conforming(CadRead& cr, const ReadOptions& opt, ReadReport& report) {
  cr.stage = "making the assembly conforming (general fuse)";
  const auto ts = Clock::now();
  // The solids are fused; the shells and faces that belong to no solid are kept as they
  // are, next to the result (fusing the solids and returning the fuse's result alone
  // dropped everything else: faces lost, the bounding box shrunk). They are not fused
  // themselves: `conform` imprints touching solids on each other (what volume meshing
  // needs); a surface crossing a solid is the model's, and is reported as such.
  TopTools_ListOfShape args, loose;
  collect_conform_pieces(cr.shape, args, loose);
  BRepAlgoAPI_BuilderAlgo fuse;
  const TopoDS_Shape out = run_fuse(fuse, args, loose, cr.shape, opt);
  HealStep h;
  const std::string pieces =
      std::to_string(args.Extent()) + " solids" +
      (loose.IsEmpty() ? std::string()
                       : " (" + std::to_string(loose.Extent()) +
                             " shells or faces outside them kept as they are)");
  // The fuse must not open a solid: a closed solid must give a closed surface mesh. The
  // fuse can "succeed" with alerts (intersection of a pair of shapes failed, unable to
  // orient a shape) and return solids with free edges that the input did not have.
  const int open_before = count_open_solids(cr.shape);
  const int open_after = out.IsNull() ? 0 : count_open_solids(out);
  if (!out.IsNull() && open_after <= open_before) {
    const Counts c1 = count(out);
    h = make_step("conform", cr.c0, c1);
    h.applied = true;
    h.detail = "general fuse of " + pieces + ": " + counts_text(h);
    cr.shape = out;
    cr.c0 = c1;
    cr.names.follow([&](const TopoDS_Shape& s) {
      std::vector<TopoDS_Shape> images;
      for (const TopoDS_Shape& im : fuse.Modified(s)) images.push_back(im);
      if (images.empty() && !fuse.IsDeleted(s)) images.push_back(s);
      return images;
    });
  } else {
    h = make_step("conform", cr.c0, cr.c0);
    std::ostringstream os;
    if (out.IsNull())
      os << "general fuse of " << pieces << " failed";
    else
      os << "general fuse of " << pieces << " not kept: it would leave " << open_after
         << " solid(s) with free edges, the input has " << open_before;
    const std::string alerts = fuse_alerts(fuse);
    if (!alerts.empty()) os << " (OCC alerts: " << alerts << ")";
    os << "; the assembly is left non-conforming";
    h.detail = os.str();
    report.warnings.push_back(h.detail);
  }
  h.name = "conform";
  h.seconds = seconds_since(ts);
  report.healing.push_back(h);
}

// 3. Model.
void build_model(CadRead& cr, const ReadOptions& opt, ReadResult& res) {
  cr.stage = "building the model";
  const auto tb = Clock::now();
  geom::OccModelOptions mo;
  mo.check_validity = opt.check_validity;
  res.report.validity_checked = opt.check_validity;
  res.model = geom::model_from_occ(cr.shape, mo);
  cr.names.apply(cr.shape, res.model);
  for (const geom::VertexSplit& v : res.model.vertex_splits)
    res.report.warnings.push_back(v.reason);
  res.report.build_seconds = seconds_since(tb);
}

// 4. Sanity of the result: coordinates that cannot be real. "" or the reason.
std::string check_coordinates(const geom::Model& model, const ReadOptions& opt) {
  for (std::size_t i = 0; i < model.vertices.size(); ++i) {
    const geom::Vec3& p = model.vertices[i].p;
    const double m = std::max({std::abs(p.x), std::abs(p.y), std::abs(p.z)});
    if (!(m <= opt.max_abs_coordinate)) {
      std::ostringstream os;
      os << "vertex " << i << " has a coordinate of magnitude " << m << ", beyond "
         << opt.max_abs_coordinate << " (corrupted coordinate?)";
      return os.str();
    }
  }
  return {};
}

}  // namespace

ReadResult read_cad(const std::string& path, const ReadOptions& opt) {
  ReadResult res;
  auto fail = [&](const std::string& what) {
    res.ok = false;
    res.error = path + ": " + what;
    return res;
  };
  const auto t0 = Clock::now();
  PrescanResult pre;
  if (std::string e = prescan_step(path, opt, pre, res.report); !e.empty()) return fail(e);
  std::string requested_units;
  if (!opt.units.empty()) {
    requested_units = canonical_length_unit(opt.units);
    if (requested_units.empty())
      return fail("unknown length unit '" + opt.units +
                  "' requested (known: " + known_length_units() + ")");
  }

  std::lock_guard<std::mutex> lock(g_occ_mutex);
  prepare_occ(opt);
  CadRead cr;
  std::string units;
  try {
    OCC_CATCH_SIGNALS
    if (std::string e =
            read_shape(path, pre, requested_units, cr.shape, res.report, units, cr.names);
        !e.empty())
      return fail(e);
    res.report.read_seconds = seconds_since(t0);
    cr.c0 = cr.shape.IsNull() ? Counts{} : count(cr.shape);
    if (cr.c0.faces == 0) return fail(no_faces_reason(pre, cr.shape));
    // 2. Healing.
    const auto th = Clock::now();
    if (opt.heal) {
      heal_shapefix(cr, res.report);
      if (cr.c0.free_edges > 0 && cr.c0.faces > 1) heal_sewing(cr, opt, res.report);
    }
    if (opt.conform && cr.c0.solids > 1) make_conforming(cr, opt, res.report);
    res.report.heal_seconds = seconds_since(th);
    build_model(cr, opt, res);
  } catch (const Standard_Failure& f) {
    return fail("OpenCASCADE failed while " + cr.stage + ": " + occ_message(f));
  } catch (const std::exception& e) {
    return fail(std::string("failed while ") + cr.stage + ": " + e.what());
  }
  res.model.source = path;
  res.model.format = res.report.format;
  res.model.units = units;  // the file's unit unless another was requested; "" for BREP
  if (std::string e = check_coordinates(res.model, opt); !e.empty()) return fail(e);
  res.ok = true;
  return res;
}

}  // namespace uvmesh::io
