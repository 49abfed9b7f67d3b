// The whole corpus through the `uvmesh` program, as a user runs it:
//  - `uvmesh info --json --no-heal`: face / edge / solid counts, surface kinds and
//    bounding-box diagonal equal MANIFEST.tsv's; the defects its notes list (short,
//    free, non-manifold, degenerated edges, faces with seams, BRepCheck INVALID) too;
//  - with healing on, every difference from the MANIFEST is accounted for by a reported
//    healing step;
//  - every file in bad/ gives its expected outcome: a clean one-line error naming the
//    file and the defect with exit code 2, or a load with the MANIFEST counts;
//  - a NaN coordinate (the input that crashes a plain OCC import) is rejected;
//  - the model keeps the file's length unit (MANIFEST's bounding boxes are in mm: compared
//    through the reported factor), `--units` converts by exactly the declared factor.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
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
  const std::string base =
      std::string(UVMESH_BINARY_DIR) + "/tests/io/run_" + std::to_string(::getpid());
  const std::string cmd =
      "timeout 300 " + kExe + " " + args + " >" + base + ".out 2>" + base + ".err";
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

// Millimetres per unit of the reported coordinates; 1 for unitless BREP (MANIFEST takes
// BREP coordinates as they are stored).
double mm_per_unit(const json& j) {
  return j["unit_in_mm"].is_null() ? 1.0 : j["unit_in_mm"].get<double>();
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
    // Coordinates are in the file's unit; MANIFEST's diagonal is in mm (BREP: as stored).
    CHECK(j["bbox"]["diagonal"].get<double>() * mm_per_unit(j) ==
          Approx(std::stod(r.at("bbox_diag"))).epsilon(1e-5));
    if (j["format"] == "brep") {
      CHECK(j["units"] == "unitless");
    } else {
      CHECK(j["units"] ==
            j["file_units"]);  // every STEP / IGES file of the corpus declares a known unit
      CHECK_FALSE(j["units_converted"].get<bool>());
      CHECK(j["unit_in_m"].get<double>() == Approx(j["unit_in_mm"].get<double>() / 1000.0));
    }
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

TEST_CASE("corpus: with healing, every difference from MANIFEST is reported by a healing step",
          "[io][corpus][heal]") {
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
    int faces = std::stoi(r.at("n_faces")), edges = std::stoi(r.at("n_edges")),
        solids = std::stoi(r.at("n_solids"));
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

TEST_CASE(
    "corpus: gaps of ~1e-5 of the diagonal close by retried sewing (gmsh_t106_blade, occt_hammer)",
    "[io][corpus][heal]") {
  // Sewn once at 1e-6 of the diagonal, t106_blade kept 2 free edges and hammer 2: copies
  // of one curve on two faces, ~1e-5 of the diagonal apart. Meshed unsewn, the two
  // discretizations of the curve crossed each other: 42 and 29 self-intersections. The
  // retries at 1e-5 and 1e-4 close them; --sew-max-tol equal to --sew-tol sews once.
  for (const std::string f : {"cad/gmsh_t106_blade.step", "cad/occt_hammer.igs"}) {
    INFO(f);
    const json j = json::parse(run("info --json " + kData + "/" + f).out);
    CHECK(j["free_edges"].get<int>() == 0);
    const json once = json::parse(run("info --json --sew-max-tol 1e-6 " + kData + "/" + f).out);
    CHECK(once["free_edges"].get<int>() == 2);
  }
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

TEST_CASE(
    "corpus: --conform keeps the shells and faces outside the solids and refuses a fuse that opens "
    "a solid (occt_caxif_k1)",
    "[io][corpus][conform]") {
  // occt_caxif_k1: 5 closed solids, 9 open shells and 4 loose faces. The general fuse of
  // the solids used to be the whole result: 50 of the 94 faces were dropped without a word
  // and the bounding box shrank from 52.6 to 35.7 cm. The fuse itself, on these solids,
  // returns two solids with free edges the input does not have (OCC alerts: intersection of
  // a pair of shapes failed, unable to orient): it is refused with a warning.
  const Run plain = run("info --json --no-heal " + kData + "/cad/occt_caxif_k1.stp");
  const Run x = run("info --json --conform " + kData + "/cad/occt_caxif_k1.stp");
  REQUIRE(plain.rc == 0);
  REQUIRE(x.rc == 0);
  const json p = json::parse(plain.out);
  const json j = json::parse(x.out);
  CHECK(j["counts"]["faces"] == p["counts"]["faces"]);
  CHECK(j["counts"]["solids"] == p["counts"]["solids"]);
  CHECK(j["bbox"]["diagonal"].get<double>() ==
        Approx(p["bbox"]["diagonal"].get<double>()).epsilon(1e-6));
  bool refused = false;
  for (const json& s : j["healing"]["steps"])
    if (s["name"] == "conform") refused = !s["applied"].get<bool>();
  CHECK(refused);
  bool warned = false;
  for (const json& w : j["warnings"])
    if (w.get<std::string>().find("not kept: it would leave 2 solid(s) with free edges") !=
        std::string::npos)
      warned = true;
  CHECK(warned);
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
      if (r.at("notes").find("INVALID") != std::string::npos)
        CHECK_FALSE(j["invalid_faces"].empty());
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

namespace {

// Vertices of two readings of the same file: b == a * factor, to rounding.
void check_scaled(const uvmesh::geom::Model& a, const uvmesh::geom::Model& b, double factor) {
  REQUIRE(a.vertices.size() == b.vertices.size());
  REQUIRE_FALSE(a.vertices.empty());
  const double size = a.bbox.diagonal() * factor;
  double worst = 0.0;
  for (std::size_t i = 0; i < a.vertices.size(); ++i) {
    const uvmesh::geom::Vec3& p = a.vertices[i].p;
    const uvmesh::geom::Vec3& q = b.vertices[i].p;
    worst = std::max({worst, std::abs(p.x * factor - q.x), std::abs(p.y * factor - q.y),
                      std::abs(p.z * factor - q.z)});
  }
  CHECK(worst <= 1e-12 * size);
}

}  // namespace

TEST_CASE("units: a STEP file in centimetres keeps its unit; --units mm scales by exactly 10",
          "[io][units]") {
  const std::string f = kData + "/cad/axom_tet.step";
  const Run native = run("info --json --no-heal " + f);
  const Run mm = run("info --json --no-heal --units mm " + f);
  REQUIRE(native.rc == 0);
  REQUIRE(mm.rc == 0);
  const json a = json::parse(native.out), b = json::parse(mm.out);
  CHECK(a["units"] == "cm");
  CHECK(a["file_units"] == "cm");
  CHECK(a["file_units_declared"] == "centimetre");
  CHECK(a["unit_in_mm"].get<double>() == 10.0);
  CHECK(a["unit_in_m"].get<double>() == Approx(0.01));
  CHECK_FALSE(a["units_converted"].get<bool>());
  CHECK(b["units"] == "mm");
  CHECK(b["file_units"] == "cm");
  CHECK(b["unit_in_mm"].get<double>() == 1.0);
  CHECK(b["units_converted"].get<bool>());
  // The tetrahedron's corners are (+-1, +-1, +-1) in the file: read as they are.
  for (int k = 0; k < 3; ++k) {
    CHECK(a["bbox"]["min"][k].get<double>() == Approx(-1.0).margin(1e-6));
    CHECK(a["bbox"]["max"][k].get<double>() == Approx(1.0).margin(1e-6));
  }
  CHECK(b["bbox"]["diagonal"].get<double>() ==
        Approx(10.0 * a["bbox"]["diagonal"].get<double>()).epsilon(1e-6));
  CHECK(native.out.find("\"warnings\": []") != std::string::npos);

  // Vertex by vertex through the library: the file's numbers exactly, and x 10 in mm.
  uvmesh::io::ReadOptions o;
  o.heal = false;
  o.check_validity = false;
  const uvmesh::io::ReadResult rc = uvmesh::io::read_cad(f, o);
  o.units = "millimetre";
  const uvmesh::io::ReadResult rm = uvmesh::io::read_cad(f, o);
  REQUIRE(rc.ok);
  REQUIRE(rm.ok);
  CHECK(rc.model.units == "cm");
  CHECK(rm.model.units == "mm");
  for (const auto& v : rc.model.vertices)
    for (const double x : {v.p.x, v.p.y, v.p.z}) CHECK(std::abs(x) == 1.0);
  check_scaled(rc.model, rm.model, 10.0);
  // Tolerances do not scale: OCC gives vertices its Precision::Confusion() (1e-7) in
  // whatever unit the model is in, and only enlarges them where the geometry needs it.
  for (std::size_t i = 0; i < rc.model.vertices.size(); ++i)
    CHECK(rc.model.vertices[i].tol == rm.model.vertices[i].tol);
}

TEST_CASE(
    "units: inch STEP, metre and inch IGES keep their unit; conversions use the declared factor",
    "[io][units]") {
  struct Case {
    const char* file;
    const char* unit;
    double mm;
  };
  for (const Case c : {Case{"cad/gmsh_crankshaft.stp", "inch", 25.4},
                       Case{"cad/dealii_wigley_hull.igs", "m", 1000.0},
                       Case{"cad/gmsh_model1.igs", "inch", 25.4}}) {
    INFO(c.file);
    uvmesh::io::ReadOptions o;
    o.heal = false;
    o.check_validity = false;
    const uvmesh::io::ReadResult native = uvmesh::io::read_cad(kData + "/" + c.file, o);
    REQUIRE(native.ok);
    CHECK(native.model.units == c.unit);
    CHECK(native.report.file_units == c.unit);
    CHECK(native.report.mm_per_unit == c.mm);
    CHECK_FALSE(native.report.units_converted);
    o.units = "mm";
    const uvmesh::io::ReadResult mm = uvmesh::io::read_cad(kData + "/" + c.file, o);
    REQUIRE(mm.ok);
    CHECK(mm.model.units == "mm");
    CHECK(mm.report.units_converted);
    check_scaled(native.model, mm.model, c.mm);
    o.units = "cm";  // a unit that is neither the file's nor OCC's default
    const uvmesh::io::ReadResult cm = uvmesh::io::read_cad(kData + "/" + c.file, o);
    REQUIRE(cm.ok);
    CHECK(cm.model.units == "cm");
    check_scaled(native.model, cm.model, c.mm / 10.0);
  }
}

TEST_CASE(
    "units: BREP is unitless; --units is reported as ignored there; unknown units are refused",
    "[io][units]") {
  const Run x =
      run("info --json --no-heal --no-check --units mm " + kData + "/cad/occt_bottle.brep");
  REQUIRE(x.rc == 0);
  const json j = json::parse(x.out);
  CHECK(j["units"] == "unitless");
  CHECK(j["unit_in_mm"].is_null());
  CHECK(j["file_units"] == "");
  bool warned = false;
  for (const json& w : j["warnings"])
    if (w.get<std::string>().find("no length unit") != std::string::npos) warned = true;
  CHECK(warned);
  const Run t = run("info --no-heal --no-check " + kData + "/cad/occt_bottle.brep");
  CHECK(t.out.find("units: unitless") != std::string::npos);
  const Run s = run("info --no-heal --no-check " + kData + "/cad/axom_tet.step");
  CHECK(s.out.find("units: cm (1 cm = 10 mm = 0.01 m)") != std::string::npos);

  CHECK(run("info --units furlong " + kData + "/cad/axom_tet.step").rc != 0);
  uvmesh::io::ReadOptions o;
  o.units = "furlong";
  const uvmesh::io::ReadResult r = uvmesh::io::read_cad(kData + "/cad/axom_tet.step", o);
  CHECK_FALSE(r.ok);
  CHECK(r.error.find("unknown length unit") != std::string::npos);
}
