// `uvmesh check MESH`: read a mesh file (io/mesh_reader.h), run the report checks
// (io/report.h, the same report `uvmesh mesh --report` writes), print it as text or
// JSON, and optionally draw SVG histograms and a face's (u,v) mesh.
//
// Exit codes: 0 the mesh was checked (whatever it holds); 1 command-line error; 2 the
// mesh or the model could not be read (one line on stderr: file, where, problem); 4 an
// SVG could not be written.
#include "check_cmd.h"

#include <filesystem>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>
#include <numbers>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/mesh_reader.h"
#include "uvmesh/io/report.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::cli {

namespace {

bool write_file(const std::filesystem::path& p, const std::string& text) {
  std::ofstream out(p, std::ios::binary);
  out << text;
  out.close();
  return static_cast<bool>(out);
}

}  // namespace

CLI::App* add_check_command(CLI::App& app, CheckFlags& f) {
  CLI::App* c = app.add_subcommand(
      "check",
      "grade a surface mesh: topology (free, non-manifold, inconsistently oriented edges, "
      "components),\n"
      "self-intersections, shape quality (Q, q, angles), edge lengths, chordal deviation against "
      "the\n"
      "CAD model (--model; the mesh's face ids must be the model's, as uvmesh writes them)");
  c->add_option("MESH", f.mesh, "mesh file (" + io::readable_mesh_extensions() + ")")->required();
  c->add_option(
      "--format", f.format,
      "read as this format instead of the extension's (msh41, medit, meshb, stl, obj, ply, drc)");
  c->add_option("--model", f.model.model, "CAD model the mesh was made from (STEP, IGES, BREP)");
  c->add_flag("--no-heal", f.model.no_heal,
              "read the model without healing (as `uvmesh mesh --no-heal` did)");
  c->add_flag("--conform", f.model.conform,
              "read the model made conforming (as `uvmesh mesh --conform` did)");
  c->add_option("--chordal", f.chordal, "chordal tolerance to compare the deviation with")
      ->check(CLI::PositiveNumber);
  // The size options of `uvmesh mesh`, for edge lengths in the size metric (with --model).
  c->add_option("--hmax", f.hmax, "with --model: largest size of the metric (default D/20)")
      ->check(CLI::PositiveNumber);
  c->add_option("--hmin", f.hmin, "with --model: smallest size of the metric (default D/1000)")
      ->check(CLI::PositiveNumber);
  c->add_option("--angle", f.angle_deg, "with --model: curvature angle per element, degrees")
      ->check(CLI::Range(0.1, 180.0));
  c->add_option("--grad", f.grad, "with --model: gradation of the metric")
      ->check(CLI::Range(1.0, 100.0));
  c->add_option("--aniso", f.aniso,
                "with --model: anisotropic curvature sizes, stretch ratio at most R")
      ->check(CLI::Range(1.0, 1e4));
  c->add_flag("--json", f.json, "the JSON report on stdout");
  c->add_option("--svg", f.svg_dir,
                "write histograms of quality, angles and edge sizes as SVG into DIR");
  c->add_option("--face", f.face,
                "with --svg: also draw face N's mesh in its (u,v) domain (needs --model for a file "
                "without (u,v))")
      ->check(CLI::NonNegativeNumber);
  c->add_option("--threads", f.threads, "worker threads (default: all cores)")
      ->check(CLI::NonNegativeNumber);
  c->add_flag("--no-selfint", f.no_selfint, "skip the self-intersection search");
  return c;
}

