// `uvmesh mesh MODEL -o OUT`: read, mesh (surface::mesh_model), check, write, report.
//
// Exit codes: 0 success; 1 command-line error (also --volume in a build without nglib);
// 2 the model could not be read; 3 some faces could not be meshed, or with --volume some
// solids could not be filled (the rest is written; 0 with --allow-holes); 4 the output
// could not be written.
#include "mesh_cmd.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <map>
#include <mutex>
#include <nlohmann/json.hpp>
#include <numbers>
#include <sstream>

#include "uvmesh/geom/subd.h"
#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/io/report.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"
#ifdef UVMESH_HAVE_VOLUME
#include "uvmesh/surface/volume.h"
#endif

namespace uvmesh::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// "ID=H" -> (ID, H); false when malformed.
bool parse_id_size(const std::string& s, geom::Id& id, double& h) {
  const auto eq = s.find('=');
  if (eq == std::string::npos) return false;
  try {
    std::size_t k1 = 0, k2 = 0;
    const long v = std::stol(s.substr(0, eq), &k1);
    h = std::stod(s.substr(eq + 1), &k2);
    if (k1 != eq || k2 != s.size() - eq - 1 || v < 0 || !(h > 0) || !std::isfinite(h)) return false;
    id = static_cast<geom::Id>(v);
    return true;
  } catch (...) {
    return false;
  }
}

// Local sizes file: one "face ID H" or "edge ID H" per line; '#' starts a comment.
bool read_size_file(const std::string& path, param::SizeSpec& spec, std::string& err) {
  std::ifstream in(path);
  if (!in) {
    err = path + ": cannot open the sizes file";
    return false;
  }
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (auto c = line.find('#'); c != std::string::npos) line.resize(c);
    std::istringstream ss(line);
    std::string kind;
    if (!(ss >> kind)) continue;
    long id = -1;
    double h = 0;
    std::string extra;
    if (!(ss >> id >> h) || (ss >> extra) || id < 0 || !(h > 0) || !std::isfinite(h) ||
        (kind != "face" && kind != "edge")) {
      err = path + ":" + std::to_string(ln) + ": expected 'face ID SIZE' or 'edge ID SIZE'";
      return false;
    }
    (kind == "face" ? spec.face_size : spec.edge_size)[static_cast<geom::Id>(id)] = h;
  }
  return true;
}

bool has_obj_extension(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  return ext == ".obj";
}

// "" when a file can be created at `path` (probed with a file created and removed beside
// it), else why not. Checked before reading and meshing, which can take minutes, so that
// an unwritable -o or --report fails at once and leaves nothing behind.
std::string check_writable(const std::string& path) {
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return path + ": is a directory";
  const std::string probe = path + ".probe-" + std::to_string(::getpid());
  const int fd = ::open(probe.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
  if (fd < 0) return path + ": cannot create a file there: " + std::strerror(errno);
  ::close(fd);
  ::unlink(probe.c_str());
  return "";
}

// The option checks that need no model: output format and paths, absolute sizes, the
// syntax of local sizes. What needs the model (hmin against a relative or default hmax,
// face and edge ids) is checked once it is read.
std::string check_flags(const MeshFlags& f, const io::WriteOptions& wo) {
  if (f.hmin > 0 && f.hmax > 0 && f.hmin > f.hmax) {
    std::ostringstream m;
    m << "--hmin " << f.hmin << " is larger than hmax " << f.hmax;
    return m.str();
  }
  for (const std::vector<std::string>* list : {&f.face_size, &f.edge_size})
    for (const std::string& s : *list) {
      geom::Id id;
      double h;
      if (!parse_id_size(s, id, h)) return "'" + s + "': expected ID=SIZE";
    }
  if (!wo.format && !io::format_from_path(f.out))
    return f.out + ": unknown mesh extension (known: " + io::known_mesh_extensions() + ")";
  if (f.volume) {
#ifndef UVMESH_HAVE_VOLUME
    return "--volume needs Netgen's nglib, and this uvmesh was built without it (install "
           "libnglib-dev and rebuild)";
#endif
    const io::MeshFormat fmt = wo.format ? *wo.format : *io::format_from_path(f.out);
    if (fmt != io::MeshFormat::Msh41 && fmt != io::MeshFormat::Msh22 &&
        fmt != io::MeshFormat::Medit && fmt != io::MeshFormat::Vtu)
      return f.out + ": --volume writes tetrahedra to .msh, .mesh or .vtu only";
  }
  if (!f.report.empty() && f.report == f.out)
    return f.out + ": given both as the mesh and as the report";
  if (std::string e = check_writable(f.out); !e.empty()) return e;
  if (!f.report.empty())
    if (std::string e = check_writable(f.report); !e.empty()) return e;
  return "";
}

}  // namespace

