// Shared by the io tests (test_mesh_writer.cpp, test_mesh_formats.cpp): a hand-built cube
// mesh and model, a scratch directory, and the reference readers (meshio, Gmsh,
// grade_mesh.py) run as child processes whose "@key value" lines are collected.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <charconv>
#include <cmath>
#include <cstdio>
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

namespace uvmesh_test {

using namespace uvmesh;
namespace fs = std::filesystem;

using Lattice = std::array<int, 3>;

struct Cube {
  geom::Model model;
  surface::SurfaceMesh mesh;
};

// Unit cube, lattice step 1/n (n >= 1). Model ids: vertex = x + 2y + 4z over the corner
// bits; edge along axis a = 4a + 2*b + c with b, c the corner bits of axes a+1, a+2;
// face with axis a fixed at side s = 2a + s. Faces at s = 0 are reversed (their
// natural normal sigma_u x sigma_v = +e_a points inward), as OCC gives them.
inline Cube make_cube(int n) {
  Cube c;
  geom::Model& md = c.model;
  surface::SurfaceMesh& m = c.mesh;
  std::map<Lattice, surface::NodeId> node;
  auto add = [&](Lattice p, int dim, int entity, double t) {
    node[p] = static_cast<surface::NodeId>(m.points.size());
    m.points.push_back(geom::Vec3(p[0], p[1], p[2]) / double(n));
    m.point_dim.push_back(static_cast<std::int8_t>(dim));
    m.point_entity.push_back(entity);
    m.point_t.push_back(t);
  };
  auto corner = [n](int v) { return Lattice{(v & 1) * n, ((v >> 1) & 1) * n, ((v >> 2) & 1) * n}; };
  auto vertex_id = [n](Lattice p) { return p[0] / n + 2 * (p[1] / n) + 4 * (p[2] / n); };

  for (int v = 0; v < 8; ++v) {
    md.vertices.push_back({geom::Vec3(corner(v)[0], corner(v)[1], corner(v)[2]) / double(n), 1e-7});
    add(corner(v), 0, v, 0.0);
  }
  for (int e = 0; e < 12; ++e) {
    const int a = e / 4;
    Lattice p{};
    p[(a + 1) % 3] = ((e >> 1) & 1) * n;
    p[(a + 2) % 3] = (e & 1) * n;
    geom::Edge edge;
    edge.range = {0.0, 1.0};
    edge.length = 1.0;
    edge.v0 = vertex_id(p);
    std::vector<surface::NodeId> chain{node.at(p)};
    for (int i = 1; i < n; ++i) {
      p[a] = i;
      add(p, 1, e, double(i) / n);
      chain.push_back(node.at(p));
    }
    p[a] = n;
    edge.v1 = vertex_id(p);
    chain.push_back(node.at(p));
    for (std::size_t i = 0; i + 1 < chain.size(); ++i)
      m.segments.push_back({chain[i], chain[i + 1], e});
    md.edges.push_back(edge);
  }
  // The edge between two lattice corners and whether a walk from p to q runs against it.
  auto edge_use = [n](Lattice p, Lattice q) {
    int a = 0;
    while (p[a] == q[a]) ++a;
    geom::EdgeUse use;
    use.edge = 4 * a + 2 * (p[(a + 1) % 3] / n) + p[(a + 2) % 3] / n;
    use.reversed = p[a] > q[a];
    return use;
  };
  for (int f = 0; f < 6; ++f) {
    const int a = f / 2, u = (a + 1) % 3, w = (a + 2) % 3;
    auto at = [&](int iu, int iw) {
      Lattice p{};
      p[a] = (f & 1) * n;
      p[u] = iu;
      p[w] = iw;
      return p;
    };
    for (int iw = 1; iw < n; ++iw)
      for (int iu = 1; iu < n; ++iu) add(at(iu, iw), 2, f, 0.0);
    geom::Face face;
    face.reversed = (f & 1) == 0;
    face.shell = 0;
    geom::Loop loop;
    loop.outer = true;
    const Lattice ring[4] = {at(0, 0), at(n, 0), at(n, n), at(0, n)};  // counter-clockwise in (u,v)
    for (int i = 0; i < 4; ++i) loop.uses.push_back(edge_use(ring[i], ring[(i + 1) % 4]));
    face.loops.push_back(loop);
    md.faces.push_back(face);
    for (int iw = 0; iw < n; ++iw)
      for (int iu = 0; iu < n; ++iu) {
        const surface::NodeId p00 = node.at(at(iu, iw)), p10 = node.at(at(iu + 1, iw)),
                              p11 = node.at(at(iu + 1, iw + 1)), p01 = node.at(at(iu, iw + 1));
        // Counter-clockwise in (u,v) is along +e_a; reversed faces are flipped (outward).
        if (face.reversed) {
          m.triangles.push_back({p00, p11, p10});
          m.triangles.push_back({p00, p01, p11});
        } else {
          m.triangles.push_back({p00, p10, p11});
          m.triangles.push_back({p00, p11, p01});
        }
        m.triangle_face.push_back(f);
        m.triangle_face.push_back(f);
      }
  }
  md.shells.push_back({{0, 1, 2, 3, 4, 5}, true});
  md.solids.push_back({{0}, "cube"});
  md.format = "analytic";
  return c;
}

struct TempDir {
  fs::path path;
  explicit TempDir(const std::string& name = "mesh_writer") {
    path = fs::temp_directory_path() / ("uvmesh_test_" + name + "_" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~TempDir() {
    std::error_code ec;
    fs::permissions(path, fs::perms::owner_all, fs::perm_options::add, ec);
    fs::remove_all(path, ec);
  }
  std::string file(const std::string& name) const { return (path / name).string(); }
  std::vector<std::string> entries() const {
    std::vector<std::string> names;
    for (const auto& e : fs::directory_iterator(path))
      names.push_back(e.path().filename().string());
    std::sort(names.begin(), names.end());
    return names;
  }
};

// The Debian interpreter: Debian's python3-meshio and python3-gmsh are installed for it,
// while a python3 earlier on PATH (pyenv, a venv) may not see them.
inline std::string python() {
  return fs::exists("/usr/bin/python3") ? "/usr/bin/python3" : "python3";
}

inline std::string quoted(const std::string& s) {
  std::string q = "'";
  for (char ch : s) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

struct Run {
  int status = -1;
  std::string out;  // stdout and stderr
};

inline Run run(const std::string& cmd) {
  Run r;
  FILE* p = ::popen((cmd + " 2>&1").c_str(), "r");
  if (!p) return r;
  char buf[4096];
  std::size_t n;
  while ((n = std::fread(buf, 1, sizeof buf, p)) > 0) r.out.append(buf, n);
  const int st = ::pclose(p);
  r.status = WIFEXITED(st) ? WEXITSTATUS(st) : -1;
  return r;
}

// The reader script prints its findings as "@key values..." lines (tool chatter is
// interleaved on the same stream and ignored).
inline constexpr const char* kReader = R"PY(
import sys
mode, path = sys.argv[1], sys.argv[2]
def xyz(p):
    print("@xyz", repr(float(p[0])), repr(float(p[1])), repr(float(p[2])))
if mode == "meshio":
    import meshio
    m = meshio.read(path)
    print("@points", len(m.points))
    for kind in ("vertex", "line", "triangle"):
        print("@" + kind, sum(len(c.data) for c in m.cells if c.type == kind))
    for p in m.points:
        xyz(p)
    for name, blocks in m.cell_data.items():
        if not name.startswith("gmsh:"):
            print("@cell_data", name, " ".join(str(int(v)) for b in blocks for v in b.ravel()))
elif mode == "gmsh":
    import gmsh
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.open(path)
    for d in range(4):
        print("@entities%d" % d, len(gmsh.model.getEntities(d)))
    for d, name in ((0, "vertex"), (1, "line"), (2, "triangle")):
        types, tags, _ = gmsh.model.mesh.getElements(d)
        print("@" + name, sum(len(t) for t in tags))
    for _, t in gmsh.model.getEntities(2):
        b = gmsh.model.getBoundary([(2, t)], combined=False, oriented=True)
        types, tags, _ = gmsh.model.mesh.getElements(2, t)
        print("@surface", t, sum(len(x) for x in tags), " ".join(str(bt) for _, bt in b))
    for _, t in gmsh.model.getEntities(1):
        b = gmsh.model.getBoundary([(1, t)], combined=False, oriented=True)
        print("@curve", t, " ".join(str(bt) for _, bt in b))
    for _, t in gmsh.model.getEntities(3):
        b = gmsh.model.getBoundary([(3, t)], combined=False, oriented=False)
        print("@volume", t, " ".join(str(bt) for _, bt in b))
    tags, coords, _ = gmsh.model.mesh.getNodes()
    print("@points", len(tags))
    for i in sorted(range(len(tags)), key=lambda i: tags[i]):
        print("@node", int(tags[i]))
        xyz(coords[3 * i:3 * i + 3])
    gmsh.finalize()
)PY";

struct Reading {
  Run run;
  std::multimap<std::string, std::string> lines;  // "@key" -> rest of the line
  long count(const std::string& key) const {
    auto it = lines.find(key);
    return it == lines.end() ? -1 : std::stol(it->second);
  }
  std::vector<std::string> all(const std::string& key) const {
    std::vector<std::string> v;
    for (auto [it, end] = lines.equal_range(key); it != end; ++it) v.push_back(it->second);
    return v;
  }
};

inline Reading read_back(const TempDir& dir, const std::string& mode, const std::string& file) {
  const std::string script = dir.file("reader.py");
  if (!fs::exists(script)) std::ofstream(script) << kReader;
  Reading r;
  r.run = run(python() + " " + quoted(script) + " " + mode + " " + quoted(file));
  std::istringstream in(r.run.out);
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] != '@') continue;
    const std::size_t sp = line.find(' ');
    r.lines.emplace(line.substr(0, sp), sp == std::string::npos ? "" : line.substr(sp + 1));
  }
  if (r.run.status != 0) FAIL(mode << " could not read " << file << ":\n" << r.run.out);
  return r;
}

