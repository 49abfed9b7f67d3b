// End-to-end tests of surface::mesh_model on corpus models: success, conformity
// (every edge of a closed solid's mesh shared by exactly two triangles, consistently
// oriented), quality and unit edges.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <map>
#include <string>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;

namespace {

std::string data(const std::string& rel) { return std::string(UVMESH_SHARED_DATA) + "/" + rel; }

struct Topo {
  int free = 0, nonmanifold = 0, misoriented = 0;
};

Topo topo(const surface::SurfaceMesh& m) {
  std::map<std::pair<int, int>, int> dir;
  for (const auto& t : m.triangles)
    for (int i = 0; i < 3; ++i) dir[{t[i], t[(i + 1) % 3]}]++;
  Topo r;
  for (const auto& [e, n] : dir) {
    const auto it = dir.find({e.second, e.first});
    const int back = it == dir.end() ? 0 : it->second;
    if (e.first > e.second && back > 0) continue;
    if (n + back == 1) ++r.free;
    if (n + back > 2) ++r.nonmanifold;
    if (n > 1 || back > 1) ++r.misoriented;
  }
  return r;
}

}  // namespace

TEST_CASE("dev: mesh one model from UVMESH_DEV_MODEL", "[.dev]") {
  const char* path = std::getenv("UVMESH_DEV_MODEL");
  REQUIRE(path);
  io::ReadResult rr = io::read_cad(path);
  REQUIRE(rr.ok);
  surface::MeshOptions o;
  o.size = surface::default_size(rr.model);
  if (const char* th = std::getenv("UVMESH_DEV_THREADS")) o.threads = std::atoi(th);
  const auto r = surface::mesh_model(rr.model, o);
  const Topo t = topo(r.mesh);
  WARN("faces " << rr.model.faces.size() << " failed " << r.failed.size() << " points " << r.mesh.points.size()
                << " tris " << r.mesh.triangles.size() << " free " << t.free << " nonman " << t.nonmanifold
                << " misoriented " << t.misoriented);
  for (const auto& s : r.stages) WARN(s.name << " " << s.seconds);
  for (const auto& f : r.failed) WARN("face " << f.face << ": " << f.reason);
}
