// Helpers for the cli2d tests: scratch directories, running the uvmesh2d executable,
// small hand-made meshes.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "uvmesh/mesher2d/mesher2d.h"

namespace cli2d_test {

namespace fs = std::filesystem;

// A fresh directory under the build tree, removed at the end of the test.
class ScratchDir {
 public:
  explicit ScratchDir(const std::string& tag) {
    static int counter = 0;
    path_ = fs::path(UVMESH_BINARY_DIR) / "tests-tmp" /
            ("cli2d-" + tag + "-" + std::to_string(::getpid()) + "-" + std::to_string(counter++));
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  std::string operator/(const std::string& name) const { return (path_ / name).string(); }
  const fs::path& path() const { return path_; }
  // Every file name in the directory (to check that no output or temporary was left).
  std::vector<std::string> files() const {
    std::vector<std::string> r;
    for (const auto& e : fs::directory_iterator(path_)) r.push_back(e.path().filename().string());
    return r;
  }

 private:
  fs::path path_;
};

inline std::string read_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_file(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

inline std::string quote(const std::string& s) {
  std::string q = "'";
  for (char c : s) {
    if (c == '\'')
      q += "'\\''";
    else
      q += c;
  }
  return q + "'";
}

struct RunResult {
  int status = -1;  // exit status, -1 if killed by a signal
  std::string out, err;
};

// Runs uvmesh2d with the given (already quoted) arguments in `dir`'s files.
inline RunResult run_uvmesh2d(const ScratchDir& dir, const std::string& args) {
  const std::string out = dir / ".stdout", err = dir / ".stderr";
  const std::string cmd = quote(UVMESH2D_EXE) + " " + args + " >" + quote(out) + " 2>" + quote(err);
  const int rc = std::system(cmd.c_str());
  RunResult r;
  r.status = WIFEXITED(rc) ? WEXITSTATUS(rc) : -1;
  r.out = read_file(out);
  r.err = read_file(err);
  std::error_code ec;
  fs::remove(out, ec);
  fs::remove(err, ec);
  return r;
}

inline std::string sample(const std::string& name) {
  return std::string(UVMESH_SOURCE_DIR) + "/samples/data/" + name;
}

// Unit square cut along its diagonal: 4 vertices (markers 1..4), 2 CCW triangles in
// components 0 and 1 with attributes 7 and 8, 4 boundary edges (markers 11..14).
inline uvmesh::m2d::Mesh square_mesh() {
  uvmesh::m2d::Mesh m;
  m.vertices = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  m.vertex_markers = {1, 2, 3, 4};
  m.triangles = {{0, 1, 2}, {0, 2, 3}};
  m.triangle_region = {0, 1};
  m.triangle_attribute = {7, 8};
  m.boundary_edges = {{0, 1, 11}, {1, 2, 12}, {2, 3, 13}, {3, 0, 14}};
  return m;
}

// n x n grid on [0,1]^2 with awkward coordinates (1/3-like values exercise exact round trip).
inline uvmesh::m2d::Mesh grid_mesh(int n) {
  uvmesh::m2d::Mesh m;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      m.vertices.push_back({static_cast<double>(i) / n, static_cast<double>(j) / n});
      m.vertex_markers.push_back(i == 0 || j == 0 || i == n || j == n ? 1 : 0);
    }
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int v = j * (n + 1) + i;
      m.triangles.push_back({v, v + 1, v + n + 2});
      m.triangles.push_back({v, v + n + 2, v + n + 1});
      m.triangle_region.push_back(0);
      m.triangle_region.push_back(0);
      m.triangle_attribute.push_back(0);
      m.triangle_attribute.push_back(0);
    }
  for (int i = 0; i < n; ++i) {
    m.boundary_edges.push_back({i, i + 1, 1});
    m.boundary_edges.push_back({n * (n + 1) + i, n * (n + 1) + i + 1, 3});
    m.boundary_edges.push_back({i * (n + 1), (i + 1) * (n + 1), 4});
    m.boundary_edges.push_back({i * (n + 1) + n, (i + 1) * (n + 1) + n, 2});
  }
  return m;
}

}  // namespace cli2d_test
