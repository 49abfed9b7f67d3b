// `uvmesh check` end to end on the bundled bracket: the report it prints for a mesh file
// is the report `uvmesh mesh --report` wrote for the same mesh (one library function makes
// both); SVG pictures; corrupt and truncated files give one clear error and exit 2.
#include <catch2/catch.hpp>
#include <nlohmann/json.hpp>
#include <set>

#include "mesh_test_util.h"
#include "uvmesh/io/mesh_reader.h"

using namespace uvmesh_test;

namespace {

const std::string kExe = UVMESH_EXE;
const std::string kBracket = std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step";

// Runs a command with stdout and stderr kept apart.
struct Split {
  int status = -1;
  std::string out, err;
};
Split run_split(const TempDir& dir, const std::string& cmd) {
  const std::string err = dir.file("stderr.txt");
  Split s;
  // run() sends stderr to stdout after the command: the inner redirection wins.
  const Run r = run("(" + cmd + " 2>" + quoted(err) + ")");
  s.status = r.status;
  s.out = r.out;
  s.err = slurp(err);
  return s;
}

}  // namespace

TEST_CASE("check: the report of a mesh file is the report uvmesh mesh wrote", "[io][check][cli]") {
  TempDir dir("check_cli");
  const std::string msh = dir.file("b.msh"), report = dir.file("b.json");
  const Split m = run_split(dir, quoted(kExe) + " mesh " + quoted(kBracket) + " -o " + quoted(msh) +
                                     " --report " + quoted(report) + " -q --threads 1");
  INFO(m.err);
  REQUIRE(m.status == 0);
  const Split c = run_split(dir, quoted(kExe) + " check " + quoted(msh) + " --model " +
                                     quoted(kBracket) + " --json --threads 1");
  INFO(c.err);
  REQUIRE(c.status == 0);
  const nlohmann::json a = nlohmann::json::parse(slurp(report)), b = nlohmann::json::parse(c.out);
  // .msh 4.1 keeps node and triangle order and the exact coordinates: the same mesh, so
  // the same numbers.
  for (const char* section : {"quality", "topology", "edge_length_distribution", "histograms"}) {
    INFO(section);
    CHECK(a.at(section) == b.at(section));
  }
  for (const char* key : {"points", "triangles", "segments"})
    CHECK(a["counts"][key] == b["counts"][key]);
  // Chordal: the mesher's (u,v) there, projections recovered from the file here.
  CHECK(b["chordal"]["max"].get<double>() ==
        Approx(a["chordal"]["max"].get<double>()).epsilon(1e-6));
  CHECK(b["chordal"]["samples"] == a["chordal"]["samples"]);
  // Edge lengths in the size metric: the same default sizes, node (u,v) recovered.
  CHECK(b["metric_edge_lengths"]["edges"] == a["metric_edge_lengths"]["edges"]);
  CHECK(b["metric_edge_lengths"]["unit_share"].get<double>() ==
        Approx(a["metric_edge_lengths"]["unit_share"].get<double>()).margin(0.01));
  CHECK(b["topology"]["watertight"] == true);
  CHECK(b["topology"]["components"] == 1);

  // The text form names the essentials.
  const Split t = run_split(dir, quoted(kExe) + " check " + quoted(msh) + " --no-selfint");
  REQUIRE(t.status == 0);
  CHECK_THAT(t.out,
             Catch::Contains("0 free, 0 non-manifold, 0 inconsistently oriented; 1 component(s)"));
  CHECK_THAT(t.out, Catch::Contains("quality: Q max"));
}

TEST_CASE("check: --svg draws histograms and a face's (u,v) mesh", "[io][check][cli]") {
  TempDir dir("check_cli");
  const std::string stl = dir.file("b.stl"), msh = dir.file("b.msh"), svg = dir.file("svg");
  REQUIRE(run(quoted(kExe) + " mesh " + quoted(kBracket) + " -o " + quoted(msh) + " -q").status ==
          0);
  const Split s =
      run_split(dir, quoted(kExe) + " check " + quoted(msh) + " --model " + quoted(kBracket) +
                         " --svg " + quoted(svg) + " --face 3 --no-selfint");
  INFO(s.err);
  REQUIRE(s.status == 0);
  for (const char* f : {"quality_q.svg", "angles.svg", "edge_length.svg", "face_3_uv.svg"}) {
    INFO(f);
    const std::string text = slurp((fs::path(svg) / f).string());
    CHECK(text.rfind("<svg ", 0) == 0);
    CHECK(text.find("</svg>") != std::string::npos);
  }
  CHECK(slurp((fs::path(svg) / "face_3_uv.svg").string()).find("<polygon") != std::string::npos);
  // --face needs (u,v): an STL file has no face ids to recover them from.
  REQUIRE(run(quoted(kExe) + " mesh " + quoted(kBracket) + " -o " + quoted(stl) + " -q").status ==
          0);
  const Split n = run_split(
      dir, quoted(kExe) + " check " + quoted(stl) + " --svg " + quoted(svg) + " --face 3");
  CHECK(n.status == 1);
  CHECK_THAT(n.err, Catch::Contains("the mesh has no (u,v)"));
}

