// uvmesh2d -- mesh a Triangle .poly domain with the uvmesh 2D Delaunay mesher and write
// Medit / Gmsh / SVG files. See README.md in this folder.
//
// Exit status: 0 success (also for an Incomplete mesh, with a warning), 2 usage or input
// error, 3 meshing failure, 1 unexpected internal error. On any failure no output file is
// created or replaced: outputs are written to temporaries beside their destinations and
// renamed only when every one of them is complete.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <set>
#include <sstream>

#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/background.h"
#include "uvmesh2d/fields.h"
#include "uvmesh2d/gmsh.h"
#include "uvmesh2d/medit.h"
#include "uvmesh2d/output.h"
#include "uvmesh2d/poly.h"
#include "uvmesh2d/regions.h"
#include "uvmesh2d/report.h"
#include "uvmesh2d/svg.h"
#include "uvmesh2d/text.h"

namespace {

namespace c2 = uvmesh::cli2d;
namespace m2d = uvmesh::m2d;

constexpr int kExitInternal = 1, kExitUsage = 2, kExitMeshing = 3;

int usage_error(const std::string& msg) {
  std::cerr << "uvmesh2d: error: " << msg << " (see uvmesh2d --help)\n";
  return kExitUsage;
}

int input_error(const c2::Diagnostic& d) {
  std::cerr << d.str() << '\n';
  return kExitUsage;
}

std::string fmt(double v, int prec = 3) {
  std::ostringstream s;
  s.precision(prec);
  s << v;
  return s.str();
}

// Q_K per triangle for the picture: in the metric at the centroid when the size is a
// metric (that is the quality the mesher optimizes), Euclidean otherwise (an isotropic
// size scales a triangle without changing its shape).
std::vector<double> triangle_qualities(const m2d::Mesh& m, const m2d::SizeSpec& size) {
  std::vector<double> q(m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& t = m.triangles[i];
    const m2d::Vec2 a = m.vertices[static_cast<std::size_t>(t[0])],
                    b = m.vertices[static_cast<std::size_t>(t[1])],
                    c = m.vertices[static_cast<std::size_t>(t[2])];
    m2d::Metric2 metric;
    if (size.kind == m2d::SizeSpec::Kind::Metric && size.metric)
      metric = size.metric((a.x + b.x + c.x) / 3.0, (a.y + b.y + c.y) / 3.0);
    q[i] = m2d::triangle_quality(a, b, c, metric);
  }
  return q;
}

int run(int argc, char** argv) {
  const auto t0 = std::chrono::steady_clock::now();
  CLI::App app{
      "uvmesh2d -- anisotropic Delaunay mesh of a planar domain given as a Triangle .poly file\n"
      "(reference chapter, sections 7.3, 7.5 and 7.6.1).",
      "uvmesh2d"};
  app.set_help_flag("-h,--help", "Print this help and exit");
  std::string input;
  std::vector<std::string> outputs;
  double size = 0;
  std::vector<std::string> metric_files;
  std::string metric_fn;
  bool no_refine = false, split_crossing = false, no_optimize = false, quiet = false, json = false,
       check = false, frontal = false, no_feature_size = false;
  std::int64_t max_vertices = 0;

  app.add_option("input", input, "Domain: Triangle .poly file")->required();
  app.add_option("-o,--output", outputs,
                 "Output file, repeatable; the extension picks the format (below)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  auto* o_size = app.add_option("--size", size,
                                "Uniform target edge length H > 0 (default: from the boundary)");
  auto* o_metric =
      app.add_option("--metric", metric_files, "Background size field: BG.mesh BG.sol (below)")
          ->expected(2)
          ->type_name("FILE");
  auto* o_fn = app.add_option("--metric-fn", metric_fn, "Built-in size field NAME:ARGS (below)");
  o_size->excludes(o_metric)->excludes(o_fn);
  o_metric->excludes(o_fn);
  app.add_flag("--no-refine", no_refine,
               "Constrained Delaunay triangulation only (no field points)");
  app.add_flag("--split-crossing", split_crossing, "Split crossing segments instead of failing");
  app.add_flag("--no-optimize", no_optimize, "Skip the optimization stage (swaps, relocation)");
  app.add_flag("--frontal", frontal,
               "Frontal field points (advancing-front-Delaunay, section 7.4.3) instead of edge "
               "saturation");
  app.add_flag("--no-feature-size", no_feature_size,
               "Do not cap the size by the local feature size (by default a slot or spike "
               "narrower than the size gets triangles as wide as it is)");
  app.add_flag("--check", check, "Run the mesh checker; a failed check exits with status 3");
  app.add_option("--max-vertices", max_vertices,
                 "Stop refining beyond N vertices (mesh Incomplete)");
  app.add_flag("--json", json, "Print one JSON record (counts, stage times, quality) on stdout");
  app.add_flag("-q,--quiet", quiet, "No summary and no warnings on stderr (errors still)");
  app.footer(
      std::string(
          "\nOutputs (by extension):\n"
          "  .mesh  Medit: vertex refs = node markers, triangle refs = regional attribute "
          "(component + 1\n"
          "         without regions), Edges = boundary edges with their segment markers\n"
          "  .msh   Gmsh 2.2 ASCII: the same references as physical tags\n"
          "  .svg   picture: triangles coloured by quality Q (in the metric), boundary thick\n"
          "\nBackground size field (--metric BG.mesh BG.sol): a Medit 2D mesh and a .sol with\n"
          "SolAtVertices of type 3 (metric m11 m12 m22) or 1 (size h); located with a bucket "
          "grid,\n"
          "interpolated log-Euclidean, nearest triangle outside the background mesh.\n"
          "Region lines with a maximum area bound the size there by sqrt(4 A / sqrt 3).\n\n") +
      c2::fields::kHelp +
      "\n\nExit status: 0 success, 2 usage or input error (the message names file and line),\n"
      "3 meshing failure, 1 internal error. On failure no output file is written.");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success))
      return app.exit(e);  // --help
    return usage_error(e.what());
  }

  // 1. Options that can be checked without reading anything.
  std::string size_text = "boundary";
  m2d::SizeSpec spec = m2d::SizeSpec::uniform(0);
  if (*o_size) {
    if (!std::isfinite(size) || !(size > 0))
      return usage_error("--size must be a finite number > 0, found " + fmt(size));
    spec = m2d::SizeSpec::uniform(size);
    size_text = "uniform:";
    c2::text::append_double(size_text, size);
  }
  if (*o_fn) {
    c2::fields::Parsed p = c2::fields::parse(metric_fn);
    if (!p.ok()) return usage_error(p.error);
    spec = p.spec;
    size_text = "metric-fn " + metric_fn;
  }
  if (max_vertices < 0) return usage_error("--max-vertices must be >= 0");
  std::vector<c2::OutputFormat> formats;
  std::set<std::string> seen;
  for (const std::string& o : outputs) {
    auto f = c2::output_format(o);
    if (!f)
      return usage_error("output '" + o + "': unknown extension (known: " + c2::kOutputExtensions +
                         ")");
    if (!seen.insert(o).second) return usage_error("output '" + o + "' is given twice");
    formats.push_back(*f);
  }

  // 2. Input and size field.
  c2::PolyRead poly = c2::read_poly(input);
  if (!poly.ok()) return input_error(*poly.error);
  const c2::PolyData& pd = poly.poly;
  if (*o_metric) {
    c2::BackgroundLoad bg = c2::load_background(metric_files[0], metric_files[1]);
    if (!bg.ok()) return input_error(*bg.error);
    spec = bg.spec;
    size_text = "background " + metric_files[0] + " " + metric_files[1];
  }
  std::vector<std::string> warnings;
  // 3. Claim the outputs before the (possibly long) meshing run: an unwritable directory
  // fails now, and the temporaries are removed on every later failure.
  std::vector<c2::PendingOutput> pending(outputs.size());
  for (std::size_t i = 0; i < outputs.size(); ++i)
    if (auto e = pending[i].open(outputs[i])) return input_error(*e);

  // 4. Mesh.
  m2d::Options opt;
  opt.refine = !no_refine;
  opt.optimize = !no_optimize;
  if (frontal) opt.field_points = m2d::FieldPointMethod::Frontal;
  // On by default, as Triangle's quality refinement follows the local feature size
  // without being asked: a requested size is an upper bound, and a domain narrower than
  // it is meshed with well shaped triangles rather than needles across it.
  opt.feature_size = !no_feature_size;
  opt.split_crossing_segments = split_crossing;
  if (max_vertices > 0) opt.max_vertices = max_vertices;
  c2::RegionSize rs = c2::apply_region_max_area(pd, spec, opt);
  for (const std::string& n : rs.notes) warnings.push_back(n);
  if (rs.constrained_regions > 0) {
    spec = rs.spec;
    size_text += " + region maximum areas";
  }
  m2d::Result r = m2d::mesh(pd.pslg, spec, opt);
  if (!r.usable()) {
    std::string msg = "uvmesh2d: " + input + ": meshing failed (" + c2::status_name(r.status.code) +
                      "): " + r.status.message;
    if (r.status.code == m2d::StatusCode::CrossingSegments && !r.status.entities.empty()) {
      // The mesher numbers segments 0-based in input order; name them as the file does.
      std::string where;
      for (std::int64_t s : r.status.entities)
        if (s >= 0 && static_cast<std::size_t>(s) < pd.segment_ids.size())
          where += (where.empty() ? "" : ", ") + pd.describe_segment(static_cast<std::size_t>(s));
      if (!where.empty()) msg += " [in the file: " + where + "]";
    }
    std::cerr << msg << '\n';
    return kExitMeshing;
  }
  if (check) {
    m2d::CheckReport rep = m2d::check(r.mesh, pd.pslg);
    if (!rep.ok()) {
      std::cerr << "uvmesh2d: " << input << ": the mesh fails the checker (" << rep.errors.size()
                << " errors), first: " << rep.errors.front() << '\n';
      return kExitMeshing;
    }
  }

  // 5. Write every output, then publish them all.
  std::string ref_warning;
  const std::vector<int> refs = c2::triangle_refs(r.mesh, !pd.pslg.regions.empty(), &ref_warning);
  if (!ref_warning.empty()) warnings.push_back(ref_warning);
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    std::ostream& os = pending[i].stream();
    switch (formats[i]) {
      case c2::OutputFormat::Medit:
        c2::write_medit(os, r.mesh, refs);
        break;
      case c2::OutputFormat::Gmsh22:
        c2::write_gmsh22(os, r.mesh, refs);
        break;
      case c2::OutputFormat::Svg: {
        c2::SvgOptions so;
        so.quality = triangle_qualities(r.mesh, spec);
        so.title = input + ": " + std::to_string(r.mesh.vertices.size()) + " vertices, " +
                   std::to_string(r.mesh.triangles.size()) + " triangles, Q_M " +
                   fmt(r.stats.quality.q_max) +
                   (spec.kind == m2d::SizeSpec::Kind::Metric
                        ? ", metric Q_M " + fmt(r.stats.quality.metric_q_max)
                        : "");
        c2::write_svg(os, r.mesh, so);
        break;
      }
    }
  }
  for (std::size_t i = 0; i < outputs.size(); ++i) {
    if (auto e = pending[i].commit()) {
      for (std::size_t k = 0; k < i; ++k) pending[k].undo_commit();
      return input_error(*e);
    }
  }

  // 6. Report.
  const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (json) {
    c2::RunInfo info{input, size_text, outputs, total};
    std::cout << c2::json_record(r, info) << std::endl;
  }
  if (!quiet) {
    for (const std::string& w : r.status.warnings) std::cerr << "uvmesh2d: warning: " << w << '\n';
    for (const std::string& w : warnings) std::cerr << "uvmesh2d: warning: " << w << '\n';
    if (r.status.code == m2d::StatusCode::Incomplete)
      std::cerr << "uvmesh2d: warning: the mesh is incomplete: " << r.status.message << '\n';
    const m2d::Quality& q = r.stats.quality;
    std::cerr << "uvmesh2d: " << input << ": " << r.mesh.vertices.size() << " vertices, "
              << r.mesh.triangles.size() << " triangles in " << fmt(total) << " s; Q_M "
              << fmt(q.q_max) << " (metric " << fmt(q.metric_q_max) << "), unit edges "
              << fmt(100 * q.unit_edge_share) << "%, angles " << fmt(q.min_angle_deg) << "-"
              << fmt(q.max_angle_deg) << " deg";
    for (const std::string& o : outputs)
      std::cerr << (&o == &outputs.front() ? "; wrote " : ", ") << o;
    std::cerr << '\n';
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::cerr << "uvmesh2d: internal error: " << e.what() << '\n';
    return kExitInternal;
  }
}
