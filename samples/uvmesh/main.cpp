// uvmesh -- command-line front end. Subcommands:
//   uvmesh info MODEL [--json] [--no-heal] [--conform] [--any-extension] [--units UNIT]
// (`uvmesh mesh` arrives with the surface stage; each subcommand is one function below.)
//
// Exit codes: 0 success, 2 the model could not be read (one line on stderr naming the
// file and the defect), 1 command-line errors.
#include <CLI/CLI.hpp>

#include <iostream>
#include <string>

#include "uvmesh/geom/model.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/info.h"
#include "uvmesh/io/units.h"

namespace {

struct ReadFlags {
  std::string model;
  bool no_heal = false;
  bool conform = false;
  bool any_extension = false;
  bool partial = false;
  bool no_check = false;
  double sew_rel_tol = 1e-6;
  std::string units;  // "" = the file's own unit
};

void add_read_flags(CLI::App* cmd, ReadFlags& f) {
  cmd->add_option("MODEL", f.model, "STEP (.step/.stp), IGES (.igs/.iges) or BREP (.brep) file")
      ->required();
  cmd->add_flag("--no-heal", f.no_heal, "use the model exactly as read (no ShapeFix, no sewing)");
  cmd->add_flag("--conform", f.conform,
                "make an assembly conforming: touching solids are imprinted (general fuse)");
  cmd->add_flag("--any-extension", f.any_extension, "read by content when the extension disagrees");
  cmd->add_flag("--no-check", f.no_check, "skip OCC's per-face validity check (BRepCheck), the slowest part of a load");
  cmd->add_flag("--partial", f.partial, "import what can be resolved from a STEP file with dangling references");
  cmd->add_option("--sew-tol", f.sew_rel_tol, "sewing tolerance relative to the bounding-box diagonal")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--units", f.units,
                  "convert coordinates to this length unit (" + uvmesh::io::known_length_units() +
                      "); default: keep the unit the file declares (BREP files have none)")
      ->check(CLI::Validator(
          [](std::string& s) {
            return uvmesh::io::canonical_length_unit(s).empty()
                       ? "unknown length unit '" + s + "' (known: " + uvmesh::io::known_length_units() + ")"
                       : std::string();
          },
          "UNIT"));
}

uvmesh::io::ReadOptions read_options(const ReadFlags& f) {
  uvmesh::io::ReadOptions o;
  o.heal = !f.no_heal;
  o.conform = f.conform;
  o.trust_content = f.any_extension;
  o.sew_rel_tol = f.sew_rel_tol;
  o.allow_partial = f.partial;
  o.check_validity = !f.no_check;
  o.units = f.units;
  return o;
}

int run_info(const ReadFlags& f, bool json) {
  const uvmesh::io::ReadOptions opt = read_options(f);
  const uvmesh::io::ReadResult r = uvmesh::io::read_cad(f.model, opt);
  if (!r.ok) {
    std::cerr << "uvmesh: error: " << r.error << "\n";
    return 2;
  }
  const uvmesh::geom::ModelStats s = uvmesh::geom::compute_stats(r.model);
  if (json) std::cout << uvmesh::io::info_json(r.model, s, r.report, opt.heal) << "\n";
  else std::cout << uvmesh::io::info_text(r.model, s, r.report, opt.heal);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"uvmesh: CAD surface mesher (parametric anisotropic Delaunay)"};
  app.require_subcommand(1);

  ReadFlags info_flags;
  bool info_json = false;
  CLI::App* info = app.add_subcommand("info", "describe a CAD model: topology, geometry kinds, defects, healing");
  add_read_flags(info, info_flags);
  info->add_flag("--json", info_json, "machine-readable JSON on stdout");

  CLI11_PARSE(app, argc, argv);
  try {
    if (info->parsed()) return run_info(info_flags, info_json);
  } catch (const std::exception& e) {
    std::cerr << "uvmesh: error: " << e.what() << "\n";
    return 2;
  }
  return 1;
}
