// Mesh readers other than Gmsh's (mesh_parse.h). Formats, as read here:
//  - Medit: INRIA RT-0253 (ASCII keywords); libMeshb's binary layout (int32 code 1 for
//    the byte order, int32 version, keywords with the position of the next one).
//  - STL, OBJ: as in mesh_writer_formats.cpp. PLY: Turk's header/element/property format.
#include <array>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "mesh_parse.h"

namespace uvmesh::io::detail {

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

namespace {

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

}  // namespace

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

namespace {

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

// The PLY header after the magic line, up to end_header: the format and the elements
// with their properties.
std::string read_ply_header(Text& t, std::vector<PlyElement>& elements) {
  std::string format;
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
  return format;
}

}  // namespace

void read_ply(const std::string& data, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  Text t(data.data(), data.data() + data.size());
  if (t.rest_of_line() != "ply") fail("line 1: not a PLY file (no 'ply' magic)");
  std::vector<PlyElement> elements;
  const std::string format = read_ply_header(t, elements);
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
      // count of 1e9 read nothing and took minutes (found by the PLY fuzzer). Vertices and faces
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
            // undefined behaviour (the PLY fuzzer found 2e24).
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

}  // namespace uvmesh::io::detail
