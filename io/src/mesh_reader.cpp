// Mesh readers (mesh_reader.h). The whole file is read into memory and parsed by two
// cursors: Text (tokens with line numbers) and Bytes (fixed-size binary values with byte
// offsets). Both throw ParseError, caught once in read_mesh and turned into
// "<path>: <where>: <problem>"; nothing else in uvmesh::io throws.
//
// Formats, as read here:
//  - Gmsh MSH 4.1 and 2.2: Gmsh reference manual, "MSH file format" (4.1 and the legacy
//    2.2 appendix).
//  - Medit: INRIA RT-0253 (ASCII keywords); libMeshb's binary layout (int32 code 1 for
//    the byte order, int32 version, keywords with the position of the next one).
//  - STL, OBJ: as in mesh_writer.cpp. PLY: Turk's header/element/property format.
#include "uvmesh/io/mesh_reader.h"

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <new>
#include <string_view>
#include <unordered_map>

#include "draco_io.h"

namespace uvmesh::io {

namespace {

using surface::NodeId;
using surface::SurfaceMesh;

struct ParseError {
  std::string what;
};

[[noreturn]] void fail(std::string what) {
  throw ParseError{std::move(what)};
}

// std::byteswap is C++23.
std::int32_t byteswap32(std::int32_t v) {
  const auto u = static_cast<std::uint32_t>(v);
  return static_cast<std::int32_t>((u >> 24) | ((u >> 8) & 0xff00u) | ((u << 8) & 0xff0000u) |
                                   (u << 24));
}

// ----------------------------------------------------------------------------- cursors

class Text {
 public:
  Text(const char* p, const char* end) : p_(p), end_(end) {}

  int line() const { return line_; }
  std::string where() const { return "line " + std::to_string(line_); }
  const char* pos() const { return p_; }
  const char* end() const { return end_; }
  void seek(const char* p) { p_ = p; }

  // Next whitespace-separated token; "" at the end of the data.
  std::string_view token() {
    skip_space();
    const char* b = p_;
    while (p_ < end_ && !std::isspace(static_cast<unsigned char>(*p_))) ++p_;
    return {b, static_cast<std::size_t>(p_ - b)};
  }
  // The rest of the current line (without its newline), moving to the next line.
  std::string_view rest_of_line() {
    while (p_ < end_ && (*p_ == ' ' || *p_ == '\t')) ++p_;
    const char* b = p_;
    while (p_ < end_ && *p_ != '\n') ++p_;
    std::string_view s(b, static_cast<std::size_t>(p_ - b));
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
    while (!s.empty() && (s.back() == '\r' || s.back() == ' ' || s.back() == '\t'))
      s.remove_suffix(1);
    return s;
  }
  bool at_end() {
    skip_space();
    return p_ >= end_;
  }
  // Skips to just after the next newline (binary data follows a header line directly).
  void skip_newline() {
    while (p_ < end_ && *p_ != '\n') ++p_;
    if (p_ < end_) {
      ++p_;
      ++line_;
    }
  }

  template <class T>
  T number(const char* what) {
    const std::string_view t = token();
    if (t.empty())
      fail(where() + ": file ends where " + std::string(what) + " was expected (truncated?)");
    T v{};
    const char* b = t.data();
    // from_chars rejects a leading '+', which some writers emit.
    if (t.size() > 1 && b[0] == '+') ++b;
    const auto r = std::from_chars(b, t.data() + t.size(), v);
    if (r.ec != std::errc() || r.ptr != t.data() + t.size())
      fail(where() + ": expected " + std::string(what) + ", found '" +
           std::string(t.substr(0, 40)) + "'");
    if constexpr (std::is_floating_point_v<T>)
      if (!std::isfinite(v)) fail(where() + ": " + std::string(what) + " is not finite");
    return v;
  }
  std::int64_t integer(const char* what) { return number<std::int64_t>(what); }
  double real(const char* what) { return number<double>(what); }
  std::int64_t count(const char* what,
                     std::int64_t max = std::numeric_limits<std::int32_t>::max()) {
    const std::int64_t n = integer(what);
    if (n < 0 || n > max)
      fail(where() + ": " + std::string(what) + " " + std::to_string(n) + " is out of range");
    return n;
  }
  void expect(std::string_view word) {
    const std::string_view t = token();
    if (t == word) return;
    // Built with append: GCC 12 warns (-Wrestrict, a false positive) on "'" + string.
    std::string found = "the end of the file (truncated?)";
    if (!t.empty()) found = std::string(1, '\'').append(t.substr(0, 40)).append(1, '\'');
    fail(where() + ": expected '" + std::string(word) + "', found " + found);
  }

 private:
  void skip_space() {
    while (p_ < end_ && std::isspace(static_cast<unsigned char>(*p_))) {
      if (*p_ == '\n') ++line_;
      ++p_;
    }
  }
  const char* p_;
  const char* end_;
  int line_ = 1;
};

class Bytes {
 public:
  Bytes(const char* base, const char* p, const char* end, bool big_endian = false)
      : base_(base), p_(p), end_(end), big_(big_endian) {}

  std::size_t offset() const { return static_cast<std::size_t>(p_ - base_); }
  std::string where() const { return "byte offset " + std::to_string(offset()); }
  const char* pos() const { return p_; }
  void seek(const char* p) { p_ = p; }
  std::size_t left() const { return static_cast<std::size_t>(end_ - p_); }

