// The volume stage (surface/volume.h, Netgen's nglib): tetrahedra fill closed solids and
// keep the surface mesh exactly; an assembly stays conforming across its interface; an
// open solid is named and skipped while the others are filled; the writers carry the
// tetrahedra; `uvmesh mesh --volume` end to end.
#include <BRepBuilderAPI_Transform.hxx>
#include <BRepGProp.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRep_Builder.hxx>
#include <GProp_GProps.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Compound.hxx>
#include <TopoDS_Shell.hxx>
#include <TopoDS_Solid.hxx>
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <thread>

#include "uvmesh/geom/occ.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"
#include "uvmesh/surface/volume.h"

using namespace uvmesh;

namespace {

using Face3 = std::array<surface::NodeId, 3>;

Face3 sorted(Face3 f) {
  std::sort(f.begin(), f.end());
  return f;
}

// Every face of the tetrahedra with the number of tetrahedra using it, and the solids.
std::map<Face3, std::vector<geom::Id>> tet_faces(const surface::TetMesh& v) {
  std::map<Face3, std::vector<geom::Id>> faces;
  for (std::size_t t = 0; t < v.tets.size(); ++t) {
    const auto& k = v.tets[t];
    for (int o = 0; o < 4; ++o)
      faces[sorted({k[static_cast<std::size_t>(o)], k[static_cast<std::size_t>((o + 1) % 4)],
                    k[static_cast<std::size_t>((o + 2) % 4)]})]
          .push_back(v.tet_solid[t]);
  }
  return faces;
}

surface::MeshResult mesh(const geom::Model& m, double hmax_rel) {
  surface::MeshOptions o;
  o.size = surface::default_size(m);
  o.size.hmax = m.bbox.diagonal() / hmax_rel;
  o.threads = 1;
  return surface::mesh_model(m, o);
}

surface::VolumeResult fill(const geom::Model& m, const surface::MeshResult& r) {
  surface::VolumeOptions vo;
  vo.hmax = r.size.hmax;
  return surface::fill_solids(m, r.mesh, vo);
}

std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

std::filesystem::path temp_dir(const std::string& name) {
  auto d = std::filesystem::temp_directory_path() / ("uvmesh_test_volume_" + name);
  std::filesystem::remove_all(d);
  std::filesystem::create_directories(d);
  return d;
}

}  // namespace

TEST_CASE("volume: a box is filled, its surface mesh is the tetrahedra's boundary", "[volume]") {
  const TopoDS_Shape box = BRepPrimAPI_MakeBox(10.0, 20.0, 30.0).Shape();
  const geom::Model m = geom::model_from_occ(box, {});
  const surface::MeshResult r = mesh(m, 10);
  REQUIRE(r.ok());
  const surface::VolumeResult v = fill(m, r);
  REQUIRE(v.ok());
  REQUIRE(v.solids.size() == 1);
  REQUIRE(v.mesh.tets.size() > 0);
  // The surface points first and bit-identical.
  REQUIRE(v.mesh.surface_points == r.mesh.points.size());
  for (std::size_t i = 0; i < r.mesh.points.size(); ++i)
    REQUIRE(v.mesh.points[i] == r.mesh.points[i]);
  // Boundary faces (used once) are exactly the triangles; no face used three times.
  std::set<Face3> boundary, tris;
  for (const auto& [f, users] : tet_faces(v.mesh)) {
    REQUIRE(users.size() <= 2);
    if (users.size() == 1) boundary.insert(f);
  }
  for (const auto& t : r.mesh.triangles) tris.insert(sorted(t));
  CHECK(boundary == tris);
  // Positive volumes summing to the solid's volume; a non-flat tetrahedron everywhere.
  const surface::TetQualityReport q = surface::measure_tet_quality(v.mesh);
  CHECK(q.inverted == 0);
  GProp_GProps props;
  BRepGProp::VolumeProperties(box, props);
  CHECK(std::abs(q.volume - props.Mass()) <= 1e-9 * props.Mass());
  CHECK(q.dihedral_min > 0.0);
  CHECK(q.radius_edge_max < 1e3);
}

TEST_CASE("volume: two threads filling at once get what one thread gets", "[volume]") {
  // Netgen's state is global; fill_solids serializes its sessions (volume.h).
  const geom::Model m = geom::model_from_occ(BRepPrimAPI_MakeBox(1.0, 2.0, 3.0).Shape(), {});
  const surface::MeshResult r = mesh(m, 8);
  const surface::VolumeResult one = fill(m, r);
  REQUIRE(one.ok());
  surface::VolumeResult a, b;
  std::thread ta([&] { a = fill(m, r); });
  std::thread tb([&] { b = fill(m, r); });
  ta.join();
  tb.join();
  for (const surface::VolumeResult* v : {&a, &b}) {
    REQUIRE(v->ok());
    CHECK(v->mesh.tets == one.mesh.tets);
    CHECK(v->mesh.points == one.mesh.points);
  }
}

