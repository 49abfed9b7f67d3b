// `uvmesh mesh MODEL -o OUT`: read, mesh, check, write, report. The job itself (options and
// their defaults and checks, read, mesh, report) is io/job.h, shared with the Python module;
// this is its command line: flags, output paths, messages and exit codes.
//
// Exit codes: 0 success; 1 command-line error (also --volume in a build without nglib);
// 2 the model could not be read; 3 some faces could not be meshed, or with --volume some
// solids could not be filled (the rest is written; 0 with --allow-holes); 4 the output
// could not be written.
#include "mesh_cmd.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <mutex>
#include <nlohmann/json.hpp>

#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::cli {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
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
std::string check_flags(const MeshFlags& f, const io::MeshJobOptions& job,
                        const io::WriteOptions& wo) {
  if (std::string e = io::check_options(job); !e.empty()) return e;
  for (const std::vector<std::string>* list : {&f.face_size, &f.edge_size})
    for (const std::string& s : *list) {
      geom::Id id;
      double h;
      if (!io::parse_id_size(s, id, h)) return "'" + s + "': expected ID=SIZE";
    }
  if (!wo.format && !io::format_from_path(f.out))
    return f.out + ": unknown mesh extension (known: " + io::known_mesh_extensions() + ")";
  if (job.volume) {
    const io::MeshFormat fmt = wo.format ? *wo.format : *io::format_from_path(f.out);
    if (!io::carries_tetrahedra(fmt))
      return f.out + ": --volume writes tetrahedra to .msh, .mesh or .vtu only";
  }
  if (!f.report.empty() && f.report == f.out)
    return f.out + ": given both as the mesh and as the report";
  if (std::string e = check_writable(f.out); !e.empty()) return e;
  if (!f.report.empty())
    if (std::string e = check_writable(f.report); !e.empty()) return e;
  return "";
}

