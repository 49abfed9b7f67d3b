// uvmesh::cli2d -- one-line JSON record of a 2D meshing run (uvmesh2d --json, benchmarks).
//
// Usage:
//   std::cout << uvmesh::cli2d::json_record(result, {.input = "a.poly", .size = "uniform:0.05"}) <<
//   '\n';
//
// Record (keys in this order; non-finite numbers are written as null):
//   {"input", "size", "outputs": [...], "status", "message", "vertices", "triangles",
//    "boundary_edges", "seconds": {"<stage>": s, ..., "total": s},
//    "quality": {"euclidean": {"Q_M", "Q_mean", "share_Q_below_1_5", "share_Q_below_2",
//                              "min_angle_deg", "max_angle_deg"},
//                "metric": {same keys, measured in the metric},
//                "unit_edge_share", "edges", "edge_length_min", "edge_length_max",
//                "edge_length_mean"},
//    "counts": {"duplicates_merged", "segments_split_at_vertices", "crossings_split",
//               "field_points_inserted", "field_points_rejected", "saturation_waves",
//               "swaps", "relocations"},
//    "warnings": [...]}
// Q is Q_K = alpha h_max / rho_K (eq. 7.6 of the reference chapter), Q_M its maximum (7.7);
// a unit edge has metric length in [1/sqrt 2, sqrt 2].
#pragma once

#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::cli2d {

struct RunInfo {
  std::string input;
  std::string size;  // how the size was given, e.g. "metric-fn ring:0.002,0.05"
  std::vector<std::string> outputs;
  double total_seconds = -1;  // wall time of the whole run; < 0: sum of the stages
};

std::string status_name(m2d::StatusCode c);
std::string json_record(const m2d::Result& r, const RunInfo& info);

}  // namespace uvmesh::cli2d