namespace {

// The SVG pictures (--svg DIR): histograms, and with --face that face's (u,v) mesh; their
// paths go to j["svg"]. 0, or the exit code after an error message.
int write_svgs(const CheckFlags& f, const io::CheckData& d, const io::MeshReadResult& mr,
               nlohmann::json& j) {
  namespace fs = std::filesystem;
  std::error_code ec;
  fs::create_directories(f.svg_dir, ec);
  const fs::path dir(f.svg_dir);
  struct Picture {
    const char* file;
    std::string svg;
  };
  std::vector<Picture> pics = {
      {"quality_q.svg",
       io::histogram_svg(d.q_histogram, "shape quality q = 1/Q (1 = equilateral)", "q")},
      {"angles.svg", io::histogram_svg(d.angle_histogram, "triangle angles", "degrees")},
      {"edge_length.svg",
       io::histogram_svg(d.edge_histogram,
                         "edge length / median edge (" + std::to_string(d.median_edge) + ")",
                         "length / median (half-octave bins)")}};
  if (f.face >= 0) {
    if (mr.mesh.triangle_uv.size() != mr.mesh.triangles.size()) {
      std::cerr << "uvmesh: error: --face " << f.face
                << ": the mesh has no (u,v); give --model (and a mesh with face ids)\n";
      return 1;
    }
    std::string svg = io::face_uv_svg(mr.mesh, f.face);
    if (svg.empty()) {
      std::cerr << "uvmesh: error: --face " << f.face << ": no triangles on that face\n";
      return 1;
    }
    pics.push_back({"face_uv.svg", std::move(svg)});
  }
  for (const Picture& p : pics) {
    const fs::path path = dir / (f.face >= 0 && std::string(p.file) == "face_uv.svg"
                                     ? "face_" + std::to_string(f.face) + "_uv.svg"
                                     : std::string(p.file));
    if (!write_file(path, p.svg)) {
      std::cerr << "uvmesh: error: " << path.string() << ": cannot write\n";
      return 4;
    }
    j["svg"].push_back(path.string());
  }
  return 0;
}

// The text summary (without --json).
void print_summary(const CheckFlags& f, const io::CheckData& d, const io::MeshReadResult& mr,
                   const nlohmann::json& j) {
  const auto& t = d.topology;
  const auto& q = d.quality;
  std::cout << f.mesh << " (" << io::format_name(mr.format) << "): " << d.points << " points, "
            << d.triangles << " triangles, " << d.segments << " segments\n";
  std::cout << "topology: " << t.edges << " edges, " << t.free_edges << " free, "
            << t.non_manifold_edges << " non-manifold, " << t.inconsistent_edges
            << " inconsistently oriented; " << d.components
            << " component(s); Euler characteristic " << t.euler_characteristic << "; "
            << t.degenerate_triangles << " degenerate triangles; " << t.close_points.pairs
            << " close point pairs" << (t.watertight() ? "; watertight" : "") << "\n";
  if (d.intersections)
    std::cout << "self-intersections: " << d.intersections->intersecting_pairs << " triangle pairs"
              << (d.intersections_in_model ? " (" + std::to_string(*d.intersections_in_model) +
                                                 " where the model's own surfaces intersect)"
                                           : std::string())
              << "\n";
  // A solid's own triangles, what a volume mesher fills: a stray sheet or a second body
  // crossing it is counted above but not here.
  constexpr std::size_t kMaxSolidLines = 20;
  for (std::size_t k = 0; k < d.solids.size() && k < kMaxSolidLines; ++k) {
    const auto& s = d.solids[k];
    std::cout << "solid " << s.solid << (s.closed ? "" : " (open in the model)") << ": "
              << s.triangles << " triangles, " << s.free_edges << " free, " << s.non_manifold_edges
              << " non-manifold edges";
    if (s.self_intersections)
      std::cout << ", " << *s.self_intersections << " self-intersections ("
                << s.self_intersections_in_model.value_or(0) << " in the model)";
    std::cout << "\n";
  }
  if (d.solids.size() > kMaxSolidLines)
    std::cout << "(" << d.solids.size() - kMaxSolidLines << " more solids in --json)\n";
  std::cout << "quality: Q max " << q.Q_max << ", p95 " << q.Q_p95 << ", p50 " << q.Q_p50
            << "; q min " << q.q_min << ", mean " << q.q_mean << "; " << 100.0 * q.share_Q_lt_1_5
            << "% with Q < 1.5; angles " << q.min_angle_deg << " .. " << q.max_angle_deg
            << " deg\n";
  std::cout << "edge lengths: median " << d.median_edge << ", min "
            << d.edge_lengths.min * d.median_edge << ", max " << d.edge_lengths.max * d.median_edge
            << "; " << 100.0 * d.edge_lengths.unit_share << "% within sqrt(2) of the median\n";
  if (d.metric_edge_lengths)
    std::cout << "edge lengths in the size metric: " << 100.0 * d.metric_edge_lengths->unit_share
              << "% unit (in [1/sqrt2, sqrt2]), " << d.metric_edge_lengths->short_edges
              << " short, " << d.metric_edge_lengths->long_edges << " long\n";
  if (d.chordal)
    std::cout << "chordal deviation: max " << d.chordal->max << ", mean " << d.chordal->mean
              << " (face " << d.chordal->worst.face << ")\n";
  else if (!d.chordal_unavailable.empty())
    std::cout << "chordal deviation: not measured (" << d.chordal_unavailable << ")\n";
  if (j.contains("svg"))
    for (const auto& p : j["svg"]) std::cout << "wrote " << p.get<std::string>() << "\n";
}

}  // namespace