// The "@key n" counts a reader printed.
inline void check_counts(const Reading& r,
                         std::initializer_list<std::pair<const char*, long>> expected) {
  INFO(r.run.out);
  for (const auto& [key, n] : expected) {
    INFO(key);
    CHECK(r.count(key) == n);
  }
}

// Writes and requires success.
inline void write_ok(const surface::SurfaceMesh& m, const geom::Model* model,
                     const std::string& path, const io::WriteOptions& opts = {}) {
  const io::WriteResult w = io::write_mesh(m, model, path, opts);
  INFO(w.error);
  REQUIRE(w.ok);
}

// The coordinates a reader printed (Python repr: shortest round-trip form), parsed
// exactly with from_chars.
inline std::vector<geom::Vec3> coordinates(const Reading& r) {
  std::vector<geom::Vec3> pts;
  for (const std::string& s : r.all("@xyz")) {
    geom::Vec3 p;
    const char* b = s.data();
    const char* e = s.data() + s.size();
    for (int k = 0; k < 3; ++k) {
      while (b < e && *b == ' ') ++b;
      auto res = std::from_chars(b, e, p[k]);
      if (res.ec != std::errc()) return {};
      b = res.ptr;
    }
    pts.push_back(p);
  }
  return pts;
}

inline std::vector<geom::Vec3> sorted(std::vector<geom::Vec3> v) {
  std::sort(v.begin(), v.end(), [](const geom::Vec3& a, const geom::Vec3& b) {
    return std::tie(a.x, a.y, a.z) < std::tie(b.x, b.y, b.z);
  });
  return v;
}

// A number field of grade_mesh.py's one-line JSON ("key": value); NaN when absent.
inline double json_number(const std::string& json, const std::string& key) {
  const std::size_t k = json.find("\"" + key + "\":");
  if (k == std::string::npos) return std::nan("");
  return std::strtod(json.c_str() + k + key.size() + 3, nullptr);
}

inline std::string grade_mesh_script() {
  return (fs::path(UVMESH_SHARED_DATA).parent_path() / "tools" / "grade_mesh.py").string();
}

// grade_mesh.py on a written cube: closed, consistently oriented, outward (volume +1).
inline void check_closed_cube(const std::string& path) {
  const Run r =
      run(python() + " " + quoted(grade_mesh_script()) + " " + quoted(path) + " --no-tetgen");
  INFO("grade_mesh.py " << path << ": " << r.out);
  REQUIRE(r.status == 0);
  CHECK(json_number(r.out, "free_edges") == 0);
  CHECK(json_number(r.out, "nonmanifold_edges") == 0);
  CHECK(json_number(r.out, "inconsistent_orientation_edges") == 0);
  CHECK(json_number(r.out, "volume") == Approx(1.0));
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), {});
}

}  // namespace uvmesh_test
