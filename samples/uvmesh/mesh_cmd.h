// `uvmesh mesh MODEL -o OUT`: the main job (mesh_cmd.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "read_flags.h"
#include "uvmesh/io/job.h"
#include "write_flags.h"

namespace uvmesh::cli {

// The command line of `uvmesh mesh`: its own syntax (paths, output and report, flags
// spelled as negations, "ID=H" strings) around the job's options (io/job.h), which hold
// the defaults and are bound to the flags directly.
struct MeshFlags {
  ReadFlags read;
  WriteFlags write;
  io::MeshJobOptions job;
  std::string out;
  std::string report;
  bool iso = false;
  bool allow_holes = false;
  bool no_optimize3d = false;
  bool no_selfint = false;
  bool features = false;  ///< --features: absorb entities below the default feature size
  std::vector<std::string> face_size, edge_size;  ///< "ID=H"
  bool quiet = false;
};

CLI::App* add_mesh_command(CLI::App& app, MeshFlags& f);
int run_mesh(const MeshFlags& f);

}  // namespace uvmesh::cli
