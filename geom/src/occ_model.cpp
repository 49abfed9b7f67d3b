// OCC back end of uvmesh::geom: Surface / Curve / Curve2 adapters over BRepAdaptor and
// the topology walk that builds a Model from a TopoDS_Shape. The only translation unit
// of geom that includes OCCT.
#define OCC_CONVERT_SIGNALS 1
#include <BRepAdaptor_Curve.hxx>
#include <BRepAdaptor_Surface.hxx>
#include <BRepBndLib.hxx>
#include <BRepCheck.hxx>
#include <BRepCheck_Analyzer.hxx>
#include <BRepCheck_ListOfStatus.hxx>
#include <BRepCheck_Result.hxx>
#include <BRepGProp.hxx>
#include <BRepTools.hxx>
#include <BRepTools_WireExplorer.hxx>
#include <BRep_Tool.hxx>
#include <Bnd_Box.hxx>
#include <GProp_GProps.hxx>
#include <Geom2dAdaptor_Curve.hxx>
#include <Geom2d_Curve.hxx>
#include <Geom_Surface.hxx>
#include <Standard_ErrorHandler.hxx>
#include <Standard_Failure.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopTools_IndexedMapOfShape.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Edge.hxx>
#include <TopoDS_Face.hxx>
#include <TopoDS_Iterator.hxx>
#include <TopoDS_Shape.hxx>
#include <TopoDS_Wire.hxx>
#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <string>

#include "uvmesh/geom/occ.h"

namespace uvmesh::geom {
namespace {

Vec3 v3(const gp_Pnt& p) {
  return {p.X(), p.Y(), p.Z()};
}
Vec3 v3(const gp_Vec& p) {
  return {p.X(), p.Y(), p.Z()};
}
Vec2 v2(const gp_Pnt2d& p) {
  return {p.X(), p.Y()};
}
Vec2 v2(const gp_Vec2d& p) {
  return {p.X(), p.Y()};
}

std::string occ_message(const Standard_Failure& f) {
  std::string s = f.DynamicType()->Name();
  const char* m = f.GetMessageString();
  if (m && *m) s += std::string(": ") + m;
  return s;
}

SurfaceKind surface_kind(GeomAbs_SurfaceType t) {
  switch (t) {
    case GeomAbs_Plane:
      return SurfaceKind::Plane;
    case GeomAbs_Cylinder:
      return SurfaceKind::Cylinder;
    case GeomAbs_Cone:
      return SurfaceKind::Cone;
    case GeomAbs_Sphere:
      return SurfaceKind::Sphere;
    case GeomAbs_Torus:
      return SurfaceKind::Torus;
    case GeomAbs_BezierSurface:
      return SurfaceKind::Bezier;
    case GeomAbs_BSplineSurface:
      return SurfaceKind::BSpline;
    case GeomAbs_SurfaceOfRevolution:
      return SurfaceKind::Revolution;
    case GeomAbs_SurfaceOfExtrusion:
      return SurfaceKind::Extrusion;
    case GeomAbs_OffsetSurface:
      return SurfaceKind::Offset;
    default:
      return SurfaceKind::Other;
  }
}

CurveKind curve_kind(GeomAbs_CurveType t) {
  switch (t) {
    case GeomAbs_Line:
      return CurveKind::Line;
    case GeomAbs_Circle:
      return CurveKind::Circle;
    case GeomAbs_Ellipse:
      return CurveKind::Ellipse;
    case GeomAbs_Hyperbola:
      return CurveKind::Hyperbola;
    case GeomAbs_Parabola:
      return CurveKind::Parabola;
    case GeomAbs_BezierCurve:
      return CurveKind::Bezier;
    case GeomAbs_BSplineCurve:
      return CurveKind::BSpline;
    case GeomAbs_OffsetCurve:
      return CurveKind::Offset;
    default:
      return CurveKind::Other;
  }
}

// Evaluation failures inside OCC (a B-spline evaluated far outside its knots, a
// degenerate offset) become std::runtime_error naming the parameter.
[[noreturn]] void eval_failed(const char* what, const Standard_Failure& f, double u, double v) {
  std::ostringstream os;
  os << "OCC " << what << " evaluation failed at (" << u << ", " << v << "): " << occ_message(f);
  throw std::runtime_error(os.str());
}

class OccSurface final : public Surface {
 public:
  OccSurface(const TopoDS_Face& f, const Box2& box, double pole_rel_tol)
      : a_(f, Standard_True), box_(box), kind_(surface_kind(a_.GetType())) {
    up_ = a_.IsUPeriodic();
    vp_ = a_.IsVPeriodic();
    uper_ = up_ ? a_.UPeriod() : 0.0;
    vper_ = vp_ ? a_.VPeriod() : 0.0;
    // Planes and cylinders cannot have poles; everything else is sampled once here.
    sing_ = (kind_ == SurfaceKind::Plane || kind_ == SurfaceKind::Cylinder)
                ? 0u
                : detect_singular_sides(*this, pole_rel_tol);
  }
  SurfacePoint eval(double u, double v) const override {
    gp_Pnt p;
    gp_Vec du, dv, duu, dvv, duv;
    try {
      OCC_CATCH_SIGNALS
      a_.D2(u, v, p, du, dv, duu, dvv, duv);
    } catch (const Standard_Failure& f) {
      eval_failed("surface", f, u, v);
    }
    return {v3(p), v3(du), v3(dv), v3(duu), v3(duv), v3(dvv)};
  }
  Box2 bounds() const override { return box_; }
  SurfaceKind kind() const override { return kind_; }
  bool u_periodic() const override { return up_; }
  bool v_periodic() const override { return vp_; }
  double u_period() const override { return uper_; }
  double v_period() const override { return vper_; }
  unsigned singular_sides() const override { return sing_; }

