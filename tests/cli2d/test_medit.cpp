// Medit .mesh / .sol readers (background size fields) and the .mesh writer round trip.
#include <catch2/catch.hpp>
#include <sstream>

#include "cli2d_test_util.h"
#include "uvmesh2d/medit.h"

using namespace uvmesh::cli2d;

namespace {

MeditRead mesh_of(const std::string& text) {
  std::istringstream in(text);
  return parse_medit_mesh(in, "bg.mesh");
}
SolRead sol_of(const std::string& text, std::int64_t nv = -1) {
  std::istringstream in(text);
  return parse_medit_sol(in, "bg.sol", nv);
}
std::string mesh_error(const std::string& text) {
  MeditRead r = mesh_of(text);
  REQUIRE_FALSE(r.ok());
  return r.error->str();
}
std::string sol_error(const std::string& text, std::int64_t nv = -1) {
  SolRead r = sol_of(text, nv);
  REQUIRE_FALSE(r.ok());
  return r.error->str();
}

const char* kHead = "MeshVersionFormatted 2\nDimension 2\n";

}  // namespace

TEST_CASE("medit: 2D mesh with comments, skipped sections and edges", "[cli2d][medit]") {
  MeditRead r = mesh_of(
      "# background\n"
      "MeshVersionFormatted 1\n"
      "Dimension\n2\n"
      "Vertices 4\n"
      "0 0 1\n1 0 2\n1 1 3\n0 1 4   # last vertex\n"
      "Corners 2 1 3\n"
      "Triangles\n2\n"
      "1 2 3 10\n"
      "1 3 4 20\n"
      "Edges 1\n1 2 5\n"
      "RequiredVertices 1 2\n"
      "End\n"
      "anything after End is ignored\n");
  REQUIRE(r.ok());
  const MeditMesh2& m = r.mesh;
  CHECK(m.version == 1);
  REQUIRE(m.vertices.size() == 4);
  CHECK(m.vertices[2].x == 1);
  CHECK(m.vertex_refs == std::vector<int>{1, 2, 3, 4});
  REQUIRE(m.triangles.size() == 2);
  CHECK(m.triangles[1] == std::array<int, 3>{0, 2, 3});
  CHECK(m.triangle_refs == std::vector<int>{10, 20});
  CHECK(m.triangle_lines == std::vector<int>{13, 14});
  REQUIRE(m.edges.size() == 1);
  CHECK(m.edge_refs[0] == 5);
}

TEST_CASE("medit: Dimension 3 keeps x and y", "[cli2d][medit]") {
  MeditRead r = mesh_of(
      "MeshVersionFormatted 2\nDimension 3\nVertices 3\n0 0 7 0\n1 0 7 0\n0 1 7 0\nTriangles 1\n1 "
      "2 3 0\nEnd\n");
  REQUIRE(r.ok());
  CHECK(r.mesh.dimension == 3);
  CHECK(r.mesh.vertices[1].x == 1);
  CHECK(r.mesh.vertices[1].y == 0);
}