CLI::App* add_mesh_command(CLI::App& app, MeshFlags& f) {
  CLI::App* c = app.add_subcommand(
      "mesh",
      "mesh a CAD model into one conforming surface mesh.\n"
      "Defaults (D = bounding-box diagonal): --hmax D/20, --hmin D/1000, --angle 18 (20 elements\n"
      "per 2 pi), --chordal D/1000, --grad 1.3, isotropic sizes. Giving --angle or --chordal\n"
      "replaces both curvature defaults (the other is then off unless also given).\n"
      "Feature size (--min-feature L; default: hmin, at most the model box's thinnest side / 50):\n"
      "model edges shorter, faces narrower and gaps narrower than it set no size below it and\n"
      "are absorbed into their neighbours; model edges where the faces meet at less than\n"
      "--feature-angle (default 20) may be crossed by mesh edges. --keep-topology keeps every\n"
      "CAD entity in the mesh instead. --report lists each absorption.");
  add_read_flags(c, f.read);
  c->add_option("-o,--output", f.out,
                "output mesh; the extension picks the format (" + io::known_mesh_extensions() + ")")
      ->required();
  c->add_option("--hmax", f.hmax, "largest element size (model units)")->check(finite_positive());
  c->add_option("--hmax-rel", f.hmax_rel, "largest element size as a fraction of D")
      ->check(finite_positive());
  c->add_option("--hmin", f.hmin, "smallest element size")->check(finite_positive());
  c->add_option("--chordal", f.chordal, "maximum distance between the mesh and the surface")
      ->check(finite_positive());
  c->add_option("--angle", f.angle_deg, "each element spans at most DEG degrees of curvature arc")
      ->check(CLI::Range(0.1, 180.0));
  c->add_option("--min-feature", f.min_feature,
                "feature size: smaller CAD entities are absorbed (default: hmin)")
      ->check(finite_positive());
  c->add_option("--feature-angle", f.feature_angle_deg,
                "dihedral angle in degrees below which a CAD edge is smooth (default 20)")
      ->check(CLI::Range(0.0, 180.0));
  c->add_flag("--features", f.features,
              "absorb CAD entities below the default feature size (the default; see above)");
  c->add_flag("--keep-topology", f.keep_topology,
              "every CAD edge and face stays in the mesh; nothing is absorbed");
  c->add_option("--grad", f.grad, "gradation: neighbouring sizes differ by at most this ratio")
      ->check(CLI::Range(1.0, 100.0));
  c->add_flag("--iso", f.iso, "isotropic curvature sizes (the default)");
  c->add_option("--aniso", f.aniso,
                "anisotropic curvature sizes, stretch ratio at most R (e.g. 10)")
      ->check(CLI::Range(1.0, 1e4));
  c->add_option("--face-size", f.face_size, "local size on a face: ID=H (repeatable)");
  c->add_option("--edge-size", f.edge_size, "local size on an edge: ID=H (repeatable)");
  c->add_option("--sizes", f.size_file, "file of local sizes, lines 'face ID H' or 'edge ID H'");
  c->add_option("--threads", f.threads, "worker threads (default: all cores)")
      ->check(CLI::Range(0, 4096));
  c->add_option("--report", f.report,
                "write a JSON report (counts, times, quality, chordal, topology)");
  c->add_flag("--allow-holes", f.allow_holes,
              "exit 0 even when some faces could not be meshed (or, with --volume, some solids "
              "not filled)");
  c->add_flag("--volume", f.volume,
              "also fill every closed solid with tetrahedra (Netgen), bounded by the surface "
              "mesh unchanged; one region per solid (.msh, .mesh, .vtu); a solid that is not "
              "closed is named and skipped (exit 3 unless --allow-holes)");
  c->add_flag("--no-optimize3d", f.no_optimize3d, "skip the 3D swaps and smoothing");
  c->add_option("--face-time-limit", f.face_time_limit,
                "seconds the 2D mesher may spend on one face (0: no limit); a face beyond it is "
                "reported as failed and the rest of the model is meshed")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  c->add_flag("--no-selfint", f.no_selfint, "skip the self-intersection check of the report");
  c->add_flag("-q,--quiet", f.quiet, "no summary line");
  add_write_flags(c, f.write);
  c->add_option(
       "--scheme", f.scheme,
       "subdivision scheme of an .obj control cage (auto: loop when all faces are triangles)")
      ->check(CLI::IsMember({"auto", "catmark", "loop"}));
  c->add_option("--boundary-interp", f.boundary_interp,
                "boundary interpolation of an .obj cage (file: its 'interpolateboundary' tag, else "
                "edge-only)")
      ->check(CLI::IsMember({"file", "none", "edge-only", "edge-and-corner"}));
  return c;
}

