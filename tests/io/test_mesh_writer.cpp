// Mesh writers (io/mesh_writer.h), checked by reading every file back with independent
// readers: meshio (Debian python3-meshio), Gmsh (the gmsh binary and python3-gmsh) and
// ../shared/tools/grade_mesh.py. A missing tool fails the test: scripts/install-deps.sh
// installs them all.
//
// The input is a unit cube built by hand on a lattice of step 1/n: 8 model vertices,
// 12 edges with n-1 interior nodes each, 6 faces with (n-1)^2 interior nodes and 2n^2
// triangles each, classification, segments and a one-solid model whose loops carry the
// edge uses -- what surface::mesh_model produces for a cube, without the mesher.
#include <sys/resource.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <charconv>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "uvmesh/io/mesh_writer.h"

using namespace uvmesh;
namespace fs = std::filesystem;

#include "mesh_test_util.h"

using namespace uvmesh_test;

TEST_CASE("mesh_writer: the reference readers are installed", "[io][mesh_writer]") {
  // Missing tools are a failure, not a skip: the other cases depend on them.
  const Run py = run(python() + " -c 'import meshio, gmsh; print(\"@ok\")'");
  INFO(py.out);
  CHECK(py.status == 0);
  const Run g = run("gmsh -version");
  INFO(g.out);
  CHECK(g.status == 0);
  CHECK(fs::exists(grade_mesh_script()));
}

TEST_CASE("mesh_writer: formats from extensions", "[io][mesh_writer]") {
  CHECK(io::format_from_path("a/b.msh") == io::MeshFormat::Msh41);
  CHECK(io::format_from_path("B.MESH") == io::MeshFormat::Medit);
  CHECK(io::format_from_path("x.Stl") == io::MeshFormat::Stl);
  CHECK(io::format_from_path("x.obj") == io::MeshFormat::Obj);
  CHECK(io::format_from_path("x.vtk") == io::MeshFormat::Vtk);
  CHECK(io::format_from_path("x.vtu") == io::MeshFormat::Vtu);
  CHECK(io::format_from_path("x.MESHB") == io::MeshFormat::Meshb);
  CHECK(io::format_from_path("x.glb") == io::MeshFormat::Glb);
  CHECK_FALSE(io::format_from_path("x.xyz"));
  CHECK(io::format_from_name("msh22") == io::MeshFormat::Msh22);
  CHECK_FALSE(io::format_from_name("msh3"));
  CHECK_FALSE(io::format_from_path("msh"));
  CHECK_FALSE(io::format_from_path("dir.msh/file"));
  CHECK(io::known_mesh_extensions() ==
        ".msh, .mesh, .meshb, .stl, .obj, .ply, .vtk, .vtu, .poly, .smesh, .drc, .glb");
}