TEST_CASE("medit: mesh errors carry file and line", "[cli2d][medit][errors]") {
  CHECK(mesh_error("Dimension 2\nVertices 0\n") ==
        "bg.mesh:2: not a Medit mesh: MeshVersionFormatted is missing");
  CHECK(mesh_error(std::string(kHead) + "Vertices 2\n0 0 0\n1 0 0\nTriangles 1\n1 2 3 0\n") ==
        "bg.mesh:7: triangle 1 vertex 3 is 3, but there are 2 vertices (numbered 1 to 2)");
  CHECK(mesh_error(std::string(kHead) + "Vertices 1\n0 nan 0\n") ==
        "bg.mesh:4: vertex 1 y is 'nan'; numbers must be finite");
  CHECK(mesh_error(std::string(kHead) + "Vertices 2\n0 0 0\n") ==
        "bg.mesh:4: unexpected end of file: expected vertex 2 x");
  CHECK(mesh_error(std::string(kHead) + "Triangles 0\n") == "bg.mesh:3: Triangles before Vertices");
  CHECK_THAT(mesh_error(std::string(kHead) + "Tetrahedra 0\n"),
             Catch::StartsWith("bg.mesh:3: unsupported keyword 'Tetrahedra'"));
  CHECK(mesh_error("MeshVersionFormatted 2\nDimension 4\n") ==
        "bg.mesh:2: Dimension must be 2 (or 3 with z ignored), found 4");
  CHECK(mesh_error(std::string(kHead) + "Vertices -1\n") ==
        "bg.mesh:3: number of vertices is out of range (-1)");
  CHECK(read_medit_mesh("/nonexistent/bg.mesh").error->str() ==
        "/nonexistent/bg.mesh: cannot open the file for reading");
  CHECK_THAT(read_medit_mesh("x.meshb").error->message, Catch::Contains("binary"));
}

TEST_CASE("medit: .sol with a metric, a size, and several fields", "[cli2d][medit]") {
  SolRead t = sol_of(std::string(kHead) + "SolAtVertices\n2\n1 3\n1 0 1\n4 1 9\nEnd\n", 2);
  REQUIRE(t.ok());
  CHECK(t.sol.type == MeditSol::Type::Tensor);
  CHECK(t.sol.values == std::vector<double>{1, 0, 1, 4, 1, 9});
  CHECK(t.sol.lines == std::vector<int>{6, 7});

  SolRead s = sol_of(std::string(kHead) + "SolAtVertices 3 1 1\n0.5\n0.25\n2e-3\n");
  REQUIRE(s.ok());
  CHECK(s.sol.type == MeditSol::Type::Scalar);
  CHECK(s.sol.values == std::vector<double>{0.5, 0.25, 2e-3});

  // A vector field first, then a metric: the metric is kept, the vector skipped.
  SolRead v = sol_of(std::string(kHead) + "SolAtVertices 2 2 2 3\n9 9 1 0 1\n9 9 2 0 2\n");
  REQUIRE(v.ok());
  CHECK(v.sol.type == MeditSol::Type::Tensor);
  CHECK(v.sol.values == std::vector<double>{1, 0, 1, 2, 0, 2});
}

TEST_CASE("medit: .sol errors carry file and line", "[cli2d][medit][errors]") {
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 2 1 3\n1 0 1\n1 2 1\n") ==
        "bg.sol:5: vertex 2: the metric (m11 m12 m22) = (1 2 1) is not positive definite");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 2 1 1\n0.1\n\n-0.1\n") ==
        "bg.sol:6: vertex 2: the size must be > 0, found -0.1");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 2 1 1\n0.1\n0\n") ==
        "bg.sol:5: vertex 2: the size must be > 0, found 0");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 2 1 1\n0.1\ninf\n") ==
        "bg.sol:5: vertex 2 value 1 is 'inf'; numbers must be finite");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices\n3\n1 1\n0.1 0.1 0.1\n", 4) ==
        "bg.sol:4: the solution has values at 3 vertices, but the background mesh has 4");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 1 1 5\n1\n") ==
        "bg.sol:3: field type must be 1 (scalar), 2 (vector) or 3 (symmetric tensor), found 5");
  CHECK(sol_error(std::string(kHead) + "SolAtVertices 1 1 2\n1 2\n") ==
        "bg.sol:3: no size (type 1) or metric (type 3) field: only vectors");
  CHECK_THAT(sol_error(std::string(kHead) + "SolAtTriangles 1 1 1\n1\n"),
             Catch::Contains("only SolAtVertices"));
  CHECK(sol_error("MeshVersionFormatted 2\nDimension 3\n") ==
        "bg.sol:2: Dimension must be 2 for a 2D size field, found 3");
  CHECK(sol_error(std::string(kHead) + "End\n") == "bg.sol:3: no SolAtVertices section");
}

