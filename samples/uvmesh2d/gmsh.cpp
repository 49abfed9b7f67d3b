#include "uvmesh2d/gmsh.h"

#include "uvmesh2d/text.h"

namespace uvmesh::cli2d {

void write_gmsh22(std::ostream& out, const m2d::Mesh& m, const std::vector<int>& tri_refs) {
  std::string b;
  b.reserve(1 << 20);
  auto flush = [&](bool force) { text::flush_buffer(out, b, force); };
  b += "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n";
  text::append_int(b, static_cast<std::int64_t>(m.vertices.size()));
  b += '\n';
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    text::append_int(b, static_cast<std::int64_t>(i) + 1);
    b += ' ';
    text::append_double(b, m.vertices[i].x);
    b += ' ';
    text::append_double(b, m.vertices[i].y);
    b += " 0\n";
    flush(false);
  }
  b += "$EndNodes\n$Elements\n";
  text::append_int(b, static_cast<std::int64_t>(m.boundary_edges.size() + m.triangles.size()));
  b += '\n';
  std::int64_t id = 1;
  for (const m2d::BoundaryEdge& e : m.boundary_edges) {
    text::append_int(b, id++);
    b += " 1 2 ";
    text::append_int(b, e.marker);
    b += ' ';
    text::append_int(b, e.marker > 0 ? e.marker : 1);
    b += ' ';
    text::append_int(b, e.a + 1);
    b += ' ';
    text::append_int(b, e.b + 1);
    b += '\n';
    flush(false);
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    text::append_int(b, id++);
    b += " 2 2 ";
    text::append_int(b, i < tri_refs.size() ? tri_refs[i] : 0);
    b += ' ';
    text::append_int(b, i < m.triangle_region.size() ? m.triangle_region[i] + 1 : 1);
    for (m2d::VertId v : m.triangles[i]) {
      b += ' ';
      text::append_int(b, v + 1);
    }
    b += '\n';
    flush(false);
  }
  b += "$EndElements\n";
  flush(true);
}

}  // namespace uvmesh::cli2d