  void need(std::size_t n, const char* what) {
    if (left() < n)
      fail(where() + ": file ends inside " + std::string(what) + " (" + std::to_string(n) +
           " bytes needed, " + std::to_string(left()) + " left; truncated?)");
  }
  template <class T>
  T get(const char* what) {
    need(sizeof(T), what);
    std::array<unsigned char, sizeof(T)> b;
    std::memcpy(b.data(), p_, sizeof(T));
    p_ += sizeof(T);
    const bool swap = big_ != (std::endian::native == std::endian::big);
    if (swap) std::reverse(b.begin(), b.end());
    return std::bit_cast<T>(b);
  }
  double real(const char* what) {
    const double v = get<double>(what);
    if (!std::isfinite(v)) fail(where() + ": " + std::string(what) + " is not finite");
    return v;
  }
  void skip(std::size_t n, const char* what) {
    need(n, what);
    p_ += n;
  }

 private:
  const char* base_;
  const char* p_;
  const char* end_;
  bool big_;
};

// ----------------------------------------------------------------------------- helpers

// Node numbering of a file (1-based tags, possibly sparse) -> point indices.
class NodeMap {
 public:
  void add(std::int64_t tag, NodeId index, const std::string& where) {
    if (tag < 1) fail(where + ": node tag " + std::to_string(tag) + " (tags start at 1)");
    if (!map_.emplace(tag, index).second)
      fail(where + ": node tag " + std::to_string(tag) + " appears twice");
  }
  NodeId at(std::int64_t tag, const std::string& where) const {
    auto it = map_.find(tag);
    if (it == map_.end())
      fail(where + ": element refers to node " + std::to_string(tag) + ", which is not defined");
    return it->second;
  }
  void reserve(std::size_t n) { map_.reserve(n); }