int run_check(const CheckFlags& f) {
  io::MeshReadOptions ro;
  if (!f.format.empty()) {
    ro.format = io::format_from_name(f.format);
    if (!ro.format) {
      std::cerr << "uvmesh: error: unknown format '" << f.format
                << "' (known: " << io::known_format_names() << ")\n";
      return 1;
    }
  }
  if (f.face >= 0 && f.svg_dir.empty()) {
    std::cerr << "uvmesh: error: --face draws into the --svg directory; give --svg DIR\n";
    return 1;
  }
  io::MeshReadResult mr = io::read_mesh(f.mesh, ro);
  if (!mr.ok) {
    std::cerr << "uvmesh: error: " << mr.error << "\n";
    return 2;
  }
  for (const std::string& w : mr.warnings)
    std::cerr << "uvmesh: warning: " << f.mesh << ": " << w << "\n";

  io::ReadResult model;
  if (!f.model.model.empty()) {
    model = io::read_cad(f.model.model, read_options(f.model));
    if (!model.ok) {
      std::cerr << "uvmesh: error: " << model.error << "\n";
      return 2;
    }
    if (!mr.has_face_ids) {
      std::cerr << "uvmesh: warning: " << f.mesh
                << ": the file carries no face ids; chordal deviation is not measured\n";
    } else if (std::string why = io::attach_uv(mr.mesh, model.model); !why.empty()) {
      std::cerr << "uvmesh: warning: " << f.mesh << ": " << why
                << "; chordal deviation is not measured\n";
      mr.mesh.triangle_uv.clear();
    }
  }

  io::CheckOptions co;
  co.threads = f.threads;
  co.self_intersections = !f.no_selfint;
  co.chordal_tolerance = f.chordal;
  if (model.ok) {
    // The sizes `uvmesh mesh` would use with the same options (mesh_cmd.cpp).
    param::SizeSpec size = surface::default_size(model.model);
    if (f.hmax > 0) size.hmax = f.hmax;
    if (f.hmin > 0) size.hmin = f.hmin;
    size.hmin = std::min(size.hmin, size.hmax);
    if (f.chordal > 0 || f.angle_deg > 0) {
      size.chordal_tol = f.chordal;
      size.angle_tol = f.angle_deg * std::numbers::pi / 180.0;
    }
    if (f.grad > 0) size.gradation = f.grad;
    if (f.aniso > 0) {
      size.isotropic = false;
      size.max_anisotropy = f.aniso;
    }
    co.chordal_tolerance = size.chordal_tol;
    // What mesh_model would make elements for with these sizes and its default options.
    surface::MeshOptions mo;
    mo.size = std::move(size);
    co.size = surface::meshing_size(mo);
  }
  const io::CheckData d = io::check_mesh(mr.mesh, model.ok ? &model.model : nullptr, co);
  nlohmann::json j = io::report_json(d);
  j["mesh"] = f.mesh;
  j["format"] = std::string(io::format_name(mr.format));
  if (model.ok) j["model"] = f.model.model;

  if (!f.svg_dir.empty())
    if (int rc = write_svgs(f, d, mr, j); rc != 0) return rc;

  if (f.json)
    std::cout << j.dump(2) << "\n";
  else
    print_summary(f, d, mr, j);
  return 0;
}

}  // namespace uvmesh::cli