// A flag's validator from the job's bounds (io::check_option_value): the command line and
// the Python module accept the same values, with the same messages.
CLI::Validator job_bounds(const char* flag) {
  return CLI::Validator(
      [flag](std::string& s) {
        double v = std::nan("");
        std::size_t used = 0;
        try {
          v = std::stod(s, &used);
        } catch (...) {
          used = 0;
        }
        return io::check_option_value(flag, used == s.size() ? v : std::nan(""), s);
      },
      io::option_bounds_text(flag));
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
  c->add_option("--hmax", f.job.hmax, "largest element size (model units)")
      ->check(job_bounds("--hmax"));
  c->add_option("--hmax-rel", f.job.hmax_rel, "largest element size as a fraction of D")
      ->check(job_bounds("--hmax-rel"));
  c->add_option("--hmin", f.job.hmin, "smallest element size")->check(job_bounds("--hmin"));
  c->add_option("--chordal", f.job.chordal, "maximum distance between the mesh and the surface")
      ->check(job_bounds("--chordal"));
  c->add_option("--angle", f.job.angle_deg,
                "each element spans at most DEG degrees of curvature arc")
      ->check(job_bounds("--angle"));
  c->add_option("--min-feature", f.job.min_feature,
                "feature size: smaller CAD entities are absorbed (default: hmin)")
      ->check(job_bounds("--min-feature"));
  c->add_option("--feature-angle", f.job.feature_angle_deg,
                "dihedral angle in degrees below which a CAD edge is smooth (default 20)")
      ->check(job_bounds("--feature-angle"));
  c->add_flag("--features", f.features,
              "absorb CAD entities below the default feature size (the default; see above)");
  c->add_flag("--keep-topology", f.job.keep_topology,
              "every CAD edge and face stays in the mesh; nothing is absorbed");
  c->add_option("--grad", f.job.grad, "gradation: neighbouring sizes differ by at most this ratio")
      ->check(job_bounds("--grad"));
  c->add_flag("--iso", f.iso, "isotropic curvature sizes (the default)");
  c->add_option("--aniso", f.job.aniso,
                "anisotropic curvature sizes, stretch ratio at most R (e.g. 10)")
      ->check(job_bounds("--aniso"));
  c->add_option("--face-size", f.face_size, "local size on a face: ID=H (repeatable)");
  c->add_option("--edge-size", f.edge_size, "local size on an edge: ID=H (repeatable)");
  c->add_option("--sizes", f.job.size_file,
                "file of local sizes, lines 'face ID H' or 'edge ID H'");
  c->add_option("--threads", f.job.threads, "worker threads (default: all cores)")
      ->check(job_bounds("--threads"));
  c->add_option("--report", f.report,
                "write a JSON report (counts, times, quality, chordal, topology)");
  c->add_flag("--allow-holes", f.allow_holes,
              "exit 0 even when some faces could not be meshed (or, with --volume, some solids "
              "not filled)");
  c->add_flag("--volume", f.job.volume,
              "also fill every closed solid with tetrahedra (Netgen), bounded by the surface "
              "mesh unchanged; one region per solid (.msh, .mesh, .vtu); a solid that is not "
              "closed is named and skipped (exit 3 unless --allow-holes)");
  c->add_flag("--no-optimize3d", f.no_optimize3d, "skip the 3D swaps and smoothing");
  c->add_flag("--frontal", f.job.frontal,
              "place each face's interior points frontally (more nearly equilateral typical "
              "triangles, a few percent more of them) instead of by edge saturation");
  c->add_option("--face-time-limit", f.job.face_time_limit,
                "seconds the 2D mesher may spend on one face (0: no limit); a face beyond it is "
                "reported as failed and the rest of the model is meshed")
      ->check(job_bounds("--face-time-limit"))
      ->capture_default_str();
  c->add_flag("--no-selfint", f.no_selfint, "skip the self-intersection check of the report");
  c->add_flag("-q,--quiet", f.quiet, "no summary line");
  add_write_flags(c, f.write);
  c->add_option(
       "--scheme", f.job.scheme,
       "subdivision scheme of an .obj control cage (auto: loop when all faces are triangles)")
      ->check(CLI::IsMember({"auto", "catmark", "loop"}));
  c->add_option("--boundary-interp", f.job.boundary_interp,
                "boundary interpolation of an .obj cage (file: its 'interpolateboundary' tag, else "
                "edge-only)")
      ->check(CLI::IsMember({"file", "none", "edge-only", "edge-and-corner"}));
  return c;
}

namespace {

// The job's options from the flags: the reading flags (shared with `uvmesh info`), the
// negated flags and the "ID=H" strings (already checked by check_flags).
io::MeshJobOptions job_options(const MeshFlags& f) {
  io::MeshJobOptions o = f.job;
  o.read = read_options(f.read);
  o.optimize3d = !f.no_optimize3d;
  o.self_intersections = !f.no_selfint;
  if (f.iso) o.aniso = 0;
  for (const auto& [list, target] :
       {std::pair{&f.face_size, &o.face_size}, std::pair{&f.edge_size, &o.edge_size}})
    for (const std::string& s : *list) {
      geom::Id id;
      double h;
      if (io::parse_id_size(s, id, h)) (*target)[id] = h;
    }
  return o;
}

// The report at f.report (written atomically); 0, or 4 after an error message.
int write_report(const std::string& path, const nlohmann::json& j) {
  const std::string tmp = path + ".tmp";
  {
    std::ofstream out(tmp);
    out << j.dump(2) << "\n";
    if (!out) {
      std::cerr << "uvmesh: error: " << path << ": cannot write the report\n";
      std::remove(tmp.c_str());
      return 4;
    }
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    std::cerr << "uvmesh: error: " << path << ": cannot write the report\n";
    std::remove(tmp.c_str());
    return 4;
  }
  return 0;
}

// What was left out of the mesh, one line per face (failed faces always; the others
// unless --quiet).
void print_left_out(const MeshFlags& f, const surface::MeshResult& r) {
  for (const auto& ff : r.failed)
    std::cerr << "uvmesh: face " << ff.face << " not meshed: " << ff.reason << "\n";
  if (f.quiet) return;
  for (const auto& d : r.degenerate)
    std::cerr << "uvmesh: face " << d.face << " not meshed, degenerate in the model: " << d.reason
              << "\n";
  for (const auto& c : r.collapsed)
    std::cerr << "uvmesh: face " << c.face << " not meshed, collapsed onto one curve: " << c.reason
              << "\n";
}

}  // namespace

