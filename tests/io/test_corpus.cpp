// The whole corpus through the `uvmesh` program, as a user runs it:
//  - `uvmesh info --json --no-heal`: face / edge / solid counts, surface kinds and
//    bounding-box diagonal equal MANIFEST.tsv's; the defects its notes list (short,
//    free, non-manifold, degenerated edges, faces with seams, BRepCheck INVALID) too;
//  - with healing on, every difference from the MANIFEST is accounted for by a reported
//    healing step;
//  - every file in bad/ gives its expected outcome: a clean one-line error naming the
//    file and the defect with exit code 2, or a load with the MANIFEST counts;
//  - a NaN coordinate (the input that crashes a plain OCC import) is rejected.
#include <catch2/catch.hpp>

#include <nlohmann/json.hpp>

#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "uvmesh/io/cad_reader.h"

using nlohmann::json;

namespace {

const std::string kData = UVMESH_SHARED_DATA;
const std::string kExe = UVMESH_EXE;

struct Run {
  int rc = -1;
  std::string out, err;
};

std::string slurp(const std::string& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

Run run(const std::string& args) {
  const std::string base = std::string(UVMESH_BINARY_DIR) + "/tests/io/run_" + std::to_string(::getpid());
  const std::string cmd = "timeout 300 " + kExe + " " + args + " >" + base + ".out 2>" + base + ".err";
  const int st = std::system(cmd.c_str());
  Run r;
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = slurp(base + ".out");
  r.err = slurp(base + ".err");
  std::remove((base + ".out").c_str());
  std::remove((base + ".err").c_str());
  return r;
}

using Row = std::map<std::string, std::string>;

std::vector<Row> manifest() {
  std::ifstream in(kData + "/MANIFEST.tsv");
  std::string line;
  std::getline(in, line);
  std::vector<std::string> cols;
  {
    std::stringstream h(line);
    std::string c;
    while (std::getline(h, c, '\t')) cols.push_back(c);
  }
  std::vector<Row> rows;
  while (std::getline(in, line)) {
    std::stringstream s(line);
    std::string c;
    Row r;
    for (std::size_t i = 0; i < cols.size() && std::getline(s, c, '\t'); ++i) r[cols[i]] = c;
    rows.push_back(r);
  }
  return rows;
}

int note_count(const std::string& notes, const std::string& pattern) {
  std::smatch m;
  if (std::regex_search(notes, m, std::regex("(\\d+) " + pattern))) return std::stoi(m[1]);
  return 0;
}

std::map<std::string, int> parse_kinds(const std::string& s) {
  std::map<std::string, int> k;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ',')) {
    const auto c = item.find(':');
    k[item.substr(0, c)] = std::stoi(item.substr(c + 1));
  }
  return k;
}

}  // namespace

TEST_CASE("corpus: uvmesh info --no-heal matches MANIFEST for every CAD model", "[io][corpus]") {
  int models = 0;
  for (const Row& r : manifest()) {
    if (r.at("file").rfind("cad/", 0) != 0) continue;
    ++models;
    INFO(r.at("file"));
    const Run x = run("info --json --no-heal " + kData + "/" + r.at("file"));
    INFO(x.err);
    REQUIRE(x.rc == 0);
    const json j = json::parse(x.out);
    CHECK(j["counts"]["faces"] == std::stoi(r.at("n_faces")));
    CHECK(j["counts"]["edges"] == std::stoi(r.at("n_edges")));
    CHECK(j["counts"]["solids"] == std::stoi(r.at("n_solids")));
    CHECK(j["surface_kinds"].get<std::map<std::string, int>>() == parse_kinds(r.at("kinds")));
    CHECK(j["bbox"]["diagonal"].get<double>() == Approx(std::stod(r.at("bbox_diag"))).epsilon(1e-5));
    const std::string& notes = r.at("notes");
    CHECK(j["short_edges"] == note_count(notes, "edges shorter than 1e-3"));
    CHECK(j["free_edges"] == note_count(notes, "free \\(boundary\\) edges"));
    CHECK(j["non_manifold_edges"] == note_count(notes, "non-manifold edges"));
    CHECK(j["degenerate_edges"] == note_count(notes, "degenerated edges"));
    CHECK(j["faces_with_seams"] == note_count(notes, "faces with seam edges"));
    CHECK(j["invalid_faces"].empty() == (notes.find("INVALID") == std::string::npos));
    CHECK(j["healing"]["steps"].empty());
  }
  CHECK(models >= 70);
}

