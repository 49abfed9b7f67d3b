// Every mesh format: written by io::write_mesh, read back by io::read_mesh (round trip:
// same counts, coordinates within the format's precision, same face ids) and by the
// reference tools (meshio, Gmsh, TetGen, draco_decoder); corrupt and truncated files give
// located errors. The browser test of .glb is test_glb_browser.cpp.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <limits>

#include "mesh_test_util.h"
#include "uvmesh/io/mesh_reader.h"

using namespace uvmesh_test;

namespace {

// The cube of mesh_test_util.h with two faces sharing a name (one physical group).
Cube named_cube(int n) {
  Cube c = make_cube(n);
  c.model.faces[0].name = "x_walls";
  c.model.faces[1].name = "x_walls";
  return c;
}

struct Case {
  const char* name;
  const char* file;
  io::Encoding encoding = io::Encoding::Default;
  std::optional<io::MeshFormat> format;
  bool segments = false;  ///< the format stores the edge segments
  bool face_ids = true;   ///< the format stores face ids
  double tol = 0.0;       ///< coordinate precision (0: exact)
};

// Draco's quantization step for the cube (extent 1) at `bits`; the error is at most half.
double draco_step(int bits) {
  return 1.0 / ((1 << bits) - 1);
}

const std::vector<Case>& readable_cases() {
  static const std::vector<Case> cases = {
      {"msh 4.1 ASCII", "c.msh", io::Encoding::Ascii, {}, true},
      {"msh 4.1 binary", "cb.msh", io::Encoding::Binary, {}, true},
      {"msh 2.2", "c22.msh", io::Encoding::Default, io::MeshFormat::Msh22, true},
      {"Medit", "c.mesh", io::Encoding::Default, {}, true},
      {"Medit binary", "c.meshb", io::Encoding::Default, {}, true},
      {"STL binary", "c.stl", io::Encoding::Default, {}, false, false, 1e-7},
      {"STL ASCII", "ca.stl", io::Encoding::Ascii, {}, false, false},
      {"OBJ", "c.obj", io::Encoding::Default, {}, false, true},
      {"PLY binary", "c.ply", io::Encoding::Default, {}, false, false},
      {"PLY ASCII", "ca.ply", io::Encoding::Ascii, {}, false, true},
      {"Draco",
       "c.drc",
       io::Encoding::Default,
       {},
       false,
       true,
       0.5 * std::sqrt(3.0) * draco_step(14)},
  };
  return cases;
}

io::WriteOptions options_of(const Case& c) {
  io::WriteOptions o;
  o.encoding = c.encoding;
  o.format = c.format;
  return o;
}

// Index of the original point nearest to p, and the distance.
std::pair<surface::NodeId, double> nearest(const surface::SurfaceMesh& m, const geom::Vec3& p) {
  std::pair<surface::NodeId, double> best{-1, std::numeric_limits<double>::infinity()};
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    const double d = glm::distance(m.points[i], p);
    if (d < best.second) best = {static_cast<surface::NodeId>(i), d};
  }
  return best;
}

// A triangle as original indices, rotated to start at its smallest index (orientation
// kept), with its face id.
using Tri = std::tuple<surface::NodeId, surface::NodeId, surface::NodeId, geom::Id>;
Tri canonical(std::array<surface::NodeId, 3> t, geom::Id face) {
  while (t[0] > t[1] || t[0] > t[2]) t = {t[1], t[2], t[0]};
  return {t[0], t[1], t[2], face};
}

// Writes the cube as `file` in that encoding and format; returns the path.
std::string write_as(const TempDir& dir, const Cube& cube, const char* file, io::Encoding enc,
                     std::optional<io::MeshFormat> fmt) {
  io::WriteOptions o;
  o.encoding = enc;
  o.format = fmt;
  const std::string path = dir.file(file);
  write_ok(cube.mesh, &cube.model, path, o);
  return path;
}

std::string truncated_copy(const TempDir& dir, const std::string& path, std::size_t size) {
  const std::string data = slurp(path);
  const std::string out =
      dir.file("cut_" + std::to_string(size) + "_" + fs::path(path).filename().string());
  std::ofstream(out, std::ios::binary)
      .write(data.data(), static_cast<std::streamsize>(std::min(size, data.size())));
  return out;
}

}  // namespace