TEST_CASE("mesh_writer: .msh 4.1 has one entity per CAD entity and reads back in Gmsh and meshio",
          "[io][mesh_writer]") {
  TempDir dir;
  const Cube cube = make_cube(4);
  REQUIRE(cube.mesh.num_points() == 98);
  REQUIRE(cube.mesh.num_triangles() == 192);
  const std::string path = dir.file("cube.msh");
  write_ok(cube.mesh, &cube.model, path);
  CHECK(dir.entries() == std::vector<std::string>{"cube.msh"});

  const Reading g = read_back(dir, "gmsh", path);
  INFO(g.run.out);
  check_counts(g, {{"@entities0", 8},
                   {"@entities1", 12},
                   {"@entities2", 6},
                   {"@entities3", 1},
                   {"@points", 98},
                   {"@vertex", 8},
                   {"@line", 48},
                   {"@triangle", 192}});
  // Node tags are the mesh's indices + 1, whatever the entity blocks.
  const std::vector<geom::Vec3> by_tag = coordinates(g);
  CHECK(by_tag == cube.mesh.points);
  // Every face: its 32 triangles and its 4 bounding curves, signed as the loop runs along
  // the written (outward) triangles. Face 0 (x = 0, reversed) runs, counter-clockwise in
  // (y,z): edge 4 (along y at z = 0) forward, edge 9 (along z at y = 1) forward, edge 6
  // (along y at z = 1) backward, edge 8 (along z at y = 0) backward; the face is
  // reversed, so every sign flips: tags -5, -10, +7, +9.
  const std::vector<std::string> surfaces = g.all("@surface");
  REQUIRE(surfaces.size() == 6);
  for (const std::string& s : surfaces) {
    std::istringstream in(s);
    int tag = 0, ntri = 0;
    in >> tag >> ntri;
    std::vector<int> bound;
    for (int b; in >> b;) bound.push_back(b);
    INFO("surface " << tag);
    CHECK(ntri == 32);
    CHECK(bound.size() == 4);
    if (tag == 1) CHECK(bound == std::vector<int>{-5, -10, 7, 9});
  }
  // Curves are bounded by their begin (+tag in the file) and end (-tag) vertices: edge 0
  // runs along x from vertex 0 to vertex 1. (Gmsh 4.8's getBoundary gives points
  // unsigned, so the sign is checked in the file itself: the curve line that follows the
  // 8 point lines of $Entities.)
  for (const std::string& s : g.all("@curve"))
    if (s.rfind("1 ", 0) == 0) CHECK((s == "1 1 2" || s == "1 1 -2"));
  {
    std::istringstream in(slurp(path));
    std::string line;
    while (std::getline(in, line) && line != "$Entities") {
    }
    for (int i = 0; i < 10; ++i) std::getline(in, line);
    // ... 0 0 0 1 0 0 (box), 1 1 (its physical group: model_edges, every element of a file
    // with a solid is in a group), 2 1 -2 (bounding vertices).
    CHECK(line == "1 0 0 0 1 0 0 1 1 2 1 -2");
  }
  CHECK(g.all("@volume") == std::vector<std::string>{"1 1 2 3 4 5 6"});

  const Reading mi = read_back(dir, "meshio", path);
  INFO(mi.run.out);
  check_counts(mi, {{"@points", 98}, {"@vertex", 8}, {"@line", 48}, {"@triangle", 192}});
  CHECK(sorted(coordinates(mi)) == sorted(cube.mesh.points));

  // The gmsh program reads the file and saves it again. Without -save_all Gmsh saves only
  // the elements of physical groups: every element is in one (unnamed_faces, model_edges,
  // model_vertices beside the solid's volume group), so nothing is lost.
  const std::string again = dir.file("again.msh");
  const Run re = run("gmsh " + quoted(path) + " -0 -o " + quoted(again));
  INFO(re.out);
  CHECK(re.status == 0);
  CHECK(fs::exists(again));
  const Reading g2 = read_back(dir, "gmsh", again);
  check_counts(g2, {{"@entities2", 6}, {"@triangle", 192}});

  check_closed_cube(path);
}

TEST_CASE("mesh_writer: .msh without a model derives its entities from the classification",
          "[io][mesh_writer]") {
  TempDir dir;
  Cube cube = make_cube(3);
  // Nodes not grouped by entity in the mesh: the writer groups them in blocks, node tags
  // stay index + 1.
  surface::SurfaceMesh& m = cube.mesh;
  std::swap(m.points[0], m.points.back());
  std::swap(m.point_dim[0], m.point_dim.back());
  std::swap(m.point_entity[0], m.point_entity.back());
  const auto last = static_cast<surface::NodeId>(m.points.size() - 1);
  auto swap_ids = [last](surface::NodeId& v) { v = v == 0 ? last : v == last ? 0 : v; };
  for (auto& t : m.triangles)
    for (auto& v : t) swap_ids(v);
  for (auto& s : m.segments) {
    swap_ids(s.a);
    swap_ids(s.b);
  }
  const std::string path = dir.file("cube.msh");
  write_ok(m, nullptr, path);
  const Reading g = read_back(dir, "gmsh", path);
  INFO(g.run.out);
  check_counts(g, {{"@entities0", 8},
                   {"@entities1", 12},
                   {"@entities2", 6},
                   {"@entities3", 0},
                   {"@triangle", 6 * 18}});
  CHECK(coordinates(g) == m.points);
  for (const std::string& s : g.all("@curve")) CHECK(std::count(s.begin(), s.end(), ' ') == 2);
  check_closed_cube(path);
}

TEST_CASE("mesh_writer: .mesh, .stl, .obj and .vtk read back in meshio and grade closed",
          "[io][mesh_writer]") {
  TempDir dir;
  const Cube cube = make_cube(4);
  struct Case {
    std::string name;
    io::Encoding encoding;
    bool graded;  // grade_mesh.py reads it
  };
  const Case cases[] = {
      {"cube.mesh", io::Encoding::Default, true}, {"cube.stl", io::Encoding::Default, true},
      {"ascii.stl", io::Encoding::Ascii, true},   {"cube.obj", io::Encoding::Default, true},
      {"cube.vtk", io::Encoding::Default, false}, {"binary.vtk", io::Encoding::Binary, false},
  };
  for (const Case& c : cases) {
    SECTION(c.name) {
      const std::string path = dir.file(c.name);
      io::WriteOptions opts;
      opts.encoding = c.encoding;
      write_ok(cube.mesh, &cube.model, path, opts);
      CHECK(dir.entries() == std::vector<std::string>{c.name});
      const Reading mi = read_back(dir, "meshio", path);
      INFO(mi.run.out);
      CHECK(mi.count("@triangle") == 192);
      const bool stl = c.name.ends_with(".stl");
      if (!stl) {
        CHECK(mi.count("@points") == 98);
        CHECK(sorted(coordinates(mi)) == sorted(cube.mesh.points));
      }
      if (c.name.ends_with(".mesh")) CHECK(mi.count("@line") == 48);
      if (c.name.ends_with(".vtk")) {
        // face_id per cell, in the mesh's triangle order.
        std::string expect = "face_id";
        for (geom::Id f : cube.mesh.triangle_face) expect += " " + std::to_string(f);
        CHECK(mi.all("@cell_data") == std::vector<std::string>{expect});
      }
      if (c.graded) check_closed_cube(path);
    }
  }
}