 private:
  std::unordered_map<std::int64_t, NodeId> map_;
};

NodeId checked_index(std::int64_t one_based, std::size_t np, const std::string& where) {
  if (one_based < 1 || static_cast<std::size_t>(one_based) > np)
    fail(where + ": vertex index " + std::to_string(one_based) + " is out of range 1.." +
         std::to_string(np));
  return static_cast<NodeId>(one_based - 1);
}

// A count read from a file sizes a reservation only up to a bound: a corrupt count must
// give "file ends" at the data, not an allocation of gigabytes first.
std::size_t bounded(std::int64_t n) {
  return static_cast<std::size_t>(std::clamp<std::int64_t>(n, 0, 1 << 20));
}

// A number read from a file, for a message: the shortest form that reads back the same
// (std::to_chars). Not a cast to an integer: a value beyond long long's range would make
// that cast undefined (fuzz_mesh_ply: a PLY vertex index of 8.9e19).
std::string shortest(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

geom::Id entity_id(std::int64_t tag) {
  return tag >= 1 ? static_cast<geom::Id>(tag - 1) : 0;
}

// Classification from the elements (mesh_reader.h): vertices of point elements, nodes of
// segments, then the face of the first triangle; unused points on face 0.
void classify_from_elements(SurfaceMesh& m,
                            const std::vector<std::pair<NodeId, geom::Id>>& point_elements) {
  const std::size_t np = m.points.size();
  m.point_dim.assign(np, 2);
  m.point_entity.assign(np, -1);
  m.point_t.assign(np, 0.0);
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (NodeId v : m.triangles[t])
      if (m.point_entity[static_cast<std::size_t>(v)] < 0)
        m.point_entity[static_cast<std::size_t>(v)] = m.triangle_face[t];
  for (const auto& s : m.segments)
    for (NodeId v : {s.a, s.b}) {
      m.point_dim[static_cast<std::size_t>(v)] = 1;
      m.point_entity[static_cast<std::size_t>(v)] = s.edge;
    }
  for (const auto& [v, id] : point_elements) {
    m.point_dim[static_cast<std::size_t>(v)] = 0;
    m.point_entity[static_cast<std::size_t>(v)] = id;
  }
  for (geom::Id& e : m.point_entity) e = std::max<geom::Id>(e, 0);
}

// Nodes per element of the MSH element types a surface-mesh file may hold; -1 unknown.
int msh_nodes_of_type(std::int64_t type) {
  switch (type) {
    case 1:
      return 2;  // line
    case 2:
      return 3;  // triangle
    case 3:
      return 4;  // quadrangle
    case 4:
      return 4;  // tetrahedron
    case 5:
      return 8;  // hexahedron
    case 6:
      return 6;  // prism
    case 7:
      return 5;  // pyramid
    case 8:
      return 3;  // 3-node line
    case 9:
      return 6;  // 6-node triangle
    case 10:
      return 9;  // 9-node quadrangle
    case 11:
      return 10;  // 10-node tetrahedron
    case 15:
      return 1;  // point
    case 16:
      return 8;  // 8-node quadrangle
    default:
      return -1;
  }
}

// Collects elements of any format into the mesh.
struct ElementSink {
  SurfaceMesh& m;
  MeshReadResult& r;
  std::vector<std::pair<NodeId, geom::Id>> point_elements;

  void element(std::int64_t type, const NodeId* nodes, geom::Id entity) {
    if (type == 2) {
      m.triangles.push_back({nodes[0], nodes[1], nodes[2]});
      m.triangle_face.push_back(entity);
    } else if (type == 1) {
      m.segments.push_back({nodes[0], nodes[1], entity});
    } else if (type == 15) {
      point_elements.emplace_back(nodes[0], entity);
    } else {
      ++r.skipped_elements;
    }
  }
};

// ----------------------------------------------------------------------------- Gmsh

// Skips a section's body up to and including its "$End..." line (sections this reader
// does not need; binary bodies contain no line that starts with "$End").
void skip_msh_section(Text& t, std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  while (true) {
    if (t.pos() >= t.end())
      fail(t.where() + ": file ends inside section " + std::string(name) + " (truncated?)");
    const std::string_view l = t.rest_of_line();
    if (l == end) return;
  }
}

void read_physical_names(Text& t, MeshReadResult& r) {
  const std::int64_t n = t.count("the number of physical names");
  for (std::int64_t i = 0; i < n; ++i) {
    MeshReadResult::Physical p;
    p.dim = static_cast<int>(t.integer("a physical group dimension"));
    p.tag = static_cast<int>(t.integer("a physical group tag"));
    std::string_view name = t.rest_of_line();
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
      name = name.substr(1, name.size() - 2);
    p.name = std::string(name);
    r.physicals.push_back(std::move(p));
  }
  t.expect("$EndPhysicalNames");
}

// A section other than the ones a format's reader parses itself: physical names are
// kept, other sections skipped, anything else is an error.
void other_msh_section(Text& t, std::string_view sec, MeshReadResult& r, const char* known) {
  if (sec == "$PhysicalNames") {
    read_physical_names(t, r);
  } else if (!sec.empty() && sec[0] == '$') {
    t.rest_of_line();
    skip_msh_section(t, sec);
  } else {
    fail(t.where() + ": expected a section (" + known + "), found '" +
         std::string(sec.substr(0, 40)) + "'");
  }
}

void read_msh22(Text& t, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  NodeMap nodes;
  ElementSink sink{m, r, {}};
  bool have_nodes = false;
  while (!t.at_end()) {
    const std::string_view sec = t.token();
    if (sec == "$Nodes") {
      const std::int64_t n = t.count("the number of nodes");
      nodes.reserve(bounded(n));
      m.points.reserve(bounded(n));
      for (std::int64_t i = 0; i < n; ++i) {
        const std::int64_t tag = t.integer("a node tag");
        nodes.add(tag, static_cast<NodeId>(m.points.size()), t.where());
        const double x = t.real("x"), y = t.real("y"), z = t.real("z");
        m.points.emplace_back(x, y, z);
      }
      t.expect("$EndNodes");
      have_nodes = true;
    } else if (sec == "$Elements") {
      if (!have_nodes) fail(t.where() + ": $Elements before $Nodes");
      const std::int64_t n = t.count("the number of elements");
      for (std::int64_t i = 0; i < n; ++i) {
        t.integer("an element tag");
        const std::int64_t type = t.integer("an element type");
        const int nn = msh_nodes_of_type(type);
        if (nn < 0) fail(t.where() + ": unknown element type " + std::to_string(type));
        const std::int64_t ntags = t.count("the number of element tags", 100);
        std::int64_t tags[2] = {0, 0};
        for (std::int64_t k = 0; k < ntags; ++k) {
          const std::int64_t v = t.integer("an element tag value");
          if (k < 2) tags[k] = v;
        }
        // tags: physical, elementary (a single tag is taken as the entity).
        const std::int64_t entity = ntags >= 2 ? tags[1] : tags[0];
        NodeId nd[10];
        for (int k = 0; k < nn; ++k) nd[k] = nodes.at(t.integer("an element node"), t.where());
        sink.element(type, nd, entity_id(entity));
      }
      t.expect("$EndElements");
    } else {
      other_msh_section(t, sec, r, "$Nodes, $Elements, ...");
    }
  }
  if (!have_nodes) fail("no $Nodes section");
  r.has_face_ids = true;
  classify_from_elements(m, sink.point_elements);
}

// MSH 4.1, ASCII or binary: the same records, read through one of the two cursors.
class MshIn {
 public:
  MshIn(Text& t, Bytes* b) : t_(t), b_(b) {}
  std::string where() const { return b_ ? b_->where() : t_.where(); }
  std::int64_t i(const char* what) { return b_ ? b_->get<std::int32_t>(what) : t_.integer(what); }
  std::int64_t z(const char* what) {
    if (!b_) return t_.count(what, std::numeric_limits<std::int64_t>::max());
    const std::uint64_t v = b_->get<std::uint64_t>(what);
    if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      fail(where() + ": " + what + " out of range");
    return static_cast<std::int64_t>(v);
  }
  std::int64_t count(const char* what) {
    const std::int64_t n = z(what);
    if (n > std::numeric_limits<std::int32_t>::max())
      fail(where() + ": " + std::string(what) + " " + std::to_string(n) + " is out of range");
    return n;
  }
  double d(const char* what) { return b_ ? b_->real(what) : t_.real(what); }
  // Back to text at the end of a binary section: the "$End..." line follows a newline.
  void end_section(std::string_view end_word) {
    if (b_) {
      t_.seek(b_->pos());
    }
    t_.expect(end_word);
  }
  void begin_section() {
    if (b_) {
      t_.skip_newline();  // the section name's line end
      b_->seek(t_.pos());
    }
  }

 private:
  Text& t_;
  Bytes* b_;
};

void read_msh41(Text& t, Bytes* bin, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  MshIn in(t, bin);
  NodeMap nodes;
  ElementSink sink{m, r, {}};
  bool have_nodes = false, have_elements = false;
  while (!t.at_end()) {
    const std::string_view sec = t.token();
    if (sec == "$Entities") {
      in.begin_section();
      std::int64_t n[4];
      for (auto& k : n) k = in.count("an entity count");
      for (int d = 0; d < 4; ++d) {
        r.entities[static_cast<std::size_t>(d)] = static_cast<std::size_t>(n[d]);
        for (std::int64_t e = 0; e < n[d]; ++e) {
          in.i("an entity tag");
          for (int k = 0; k < (d == 0 ? 3 : 6); ++k) in.d("an entity bounding-box coordinate");
          const std::int64_t nphys = in.count("the number of physical tags");
          for (std::int64_t k = 0; k < nphys; ++k) in.i("a physical tag");
          if (d > 0) {
            const std::int64_t nb = in.count("the number of bounding entities");
            for (std::int64_t k = 0; k < nb; ++k) in.i("a bounding entity tag");
          }
        }
      }
      in.end_section("$EndEntities");
    } else if (sec == "$Nodes") {
      in.begin_section();
      const std::int64_t blocks = in.count("the number of node blocks");
      const std::int64_t total = in.count("the number of nodes");
      in.z("the smallest node tag");
      in.z("the largest node tag");
      nodes.reserve(bounded(total));
      m.points.reserve(bounded(total));
      for (std::int64_t b = 0; b < blocks; ++b) {
        const std::int64_t dim = in.i("a node block dimension");
        const std::int64_t tag = in.i("a node block entity tag");
        const std::int64_t parametric = in.i("the parametric flag");
        const std::int64_t n = in.count("the number of nodes in the block");
        if (dim < 0 || dim > 3)
          fail(in.where() + ": node block of dimension " + std::to_string(dim));
        if (static_cast<std::int64_t>(m.points.size()) + n > total)
          fail(in.where() + ": the node blocks hold more nodes than the " + std::to_string(total) +
               " announced");
        const std::size_t first = m.points.size();
        for (std::int64_t k = 0; k < n; ++k) {
          const std::int64_t nt = in.z("a node tag");
          nodes.add(nt, static_cast<NodeId>(first + static_cast<std::size_t>(k)), in.where());
        }
        for (std::int64_t k = 0; k < n; ++k) {
          const double x = in.d("x"), y = in.d("y"), z = in.d("z");
          if (parametric)
            for (std::int64_t u = 0; u < std::min<std::int64_t>(dim, 2); ++u)
              in.d("a parametric coordinate");
          m.points.emplace_back(x, y, z);
          // A surface mesh has no volume nodes; a volume mesh's are put on face 0.
          m.point_dim.push_back(static_cast<std::int8_t>(std::min<std::int64_t>(dim, 2)));
          m.point_entity.push_back(dim == 3 ? 0 : entity_id(tag));
          m.point_t.push_back(0.0);
        }
      }
      if (static_cast<std::int64_t>(m.points.size()) != total)
        fail(in.where() + ": " + std::to_string(total) + " nodes announced, " +
             std::to_string(m.points.size()) + " found");
      in.end_section("$EndNodes");
      have_nodes = true;
    } else if (sec == "$Elements") {
      if (!have_nodes) fail(t.where() + ": $Elements before $Nodes");
      in.begin_section();
      const std::int64_t blocks = in.count("the number of element blocks");
      const std::int64_t total = in.count("the number of elements");
      in.z("the smallest element tag");
      in.z("the largest element tag");
      std::int64_t seen = 0;
      for (std::int64_t b = 0; b < blocks; ++b) {
        in.i("an element block dimension");
        const std::int64_t tag = in.i("an element block entity tag");
        const std::int64_t type = in.i("an element type");
        const std::int64_t n = in.count("the number of elements in the block");
        const int nn = msh_nodes_of_type(type);
        if (nn < 0) fail(in.where() + ": unknown element type " + std::to_string(type));
        seen += n;
        if (seen > total)
          fail(in.where() + ": the element blocks hold more elements than the " +
               std::to_string(total) + " announced");
        NodeId nd[10];
        for (std::int64_t k = 0; k < n; ++k) {
          in.z("an element tag");
          for (int j = 0; j < nn; ++j) nd[j] = nodes.at(in.z("an element node tag"), in.where());
          sink.element(type, nd, entity_id(tag));
        }
      }
      if (seen != total)
        fail(in.where() + ": " + std::to_string(total) + " elements announced, " +
             std::to_string(seen) + " found");
      in.end_section("$EndElements");
      have_elements = true;
    } else {
      other_msh_section(t, sec, r, "$Entities, $Nodes, $Elements, ...");
    }
  }
  if (!have_nodes) fail("no $Nodes section");
  if (!have_elements) fail("no $Elements section");
  r.has_face_ids = true;
  r.classified = true;
  // Point elements name the vertex a node is classified on; the node blocks already did.
}

void read_msh(const std::string& data, MeshReadResult& r) {
  Text t(data.data(), data.data() + data.size());
  t.expect("$MeshFormat");
  const std::string_view version = t.token();
  const std::int64_t file_type = t.integer("the file type (0 ASCII, 1 binary)");
  const std::int64_t size = t.integer("the data size");
  if (version != "4.1" && version != "2.2" && version != "2.1" && version != "2.0")
    fail("line 2: MSH version " + std::string(version) + " is not read (4.1 and 2.2 are)");
  if (file_type != 0 && file_type != 1) fail("line 2: file type must be 0 (ASCII) or 1 (binary)");
  if (size != 8) fail("line 2: data size " + std::to_string(size) + " is not read (8 is)");
  r.binary = file_type == 1;
  bool big = false;
  if (r.binary) {
    t.skip_newline();
    Bytes b(data.data(), t.pos(), data.data() + data.size());
    const std::int32_t one = b.get<std::int32_t>("the endianness marker");
    if (one != 1) {
      if (byteswap32(one) != 1) fail(b.where() + ": bad endianness marker in $MeshFormat");
      big = std::endian::native == std::endian::little;
    }
    t.seek(b.pos());
  }
  t.expect("$EndMeshFormat");
  if (version != "4.1") {
    if (r.binary)
      fail("binary MSH " + std::string(version) +
           " is not read (ASCII 2.2 and 4.1 ASCII/binary are)");
    r.format = MeshFormat::Msh22;
    read_msh22(t, r);
    return;
  }
  r.format = MeshFormat::Msh41;
  if (r.binary) {
    Bytes b(data.data(), t.pos(), data.data() + data.size(), big);
    read_msh41(t, &b, r);
  } else {
    read_msh41(t, nullptr, r);
  }
}

// ----------------------------------------------------------------------------- Medit

void read_medit_ascii(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  ElementSink sink{m, r, {}};
  Text t(data.data(), data.data() + data.size());
  int dim = 3;
  bool version = false;
  while (true) {
    std::string_view kw = t.token();
    if (kw.empty()) fail(t.where() + ": file ends without 'End' (truncated?)");
    if (kw[0] == '#') {
      t.rest_of_line();
      continue;
    }
    if (kw == "End") break;
    if (kw == "MeshVersionFormatted") {
      t.integer("the version");
      version = true;
    } else if (kw == "Dimension") {
      dim = static_cast<int>(t.integer("the dimension"));
      if (dim != 2 && dim != 3) fail(t.where() + ": dimension " + std::to_string(dim));
    } else if (kw == "Vertices") {
      const std::int64_t n = t.count("the number of vertices");
      m.points.reserve(bounded(n));
      for (std::int64_t i = 0; i < n; ++i) {
        geom::Vec3 p(0.0);
        for (int k = 0; k < dim; ++k) p[k] = t.real("a coordinate");
        t.integer("a vertex reference");
        m.points.push_back(p);
      }
    } else {
      // Element keywords: nodes per record (+1 reference); a few vertex/entity lists.
      static const std::map<std::string_view, std::pair<int, int>> kElems = {
          {"Edges", {2, 1}},      {"Triangles", {3, 2}},     {"Quadrilaterals", {4, 3}},
          {"Tetrahedra", {4, 4}}, {"Hexahedra", {8, 5}},     {"Prisms", {6, 6}},
          {"Pyramids", {5, 7}},   {"Corners", {1, 0}},       {"RequiredVertices", {1, 0}},
          {"Ridges", {1, 0}},     {"RequiredEdges", {1, 0}}, {"RequiredTriangles", {1, 0}}};
      auto it = kElems.find(kw);
      if (it == kElems.end())
        fail(t.where() + ": unknown Medit keyword '" + std::string(kw.substr(0, 40)) + "'");
      const auto [nn, type] = it->second;
      const bool has_ref = type > 0;
      const std::int64_t n = t.count("an element count");
      for (std::int64_t i = 0; i < n; ++i) {
        NodeId nd[8];
        for (int k = 0; k < nn; ++k)
          nd[k] = checked_index(t.integer("a vertex index"), m.points.size(), t.where());
        if (!has_ref) continue;
        const std::int64_t ref = t.integer("an element reference");
        if (type == 1)
          sink.element(1, nd, entity_id(ref));
        else if (type == 2)
          sink.element(2, nd, entity_id(ref));
        else
          ++r.skipped_elements;
      }
    }
  }
  if (!version) fail("no MeshVersionFormatted keyword: not a Medit file");
  r.has_face_ids = true;
  classify_from_elements(m, sink.point_elements);
}

void read_meshb(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  ElementSink sink{m, r, {}};
  const char* base = data.data();
  Bytes probe(base, base, base + data.size());
  const std::int32_t code = probe.get<std::int32_t>("the byte-order code");
  bool big = false;
  if (code != 1) {
    if (byteswap32(code) != 1)
      fail("byte offset 0: not a binary Medit file (code " + std::to_string(code) +
           ", expected 1)");
    big = true;
  }
  if (std::endian::native == std::endian::big) big = !big;
  Bytes b(base, probe.pos(), base + data.size(), big);
  const std::int32_t version = b.get<std::int32_t>("the version");
  if (version < 1 || version > 4)
    fail("byte offset 4: unknown libMeshb version " + std::to_string(version));
  auto integer = [&](const char* what) -> std::int64_t {
    return version == 4 ? b.get<std::int64_t>(what) : b.get<std::int32_t>(what);
  };
  auto position = [&]() -> std::int64_t {
    return version >= 3 ? b.get<std::int64_t>("a keyword position")
                        : b.get<std::int32_t>("a keyword position");
  };
  auto real = [&](const char* what) -> double {
    if (version == 1) {
      const float f = b.get<float>(what);
      if (!std::isfinite(f)) fail(b.where() + ": " + std::string(what) + " is not finite");
      return f;
    }
    return b.real(what);
  };
  int dim = 3;
  bool end = false;
  while (b.left() > 0) {
    const std::int32_t kw = b.get<std::int32_t>("a keyword code");
    const std::int64_t next = position();
    if (kw == 54) {  // End
      end = true;
      break;
    }
    auto count = [&](const char* what) {
      const std::int64_t n = integer(what);
      if (n < 0 || n > std::numeric_limits<std::int32_t>::max())
        fail(b.where() + ": " + std::string(what) + " out of range");
      return n;
    };
    if (kw == 3) {
      dim = static_cast<int>(b.get<std::int32_t>("the dimension"));
      if (dim != 2 && dim != 3) fail(b.where() + ": dimension " + std::to_string(dim));
    } else if (kw == 4) {
      const std::int64_t n = count("the number of vertices");
      b.need(static_cast<std::size_t>(n) * static_cast<std::size_t>(dim + 1) * 4, "the vertices");
      for (std::int64_t i = 0; i < n; ++i) {
        geom::Vec3 p(0.0);
        for (int k = 0; k < dim; ++k) p[k] = real("a coordinate");
        integer("a vertex reference");
        m.points.push_back(p);
      }
    } else if (kw == 5 || kw == 6) {
      const int nn = kw == 5 ? 2 : 3;
      const std::int64_t n = count("an element count");
      for (std::int64_t i = 0; i < n; ++i) {
        NodeId nd[3];
        for (int k = 0; k < nn; ++k)
          nd[k] = checked_index(integer("a vertex index"), m.points.size(), b.where());
        sink.element(kw == 5 ? 1 : 2, nd, entity_id(integer("an element reference")));
      }
    } else {
      // Any other keyword is skipped through its next-keyword position.
      if (next <= static_cast<std::int64_t>(b.offset()) ||
          next > static_cast<std::int64_t>(data.size()))
        fail(b.where() + ": keyword " + std::to_string(kw) + " has a bad next-keyword position " +
             std::to_string(next));
      b.seek(base + next);
    }
  }
  if (!end) fail(b.where() + ": file ends without the End keyword (truncated?)");
  r.binary = true;
  r.has_face_ids = true;
  classify_from_elements(m, sink.point_elements);
}

// ----------------------------------------------------------------------------- STL

// Corners at bit-identical coordinates become one point.
struct PointMerger {
  SurfaceMesh& m;
  std::map<std::array<double, 3>, NodeId> index;
  NodeId add(double x, double y, double z) {
    auto [it, fresh] =
        index.emplace(std::array<double, 3>{x, y, z}, static_cast<NodeId>(m.points.size()));
    if (fresh) m.points.emplace_back(x, y, z);
    return it->second;
  }
};

void read_stl(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  PointMerger merge{m, {}};
  // Binary when the size matches the count in the header; some binary files start with
  // "solid" too, so the size decides first.
  bool binary = data.size() >= 84;
  std::uint32_t n = 0;
  if (binary) {
    Bytes b(data.data(), data.data() + 80, data.data() + data.size());
    n = b.get<std::uint32_t>("the triangle count");
    binary = data.size() == 84 + 50 * static_cast<std::uint64_t>(n);
  }
  const bool starts_solid = data.compare(0, 5, "solid") == 0;
  if (!binary && !starts_solid) {
    if (data.size() < 84)
      fail("byte offset 0: too short for binary STL (84-byte header) and not ASCII STL");
    fail("byte offset 80: binary STL announces " + std::to_string(n) + " triangles (" +
         std::to_string(84 + 50 * static_cast<std::uint64_t>(n)) + " bytes) but the file has " +
         std::to_string(data.size()) + " bytes (truncated?)");
  }
  if (binary) {
    r.binary = true;
    Bytes b(data.data(), data.data() + 84, data.data() + data.size());
    for (std::uint32_t t = 0; t < n; ++t) {
      b.skip(12, "a facet normal");
      NodeId v[3];
      for (int k = 0; k < 3; ++k) {
        const float x = b.get<float>("x"), y = b.get<float>("y"), z = b.get<float>("z");
        if (!std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
          fail(b.where() + ": a non-finite coordinate");
        v[k] = merge.add(x, y, z);
      }
      b.skip(2, "the attribute byte count");
      m.triangles.push_back({v[0], v[1], v[2]});
      m.triangle_face.push_back(0);
    }
  } else {
    Text t(data.data(), data.data() + data.size());
    geom::Id solid = -1;
    while (!t.at_end()) {
      t.expect("solid");
      t.rest_of_line();
      ++solid;
      while (true) {
        const std::string_view w = t.token();
        if (w == "endsolid") {
          t.rest_of_line();
          break;
        }
        if (w != "facet")
          fail(t.where() + ": expected 'facet' or 'endsolid', found " +
               (w.empty() ? std::string("the end of the file (truncated?)")
                          : "'" + std::string(w.substr(0, 40)) + "'"));
        t.expect("normal");
        for (int k = 0; k < 3; ++k) t.real("a normal component");
        t.expect("outer");
        t.expect("loop");
        NodeId v[3];
        for (int k = 0; k < 3; ++k) {
          t.expect("vertex");
          const double x = t.real("x"), y = t.real("y"), z = t.real("z");
          v[k] = merge.add(x, y, z);
        }
        t.expect("endloop");
        t.expect("endfacet");
        m.triangles.push_back({v[0], v[1], v[2]});
        m.triangle_face.push_back(solid);
      }
    }
    r.has_face_ids = solid > 0;  // several solids: one id each
  }
  classify_from_elements(m, {});
}

// ----------------------------------------------------------------------------- OBJ

void read_obj(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  Text t(data.data(), data.data() + data.size());
  std::map<std::string, geom::Id, std::less<>> groups;
  geom::Id face = 0;
  bool grouped = false, fanned = false;
  std::vector<NodeId> poly;
  while (t.pos() < t.end()) {
    const int ln = t.line();
    std::string_view l = t.rest_of_line();
    const std::string where = "line " + std::to_string(ln);
    Text lt(l.data(), l.data() + l.size());
    const std::string_view kw = lt.token();
    if (kw == "v") {
      geom::Vec3 p(0.0);
      for (int k = 0; k < 3; ++k) {
        const std::string_view tok = lt.token();
        double v = 0;
        const auto res = std::from_chars(tok.data(), tok.data() + tok.size(), v);
        if (tok.empty() || res.ec != std::errc() || res.ptr != tok.data() + tok.size() ||
            !std::isfinite(v))
          fail(where + ": expected a vertex coordinate, found '" + std::string(tok.substr(0, 40)) +
               "'");
        p[k] = v;
      }
      m.points.push_back(p);
    } else if (kw == "f") {
      poly.clear();
      for (std::string_view tok = lt.token(); !tok.empty(); tok = lt.token()) {
        const std::string_view idx = tok.substr(0, tok.find('/'));
        std::int64_t i = 0;
        const auto res = std::from_chars(idx.data(), idx.data() + idx.size(), i);
        if (idx.empty() || res.ec != std::errc() || res.ptr != idx.data() + idx.size())
          fail(where + ": expected a vertex index, found '" + std::string(tok.substr(0, 40)) + "'");
        // Negative indices count back from the last vertex read so far.
        if (i < 0) i = static_cast<std::int64_t>(m.points.size()) + 1 + i;
        poly.push_back(checked_index(i, m.points.size(), where));
      }
      if (poly.size() < 3) fail(where + ": a face needs at least 3 vertices");
      fanned = fanned || poly.size() > 3;
      for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
        m.triangles.push_back({poly[0], poly[k], poly[k + 1]});
        m.triangle_face.push_back(face);
      }
    } else if (kw == "g" || kw == "o") {
      std::string_view name = lt.rest_of_line();
      grouped = true;
      geom::Id id = -1;
      if (name.starts_with("face_")) {
        const auto res = std::from_chars(name.data() + 5, name.data() + name.size(), id);
        if (res.ec != std::errc() || res.ptr != name.data() + name.size() || id < 0) id = -1;
      }
      if (id < 0) {
        auto it = groups.find(name);
        if (it == groups.end())
          it = groups.emplace(std::string(name), static_cast<geom::Id>(groups.size())).first;
        id = it->second;
      }
      face = id;
    }
    // vn, vt, s, usemtl, mtllib, comments: not part of the surface mesh.
  }
  if (fanned) r.warnings.push_back("polygons with more than 3 vertices were split into triangles");
  r.has_face_ids = grouped;
  classify_from_elements(m, {});
}

// ----------------------------------------------------------------------------- PLY

enum class PlyType { I8, U8, I16, U16, I32, U32, F32, F64 };

std::optional<PlyType> ply_type(std::string_view s) {
  if (s == "char" || s == "int8") return PlyType::I8;
  if (s == "uchar" || s == "uint8") return PlyType::U8;
  if (s == "short" || s == "int16") return PlyType::I16;
  if (s == "ushort" || s == "uint16") return PlyType::U16;
  if (s == "int" || s == "int32") return PlyType::I32;
  if (s == "uint" || s == "uint32") return PlyType::U32;
  if (s == "float" || s == "float32") return PlyType::F32;
  if (s == "double" || s == "float64") return PlyType::F64;
  return std::nullopt;
}

struct PlyProperty {
  std::string name;
  PlyType type = PlyType::F32;
  bool list = false;
  PlyType count_type = PlyType::U8;
};

struct PlyElement {
  std::string name;
  std::int64_t count = 0;
  std::vector<PlyProperty> props;
};

double ply_value(PlyType ty, Text* t, Bytes* b) {
  if (t) return t->real("a PLY value");
  switch (ty) {
    case PlyType::I8:
      return b->get<std::int8_t>("a PLY value");
    case PlyType::U8:
      return b->get<std::uint8_t>("a PLY value");
    case PlyType::I16:
      return b->get<std::int16_t>("a PLY value");
    case PlyType::U16:
      return b->get<std::uint16_t>("a PLY value");
    case PlyType::I32:
      return b->get<std::int32_t>("a PLY value");
    case PlyType::U32:
      return b->get<std::uint32_t>("a PLY value");
    case PlyType::F32:
      return b->get<float>("a PLY value");
    case PlyType::F64:
      return b->get<double>("a PLY value");
  }
  return 0;
}

void read_ply(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  Text t(data.data(), data.data() + data.size());
  if (t.rest_of_line() != "ply") fail("line 1: not a PLY file (no 'ply' magic)");
  std::string format;
  std::vector<PlyElement> elements;
  while (true) {
    if (t.pos() >= t.end()) fail(t.where() + ": file ends inside the header (truncated?)");
    const int ln = t.line();
    const std::string_view l = t.rest_of_line();
    const std::string where = "line " + std::to_string(ln);
    Text lt(l.data(), l.data() + l.size());
    const std::string_view kw = lt.token();
    if (kw == "end_header") break;
    if (kw == "format") {
      format = std::string(lt.token());
      if (format != "ascii" && format != "binary_little_endian" && format != "binary_big_endian")
        fail(where + ": unknown PLY format '" + format + "'");
    } else if (kw == "element") {
      PlyElement e;
      e.name = std::string(lt.token());
      e.count = lt.count("an element count");
      elements.push_back(std::move(e));
    } else if (kw == "property") {
      if (elements.empty()) fail(where + ": property before any element");
      PlyProperty p;
      std::string_view ty = lt.token();
      if (ty == "list") {
        p.list = true;
        const auto ct = ply_type(lt.token());
        if (!ct) fail(where + ": bad list count type");
        p.count_type = *ct;
        ty = lt.token();
      }
      const auto vt = ply_type(ty);
      if (!vt) fail(where + ": unknown property type '" + std::string(ty) + "'");
      p.type = *vt;
      p.name = std::string(lt.token());
      elements.back().props.push_back(std::move(p));
    } else if (kw != "comment" && kw != "obj_info" && !kw.empty()) {
      fail(where + ": unknown PLY header keyword '" + std::string(kw.substr(0, 40)) + "'");
    }
  }
  if (format.empty()) fail(t.where() + ": the header has no format line");
  const bool ascii = format == "ascii";
  r.binary = !ascii;
  Bytes bytes(data.data(), t.pos(), data.data() + data.size(), format == "binary_big_endian");
  Text* tp = ascii ? &t : nullptr;
  Bytes* bp = ascii ? nullptr : &bytes;
  auto where = [&] { return ascii ? t.where() : bytes.where(); };
  bool have_vertices = false;
  for (const PlyElement& e : elements) {
    const bool is_vertex = e.name == "vertex", is_face = e.name == "face";
    if (e.props.empty()) {
      // An element without properties holds no data whatever its count: looping over a
      // count of 1e9 read nothing and took minutes (fuzz_mesh_ply). Vertices and faces
      // without properties cannot be read.
      if ((is_vertex || is_face) && e.count > 0)
        fail(where() + ": element '" + e.name + "' has " + std::to_string(e.count) +
             " entries but no properties");
      have_vertices = have_vertices || is_vertex;
      continue;
    }
    for (std::int64_t i = 0; i < e.count; ++i) {
      geom::Vec3 p(0.0);
      std::vector<NodeId> poly;
      geom::Id face = 0;
      for (const PlyProperty& pr : e.props) {
        if (pr.list) {
          const double n = ply_value(pr.count_type, tp, bp);
          if (!(n >= 0 && n <= 1e6)) fail(where() + ": bad list length");
          for (int k = 0; k < static_cast<int>(n); ++k) {
            const double v = ply_value(pr.type, tp, bp);
            if (is_face && (pr.name == "vertex_indices" || pr.name == "vertex_index")) {
              if (!(v >= 0 && v < static_cast<double>(m.points.size())))
                fail(where() + ": vertex index " + shortest(v) + " out of range");
              poly.push_back(static_cast<NodeId>(v));
            }
          }
        } else {
          const double v = ply_value(pr.type, tp, bp);
          if (!std::isfinite(v)) fail(where() + ": a non-finite value");
          if (is_vertex && pr.name == "x") p.x = v;
          if (is_vertex && pr.name == "y") p.y = v;
          if (is_vertex && pr.name == "z") p.z = v;
          if (is_face && pr.name == "face_id") {
            // Checked before the cast: a double beyond int's range converts with
            // undefined behaviour (fuzz_mesh_ply found 2e24).
            if (!(v >= 0 && v <= std::numeric_limits<geom::Id>::max() && v == std::floor(v)))
              fail(where() + ": face_id " + shortest(v) + " is not a face number (0 to " +
                   std::to_string(std::numeric_limits<geom::Id>::max()) + ")");
            face = static_cast<geom::Id>(v);
            r.has_face_ids = true;
          }
        }
      }
      if (is_vertex) m.points.push_back(p);
      if (is_face) {
        if (!have_vertices) fail(where() + ": faces before vertices");
        if (poly.size() < 3) fail(where() + ": a face needs at least 3 vertices");
        for (std::size_t k = 1; k + 1 < poly.size(); ++k) {
          m.triangles.push_back({poly[0], poly[k], poly[k + 1]});
          m.triangle_face.push_back(face);
        }
      }
    }
    have_vertices = have_vertices || is_vertex;
  }
  classify_from_elements(m, {});
}

// ----------------------------------------------------------------------------- Draco

void read_drc(const std::string& data, MeshReadResult& r) {
  bool face_ids = false;
  if (std::string why = detail::decode_drc(data.data(), data.size(), r.mesh, face_ids);
      !why.empty())
    fail(why);
  r.binary = true;
  r.has_face_ids = face_ids;
  classify_from_elements(r.mesh, {});
}

bool readable(MeshFormat f) {
  return f == MeshFormat::Msh41 || f == MeshFormat::Msh22 || f == MeshFormat::Medit ||
         f == MeshFormat::Meshb || f == MeshFormat::Stl || f == MeshFormat::Obj ||
         f == MeshFormat::Ply || f == MeshFormat::Drc;
}

}  // namespace

std::string readable_mesh_extensions() {
  return ".msh, .mesh, .meshb, .stl, .obj, .ply, .drc";
}

MeshReadResult read_mesh(const std::string& path, const MeshReadOptions& opts) {
  MeshReadResult r;
  const std::optional<MeshFormat> fmt = opts.format ? opts.format : format_from_path(path);
  if (!fmt || !readable(*fmt)) {
    r.error = path + ": not a mesh format read here (known: " + readable_mesh_extensions() + ")";
    return r;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    r.error = path + ": is a directory";
    return r;
  }
  std::string data;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      r.error = path + ": cannot open: " + std::strerror(errno);
      return r;
    }
    // One read of the whole file (meshes reach hundreds of MB; a character iterator is
    // several times slower).
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size > 0) {
      data.resize(static_cast<std::size_t>(size));
      in.read(data.data(), size);
    }
    if (in.bad() || (size > 0 && in.gcount() != size)) {
      r.error = path + ": read error";
      return r;
    }
  }
  return read_mesh_data(data, *fmt, path);
}