TEST_CASE("mesh formats: every readable format round-trips counts, coordinates and face ids",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(4);
  const surface::SurfaceMesh& orig = cube.mesh;
  std::vector<Tri> want;
  for (std::size_t t = 0; t < orig.triangles.size(); ++t)
    want.push_back(canonical(orig.triangles[t], orig.triangle_face[t]));
  std::sort(want.begin(), want.end());

  for (const Case& c : readable_cases()) {
    SECTION(c.name) {
      const std::string path = dir.file(c.file);
      write_ok(orig, &cube.model, path, options_of(c));
      io::MeshReadOptions ro;
      ro.format = c.format;
      const io::MeshReadResult r = io::read_mesh(path, ro);
      INFO(r.error);
      REQUIRE(r.ok);
      CHECK(r.has_face_ids == c.face_ids);
      CHECK(r.mesh.points.size() == orig.points.size());
      CHECK(r.mesh.triangles.size() == orig.triangles.size());
      CHECK(r.mesh.segments.size() == (c.segments ? orig.segments.size() : 0));
      // Every point lands within the format's precision of one original point, and the
      // triangles (orientation included) are the original ones.
      std::vector<surface::NodeId> to_orig(r.mesh.points.size());
      double worst = 0;
      for (std::size_t i = 0; i < r.mesh.points.size(); ++i) {
        const auto [k, d] = nearest(orig, r.mesh.points[i]);
        to_orig[i] = k;
        worst = std::max(worst, d);
      }
      CHECK(worst <= c.tol);
      std::vector<Tri> got;
      for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
        const auto& tri = r.mesh.triangles[t];
        const geom::Id f = c.face_ids ? r.mesh.triangle_face[t] : 0;
        got.push_back(canonical(
            {to_orig[static_cast<std::size_t>(tri[0])], to_orig[static_cast<std::size_t>(tri[1])],
             to_orig[static_cast<std::size_t>(tri[2])]},
            f));
      }
      std::sort(got.begin(), got.end());
      if (c.face_ids) {
        CHECK(got == want);
      } else {
        std::vector<Tri> want0;
        for (auto [a, b, cc, f] : want) want0.emplace_back(a, b, cc, 0);
        std::sort(want0.begin(), want0.end());
        CHECK(got == want0);
      }
      // The mesh read back can be written again (classification present or derived).
      const io::WriteResult again = io::write_mesh(r.mesh, nullptr, dir.file("again.msh"));
      INFO(again.error);
      CHECK(again.ok);
    }
  }
}

TEST_CASE("mesh formats: .msh 4.1 keeps the classification and the physical groups",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(3);
  for (io::Encoding enc : {io::Encoding::Ascii, io::Encoding::Binary}) {
    io::WriteOptions o;
    o.encoding = enc;
    const std::string path = dir.file(enc == io::Encoding::Binary ? "b.msh" : "a.msh");
    write_ok(cube.mesh, &cube.model, path, o);
    const io::MeshReadResult r = io::read_mesh(path);
    INFO(r.error);
    REQUIRE(r.ok);
    CHECK(r.binary == (enc == io::Encoding::Binary));
    CHECK(r.classified);
    CHECK(r.mesh.point_dim == cube.mesh.point_dim);
    CHECK(r.mesh.point_entity == cube.mesh.point_entity);
    CHECK(r.mesh.points == cube.mesh.points);
    CHECK(r.entities == std::array<std::size_t, 4>{8, 12, 6, 1});
    std::vector<std::string> groups;
    for (const auto& p : r.physicals)
      groups.push_back(std::to_string(p.dim) + " " + std::to_string(p.tag) + " " + p.name);
    CHECK(groups == std::vector<std::string>{"0 1 model_vertices", "1 1 model_edges", "2 1 x_walls",
                                             "2 2 unnamed_faces", "3 1 cube"});
  }
  // Without physical groups there is no $PhysicalNames section.
  io::WriteOptions plain;
  plain.physical_groups = false;
  write_ok(cube.mesh, &cube.model, dir.file("p.msh"), plain);
  CHECK(slurp(dir.file("p.msh")).find("$PhysicalNames") == std::string::npos);
}

