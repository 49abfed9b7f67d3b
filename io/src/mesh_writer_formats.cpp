// Writers of the whole-model surface mesh in the formats other than Gmsh's
// (mesh_formats.h). Formats, as written here:
//  - Medit: Frey, "MEDIT: an interactive mesh visualization software" (INRIA RT-0253),
//    the keyword format also read by MMG, TetGen and Gmsh (MeshVersionFormatted 2 stores
//    double-precision coordinates); .meshb its binary form.
//  - TetGen .poly / .smesh, PLY.
//  - STL: 3D Systems' StereoLithography Interface Specification (binary: 80-byte header,
//    uint32 count, 50-byte little-endian records).
//  - OBJ: Wavefront "Object Files (.obj)" appendix B1 (v, f, g statements).
//  - VTK legacy: "The VTK User's Guide", section "VTK File Formats", simple legacy
//    formats (binary data big-endian; int is 4 bytes); VTK XML UnstructuredGrid.
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "mesh_formats.h"

namespace uvmesh::io::detail {

using surface::NodeId;
using surface::SurfaceMesh;

// ----------------------------------------------------------------------------- Medit

void write_medit(Sink& out, const SurfaceMesh& m, const surface::TetMesh* vol) {
  out.put("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n");
  out.num(vol ? vol->points.size() : m.points.size());
  out.put('\n');
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    out.xyz(m.points[i]);
    out.put(' ');
    out.num(one_based(m.point_entity[i]));
    out.put('\n');
  }
  if (vol)
    for (std::size_t i = m.points.size(); i < vol->points.size(); ++i) {
      out.xyz(vol->points[i]);
      out.put(' ');
      out.num(one_based(vol->interior_point_solid[i - m.points.size()]));
      out.put('\n');
    }
  // Empty sections are left out: some readers reject a keyword followed by 0.
  if (!m.segments.empty()) {
    out.put("\nEdges\n");
    out.num(m.segments.size());
    out.put('\n');
    for (const auto& s : m.segments) out.line({one_based(s.a), one_based(s.b), one_based(s.edge)});
  }
  if (!m.triangles.empty()) {
    out.put("\nTriangles\n");
    out.num(m.triangles.size());
    out.put('\n');
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      out.line(
          {one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), one_based(m.triangle_face[t])});
    }
  }
  if (vol && !vol->tets.empty()) {
    out.put("\nTetrahedra\n");
    out.num(vol->tets.size());
    out.put('\n');
    for (std::size_t t = 0; t < vol->tets.size(); ++t) {
      const auto& tet = vol->tets[t];
      out.line({one_based(tet[0]), one_based(tet[1]), one_based(tet[2]), one_based(tet[3]),
                one_based(vol->tet_solid[t])});
    }
  }
  out.put("\nEnd\n");
}

// Binary Medit, as libMeshb writes it (version 3): int32 code 1 (the reader's byte-order
// check), int32 version, then keywords "int32 code, int64 position of the next keyword,
// [int32 count], records". Version 3 = double reals, 32-bit integers, 64-bit positions,
// so a file may pass 2 GiB.
void write_meshb(Sink& out, const SurfaceMesh& m) {
  constexpr std::int32_t kDimension = 3, kVertices = 4, kEdges = 5, kTriangles = 6, kEnd = 54;
  std::int64_t pos = 8;  // bytes written so far: the code and the version
  put_le(out, std::int32_t{1});
  put_le(out, std::int32_t{3});
  auto keyword = [&](std::int32_t code, std::int64_t payload) {
    pos += 4 + 8 + payload;
    put_le(out, code);
    put_le(out, code == kEnd ? std::int64_t{0} : pos);
  };
  keyword(kDimension, 4);
  put_le(out, std::int32_t{3});
  const auto np = static_cast<std::int64_t>(m.points.size());
  keyword(kVertices, 4 + np * (3 * 8 + 4));
  put_le(out, static_cast<std::int32_t>(np));
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    put_le(out, m.points[i].x);
    put_le(out, m.points[i].y);
    put_le(out, m.points[i].z);
    put_le(out, static_cast<std::int32_t>(one_based(m.point_entity[i])));
  }
  if (!m.segments.empty()) {
    keyword(kEdges, 4 + static_cast<std::int64_t>(m.segments.size()) * 12);
    put_le(out, static_cast<std::int32_t>(m.segments.size()));
    for (const auto& sg : m.segments)
      for (std::int64_t v : {one_based(sg.a), one_based(sg.b), one_based(sg.edge)})
        put_le(out, static_cast<std::int32_t>(v));
  }
  if (!m.triangles.empty()) {
    keyword(kTriangles, 4 + static_cast<std::int64_t>(m.triangles.size()) * 16);
    put_le(out, static_cast<std::int32_t>(m.triangles.size()));
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      for (std::int64_t v :
           {one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), one_based(m.triangle_face[t])})
        put_le(out, static_cast<std::int32_t>(v));
    }
  }
  keyword(kEnd, 0);
}

