// uvmesh::io meshing job -- the one definition of what `uvmesh mesh` and the Python
// module's uvmesh.mesh() do: the options with their defaults, their validation (the
// messages the CLI prints), their conversion into surface::MeshOptions, reading a model
// (CAD file or subdivision cage), meshing it and building the JSON report. Front ends
// only parse their own syntax into MeshJobOptions and present the results: nothing here
// prints, nothing is global.
//
//   io::MeshJobOptions o;                       // the CLI's defaults
//   o.hmax = 2.5;
//   if (std::string e = io::check_options(o); !e.empty()) return usage_error(e);
//   io::ReadResult rr = io::read_model("part.step", o);
//   io::MeshRun run = io::mesh_job(rr.model, o);          // run.error: sizes vs the model
//   nlohmann::json j = io::mesh_report(o, rr, run, {"part.step", "part.msh", times});
//
// Available with UVMESH_BUILD_CAD only (read_model uses the OCC readers).
#pragma once

#include <chrono>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>

#include "uvmesh/geom/model.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/surface/mesher.h"
#include "uvmesh/surface/tet_mesh.h"

namespace uvmesh::io {

/// `uvmesh mesh` reads assemblies conforming (imprinted): two triangulations of one
/// interface intersect, and volume meshers reject them. `uvmesh info` does not.
inline ReadOptions mesh_read_defaults() {
  ReadOptions r;
  r.conform = true;
  return r;
}

/// Every option of a meshing job. A size or angle of 0 means "the default", which depends
/// on the model (D = bounding-box diagonal: hmax D/20, hmin D/1000, chordal D/1000, angle
/// 18 degrees, gradation 1.3; surface::default_size). Giving chordal or angle replaces
/// both curvature defaults.
struct MeshJobOptions {
  ReadOptions read = mesh_read_defaults();
  double hmax = 0, hmax_rel = 0, hmin = 0, chordal = 0, angle_deg = 0, grad = 0;
  double aniso = 0;              ///< > 0: anisotropic curvature sizes with this maximum ratio
  double min_feature = 0;        ///< 0: hmin (surface::feature_size)
  double feature_angle_deg = 0;  ///< 0: MeshOptions' default
  bool keep_topology = false;
  std::map<geom::Id, double> face_size, edge_size;  ///< local sizes by entity id
  std::string size_file;           ///< lines "face ID H" / "edge ID H"; '#' starts a comment
  int threads = 0;                 ///< 0: all cores (reading's general fuse, faces, checks)
  double face_time_limit = 120.0;  ///< seconds per face in the 2D mesher; 0 = none
  bool optimize3d = true;
  bool frontal = false;            ///< surface::MeshOptions::frontal
  bool self_intersections = true;  ///< the report's self-intersection search
  /// Also fill every closed solid with tetrahedra bounded by the surface mesh unchanged
  /// (surface::fill_solids, Netgen's nglib; volume_available()).
  bool volume = false;
  /// Subdivision cages (.obj): OpenSubdiv scheme and boundary interpolation names
  /// (geom/subd.h).
  std::string scheme = "auto";
  std::string boundary_interp = "file";
  /// Called as faces are meshed (faces done, faces in all), from worker threads, one call
  /// at a time per job but not always from the same thread.
  std::function<void(int, int)> progress;
};

/// "" when the options are usable, else the message `uvmesh mesh` gives (naming the
/// flag). Checks what needs no model; mesh_job checks the rest.
std::string check_options(const MeshJobOptions& o);

/// The bounds of a numeric option, named by its command-line flag ("--grad"): "" when `v`
/// is allowed, else why not, without the flag's name ("value 0.5 not in range 1 to 100";
/// `text`, when given, is how the value was written). The one definition of the bounds:
/// the CLI's validators call it, check_options too. "" for a flag it does not know.
std::string check_option_value(std::string_view flag, double v, std::string_view text = {});

/// The bounds of check_option_value as `--help` shows them: "X>0", "[1 - 100]".
std::string option_bounds_text(std::string_view flag);

/// "ID=H" -> (ID, H); false when malformed (the syntax of --face-size and --edge-size).
bool parse_id_size(const std::string& s, geom::Id& id, double& h);

/// True for a path with the .obj extension (any case): a subdivision control cage.
bool is_cage_path(const std::string& path);

/// The model at `path`: an .obj is a subdivision control cage (meshed on its OpenSubdiv
/// limit surface, with o.scheme and o.boundary_interp); anything else goes to read_cad
/// with o.read (its threads set to o.threads).
ReadResult read_model(const std::string& path, const MeshJobOptions& o);

/// surface::MeshOptions from the job's options and the model (sizes relative to its
/// diagonal, local sizes, the sizes file). "" or the error (hmin above the resolved hmax,
/// a face or edge id the model does not have, an unreadable sizes file).
std::string mesh_options(const MeshJobOptions& o, const geom::Model& model,
                         surface::MeshOptions& out);

/// True when this build can fill solids with tetrahedra (nglib was found).
bool volume_available();

/// The volume stage's outcome (MeshJobOptions::volume).
struct VolumeRun {
  bool requested = false;
  surface::TetMesh mesh;                            ///< the surface's points first, same indices
  std::vector<std::string> failed;                  ///< one message per solid not filled, naming it
  nlohmann::json solids = nlohmann::json::array();  ///< per filled solid: counts, seconds
  double seconds = 0;
};

/// A meshed model: what mesh_job gives.
struct MeshRun {
  std::string error;  ///< the options do not fit the model (nothing was meshed)
  surface::MeshOptions asked;
  surface::MeshResult result;
  double seconds = 0;  ///< mesh_model's wall time
  VolumeRun volume;    ///< requested only with MeshJobOptions::volume
};

MeshRun mesh_job(const geom::Model& model, const MeshJobOptions& o);

/// What the report says beyond the meshes: where the model came from and went to, times.
struct ReportContext {
  std::string model_path;
  std::string output;                           ///< "" = not written (JSON null)
  std::chrono::steady_clock::time_point start;  ///< the job's start ("total" seconds)
  double read_seconds = 0, write_seconds = 0;
};

/// The JSON report of `uvmesh mesh --report` (io/report.h's check report plus sizes,
/// times, failed, degenerate, collapsed and simplified faces, reading's warnings).
nlohmann::json mesh_report(const MeshJobOptions& o, const ReadResult& rr, const MeshRun& run,
                           const ReportContext& ctx);

}  // namespace uvmesh::io