MeshReadResult read_mesh_data(const std::string& data, MeshFormat format, const std::string& path) {
  MeshReadResult r;
  if (!readable(format)) {
    r.error = path + ": not a mesh format read here (known: " + readable_mesh_extensions() + ")";
    return r;
  }
  if (data.empty()) {
    r.error = path + ": the file is empty";
    return r;
  }
  r.format = format;
  try {
    switch (format) {
      case MeshFormat::Msh41:
      case MeshFormat::Msh22:
        read_msh(data, r);
        break;
      case MeshFormat::Medit:
        read_medit_ascii(data, r);
        break;
      case MeshFormat::Meshb:
        read_meshb(data, r);
        break;
      case MeshFormat::Stl:
        read_stl(data, r);
        break;
      case MeshFormat::Obj:
        read_obj(data, r);
        break;
      case MeshFormat::Ply:
        read_ply(data, r);
        break;
      case MeshFormat::Drc:
        read_drc(data, r);
        break;
      default:
        break;
    }
  } catch (const ParseError& e) {
    r = MeshReadResult{};
    r.error = path + ": " + e.what;
    return r;
  } catch (const std::bad_alloc&) {
    r = MeshReadResult{};
    r.error = path + ": out of memory while reading (corrupt counts?)";
    return r;
  }
  if (r.mesh.triangles.empty()) {
    r = MeshReadResult{};
    r.error = path + ": no triangles in the file";
    return r;
  }
  if (r.skipped_elements > 0)
    r.warnings.push_back(std::to_string(r.skipped_elements) +
                         " elements other than points, lines and triangles were skipped");
  r.ok = true;
  return r;
}

}  // namespace uvmesh::io