TEST_CASE("mesh_writer: binary STL layout and OBJ groups", "[io][mesh_writer]") {
  TempDir dir;
  const Cube cube = make_cube(2);
  const std::string stl = dir.file("cube.stl");
  write_ok(cube.mesh, nullptr, stl);
  const std::string bytes = slurp(stl);
  // 80-byte header (not "solid ...", which readers take for ASCII), uint32 count, 50 bytes
  // a triangle.
  REQUIRE(bytes.size() == 84 + 50 * cube.mesh.num_triangles());
  CHECK(bytes.rfind("uvmesh", 0) == 0);
  std::uint32_t count = 0;
  std::memcpy(&count, bytes.data() + 80, 4);  // little-endian, as this machine
  CHECK(count == cube.mesh.num_triangles());
  // The first triangle lies on face 0 (x = 0): outward normal -x.
  float normal[3];
  std::memcpy(normal, bytes.data() + 84, sizeof normal);
  CHECK(normal[0] == -1.0f);
  CHECK(normal[1] == 0.0f);
  CHECK(normal[2] == 0.0f);

  const std::string obj = dir.file("cube.obj");
  write_ok(cube.mesh, nullptr, obj);
  const std::string text = slurp(obj);
  std::vector<std::string> groups;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    if (line.rfind("g ", 0) == 0) groups.push_back(line);
  CHECK(groups == std::vector<std::string>{"g face_0", "g face_1", "g face_2", "g face_3",
                                           "g face_4", "g face_5"});
}

TEST_CASE("mesh_writer: coordinates round-trip exactly through every ASCII format",
          "[io][mesh_writer]") {
  TempDir dir;
  Cube cube = make_cube(2);
  // Values with no short decimal form, extreme exponents and a long mantissa. (The mesh is
  // no longer a cube; only the numbers matter here.)
  auto& p = cube.mesh.points;
  p[0] = {0.1, 1e-300, -123456.789};
  p[8] = {1.0 / 3.0, 2.0 / 3.0, 0.1 + 0.2};
  p[p.size() - 1] = {1e300, -2.2250738585072014e-308, 123456789.12345679};
  p[9] = {-0.0, 4.9406564584124654e-324, 9007199254740993.0};
  for (const char* name : {"rt.msh", "rt.mesh", "rt.obj", "rt.vtk"}) {
    SECTION(name) {
      const std::string path = dir.file(name);
      write_ok(cube.mesh, &cube.model, path);
      const Reading mi = read_back(dir, "meshio", path);
      INFO(mi.run.out);
      CHECK(sorted(coordinates(mi)) == sorted(p));
      if (std::string(name) == "rt.msh") {
        const Reading g = read_back(dir, "gmsh", path);
        INFO(g.run.out);
        CHECK(coordinates(g) == p);
      }
    }
  }
}

