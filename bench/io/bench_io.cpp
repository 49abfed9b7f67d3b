// bench_io: write time and file size of every mesh format for one large mesh, and Draco's
// compression against binary STL and PLY with the largest position error (bench/io/run.sh).
//
//   bench_io MESH.msh [--model MODEL] [--repeat N] [--dir DIR]   -> Markdown tables on stdout
//
// The mesh is read once (io::read_mesh); with --model the writers get the model too (the
// .msh entities and physical groups, the .glb per-solid meshes), as `uvmesh mesh` does.
// Each write is timed N times (default 3) and the fastest is kept: the machine is shared,
// and the minimum is the least disturbed measure of the writer itself.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <limits>
#include <string>
#include <unordered_map>
#include <vector>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/mesh_reader.h"
#include "uvmesh/io/mesh_writer.h"

using namespace uvmesh;
namespace fs = std::filesystem;

namespace {

struct Written {
  double seconds = 0;
  std::uintmax_t bytes = 0;
};

Written write_timed(const surface::SurfaceMesh& m, const geom::Model* model,
                    const std::string& path, const io::WriteOptions& o, int repeat) {
  Written w;
  w.seconds = std::numeric_limits<double>::infinity();
  for (int i = 0; i < repeat; ++i) {
    const auto t0 = std::chrono::steady_clock::now();
    const io::WriteResult r = io::write_mesh(m, model, path, o);
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (!r.ok) {
      std::cerr << "bench_io: " << r.error << "\n";
      std::exit(1);
    }
    w.seconds = std::min(w.seconds, s);
  }
  w.bytes = fs::file_size(path);
  return w;
}

// Largest distance from a decoded point to the nearest original point, through a uniform
// grid of cell `h` (h at least the largest expected error, so the 27 neighbour cells
// hold the nearest point).
double max_position_error(const surface::SurfaceMesh& orig, const surface::SurfaceMesh& dec,
                          double h) {
  auto key = [h](const geom::Vec3& p, int dx, int dy, int dz) {
    const auto c = [h](double v, int d) {
      return static_cast<std::int64_t>(std::floor(v / h)) + d;
    };
    return (c(p.x, dx) * 73856093) ^ (c(p.y, dy) * 19349663) ^ (c(p.z, dz) * 83492791);
  };
  std::unordered_multimap<std::int64_t, std::size_t> grid;
  grid.reserve(orig.points.size());
  for (std::size_t i = 0; i < orig.points.size(); ++i)
    grid.emplace(key(orig.points[i], 0, 0, 0), i);
  double worst = 0;
  for (const geom::Vec3& p : dec.points) {
    double best = std::numeric_limits<double>::infinity();
    for (int dx = -1; dx <= 1; ++dx)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dz = -1; dz <= 1; ++dz) {
          auto [a, b] = grid.equal_range(key(p, dx, dy, dz));
          for (; a != b; ++a) best = std::min(best, glm::distance(p, orig.points[a->second]));
        }
    worst = std::max(worst, best);
  }
  return worst;
}

std::string mib(std::uintmax_t b) {
  char s[32];
  std::snprintf(s, sizeof s, "%.2f", static_cast<double>(b) / (1024.0 * 1024.0));
  return s;
}

}  // namespace

