// `uvmesh info` reports (JSON and text).
#include "uvmesh/io/info.h"

#include <nlohmann/json.hpp>
#include <sstream>

namespace uvmesh::io {

std::string info_json(const geom::Model& m, const geom::ModelStats& s, const ReadReport& r,
                      bool heal_enabled, int indent) {
  using nlohmann::json;
  json j;
  j["file"] = m.source;
  j["format"] = m.format;
  // Units of the coordinates (and of every length below): the file's unit unless another
  // was requested; BREP files have none ("unitless", factors null).
  j["units"] = m.units.empty() ? "unitless" : m.units;
  if (r.mm_per_unit > 0.0) {
    j["unit_in_mm"] = r.mm_per_unit;
    j["unit_in_m"] = r.mm_per_unit / 1000.0;
  } else {
    j["unit_in_mm"] = nullptr;
    j["unit_in_m"] = nullptr;
  }
  j["file_units"] = r.file_units;
  j["file_units_declared"] = r.file_units_declared;
  j["units_converted"] = r.units_converted;
  j["counts"] = {{"solids", s.solids},
                 {"shells", s.shells},
                 {"faces", s.faces},
                 {"edges", s.edges},
                 {"vertices", s.vertices}};
  j["surface_kinds"] = s.surface_kinds;
  j["curve_kinds"] = s.curve_kinds;
  j["seam_edges"] = s.seam_edges;
  j["faces_with_seams"] = s.faces_with_seams;
  j["degenerate_edges"] = s.degenerate_edges;
  j["free_edges"] = s.free_edges;
  j["non_manifold_edges"] = s.non_manifold_edges;
  j["short_edges"] = s.short_edges;
  j["short_edge_threshold"] = s.short_edge_threshold;
  j["min_edge_length"] = s.min_edge_length;
  j["open_shells"] = s.open_shells;
  j["vertex_gaps"] = s.vertex_gaps;
  if (m.bbox.empty()) {
    j["bbox"] = nullptr;
  } else {
    j["bbox"] = {{"min", {m.bbox.lo.x, m.bbox.lo.y, m.bbox.lo.z}},
                 {"max", {m.bbox.hi.x, m.bbox.hi.y, m.bbox.hi.z}},
                 {"diagonal", m.bbox.diagonal()}};
  }
  json inv = json::array();
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    if (!m.faces[f].valid) inv.push_back({{"face", f}, {"reason", m.faces[f].invalid_reason}});
  j["invalid_faces"] = inv;
  j["validity_checked"] = r.validity_checked;
  json steps = json::array();
  for (const HealStep& h : r.healing)
    steps.push_back({{"name", h.name},
                     {"applied", h.applied},
                     {"detail", h.detail},
                     {"faces_before", h.faces_before},
                     {"faces_after", h.faces_after},
                     {"edges_before", h.edges_before},
                     {"edges_after", h.edges_after},
                     {"solids_before", h.solids_before},
                     {"solids_after", h.solids_after},
                     {"free_edges_before", h.free_edges_before},
                     {"free_edges_after", h.free_edges_after},
                     {"seconds", h.seconds}});
  j["healing"] = {{"enabled", heal_enabled}, {"steps", steps}};
  j["warnings"] = r.warnings;
  j["timing"] = {{"read", r.read_seconds}, {"heal", r.heal_seconds}, {"build", r.build_seconds}};
  return j.dump(indent);
}

std::string info_text(const geom::Model& m, const geom::ModelStats& s, const ReadReport& r,
                      bool heal_enabled) {
  std::ostringstream os;
  os << m.source << "  (" << m.format << ")\n";
  os << "  units: ";
  if (m.units.empty()) {
    os << "unitless (" << (m.format == "brep" ? "BREP files carry no length unit" : "none declared")
       << ")\n";
  } else {
    os << m.units << " (1 " << m.units << " = ";
    if (m.units != "mm") os << r.mm_per_unit << " mm = ";
    os << r.mm_per_unit / 1000.0 << " m)";
    if (r.units_converted)
      os << ", converted from the file's "
         << (r.file_units.empty() ? r.file_units_declared : r.file_units);
    else
      os << ", as declared by the file";
    if (!r.file_units_declared.empty() && r.file_units_declared != m.units)
      os << " ('" << r.file_units_declared << "')";
    os << "\n";
  }
  os << "  solids " << s.solids << ", shells " << s.shells << " (" << s.open_shells
     << " open), faces " << s.faces << ", edges " << s.edges << ", vertices " << s.vertices << "\n";
  os << "  surfaces:";
  for (const auto& [k, n] : s.surface_kinds) os << " " << k << ":" << n;
  os << "\n  curves:  ";
  for (const auto& [k, n] : s.curve_kinds) os << " " << k << ":" << n;
  os << "\n  seam edges " << s.seam_edges << " (on " << s.faces_with_seams
     << " faces), degenerate edges " << s.degenerate_edges << ", free edges " << s.free_edges
     << ", non-manifold edges " << s.non_manifold_edges << "\n  edges shorter than "
     << s.short_edge_threshold << " (1e-3 of the diagonal): " << s.short_edges << " (shortest "
     << s.min_edge_length << ")\n";
  if (!m.bbox.empty())
    os << "  bbox [" << m.bbox.lo.x << ", " << m.bbox.lo.y << ", " << m.bbox.lo.z << "] - ["
       << m.bbox.hi.x << ", " << m.bbox.hi.y << ", " << m.bbox.hi.z << "], diagonal "
       << m.bbox.diagonal() << (m.units.empty() ? "" : " " + m.units) << "\n";
  if (r.validity_checked)
    os << "  OCC validity: " << (s.faces - s.invalid_faces) << " of " << s.faces
       << " faces valid\n";
  else
    os << "  OCC validity: not checked (--no-check)\n";
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    if (!m.faces[f].valid) os << "    face " << f << ": " << m.faces[f].invalid_reason << "\n";
  if (s.vertex_gaps > 0)
    os << "  " << s.vertex_gaps << " vertex/edge-end gaps beyond 1e3 tolerances (max "
       << s.max_vertex_gap << ")\n";
  if (!heal_enabled) {
    os << "  healing: off (--no-heal)\n";
  } else {
    os << "  healing:\n";
    for (const HealStep& h : r.healing)
      os << "    " << h.name << (h.applied ? " [applied] " : " [no change] ") << h.detail << "\n";
  }
  for (const std::string& w : r.warnings) os << "  warning: " << w << "\n";
  os << "  time: read " << r.read_seconds << " s, heal " << r.heal_seconds << " s, model "
     << r.build_seconds << " s\n";
  return os.str();
}

}  // namespace uvmesh::io