TEST_CASE("mesh_writer: a rewrite replaces the file and failures leave nothing behind",
          "[io][mesh_writer]") {
  TempDir dir;
  const Cube big = make_cube(4), small = make_cube(1);
  const std::string path = dir.file("cube.msh");
  write_ok(big.mesh, &big.model, path);
  write_ok(small.mesh, &small.model, path);
  CHECK(dir.entries() == std::vector<std::string>{"cube.msh"});
  const Reading g = read_back(dir, "gmsh", path);
  INFO(g.run.out);
  check_counts(g, {{"@points", 8}, {"@triangle", 12}});
  fs::remove(dir.file("reader.py"));
  const std::string before = slurp(path);

  SECTION("the directory does not exist") {
    const std::string bad = dir.file("missing/cube.msh");
    const io::WriteResult w = io::write_mesh(big.mesh, &big.model, bad);
    CHECK_FALSE(w.ok);
    CHECK(w.error.find(bad) != std::string::npos);
    CHECK(w.error.find("No such file or directory") != std::string::npos);
  }
  SECTION("the target is a directory") {
    fs::create_directory(dir.file("sub.msh"));
    const io::WriteResult w = io::write_mesh(big.mesh, &big.model, dir.file("sub.msh"));
    CHECK_FALSE(w.ok);
    CHECK(w.error == dir.file("sub.msh") + ": is a directory");
    fs::remove(dir.file("sub.msh"));
  }
  SECTION("the directory is read-only") {
    const fs::path ro = dir.path / "ro";
    fs::create_directory(ro);
    const std::string bad = (ro / "cube.msh").string();
    fs::permissions(ro, fs::perms::owner_read | fs::perms::owner_exec);
    if (::geteuid() == 0) {
      // Permission bits do not stop root; a parent that is a regular file stops anyone at
      // the same step (creating the temporary file).
      WARN("running as root: a read-only directory is writable, testing a file as parent");
      const std::string under_file = path + "/cube.msh";
      const io::WriteResult w = io::write_mesh(big.mesh, &big.model, under_file);
      CHECK_FALSE(w.ok);
      CHECK(w.error.find(under_file) != std::string::npos);
      CHECK(w.error.find("Not a directory") != std::string::npos);
    } else {
      const io::WriteResult w = io::write_mesh(big.mesh, &big.model, bad);
      CHECK_FALSE(w.ok);
      CHECK(w.error.find(bad) != std::string::npos);
      CHECK(w.error.find("Permission denied") != std::string::npos);
    }
    CHECK(fs::is_empty(ro));
    fs::permissions(ro, fs::perms::owner_all);
    fs::remove(ro);
  }
  SECTION("the disk fills up in the middle of the file") {
    // RLIMIT_FSIZE makes write(2) fail with EFBIG past 64 KiB (SIGXFSZ ignored so that the
    // process survives): the write error must surface, the temporary file go, and the
    // previous file stay as it was. The limit is restored before anything else runs.
    const auto old_handler = std::signal(SIGXFSZ, SIG_IGN);
    rlimit old_limit{};
    REQUIRE(::getrlimit(RLIMIT_FSIZE, &old_limit) == 0);
    rlimit limit = old_limit;
    limit.rlim_cur = 64 * 1024;
    REQUIRE(::setrlimit(RLIMIT_FSIZE, &limit) == 0);
    const Cube huge = make_cube(40);  // about 1.4 MB of .msh
    const io::WriteResult w = io::write_mesh(huge.mesh, &huge.model, path);
    ::setrlimit(RLIMIT_FSIZE, &old_limit);
    std::signal(SIGXFSZ, old_handler);
    CHECK_FALSE(w.ok);
    CHECK(w.error.find(path + ": write failed") == 0);
    CHECK(slurp(path) == before);
  }
  SECTION("the mesh or the options are malformed") {
    surface::SurfaceMesh bad = big.mesh;
    bad.triangles[5][1] = 100000;
    io::WriteResult w = io::write_mesh(bad, &big.model, path);
    CHECK_FALSE(w.ok);
    CHECK(w.error == path + ": invalid mesh: triangle 5 has a node index out of range");

    bad = big.mesh;
    bad.triangle_face.pop_back();
    CHECK_FALSE(io::write_mesh(bad, nullptr, path).ok);

    // A model smaller than the mesh's classification.
    geom::Model fewer = big.model;
    fewer.faces.resize(3);
    w = io::write_mesh(big.mesh, &fewer, path);
    CHECK_FALSE(w.ok);
    CHECK(w.error.find("model entities the model does not have") != std::string::npos);

    w = io::write_mesh(big.mesh, nullptr, dir.file("cube.xyz"));
    CHECK_FALSE(w.ok);
    CHECK(w.error.find("unknown mesh file extension") != std::string::npos);

    io::WriteOptions binary;
    binary.encoding = io::Encoding::Binary;
    w = io::write_mesh(big.mesh, nullptr, dir.file("cube.obj"), binary);
    CHECK_FALSE(w.ok);
    CHECK(w.error.find("no binary form of obj") != std::string::npos);

    // An explicit format wins over the extension.
    io::WriteOptions as_obj;
    as_obj.format = io::MeshFormat::Obj;
    write_ok(small.mesh, nullptr, dir.file("cube.txt"), as_obj);
    CHECK(slurp(dir.file("cube.txt")).rfind("# uvmesh", 0) == 0);
    fs::remove(dir.file("cube.txt"));
    CHECK(slurp(path) == before);
  }
  CHECK(dir.entries() == std::vector<std::string>{"cube.msh"});
}
