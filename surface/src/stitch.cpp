// Stage 3 of mesh_model: stitch. Face points are appended in face order after the
// vertex and edge nodes; triangles refer to global ids. Memory is watched here because
// the face meshes and the whole output coexist while stitching.
#include <algorithm>
#if defined(__GLIBC__)
#include <malloc.h>
#endif

#include "model_run.h"

namespace uvmesh::surface::detail {

namespace {

// Gives the pages of freed heap memory back to the system. glibc keeps freed blocks (the face
// meshes are many small vectors, allocated in the worker threads' arenas), so without it the
// resident size never falls while stitching copies them into the output.
void release_freed_memory() {
#if defined(__GLIBC__)
  malloc_trim(0);
#endif
}

// Peak memory (bench/memory): the output arrays are sized once instead of doubling as
// they grow (a doubling holds 1.5-3x the final array; a reservation is not resident until
// written), and the memory of the face meshes and of the meshers' working sets is given
// back as they are freed. Measured by bench/memory/run.sh.
void reserve_output(ModelRun& run) {
  SurfaceMesh& M = run.res.mesh;
  std::size_t add_points = 0, add_tris = 0;
  for (std::size_t f = 0; f < run.nf; ++f)
    if (run.meshed(f)) add_points += run.fm[f].points.size(), add_tris += run.fm[f].tris.size();
  M.points.reserve(M.points.size() + add_points);
  M.point_dim.reserve(M.points.capacity());
  M.point_entity.reserve(M.points.capacity());
  M.point_t.reserve(M.points.capacity());
  M.triangles.reserve(add_tris);
  M.triangle_face.reserve(add_tris);
  M.triangle_uv.reserve(add_tris);
}

// Face f's points and triangles appended to the output; returns the bytes of its mesh.
std::size_t append_face(SurfaceMesh& M, std::size_t f, const FaceMesh& F) {
  const auto base = static_cast<NodeId>(M.points.size());
  for (std::size_t k = 0; k < F.points.size(); ++k) {
    M.points.push_back(F.points[k]);
    M.point_dim.push_back(2);
    M.point_entity.push_back(static_cast<geom::Id>(f));
    M.point_t.push_back(0.0);
  }
  for (std::size_t t = 0; t < F.tris.size(); ++t) {
    std::array<NodeId, 3> g{};
    for (int i = 0; i < 3; ++i)
      g[i] = F.tris[t][i] >= 0 ? F.tris[t][i] : base + (-F.tris[t][i] - 1);
    M.triangles.push_back(g);
    M.triangle_face.push_back(static_cast<geom::Id>(f));
    M.triangle_uv.push_back(F.tri_uv[t]);
  }
  return F.points.capacity() * sizeof(F.points[0]) + F.tris.capacity() * sizeof(F.tris[0]) +
         F.tri_uv.capacity() * sizeof(F.tri_uv[0]);
}

void stitch_faces(ModelRun& run) {
  MeshResult& res = run.res;
  std::size_t freed = 0;  // bytes of face meshes freed since the last release
  for (std::size_t f = 0; f < run.nf; ++f) {
    if (!run.face_error[f].empty()) {
      res.failed.push_back({static_cast<geom::Id>(f), run.face_error[f]});
      run.fm[f] = {};
      continue;
    }
    if (run.m.faces[f].degenerate) {
      res.degenerate.push_back({static_cast<geom::Id>(f), run.m.faces[f].degenerate_reason});
      continue;
    }
    if (run.twin_of[f] != geom::kNone || run.collapsed[f]) continue;
    FaceMesh& F = run.fm[f];
    freed += append_face(res.mesh, f, F);
    res.faces.push_back(F.stats);
    F = {};
    if (freed >= (std::size_t{4} << 20)) release_freed_memory(), freed = 0;
  }
}

// Model vertices used by nothing (isolated CAD vertices) are dropped so that the mesh
// has no unreferenced points; ids are compacted in order.
void drop_unused_points(SurfaceMesh& M) {
  std::vector<char> used(M.points.size(), 0);
  for (const auto& t : M.triangles)
    for (NodeId v : t) used[static_cast<std::size_t>(v)] = 1;
  for (const auto& s : M.segments)
    used[static_cast<std::size_t>(s.a)] = used[static_cast<std::size_t>(s.b)] = 1;
  if (std::find(used.begin(), used.end(), 0) == used.end()) return;
  std::vector<NodeId> nid(M.points.size(), -1);
  NodeId k = 0;
  for (std::size_t i = 0; i < used.size(); ++i)
    if (used[i]) {
      nid[i] = k;
      M.points[static_cast<std::size_t>(k)] = M.points[i];
      M.point_dim[static_cast<std::size_t>(k)] = M.point_dim[i];
      M.point_entity[static_cast<std::size_t>(k)] = M.point_entity[i];
      M.point_t[static_cast<std::size_t>(k)] = M.point_t[i];
      ++k;
    }
  M.points.resize(static_cast<std::size_t>(k));
  M.point_dim.resize(static_cast<std::size_t>(k));
  M.point_entity.resize(static_cast<std::size_t>(k));
  M.point_t.resize(static_cast<std::size_t>(k));
  for (auto& t : M.triangles)
    for (NodeId& v : t) v = nid[static_cast<std::size_t>(v)];
  for (auto& s : M.segments)
    s.a = nid[static_cast<std::size_t>(s.a)], s.b = nid[static_cast<std::size_t>(s.b)];
}

}  // namespace

void stitch(ModelRun& run) {
  release_freed_memory();
  reserve_output(run);
  const auto t0 = Clock::now();
  stitch_faces(run);
  drop_unused_points(run.res.mesh);
  run.res.stages.push_back({"stitch", seconds_since(t0)});
}

}  // namespace uvmesh::surface::detail