TEST_CASE("mesh formats: corrupt and truncated files give one located error",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(3);
  for (const Case& c : readable_cases()) {
    SECTION(c.name) {
      const std::string path = dir.file(c.file);
      write_ok(cube.mesh, &cube.model, path, options_of(c));
      const std::size_t size = fs::file_size(path);
      io::MeshReadOptions ro;
      ro.format = c.format;
      // OBJ has no counts: a file cut between two lines is a smaller valid mesh, so only
      // cuts inside the header-like start are certain to fail.
      // A text file cut inside its last keyword ("endsolid uvm") can still be complete, so
      // text cuts stop 20 bytes short; a binary file loses its last byte too.
      const std::string f = c.file;
      std::vector<std::size_t> cuts = {size / 2, size - 20, 5};
      if (f == "c.meshb" || f == "c.stl" || f == "c.ply" || f == "c.drc") cuts.push_back(size - 1);
      if (f == "c.obj") cuts = {5};
      for (std::size_t cut : cuts) {
        const std::string bad = truncated_copy(dir, path, cut);
        const io::MeshReadResult r = io::read_mesh(bad, ro);
        INFO(c.name << " cut at " << cut << " of " << size << ": " << r.error);
        CHECK_FALSE(r.ok);
        CHECK(r.error.rfind(bad + ": ", 0) == 0);
        CHECK(r.mesh.triangles.empty());
      }
    }
  }
}

TEST_CASE("mesh formats: random byte corruptions give a mesh or an error, never a crash",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(2);
  std::uint64_t state = 0x9e3779b97f4a7c15ULL;  // fixed seed: the same files every run
  auto next = [&state] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (const Case& c : readable_cases()) {
    SECTION(c.name) {
      const std::string path = dir.file(c.file);
      write_ok(cube.mesh, &cube.model, path, options_of(c));
      const std::string data = slurp(path);
      io::MeshReadOptions ro;
      ro.format = c.format;
      int errors = 0;
      for (int k = 0; k < 150; ++k) {
        std::string bad = data;
        const int flips = 1 + static_cast<int>(next() % 4);
        for (int i = 0; i < flips; ++i) {
          const std::size_t at = next() % bad.size();
          // Digits, separators and random bytes: the text formats' likely corruptions.
          static constexpr char kChars[] = "0123456789 -.\n$eE";
          bad[at] =
              next() % 2 ? kChars[next() % (sizeof kChars - 1)] : static_cast<char>(next() & 0xff);
        }
        const std::string p = dir.file("fuzz_" + std::string(c.file));
        std::ofstream(p, std::ios::binary) << bad;
        const io::MeshReadResult r = io::read_mesh(p, ro);
        if (!r.ok) {
          ++errors;
          CHECK(r.error.rfind(p + ": ", 0) == 0);
        } else {
          // A mesh that reads is consistent: indices in range, one face id per triangle.
          CHECK(r.mesh.triangle_face.size() == r.mesh.triangles.size());
          for (const auto& t : r.mesh.triangles)
            for (surface::NodeId v : t)
              CHECK((v >= 0 && static_cast<std::size_t>(v) < r.mesh.points.size()));
        }
      }
      INFO(errors << " of 150 corrupted files rejected");
      CHECK(errors > 0);
    }
  }
}

TEST_CASE("mesh formats: malformed files name the line or byte and the problem",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  auto error_of = [&](const std::string& name, const std::string& text) {
    const std::string p = dir.file(name);
    std::ofstream(p, std::ios::binary) << text;
    const io::MeshReadResult r = io::read_mesh(p);
    CHECK_FALSE(r.ok);
    return r.error;
  };
  CHECK_THAT(error_of("x.msh", "hello\n"),
             Catch::Contains("x.msh: line 1: expected '$MeshFormat'"));
  CHECK_THAT(error_of("v.msh", "$MeshFormat\n3.0 0 8\n$EndMeshFormat\n"),
             Catch::Contains("MSH version 3.0 is not read"));
  CHECK_THAT(
      error_of("n.msh",
               "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n2\n1 0 0 0\n2 1 x 0\n$EndNodes\n"),
      Catch::Contains("line 7: expected y, found 'x'"));
  CHECK_THAT(error_of("e.msh",
                      "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n1\n1 0 0 0\n$EndNodes\n"
                      "$Elements\n1\n1 2 2 0 1 1 1 7\n$EndElements\n"),
             Catch::Contains("line 10: element refers to node 7, which is not defined"));
  CHECK_THAT(error_of("i.mesh",
                      "MeshVersionFormatted 2\nDimension 3\nVertices\n1\n0 0 0 1\nTriangles\n1\n1 "
                      "1 9 1\nEnd\n"),
             Catch::Contains("line 8: vertex index 9 is out of range 1..1"));
  CHECK_THAT(error_of("s.stl", std::string(84, '\0') + "xyz"),
             Catch::Contains("s.stl: byte offset 80: binary STL announces 0 triangles (84 bytes) "
                             "but the file has 87 bytes (truncated?)"));
  CHECK_THAT(error_of("d.drc", "DRACO but not really"),
             Catch::Contains("d.drc: not a Draco mesh, or a corrupt one"));
  CHECK_THAT(error_of("empty.ply", ""), Catch::Contains("empty.ply: the file is empty"));
  CHECK_THAT(
      error_of("q.ply", "ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n"),
      Catch::Contains("file ends where a PLY value was expected"));
}

