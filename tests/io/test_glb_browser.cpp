// The .glb output in a real browser: headless Chromium loads it with three.js's GLTFLoader
// and DRACOLoader (tests/browser: index.html, glb_in_browser.py; three.js installed from
// npm by tests/browser/install.sh, which scripts/install-deps.sh runs). The page reports
// the meshes, triangles and vertices it decoded; a PNG screenshot is saved beside the test
// binary (glb_browser_cube.png) for a person to look at.
#include <catch2/catch.hpp>
#include <set>

#include "mesh_test_util.h"

using namespace uvmesh_test;

namespace {

// Vertices the writer emits: one per (CAD face, node) used by a triangle.
long split_vertices(const surface::SurfaceMesh& m) {
  std::set<std::pair<geom::Id, surface::NodeId>> seen;
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (surface::NodeId v : m.triangles[t]) seen.emplace(m.triangle_face[t], v);
  return static_cast<long>(seen.size());
}

}  // namespace

TEST_CASE("glb: three.js in headless Chromium loads the Draco-compressed .glb",
          "[io][glb][browser]") {
  TempDir dir("glb_browser");
  const Cube cube = make_cube(6);
  const std::string script = std::string(UVMESH_SOURCE_DIR) + "/tests/browser/glb_in_browser.py";
  struct Case {
    const char* name;
    io::GlbGroups groups;
    long meshes;
  };
  for (const Case& c : {Case{"one mesh per solid", io::GlbGroups::Solid, 1},
                        Case{"one mesh per face", io::GlbGroups::Face, 6}}) {
    SECTION(c.name) {
      io::WriteOptions o;
      o.glb_groups = c.groups;
      const std::string glb = dir.file("cube.glb");
      write_ok(cube.mesh, &cube.model, glb, o);
      const std::string png = std::string(UVMESH_BINARY_DIR) + "/glb_browser_cube" +
                              (c.groups == io::GlbGroups::Face ? "_faces" : "") + ".png";
      std::error_code ec;
      fs::remove(png, ec);
      const Run r =
          run(python() + " " + quoted(script) + " " + quoted(glb) + " --screenshot " + quoted(png));
      INFO(r.out);
      REQUIRE(r.status == 0);
      Reading page;
      std::istringstream in(r.out);
      for (std::string l; std::getline(in, l);)
        if (!l.empty() && l[0] == '@')
          page.lines.emplace(l.substr(0, l.find(' ')), l.substr(l.find(' ') + 1));
      CHECK(page.count("@meshes") == c.meshes);
      CHECK(page.count("@triangles") == static_cast<long>(cube.mesh.triangles.size()));
      CHECK(page.count("@vertices") == split_vertices(cube.mesh));
      REQUIRE(fs::exists(png));
      // A PNG, not an empty file: the signature and a plausible size.
      CHECK(slurp(png).substr(1, 3) == "PNG");
      CHECK(fs::file_size(png) > 2000);
    }
  }
}
