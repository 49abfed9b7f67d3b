// `uvmesh check MESH [--model MODEL] [--json] [--svg DIR] [--face N]`: grade any surface
// mesh (check_cmd.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "read_flags.h"

namespace uvmesh::cli {

struct CheckFlags {
  std::string mesh;
  std::string format;  ///< overrides the extension
  ReadFlags model;     ///< model.model = "" when no --model
  bool json = false;
  std::string svg_dir;
  int face = -1;
  int threads = 0;
  bool no_selfint = false;
  double chordal = 0;
  /// Sizes for the metric edge lengths (with --model): `uvmesh mesh`'s defaults unless given.
  double hmax = 0, hmin = 0, angle_deg = 0, grad = 0, aniso = 0;
};

CLI::App* add_check_command(CLI::App& app, CheckFlags& f);
int run_check(const CheckFlags& f);

}  // namespace uvmesh::cli