TEST_CASE("medit: the bundled background files read and match", "[cli2d][medit]") {
  MeditRead m = read_medit_mesh(cli2d_test::sample("bg_square.mesh"));
  REQUIRE(m.ok());
  CHECK(m.mesh.vertices.size() == 289);
  CHECK(m.mesh.triangles.size() == 512);
  const auto nv = static_cast<std::int64_t>(m.mesh.vertices.size());
  SolRead t = read_medit_sol(cli2d_test::sample("bg_square.sol"), nv);
  REQUIRE(t.ok());
  CHECK(t.sol.type == MeditSol::Type::Tensor);
  SolRead s = read_medit_sol(cli2d_test::sample("bg_square_h.sol"), nv);
  REQUIRE(s.ok());
  CHECK(s.sol.type == MeditSol::Type::Scalar);
}

TEST_CASE("medit: write_medit then read back is exact", "[cli2d][medit][writers]") {
  uvmesh::m2d::Mesh m = cli2d_test::grid_mesh(7);  // coordinates i/7: not exact in decimal
  m.vertices[9].x = 0.1 + 0.2;                     // 0.30000000000000004
  m.vertices[10].y = -1e-300;
  std::vector<int> refs(m.triangles.size());
  for (std::size_t i = 0; i < refs.size(); ++i) refs[i] = static_cast<int>(i % 5) - 2;
  std::ostringstream out;
  write_medit(out, m, refs);
  const std::string text = out.str();
  CHECK_THAT(text, Catch::StartsWith("MeshVersionFormatted 2\nDimension 2\n"));
  CHECK_THAT(text, Catch::EndsWith("End\n"));
  MeditRead r = mesh_of(text);
  REQUIRE(r.ok());
  REQUIRE(r.mesh.vertices.size() == m.vertices.size());
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    CHECK(r.mesh.vertices[i].x == m.vertices[i].x);  // bit-exact
    CHECK(r.mesh.vertices[i].y == m.vertices[i].y);
  }
  CHECK(r.mesh.vertex_refs == m.vertex_markers);
  REQUIRE(r.mesh.triangles.size() == m.triangles.size());
  for (std::size_t i = 0; i < m.triangles.size(); ++i) CHECK(r.mesh.triangles[i] == m.triangles[i]);
  CHECK(r.mesh.triangle_refs == refs);
  REQUIRE(r.mesh.edges.size() == m.boundary_edges.size());
  for (std::size_t i = 0; i < m.boundary_edges.size(); ++i) {
    CHECK(r.mesh.edges[i][0] == m.boundary_edges[i].a);
    CHECK(r.mesh.edges[i][1] == m.boundary_edges[i].b);
    CHECK(r.mesh.edge_refs[i] == m.boundary_edges[i].marker);
  }
}

TEST_CASE("medit: an empty mesh writes and reads", "[cli2d][medit][writers]") {
  std::ostringstream out;
  write_medit(out, uvmesh::m2d::Mesh{}, {});
  MeditRead r = mesh_of(out.str());
  REQUIRE(r.ok());
  CHECK(r.mesh.vertices.empty());
  CHECK(r.mesh.triangles.empty());
}

TEST_CASE("medit: triangle references", "[cli2d][medit][writers]") {
  uvmesh::m2d::Mesh m = cli2d_test::square_mesh();
  std::string warning;
  CHECK(triangle_refs(m, true, &warning) == std::vector<int>{7, 8});  // regional attributes
  CHECK(warning.empty());
  CHECK(triangle_refs(m, false, &warning) == std::vector<int>{1, 2});  // component + 1
  m.triangle_attribute = {7, 8.5};
  CHECK(triangle_refs(m, true, &warning) == std::vector<int>{1, 2});
  CHECK_THAT(warning, Catch::Contains("not all integers"));
}