TEST_CASE("corpus: with healing, every difference from MANIFEST is reported by a healing step", "[io][corpus][heal]") {
  int sewn = 0;
  for (const Row& r : manifest()) {
    if (r.at("file").rfind("cad/", 0) != 0) continue;
    INFO(r.at("file"));
    // --no-check: validity is covered by the --no-heal test; this one is about counts.
    const Run x = run("info --json --no-check " + kData + "/" + r.at("file"));
    INFO(x.err);
    REQUIRE(x.rc == 0);
    const json j = json::parse(x.out);
    CHECK_FALSE(j["validity_checked"].get<bool>());
    int faces = std::stoi(r.at("n_faces")), edges = std::stoi(r.at("n_edges")), solids = std::stoi(r.at("n_solids"));
    const json& steps = j["healing"]["steps"];
    REQUIRE_FALSE(steps.empty());
    CHECK(steps[0]["name"] == "shapefix");
    for (const json& s : steps) {
      INFO(s["name"].get<std::string>());
      CHECK(s["faces_before"] == faces);  // each step starts from what the previous left
      CHECK(s["edges_before"] == edges);
      CHECK(s["solids_before"] == solids);
      if (s["applied"].get<bool>()) {
        faces = s["faces_after"];
        edges = s["edges_after"];
        solids = s["solids_after"];
        if (s["name"] == "sewing") {
          ++sewn;
          CHECK(s["free_edges_after"].get<int>() < s["free_edges_before"].get<int>());
        }
      }
    }
    CHECK(j["counts"]["faces"] == faces);
    CHECK(j["counts"]["edges"] == edges);
    CHECK(j["counts"]["solids"] == solids);
    // Healing never drops a face or a solid (regression: sewing dissolved the 5 solids of
    // occt_caxif_k1.stp, ShapeFix dropped one of dagmc_ball_reactor.brep's 8).
    CHECK(faces >= std::stoi(r.at("n_faces")));
    CHECK(solids >= std::stoi(r.at("n_solids")));
  }
  CHECK(sewn >= 5);  // the unsewn IGES / face-set models of the corpus
}

TEST_CASE("corpus: the loose faces named by the issue get sewn", "[io][corpus][heal]") {
  for (const std::string f : {"cad/occt_bearing.igs", "cad/gmsh_sewfaces.step"}) {
    INFO(f);
    const Run x = run("info --json " + kData + "/" + f);
    REQUIRE(x.rc == 0);
    const json j = json::parse(x.out);
    bool sewing = false;
    for (const json& s : j["healing"]["steps"])
      if (s["name"] == "sewing" && s["applied"].get<bool>()) sewing = true;
    CHECK(sewing);
  }
  // occt_bearing.igs: 925 free edges as read, 25 after sewing (real boundaries).
  const json j = json::parse(run("info --json " + kData + "/cad/occt_bearing.igs").out);
  CHECK(j["free_edges"].get<int>() < 50);
}

TEST_CASE("corpus: --conform imprints touching solids on each other", "[io][corpus][conform]") {
  const Run x = run("info --json --conform " + kData + "/cad/dagmc_two_cubes.stp");
  REQUIRE(x.rc == 0);
  const json j = json::parse(x.out);
  // Two cubes sharing a face: 12 faces / 24 edges as two separate solids, 11 / 20 once the
  // interface is one shared face.
  CHECK(j["counts"]["solids"] == 2);
  CHECK(j["counts"]["faces"] == 11);
  CHECK(j["counts"]["edges"] == 20);
  bool reported = false;
  for (const json& s : j["healing"]["steps"])
    if (s["name"] == "conform" && s["applied"].get<bool>()) reported = true;
  CHECK(reported);
}

