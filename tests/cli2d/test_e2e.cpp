// End-to-end runs of the uvmesh2d executable. Bad inputs: exit status, one message naming
// file and line, and no output file (nor temporary) left behind. Good inputs: outputs
// agree with the JSON record and pass the mesher's checker.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <map>
#include <nlohmann/json.hpp>

#include "cli2d_test_util.h"
#include "uvmesh2d/medit.h"

using cli2d_test::quote;
using cli2d_test::RunResult;
using cli2d_test::ScratchDir;

namespace {

const char* kSquare =
    "4 2 0 1\n"
    "1 0 0 1\n"
    "2 1 0 1\n"
    "3 1 1 1\n"
    "4 0 1 1\n"
    "4 1\n"
    "1 1 2 1\n"
    "2 2 3 2\n"
    "3 3 4 3\n"
    "4 4 1 4\n"
    "0\n";

// Runs a command that must fail: checks the status, that stderr is one line containing
// every `needle`, and that the directory holds only the files that were there before.
void expect_failure(const ScratchDir& dir, const std::string& args, int status,
                    const std::vector<std::string>& needles) {
  const std::vector<std::string> before = dir.files();
  const RunResult r = cli2d_test::run_uvmesh2d(dir, args);
  INFO("args: " << args << "\nstderr: " << r.err);
  CHECK(r.status == status);
  CHECK(r.out.empty());
  REQUIRE_FALSE(r.err.empty());
  CHECK(r.err.find('\n') == r.err.size() - 1);  // exactly one line
  for (const std::string& n : needles) CHECK_THAT(r.err, Catch::Contains(n));
  std::vector<std::string> after = dir.files();
  std::sort(after.begin(), after.end());
  std::vector<std::string> expect = before;
  std::sort(expect.begin(), expect.end());
  CHECK(after == expect);
}

}  // namespace

TEST_CASE("e2e: input errors exit 2 with file:line and write nothing", "[cli2d][e2e][errors]") {
  ScratchDir dir("e2e-input");
  const std::string out = quote(dir / "out.mesh");
  auto poly = [&](const std::string& name, const std::string& text) {
    cli2d_test::write_file(dir / name, text);
    return quote(dir / name);
  };

  SECTION("missing input file") {
    expect_failure(dir, quote(dir / "missing.poly") + " -o " + out, 2,
                   {dir / "missing.poly", "cannot open"});
  }
  SECTION("malformed line") {
    const std::string p = poly("bad.poly", "4 2 0 0\n1 0 0\n2 1 0 oops\n");
    expect_failure(dir, p + " -o " + out, 2, {dir / "bad.poly:3:", "node 2: expected 3 fields"});
  }
  SECTION("index out of range") {
    std::string t = "40 2 0 0\n";
    for (int i = 1; i <= 40; ++i)
      t += std::to_string(i) + " " + std::to_string(i) + " " + std::to_string(i * i % 11) + "\n";
    t += "3 0\n1 1 2\n2 2 3\n3 3 57\n0\n";
    const std::string p = poly("range.poly", t);
    expect_failure(dir, p + " -o " + out, 2,
                   {dir / "range.poly:45: segment 3 references node 57, but there are 40 nodes"});
  }
  SECTION("NaN and Inf") {
    const std::string p = poly("nan.poly", "3 2 0 0\n1 0 0\n2 NaN 0\n3 0 1\n0 0\n0\n");
    expect_failure(dir, p + " -o " + out, 2,
                   {dir / "nan.poly:3:", "node 2 x coordinate is 'NaN'; numbers must be finite"});
    const std::string q = poly("inf.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n0 0\n1\n1 inf 0\n");
    expect_failure(dir, q + " -o " + out, 2, {dir / "inf.poly:7:", "hole 1 x coordinate is 'inf'"});
  }
  SECTION("empty PSLG") {
    const std::string p = poly("empty.poly", "# nothing here\n0 2 0 0\n0 0\n0\n");
    expect_failure(dir, p + " -o " + out, 2, {dir / "empty.poly:2:", "PSLG is empty"});
  }
  SECTION("duplicate segment ids") {
    const std::string p =
        poly("dup.poly", "3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n3 0\n1 1 2\n2 2 3\n2 3 1\n0\n");
    expect_failure(dir, p + " -o " + out, 2,
                   {dir / "dup.poly:8:", "segment 2 is defined twice (first at line 7)"});
  }
  SECTION("an existing output is left untouched") {
    cli2d_test::write_file(dir / "out.mesh", "old contents");
    const std::string p = poly("bad2.poly", "3 2 0 0\n1 0 0\n");
    expect_failure(dir, p + " -o " + out, 2, {dir / "bad2.poly:2:", "unexpected end of file"});
    CHECK(cli2d_test::read_file(dir / "out.mesh") == "old contents");
  }
}

