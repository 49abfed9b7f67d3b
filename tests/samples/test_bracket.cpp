// The bundled sample samples/data/bracket.step is what `make_bracket` makes, and it is
// the clean model the README's set-up meshes:
//  - `uvmesh info --json` on the bundled file: 1 solid, a closed shell, 0 free and 0
//    non-manifold edges, every face valid, millimetres, planes + cylinders + tori;
//  - `make_bracket` run again into a temporary folder gives a model with the same
//    topology counts and surface kinds as the bundled file;
//  - an unwritable output gives one error line, a non-zero exit and no file.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

const std::string kUvmesh = UVMESH_EXE;
const std::string kMakeBracket = MAKE_BRACKET_EXE;
const std::string kBundled = std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step";

struct Run {
  int rc = -1;
  std::string out, err;
};

std::string slurp(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// A fresh folder under the system temp dir, removed when the test ends.
struct TempDir {
  fs::path path;
  TempDir() {
    path = fs::temp_directory_path() / ("uvmesh_test_bracket_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

Run run(const std::string& exe, const std::string& args, const fs::path& dir) {
  const fs::path out = dir / "run.out", err = dir / "run.err";
  const std::string cmd =
      "timeout 300 " + exe + " " + args + " >" + out.string() + " 2>" + err.string();
  const int st = std::system(cmd.c_str());
  Run r;
  r.rc = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  r.out = slurp(out);
  r.err = slurp(err);
  return r;
}

json info(const std::string& model, const fs::path& dir) {
  const Run r = run(kUvmesh, "info --json " + model, dir);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  return json::parse(r.out);
}

}  // namespace

TEST_CASE("bracket: the bundled bracket.step is one clean closed solid in mm",
          "[samples][bracket]") {
  TempDir tmp;
  REQUIRE(fs::exists(kBundled));
  const json j = info(kBundled, tmp.path);
  CHECK(j["counts"]["solids"] == 1);
  CHECK(j["counts"]["shells"] == 1);
  CHECK(j["open_shells"] == 0);
  CHECK(j["free_edges"] == 0);
  CHECK(j["non_manifold_edges"] == 0);
  CHECK(j["invalid_faces"].empty());
  CHECK(j["units"] == "mm");
  const int faces = j["counts"]["faces"];
  CHECK(faces >= 20);
  CHECK(faces <= 60);
  const auto kinds = j["surface_kinds"].get<std::map<std::string, int>>();
  CHECK(kinds.count("planar") == 1);
  CHECK(kinds.count("cylinder") == 1);
  CHECK(kinds.count("torus") == 1);
  const double diag = j["bbox"]["diagonal"];
  CHECK(diag > 100.0);
  CHECK(diag < 200.0);
}

TEST_CASE("bracket: make_bracket regenerates the bundled model (same counts and kinds)",
          "[samples][bracket]") {
  TempDir tmp;
  const fs::path out = tmp.path / "bracket.step";
  const Run r = run(kMakeBracket, out.string(), tmp.path);
  INFO(r.err);
  REQUIRE(r.rc == 0);
  CHECK(r.err.empty());
  REQUIRE(fs::exists(out));
  // Written through a temporary file that is renamed: nothing else is left behind.
  int files = 0;
  for (const auto& e : fs::directory_iterator(tmp.path))
    if (e.path().filename().string().rfind("bracket.step", 0) == 0) ++files;
  CHECK(files == 1);

  const json fresh = info(out.string(), tmp.path);
  const json bundled = info(kBundled, tmp.path);
  for (const char* k : {"faces", "edges", "vertices", "shells", "solids"}) {
    INFO(k);
    CHECK(fresh["counts"][k] == bundled["counts"][k]);
  }
  CHECK(fresh["surface_kinds"] == bundled["surface_kinds"]);
  CHECK(fresh["curve_kinds"] == bundled["curve_kinds"]);
  CHECK(fresh["free_edges"] == 0);
  CHECK(fresh["units"] == bundled["units"]);
  CHECK(fresh["bbox"]["diagonal"].get<double>() ==
        Approx(bundled["bbox"]["diagonal"].get<double>()).epsilon(1e-9));
}

TEST_CASE("bracket: an unwritable output is one error line, exit 1, no file",
          "[samples][bracket]") {
  TempDir tmp;
  const fs::path out = tmp.path / "no_such_dir" / "bracket.step";
  const Run r = run(kMakeBracket, out.string(), tmp.path);
  CHECK(r.rc == 1);
  CHECK(r.err.rfind("make_bracket: error: ", 0) == 0);
  CHECK(std::count(r.err.begin(), r.err.end(), '\n') == 1);
  CHECK_FALSE(fs::exists(tmp.path / "no_such_dir"));

  const Run usage = run(kMakeBracket, "", tmp.path);
  CHECK(usage.rc == 1);
  CHECK_FALSE(usage.err.empty());
}
