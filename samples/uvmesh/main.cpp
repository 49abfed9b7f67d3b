// uvmesh -- command-line front end. Subcommands:
//   uvmesh info MODEL [--json] [--no-heal] [--conform] [--any-extension] [--units UNIT]
//   uvmesh mesh MODEL -o OUT [size options] [--report FILE.json]   (mesh_cmd.cpp)
//   uvmesh check MESH [--model MODEL] [--json] [--svg DIR] [--face N] (check_cmd.cpp)
//
// Exit codes: 0 success, 2 the model could not be read (one line on stderr naming the
// file and the defect), 1 command-line errors.
#include <CLI/CLI.hpp>
#include <iostream>
#include <string>

#include "check_cmd.h"
#include "mesh_cmd.h"
#include "read_flags.h"
#include "uvmesh/geom/model.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/info.h"
#include "uvmesh/io/units.h"

namespace {

using uvmesh::cli::add_read_flags;
using uvmesh::cli::read_options;
using uvmesh::cli::ReadFlags;

int run_info(const ReadFlags& f, bool json) {
  const uvmesh::io::ReadOptions opt = read_options(f);
  const uvmesh::io::ReadResult r = uvmesh::io::read_cad(f.model, opt);
  if (!r.ok) {
    std::cerr << "uvmesh: error: " << r.error << "\n";
    return 2;
  }
  const uvmesh::geom::ModelStats s = uvmesh::geom::compute_stats(r.model);
  if (json)
    std::cout << uvmesh::io::info_json(r.model, s, r.report, opt.heal) << "\n";
  else
    std::cout << uvmesh::io::info_text(r.model, s, r.report, opt.heal);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"uvmesh: CAD surface mesher (parametric anisotropic Delaunay)"};
  app.require_subcommand(1);

  ReadFlags info_flags;
  bool info_json = false;
  CLI::App* info = app.add_subcommand(
      "info", "describe a CAD model: topology, geometry kinds, defects, healing");
  add_read_flags(info, info_flags);
  info->add_flag("--json", info_json, "machine-readable JSON on stdout");

  uvmesh::cli::MeshFlags mesh_flags;
  CLI::App* mesh = uvmesh::cli::add_mesh_command(app, mesh_flags);

  uvmesh::cli::CheckFlags check_flags;
  CLI::App* check = uvmesh::cli::add_check_command(app, check_flags);

  // CLI11_PARSE would exit with CLI11's own codes (105, 106, ...) and an unprefixed
  // message; the documented contract is exit 1 and one "uvmesh: error:" line.
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == static_cast<int>(CLI::ExitCodes::Success))
      return app.exit(e);  // --help
    std::cerr << "uvmesh: error: " << e.what() << "\n";
    return 1;
  }
  try {
    if (info->parsed()) return run_info(info_flags, info_json);
    if (mesh->parsed()) return uvmesh::cli::run_mesh(mesh_flags);
    if (check->parsed()) return uvmesh::cli::run_check(check_flags);
  } catch (const std::exception& e) {
    std::cerr << "uvmesh: error: " << e.what() << "\n";
    return 2;
  }
  return 1;
}