TEST_CASE("e2e: usage errors exit 2 before any work", "[cli2d][e2e][errors]") {
  ScratchDir dir("e2e-usage");
  cli2d_test::write_file(dir / "sq.poly", kSquare);
  const std::string in = quote(dir / "sq.poly");

  SECTION("unknown output extension, even next to a valid one") {
    expect_failure(dir, in + " -o " + quote(dir / "good.mesh") + " -o " + quote(dir / "bad.vtk"), 2,
                   {"bad.vtk", "unknown extension", ".mesh"});
  }
  SECTION("unwritable output path") {
    expect_failure(
        dir, in + " -o " + quote(dir / "a.msh") + " -o " + quote(dir / "no/such/dir/out.mesh"), 2,
        {dir / "no/such/dir/out.mesh", "cannot write here"});
  }
  SECTION("output is a directory") {
    cli2d_test::fs::create_directory(dir / "d.svg");
    expect_failure(dir, in + " -o " + quote(dir / "d.svg"), 2, {dir / "d.svg", "is a directory"});
  }
  SECTION("the same output twice") {
    expect_failure(dir, in + " -o " + quote(dir / "a.msh") + " -o " + quote(dir / "a.msh"), 2,
                   {"given twice"});
  }
  SECTION("negative, zero and NaN sizes") {
    expect_failure(dir, in + " --size -0.1 -o " + quote(dir / "a.msh"), 2,
                   {"--size must be a finite number > 0"});
    expect_failure(dir, in + " --size 0 -o " + quote(dir / "a.msh"), 2,
                   {"--size must be a finite number > 0"});
    expect_failure(dir, in + " --size nan -o " + quote(dir / "a.msh"), 2, {"--size"});
    expect_failure(dir, in + " --metric-fn ring:0,0.1 -o " + quote(dir / "a.msh"), 2,
                   {"sizes must be finite and > 0"});
    expect_failure(dir, in + " --metric-fn bl:0.1,0.01 -o " + quote(dir / "a.msh"), 2,
                   {"h0 must not exceed hmax"});
    expect_failure(dir, in + " --metric-fn wave:1 -o " + quote(dir / "a.msh"), 2,
                   {"unknown size field 'wave'"});
  }
  SECTION("conflicting size options and bad flags") {
    expect_failure(dir, in + " --size 0.1 --metric-fn uniform:0.1", 2, {"excludes"});
    expect_failure(dir, in + " --frobnicate", 2, {"frobnicate"});
    expect_failure(dir, "", 2, {"input"});
  }
  SECTION("bad background metric files") {
    cli2d_test::write_file(dir / "bg.mesh",
                           "MeshVersionFormatted 2\nDimension 2\nVertices 3\n0 0 0\n1 0 0\n0 1 "
                           "0\nTriangles 1\n1 2 3 0\nEnd\n");
    cli2d_test::write_file(
        dir / "bg.sol",
        "MeshVersionFormatted 2\nDimension 2\nSolAtVertices 3 1 3\n1 0 1\n1 0 1\n1 5 1\nEnd\n");
    expect_failure(dir,
                   in + " --metric " + quote(dir / "bg.mesh") + " " + quote(dir / "bg.sol") +
                       " -o " + quote(dir / "a.msh"),
                   2, {dir / "bg.sol:6:", "not positive definite"});
    expect_failure(dir,
                   in + " --metric " + quote(dir / "bg.mesh") + " " + quote(dir / "nope.sol") +
                       " -o " + quote(dir / "a.msh"),
                   2, {dir / "nope.sol", "cannot open"});
  }
}

