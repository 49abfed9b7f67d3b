#include "uvmesh2d/poly.h"

#include <cmath>
#include <cstdint>
#include <fstream>
#include <limits>
#include <string_view>
#include <unordered_map>

#include "uvmesh2d/text.h"

namespace uvmesh::cli2d {

namespace {

using text::LineReader;
using text::quoted;

// Counts above this are rejected: vertex ids are int32 in the mesher, and a corrupt header
// must not make us reserve gigabytes before the first record is read.
constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max() - 1;
// Reserve at most this many entries up front; vectors grow past it if the file is real.
constexpr std::int64_t kMaxReserve = 1 << 20;

std::string plural(std::int64_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// One parse of one file: knows the file name and the current line for messages.
class Parser {
 public:
  Parser(std::istream& in, std::string name) : lr_(in), name_(std::move(name)) {}

  std::optional<Diagnostic> error;
  std::vector<std::string_view> f;  // fields of the current record

  bool fail(const std::string& msg) {
    error = Diagnostic{name_, lr_.line(), msg};
    return false;
  }

  // Reads the next record; at end of input fails with "unexpected end of file: <expected>".
  bool record(const std::string& expected) {
    if (lr_.next(f)) return true;
    return fail("unexpected end of file: expected " + expected);
  }
  bool try_record() { return lr_.next(f); }
  int line() const { return lr_.line(); }
  const std::string& name() const { return name_; }

  // Field i as an integer / finite real; `what` names it in the message.
  bool get_int(std::size_t i, const std::string& what, std::int64_t& v) {
    auto p = text::parse_int(f[i]);
    if (!p) return fail(what + ": " + quoted(f[i]) + " is not an integer");
    v = *p;
    return true;
  }
  bool get_real(std::size_t i, const std::string& what, double& v) {
    auto p = text::parse_double(f[i]);
    if (!p) return fail(what + ": " + quoted(f[i]) + " is not a number");
    if (!std::isfinite(*p)) return fail(what + " is " + quoted(f[i]) + "; numbers must be finite");
    v = *p;
    return true;
  }
  bool get_count(std::size_t i, const std::string& what, std::int64_t& v) {
    if (!get_int(i, what, v)) return false;
    if (v < 0) return fail(what + " is negative (" + std::to_string(v) + ")");
    if (v > kMaxCount) return fail(what + " is too large (" + std::to_string(v) + ")");
    return true;
  }
  bool expect_fields(std::size_t lo, std::size_t hi, const std::string& what,
                     const std::string& layout) {
    if (f.size() >= lo && f.size() <= hi) return true;
    std::string n =
        lo == hi ? std::to_string(lo) : std::to_string(lo) + " to " + std::to_string(hi);
    return fail(what + ": expected " + n + " fields (" + layout + "), found " +
                std::to_string(f.size()));
  }

 private:
  LineReader lr_;
  std::string name_;
};

// The node header ("<#nodes> <dim> <#attributes> <#markers>", trailing fields optional as
// in Triangle) has been read into p.f; reads the nodes that follow.
bool parse_nodes(Parser& p, PolyData& poly, std::int64_t& count) {
  if (!p.expect_fields(1, 4, "node header",
                       "<#nodes> <dimension> <#attributes> <#boundary markers>"))
    return false;
  std::int64_t dim = 2, nattr = 0, nmark = 0;
  if (!p.get_count(0, "number of nodes", count)) return false;
  if (p.f.size() > 1 && !p.get_int(1, "dimension", dim)) return false;
  if (p.f.size() > 2 && !p.get_count(2, "number of node attributes", nattr)) return false;
  if (p.f.size() > 3 && !p.get_int(3, "number of node boundary markers", nmark)) return false;
  if (dim != 2) return p.fail("dimension must be 2, found " + std::to_string(dim));
  if (nmark != 0 && nmark != 1)
    return p.fail("number of node boundary markers must be 0 or 1, found " + std::to_string(nmark));
  if (nattr > 1000)
    return p.fail("number of node attributes is too large (" + std::to_string(nattr) + ")");
  if (count == 0) return true;  // nodes come from a .node file

  poly.node_file = p.name();
  poly.node_attribute_count = static_cast<int>(nattr);
  poly.has_node_markers = nmark == 1;
  auto& pts = poly.pslg.points;
  pts.clear();
  poly.pslg.point_markers.clear();
  poly.node_attributes.clear();
  poly.node_lines.clear();
  pts.reserve(static_cast<std::size_t>(std::min(count, kMaxReserve)));
  std::size_t nf = 3 + static_cast<std::size_t>(nattr + nmark);
  std::string layout = "<node id> <x> <y>";
  if (nattr > 0) layout += " " + plural(nattr, "attribute", "attributes");
  if (nmark > 0) layout += " <boundary marker>";
  for (std::int64_t i = 0; i < count; ++i) {
    if (!p.record(plural(count, "node", "nodes") + ", found " + std::to_string(i))) return false;
    std::int64_t id = 0;
    if (!p.get_int(0, "node id", id)) return false;
    if (i == 0) {
      if (id != 0 && id != 1)
        return p.fail("the first node id must be 0 or 1 (it fixes the numbering), found " +
                      std::to_string(id));
      poly.first_index = static_cast<int>(id);
    } else if (id != poly.first_index + i) {
      return p.fail("node ids must be consecutive: expected node " +
                    std::to_string(poly.first_index + i) + ", found node " + std::to_string(id));
    }
    std::string what = "node " + std::to_string(id);
    if (!p.expect_fields(nf, nf, what, layout)) return false;
    m2d::Vec2 v;
    if (!p.get_real(1, what + " x coordinate", v.x) || !p.get_real(2, what + " y coordinate", v.y))
      return false;
    pts.push_back(v);
    for (std::int64_t a = 0; a < nattr; ++a) {
      double val = 0;
      if (!p.get_real(3 + static_cast<std::size_t>(a), what + " attribute " + std::to_string(a + 1),
                      val))
        return false;
      poly.node_attributes.push_back(val);
    }
    if (nmark == 1) {
      std::int64_t m = 0;
      if (!p.get_int(nf - 1, what + " boundary marker", m)) return false;
      if (m < std::numeric_limits<int>::min() || m > std::numeric_limits<int>::max())
        return p.fail(what + " boundary marker is out of range (" + std::to_string(m) + ")");
      poly.pslg.point_markers.push_back(static_cast<int>(m));
    }
    poly.node_lines.push_back(p.line());
  }
  return true;
}

std::string node_file_name(const std::string& poly_name) {
  std::string ext = text::extension(poly_name);
  if (ext == ".poly") return poly_name.substr(0, poly_name.size() - 5) + ".node";
  return poly_name + ".node";
}

}  // namespace

std::string PolyData::describe_segment(std::size_t i) const {
  std::string s = "segment ";
  s += i < segment_ids.size() ? std::to_string(segment_ids[i]) : std::to_string(i + first_index);
  if (i < segment_lines.size()) s += " (" + file + ":" + std::to_string(segment_lines[i]) + ")";
  return s;
}

std::string PolyData::describe_node(std::size_t i) const {
  std::string s = "node " + std::to_string(static_cast<std::int64_t>(i) + first_index);
  if (i < node_lines.size()) s += " (" + node_file + ":" + std::to_string(node_lines[i]) + ")";
  return s;
}

std::optional<Diagnostic> parse_node_file(std::istream& in, const std::string& name,
                                          PolyData& poly) {
  Parser p(in, name);
  if (!p.record("the node header '<#nodes> <dimension> <#attributes> <#boundary markers>'"))
    return p.error;
  std::int64_t count = 0;
  if (!parse_nodes(p, poly, count)) return p.error;
  if (count == 0) {
    p.fail("the file has no nodes");
    return p.error;
  }
  if (p.try_record()) {
    p.fail("unexpected content after the last node");
    return p.error;
  }
  return std::nullopt;
}

PolyRead parse_poly(std::istream& in, const std::string& name, const FileOpener& open_node_file) {
  PolyRead r;
  PolyData& poly = r.poly;
  poly.file = name;
  Parser p(in, name);
  auto failed = [&]() -> PolyRead& {
    r.error = p.error;
    return r;
  };
  auto fail = [&](const std::string& msg) -> PolyRead& {
    p.fail(msg);
    return failed();
  };

  // Nodes.
  if (!p.record("the node header '<#nodes> <dimension> <#attributes> <#boundary markers>'"))
    return failed();
  std::int64_t count = 0;
  if (!parse_nodes(p, poly, count)) return failed();
  if (count == 0) {
    std::string node_name = node_file_name(name);
    std::unique_ptr<std::istream> nin = open_node_file ? open_node_file(node_name) : nullptr;
    if (!nin) {
      p.fail("the PSLG is empty: the node section has 0 nodes and there is no " + node_name +
             " to read them from");
      return failed();
    }
    if (auto e = parse_node_file(*nin, node_name, poly)) {
      r.error = e;
      return r;
    }
  }
  const std::int64_t nodes = static_cast<std::int64_t>(poly.pslg.points.size());
  const std::int64_t lo = poly.first_index, hi = poly.first_index + nodes - 1;

  // Segments.
  if (!p.record("the segment header '<#segments> <#boundary markers>'")) return failed();
  if (!p.expect_fields(1, 2, "segment header", "<#segments> <#boundary markers>")) return failed();
  std::int64_t nseg = 0, smark = 0;
  if (!p.get_count(0, "number of segments", nseg)) return failed();
  if (p.f.size() > 1 && !p.get_int(1, "number of segment boundary markers", smark)) return failed();
  if (smark != 0 && smark != 1)
    return fail("number of segment boundary markers must be 0 or 1, found " +
                std::to_string(smark));
  poly.has_segment_markers = smark == 1;
  poly.pslg.segments.reserve(static_cast<std::size_t>(std::min(nseg, kMaxReserve)));
  std::unordered_map<std::int64_t, int> seen;  // segment id -> line
  const std::size_t nf = 3 + static_cast<std::size_t>(smark);
  const std::string layout =
      smark ? "<segment id> <node> <node> <boundary marker>" : "<segment id> <node> <node>";
  for (std::int64_t i = 0; i < nseg; ++i) {
    if (!p.record(plural(nseg, "segment", "segments") + ", found " + std::to_string(i)))
      return failed();
    std::int64_t id = 0;
    if (!p.get_int(0, "segment id", id)) return failed();
    std::string what = "segment " + std::to_string(id);
    if (!p.expect_fields(nf, nf, what, layout)) return failed();
    auto [it, fresh] = seen.emplace(id, p.line());
    if (!fresh)
      return fail(what + " is defined twice (first at line " + std::to_string(it->second) + ")");
    std::int64_t ends[2] = {0, 0};
    for (int k = 0; k < 2; ++k) {
      if (!p.get_int(1 + static_cast<std::size_t>(k), what + " endpoint", ends[k])) return failed();
      if (ends[k] < lo || ends[k] > hi)
        return fail(what + " references node " + std::to_string(ends[k]) + ", but there are " +
                    plural(nodes, "node", "nodes") + " (numbered " + std::to_string(lo) + " to " +
                    std::to_string(hi) + ")");
    }
    if (ends[0] == ends[1]) return fail(what + " has both ends at node " + std::to_string(ends[0]));
    m2d::Pslg::Segment s;
    s.a = static_cast<m2d::VertId>(ends[0] - lo);
    s.b = static_cast<m2d::VertId>(ends[1] - lo);
    if (smark) {
      std::int64_t m = 0;
      if (!p.get_int(3, what + " boundary marker", m)) return failed();
      if (m < std::numeric_limits<int>::min() || m > std::numeric_limits<int>::max())
        return fail(what + " boundary marker is out of range (" + std::to_string(m) + ")");
      s.marker = static_cast<int>(m);
    }
    poly.pslg.segments.push_back(s);
    poly.segment_ids.push_back(id);
    poly.segment_lines.push_back(p.line());
  }

  // Holes (the count line is required, as in Triangle).
  if (!p.record("the hole header '<#holes>'")) return failed();
  if (!p.expect_fields(1, 1, "hole header", "<#holes>")) return failed();
  std::int64_t nholes = 0;
  if (!p.get_count(0, "number of holes", nholes)) return failed();
  for (std::int64_t i = 0; i < nholes; ++i) {
    if (!p.record(plural(nholes, "hole", "holes") + ", found " + std::to_string(i)))
      return failed();
    std::int64_t id = 0;
    if (!p.get_int(0, "hole id", id)) return failed();
    std::string what = "hole " + std::to_string(id);
    if (!p.expect_fields(3, 3, what, "<hole id> <x> <y>")) return failed();
    m2d::Vec2 v;
    if (!p.get_real(1, what + " x coordinate", v.x) || !p.get_real(2, what + " y coordinate", v.y))
      return failed();
    poly.pslg.holes.push_back(v);
    poly.hole_lines.push_back(p.line());
  }

  // Regions (optional section).
  if (!p.try_record()) return r;
  if (!p.expect_fields(1, 1, "region header", "<#regions>")) return failed();
  std::int64_t nreg = 0;
  if (!p.get_count(0, "number of regions", nreg)) return failed();
  for (std::int64_t i = 0; i < nreg; ++i) {
    if (!p.record(plural(nreg, "region", "regions") + ", found " + std::to_string(i)))
      return failed();
    std::int64_t id = 0;
    if (!p.get_int(0, "region id", id)) return failed();
    std::string what = "region " + std::to_string(id);
    if (!p.expect_fields(4, 5, what, "<region id> <x> <y> <attribute> [<maximum area>]"))
      return failed();
    m2d::Pslg::Region reg;
    double area = -1;
    if (!p.get_real(1, what + " x coordinate", reg.seed.x) ||
        !p.get_real(2, what + " y coordinate", reg.seed.y) ||
        !p.get_real(3, what + " attribute", reg.attribute))
      return failed();
    if (p.f.size() == 5 && !p.get_real(4, what + " maximum area", area)) return failed();
    poly.pslg.regions.push_back(reg);
    poly.region_max_area.push_back(area > 0 ? area : -1.0);
    poly.region_lines.push_back(p.line());
  }
  if (p.try_record()) return fail("unexpected content after the region section");
  return r;
}

PolyRead read_poly(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    PolyRead r;
    r.poly.file = path;
    r.error = Diagnostic{path, 0, "cannot open the file for reading"};
    return r;
  }
  FileOpener opener = [](const std::string& node_path) -> std::unique_ptr<std::istream> {
    auto f = std::make_unique<std::ifstream>(node_path, std::ios::binary);
    if (!*f) return nullptr;
    return f;
  };
  PolyRead r = parse_poly(in, path, opener);
  if (r.ok() && in.bad()) r.error = Diagnostic{path, 0, "read error"};
  return r;
}

}  // namespace uvmesh::cli2d