TEST_CASE("mesh formats: meshio reads every format it knows with the same counts",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(4);
  struct Ext {
    const char* file;
    io::Encoding enc;
    std::optional<io::MeshFormat> fmt;
    long lines;  ///< line cells meshio reports (the segments where the format has them)
  };
  const Ext exts[] = {{"m.msh", io::Encoding::Ascii, {}, 48},
                      {"mb.msh", io::Encoding::Binary, {}, 48},
                      {"m22.msh", io::Encoding::Default, io::MeshFormat::Msh22, 48},
                      {"m.mesh", io::Encoding::Default, {}, 48},
                      {"m.meshb", io::Encoding::Default, {}, 48},
                      {"m.vtk", io::Encoding::Ascii, {}, 0},
                      {"mb.vtk", io::Encoding::Binary, {}, 0},
                      {"m.vtu", io::Encoding::Binary, {}, 0},
                      {"ma.vtu", io::Encoding::Ascii, {}, 0},
                      {"m.stl", io::Encoding::Binary, {}, 0},
                      {"ma.stl", io::Encoding::Ascii, {}, 0},
                      {"m.obj", io::Encoding::Default, {}, 0},
                      {"m.ply", io::Encoding::Binary, {}, 0},
                      {"ma.ply", io::Encoding::Ascii, {}, 0}};
  for (const Ext& e : exts) {
    SECTION(e.file) {
      const std::string path = write_as(dir, cube, e.file, e.enc, e.fmt);
      const Reading r = read_back(dir, "meshio", path);
      check_counts(r, {{"@points", 98}, {"@triangle", 192}, {"@line", e.lines}});
      // Exact coordinates where the format stores doubles (STL stores floats; these
      // lattice coordinates are exact in float too).
      CHECK(sorted(coordinates(r)) == sorted(cube.mesh.points));
    }
  }
}

TEST_CASE(
    "mesh formats: Gmsh opens every .msh form with the same nodes, triangles, entities and groups",
    "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(4);
  const std::string physicals = dir.file("physicals.py");
  std::ofstream(physicals)
      << "import sys, gmsh\ngmsh.initialize()\ngmsh.option.setNumber('General.Terminal', 0)\n"
         "gmsh.open(sys.argv[1])\n"
         "for d, t in gmsh.model.getPhysicalGroups():\n"
         "    print('@physical', d, t, gmsh.model.getPhysicalName(d, t))\n"
         "gmsh.finalize()\n";
  struct Form {
    const char* file;
    io::Encoding enc;
    std::optional<io::MeshFormat> fmt;
    long volumes;
    std::vector<std::string> groups;
  };
  const std::vector<std::string> all = {"0 1 model_vertices", "1 1 model_edges", "2 1 x_walls",
                                        "2 2 unnamed_faces", "3 1 cube"};
  const Form forms[] = {
      {"g.msh", io::Encoding::Ascii, {}, 1, all},
      {"gb.msh", io::Encoding::Binary, {}, 1, all},
      // 2.2 has no volume entity without volume elements (see mesh_writer.h).
      {"g22.msh", io::Encoding::Default, io::MeshFormat::Msh22, 0, {all.begin(), all.end() - 1}}};
  for (const Form& f : forms) {
    SECTION(f.file) {
      const std::string path = write_as(dir, cube, f.file, f.enc, f.fmt);
      const Reading g = read_back(dir, "gmsh", path);
      check_counts(g, {{"@points", 98},
                       {"@triangle", 192},
                       {"@line", 48},
                       {"@vertex", 8},
                       {"@entities0", 8},
                       {"@entities1", 12},
                       {"@entities2", 6},
                       {"@entities3", f.volumes}});
      CHECK(sorted(coordinates(g)) == sorted(cube.mesh.points));
      const Run p = run(python() + " " + quoted(physicals) + " " + quoted(path));
      INFO(p.out);
      REQUIRE(p.status == 0);
      std::vector<std::string> groups;
      std::istringstream in(p.out);
      for (std::string l; std::getline(in, l);)
        if (l.rfind("@physical ", 0) == 0) groups.push_back(l.substr(10));
      CHECK(groups == f.groups);
    }
  }
}

