// uvmesh::io CAD readers: STEP (.step/.stp), IGES (.igs/.iges) and OpenCASCADE BREP
// (.brep/.brp/.rle, with or without a leading DBRep_DrawableShape line) into a
// geom::Model, with the healing users expect and a report of every change.
//
//   io::ReadOptions opt;                 // heal = true: ShapeFix, then sewing if needed
//   io::ReadResult r = io::read_cad("part.step", opt);
//   if (!r.ok) { std::cerr << r.error << "\n"; return 2; }   // names the file and the defect
//   const geom::Model& m = r.model;     // m.units: length unit of the coordinates
//   r.report.mm_per_unit                 // 25.4 for a STEP file in inches; 0 for BREP
//   for (const io::HealStep& s : r.report.healing) ...       // what healing changed
//
// Bad input never crashes or hangs: the file is pre-scanned (format sniffing, truncation,
// NaN / infinite / huge coordinates, dangling STEP references) before OpenCASCADE sees
// it, OCC exceptions and signals are caught, and an empty result is an error.
//
// Units: the model keeps the file's length unit. A STEP file in inches gives coordinates
// in inches (m.units == "inch"), an IGES file in metres coordinates in metres; BREP has no
// unit (m.units == ""). ReadOptions::units asks for another unit instead ("mm": what OCC
// gives by default). Both go through OCC's own unit handling at transfer time (the STEP
// reader's system length unit, the IGES global section's cascade unit), so reading in the
// file's unit applies a factor of exactly 1: coordinates are the numbers in the file.
// Available with UVMESH_BUILD_CAD only.
#pragma once

#include <string>
#include <vector>

#include "uvmesh/geom/model.h"

namespace uvmesh::io {

struct ReadOptions {
  /// Heal the shape: ShapeFix_Shape on faces and wires, then sewing when the model has
  /// free edges. false = use the model exactly as read (`--no-heal`).
  bool heal = true;
  /// Sewing tolerance, relative to the bounding-box diagonal. 1e-6 closes the gaps of
  /// typical IGES exports (single-precision writers leave ~1e-7 relative gaps) without
  /// merging features: the corpus' shortest real edges are ~1e-4 of the diagonal.
  double sew_rel_tol = 1e-6;
  /// Largest sewing tolerance tried, relative to the diagonal, when free edges remain
  /// after sewing at sew_rel_tol: the tolerance grows tenfold per attempt up to this
  /// value, and never beyond a tenth of the model's shortest edge (sewing at a tolerance
  /// near an edge's length merges that edge's ends). Some exports leave gaps of ~1e-5 of
  /// the diagonal between faces that meet; meshing such a
  /// model unsewn gives two independent discretizations of one curve, whose chords cross
  /// each other: self-intersections. 1e-4 is a tenth of the default hmin (D/1000), a gap
  /// no mesh at these sizes can represent. Set it to sew_rel_tol to sew only once.
  double sew_max_rel_tol = 1e-4;
  /// Make an assembly conforming: general fuse (BRepAlgoAPI_BuilderAlgo) of all solids,
  /// so that touching solids share their interface faces. Off by default: it changes
  /// the topology and costs seconds on large assemblies.
  bool conform = false;
  /// Threads the general fuse of `conform` may use. 1: OCC's sequential mode. 0 (all
  /// cores) or more: OCC's parallel mode (the interferences of independent pairs of
  /// sub-shapes computed concurrently, then merged in a fixed order, so the result does not
  /// depend on the thread count: the determinism test compares the meshes byte for byte),
  /// run inside a TBB arena of that many threads. On a large assembly the fuse is most of a
  /// 1-thread run.
  int threads = 1;
  /// Run BRepCheck per face (geom::Face::valid).
  bool check_validity = true;
  /// Import a STEP file with references to undefined entities, dropping what depends on
  /// them (with a warning), instead of rejecting it. See PrescanOptions.
  bool allow_partial = false;
  /// Read by content when the extension disagrees with it (otherwise an error).
  bool trust_content = false;
  /// Coordinates beyond this magnitude are rejected (1e12: a kilometre-size part in
  /// micrometres is 1e9; beyond 1e12 double spacing exceeds 1e-4 and no CAD model has
  /// a meaningful point there -- a corrupted number is far more likely).
  double max_abs_coordinate = 1e12;
  /// Length unit of the model's coordinates: "" keeps the file's unit; otherwise a unit
  /// name (io/units.h: "mm", "cm", "m", "inch", ...) the STEP / IGES transfer converts to.
  /// BREP files carry no unit: there the request is ignored with a warning.
  std::string units;
  /// Install OCC's signal handlers (OSD::SetSignal, no floating-point traps) once, so
  /// that a crash inside OCC becomes a reported error. Process-wide; tools want it.
  bool install_signal_handlers = true;
};

/// One healing step and what it changed.
struct HealStep {
  std::string name;      ///< "shapefix", "sewing", "conform"
  bool applied = false;  ///< the result was kept
  std::string detail;    ///< human-readable: counts before -> after, tolerance, reason
  int faces_before = 0, faces_after = 0;
  int edges_before = 0, edges_after = 0;
  int solids_before = 0, solids_after = 0;
  int free_edges_before = 0, free_edges_after = 0;
  double seconds = 0.0;
};

struct ReadReport {
  std::string format;      ///< "step", "iges", "brep"
  std::string file_units;  ///< canonical unit the file declares (io/units.h); "" for BREP, or
                           ///< when the file declares none or one this reader does not know
  std::string file_units_declared;  ///< the file's own spelling ("INCH", "centimetre", IGES flag)
  double mm_per_unit = 0.0;      ///< millimetres per unit of the coordinates; 0 = unitless (BREP)
  bool units_converted = false;  ///< coordinates were converted from the file's unit
  std::vector<HealStep> healing;
  std::vector<std::string> warnings;
  bool validity_checked = false;  ///< geom::Face::valid comes from BRepCheck
  double read_seconds = 0.0;      ///< parse + transfer
  double heal_seconds = 0.0;
  double build_seconds = 0.0;  ///< geom::Model construction (incl. validity checks)
};

struct ReadResult {
  bool ok = false;
  std::string error;  ///< "<file>: <what is wrong>" when !ok
  geom::Model model;
  ReadReport report;
};

ReadResult read_cad(const std::string& path, const ReadOptions& opt = {});

}  // namespace uvmesh::io