 private:
  BRepAdaptor_Surface a_;
  Box2 box_;
  SurfaceKind kind_;
  bool up_ = false, vp_ = false;
  double uper_ = 0.0, vper_ = 0.0;
  unsigned sing_ = 0u;
};

class OccCurve final : public Curve {
 public:
  explicit OccCurve(const TopoDS_Edge& e) : a_(e), kind_(curve_kind(a_.GetType())) {
    r_ = {a_.FirstParameter(), a_.LastParameter()};
    per_ = a_.IsPeriodic() ? a_.Period() : 0.0;
  }
  CurvePoint3 eval(double t) const override {
    gp_Pnt p;
    gp_Vec d1, d2;
    try {
      OCC_CATCH_SIGNALS
      a_.D2(t, p, d1, d2);
    } catch (const Standard_Failure& f) {
      eval_failed("curve", f, t, 0.0);
    }
    return {v3(p), v3(d1), v3(d2)};
  }
  Interval range() const override { return r_; }
  CurveKind kind() const override { return kind_; }
  bool periodic() const override { return per_ > 0.0; }
  double period() const override { return per_; }

 private:
  BRepAdaptor_Curve a_;
  CurveKind kind_;
  Interval r_;
  double per_ = 0.0;
};

class OccCurve2 final : public Curve2 {
 public:
  OccCurve2(const Handle(Geom2d_Curve) & c, double first, double last)
      : a_(c, first, last), kind_(curve_kind(a_.GetType())), r_{first, last} {}
  CurvePoint2 eval(double t) const override {
    gp_Pnt2d p;
    gp_Vec2d d1, d2;
    try {
      OCC_CATCH_SIGNALS
      a_.D2(t, p, d1, d2);
    } catch (const Standard_Failure& f) {
      eval_failed("pcurve", f, t, 0.0);
    }
    return {v2(p), v2(d1), v2(d2)};
  }
  Interval range() const override { return r_; }
  CurveKind kind() const override { return kind_; }

