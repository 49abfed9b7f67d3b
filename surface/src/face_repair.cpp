// Repairs of a face's mesh after the 3D improvement (face.cpp's mesh_face): the chordal
// repair, the flatness repair at apexes and the removal of folds at seams and poles.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>

#include "face_stage.h"
#include "uvmesh/surface/check3d.h"

namespace uvmesh::surface::detail {

namespace {

// A new interior point of the face at (u,v) uv; -1 where sigma is not finite.
int add_local_point(LocalMesh& lm, const geom::Surface& s, const geom::Vec2& uv, double scale) {
  const geom::Vec3 q = s.point(uv.x, uv.y);
  if (!std::isfinite(q.x + q.y + q.z)) return -1;
  lm.uv.push_back(uv);
  lm.p.push_back(q);
  lm.global.push_back(-1);
  lm.fixed.push_back(0);
  lm.scale.push_back(scale);
  return static_cast<int>(lm.uv.size()) - 1;
}

// A new point q splits a-b in 3D when it is at least a thousandth of |ab| from both.
bool splits_in_3d(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& q) {
  const double l = 1e-3 * glm::length(b - a);
  return glm::length(q - a) > l && glm::length(q - b) > l;
}

// Splits each edge of to_split (two uses, neither triangle split yet this round: touched)
// at its (u,v) midpoint, 2 triangles to 4; returns the splits made.
int split_edges_at_uv_midpoints(LocalMesh& lm, const geom::Surface& s, const EdgeUses& uses,
                                const std::vector<std::pair<int, int>>& to_split,
                                std::vector<char>& touched) {
  int splits = 0;
  for (auto [a, b] : to_split) {
    const auto u = uses.of(a, b).first;
    const std::size_t t1 = u[0].t, t2 = u[1].t;
    const int i1 = u[0].i, i2 = u[1].i;
    if (touched[t1] || touched[t2]) continue;
    // The (u,v) midpoint lies on the shared (u,v) edge: the four halves stay CCW.
    // Where the surface folds over itself (a swept tube whose sigma_u x sigma_v
    // vanishes along lines, the normal reversing across them) the midpoint can map onto
    // an end point or onto a corner opposite the edge: the split would only add
    // zero-area triangles, round after round (copies of one point, one per round).
    const geom::Vec2 mid = 0.5 * (lm.uv[a] + lm.uv[b]);
    const geom::Vec3 q = s.point(mid.x, mid.y);
    const int c1 = lm.tris[t1][i1], c2 = lm.tris[t2][i2];  // the corners opposite a-b
    if (!splits_in_3d(lm.p[a], lm.p[b], q) || !splits_in_3d(lm.p[a], lm.p[c1], q) ||
        !splits_in_3d(lm.p[a], lm.p[c2], q))
      continue;
    const int n = add_local_point(lm, s, mid, 0.5 * (lm.scale[a] + lm.scale[b]));
    if (n < 0) continue;
    for (const auto& [t, i] : {std::pair{t1, i1}, std::pair{t2, i2}}) {
      const auto T = lm.tris[t];  // corner c opposite the edge x-y, CCW
      const int c = T[i], x = T[(i + 1) % 3], y = T[(i + 2) % 3];
      lm.tris[t] = {c, x, n};
      lm.tris.push_back({c, n, y});
      touched[t] = 1;
    }
    ++splits;
  }
  return splits;
}

// One round of the flatness repair (repair_flat_apex): returns the splits made.
int flat_split_round(LocalMesh& lm, const geom::Surface& s, const geom::Box2& box, double rel) {
  const EdgeUses uses(lm);
  std::vector<std::pair<int, int>> to_split;
  uses.for_each_edge([&](int a, int b, std::size_t n) {
    if (n != 2) return;  // on the face's boundary: the curves' discretization
    // A chord between two boundary nodes: an edge a neighbouring face can have too.
    if (!lm.fixed[static_cast<std::size_t>(a)] || !lm.fixed[static_cast<std::size_t>(b)]) return;
    const geom::Vec3 x = 0.5 * (lm.p[a] + lm.p[b]);
    const double len = glm::length(lm.p[b] - lm.p[a]), lim = rel * len;
    // The distance from the chord's midpoint to the surface (not to sigma at the (u,v)
    // midpoint, which moves along a flat but unevenly parametrized surface too). sigma
    // there is a surface point: within lim of x, so is the surface, no projection needed.
    const geom::Vec2 mid = 0.5 * (lm.uv[a] + lm.uv[b]);
    if (glm::length(s.point(mid.x, mid.y) - x) <= lim) return;
    const Projection pr = project_to_surface(s, x, mid, box, len);
    if (pr.converged && pr.distance > lim) to_split.push_back({a, b});
  });
  std::vector<char> touched(lm.tris.size(), 0);
  return split_edges_at_uv_midpoints(lm, s, uses, to_split, touched);
}

// Whether the 3D point x, near sigma(uv0), lies farther than lim from the surface; with
// foot, also the (u,v) of its projection.
struct Deviates {
  const geom::Surface& s;
  const geom::Box2& box;
  double lim;
  bool operator()(const geom::Vec3& x, const geom::Vec2& uv0, double scale,
                  geom::Vec2* foot) const {
    // sigma(uv0) is a point of the surface: when it is within lim of x, so is the
    // surface, and the Newton projection (several evaluations with derivatives, a
    // large share of the repair's time) is not needed.
    if (!foot) {
      const geom::Vec3 q = s.point(uv0.x, uv0.y);
      if (glm::length(q - x) <= lim) return false;
    }
    const Projection pr = project_to_surface(s, x, uv0, box, scale);
    if (foot) *foot = pr.uv;
    return pr.converged && pr.distance > lim;
  }
};

// Splits each triangle of centroid_split not touched yet, 1 to 3, at the foot of its 3D
// centroid on the surface; returns the splits made.
int split_at_centroid_feet(LocalMesh& lm, const geom::Surface& s, const Deviates& deviates,
                           const std::vector<std::size_t>& centroid_split,
                           const std::vector<char>& touched) {
  auto ccw = [](const geom::Vec2& a, const geom::Vec2& b, const geom::Vec2& c) {
    return (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) > 0;
  };
  int splits = 0;
  for (std::size_t t : centroid_split) {
    if (touched[t]) continue;
    const auto T = lm.tris[t];
    const geom::Vec2 uc = (lm.uv[T[0]] + lm.uv[T[1]] + lm.uv[T[2]]) / 3.0;
    geom::Vec2 foot = uc;
    const geom::Vec3 pc = (lm.p[T[0]] + lm.p[T[1]] + lm.p[T[2]]) / 3.0;
    deviates(pc, uc, glm::length(lm.p[T[1]] - lm.p[T[0]]), &foot);
    // The foot, when it lies inside the (u,v) triangle; else the (u,v) centroid.
    if (!ccw(lm.uv[T[0]], lm.uv[T[1]], foot) || !ccw(lm.uv[T[1]], lm.uv[T[2]], foot) ||
        !ccw(lm.uv[T[2]], lm.uv[T[0]], foot))
      foot = uc;
    {
      const geom::Vec3 q = s.point(foot.x, foot.y);
      if (!splits_in_3d(lm.p[T[0]], lm.p[T[1]], q) || !splits_in_3d(lm.p[T[1]], lm.p[T[2]], q))
        continue;
    }
    const int n =
        add_local_point(lm, s, foot, (lm.scale[T[0]] + lm.scale[T[1]] + lm.scale[T[2]]) / 3.0);
    if (n < 0) continue;
    lm.tris[t] = {T[0], T[1], n};
    lm.tris.push_back({T[1], T[2], n});
    lm.tris.push_back({T[2], T[0], n});
    ++splits;
  }
  return splits;
}

// One round of the chordal repair (repair_chordal): returns the splits made.
int chordal_split_round(LocalMesh& lm, const geom::Surface& s, const geom::Box2& box, double lim) {
  const Deviates deviates{s, box, lim};
  const std::size_t nt = lm.tris.size();
  // Interior edges -> their two (triangle, opposite corner) uses.
  const EdgeUses uses(lm);
  auto interior = [&](int a, int b) {
    const auto [lo, hi] = uses.of(a, b);
    return hi - lo == 2 && !(lm.fixed[a] && lm.fixed[b]);
  };
  std::vector<std::pair<int, int>> to_split;
  std::vector<std::size_t> centroid_split;
  for (std::size_t t = 0; t < nt; ++t) {
    const auto T = lm.tris[t];
    const geom::Vec3 pc = (lm.p[T[0]] + lm.p[T[1]] + lm.p[T[2]]) / 3.0;
    double len[3];
    for (int i = 0; i < 3; ++i) len[i] = glm::length(lm.p[T[(i + 2) % 3]] - lm.p[T[(i + 1) % 3]]);
    if (!deviates(pc, (lm.uv[T[0]] + lm.uv[T[1]] + lm.uv[T[2]]) / 3.0,
                  std::max({len[0], len[1], len[2]}), nullptr))
      continue;
    int best = -1;
    for (int i = 0; i < 3; ++i)
      if (interior(T[(i + 1) % 3], T[(i + 2) % 3]) && (best < 0 || len[i] > len[best])) best = i;
    if (best >= 0)
      to_split.push_back({T[(best + 1) % 3], T[(best + 2) % 3]});
    else
      centroid_split.push_back(t);
  }
  uses.for_each_edge([&](int a, int b, std::size_t) {
    if (!interior(a, b)) return;
    if (deviates(0.5 * (lm.p[a] + lm.p[b]), 0.5 * (lm.uv[a] + lm.uv[b]),
                 glm::length(lm.p[b] - lm.p[a]), nullptr))
      to_split.push_back({a, b});
  });
  std::vector<char> touched(nt, 0);
  const int splits = split_edges_at_uv_midpoints(lm, s, uses, to_split, touched);
  return splits + split_at_centroid_feet(lm, s, deviates, centroid_split, touched);
}

}  // namespace

// ---- chordal repair. The sizes come from curvatures sampled on a background grid
// (§7.5.1) and clamped at hmin, so a narrow high-curvature band of a large freeform
// face, or the tip of a cone cut in halves, can be missed; the acceptance is the
// measured deviation, at triangle centroids and edge midpoints (Newton projection).
// A triangle whose centroid deviates by more than 0.9 tol has its longest interior
// edge split, and so has an interior edge whose midpoint deviates: 2 triangles to 4 at
// the (u,v) midpoint, which gives two pairs of halves instead of the 120-degree caps of
// a 1-to-3 split (centroid splits left many more poor triangles). A triangle with no interior edge
// is split at its centroid's foot. Then 3D swaps and smoothing.
void repair_chordal(const FaceInput& job, LocalMesh& lm, FaceStats& stats) {
  const MeshOptions& opt = job.opt;
  if (opt.size.chordal_tol > 0)
    for (int round = 0; round < opt.chordal_repair_rounds; ++round) {
      const int n = chordal_split_round(lm, job.s, job.f.uv_box, 0.9 * opt.size.chordal_tol);
      stats.chordal_splits += n;
      if (n == 0) break;
      if (opt.optimize3d) improve3d(lm, job.s, 2, /*collapse=*/false);
    }
}

// ---- flatness at apexes. Sizes are clamped at hmin, and at a cone's apex (curvature
// 1/r) nothing below hmin is resolved: without a chordal tolerance (--angle alone) the
// repair above does not run, and a cone cut in halves then got the same chord through
// its axis -- even the same triangle (apex, n1, n2) -- in both halves, each the other
// turned over: non-manifold edges and coincident triangles. On a face with a pole, a
// chord between two boundary nodes whose midpoint lies farther than a quarter of its
// length from the surface -- it spans more than about 105 degrees of arc -- is split at
// its (u,v) midpoint, so a half turn keeps at least two edges, each face its own.
// (Every interior edge, or every face, measured worse: such splits without the sizes'
// context made slivers on terrain and sliver faces, and moved other meshes.)
void repair_flat_apex(const FaceInput& job, LocalMesh& lm, FaceStats& stats) {
  constexpr double kFlatRel = 0.25;
  for (int round = 0; round < 4; ++round) {
    const int n = flat_split_round(lm, job.s, job.f.uv_box, kFlatRel);
    stats.chordal_splits += n;
    if (n == 0) break;
    if (job.opt.optimize3d) improve3d(lm, job.s, 2, /*collapse=*/false);
  }
}

// ---- folds at seams and poles: near a cone apex the (u,v) strip is so narrow in the
// metric that a vertex can see a seam node on both sides of the period; the two
// triangles it then makes are one 3D triangle with both orientations (a zero-volume
// fold). Removing the pair leaves the surrounding fan manifold.
void remove_folds(LocalMesh& lm) {
  auto node = [&](int v) {
    return lm.global[v] >= 0 ? static_cast<std::int64_t>(lm.global[v])
                             : -1 - static_cast<std::int64_t>(v);
  };
  std::map<std::array<std::int64_t, 3>, std::vector<std::size_t>> seen;
  for (std::size_t t = 0; t < lm.tris.size(); ++t) {
    std::array<std::int64_t, 3> k{node(lm.tris[t][0]), node(lm.tris[t][1]), node(lm.tris[t][2])};
    std::sort(k.begin(), k.end());
    seen[k].push_back(t);
  }
  std::vector<char> drop(lm.tris.size(), 0);
  for (const auto& [k, ts] : seen)
    if (ts.size() == 2) drop[ts[0]] = drop[ts[1]] = 1;
  if (std::find(drop.begin(), drop.end(), 1) != drop.end()) {
    std::size_t w = 0;
    for (std::size_t t = 0; t < lm.tris.size(); ++t)
      if (!drop[t]) lm.tris[w++] = lm.tris[t];
    lm.tris.resize(w);
  }
}

}  // namespace uvmesh::surface::detail
