#include "uvmesh2d/report.h"

#include <nlohmann/json.hpp>

namespace uvmesh::cli2d {

std::string status_name(m2d::StatusCode c) {
  switch (c) {
    case m2d::StatusCode::Ok:
      return "Ok";
    case m2d::StatusCode::InvalidInput:
      return "InvalidInput";
    case m2d::StatusCode::CrossingSegments:
      return "CrossingSegments";
    case m2d::StatusCode::OpenBoundary:
      return "OpenBoundary";
    case m2d::StatusCode::Incomplete:
      return "Incomplete";
    case m2d::StatusCode::InternalError:
      return "InternalError";
    case m2d::StatusCode::TimeLimit:
      return "TimeLimit";
  }
  return "Unknown";
}

std::string json_record(const m2d::Result& r, const RunInfo& info) {
  using J = nlohmann::ordered_json;
  const m2d::Quality& q = r.stats.quality;
  J j;
  j["input"] = info.input;
  j["size"] = info.size;
  j["outputs"] = info.outputs;
  j["status"] = status_name(r.status.code);
  j["message"] = r.status.message;
  j["vertices"] = r.mesh.vertices.size();
  j["triangles"] = r.mesh.triangles.size();
  j["boundary_edges"] = r.mesh.boundary_edges.size();
  J sec = J::object();
  double sum = 0;
  for (const auto& s : r.stats.stages) {
    // Stage names should be unique; if one repeats, its times add up.
    sec[s.name] = (sec.contains(s.name) ? sec[s.name].get<double>() : 0.0) + s.seconds;
    sum += s.seconds;
  }
  sec["total"] = info.total_seconds >= 0 ? info.total_seconds : sum;
  j["seconds"] = sec;
  J qual;
  qual["euclidean"] = {{"Q_M", q.q_max},
                       {"Q_mean", q.q_mean},
                       {"share_Q_below_1_5", q.share_q_below_1_5},
                       {"share_Q_below_2", q.share_q_below_2},
                       {"min_angle_deg", q.min_angle_deg},
                       {"max_angle_deg", q.max_angle_deg}};
  qual["metric"] = {{"Q_M", q.metric_q_max},
                    {"Q_mean", q.metric_q_mean},
                    {"share_Q_below_1_5", q.metric_share_q_below_1_5},
                    {"share_Q_below_2", q.metric_share_q_below_2},
                    {"min_angle_deg", q.metric_min_angle_deg},
                    {"max_angle_deg", q.metric_max_angle_deg}};
  qual["unit_edge_share"] = q.unit_edge_share;
  qual["edges"] = q.edges;
  qual["edge_length_min"] = q.edge_len_min;
  qual["edge_length_max"] = q.edge_len_max;
  qual["edge_length_mean"] = q.edge_len_mean;
  j["quality"] = qual;
  const m2d::Stats& st = r.stats;
  j["counts"] = {{"duplicates_merged", st.duplicates_merged},
                 {"segments_split_at_vertices", st.segments_split_at_vertices},
                 {"crossings_split", st.crossings_split},
                 {"field_points_inserted", st.field_points_inserted},
                 {"field_points_rejected", st.field_points_rejected},
                 {"saturation_waves", st.saturation_waves},
                 {"swaps", st.swaps},
                 {"relocations", st.relocations}};
  j["warnings"] = r.status.warnings;
  // Invalid UTF-8 (e.g. from a file name) is replaced rather than throwing.
  return j.dump(-1, ' ', false, nlohmann::ordered_json::error_handler_t::replace);
}

}  // namespace uvmesh::cli2d
