// Model reports for `uvmesh info`: a JSON document (stable keys, for tests and tools) and
// a plain-text summary for a person.
//
//   io::ReadResult r = io::read_cad(path, opt);
//   geom::ModelStats s = geom::compute_stats(r.model);
//   std::cout << io::info_text(r.model, s, r.report);
//   std::string js = io::info_json(r.model, s, r.report, /*indent=*/2);
//
// JSON keys: file, format, units ("inch", "mm", ...; "unitless" for BREP), unit_in_mm and
// unit_in_m (size of one unit; null when unitless), file_units (canonical unit the file
// declares), file_units_declared (its own spelling), units_converted,
// counts{solids,shells,faces,edges,vertices}, surface_kinds{planar:n,...}, curve_kinds{line:n,...},
// seam_edges, faces_with_seams, degenerate_edges, free_edges, non_manifold_edges, short_edges,
// short_edge_threshold, min_edge_length, open_shells, vertex_gaps, bbox{min,max,diagonal},
// validity_checked, invalid_faces[{face, reason}], healing{enabled,
// steps[{name,applied,detail,faces_before,...}]}, warnings[], timing{read,heal,build}.
#pragma once

#include <string>

#include "uvmesh/geom/model.h"
#include "uvmesh/io/cad_reader.h"

namespace uvmesh::io {

std::string info_json(const geom::Model& m, const geom::ModelStats& s, const ReadReport& r,
                      bool heal_enabled, int indent = 2);
std::string info_text(const geom::Model& m, const geom::ModelStats& s, const ReadReport& r,
                      bool heal_enabled);

}  // namespace uvmesh::io
