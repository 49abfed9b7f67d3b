// Coincident faces: an assembly written without imprinting often gives the interface
// between two solids twice, as two faces on the same edges and the same surface. Both
// meshed would put two different triangulations on one surface (intersecting, and
// rejected by TetGen as duplicated facets); the interface is meshed once, as the first
// face, which then bounds both solids (as Gmsh's conformal fragments do).
#include <algorithm>
#include <map>

#include "model_run.h"
#include "uvmesh/geom/project.h"

namespace uvmesh::surface::detail {

namespace {

// Faces that may be meshed, grouped by the sorted set of their edges.
std::map<std::vector<geom::Id>, std::vector<std::size_t>> faces_by_edges(const ModelRun& run) {
  std::map<std::vector<geom::Id>, std::vector<std::size_t>> by_edges;
  for (std::size_t f = 0; f < run.nf; ++f) {
    if (!run.face_error[f].empty() || run.m.faces[f].degenerate) continue;
    std::vector<geom::Id> k;
    for (const geom::Loop& l : run.m.faces[f].loops)
      for (const geom::EdgeUse& u : l.uses) k.push_back(u.edge);
    std::sort(k.begin(), k.end());
    k.erase(std::unique(k.begin(), k.end()), k.end());
    if (!k.empty()) by_edges[k].push_back(f);
  }
  return by_edges;
}

// Two faces on the same edges lie on one surface: both planes, or (two different
// surfaces, a lens) an inside point of a on b's surface.
bool same_surface(const geom::Face& a, const geom::Face& b, double tol) {
  if (a.kind == geom::SurfaceKind::Plane && b.kind == geom::SurfaceKind::Plane) return true;
  try {
    const geom::Vec3 p = a.surface->point(a.uv_box.u.mid(), a.uv_box.v.mid());
    const geom::Projection pr = geom::project_to_surface(
        *b.surface, p, {b.uv_box.u.mid(), b.uv_box.v.mid()}, b.uv_box, std::max(a.tol, tol));
    return pr.converged && pr.distance <= std::max(10 * std::max(a.tol, b.tol), tol);
  } catch (...) {
    return false;
  }
}

}  // namespace

void find_twin_faces(ModelRun& run) {
  const geom::Model& m = run.m;
  const double tol = 1e-6 * std::max(m.bbox.diagonal(), 1e-300);
  for (const auto& [k, fs] : faces_by_edges(run))
    for (std::size_t i = 1; i < fs.size(); ++i)
      for (std::size_t j = 0; j < i; ++j) {
        if (run.twin_of[fs[j]] != geom::kNone) continue;
        if (same_surface(m.faces[fs[j]], m.faces[fs[i]], tol)) {
          run.twin_of[fs[i]] = static_cast<geom::Id>(fs[j]);
          run.res.twins.push_back({static_cast<geom::Id>(fs[i]), static_cast<geom::Id>(fs[j])});
          break;
        }
      }
}

}  // namespace uvmesh::surface::detail