int run_mesh(const MeshFlags& f) {
  const auto t_all = Clock::now();
  const io::WriteOptions wo = write_options(f.write);
  io::MeshJobOptions job = job_options(f);
  if (std::string e = check_flags(f, job, wo); !e.empty()) {
    std::cerr << "uvmesh: error: " << e << "\n";
    return 1;
  }
  auto t0 = Clock::now();
  const io::ReadResult rr = io::read_model(f.read.model, job);
  if (!rr.ok) {
    std::cerr << "uvmesh: error: " << rr.error << "\n";
    return 2;
  }
  const double t_read = since(t0);
  const geom::Model& model = rr.model;

  const bool tty = isatty(STDERR_FILENO) && !f.quiet;
  std::mutex mu;
  if (tty)
    job.progress = [&](int done, int total) {
      std::lock_guard<std::mutex> lock(mu);
      std::cerr << "\ruvmesh: faces " << done << "/" << total << std::flush;
    };
  const io::MeshRun run = io::mesh_job(model, job);
  if (!run.error.empty()) {
    std::cerr << "uvmesh: error: " << run.error << "\n";
    return 1;
  }
  const surface::MeshResult& r = run.result;
  if (tty) std::cerr << "\r" << std::string(40, ' ') << "\r";

  // ---- write (atomic: temporary file renamed over the target)
  t0 = Clock::now();
  io::WriteOptions wov = wo;
  if (run.volume.requested) wov.volume = &run.volume.mesh;
  const io::WriteResult wr = io::write_mesh(r.mesh, &model, f.out, wov);
  const double t_write = since(t0);
  if (!wr.ok) {
    std::cerr << "uvmesh: error: " << wr.error << "\n";
    return 4;
  }
  print_left_out(f, r);
  for (const std::string& m : run.volume.failed) std::cerr << "uvmesh: not filled: " << m << "\n";

  // ---- report
  std::size_t free_edges = 0, nonman = 0;
  if (!f.report.empty()) {
    const nlohmann::json j =
        io::mesh_report(job, rr, run, {f.read.model, f.out, t_all, t_read, t_write});
    free_edges = j["topology"]["free_edges"];
    nonman = j["topology"]["non_manifold_edges"];
    if (int rc = write_report(f.report, j); rc != 0) return rc;
  }

  if (!f.quiet) {
    std::cerr << "uvmesh: " << f.out << ": " << r.mesh.points.size() << " points, "
              << r.mesh.triangles.size() << " triangles, "
              << model.faces.size() - r.failed.size() - r.degenerate.size() - r.collapsed.size()
              << "/" << model.faces.size() << " faces meshed in " << run.seconds << " s";
    if (!r.degenerate.empty()) std::cerr << " (" << r.degenerate.size() << " degenerate)";
    if (!r.collapsed.empty()) std::cerr << " (" << r.collapsed.size() << " collapsed strips)";
    if (!f.report.empty())
      std::cerr << ", " << free_edges << " free / " << nonman << " non-manifold edges";
    if (run.volume.requested)
      std::cerr << "; " << run.volume.mesh.tets.size() << " tetrahedra in "
                << run.volume.solids.size() << "/" << model.solids.size() << " solids in "
                << run.volume.seconds << " s";
    std::cerr << "\n";
  }
  if (!r.failed.empty() && !f.allow_holes) {
    std::cerr << "uvmesh: error: " << r.failed.size()
              << " face(s) could not be meshed (the mesh was written with holes; --allow-holes "
                 "accepts that)\n";
    return 3;
  }
  if (!run.volume.failed.empty() && !f.allow_holes) {
    std::cerr << "uvmesh: error: " << run.volume.failed.size()
              << " solid(s) could not be filled (the others were written; --allow-holes "
                 "accepts that)\n";
    return 3;
  }
  return 0;
}

}  // namespace uvmesh::cli