 private:
  Geom2dAdaptor_Curve a_;
  CurveKind kind_;
  Interval r_;
};

std::string check_reason(const BRepCheck_Analyzer& an, const TopoDS_Face& f) {
  // First non-OK status of the face itself, else of one of its sub-shapes.
  auto first_bad = [&](const TopoDS_Shape& s) -> std::string {
    const Handle(BRepCheck_Result)& r = an.Result(s);
    if (r.IsNull()) return {};
    for (BRepCheck_ListIteratorOfListOfStatus it(r->Status()); it.More(); it.Next()) {
      if (it.Value() == BRepCheck_NoError) continue;
      std::ostringstream os;
      BRepCheck::Print(it.Value(), os);
      std::string s2 = os.str();
      while (!s2.empty() && (s2.back() == '\n' || s2.back() == ' ')) s2.pop_back();
      return s2;
    }
    return {};
  };
  if (std::string s = first_bad(f); !s.empty()) return "face: " + s;
  for (TopExp_Explorer ex(f, TopAbs_WIRE); ex.More(); ex.Next())
    if (std::string s = first_bad(ex.Current()); !s.empty()) return "wire: " + s;
  for (TopExp_Explorer ex(f, TopAbs_EDGE); ex.More(); ex.Next())
    if (std::string s = first_bad(ex.Current()); !s.empty()) return "edge: " + s;
  for (TopExp_Explorer ex(f, TopAbs_VERTEX); ex.More(); ex.Next())
    if (std::string s = first_bad(ex.Current()); !s.empty()) return "vertex: " + s;
  return "invalid (BRepCheck)";
}

// Why a face with an open wire is degenerate (Face::degenerate), or "" when it is not: its area A
// is at most its boundary length P times the largest tolerance T of its boundary edges and
// vertices, i.e. its mean width 2A/P is at most 2T: the whole face lies within the
// tolerance tube of its own boundary (e.g. one B-spline edge whose ends are farther
// apart than its tolerance, so the wire is open, bounding a sliver narrower than that
// tolerance); meshing such faces fails, or gives needles that deviate from the surface.
std::string degenerate_face_reason(const TopoDS_Face& f) {
  double perimeter = 0.0, tol = BRep_Tool::Tolerance(f);
  for (TopExp_Explorer ex(f, TopAbs_EDGE); ex.More(); ex.Next()) {
    const TopoDS_Edge& e = TopoDS::Edge(ex.Current());
    tol = std::max(tol, BRep_Tool::Tolerance(e));
    if (BRep_Tool::Degenerated(e)) continue;
    GProp_GProps g;
    BRepGProp::LinearProperties(e, g);
    perimeter += g.Mass();
  }
  for (TopExp_Explorer ex(f, TopAbs_VERTEX); ex.More(); ex.Next())
    tol = std::max(tol, BRep_Tool::Tolerance(TopoDS::Vertex(ex.Current())));
  GProp_GProps g;
  BRepGProp::SurfaceProperties(f, g);
  const double area = std::abs(g.Mass());
  if (!(area <= perimeter * tol)) return {};
  std::ostringstream os;
  os << "area " << area << " within its boundary's tolerance tube (boundary length " << perimeter
     << ", tolerance " << tol << ": mean width " << (perimeter > 0 ? 2 * area / perimeter : 0.0)
     << " <= " << 2 * tol << "; its wire is open)";
  return os.str();
}

// The pcurve of one use of a seam edge, to compare with the other use's.
struct SeamPcurve {
  std::size_t loop, use;
  Handle(Geom2d_Curve) c;
};

// Some files give both uses of a seam edge the same pcurve (a doubly periodic surface
// of revolution: both uses of the u-seam at u = 0, both of the v-seam at v = vmax), so the loop
// encloses nothing. The face's loop must run counter-clockwise: on a seam at constant u, the use
// going up (v increasing) is the right side and the one going down the left side; on a seam at
// constant v, the use going in +u is the bottom side. The use on the wrong side is moved by the
// period.
void fix_coincident_seams(Face& fc, const std::vector<SeamPcurve>& pcs) {
  if (!fc.surface) return;
  for (std::size_t i = 0; i < pcs.size(); ++i)
    for (std::size_t j = i + 1; j < pcs.size(); ++j) {
      EdgeUse& a = fc.loops[pcs[i].loop].uses[pcs[i].use];
      EdgeUse& b = fc.loops[pcs[j].loop].uses[pcs[j].use];
      if (a.edge != b.edge) continue;
      const Vec2 ma = a.pcurve->point(a.range.mid()), mb = b.pcurve->point(b.range.mid());
      const Box2 box = fc.surface->bounds();
      const double ext = std::max({box.u.length(), box.v.length(), 1e-300});
      if (glm::length(ma - mb) > 1e-9 * ext) continue;
      const Vec2 d = a.pcurve->point(a.range.hi) - a.pcurve->point(a.range.lo);
      const bool along_v = std::abs(d.y) > std::abs(d.x);  // a seam at constant u
      const Interval side = along_v ? box.u : box.v;
      // The period, or for a surface closed but not periodic in that direction (the
      // revolution of a closed B-spline profile) the parameter range, once its two
      // sides are checked to be one curve in space.
      double period = along_v ? fc.surface->u_period() : fc.surface->v_period();
      if (!(along_v ? fc.surface->u_periodic() : fc.surface->v_periodic()) || !(period > 0)) {
        period = side.length();
        const Interval other = along_v ? box.v : box.u;
        bool closed = period > 0;
        for (double w : {0.25, 0.5, 0.75}) {
          const double o = other.at(w);
          const Vec3 p0 = along_v ? fc.surface->point(side.lo, o) : fc.surface->point(o, side.lo);
          const Vec3 p1 = along_v ? fc.surface->point(side.hi, o) : fc.surface->point(o, side.hi);
          closed = closed && glm::length(p1 - p0) <= std::max(10 * fc.tol, 1e-9);
        }
        if (!closed) continue;
      }
      // Direction of each use in traversal order along the seam.
      const double sa = (along_v ? d.y : d.x) * (a.reversed ? -1 : 1);
      const double at = along_v ? ma.x : ma.y;
      const bool at_low = std::abs(at - side.lo) <= std::abs(at - side.hi);
      // along_v: the up-going use is the high side; along u: the +u use is the low side.
      const bool a_high = along_v ? sa > 0 : sa < 0;
      EdgeUse& mv = at_low ? (a_high ? a : b) : (a_high ? b : a);
      const SeamPcurve& pc = &mv == &a ? pcs[i] : pcs[j];
      const double shift = at_low ? period : -period;
      const gp_Vec2d t = along_v ? gp_Vec2d(shift, 0.0) : gp_Vec2d(0.0, shift);
      Handle(Geom2d_Curve) moved = Handle(Geom2d_Curve)::DownCast(pc.c->Translated(t));
      if (!moved.IsNull()) mv.pcurve = std::make_shared<OccCurve2>(moved, mv.range.lo, mv.range.hi);
    }
}

// Orders a loop's uses so that each starts, in (u,v), where the previous one ends. The
// wire explorer chains edges through their 3D vertices, which is ambiguous when one
// vertex closes several edges: on a doubly closed face (the revolution of a closed
// profile: one vertex and two seams) it returned
// "bottom, top, left, right", and the (u,v) boundary built from it jumped across the
// domain and crossed itself. A loop that already chains (total gap ~0) is left alone;
// otherwise a greedy chain from the first use is kept when it closes the gaps better.
void chain_loop_in_uv(Loop& loop, const Box2& box) {
  const double ext = std::max({box.u.length(), box.v.length(), 1e-300});
  std::vector<std::size_t> idx;
  for (std::size_t i = 0; i < loop.uses.size(); ++i)
    if (!loop.uses[i].internal) {
      if (!loop.uses[i].pcurve) return;
      idx.push_back(i);
    }
  if (idx.size() < 3) return;
  auto end_pt = [&](std::size_t i, bool start) {
    const EdgeUse& u = loop.uses[i];
    const bool lo = start != u.reversed;
    return u.pcurve->point(lo ? u.range.lo : u.range.hi);
  };
  auto total_gap = [&](const std::vector<std::size_t>& order) {
    double g = 0;
    for (std::size_t k = 0; k < order.size(); ++k)
      g += glm::length(end_pt(order[(k + 1) % order.size()], true) - end_pt(order[k], false));
    return g;
  };
  const double g0 = total_gap(idx);
  if (!(g0 > 1e-7 * ext)) return;
  std::vector<std::size_t> chain{idx[0]};
  std::vector<char> used(idx.size(), 0);
  used[0] = 1;
  for (std::size_t step = 1; step < idx.size(); ++step) {
    const Vec2 at = end_pt(chain.back(), false);
    std::size_t best = 0;
    double bd = std::numeric_limits<double>::infinity();
    for (std::size_t k = 1; k < idx.size(); ++k)
      if (!used[k]) {
        const double d = glm::length(end_pt(idx[k], true) - at);
        if (d < bd) bd = d, best = k;
      }
    used[best] = 1;
    chain.push_back(idx[best]);
  }
  if (!(total_gap(chain) < 0.5 * g0)) return;
  std::vector<EdgeUse> uses;
  uses.reserve(loop.uses.size());
  for (std::size_t i : chain) uses.push_back(std::move(loop.uses[i]));
  for (auto& u : loop.uses)
    if (u.internal) uses.push_back(std::move(u));
  loop.uses = std::move(uses);
}

// The shape's sub-shapes of every kind, numbered as the Model numbers them (index - 1).
struct OccMaps {
  TopTools_IndexedMapOfShape vmap, emap, fmap, shmap, somap;
};

void convert_vertices(const OccMaps& M, Model& m, std::string& where) {
  m.vertices.resize(static_cast<std::size_t>(M.vmap.Extent()));
  for (int i = 1; i <= M.vmap.Extent(); ++i) {
    where = "vertex " + std::to_string(i - 1);
    const TopoDS_Vertex& v = TopoDS::Vertex(M.vmap(i));
    m.vertices[i - 1] = {v3(BRep_Tool::Pnt(v)), BRep_Tool::Tolerance(v)};
  }
}

void convert_edges(const OccMaps& M, Model& m, std::string& where) {
  m.edges.resize(static_cast<std::size_t>(M.emap.Extent()));
  for (int i = 1; i <= M.emap.Extent(); ++i) {
    where = "edge " + std::to_string(i - 1);
    const TopoDS_Edge e = TopoDS::Edge(M.emap(i).Oriented(TopAbs_FORWARD));
    Edge& ed = m.edges[i - 1];
    ed.tol = BRep_Tool::Tolerance(e);
    ed.degenerate = BRep_Tool::Degenerated(e);
    TopoDS_Vertex vf, vl;
    TopExp::Vertices(e, vf, vl);
    if (!vf.IsNull()) ed.v0 = M.vmap.FindIndex(vf) - 1;
    if (!vl.IsNull()) ed.v1 = M.vmap.FindIndex(vl) - 1;
    double f = 0.0, l = 0.0;
    BRep_Tool::Range(e, f, l);
    ed.range = {f, l};
    // An edge without a 3D curve (degenerate, or some IGES edges known only by their
    // pcurves): BRepAdaptor_Curve falls back to the curve on surface when there is one.
    if (!ed.degenerate) {
      ed.curve = std::make_shared<OccCurve>(e);
      ed.range = ed.curve->range();
      ed.length = arc_length(*ed.curve, ed.range.lo, ed.range.hi);
    }
  }
}

// Boundary edges of wire w in connected order; INTERNAL edges (embedded, not a step of the
// cycle) after them; EXTERNAL ones are dropped by the caller.
std::vector<TopoDS_Edge> wire_edge_order(const TopoDS_Wire& w, const TopoDS_Face& ff) {
  auto embedded = [](const TopoDS_Shape& e) {
    return e.Orientation() == TopAbs_INTERNAL || e.Orientation() == TopAbs_EXTERNAL;
  };
  int n_edges = 0;
  for (TopoDS_Iterator it(w); it.More(); it.Next())
    if (it.Value().ShapeType() == TopAbs_EDGE && !embedded(it.Value())) ++n_edges;
  std::vector<TopoDS_Edge> order;
  // Connected order from the wire explorer; a wire it cannot chain (disconnected
  // or non-manifold) keeps its stored order instead of losing edges.
  for (BRepTools_WireExplorer wex(w, ff); wex.More(); wex.Next())
    if (!embedded(wex.Current())) order.push_back(wex.Current());
  if (static_cast<int>(order.size()) != n_edges) {
    order.clear();
    for (TopoDS_Iterator it(w); it.More(); it.Next())
      if (it.Value().ShapeType() == TopAbs_EDGE && !embedded(it.Value()))
        order.push_back(TopoDS::Edge(it.Value()));
  }
  for (TopoDS_Iterator it(w); it.More(); it.Next())
    if (it.Value().ShapeType() == TopAbs_EDGE && embedded(it.Value()))
      order.push_back(TopoDS::Edge(it.Value()));
  return order;
}

// The loops of face ff (forward) in its wires' order, with the seam pcurves that
// fix_coincident_seams inspects.
void convert_loops(const OccMaps& M, const TopoDS_Face& ff, Face& fc,
                   std::vector<SeamPcurve>& seam_pc) {
  const TopoDS_Wire outer = BRepTools::OuterWire(ff);
  for (TopoDS_Iterator wit(ff); wit.More(); wit.Next()) {
    if (wit.Value().ShapeType() != TopAbs_WIRE) continue;
    const TopoDS_Wire w = TopoDS::Wire(wit.Value());
    Loop loop;
    loop.outer = !outer.IsNull() && w.IsSame(outer);
    for (const TopoDS_Edge& e : wire_edge_order(w, ff)) {
      // EXTERNAL edges lie outside the face's material (construction geometry).
      if (e.Orientation() == TopAbs_EXTERNAL) continue;
      EdgeUse u;
      u.edge = M.emap.FindIndex(e) - 1;
      u.reversed = e.Orientation() == TopAbs_REVERSED;
      u.internal = e.Orientation() == TopAbs_INTERNAL;
      u.seam = BRep_Tool::IsClosed(e, ff);
      double f = 0.0, l = 0.0;
      Handle(Geom2d_Curve) c2 = BRep_Tool::CurveOnSurface(e, ff, f, l);
      if (!c2.IsNull()) u.pcurve = std::make_shared<OccCurve2>(c2, f, l);
      if (u.seam && !c2.IsNull()) seam_pc.push_back({fc.loops.size(), loop.uses.size(), c2});
      u.range = {f, l};
      loop.uses.push_back(std::move(u));
    }
    fc.loops.push_back(std::move(loop));
  }
}

void convert_face(const OccMaps& M, const TopoDS_Face& face0, const OccModelOptions& opt,
                  Face& fc) {
  fc.reversed = face0.Orientation() == TopAbs_REVERSED;
  const TopoDS_Face ff = TopoDS::Face(face0.Oriented(TopAbs_FORWARD));
  fc.tol = BRep_Tool::Tolerance(ff);
  double u0 = 0, u1 = 0, w0 = 0, w1 = 0;
  BRepTools::UVBounds(ff, u0, u1, w0, w1);
  fc.uv_box = {{u0, u1}, {w0, w1}};
  if (!BRep_Tool::Surface(ff).IsNull()) {
    auto s = std::make_shared<OccSurface>(ff, fc.uv_box, opt.pole_rel_tol);
    fc.kind = s->kind();
    fc.surface = std::move(s);
  }
  std::vector<SeamPcurve> seam_pc;
  convert_loops(M, ff, fc, seam_pc);
  fix_coincident_seams(fc, seam_pc);
  for (Loop& l : fc.loops) chain_loop_in_uv(l, fc.uv_box);
  std::stable_sort(fc.loops.begin(), fc.loops.end(),
                   [](const Loop& a, const Loop& b) { return a.outer && !b.outer; });
  if (opt.check_validity) {
    BRepCheck_Analyzer an(face0, Standard_True);
    fc.valid = an.IsValid();
    if (!fc.valid) fc.invalid_reason = check_reason(an, face0);
  }
  bool open_wire = false;
  for (TopoDS_Iterator wit(ff); wit.More(); wit.Next())
    if (wit.Value().ShapeType() == TopAbs_WIRE && !BRep_Tool::IsClosed(wit.Value()))
      open_wire = true;
  // Only a face with an open wire: a closed one around a sliver (strips between two
  // copies of one curve, narrower than their tolerances) still closes its solid between
  // those two curves, and is meshed.
  if (open_wire) fc.degenerate_reason = degenerate_face_reason(ff);
  fc.degenerate = !fc.degenerate_reason.empty();
}

void convert_faces(const OccMaps& M, const OccModelOptions& opt, Model& m, std::string& where) {
  m.faces.resize(static_cast<std::size_t>(M.fmap.Extent()));
  for (int i = 1; i <= M.fmap.Extent(); ++i) {
    where = "face " + std::to_string(i - 1);
    convert_face(M, TopoDS::Face(M.fmap(i)), opt, m.faces[i - 1]);
  }
}

void convert_shells_and_solids(const OccMaps& M, Model& m, std::string& where) {
  m.shells.resize(static_cast<std::size_t>(M.shmap.Extent()));
  for (int i = 1; i <= M.shmap.Extent(); ++i) {
    where = "shell " + std::to_string(i - 1);
    Shell& sh = m.shells[i - 1];
    sh.closed = BRep_Tool::IsClosed(M.shmap(i));
    for (TopExp_Explorer ex(M.shmap(i), TopAbs_FACE); ex.More(); ex.Next()) {
      const Id f = M.fmap.FindIndex(ex.Current()) - 1;
      if (std::find(sh.faces.begin(), sh.faces.end(), f) == sh.faces.end()) sh.faces.push_back(f);
      if (m.faces[f].shell == kNone) m.faces[f].shell = i - 1;
    }
  }
  m.solids.resize(static_cast<std::size_t>(M.somap.Extent()));
  for (int i = 1; i <= M.somap.Extent(); ++i) {
    Solid& so = m.solids[i - 1];
    for (TopExp_Explorer ex(M.somap(i), TopAbs_SHELL); ex.More(); ex.Next()) {
      const Id s = M.shmap.FindIndex(ex.Current()) - 1;
      if (std::find(so.shells.begin(), so.shells.end(), s) == so.shells.end())
        so.shells.push_back(s);
    }
  }
}

void add_bounding_box(const TopoDS_Shape& shape, Model& m) {
  Bnd_Box box;
  BRepBndLib::Add(shape, box, Standard_False);
  if (!box.IsVoid()) {
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    m.bbox.add(Vec3(x0, y0, z0));
    m.bbox.add(Vec3(x1, y1, z1));
  }
}

}  // namespace

Model model_from_occ(const TopoDS_Shape& shape, const OccModelOptions& opt) {
  Model m;
  std::string where = "shape";  // the entity being converted, for error messages
  try {
    // The signal handler covers every step below (they run inside this block).
    OCC_CATCH_SIGNALS
    OccMaps M;
    TopExp::MapShapes(shape, TopAbs_VERTEX, M.vmap);
    TopExp::MapShapes(shape, TopAbs_EDGE, M.emap);
    TopExp::MapShapes(shape, TopAbs_FACE, M.fmap);
    TopExp::MapShapes(shape, TopAbs_SHELL, M.shmap);
    TopExp::MapShapes(shape, TopAbs_SOLID, M.somap);
    convert_vertices(M, m, where);
    convert_edges(M, m, where);
    convert_faces(M, opt, m, where);
    convert_shells_and_solids(M, m, where);
    where = "vertices closing open edges";
    split_vertices_closing_open_edges(m);
    where = "bounding box";
    add_bounding_box(shape, m);
  } catch (const Standard_Failure& f) {
    throw std::runtime_error("OpenCASCADE failed while converting " + where + ": " +
                             occ_message(f));
  }
  return m;
}

}  // namespace uvmesh::geom