namespace {

// The model: an .obj is a subdivision control cage (meshed on its OpenSubdiv limit
// surface); anything else goes to the CAD readers.
io::ReadResult read_model(const MeshFlags& f) {
  io::ReadResult rr;
  if (has_obj_extension(f.read.model)) {
    geom::SubdOptions so;
    geom::parse_subd_scheme(f.scheme, so.scheme);
    geom::parse_subd_boundary(f.boundary_interp, so.boundary);
    geom::SubdModelResult sr = geom::read_subd(f.read.model, so);
    rr.ok = sr.ok;
    rr.error = std::move(sr.error);
    rr.model = std::move(sr.model);
  } else {
    io::ReadOptions ro = read_options(f.read);
    ro.threads = f.threads;  // the assembly's general fuse runs on the same threads as the faces
    rr = io::read_cad(f.read.model, ro);
  }
  return rr;
}

// MeshOptions::size from the flags and the model (defaults relative to its diagonal);
// 0, or 1 after an error message.
int size_options(const MeshFlags& f, const geom::Model& model, surface::MeshOptions& o) {
  o.size = surface::default_size(model);
  const double D = model.bbox.diagonal();
  if (f.hmax_rel > 0) o.size.hmax = f.hmax_rel * D;
  if (f.hmax > 0) o.size.hmax = f.hmax;
  if (f.hmin > 0) o.size.hmin = f.hmin;
  if (f.hmin > 0 && f.hmin > o.size.hmax) {
    // Only the default hmin (D/1000) gives way to a small hmax; an explicit one is an error.
    std::cerr << "uvmesh: error: --hmin " << f.hmin << " is larger than hmax " << o.size.hmax
              << "\n";
    return 1;
  }
  o.size.hmin = std::min(o.size.hmin, o.size.hmax);
  if (f.chordal > 0 || f.angle_deg > 0) {
    o.size.chordal_tol = f.chordal;
    o.size.angle_tol = f.angle_deg * std::numbers::pi / 180.0;
  }
  if (f.grad > 0) o.size.gradation = f.grad;
  if (f.min_feature > 0) o.min_feature = f.min_feature;
  if (f.feature_angle_deg > 0) o.feature_angle = f.feature_angle_deg * std::numbers::pi / 180.0;
  o.keep_topology = f.keep_topology;
  if (f.aniso > 0 && !f.iso) {
    o.size.isotropic = false;
    o.size.max_anisotropy = f.aniso;
  }
  for (const auto& [list, target] :
       {std::pair{&f.face_size, &o.size.face_size}, std::pair{&f.edge_size, &o.size.edge_size}})
    for (const std::string& s : *list) {
      geom::Id id;
      double h;
      if (!parse_id_size(s, id, h)) {
        std::cerr << "uvmesh: error: '" << s << "': expected ID=SIZE\n";
        return 1;
      }
      (*target)[id] = h;
    }
  if (!f.size_file.empty()) {
    std::string err;
    if (!read_size_file(f.size_file, o.size, err)) {
      std::cerr << "uvmesh: error: " << err << "\n";
      return 1;
    }
  }
  for (const auto& [id, h] : o.size.face_size)
    if (id >= static_cast<geom::Id>(model.faces.size())) {
      std::cerr << "uvmesh: error: --face-size names face " << id << " but the model has "
                << model.faces.size() << " faces\n";
      return 1;
    }
  for (const auto& [id, h] : o.size.edge_size)
    if (id >= static_cast<geom::Id>(model.edges.size())) {
      std::cerr << "uvmesh: error: --edge-size names edge " << id << " but the model has "
                << model.edges.size() << " edges\n";
      return 1;
    }
  return 0;
}

struct Times {
  Clock::time_point all;
  double read = 0, mesh = 0, write = 0, volume = 0;
};

// The volume stage's outcome as the command uses it (the same with or without nglib).
struct VolumeRun {
  bool requested = false;
  surface::TetMesh mesh;
  std::vector<std::string> failed;  // one message per solid not filled, naming it
  nlohmann::json solids = nlohmann::json::array();
};

VolumeRun fill_volume(const MeshFlags& f, const geom::Model& model, const surface::MeshResult& r) {
  VolumeRun v;
  v.requested = f.volume;
  if (!f.volume) return v;
#ifdef UVMESH_HAVE_VOLUME
  surface::VolumeOptions vo;
  vo.hmax = r.size.hmax;  // the surface's largest size bounds the tetrahedra too
  surface::VolumeResult vr = surface::fill_solids(model, r.mesh, vo);
  v.mesh = std::move(vr.mesh);
  for (const auto& sf : vr.failed) v.failed.push_back(sf.message);
  for (const auto& st : vr.solids)
    v.solids.push_back({{"solid", st.solid},
                        {"triangles", st.triangles},
                        {"tets", st.tets},
                        {"interior_points", st.interior_points},
                        {"seconds", st.seconds}});
#else
  (void)model;
  (void)r;
#endif
  return v;
}

// The JSON report (--report): the report of `uvmesh check` (io/report.h), plus what only
// the mesher knows. Sets the free and non-manifold edge counts; 0, or 4 after an error
// message.
int write_report(const MeshFlags& f, const io::ReadResult& rr, const surface::MeshOptions& asked,
                 const surface::MeshResult& r, const VolumeRun& vol, const Times& times,
                 std::size_t& free_edges, std::size_t& nonman) {
  const geom::Model& model = rr.model;
  const surface::MeshOptions o = surface::effective_options(model, asked);
  const double D = model.bbox.diagonal();
  const auto t0 = Clock::now();
  io::CheckOptions co;
  co.threads = f.threads;
  co.self_intersections = !f.no_selfint;
  co.chordal_tolerance = o.size.chordal_tol;
  co.size = r.size;  // the sizes mesh_model made elements for
  const io::CheckData cd = io::check_mesh(r.mesh, &model, co);
  free_edges = cd.topology.free_edges;
  nonman = cd.topology.non_manifold_edges;
  nlohmann::json j = io::report_json(cd);
  j["model"] = f.read.model;
  j["output"] = f.out;
  j["units"] = model.units;
  j["bbox_diagonal"] = D;
  j["size"] = {{"hmax", o.size.hmax},
               {"hmin", o.size.hmin},
               {"chordal", o.size.chordal_tol},
               {"angle_deg", o.size.angle_tol * 180.0 / std::numbers::pi},
               {"gradation", o.size.gradation},
               {"isotropic", o.size.isotropic},
               {"min_feature", surface::feature_size(o, model.bbox)},
               {"feature_angle_deg", o.feature_angle * 180.0 / std::numbers::pi},
               {"keep_topology", o.keep_topology}};
  j["counts"]["faces"] = model.faces.size();
  j["counts"]["edges"] = model.edges.size();
  j["counts"]["faces_failed"] = r.failed.size();
  nlohmann::json sec = {{"read", times.read}, {"mesh", times.mesh}, {"write", times.write}};
  if (vol.requested) {
    sec["volume"] = times.volume;
    nlohmann::json v = io::tet_report_json(vol.mesh);
    v["mesher"] = "netgen nglib";
    v["filled"] = vol.solids;
    v["failed_solids"] = vol.failed;
    j["volume"] = v;
    j["counts"]["tets"] = vol.mesh.tets.size();
    j["counts"]["solids_filled"] = vol.solids.size();
    j["counts"]["solids_failed"] = vol.failed.size();
  }
  for (const auto& s : r.stages) sec["mesh_" + s.name] = s.seconds;
  // Unit edges are measured face by face, in the metric each face was meshed for.
  std::int64_t ne = 0, ns = 0, nl = 0;
  for (const auto& fs : r.faces) ne += fs.edges, ns += fs.short_edges, nl += fs.long_edges;
  j["unit_edge_share"] = r.unit_edge_share();
  j["edge_lengths"] = {{"edges", ne}, {"short", ns}, {"long", nl}};
  j["unit_edge_share_metric"] = surface::kFaceMetricName;
  nlohmann::json failed = nlohmann::json::array();
  for (const auto& ff : r.failed) failed.push_back({{"face", ff.face}, {"reason", ff.reason}});
  j["failed_faces"] = failed;
  j["warnings"] = r.warnings;
  nlohmann::json tw = nlohmann::json::array();
  for (const auto& [a, b] : r.twins) tw.push_back({{"face", a}, {"meshed_as", b}});
  j["coincident_faces"] = tw;
  nlohmann::json dg = nlohmann::json::array();
  for (const auto& d : r.degenerate) dg.push_back({{"face", d.face}, {"reason", d.reason}});
  j["degenerate_faces"] = dg;
  j["counts"]["faces_degenerate"] = r.degenerate.size();
  nlohmann::json cl = nlohmann::json::array();
  for (const auto& c : r.collapsed) cl.push_back({{"face", c.face}, {"reason", c.reason}});
  j["collapsed_faces"] = cl;
  nlohmann::json simp = nlohmann::json::array();
  for (const auto& s : r.simplified)
    simp.push_back({{"what", s.what},
                    {"vertices", s.vertices},
                    {"edges", s.edges},
                    {"faces", s.faces},
                    {"size", s.size},
                    {"why", s.why}});
  j["simplified"] = simp;
  j["counts"]["simplified"] = r.simplified.size();
  j["counts"]["faces_collapsed"] = r.collapsed.size();
  // What reading and healing did to the file (uvmesh info shows the same): a refused
  // step (an assembly left non-conforming) changes what the mesh can be.
  nlohmann::json heal = nlohmann::json::array();
  for (const auto& h : rr.report.healing)
    heal.push_back({{"name", h.name}, {"applied", h.applied}, {"detail", h.detail}});
  j["read"] = {{"warnings", rr.report.warnings}, {"healing", heal}};
  sec["checks"] = since(t0);
  sec["total"] = since(times.all);
  j["seconds"] = sec;
  const std::string tmp = f.report + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) {
      std::cerr << "uvmesh: error: " << f.report << ": cannot write the report\n";
      std::remove(tmp.c_str());
      return 4;
    }
  }
  if (std::rename(tmp.c_str(), f.report.c_str()) != 0) {
    std::cerr << "uvmesh: error: " << f.report << ": cannot write the report\n";
    std::remove(tmp.c_str());
    return 4;
  }
  return 0;
}

}  // namespace

