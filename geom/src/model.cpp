// Model statistics (`uvmesh info`): counts, kinds, seams, poles, free / non-manifold /
// short edges, vertex gaps; the split of vertices that close open edges.
#include "uvmesh/geom/model.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <sstream>
#include <string>

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

namespace {

// One end of an edge at a vertex: the point where its curve ends there.
struct End {
  Id edge;
  int side;  // 0: the curve's lo end (v0), 1: its hi end (v1)
  Vec3 x;
  double tol;
};

// The edge ends at every vertex; skip: a degenerate edge, or an end that cannot be
// evaluated, is at the vertex.
void collect_edge_ends(const Model& m, std::vector<std::vector<End>>& ends,
                       std::vector<char>& skip) {
  const std::size_t nv = m.vertices.size();
  ends.assign(nv, {});
  skip.assign(nv, 0);
  auto valid = [&](Id v) { return v != kNone && v >= 0 && static_cast<std::size_t>(v) < nv; };
  for (std::size_t e = 0; e < m.edges.size(); ++e) {
    const Edge& ed = m.edges[e];
    for (int side = 0; side < 2; ++side) {
      const Id v = side ? ed.v1 : ed.v0;
      if (!valid(v)) continue;
      if (ed.degenerate || !ed.curve) {
        skip[static_cast<std::size_t>(v)] = 1;
        continue;
      }
      Vec3 x(0.0);
      try {
        x = ed.curve->point(side ? ed.range.hi : ed.range.lo);
      } catch (...) {
        x = Vec3(std::numeric_limits<double>::quiet_NaN());
      }
      if (!std::isfinite(x.x + x.y + x.z)) skip[static_cast<std::size_t>(v)] = 1;
      ends[static_cast<std::size_t>(v)].push_back({static_cast<Id>(e), side, x, ed.tol});
    }
  }
}

// The ends at one vertex grouped into clusters of points.
struct VertexClusters {
  std::vector<std::size_t> seeds;  // indices in the vertex's ends
  std::vector<Id> open_closed;     // the edges this vertex closes although their ends are apart
  std::vector<Vec3> centre;
  std::vector<double> ctol;
  std::vector<std::size_t> cl;  // cluster of every end
};

// The edges closed by this vertex only: both ends here, the curve's ends farther apart
// than the edge's tolerance.
void find_seeds(const Model& m, const std::vector<End>& E, VertexClusters& C) {
  for (std::size_t i = 0; i < E.size(); ++i) {
    if (E[i].side != 0) continue;
    const Edge& ed = m.edges[static_cast<std::size_t>(E[i].edge)];
    if (ed.v0 != ed.v1) continue;
    for (std::size_t j = 0; j < E.size(); ++j)
      if (E[j].edge == E[i].edge && E[j].side == 1 && glm::length(E[j].x - E[i].x) > ed.tol) {
        C.seeds.push_back(i);
        C.seeds.push_back(j);
        C.open_closed.push_back(E[i].edge);
      }
  }
}

// Seeds within their tolerances of each other are one cluster.
void cluster_seeds(const std::vector<End>& E, VertexClusters& C) {
  for (std::size_t i : C.seeds) {
    bool joined = false;
    for (std::size_t c = 0; c < C.centre.size() && !joined; ++c)
      if (glm::length(E[i].x - C.centre[c]) <= std::max(E[i].tol, C.ctol[c])) {
        C.ctol[c] = std::max(C.ctol[c], E[i].tol);
        joined = true;
      }
    if (!joined) C.centre.push_back(E[i].x), C.ctol.push_back(E[i].tol);
  }
}

// Every end to its nearest cluster, unambiguously; false when one is not clear.
bool assign_ends(const std::vector<End>& E, VertexClusters& C) {
  C.cl.assign(E.size(), 0);
  bool clear = true;
  for (std::size_t i = 0; i < E.size() && clear; ++i) {
    double d1 = std::numeric_limits<double>::infinity(), d2 = d1;
    for (std::size_t c = 0; c < C.centre.size(); ++c) {
      const double d = glm::length(E[i].x - C.centre[c]);
      if (d < d1)
        d2 = d1, d1 = d, C.cl[i] = c;
      else if (d < d2)
        d2 = d;
    }
    clear = d1 <= std::max(C.ctol[C.cl[i]], 0.5 * d2);
  }
  return clear;
}

long cluster_of(const std::vector<End>& E, const VertexClusters& C, Id edge, int side) {
  for (std::size_t i = 0; i < E.size(); ++i)
    if (E[i].edge == edge && E[i].side == side) return static_cast<long>(C.cl[i]);
  return -1L;
}

// The split must open every closed edge (its two ends in two clusters), and every loop
// must still chain through the vertex: where one use ends here and the next starts here,
// both ends go to the same cluster.
bool split_keeps_loops(const Model& m, std::size_t v, const std::vector<End>& E,
                       const VertexClusters& C) {
  bool clear = true;
  for (Id e : C.open_closed)
    if (cluster_of(E, C, e, 0) == cluster_of(E, C, e, 1)) clear = false;
  for (const Face& f : m.faces)
    for (const Loop& l : f.loops) {
      std::vector<const EdgeUse*> cyc;
      for (const EdgeUse& u : l.uses)
        if (!u.internal && u.edge != kNone) cyc.push_back(&u);
      for (std::size_t k = 0; k < cyc.size() && clear; ++k) {
        const EdgeUse &a = *cyc[k], &b = *cyc[(k + 1) % cyc.size()];
        const Edge &ea = m.edges[static_cast<std::size_t>(a.edge)],
                   &eb = m.edges[static_cast<std::size_t>(b.edge)];
        const int sa = a.reversed ? 0 : 1, sb = b.reversed ? 1 : 0;  // a's last end, b's first
        if ((sa ? ea.v1 : ea.v0) != static_cast<Id>(v) ||
            (sb ? eb.v1 : eb.v0) != static_cast<Id>(v))
          continue;
        if (cluster_of(E, C, a.edge, sa) != cluster_of(E, C, b.edge, sb)) clear = false;
      }
    }
  return clear;
}

// Why vertex `id` was split off vertex v, placed at `at`.
std::string split_reason(const Model& m, std::size_t v, Id id, const Vec3& at,
                         const std::vector<Id>& open_closed) {
  std::ostringstream os;
  os << "vertex " << id << " split off vertex " << v << " (tolerance " << m.vertices[v].tol
     << "): edge";
  if (open_closed.size() > 1) os << "s";
  for (std::size_t k = 0; k < open_closed.size(); ++k) {
    const Edge& ed = m.edges[static_cast<std::size_t>(open_closed[k])];
    os << (k ? ", " : " ") << open_closed[k] << " (ends "
       << glm::length(ed.curve->point(ed.range.hi) - ed.curve->point(ed.range.lo))
       << " apart, tolerance " << ed.tol << ")";
  }
  os << " had both ends at vertex " << v << "; the edge ends near " << at.x << " " << at.y << " "
     << at.z << " are now at vertex " << id;
  return os.str();
}

// Vertex v becomes one vertex per cluster: the cluster nearest the vertex's own point
// keeps it, the others get new vertices; the edge ends move to their cluster's vertex.
int split_vertex(Model& m, std::size_t v, const std::vector<End>& E, const VertexClusters& C) {
  const std::vector<Vec3>& centre = C.centre;
  int added = 0;
  const Vec3 p = m.vertices[v].p;
  std::size_t keep = 0;
  for (std::size_t c = 1; c < centre.size(); ++c)
    if (glm::length(centre[c] - p) < glm::length(centre[keep] - p)) keep = c;
  std::vector<Id> id(centre.size(), kNone);
  std::vector<Vec3> at(centre.size());
  for (std::size_t c = 0; c < centre.size(); ++c) {
    at[c] = c == keep ? p : centre[c];
    if (c == keep) {
      id[c] = static_cast<Id>(v);
      continue;
    }
    id[c] = static_cast<Id>(m.vertices.size());
    VertexSplit split;
    split.vertex = id[c];
    split.from = static_cast<Id>(v);
    split.reason = split_reason(m, v, id[c], at[c], C.open_closed);
    m.vertices.push_back({at[c], 0.0});
    m.vertex_splits.push_back(std::move(split));
    ++added;
  }
  std::vector<double> tol(centre.size(), 0.0);
  for (std::size_t i = 0; i < E.size(); ++i) {
    const std::size_t c = C.cl[i];
    tol[c] = std::max({tol[c], E[i].tol, glm::length(E[i].x - at[c])});
    Edge& ed = m.edges[static_cast<std::size_t>(E[i].edge)];
    (E[i].side ? ed.v1 : ed.v0) = id[c];
  }
  for (std::size_t c = 0; c < centre.size(); ++c)
    m.vertices[static_cast<std::size_t>(id[c])].tol = tol[c];
  return added;
}

}  // namespace

int split_vertices_closing_open_edges(Model& m) {
  const std::size_t nv = m.vertices.size();
  std::vector<std::vector<End>> ends;
  std::vector<char> skip;
  collect_edge_ends(m, ends, skip);
  int added = 0;
  for (std::size_t v = 0; v < nv; ++v) {
    if (skip[v]) continue;
    const std::vector<End>& E = ends[v];
    VertexClusters C;
    find_seeds(m, E, C);
    if (C.seeds.empty()) continue;
    cluster_seeds(E, C);
    if (C.centre.size() < 2) continue;
    if (!assign_ends(E, C)) continue;
    if (!split_keeps_loops(m, v, E, C)) continue;
    added += split_vertex(m, v, E, C);
  }
  return added;
}

}  // namespace uvmesh::geom
