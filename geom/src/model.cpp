// Model statistics (`uvmesh info`): counts, kinds, seams, poles, free / non-manifold /
// short edges, vertex gaps.
#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <string>

#include "uvmesh/geom/model.h"

namespace uvmesh::geom {

std::vector<std::vector<Id>> edge_faces(const Model& m) {
  std::vector<std::vector<Id>> ef(m.edges.size());
  for (Id f = 0; f < static_cast<Id>(m.faces.size()); ++f)
    for (const Loop& l : m.faces[f].loops)
      for (const EdgeUse& u : l.uses) {
        auto& v = ef[static_cast<std::size_t>(u.edge)];
        if (std::find(v.begin(), v.end(), f) == v.end()) v.push_back(f);
      }
  return ef;
}

ModelStats compute_stats(const Model& m, const StatsOptions& opt) {
  ModelStats s;
  s.solids = static_cast<int>(m.solids.size());
  s.shells = static_cast<int>(m.shells.size());
  s.faces = static_cast<int>(m.faces.size());
  s.edges = static_cast<int>(m.edges.size());
  s.vertices = static_cast<int>(m.vertices.size());
  for (const Face& f : m.faces) {
    ++s.surface_kinds[std::string(to_string(f.kind))];
    if (!f.valid) ++s.invalid_faces;
  }
  for (const Shell& sh : m.shells)
    if (!sh.closed) ++s.open_shells;

  std::vector<char> is_seam(m.edges.size(), 0);
  for (const Face& f : m.faces) {
    bool any = false;
    for (const Loop& l : f.loops)
      for (const EdgeUse& u : l.uses)
        if (u.seam) {
          is_seam[static_cast<std::size_t>(u.edge)] = 1;
          any = true;
        }
    if (any) ++s.faces_with_seams;
  }
  const auto ef = edge_faces(m);
  s.short_edge_threshold = opt.short_edge_rel * m.bbox.diagonal();
  s.min_edge_length = std::numeric_limits<double>::infinity();
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const Edge& ed = m.edges[e];
    if (is_seam[e]) ++s.seam_edges;
    if (ed.degenerate) {
      ++s.degenerate_edges;
      continue;
    }
    if (ed.curve) ++s.curve_kinds[std::string(to_string(ed.curve->kind()))];
    if (ef[e].size() == 1 && !is_seam[e]) ++s.free_edges;
    if (ef[e].size() >= 3) ++s.non_manifold_edges;
    if (ed.length < s.short_edge_threshold) ++s.short_edges;
    s.min_edge_length = std::min(s.min_edge_length, ed.length);
    // A vertex must lie within (a multiple of) the tolerances from the curve end it bounds.
    if (ed.curve) {
      auto gap = [&](Id v, double t) {
        if (v == kNone) return;
        const Vertex& vx = m.vertices[static_cast<std::size_t>(v)];
        const double d = glm::length(ed.curve->point(t) - vx.p);
        const double allowed = opt.gap_factor * std::max(vx.tol, ed.tol);
        if (!(d <= allowed)) {  // NaN counts as a gap
          ++s.vertex_gaps;
          s.max_vertex_gap = std::isnan(d) ? d : std::max(s.max_vertex_gap, d);
        }
      };
      gap(ed.v0, ed.range.lo);
      gap(ed.v1, ed.range.hi);
    }
  }
  if (!std::isfinite(s.min_edge_length)) s.min_edge_length = 0.0;
  return s;
}

}  // namespace uvmesh::geom
