// Private to uvmesh::io's mesh readers: the two cursors over a file read into memory --
// Text (tokens with line numbers) and Bytes (fixed-size binary values with byte offsets),
// both throwing ParseError, caught once in read_mesh_data -- the helpers every format
// shares, and the format readers (Gmsh in mesh_reader_gmsh.cpp, the others in
// mesh_reader_formats.cpp).
#pragma once

#include <algorithm>
#include <bit>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

#include "uvmesh/io/mesh_reader.h"

namespace uvmesh::io::detail {

using surface::NodeId;
using surface::SurfaceMesh;

struct ParseError {
  std::string what;
};

[[noreturn]] inline void fail(std::string what) {
  throw ParseError{std::move(what)};
}

// std::byteswap is C++23.
inline std::int32_t byteswap32(std::int32_t v) {
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

inline NodeId checked_index(std::int64_t one_based, std::size_t np, const std::string& where) {
  if (one_based < 1 || static_cast<std::size_t>(one_based) > np)
    fail(where + ": vertex index " + std::to_string(one_based) + " is out of range 1.." +
         std::to_string(np));
  return static_cast<NodeId>(one_based - 1);
}

// A count read from a file sizes a reservation only up to a bound: a corrupt count must
// give "file ends" at the data, not an allocation of gigabytes first.
inline std::size_t bounded(std::int64_t n) {
  return static_cast<std::size_t>(std::clamp<std::int64_t>(n, 0, 1 << 20));
}

// A number read from a file, for a message: the shortest form that reads back the same
// (std::to_chars). Not a cast to an integer: a value beyond long long's range would make
// that cast undefined (the PLY fuzzer found a vertex index of 8.9e19).
inline std::string shortest(double v) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

inline geom::Id entity_id(std::int64_t tag) {
  return tag >= 1 ? static_cast<geom::Id>(tag - 1) : 0;
}

// Classification from the elements (mesh_reader.h): vertices of point elements, nodes of
// segments, then the face of the first triangle; unused points on face 0.
inline void classify_from_elements(SurfaceMesh& m,
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

// ----------------------------------------------------------------------------- readers
// Each fills r.mesh (and r's format details) from the whole file's bytes, or throws
// ParseError.

void read_msh(const std::string& data, MeshReadResult& r);  // 4.1 and 2.2
void read_medit_ascii(const std::string& data, MeshReadResult& r);
void read_meshb(const std::string& data, MeshReadResult& r);
void read_stl(const std::string& data, MeshReadResult& r);
void read_obj(const std::string& data, MeshReadResult& r);
void read_ply(const std::string& data, MeshReadResult& r);

}  // namespace uvmesh::io::detail