TEST_CASE("mesh formats: the files Gmsh itself writes read back with the same counts",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(4);
  const std::string src = dir.file("src.msh");
  write_ok(cube.mesh, &cube.model, src);
  struct Out {
    const char* file;
    const char* flags;
    std::size_t segments;
  };
  for (const Out& o :
       {Out{"g41.msh", "", 48}, Out{"g41b.msh", "-bin", 48}, Out{"g22.msh", "-format msh22", 48},
        Out{"g.mesh", "-format mesh", 48}, Out{"g.stl", "-format stl", 0}}) {
    SECTION(o.file) {
      const std::string path = dir.file(o.file);
      const Run g = run("gmsh " + quoted(src) + " -0 -save_all " + o.flags + " -o " + quoted(path));
      INFO(g.out);
      REQUIRE(g.status == 0);
      const io::MeshReadResult r = io::read_mesh(path);
      INFO(r.error);
      REQUIRE(r.ok);
      CHECK(r.mesh.points.size() == cube.mesh.points.size());
      CHECK(r.mesh.triangles.size() == cube.mesh.triangles.size());
      CHECK(r.mesh.segments.size() == o.segments);
      std::vector<geom::Vec3> got = r.mesh.points, want = cube.mesh.points;
      if (std::string(o.file) == "g.stl")  // floats
        for (auto& p : want) p = geom::Vec3(glm::vec3(p));
      CHECK(sorted(got) == sorted(want));
    }
  }
}

// Regression: a model with a solid and no face names wrote the solid's volume group
// only; Gmsh re-saves only the elements of physical groups (Mesh.SaveAll off, its
// default), so `gmsh part.msh -0 -o copy.msh` gave an empty mesh (scripts/corpus.sh failed
// every solid on "gmsh reads 0 triangles from .msh").
TEST_CASE("mesh formats: with a solid and unnamed faces every element is in a physical group",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = make_cube(3);
  REQUIRE(cube.model.solids.size() == 1);
  for (const auto& f : cube.model.faces) REQUIRE(f.name.empty());
  struct Form {
    const char* file;
    io::Encoding enc;
    std::optional<io::MeshFormat> fmt;
  };
  for (const Form& f :
       {Form{"u.msh", io::Encoding::Ascii, {}}, Form{"ub.msh", io::Encoding::Binary, {}},
        Form{"u22.msh", io::Encoding::Default, io::MeshFormat::Msh22}}) {
    SECTION(f.file) {
      const std::string src = write_as(dir, cube, f.file, f.enc, f.fmt);
      const io::MeshReadResult r0 = io::read_mesh(src);
      INFO(r0.error);
      REQUIRE(r0.ok);
      std::vector<std::string> groups;
      for (const auto& p : r0.physicals)
        groups.push_back(std::to_string(p.dim) + " " + std::to_string(p.tag) + " " + p.name);
      CHECK(std::find(groups.begin(), groups.end(), "2 1 unnamed_faces") != groups.end());
      CHECK(std::find(groups.begin(), groups.end(), "1 1 model_edges") != groups.end());
      CHECK(std::find(groups.begin(), groups.end(), "0 1 model_vertices") != groups.end());
      // Gmsh's own re-save, without -save_all, keeps every triangle and segment.
      const std::string back = dir.file(std::string("resaved_") + f.file);
      const Run g = run("gmsh " + quoted(src) + " -0 -format msh22 -o " + quoted(back));
      INFO(g.out);
      REQUIRE(g.status == 0);
      const io::MeshReadResult r = io::read_mesh(back);
      INFO(r.error);
      REQUIRE(r.ok);
      CHECK(r.mesh.triangles.size() == cube.mesh.triangles.size());
      CHECK(r.mesh.segments.size() == cube.mesh.segments.size());
      CHECK(r.mesh.points.size() == cube.mesh.points.size());
    }
  }
}

