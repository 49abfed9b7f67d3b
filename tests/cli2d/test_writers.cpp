// Gmsh 2.2 and SVG writers on hand-made meshes (the Medit writer's round trip is in
// test_medit.cpp).
#include <catch2/catch.hpp>
#include <map>
#include <regex>
#include <sstream>

#include "cli2d_test_util.h"
#include "uvmesh2d/gmsh.h"
#include "uvmesh2d/medit.h"
#include "uvmesh2d/svg.h"
#include "uvmesh2d/text.h"

using namespace uvmesh::cli2d;

namespace {

// Minimal MSH 2.2 ASCII parser for the round trip: nodes and elements with their tags.
struct Msh {
  std::string version;
  std::vector<uvmesh::m2d::Vec2> nodes;
  struct Element {
    int type = 0;
    std::vector<int> tags, nodes;
  };
  std::vector<Element> elements;
};

Msh parse_msh(const std::string& text) {
  Msh m;
  std::istringstream in(text);
  std::string line;
  while (std::getline(in, line)) {
    if (line == "$MeshFormat") {
      std::getline(in, line);
      m.version = line;
      std::getline(in, line);
      REQUIRE(line == "$EndMeshFormat");
    } else if (line == "$Nodes") {
      std::size_t n = 0;
      in >> n;
      for (std::size_t i = 0; i < n; ++i) {
        std::string id, x, y, z;
        in >> id >> x >> y >> z;
        REQUIRE(id == std::to_string(i + 1));
        REQUIRE(z == "0");
        m.nodes.push_back({*text::parse_double(x), *text::parse_double(y)});
      }
      in >> line;
      REQUIRE(line == "$EndNodes");
    } else if (line == "$Elements") {
      std::size_t n = 0;
      in >> n;
      for (std::size_t i = 0; i < n; ++i) {
        Msh::Element e;
        int id = 0, ntags = 0;
        in >> id >> e.type >> ntags;
        REQUIRE(id == static_cast<int>(i + 1));
        e.tags.resize(static_cast<std::size_t>(ntags));
        for (int& t : e.tags) in >> t;
        e.nodes.resize(e.type == 1 ? 2 : 3);
        for (int& v : e.nodes) in >> v;
        m.elements.push_back(e);
      }
      in >> line;
      REQUIRE(line == "$EndElements");
    }
  }
  return m;
}

std::size_t count(const std::string& s, const std::string& what) {
  std::size_t n = 0;
  for (std::size_t p = s.find(what); p != std::string::npos; p = s.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST_CASE("gmsh: MSH 2.2 round trip of a hand-made mesh", "[cli2d][writers]") {
  uvmesh::m2d::Mesh m = cli2d_test::grid_mesh(5);
  m.vertices[4].x = 1.0 / 3.0;
  m.boundary_edges[0].marker = 0;  // physical 0, elementary 1
  m.boundary_edges[1].marker = -3;
  std::vector<int> refs = triangle_refs(m, false);
  refs[7] = 42;
  std::ostringstream out;
  write_gmsh22(out, m, refs);
  const Msh r = parse_msh(out.str());
  CHECK(r.version == "2.2 0 8");
  REQUIRE(r.nodes.size() == m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    CHECK(r.nodes[i].x == m.vertices[i].x);
    CHECK(r.nodes[i].y == m.vertices[i].y);
  }
  REQUIRE(r.elements.size() == m.boundary_edges.size() + m.triangles.size());
  for (std::size_t i = 0; i < m.boundary_edges.size(); ++i) {
    const auto& e = r.elements[i];
    CHECK(e.type == 1);
    REQUIRE(e.tags.size() == 2);
    CHECK(e.tags[0] == m.boundary_edges[i].marker);
    CHECK(e.tags[1] == (m.boundary_edges[i].marker > 0 ? m.boundary_edges[i].marker : 1));
    CHECK(e.nodes == std::vector<int>{m.boundary_edges[i].a + 1, m.boundary_edges[i].b + 1});
  }
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    const auto& e = r.elements[m.boundary_edges.size() + i];
    CHECK(e.type == 2);
    CHECK(e.tags[0] == refs[i]);
    CHECK(e.tags[1] == m.triangle_region[i] + 1);
    CHECK(e.nodes ==
          std::vector<int>{m.triangles[i][0] + 1, m.triangles[i][1] + 1, m.triangles[i][2] + 1});
  }
}

TEST_CASE("svg: one path per quality class, y up, fitted viewBox", "[cli2d][writers]") {
  uvmesh::m2d::Mesh m;
  m.vertices = {{10, 20}, {12, 20}, {10, 21}, {12, 21}};
  m.triangles = {{0, 1, 2}, {1, 3, 2}};
  m.triangle_region = {0, 0};
  m.boundary_edges = {{0, 1, 1}, {1, 3, 1}, {3, 2, 1}, {2, 0, 1}};
  SvgOptions o;
  o.quality = {1.05, 4.0};
  o.title = "a < b & c";
  std::ostringstream out;
  write_svg(out, m, o);
  const std::string s = out.str();
  CHECK_THAT(s, Catch::StartsWith("<?xml"));
  CHECK_THAT(s, Catch::EndsWith("</svg>\n"));
  // The bounding box is 2 x 1: 1000 x 500 plus margins of 20.
  CHECK_THAT(s, Catch::Contains("viewBox=\"0 0 1040.0 "));
  CHECK(count(s, "fill=\"#1a9850\" d=") == 1);  // Q 1.05: best class
  CHECK(count(s, "fill=\"#f46d43\" d=") == 1);  // Q 4: class [3, 5)
  // y up: vertex (10, 21) is at the top (Y = margin = 20), (10, 20) at the bottom (520).
  CHECK_THAT(s, Catch::Contains("M20.00 520.00 1020.00 520.00 20.00 20.00Z"));
  CHECK_THAT(s, Catch::Contains("a &lt; b &amp; c"));  // escaped title
  CHECK(count(s, "stroke=\"black\"") == 1);            // boundary path
}

TEST_CASE("svg: huge meshes drop the wireframe, then the fill", "[cli2d][writers]") {
  const uvmesh::m2d::Mesh m = cli2d_test::grid_mesh(20);  // 800 triangles
  SvgOptions o;
  o.quality.assign(m.triangles.size(), 1.2);
  o.max_wireframe_triangles = 100;
  std::ostringstream a;
  write_svg(a, m, o);
  CHECK_THAT(a.str(), !Catch::Contains("stroke=\"#202020\""));
  CHECK(count(a.str(), "Z") >= m.triangles.size());
  o.max_filled_triangles = 100;
  std::ostringstream b;
  write_svg(b, m, o);
  CHECK(count(b.str(), "Z") == 0);
  CHECK_THAT(b.str(), Catch::Contains("800 triangles: only the boundary is drawn"));
  // Size stays sane: about 40 bytes per triangle at 1 decimal.
  const uvmesh::m2d::Mesh big = cli2d_test::grid_mesh(224);  // 100352 triangles
  SvgOptions ob;
  ob.quality.assign(big.triangles.size(), 1.1);
  std::ostringstream c;
  write_svg(c, big, ob);
  CHECK(c.str().size() < 60 * big.triangles.size());
}

TEST_CASE("svg: empty mesh", "[cli2d][writers]") {
  std::ostringstream out;
  write_svg(out, uvmesh::m2d::Mesh{}, {});
  CHECK_THAT(out.str(), Catch::EndsWith("</svg>\n"));
}