// ----------------------------------------------------------------------------- TetGen

// .poly (TetGen manual, section 5.2.2) and .smesh (5.2.3): node list with index base 1,
// then facets with boundary markers (face id + 1, so a volume mesh keeps the CAD face of
// each boundary triangle), then zero holes and zero regions. A .poly facet is a list of
// polygons; here each is one triangle.
void write_tetgen(Sink& out, const SurfaceMesh& m, bool smesh) {
  out.put(smesh ? "# uvmesh surface mesh (TetGen .smesh)\n"
                : "# uvmesh surface mesh (TetGen .poly)\n");
  out.line({static_cast<std::int64_t>(m.points.size()), 3, 0, 0});
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    out.num(one_based(i));
    out.put(' ');
    out.xyz(m.points[i]);
    out.put('\n');
  }
  out.line({static_cast<std::int64_t>(m.triangles.size()), 1});
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const std::int64_t marker = one_based(m.triangle_face[t]);
    if (smesh) {
      out.line({3, one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), marker});
    } else {
      out.line({1, 0, marker});
      out.line({3, one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
    }
  }
  out.put("0\n0\n");  // holes, regions
}

// ----------------------------------------------------------------------------- PLY

// PLY (Turk's format as in the Stanford repository): double coordinates so that binary
// and ASCII files round-trip exactly; the face list count is a uchar, indices int. The
// CAD face id is an extra face property in ASCII files only: meshio 7 (a reference
// reader here) cannot read a binary face element holding anything but the index list.
void write_ply(Sink& out, const SurfaceMesh& m, bool binary) {
  out.put(binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n");
  out.put("comment uvmesh surface mesh, face_id = CAD face\nelement vertex ");
  out.num(m.points.size());
  out.put("\nproperty double x\nproperty double y\nproperty double z\nelement face ");
  out.num(m.triangles.size());
  out.put(binary ? "\nproperty list uchar int vertex_indices\nend_header\n"
                 : "\nproperty list uchar int vertex_indices\nproperty int face_id\nend_header\n");
  for (const geom::Vec3& p : m.points) {
    if (binary) {
      put_le(out, p.x);
      put_le(out, p.y);
      put_le(out, p.z);
    } else {
      out.xyz(p);
      out.put('\n');
    }
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    if (binary) {
      put_le(out, std::uint8_t{3});
      for (NodeId v : tri) put_le(out, static_cast<std::int32_t>(v));
    } else {
      out.line({3, tri[0], tri[1], tri[2], m.triangle_face[t]});
    }
  }
}

// ----------------------------------------------------------------------------- STL

namespace {

// Unit normal of a triangle from its corners (right-hand rule), 0 for a degenerate one.
geom::Vec3 unit_normal(const SurfaceMesh& m, const std::array<NodeId, 3>& t) {
  const geom::Vec3& a = m.points[static_cast<std::size_t>(t[0])];
  const geom::Vec3 n = glm::cross(m.points[static_cast<std::size_t>(t[1])] - a,
                                  m.points[static_cast<std::size_t>(t[2])] - a);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : geom::Vec3(0.0);
}

}  // namespace

void write_stl_binary(Sink& out, const SurfaceMesh& m) {
  // The header must not start with "solid": readers take that for ASCII STL.
  char header[80];
  std::memset(header, ' ', sizeof header);
  static constexpr std::string_view kHeader = "uvmesh binary STL surface mesh";
  std::memcpy(header, kHeader.data(), kHeader.size());
  out.raw(header, sizeof header);
  put_le(out, static_cast<std::uint32_t>(m.triangles.size()));
  auto put3 = [&](const geom::Vec3& p) {
    put_le(out, static_cast<float>(p.x));
    put_le(out, static_cast<float>(p.y));
    put_le(out, static_cast<float>(p.z));
  };
  for (const auto& t : m.triangles) {
    put3(unit_normal(m, t));
    for (NodeId v : t) put3(m.points[static_cast<std::size_t>(v)]);
    put_le(out, std::uint16_t{0});  // attribute byte count
  }
}

void write_stl_ascii(Sink& out, const SurfaceMesh& m) {
  out.put("solid uvmesh\n");
  for (const auto& t : m.triangles) {
    out.put("facet normal ");
    out.xyz(unit_normal(m, t));
    out.put("\nouter loop\n");
    for (NodeId v : t) {
      out.put("vertex ");
      out.xyz(m.points[static_cast<std::size_t>(v)]);
      out.put('\n');
    }
    out.put("endloop\nendfacet\n");
  }
  out.put("endsolid uvmesh\n");
}

// ----------------------------------------------------------------------------- OBJ

void write_obj(Sink& out, const SurfaceMesh& m, const Counts& c) {
  out.put("# uvmesh surface mesh: ");
  out.num(m.points.size());
  out.put(" vertices, ");
  out.num(m.triangles.size());
  out.put(" triangles, one group per CAD face\n");
  for (const geom::Vec3& p : m.points) {
    out.put("v ");
    out.xyz(p);
    out.put('\n');
  }
  const Buckets tris = bucket(m.triangles.size(), c.faces, [&](std::size_t t) {
    return static_cast<std::size_t>(m.triangle_face[t]);
  });
  for (std::size_t f = 0; f < c.faces; ++f) {
    if (tris.size(f) == 0) continue;
    out.put("g face_");
    out.num(f);
    out.put('\n');
    tris.each(f, [&](std::size_t t) {
      const auto& tri = m.triangles[t];
      out.put("f ");
      out.line({one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
    });
  }
}

// ----------------------------------------------------------------------------- VTK

void write_vtk(Sink& out, const SurfaceMesh& m, bool binary) {
  constexpr int kVtkTriangle = 5;
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  out.put("# vtk DataFile Version 3.0\nuvmesh surface mesh\n");
  out.put(binary ? "BINARY\n" : "ASCII\n");
  out.put("DATASET UNSTRUCTURED_GRID\nPOINTS ");
  out.num(np);
  out.put(" double\n");
  for (const geom::Vec3& p : m.points) {
    if (binary) {
      put_be(out, p.x);
      put_be(out, p.y);
      put_be(out, p.z);
    } else {
      out.xyz(p);
      out.put('\n');
    }
  }
  // Every section is one integer a line in ASCII, 4-byte big-endian ints in binary.
  auto int_value = [&](std::int64_t v, char sep) {
    if (binary) {
      put_be(out, static_cast<std::int32_t>(v));
    } else {
      out.num(v);
      out.put(sep);
    }
  };
  out.put(binary ? "\nCELLS " : "CELLS ");
  out.num(nt);
  out.put(' ');
  out.num(4 * nt);
  out.put('\n');
  for (const auto& t : m.triangles) {
    int_value(3, ' ');
    int_value(t[0], ' ');
    int_value(t[1], ' ');
    int_value(t[2], '\n');
  }
  out.put(binary ? "\nCELL_TYPES " : "CELL_TYPES ");
  out.num(nt);
  out.put('\n');
  for (std::size_t t = 0; t < nt; ++t) int_value(kVtkTriangle, '\n');
  out.put(binary ? "\nCELL_DATA " : "CELL_DATA ");
  out.num(nt);
  out.put("\nSCALARS face_id int 1\nLOOKUP_TABLE default\n");
  for (geom::Id f : m.triangle_face) int_value(f, '\n');
  if (binary) out.put('\n');
}

namespace {

// VTK XML UnstructuredGrid ("VTK File Formats", XML formats): inline arrays, either
// ASCII or base64 "binary" (each array's bytes preceded by a UInt32 byte count, the count
// and the data encoded as one base64 stream, as VTK's writer does without compression).
class Base64 {
 public:
  explicit Base64(Sink& out) : out_(out) {}
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      acc_[k_++] = b[i];
      if (k_ == 3) emit(3);
    }
  }
  template <class T>
  void le(T v) {
    auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
    if constexpr (std::endian::native == std::endian::big) std::reverse(bits.begin(), bits.end());
    bytes(bits.data(), bits.size());
  }
  void finish() {
    if (k_ > 0) emit(k_);
  }

 private:
  void emit(int n) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = n; i < 3; ++i) acc_[i] = 0;
    const unsigned v = (unsigned{acc_[0]} << 16) | (unsigned{acc_[1]} << 8) | acc_[2];
    char q[4] = {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63],
                 n > 1 ? kAlphabet[(v >> 6) & 63] : '=', n > 2 ? kAlphabet[v & 63] : '='};
    out_.raw(q, 4);
    k_ = 0;
  }
  Sink& out_;
  unsigned char acc_[3] = {0, 0, 0};
  int k_ = 0;
};

}  // namespace