TEST_CASE("mesh formats: TetGen tetrahedralizes the .poly and the .smesh", "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(3);
  for (const char* name : {"t.poly", "t.smesh"}) {
    SECTION(name) {
      const std::string path = dir.file(name);
      write_ok(cube.mesh, &cube.model, path);
      // -p: read a PLC; -Q quiet; no quality flag, so the boundary is kept as given.
      const Run r = run("tetgen -pQ " + quoted(path));
      INFO(r.out);
      REQUIRE(r.status == 0);
      const std::string stem = dir.file(fs::path(name).stem().string());
      const std::string ele = slurp(stem + ".1.ele"), node = slurp(stem + ".1.node"),
                        face = slurp(stem + ".1.face");
      REQUIRE_FALSE(ele.empty());
      CHECK(std::stol(ele) > 0);  // tetrahedra
      // No Steiner points: the surface nodes only.
      CHECK(std::stol(node) == static_cast<long>(cube.mesh.points.size()));
      // Boundary faces keep the markers (face id + 1) and the triangle count.
      std::istringstream fs_(face);
      long nfaces = 0, markers = 0;
      fs_ >> nfaces >> markers;
      CHECK(nfaces == 6 * 2 * 3 * 3);
      CHECK(markers == 1);
      std::vector<int> seen(7, 0);
      for (long i = 0; i < nfaces; ++i) {
        long id, a, b, c, mk;
        fs_ >> id >> a >> b >> c >> mk;
        if (mk >= 1 && mk <= 6) seen[static_cast<std::size_t>(mk)] = 1;
      }
      CHECK(std::count(seen.begin(), seen.end(), 1) == 6);
    }
  }
}

TEST_CASE("mesh formats: draco_decoder decodes the .drc within the quantization error",
          "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(4);
  for (int bits : {11, 14, 16}) {
    SECTION("bits " + std::to_string(bits)) {
      io::WriteOptions o;
      o.draco_bits = bits;
      o.draco_level = 10;
      const std::string path = dir.file("d.drc"), out = dir.file("d.ply");
      write_ok(cube.mesh, &cube.model, path, o);
      fs::remove(out);
      const Run r = run("draco_decoder -i " + quoted(path) + " -o " + quoted(out));
      INFO(r.out);
      REQUIRE(r.status == 0);
      const io::MeshReadResult d = io::read_mesh(out);
      INFO(d.error);
      REQUIRE(d.ok);
      CHECK(d.mesh.triangles.size() == 192);
      // Per coordinate at most half a quantization step of the largest extent.
      const double half = 0.5 * draco_step(bits) * (1 + 1e-6);
      double worst = 0;
      for (const geom::Vec3& p : d.mesh.points) {
        const geom::Vec3 q =
            cube.mesh.points[static_cast<std::size_t>(nearest(cube.mesh, p).first)];
        worst = std::max({worst, std::abs(p.x - q.x), std::abs(p.y - q.y), std::abs(p.z - q.z)});
      }
      INFO("worst coordinate error " << worst << ", half step " << half);
      CHECK(worst <= half);
    }
  }
}

TEST_CASE(
    "mesh formats: .glb is glTF 2.0 with KHR_draco_mesh_compression, one mesh per solid or face",
    "[io][mesh_formats]") {
  TempDir dir("mesh_formats");
  const Cube cube = named_cube(3);
  for (io::GlbGroups groups : {io::GlbGroups::Solid, io::GlbGroups::Face}) {
    io::WriteOptions o;
    o.glb_groups = groups;
    const std::string path = dir.file("c.glb");
    write_ok(cube.mesh, &cube.model, path, o);
    const std::string data = slurp(path);
    REQUIRE(data.size() > 20);
    CHECK(data.substr(0, 4) == "glTF");
    std::uint32_t version = 0, length = 0, json_len = 0;
    std::memcpy(&version, data.data() + 4, 4);
    std::memcpy(&length, data.data() + 8, 4);
    std::memcpy(&json_len, data.data() + 12, 4);
    CHECK(version == 2);
    CHECK(length == data.size());
    CHECK(data.substr(16, 4) == "JSON");
    const std::string json = data.substr(20, json_len);
    INFO(json);
    CHECK(json.find("\"extensionsRequired\"") != std::string::npos);
    CHECK(json.find("KHR_draco_mesh_compression") != std::string::npos);
    // Meshes are named after the solid ("cube") or the faces ("x_walls", "face_2", ...).
    if (groups == io::GlbGroups::Solid) {
      CHECK(json.find("\"cube\"") != std::string::npos);
    } else {
      CHECK(json.find("\"x_walls\"") != std::string::npos);
      CHECK(json.find("\"face_5\"") != std::string::npos);
    }
  }
  io::WriteOptions bad;
  bad.draco_bits = 31;
  const io::WriteResult w = io::write_mesh(cube.mesh, &cube.model, dir.file("x.glb"), bad);
  CHECK_FALSE(w.ok);
  CHECK_THAT(w.error, Catch::Contains("quantization bits must be 1..30"));
}
