// 3D measures of a SurfaceMesh, part 5: chordal deviation against the exact surfaces
// (see check3d.h; the projection is geom/project.h).
#include <tbb/blocked_range.h>
#include <tbb/enumerable_thread_specific.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>
#include <tbb/parallel_sort.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <queue>

#include "check3d_internal.h"
#include "uvmesh/geom/project.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface {

using geom::Vec2;
using geom::Vec3;
using namespace check3d_impl;

// =======================================================================================
// 5. Chordal deviation
// =======================================================================================

ChordalReport measure_chordal(const SurfaceMesh& m, const geom::Model& model, int threads) {
  ChordalReport r;
  const std::size_t nf = model.faces.size(), nt = m.triangles.size();
  r.face_max.assign(nf, 0.0);
  const bool have_uv = m.triangle_uv.size() == nt;

  // Triangles of each face, in id order.
  std::vector<std::vector<TriId>> by_face(nf);
  for (std::size_t t = 0; t < nt; ++t) {
    const geom::Id f = face_of(m, t);
    if (!have_uv || f < 0 || static_cast<std::size_t>(f) >= nf || !model.faces[f].surface ||
        tri_state(m, t) == kBadIndex) {
      ++r.skipped_triangles;
      continue;
    }
    by_face[f].push_back(static_cast<TriId>(t));
  }
  // Faces sharing one Surface object must run in the same task.
  std::vector<std::vector<geom::Id>> groups;
  {
    std::map<const geom::Surface*, std::size_t> gi;
    for (std::size_t f = 0; f < nf; ++f) {
      if (by_face[f].empty()) continue;
      const geom::Surface* s = model.faces[f].surface.get();
      auto [it, fresh] = gi.emplace(s, groups.size());
      if (fresh) groups.emplace_back();
      groups[it->second].push_back(static_cast<geom::Id>(f));
    }
  }

  struct FaceResult {
    std::size_t samples = 0, not_converged = 0;
    double sum = 0, max = 0;
    ChordalSample worst;
  };
  std::vector<FaceResult> fr(nf);
  auto run_face = [&](geom::Id f) {
    const geom::Face& face = model.faces[f];
    const geom::Surface& s = *face.surface;
    geom::Box2 box = face.uv_box;
    if (!(box.u.hi > box.u.lo && box.v.hi > box.v.lo)) box = s.bounds();
    if (s.u_periodic() && s.u_period() > 0) {
      box.u.lo -= 0.5 * s.u_period();
      box.u.hi += 0.5 * s.u_period();
    }
    if (s.v_periodic() && s.v_period() > 0) {
      box.v.lo -= 0.5 * s.v_period();
      box.v.hi += 0.5 * s.v_period();
    }
    FaceResult& out = fr[f];
    for (TriId t : by_face[f]) {
      const pred3::Tri c = corners(m, t);
      const auto& uv = m.triangle_uv[t];
      const double h =
          std::max({glm::length(c[1] - c[0]), glm::length(c[2] - c[1]), glm::length(c[0] - c[2])});
      const ChordalSamples cs = chordal_samples(c, uv);
      for (int k = 0; k < 4; ++k) {
        const geom::Projection p = geom::project_to_surface(s, cs.x[k], cs.uv[k], box, h);
        ++out.samples;
        out.not_converged += !p.converged;
        out.sum += p.distance;
        if (p.distance > out.max || out.worst.triangle < 0) {
          out.max = std::max(out.max, p.distance);
          out.worst = {t, f, k, cs.x[k], p.point, p.uv, p.distance};
        }
      }
    }
  };
  tbb::task_arena arena = make_arena(threads);
  arena.execute([&] {
    tbb::parallel_for(std::size_t(0), groups.size(), [&](std::size_t g) {
      for (geom::Id f : groups[g]) run_face(f);
    });
  });

  // Reduction in face order: deterministic sums and ties (smallest face, then triangle).
  double sum = 0;
  for (std::size_t f = 0; f < nf; ++f) {
    const FaceResult& x = fr[f];
    if (x.samples == 0) continue;
    r.samples += x.samples;
    r.triangles += by_face[f].size();
    r.not_converged += x.not_converged;
    sum += x.sum;
    r.face_max[f] = x.max;
    if (r.worst.triangle < 0 || x.max > r.max ||
        (x.max == r.max && x.worst.triangle < r.worst.triangle)) {
      r.max = x.max;
      r.worst = x.worst;
    }
  }
  r.mean = r.samples ? sum / static_cast<double>(r.samples) : 0.0;
  return r;
}

}  // namespace uvmesh::surface