TEST_CASE("e2e: meshing failures exit 3 and write nothing", "[cli2d][e2e][errors]") {
  ScratchDir dir("e2e-mesh");
  SECTION("open boundary around a hole") {
    // Three sides of a square and a hole seed inside: the hole leaks to the outside.
    cli2d_test::write_file(
        dir / "open.poly",
        "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n3 0\n1 1 2\n2 2 3\n3 3 4\n1\n1 0.5 0.5\n");
    expect_failure(
        dir,
        quote(dir / "open.poly") + " -o " + quote(dir / "o.mesh") + " -o " + quote(dir / "o.svg"),
        3, {dir / "open.poly", "OpenBoundary"});
  }
  SECTION("crossing segments name the file's segments and lines") {
    cli2d_test::write_file(dir / "cross.poly",
                           "4 2 0 0\n1 0 0\n2 1 0\n3 1 1\n4 0 1\n6 0\n1 1 2\n2 2 3\n3 3 4\n4 4 "
                           "1\n15 1 3\n16 2 4\n0\n");
    expect_failure(dir, quote(dir / "cross.poly") + " -o " + quote(dir / "c.msh"), 3,
                   {"CrossingSegments", "segment 15 (" + dir / "cross.poly:11)",
                    "segment 16 (" + dir / "cross.poly:12)"});
    // With --split-crossing it meshes.
    const RunResult r = cli2d_test::run_uvmesh2d(
        dir, quote(dir / "cross.poly") + " --split-crossing -q -o " + quote(dir / "c.msh"));
    CHECK(r.status == 0);
    CHECK(cli2d_test::fs::exists(dir / "c.msh"));
  }
}

TEST_CASE("e2e: square with --json: record, outputs and counts agree", "[cli2d][e2e]") {
  ScratchDir dir("e2e-json");
  cli2d_test::write_file(dir / "sq.poly", kSquare);
  const RunResult r = cli2d_test::run_uvmesh2d(
      dir, quote(dir / "sq.poly") + " --size 0.1 --json --check -o " + quote(dir / "sq.mesh") +
               " -o " + quote(dir / "sq.msh") + " -o " + quote(dir / "sq.svg"));
  INFO(r.err);
  REQUIRE(r.status == 0);
  CHECK_THAT(r.err, Catch::Contains("triangles") && Catch::Contains("wrote"));
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["status"] == "Ok");
  CHECK(j["size"] == "uniform:0.1");
  const auto nv = j["vertices"].get<std::size_t>(), nt = j["triangles"].get<std::size_t>();
  CHECK(nt > 150);  // unit square at h = 0.1: about 2 / (sqrt(3)/4 * 0.01) = 230 triangles
  CHECK(nt < 400);
  CHECK(j["seconds"]["total"].get<double>() >= 0);
  CHECK(j["seconds"].size() >= 2);
  const auto& q = j["quality"];
  CHECK(q["euclidean"]["Q_M"].get<double>() >= 1.0);
  CHECK(q["euclidean"]["share_Q_below_2"].get<double>() >=
        q["euclidean"]["share_Q_below_1_5"].get<double>());
  CHECK(q["euclidean"]["share_Q_below_2"].get<double>() <= 1.0);
  CHECK(q["metric"]["min_angle_deg"].get<double>() > 0);
  CHECK(q["euclidean"]["max_angle_deg"].get<double>() < 180);
  CHECK(q["unit_edge_share"].get<double>() > 0.5);

  // The .mesh holds what the record says; edge references are the segment markers.
  const auto m = uvmesh::cli2d::read_medit_mesh(dir / "sq.mesh");
  REQUIRE(m.ok());
  CHECK(m.mesh.vertices.size() == nv);
  CHECK(m.mesh.triangles.size() == nt);
  CHECK(m.mesh.edges.size() == j["boundary_edges"].get<std::size_t>());
  for (int ref : m.mesh.edge_refs) CHECK((ref >= 1 && ref <= 4));
  for (int ref : m.mesh.triangle_refs) CHECK(ref == 1);  // one component, no regions
  const std::string msh = cli2d_test::read_file(dir / "sq.msh");
  CHECK_THAT(msh, Catch::StartsWith("$MeshFormat\n2.2 0 8\n"));
  const std::string svg = cli2d_test::read_file(dir / "sq.svg");
  CHECK_THAT(svg, Catch::Contains("<svg") && Catch::EndsWith("</svg>\n"));
  std::vector<std::string> files = dir.files();
  std::sort(files.begin(), files.end());
  CHECK(files ==
        std::vector<std::string>{"sq.mesh", "sq.msh", "sq.poly", "sq.svg"});  // no temporaries
}

