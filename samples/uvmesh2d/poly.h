// uvmesh::cli2d -- reader for Triangle's .poly format (a planar straight line graph).
//
// Usage:
//   uvmesh::cli2d::PolyRead r = uvmesh::cli2d::read_poly("domain.poly");
//   if (!r.ok()) { std::cerr << r.error->str() << '\n'; return 2; }
//   uvmesh::m2d::Result m = uvmesh::m2d::mesh(r.poly.pslg, size);
//
// Format (https://www.cs.cmu.edu/~quake/triangle.poly.html), one record per line:
//   <#nodes> <dimension = 2> <#attributes> <#boundary markers: 0 or 1>
//   <node id> <x> <y> [attributes...] [marker]            (#nodes lines)
//   <#segments> <#boundary markers: 0 or 1>
//   <segment id> <node> <node> [marker]                    (#segments lines)
//   <#holes>
//   <hole id> <x> <y>                                      (#holes lines)
//   [<#regions>                                            (optional section)
//    <region id> <x> <y> <attribute> [<maximum area>]]     (#regions lines)
// '#' starts a comment anywhere on a line; blank lines are ignored. Node ids are
// consecutive and start at 0 or 1: the first node's id decides, and segments use the same
// numbering. A node count of 0 means "the nodes are in the .node file of the same name"
// (as Triangle does). Strict where Triangle is lenient: every line must have exactly the
// fields the header announces, so that a column-count mistake is reported at its line
// rather than read as shifted data.
#pragma once

#include <functional>
#include <istream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/diagnostic.h"

namespace uvmesh::cli2d {

struct PolyData {
  m2d::Pslg pslg;       // 0-based, ready for m2d::mesh()
  int first_index = 0;  // numbering used in the file: 0 or 1
  int node_attribute_count = 0;
  std::vector<double> node_attributes;    // node_attribute_count values per node, row-major
  bool has_node_markers = false;          // pslg.point_markers filled iff true
  bool has_segment_markers = false;       // otherwise every segment marker is 0
  std::vector<std::int64_t> segment_ids;  // id of each segment as written in the file
  std::vector<double> region_max_area;    // per region; <= 0 when none was given

  // Where each entity was read, so that later messages (e.g. from the mesher) can point
  // at the line that defined it.
  std::string file;       // the .poly file
  std::string node_file;  // the file the nodes came from (the .poly or its .node)
  std::vector<int> node_lines, segment_lines, hole_lines, region_lines;

  // 'segment 3 (file.poly:12)': the file's own id and where it was defined.
  std::string describe_segment(std::size_t index) const;
  std::string describe_node(std::size_t index) const;
};

struct PolyRead {
  PolyData poly;
  std::optional<Diagnostic> error;  // set iff reading failed; poly is then partial
  bool ok() const { return !error.has_value(); }
};

// Opens the .node file named by a .poly with 0 nodes; returns null when it does not exist.
using FileOpener = std::function<std::unique_ptr<std::istream>(const std::string& path)>;

// Reads a .poly file (and its .node file when the node section is empty).
PolyRead read_poly(const std::string& path);

// Parses .poly text from a stream; `name` is used in diagnostics and to derive the .node
// file name, which `open_node_file` opens (none: a 0-node file is an error).
PolyRead parse_poly(std::istream& in, const std::string& name,
                    const FileOpener& open_node_file = {});

// Parses a Triangle .node file (header and nodes) into poly's node fields.
std::optional<Diagnostic> parse_node_file(std::istream& in, const std::string& name,
                                          PolyData& poly);

}  // namespace uvmesh::cli2d