void write_vtu(Sink& out, const SurfaceMesh& m, bool binary, const surface::TetMesh* vol) {
  const std::vector<geom::Vec3>& points = vol ? vol->points : m.points;
  const std::size_t np = points.size(), nt = m.triangles.size();
  // Cells: the triangles, then the tetrahedra (with a volume mesh).
  const std::size_t nc = nt + (vol ? vol->tets.size() : 0);
  out.put(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n<Piece "
      "NumberOfPoints=\"");
  out.num(np);
  out.put("\" NumberOfCells=\"");
  out.num(nc);
  out.put("\">\n");
  // One array: n values produced by value(i, sink) in ASCII or by value(i, base64).
  auto array = [&](const char* type, const char* name, int components, std::size_t n,
                   std::size_t value_bytes, auto ascii_value, auto binary_value) {
    out.put("<DataArray type=\"");
    out.put(type);
    out.put("\" Name=\"");
    out.put(name);
    out.put("\" NumberOfComponents=\"");
    out.num(components);
    out.put(binary ? "\" format=\"binary\">\n" : "\" format=\"ascii\">\n");
    if (binary) {
      Base64 b(out);
      b.le(static_cast<std::uint32_t>(n * value_bytes));
      for (std::size_t i = 0; i < n; ++i) binary_value(i, b);
      b.finish();
      out.put('\n');
    } else {
      for (std::size_t i = 0; i < n; ++i) ascii_value(i);
    }
    out.put("</DataArray>\n");
  };
  out.put("<Points>\n");
  array(
      "Float64", "Points", 3, np, 24,
      [&](std::size_t i) {
        out.xyz(points[i]);
        out.put('\n');
      },
      [&](std::size_t i, Base64& b) {
        b.le(points[i].x);
        b.le(points[i].y);
        b.le(points[i].z);
      });
  out.put("</Points>\n<Cells>\n");
  // The connectivity array is written value by value so that triangles (3) and
  // tetrahedra (4) share it; an ASCII line per cell as before.
  const std::size_t n_conn = 3 * nt + 4 * (nc - nt);
  auto cell_nodes = [&](std::size_t c) -> std::vector<NodeId> {
    if (c < nt) return {m.triangles[c].begin(), m.triangles[c].end()};
    const auto& tet = vol->tets[c - nt];
    return {tet.begin(), tet.end()};
  };
  auto offset = [&](std::size_t c) {
    return static_cast<std::int64_t>(c < nt ? 3 * (c + 1) : 3 * nt + 4 * (c + 1 - nt));
  };
  if (binary) {
    array(
        "Int32", "connectivity", 1, n_conn, 4, [](std::size_t) {},
        [&](std::size_t k, Base64& b) {
          const NodeId v = k < 3 * nt ? m.triangles[k / 3][k % 3]
                                      : vol->tets[(k - 3 * nt) / 4][(k - 3 * nt) % 4];
          b.le(static_cast<std::int32_t>(v));
        });
  } else {
    array(
        "Int32", "connectivity", 1, nc, 0,
        [&](std::size_t c) {
          const std::vector<NodeId> v = cell_nodes(c);
          if (v.size() == 3)
            out.line({v[0], v[1], v[2]});
          else
            out.line({v[0], v[1], v[2], v[3]});
        },
        [](std::size_t, Base64&) {});
  }
  array(
      "Int32", "offsets", 1, nc, 4, [&](std::size_t c) { out.line({offset(c)}); },
      [&](std::size_t c, Base64& b) { b.le(static_cast<std::int32_t>(offset(c))); });
  constexpr std::uint8_t kVtkTriangle = 5, kVtkTetra = 10;
  array(
      "UInt8", "types", 1, nc, 1,
      [&](std::size_t c) { out.line({c < nt ? kVtkTriangle : kVtkTetra}); },
      [&](std::size_t c, Base64& b) { b.le(c < nt ? kVtkTriangle : kVtkTetra); });
  out.put("</Cells>\n<CellData Scalars=\"face_id\">\n");
  auto face_of = [&](std::size_t c) { return c < nt ? m.triangle_face[c] : geom::kNone; };
  array(
      "Int32", "face_id", 1, nc, 4, [&](std::size_t c) { out.line({face_of(c)}); },
      [&](std::size_t c, Base64& b) { b.le(static_cast<std::int32_t>(face_of(c))); });
  if (vol) {
    auto solid_of = [&](std::size_t c) { return c < nt ? geom::kNone : vol->tet_solid[c - nt]; };
    array(
        "Int32", "solid_id", 1, nc, 4, [&](std::size_t c) { out.line({solid_of(c)}); },
        [&](std::size_t c, Base64& b) { b.le(static_cast<std::int32_t>(solid_of(c))); });
  }
  out.put("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

}  // namespace uvmesh::io::detail
