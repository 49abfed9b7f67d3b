// Measures of tetrahedra (tet_mesh.h): volume, minimum dihedral angle, radius-edge ratio
// and their distribution over a TetMesh.
#include "uvmesh/surface/tet_mesh.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

namespace uvmesh::surface {

using geom::Vec3;

double tet_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  return glm::dot(d - a, glm::cross(b - a, c - a)) / 6.0;
}

double tet_min_dihedral_deg(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const std::array<Vec3, 4> p = {a, b, c, d};
  // Outward normal of the face opposite each vertex: the interior dihedral angle at the
  // edge shared by the faces opposite k and l is pi minus the angle of their normals.
  std::array<Vec3, 4> n;
  for (int k = 0; k < 4; ++k) {
    const Vec3& u = p[static_cast<std::size_t>((k + 1) % 4)];
    const Vec3& v = p[static_cast<std::size_t>((k + 2) % 4)];
    const Vec3& w = p[static_cast<std::size_t>((k + 3) % 4)];
    Vec3 nk = glm::cross(v - u, w - u);
    if (glm::dot(nk, p[static_cast<std::size_t>(k)] - u) > 0) nk = -nk;
    const double len = glm::length(nk);
    if (!(len > 0)) return 0.0;
    n[static_cast<std::size_t>(k)] = nk / len;
  }
  double best = std::numbers::pi;
  for (int k = 0; k < 4; ++k)
    for (int l = k + 1; l < 4; ++l) {
      const double cosine = std::clamp(
          glm::dot(n[static_cast<std::size_t>(k)], n[static_cast<std::size_t>(l)]), -1.0, 1.0);
      best = std::min(best, std::numbers::pi - std::acos(cosine));
    }
  return best * 180.0 / std::numbers::pi;
}

double tet_radius_edge(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const Vec3 u = a - d, v = b - d, w = c - d;
  const double det = glm::dot(u, glm::cross(v, w));
  const double inf = std::numeric_limits<double>::infinity();
  if (det == 0.0) return inf;
  const Vec3 num = glm::dot(u, u) * glm::cross(v, w) + glm::dot(v, v) * glm::cross(w, u) +
                   glm::dot(w, w) * glm::cross(u, v);
  const double radius = glm::length(num) / (2.0 * std::abs(det));
  const double shortest = std::min({glm::length(a - b), glm::length(a - c), glm::length(a - d),
                                    glm::length(b - c), glm::length(b - d), glm::length(c - d)});
  return shortest > 0 ? radius / shortest : inf;
}

namespace {

// Nearest-rank percentile of sorted values: the smallest value with at least share of the
// values at or below it.
double nearest_rank(const std::vector<double>& sorted, double share) {
  if (sorted.empty()) return 0.0;
  const auto n = static_cast<double>(sorted.size());
  auto rank = static_cast<std::size_t>(std::ceil(share * n));
  rank = std::clamp<std::size_t>(rank, 1, sorted.size());
  return sorted[rank - 1];
}

}  // namespace

TetQualityReport measure_tet_quality(const TetMesh& m, geom::Id solid) {
  TetQualityReport r;
  std::vector<double> dihedral, radius_edge;
  for (std::size_t t = 0; t < m.tets.size(); ++t) {
    if (solid != geom::kNone && (t >= m.tet_solid.size() || m.tet_solid[t] != solid)) continue;
    const auto& tet = m.tets[t];
    const Vec3& a = m.points[static_cast<std::size_t>(tet[0])];
    const Vec3& b = m.points[static_cast<std::size_t>(tet[1])];
    const Vec3& c = m.points[static_cast<std::size_t>(tet[2])];
    const Vec3& d = m.points[static_cast<std::size_t>(tet[3])];
    const double vol = tet_volume(a, b, c, d);
    r.volume += vol;
    r.inverted += vol <= 0;
    dihedral.push_back(tet_min_dihedral_deg(a, b, c, d));
    radius_edge.push_back(tet_radius_edge(a, b, c, d));
  }
  r.tets = dihedral.size();
  if (r.tets == 0) return r;
  std::sort(dihedral.begin(), dihedral.end());
  std::sort(radius_edge.begin(), radius_edge.end());
  r.dihedral_min = dihedral.front();
  r.dihedral_p1 = nearest_rank(dihedral, 0.01);
  r.dihedral_p50 = nearest_rank(dihedral, 0.5);
  r.radius_edge_max = radius_edge.back();
  // The bad tail is at the top: the value with at least 1% of the tetrahedra at or above.
  std::vector<double> desc(radius_edge.rbegin(), radius_edge.rend());
  std::transform(desc.begin(), desc.end(), desc.begin(), [](double x) { return -x; });
  r.radius_edge_p99 = -nearest_rank(desc, 0.01);
  r.radius_edge_p50 = nearest_rank(radius_edge, 0.5);
  return r;
}

}  // namespace uvmesh::surface