TEST_CASE("volume: tetrahedron measures of the regular and a flat tetrahedron", "[volume]") {
  const geom::Vec3 a(1, 1, 1), b(1, -1, -1), c(-1, 1, -1), d(-1, -1, 1);
  const double s = std::abs(surface::tet_volume(a, b, c, d));
  CHECK(s == Approx(8.0 / 3.0));
  CHECK(surface::tet_min_dihedral_deg(a, b, c, d) == Approx(70.528779).epsilon(1e-6));
  CHECK(surface::tet_radius_edge(a, b, c, d) == Approx(std::sqrt(6.0) / 4.0));
  const geom::Vec3 flat(0, 0, 0);
  CHECK(surface::tet_min_dihedral_deg(a, b, c, (a + b + c) / 3.0) == Approx(0.0).margin(1e-9));
  CHECK(std::isinf(surface::tet_radius_edge(flat, flat, c, d)));
}

TEST_CASE("volume: two cubes sharing a face give two conforming regions", "[volume][corpus]") {
  io::ReadOptions ro;
  ro.conform = true;  // as `uvmesh mesh` reads assemblies: the touching faces imprinted, shared
  const io::ReadResult rd =
      io::read_cad(std::string(UVMESH_SHARED_DATA) + "/cad/dagmc_two_cubes.stp", ro);
  REQUIRE(rd.ok);
  const geom::Model& m = rd.model;
  REQUIRE(m.solids.size() == 2);
  const surface::MeshResult r = mesh(m, 20);
  REQUIRE(r.ok());
  const surface::VolumeResult v = fill(m, r);
  REQUIRE(v.ok());
  REQUIRE(v.solids.size() == 2);
  std::set<geom::Id> regions(v.mesh.tet_solid.begin(), v.mesh.tet_solid.end());
  CHECK(regions == std::set<geom::Id>{0, 1});
  // Interface faces: in both solids' shells. Their triangles are used by one tetrahedron of
  // each solid; every other triangle by one tetrahedron; no other face is on a boundary.
  const auto s0 = surface::solid_surface(r.mesh, m, 0).faces;
  const auto s1 = surface::solid_surface(r.mesh, m, 1).faces;
  std::set<geom::Id> shared;
  std::set_intersection(s0.begin(), s0.end(), s1.begin(), s1.end(),
                        std::inserter(shared, shared.begin()));
  REQUIRE(!shared.empty());
  const auto faces = tet_faces(v.mesh);
  std::size_t interface_tris = 0;
  for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
    const auto it = faces.find(sorted(r.mesh.triangles[t]));
    REQUIRE(it != faces.end());
    if (shared.count(r.mesh.triangle_face[t])) {
      ++interface_tris;
      std::vector<geom::Id> users = it->second;
      std::sort(users.begin(), users.end());
      CHECK(users == std::vector<geom::Id>{0, 1});
    } else {
      CHECK(it->second.size() == 1);
    }
  }
  CHECK(interface_tris > 0);
  std::size_t boundary = 0;
  for (const auto& [f, users] : faces) {
    REQUIRE(users.size() <= 2);
    boundary += users.size() == 1;
  }
  CHECK(boundary == r.mesh.triangles.size() - interface_tris);
}

TEST_CASE("volume: an open solid is named and skipped, the closed one is filled", "[volume]") {
  // A closed box, and beside it a solid whose shell lacks one face of a box.
  const TopoDS_Shape closed = BRepPrimAPI_MakeBox(1.0, 1.0, 1.0).Shape();
  const TopoDS_Shape other = BRepPrimAPI_MakeBox(gp_Pnt(3, 0, 0), 1.0, 1.0, 1.0).Shape();
  BRep_Builder bb;
  TopoDS_Shell shell;
  bb.MakeShell(shell);
  int n = 0;
  for (TopExp_Explorer ex(other, TopAbs_FACE); ex.More(); ex.Next())
    if (n++ > 0) bb.Add(shell, ex.Current());
  shell.Closed(Standard_False);
  TopoDS_Solid open;
  bb.MakeSolid(open);
  bb.Add(open, shell);
  TopoDS_Compound both;
  bb.MakeCompound(both);
  bb.Add(both, closed);
  bb.Add(both, open);
  const geom::Model m = geom::model_from_occ(both, {});
  REQUIRE(m.solids.size() == 2);
  const surface::MeshResult r = mesh(m, 10);
  const surface::VolumeResult v = fill(m, r);
  REQUIRE(v.failed.size() == 1);
  CHECK(v.failed[0].solid == 1);
  CHECK(v.failed[0].message.rfind("solid 2", 0) == 0);
  CHECK(v.failed[0].message.find("not closed") != std::string::npos);
  REQUIRE(v.solids.size() == 1);
  CHECK(v.solids[0].solid == 0);
  CHECK(v.mesh.tets.size() > 0);
  for (geom::Id s : v.mesh.tet_solid) CHECK(s == 0);
  CHECK(std::abs(surface::measure_tet_quality(v.mesh).volume - 1.0) < 1e-9);
}