TEST_CASE("e2e: --quiet prints nothing, --no-refine keeps the input vertices", "[cli2d][e2e]") {
  ScratchDir dir("e2e-quiet");
  const RunResult r = cli2d_test::run_uvmesh2d(
      dir, quote(cli2d_test::sample("square_hole.poly")) + " --no-refine --quiet --json");
  REQUIRE(r.status == 0);
  CHECK(r.err.empty());
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["vertices"] == 68);
  CHECK(j["boundary_edges"] == 68);
}

TEST_CASE("e2e: every sample with every kind of size field passes the checker", "[cli2d][e2e]") {
  ScratchDir dir("e2e-samples");
  const std::string bg = quote(cli2d_test::sample("bg_square.mesh"));
  const std::vector<std::pair<std::string, std::string>> runs = {
      {"square_hole.poly", "--size 0.04"},
      {"square_hole.poly", "--metric-fn linear:0.01,0.08"},
      {"square_hole.poly", "--metric-fn ring:0.005,0.08"},
      {"square_hole.poly", "--metric " + bg + " " + quote(cli2d_test::sample("bg_square.sol"))},
      {"square_hole.poly", "--metric " + bg + " " + quote(cli2d_test::sample("bg_square_h.sol"))},
      {"square_hole.poly", "--metric-fn bl:0.005,0.1 --no-optimize"},
      {"two_regions.poly", ""},
      {"two_regions.poly", "--size 0.05"},
      {"key.poly", "--size 0.03"},
      {"key.poly", "--metric-fn uniform:0.05"},
  };
  for (const auto& [file, opts] : runs) {
    const RunResult r = cli2d_test::run_uvmesh2d(
        dir, quote(cli2d_test::sample(file)) + " " + opts + " --check --json -q -o " +
                 quote(dir / "o.mesh") + " -o " + quote(dir / "o.svg"));
    INFO(file << " " << opts << "\n" << r.err);
    REQUIRE(r.status == 0);
    const auto j = nlohmann::json::parse(r.out);
    const auto m = uvmesh::cli2d::read_medit_mesh(dir / "o.mesh");
    REQUIRE(m.ok());
    CHECK(m.mesh.triangles.size() == j["triangles"].get<std::size_t>());
    CHECK(j["quality"]["metric"]["Q_M"].get<double>() >= 1);
  }
}

TEST_CASE("e2e: two_regions: regional attributes become references, maximum area is applied",
          "[cli2d][e2e]") {
  ScratchDir dir("e2e-regions");
  const RunResult r = cli2d_test::run_uvmesh2d(
      dir, quote(cli2d_test::sample("two_regions.poly")) + " -q -o " + quote(dir / "r.mesh"));
  REQUIRE(r.status == 0);
  const auto m = uvmesh::cli2d::read_medit_mesh(dir / "r.mesh");
  REQUIRE(m.ok());
  // Areas per reference: region 1 is [0,1]x[0,1] (the wavy interface has zero net area),
  // region 2 the rest minus the hexagonal hole of circumradius 0.2.
  std::map<int, double> area;
  std::map<int, int> count;
  for (std::size_t i = 0; i < m.mesh.triangles.size(); ++i) {
    const auto& t = m.mesh.triangles[i];
    const auto a = m.mesh.vertices[static_cast<std::size_t>(t[0])],
               b = m.mesh.vertices[static_cast<std::size_t>(t[1])],
               c = m.mesh.vertices[static_cast<std::size_t>(t[2])];
    area[m.mesh.triangle_refs[i]] += 0.5 * ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x));
    ++count[m.mesh.triangle_refs[i]];
  }
  REQUIRE(area.size() == 2);
  CHECK(area[1] == Approx(1.0).epsilon(1e-9));
  CHECK(area[2] == Approx(1.0 - 1.5 * std::sqrt(3.0) * 0.04).epsilon(1e-9));
  // Region 2's maximum area 0.002: its mean triangle area is around that, and far below
  // region 1's (sizes from the boundary there).
  CHECK(area[2] / count[2] < 0.004);
  CHECK(area[1] / count[1] > 4 * area[2] / count[2]);
}