int main(int argc, char** argv) {
  std::string mesh_path, model_path, dir = "bench_io_out";
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--model" && i + 1 < argc)
      model_path = argv[++i];
    else if (a == "--repeat" && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else if (a == "--dir" && i + 1 < argc)
      dir = argv[++i];
    else if (mesh_path.empty())
      mesh_path = a;
    else {
      std::cerr << "usage: bench_io MESH.msh [--model MODEL] [--repeat N] [--dir DIR]\n";
      return 1;
    }
  }
  if (mesh_path.empty()) {
    std::cerr << "usage: bench_io MESH.msh [--model MODEL] [--repeat N] [--dir DIR]\n";
    return 1;
  }
  const io::MeshReadResult mr = io::read_mesh(mesh_path);
  if (!mr.ok) {
    std::cerr << "bench_io: " << mr.error << "\n";
    return 1;
  }
  io::ReadResult cad;
  if (!model_path.empty()) {
    cad = io::read_cad(model_path, {});
    if (!cad.ok) {
      std::cerr << "bench_io: " << cad.error << "\n";
      return 1;
    }
  }
  const geom::Model* model = cad.ok ? &cad.model : nullptr;
  const surface::SurfaceMesh& m = mr.mesh;
  fs::create_directories(dir);

  std::cout << "Mesh: " << m.points.size() << " points, " << m.triangles.size() << " triangles, "
            << m.segments.size() << " segments; fastest of " << repeat << " writes.\n\n";
  std::cout << "| format | encoding | file | MiB | bytes/triangle | write s | M triangles/s "
               "|\n|---|---|---|---:|---:|---:|---:|\n";
  struct Row {
    const char* name;
    const char* file;
    io::MeshFormat fmt;
    io::Encoding enc;
  };
  const Row rows[] = {
      {"Gmsh 4.1", "m.msh", io::MeshFormat::Msh41, io::Encoding::Ascii},
      {"Gmsh 4.1", "mb.msh", io::MeshFormat::Msh41, io::Encoding::Binary},
      {"Gmsh 2.2", "m22.msh", io::MeshFormat::Msh22, io::Encoding::Ascii},
      {"Medit", "m.mesh", io::MeshFormat::Medit, io::Encoding::Ascii},
      {"Medit", "m.meshb", io::MeshFormat::Meshb, io::Encoding::Binary},
      {"STL", "m.stl", io::MeshFormat::Stl, io::Encoding::Binary},
      {"STL", "ma.stl", io::MeshFormat::Stl, io::Encoding::Ascii},
      {"OBJ", "m.obj", io::MeshFormat::Obj, io::Encoding::Ascii},
      {"PLY", "m.ply", io::MeshFormat::Ply, io::Encoding::Binary},
      {"PLY", "ma.ply", io::MeshFormat::Ply, io::Encoding::Ascii},
      {"VTK legacy", "m.vtk", io::MeshFormat::Vtk, io::Encoding::Ascii},
      {"VTK legacy", "mb.vtk", io::MeshFormat::Vtk, io::Encoding::Binary},
      {"VTK XML", "m.vtu", io::MeshFormat::Vtu, io::Encoding::Binary},
      {"TetGen", "m.poly", io::MeshFormat::Poly, io::Encoding::Ascii},
      {"TetGen", "m.smesh", io::MeshFormat::Smesh, io::Encoding::Ascii},
      {"Draco 14 bits", "m.drc", io::MeshFormat::Drc, io::Encoding::Binary},
      {"glTF+Draco 14 bits", "m.glb", io::MeshFormat::Glb, io::Encoding::Binary},
  };
  const double nt = static_cast<double>(m.triangles.size());
  for (const Row& r : rows) {
    io::WriteOptions o;
    o.format = r.fmt;
    o.encoding = r.enc;
    const Written w = write_timed(m, model, (fs::path(dir) / r.file).string(), o, repeat);
    char line[256];
    std::snprintf(line, sizeof line, "| %s | %s | %s | %s | %.1f | %.3f | %.2f |\n", r.name,
                  r.enc == io::Encoding::Binary ? "binary" : "ASCII", r.file, mib(w.bytes).c_str(),
                  static_cast<double>(w.bytes) / nt, w.seconds, nt / 1e6 / w.seconds);
    std::cout << line;
  }
  const std::uintmax_t stl = fs::file_size(fs::path(dir) / "m.stl"),
                       ply = fs::file_size(fs::path(dir) / "m.ply");

  geom::Box3 box;
  for (const auto& p : m.points) box.add(p);
  const geom::Vec3 ext = box.hi - box.lo;
  const double extent = std::max({ext.x, ext.y, ext.z});
  std::cout << "\nDraco (compression level 10 = smallest, 7 = default) against binary STL ("
            << mib(stl) << " MiB) and binary PLY (" << mib(ply) << " MiB). Largest extent "
            << extent
            << "; max error = largest distance from a decoded .drc vertex to its original (bound: "
               "sqrt(3)/2 * extent / (2^bits - 1)).\n\n";
  std::cout
      << "| bits | level | .drc KiB | .glb KiB | STL / .drc | STL / .glb | PLY / .glb | write .glb "
         "s | max error | bound | error / extent | points merged | triangles collapsed |\n"
         "|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|\n";
  double goal_ratio = 0;
  for (int bits : {11, 14, 16})
    for (int level : {7, 10}) {
      io::WriteOptions o;
      o.draco_bits = bits;
      o.draco_level = level;
      const std::string drc = (fs::path(dir) / ("q.drc")).string(),
                        glb = (fs::path(dir) / ("q.glb")).string();
      const Written wd = write_timed(m, model, drc, o, 1);
      const Written wg = write_timed(m, model, glb, o, repeat);
      const io::MeshReadResult d = io::read_mesh(drc);
      if (!d.ok) {
        std::cerr << "bench_io: " << d.error << "\n";
        return 1;
      }
      const double step = extent / ((1 << bits) - 1);
      const double bound = 0.5 * std::sqrt(3.0) * step;
      const double err = max_position_error(m, d.mesh, 2.0 * step);
      // Points closer than a quantization step land on one grid point: the decoded mesh
      // has fewer points, and triangles spanning such a pair collapse.
      std::size_t collapsed = 0;
      for (const auto& t : d.mesh.triangles)
        collapsed += t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
      char line[400];
      std::snprintf(line, sizeof line,
                    "| %d | %d | %.0f | %.0f | %.1f | %.1f | %.1f | %.3f | %.3g | %.3g | %.2g | "
                    "%zu | %zu |\n",
                    bits, level, static_cast<double>(wd.bytes) / 1024.0,
                    static_cast<double>(wg.bytes) / 1024.0,
                    static_cast<double>(stl) / static_cast<double>(wd.bytes),
                    static_cast<double>(stl) / static_cast<double>(wg.bytes),
                    static_cast<double>(ply) / static_cast<double>(wg.bytes), wg.seconds, err,
                    bound, err / extent, m.points.size() - d.mesh.points.size(), collapsed);
      std::cout << line;
      if (bits == 14 && level == 7)
        goal_ratio = static_cast<double>(stl) / static_cast<double>(wg.bytes);
    }
  std::printf(
      "\nGoal: .glb+Draco at 14 bits (default level 7) at most 1/8 of binary STL: it is 1/%.1f, "
      "%s.\n",
      goal_ratio, goal_ratio >= 8.0 ? "met" : "NOT met");
  return 0;
}
