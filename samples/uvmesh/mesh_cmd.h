// `uvmesh mesh MODEL -o OUT`: the main job (mesh_cmd.cpp).
#pragma once

#include <CLI/CLI.hpp>
#include <string>
#include <vector>

#include "read_flags.h"
#include "write_flags.h"

namespace uvmesh::cli {

struct MeshFlags {
  ReadFlags read;
  WriteFlags write;
  std::string out;
  std::string report;
  double hmax = 0, hmin = 0, chordal = 0, angle_deg = 0, grad = 0;
  double hmax_rel = 0;
  bool iso = false;
  double aniso = 0;  ///< > 0: anisotropic curvature sizes with this maximum ratio
  int threads = 0;
  double face_time_limit = 120.0;  // seconds per face in the 2D mesher; 0 = none
  bool allow_holes = false;
  bool volume = false;  ///< --volume: tetrahedra in every closed solid (needs nglib)
  bool no_optimize3d = false;
  bool no_selfint = false;
  double min_feature = 0;        ///< --min-feature; 0: hmin
  double feature_angle_deg = 0;  ///< --feature-angle; 0: MeshOptions' default
  bool keep_topology = false;
  bool features = false;  ///< --features: absorb entities below the default feature size
  std::vector<std::string> face_size, edge_size;  ///< "ID=H"
  std::string size_file;
  bool quiet = false;
  // Subdivision cages (.obj): OpenSubdiv scheme and boundary interpolation names.
  std::string scheme = "auto";
  std::string boundary_interp = "file";
};

CLI::App* add_mesh_command(CLI::App& app, MeshFlags& f);
int run_mesh(const MeshFlags& f);

}  // namespace uvmesh::cli