TEST_CASE("e2e: an Incomplete mesh is written, with a warning and status 0", "[cli2d][e2e]") {
  ScratchDir dir("e2e-incomplete");
  const RunResult r = cli2d_test::run_uvmesh2d(
      dir, quote(cli2d_test::sample("square_hole.poly")) +
               " --size 0.01 --max-vertices 500 --json -o " + quote(dir / "i.mesh"));
  REQUIRE(r.status == 0);
  CHECK_THAT(r.err, Catch::Contains("warning: the mesh is incomplete"));
  const auto j = nlohmann::json::parse(r.out);
  CHECK(j["status"] == "Incomplete");
  const auto m = uvmesh::cli2d::read_medit_mesh(dir / "i.mesh");
  REQUIRE(m.ok());
  CHECK(m.mesh.triangles.size() == j["triangles"].get<std::size_t>());
  CHECK(m.mesh.vertices.size() < 2000);  // far from the ~18000 of a complete mesh at h = 0.01
}

TEST_CASE("e2e: the local feature size is on by default, --no-feature-size turns it off",
          "[cli2d][e2e][feature_size]") {
  // A 10-pointed star whose spikes (0.19 wide at the base) are narrower than the size 0.3:
  // by default they get triangles as wide as they are (mesher2d measured 97.8% with
  // Q < 1.5 in both field-point modes), without the cap needles across them (24-32%).
  ScratchDir dir("e2e-lfs");
  std::string poly = "20 2 0 1\n";
  for (int i = 0; i < 20; ++i) {
    const double a = 3.14159265358979323846 * i / 10, r = i % 2 == 0 ? 1.0 : 0.3;
    poly += std::to_string(i + 1) + " " + std::to_string(r * std::cos(a)) + " " +
            std::to_string(r * std::sin(a)) + " 1\n";
  }
  poly += "20 1\n";
  for (int i = 0; i < 20; ++i)
    poly += std::to_string(i + 1) + " " + std::to_string(i + 1) + " " +
            std::to_string((i + 1) % 20 + 1) + " 1\n";
  poly += "0\n";
  cli2d_test::write_file(dir / "star.poly", poly);
  for (const char* mode : {"", " --frontal"}) {
    INFO("mode:" << mode);
    const RunResult on = cli2d_test::run_uvmesh2d(
        dir, quote(dir / "star.poly") + " --size 0.3 --json --check" + mode);
    const RunResult off = cli2d_test::run_uvmesh2d(
        dir, quote(dir / "star.poly") + " --size 0.3 --json --check --no-feature-size" + mode);
    INFO(on.err << off.err);
    REQUIRE(on.status == 0);
    REQUIRE(off.status == 0);
    const auto jon = nlohmann::json::parse(on.out), joff = nlohmann::json::parse(off.out);
    const double son = jon["quality"]["euclidean"]["share_Q_below_1_5"].get<double>();
    const double soff = joff["quality"]["euclidean"]["share_Q_below_1_5"].get<double>();
    INFO("share Q < 1.5: on " << son << ", off " << soff);
    CHECK(son >= 0.95);
    CHECK(soff < 0.5);
    CHECK(jon["seconds"].contains("feature size"));
    CHECK(!joff["seconds"].contains("feature size"));
  }
}