TEST_CASE("check: a corrupt or truncated mesh gives one clear error and exit 2",
          "[io][check][cli]") {
  TempDir dir("check_cli");
  const std::string msh = dir.file("b.msh");
  REQUIRE(run(quoted(kExe) + " mesh " + quoted(kBracket) + " -o " + quoted(msh) + " -q").status ==
          0);
  const std::string data = slurp(msh);
  const std::string cut = dir.file("cut.msh");
  std::ofstream(cut, std::ios::binary)
      .write(data.data(), static_cast<std::streamsize>(data.size() / 3));
  const std::string junk = dir.file("junk.stl");
  std::ofstream(junk, std::ios::binary) << "not a mesh at all";
  const std::string glb = dir.file("b.glb");
  std::ofstream(glb, std::ios::binary) << "glTF";
  struct Bad {
    std::string path, expect;
  };
  for (const Bad& b :
       {Bad{cut, "cut.msh: line "}, Bad{junk, "junk.stl: byte offset 0: too short for binary STL"},
        Bad{glb, "b.glb: not a mesh format read here"},
        Bad{dir.file("none.msh"), "none.msh: cannot open"}}) {
    INFO(b.path);
    const Split s = run_split(dir, quoted(kExe) + " check " + quoted(b.path));
    CHECK(s.status == 2);
    CHECK(s.out.empty());
    CHECK(std::count(s.err.begin(), s.err.end(), '\n') == 1);
    CHECK_THAT(s.err, Catch::StartsWith("uvmesh: error: ") && Catch::Contains(b.expect));
  }
}

TEST_CASE("mesh: the output flags pick the format, the encoding and Draco's settings",
          "[io][check][cli]") {
  TempDir dir("check_cli");
  auto mesh = [&](const std::string& out, const std::string& flags) {
    const Split s = run_split(dir, quoted(kExe) + " mesh " + quoted(kBracket) + " -o " +
                                       quoted(dir.file(out)) + " -q --threads 1 " + flags);
    INFO(out << " " << flags << ": " << s.err);
    CHECK(s.status == 0);
    return dir.file(out);
  };
  CHECK(slurp(mesh("a.msh", "--format msh22")).rfind("$MeshFormat\n2.2 0 8\n", 0) == 0);
  CHECK(slurp(mesh("b.msh", "--binary")).rfind("$MeshFormat\n4.1 1 8\n", 0) == 0);
  CHECK(slurp(mesh("c.stl", "--ascii")).rfind("solid uvmesh", 0) == 0);
  CHECK(slurp(mesh("d.txt", "--format obj")).rfind("# uvmesh", 0) == 0);
  const auto small = fs::file_size(mesh("e.drc", "--draco-bits 11 --draco-level 10"));
  const auto large = fs::file_size(mesh("f.drc", "--draco-bits 16 --draco-level 0"));
  CHECK(small < large);
  CHECK(slurp(mesh("g.glb", "--glb-per-face")).find("\"face_25\"") != std::string::npos);
  // A format without an ASCII form is a clear error, and nothing is written.
  const Split bad = run_split(dir, quoted(kExe) + " mesh " + quoted(kBracket) + " -o " +
                                       quoted(dir.file("h.drc")) + " -q --ascii");
  CHECK(bad.status == 4);
  CHECK_THAT(bad.err, Catch::Contains("drc has no ASCII form"));
  CHECK_FALSE(fs::exists(dir.file("h.drc")));
}

TEST_CASE("mesh: STEP face names become .msh physical groups", "[io][check][cli]") {
  // CAx-IF's dm1 assembly names 24 of its faces (F1..F7 per part) in the STEP entities.
  TempDir dir("check_cli");
  const std::string model = std::string(UVMESH_SHARED_DATA) + "/cad/caxif_dm1_id.stp";
  const std::string msh = dir.file("dm1.msh");
  const Split s = run_split(dir, quoted(kExe) + " mesh " + quoted(model) + " -o " + quoted(msh) +
                                     " -q --allow-holes --threads 1 --hmax-rel 0.2 --angle 60");
  INFO(s.err);
  REQUIRE(s.status == 0);
  const io::MeshReadResult r = io::read_mesh(msh);
  INFO(r.error);
  REQUIRE(r.ok);
  std::set<std::string> surface_groups;
  std::size_t volume_groups = 0;
  for (const auto& p : r.physicals) {
    if (p.dim == 2) surface_groups.insert(p.name);
    volume_groups += p.dim == 3;
  }
  for (const char* name : {"F1", "F2", "F3", "F4", "F5", "F6", "F7", "unnamed_faces"}) {
    INFO(name);
    CHECK(surface_groups.count(name) == 1);
  }
  CHECK(volume_groups == r.entities[3]);  // one group per solid
}