int run_mesh(const MeshFlags& f) {
  const auto t_all = Clock::now();
  const io::WriteOptions wo = write_options(f.write);
  if (std::string e = check_flags(f, wo); !e.empty()) {
    std::cerr << "uvmesh: error: " << e << "\n";
    return 1;
  }
  auto t0 = Clock::now();
  io::ReadResult rr = read_model(f);
  if (!rr.ok) {
    std::cerr << "uvmesh: error: " << rr.error << "\n";
    return 2;
  }
  const double t_read = since(t0);
  const geom::Model& model = rr.model;

  // ---- sizes
  surface::MeshOptions o;
  if (int rc = size_options(f, model, o); rc != 0) return rc;
  o.threads = f.threads;
  o.face_time_limit = f.face_time_limit;
  o.optimize3d = !f.no_optimize3d;
  const bool tty = isatty(STDERR_FILENO) && !f.quiet;
  std::mutex mu;
  if (tty)
    o.progress = [&](int done, int total) {
      std::lock_guard<std::mutex> lock(mu);
      std::cerr << "\ruvmesh: faces " << done << "/" << total << std::flush;
    };

  // ---- mesh
  t0 = Clock::now();
  const surface::MeshResult r = surface::mesh_model(model, o);
  const double t_mesh = since(t0);
  if (tty) std::cerr << "\r" << std::string(40, ' ') << "\r";

  // ---- volume (--volume): tetrahedra in the closed solids
  t0 = Clock::now();
  const VolumeRun vol = fill_volume(f, model, r);
  const double t_volume = since(t0);

  // ---- write (atomic: temporary file renamed over the target)
  t0 = Clock::now();
  io::WriteOptions wov = wo;
  if (vol.requested) wov.volume = &vol.mesh;
  const io::WriteResult wr = io::write_mesh(r.mesh, &model, f.out, wov);
  const double t_write = since(t0);
  if (!wr.ok) {
    std::cerr << "uvmesh: error: " << wr.error << "\n";
    return 4;
  }

  for (const auto& ff : r.failed)
    std::cerr << "uvmesh: face " << ff.face << " not meshed: " << ff.reason << "\n";
  if (!f.quiet)
    for (const auto& d : r.degenerate)
      std::cerr << "uvmesh: face " << d.face << " not meshed, degenerate in the model: " << d.reason
                << "\n";
  if (!f.quiet)
    for (const auto& c : r.collapsed)
      std::cerr << "uvmesh: face " << c.face
                << " not meshed, collapsed onto one curve: " << c.reason << "\n";
  for (const std::string& m : vol.failed) std::cerr << "uvmesh: not filled: " << m << "\n";

  // ---- report
  std::size_t free_edges = 0, nonman = 0;
  if (!f.report.empty())
    if (int rc = write_report(f, rr, o, r, vol, {t_all, t_read, t_mesh, t_write, t_volume},
                              free_edges, nonman);
        rc != 0)
      return rc;

  if (!f.quiet) {
    std::cerr << "uvmesh: " << f.out << ": " << r.mesh.points.size() << " points, "
              << r.mesh.triangles.size() << " triangles, "
              << model.faces.size() - r.failed.size() - r.degenerate.size() - r.collapsed.size()
              << "/" << model.faces.size() << " faces meshed in " << t_mesh << " s";
    if (!r.degenerate.empty()) std::cerr << " (" << r.degenerate.size() << " degenerate)";
    if (!r.collapsed.empty()) std::cerr << " (" << r.collapsed.size() << " collapsed strips)";
    if (!f.report.empty())
      std::cerr << ", " << free_edges << " free / " << nonman << " non-manifold edges";
    if (vol.requested)
      std::cerr << "; " << vol.mesh.tets.size() << " tetrahedra in " << vol.solids.size() << "/"
                << model.solids.size() << " solids in " << t_volume << " s";
    std::cerr << "\n";
  }
  if (!r.failed.empty() && !f.allow_holes) {
    std::cerr << "uvmesh: error: " << r.failed.size()
              << " face(s) could not be meshed (the mesh was written with holes; --allow-holes "
                 "accepts that)\n";
    return 3;
  }
  if (!vol.failed.empty() && !f.allow_holes) {
    std::cerr << "uvmesh: error: " << vol.failed.size()
              << " solid(s) could not be filled (the others were written; --allow-holes "
                 "accepts that)\n";
    return 3;
  }
  return 0;
}

}  // namespace uvmesh::cli