TEST_CASE("volume: writers carry the tetrahedra", "[volume][io]") {
  const geom::Model m = geom::model_from_occ(BRepPrimAPI_MakeBox(1.0, 2.0, 3.0).Shape(), {});
  const surface::MeshResult r = mesh(m, 10);
  const surface::VolumeResult v = fill(m, r);
  REQUIRE(v.ok());
  const auto dir = temp_dir("writers");
  io::WriteOptions wo;
  wo.volume = &v.mesh;
  const std::string nt = std::to_string(v.mesh.tets.size());

  SECTION("Medit: Tetrahedra with the solid reference, all vertices") {
    const std::string p = (dir / "box.mesh").string();
    REQUIRE(io::write_mesh(r.mesh, &m, p, wo).ok);
    std::istringstream in(slurp(p));
    std::string word;
    std::size_t vertices = 0, tets = 0;
    std::vector<std::array<long, 5>> rows;
    while (in >> word) {
      if (word == "Vertices") in >> vertices;
      if (word == "Tetrahedra") {
        in >> tets;
        rows.resize(tets);
        for (auto& row : rows)
          for (long& x : row) in >> x;
      }
    }
    CHECK(vertices == v.mesh.points.size());
    REQUIRE(tets == v.mesh.tets.size());
    for (std::size_t t = 0; t < tets; ++t) {
      for (int k = 0; k < 4; ++k)
        CHECK(rows[t][static_cast<std::size_t>(k)] ==
              v.mesh.tets[t][static_cast<std::size_t>(k)] + 1);
      CHECK(rows[t][4] == 1);
    }
  }
  SECTION("msh 4.1 and 2.2: tetrahedra (type 4) in the solid's volume") {
    for (const char* name : {"box.msh", "box22.msh"}) {
      io::WriteOptions w = wo;
      if (std::string(name) == "box22.msh") w.format = io::MeshFormat::Msh22;
      const std::string p = (dir / name).string();
      REQUIRE(io::write_mesh(r.mesh, &m, p, w).ok);
      const std::string s = slurp(p);
      if (w.format) {
        std::size_t count = 0;
        std::istringstream in(s.substr(s.find("$Elements")));
        std::string line;
        while (std::getline(in, line)) {
          std::istringstream ls(line);
          long tag, type, ntags, phys, elem;
          if ((ls >> tag >> type >> ntags >> phys >> elem) && type == 4 && phys == 1 && elem == 1)
            ++count;
        }
        CHECK(count == v.mesh.tets.size());
      } else {
        CHECK(s.find("\n3 1 4 " + nt + "\n") != std::string::npos);  // the volume's block
      }
    }
  }
  SECTION("vtu: tetra cells and solid_id") {
    const std::string p = (dir / "box.vtu").string();
    wo.encoding = io::Encoding::Ascii;
    REQUIRE(io::write_mesh(r.mesh, &m, p, wo).ok);
    const std::string s = slurp(p);
    CHECK(s.find("NumberOfCells=\"" + std::to_string(r.mesh.triangles.size() + v.mesh.tets.size()) +
                 "\"") != std::string::npos);
    CHECK(s.find("Name=\"solid_id\"") != std::string::npos);
  }
  SECTION("formats without volume elements refuse them; without tetrahedra nothing changes") {
    CHECK_FALSE(io::write_mesh(r.mesh, &m, (dir / "box.stl").string(), wo).ok);
    io::WriteOptions plain;
    REQUIRE(io::write_mesh(r.mesh, &m, (dir / "a.msh").string(), plain).ok);
    CHECK(slurp((dir / "a.msh").string()).find("\n3 1 4 ") == std::string::npos);
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("volume: uvmesh mesh --volume on the bracket", "[volume][cli]") {
  const auto dir = temp_dir("cli");
  const std::string exe = std::string(UVMESH_BINARY_DIR) + "/samples/uvmesh/uvmesh";
  const std::string step = std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step";
  const std::string out = (dir / "bracket.msh").string(), rep = (dir / "r.json").string();
  const std::string so = (dir / "stdout").string();
  const int rc = std::system(("'" + exe + "' mesh '" + step + "' -o '" + out +
                              "' --volume -q --report '" + rep + "' > '" + so + "'")
                                 .c_str());
  CHECK(rc == 0);
  CHECK(slurp(so).empty());  // Netgen's messages are silenced
  const std::string r = slurp(rep);
  CHECK(r.find("\"volume\"") != std::string::npos);
  CHECK(r.find("\"min_dihedral_deg\"") != std::string::npos);
  CHECK(r.find("\"solids_filled\": 1") != std::string::npos);
  CHECK(slurp(out).find("\n3 1 4 ") != std::string::npos);
  // A format without tetrahedra: a command-line error before any work.
  const int rc2 = std::system(("'" + exe + "' mesh '" + step + "' -o '" + (dir / "b.stl").string() +
                               "' --volume -q 2>/dev/null")
                                  .c_str());
  CHECK(WEXITSTATUS(rc2) == 1);
  std::filesystem::remove_all(dir);
}