TEST_CASE("bad inputs: each gives its clean error or loads, never a crash", "[io][bad]") {
  // Expected outcome per file, from MANIFEST's `expect:` notes. Errors: substring of the
  // message. Loads: the counts.
  struct Expect {
    bool loads;
    std::string message;
  };
  const std::map<std::string, Expect> expect = {
      {"bad/nist_ftc_08_tessellated.stp", {false, "no B-rep faces"}},
      {"bad/occt_bad_header.igs", {true, ""}},
      {"bad/occt_bearing_axis.brep", {true, ""}},
      {"bad/occt_corrupted.stp", {true, ""}},
      {"bad/synth_empty.step", {false, "empty"}},
      {"bad/synth_truncated.stp", {false, "truncated"}},
      {"bad/synth_garbage.stp", {false, "not a CAD file"}},
      {"bad/synth_bad_ref.step", {false, "dangling reference: entity #14 references #999999"}},
      {"bad/synth_huge_coord.step", {false, "CARTESIAN_POINT #164"}},
      {"bad/synth_iges_no_param.igs", {false, "Parameter Data (P) section is missing"}},
      {"bad/synth_step_as_iges.igs", {false, "wrong extension"}},
  };
  int seen = 0;
  for (const Row& r : manifest()) {
    if (r.at("file").rfind("bad/", 0) != 0) continue;
    ++seen;
    INFO(r.at("file"));
    const auto it = expect.find(r.at("file"));
    REQUIRE(it != expect.end());  // a new bad file needs an expectation here
    const bool manifest_loads = r.at("notes").find("expect: loads") != std::string::npos;
    CHECK(manifest_loads == it->second.loads);
    const Run x = run("info --json --no-heal " + kData + "/" + r.at("file"));
    if (it->second.loads) {
      INFO(x.err);
      REQUIRE(x.rc == 0);
      const json j = json::parse(x.out);
      CHECK(j["counts"]["faces"] == std::stoi(r.at("n_faces")));
      CHECK(j["counts"]["edges"] == std::stoi(r.at("n_edges")));
      CHECK(j["counts"]["solids"] == std::stoi(r.at("n_solids")));
      if (r.at("notes").find("INVALID") != std::string::npos) CHECK_FALSE(j["invalid_faces"].empty());
    } else {
      CHECK(x.rc == 2);
      CHECK(x.out.empty());
      CHECK(x.err.find(r.at("file")) != std::string::npos);  // names the file
      CHECK(x.err.find(it->second.message) != std::string::npos);
      CHECK(std::count(x.err.begin(), x.err.end(), '\n') == 1);  // one line
    }
  }
  CHECK(seen == static_cast<int>(expect.size()));
  // Reading by content is an explicit choice.
  CHECK(run("info --json --any-extension " + kData + "/bad/synth_step_as_iges.igs").rc == 0);
  CHECK(run("info --json --partial " + kData + "/bad/synth_bad_ref.step").rc == 0);
  CHECK(run("info " + kData + "/does/not/exist.step").rc == 2);
}

TEST_CASE("bad inputs: a NaN coordinate never reaches OCC", "[io][bad]") {
  // axom_tet.step with one coordinate replaced by NaN (a plain OCC STEP import of such a
  // file crashes).
  std::string text = slurp(kData + "/cad/axom_tet.step");
  const std::string from = "#160=CARTESIAN_POINT('',(-1.03,";
  const auto p = text.find(from);
  REQUIRE(p != std::string::npos);
  text.replace(p, from.size(), "#160=CARTESIAN_POINT('',(NaN,");
  const std::string path = std::string(UVMESH_BINARY_DIR) + "/tests/io/nan_coordinate.step";
  std::ofstream(path) << text;
  const uvmesh::io::ReadResult r = uvmesh::io::read_cad(path);
  CHECK_FALSE(r.ok);
  CHECK(r.error.find("#160") != std::string::npos);
  CHECK(r.error.find("NaN") != std::string::npos);
  const Run x = run("info " + path);
  CHECK(x.rc == 2);
  std::remove(path.c_str());
}
