// libFuzzer target: bytes -> uvmesh::io::read_mesh_data for one format (compiled once per
// format, UVMESH_FUZZ_FORMAT_<name>). A finding is a crash, a sanitizer report, a hang or
// an out-of-memory (a count in the file must not size an allocation before the data is
// there), or a mesh reported ok whose indices or per-element arrays are inconsistent.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "uvmesh/io/mesh_reader.h"

namespace {

using uvmesh::io::MeshFormat;

#if defined(UVMESH_FUZZ_FORMAT_msh)
constexpr MeshFormat kFormat = MeshFormat::Msh41;  // reads 4.1 ASCII/binary and 2.2
#elif defined(UVMESH_FUZZ_FORMAT_medit)
constexpr MeshFormat kFormat = MeshFormat::Medit;
#elif defined(UVMESH_FUZZ_FORMAT_meshb)
constexpr MeshFormat kFormat = MeshFormat::Meshb;
#elif defined(UVMESH_FUZZ_FORMAT_stl)
constexpr MeshFormat kFormat = MeshFormat::Stl;
#elif defined(UVMESH_FUZZ_FORMAT_obj)
constexpr MeshFormat kFormat = MeshFormat::Obj;
#elif defined(UVMESH_FUZZ_FORMAT_ply)
constexpr MeshFormat kFormat = MeshFormat::Ply;
#elif defined(UVMESH_FUZZ_FORMAT_drc)
constexpr MeshFormat kFormat = MeshFormat::Drc;
#else
#error "define UVMESH_FUZZ_FORMAT_<msh|medit|meshb|stl|obj|ply|drc>"
#endif

[[noreturn]] void finding(const std::string& what) {
  std::fprintf(stderr, "fuzz_mesh_reader: inconsistent mesh reported ok: %s\n", what.c_str());
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string bytes(reinterpret_cast<const char*>(data), size);
  const uvmesh::io::MeshReadResult r = uvmesh::io::read_mesh_data(bytes, kFormat, "fuzz");
  if (!r.ok) {
    if (r.error.empty()) finding("not ok but no error message");
    return 0;
  }
  const auto& m = r.mesh;
  const std::size_t np = m.points.size();
  for (const auto& t : m.triangles)
    for (const auto v : t)
      if (v < 0 || static_cast<std::size_t>(v) >= np)
        finding("triangle vertex " + std::to_string(v) + " of " + std::to_string(np));
  for (const auto& s : m.segments)
    if (s.a < 0 || s.b < 0 || static_cast<std::size_t>(s.a) >= np ||
        static_cast<std::size_t>(s.b) >= np)
      finding("segment vertex out of range");
  if (m.triangle_face.size() != m.triangles.size()) finding("triangle_face size");
  if (m.point_dim.size() != np || m.point_entity.size() != np)
    finding("point_dim/point_entity size");
  return 0;
}
