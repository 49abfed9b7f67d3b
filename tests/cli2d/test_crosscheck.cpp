// The reference readers (meshio, and gmsh's python API) open what uvmesh2d writes and see
// the same counts. UVMESH_CLI2D_PYTHON (CMake cache, /usr/bin/python3 by default) must
// import both: scripts/install-deps.sh installs them; without them the test fails.
#include <catch2/catch.hpp>
#include <cstdlib>
#include <nlohmann/json.hpp>
#include <sstream>

#include "cli2d_test_util.h"
#include "uvmesh2d/medit.h"

using cli2d_test::quote;

TEST_CASE("crosscheck: meshio and gmsh read the .mesh and .msh files with the same counts",
          "[cli2d][crosscheck]") {
  cli2d_test::ScratchDir dir("crosscheck");
  for (const std::string sample : {"square_hole.poly", "two_regions.poly", "key.poly"}) {
    const std::string mesh = dir / "o.mesh", msh = dir / "o.msh";
    const auto r = cli2d_test::run_uvmesh2d(dir, quote(cli2d_test::sample(sample)) +
                                                     " --metric-fn linear:0.02,0.06 -q -o " +
                                                     quote(mesh) + " -o " + quote(msh));
    INFO(sample << ": " << r.err);
    REQUIRE(r.status == 0);
    const auto ours = uvmesh::cli2d::read_medit_mesh(mesh);
    REQUIRE(ours.ok());
    const std::size_t nv = ours.mesh.vertices.size(), nt = ours.mesh.triangles.size(),
                      ne = ours.mesh.edges.size();
    long tri_ref_sum = 0, edge_ref_sum = 0;
    for (int v : ours.mesh.triangle_refs) tri_ref_sum += v;
    for (int v : ours.mesh.edge_refs) edge_ref_sum += v;

    const std::string probe = quote(UVMESH_CLI2D_PYTHON) + " -c \"import meshio, gmsh\"";
    INFO(UVMESH_CLI2D_PYTHON " cannot import meshio and gmsh: run scripts/install-deps.sh");
    REQUIRE(std::system(probe.c_str()) == 0);
    const std::string json_out = dir / "counts.json";
    const std::string cmd = quote(UVMESH_CLI2D_PYTHON) + " " +
                            quote(std::string(UVMESH_SOURCE_DIR) + "/tests/cli2d/mesh_counts.py") +
                            " " + quote(mesh) + " " + quote(msh) + " >" + quote(json_out) + " 2>&1";
    const int rc = std::system(cmd.c_str());
    const std::string text = cli2d_test::read_file(json_out);
    INFO("mesh_counts.py output: " << text);
    REQUIRE(rc == 0);
    // gmsh may print before the JSON line: parse the last non-empty line.
    std::string last;
    std::istringstream lines(text);
    for (std::string l; std::getline(lines, l);)
      if (!l.empty()) last = l;
    const auto j = nlohmann::json::parse(last);
    for (const std::string& f : {mesh, msh}) {
      INFO(f);
      const auto& mi = j[f]["meshio"];
      CHECK(mi["points"] == nv);
      CHECK(mi["triangle"] == nt);
      CHECK(mi["line"] == ne);
      CHECK(mi["triangle_ref_sum"] == tri_ref_sum);
      CHECK(mi["line_ref_sum"] == edge_ref_sum);
      const auto& g = j[f]["gmsh"];
      CHECK(g["nodes"] == nv);
      CHECK(g["triangle"] == nt);
      CHECK(g["line"] == ne);
    }
  }
}
