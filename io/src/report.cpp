// The quality report (report.h): gathers surface/check3d.h's measures, adds the few
// things it does not compute (edge-connected components, free edges on open model edges,
// histograms, (u,v) for meshes read from files) and formats the JSON.
#include "uvmesh/io/report.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <numbers>
#include <numeric>
#include <unordered_map>

#include "uvmesh/geom/project.h"
#include "uvmesh/mesher2d/measures.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::io {

namespace {

using surface::NodeId;
using surface::SurfaceMesh;

// Unique undirected edges of the triangles with valid, distinct indices, each with the
// triangles using it (consecutive in `users`).
struct EdgeTable {
  std::vector<std::pair<NodeId, NodeId>> edges;  ///< (a < b), sorted
  std::vector<std::size_t> first;                ///< users of edge e: first[e]..first[e+1]
  std::vector<std::int32_t> users;
};

EdgeTable edge_table(const SurfaceMesh& m) {
  struct Use {
    NodeId a, b;
    std::int32_t t;
  };
  std::vector<Use> uses;
  uses.reserve(3 * m.triangles.size());
  const auto np = static_cast<NodeId>(m.points.size());
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    bool ok = true;
    for (NodeId v : tri) ok = ok && v >= 0 && v < np;
    if (!ok || tri[0] == tri[1] || tri[1] == tri[2] || tri[0] == tri[2]) continue;
    for (int k = 0; k < 3; ++k) {
      const NodeId a = tri[k], b = tri[(k + 1) % 3];
      uses.push_back({std::min(a, b), std::max(a, b), static_cast<std::int32_t>(t)});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const Use& x, const Use& y) {
    return x.a != y.a ? x.a < y.a : x.b != y.b ? x.b < y.b : x.t < y.t;
  });
  EdgeTable e;
  for (std::size_t i = 0; i < uses.size(); ++i) {
    if (i == 0 || uses[i].a != uses[i - 1].a || uses[i].b != uses[i - 1].b) {
      e.edges.emplace_back(uses[i].a, uses[i].b);
      e.first.push_back(i);
    }
    e.users.push_back(uses[i].t);
  }
  e.first.push_back(uses.size());
  return e;
}

std::size_t components(const SurfaceMesh& m, const EdgeTable& e) {
  std::vector<std::int32_t> parent(m.triangles.size());
  std::iota(parent.begin(), parent.end(), 0);
  auto find = [&](std::int32_t x) {
    while (parent[static_cast<std::size_t>(x)] != x) {
      parent[static_cast<std::size_t>(x)] =
          parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(x)])];
      x = parent[static_cast<std::size_t>(x)];
    }
    return x;
  };
  for (std::size_t k = 0; k + 1 < e.first.size(); ++k)
    for (std::size_t i = e.first[k] + 1; i < e.first[k + 1]; ++i) {
      const std::int32_t a = find(e.users[e.first[k]]), b = find(e.users[i]);
      if (a != b) parent[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
    }
  // Triangles left out of the edge table (degenerate by index) are no component: the
  // topology section counts them as degenerate.
  std::vector<char> in_table(m.triangles.size(), 0);
  for (std::int32_t t : e.users) in_table[static_cast<std::size_t>(t)] = 1;
  std::size_t n = 0;
  for (std::size_t t = 0; t < parent.size(); ++t)
    n += in_table[t] && find(static_cast<std::int32_t>(t)) == static_cast<std::int32_t>(t);
  return n;
}

std::size_t free_on_open_model_edges(const SurfaceMesh& m, const geom::Model& model,
                                     const EdgeTable& e) {
  const auto ef = geom::edge_faces(model);
  std::size_t n = 0;
  for (const auto& s : m.segments) {
    if (s.edge < 0 || static_cast<std::size_t>(s.edge) >= ef.size() ||
        ef[static_cast<std::size_t>(s.edge)].size() > 1)
      continue;
    const std::pair<NodeId, NodeId> key{std::min(s.a, s.b), std::max(s.a, s.b)};
    const auto it = std::lower_bound(e.edges.begin(), e.edges.end(), key);
    if (it == e.edges.end() || *it != key) continue;
    const auto k = static_cast<std::size_t>(it - e.edges.begin());
    n += e.first[k + 1] - e.first[k] == 1;
  }
  return n;
}

Histogram uniform_histogram(double lo, double hi, int bins) {
  Histogram h;
  for (int i = 0; i < bins; ++i) h.lo.push_back(lo + (hi - lo) * i / bins);
  h.hi = hi;
  h.count.assign(static_cast<std::size_t>(bins), 0);
  return h;
}

void add_uniform(Histogram& h, double x) {
  const double lo = h.lo.front(), w = (h.hi - lo) / static_cast<double>(h.count.size());
  const auto i = static_cast<std::ptrdiff_t>(std::floor((x - lo) / w));
  ++h.count[static_cast<std::size_t>(
      std::clamp<std::ptrdiff_t>(i, 0, static_cast<std::ptrdiff_t>(h.count.size()) - 1))];
}

// Metric edge lengths: each node takes the metric of its face's background size field at
// its (u,v) (the first triangle using it decides the face); an edge's length is the mean
// of its lengths in its two end metrics (the trapezoid rule of 7.5.2).
std::optional<surface::EdgeLengthReport> metric_lengths(const SurfaceMesh& m,
                                                        const geom::Model& model,
                                                        const param::SizeSpec& spec) {
  const std::size_t np = m.points.size();
  std::vector<geom::Id> face_of(np, geom::kNone);
  std::vector<geom::Vec2> uv_of(np, geom::Vec2(0.0));
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) {
      const auto v = static_cast<std::size_t>(m.triangles[t][k]);
      if (v < np && face_of[v] == geom::kNone)
        face_of[v] = m.triangle_face[t], uv_of[v] = m.triangle_uv[t][k];
    }
  std::vector<std::unique_ptr<param::FaceSizeField>> fields(model.faces.size());
  std::vector<param::Metric3> metric(np);
  std::vector<char> has(np, 0);
  for (std::size_t v = 0; v < np; ++v) {
    const geom::Id f = face_of[v];
    if (f == geom::kNone || !model.faces[static_cast<std::size_t>(f)].surface) continue;
    const geom::Face& face = model.faces[static_cast<std::size_t>(f)];
    auto& field = fields[static_cast<std::size_t>(f)];
    if (!field) {
      geom::Box2 box = face.uv_box;
      if (!(box.u.hi > box.u.lo && box.v.hi > box.v.lo)) box = face.surface->bounds();
      field = std::make_unique<param::FaceSizeField>(*face.surface, box, spec, f);
    }
    metric[v] = field->metric3(uv_of[v].x, uv_of[v].y);
    has[v] = 1;
  }
  return surface::measure_edge_lengths(m, [&](NodeId a, NodeId b) {
    const auto ia = static_cast<std::size_t>(a), ib = static_cast<std::size_t>(b);
    const geom::Vec3 e = m.points[ib] - m.points[ia];
    if (has[ia] && has[ib])
      return measures::edge_length(metric[ia].length(e), metric[ib].length(e));
    if (has[ia] || has[ib]) return metric[has[ia] ? ia : ib].length(e);
    return glm::length(e) / spec.hmax;  // no surface on either side: the largest size
  });
}

nlohmann::json edge_length_json(const surface::EdgeLengthReport& r) {
  return {{"edges", r.edges},       {"unit", r.unit},       {"unit_share", r.unit_share},
          {"short", r.short_edges}, {"long", r.long_edges}, {"min", r.min},
          {"max", r.max},           {"mean", r.mean},       {"bin_lo", r.bin_lo},
          {"count", r.bin_count}};
}

std::vector<CheckData::SolidTopology> solid_topology(const SurfaceMesh& m,
                                                     const geom::Model& model) {
  std::vector<CheckData::SolidTopology> out;
  for (std::size_t s = 0; s < model.solids.size(); ++s) {
    const surface::SolidSurface ss = surface::solid_surface(m, model, static_cast<geom::Id>(s));
    CheckData::SolidTopology st;
    st.solid = ss.solid;
    st.closed = ss.closed;
    st.triangles = ss.triangles.size();
    st.free_edges = ss.free_edges;
    st.non_manifold_edges = ss.non_manifold_edges;
    st.faces = ss.faces;
    out.push_back(st);
  }
  return out;
}

nlohmann::json histogram_json(const Histogram& h) {
  return {{"bin_lo", h.lo}, {"hi", h.hi}, {"count", h.count}};
}

// Which intersecting pairs the model's own surfaces share: in total, per solid and within
// closed solids.
void classify_intersections(CheckData& d, const SurfaceMesh& m, const geom::Model& model,
                            const CheckOptions& opt) {
  // Every pair is classified, not only the listed ones.
  const surface::IntersectionReport all =
      d.intersections->pairs.size() < d.intersections->intersecting_pairs
          ? surface::find_self_intersections(
                m, static_cast<int>(d.intersections->intersecting_pairs), opt.threads)
          : *d.intersections;
  const std::vector<std::size_t> in_model =
      surface::pairs_intersecting_in_model(m, model, all.pairs);
  d.intersections_in_model = in_model.size();
  std::vector<char> proven(all.pairs.size(), 0);
  for (std::size_t k : in_model) proven[k] = 1;
  for (auto& s : d.solids) {
    std::size_t n = 0, n_model = 0;
    for (std::size_t k = 0; k < all.pairs.size(); ++k) {
      const auto& p = all.pairs[k];
      if (std::binary_search(s.faces.begin(), s.faces.end(), p.f0) &&
          std::binary_search(s.faces.begin(), s.faces.end(), p.f1))
        ++n, n_model += proven[k];
    }
    s.self_intersections = n;
    s.self_intersections_in_model = n_model;
  }
  if (d.solids.empty()) return;
  std::vector<char> in_closed(model.faces.size() + 1, 0);
  for (const auto& s : d.solids)
    if (s.closed)
      for (geom::Id f : s.faces) in_closed[static_cast<std::size_t>(f)] = 1;
  auto closed_face = [&](geom::Id f) {
    return f >= 0 && static_cast<std::size_t>(f) < model.faces.size() &&
           in_closed[static_cast<std::size_t>(f)];
  };
  std::size_t n = 0, n_model = 0;
  for (std::size_t k = 0; k < all.pairs.size(); ++k)
    if (closed_face(all.pairs[k].f0) && closed_face(all.pairs[k].f1)) ++n, n_model += proven[k];
  d.intersections_in_closed_solids = n;
  d.intersections_in_closed_solids_in_model = n_model;
}

void check_intersections(CheckData& d, const SurfaceMesh& m, const geom::Model* model,
                         const CheckOptions& opt) {
  d.intersections = surface::find_self_intersections(m, opt.max_list, opt.threads);
  if (model && d.intersections->intersecting_pairs > 0) {
    classify_intersections(d, m, *model, opt);
  } else {
    for (auto& s : d.solids) s.self_intersections = s.self_intersections_in_model = 0;
    if (!d.solids.empty())
      d.intersections_in_closed_solids = d.intersections_in_closed_solids_in_model = 0;
  }
}

// With a model, bad triangles across gaps narrower than the mesher's proximity floor
// (for the sizes given, else the default sizes') are counted apart from the others.
// Gaps within the CAD tolerances of the two edges count as narrow as well.
void measure_shape(CheckData& d, const SurfaceMesh& m, const geom::Model* model,
                   const CheckOptions& opt) {
  double narrow_gap = 0.0;
  std::vector<double> edge_gap;
  if (model) {
    const double D = model->bbox.diagonal();
    narrow_gap =
        surface::proximity_floor(opt.size ? *opt.size : surface::default_size(*model), D, 0.0);
    edge_gap = surface::edge_gap_floors(*model);
  }
  d.quality = surface::measure_quality(m, opt.max_list, narrow_gap, model ? &edge_gap : nullptr);
}

// Edge lengths relative to the median edge: the report of a mesh without a size field
// still shows how uniform (or how graded) the sizes are.
void measure_edge_distribution(CheckData& d, const SurfaceMesh& m, const EdgeTable& e) {
  std::vector<double> len(e.edges.size());
  for (std::size_t k = 0; k < e.edges.size(); ++k)
    len[k] = glm::distance(m.points[static_cast<std::size_t>(e.edges[k].first)],
                           m.points[static_cast<std::size_t>(e.edges[k].second)]);
  if (!len.empty()) {
    std::vector<double> sorted = len;
    std::nth_element(sorted.begin(),
                     sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2), sorted.end());
    d.median_edge = sorted[sorted.size() / 2];
  }
  const double ref = d.median_edge > 0 ? d.median_edge : 1.0;
  d.edge_lengths = surface::measure_edge_lengths(m, [&](NodeId a, NodeId b) {
    return glm::distance(m.points[static_cast<std::size_t>(a)],
                         m.points[static_cast<std::size_t>(b)]) /
           ref;
  });
  d.edge_histogram.lo = d.edge_lengths.bin_lo;
  d.edge_histogram.hi = std::numeric_limits<double>::infinity();
  d.edge_histogram.count = d.edge_lengths.bin_count;
}

// q = 1/Q and the angles of every triangle.
void shape_histograms(CheckData& d, const SurfaceMesh& m) {
  d.q_histogram = uniform_histogram(0.0, 1.0, 20);
  d.angle_histogram = uniform_histogram(0.0, 180.0, 18);
  for (const auto& tri : m.triangles) {
    const geom::Vec3 p[3] = {m.points[static_cast<std::size_t>(tri[0])],
                             m.points[static_cast<std::size_t>(tri[1])],
                             m.points[static_cast<std::size_t>(tri[2])]};
    const double Q = surface::triangle_Q(p[0], p[1], p[2]);
    add_uniform(d.q_histogram, std::isfinite(Q) && Q > 0 ? 1.0 / Q : 0.0);
    for (int k = 0; k < 3; ++k) {
      const geom::Vec3 u = p[(k + 1) % 3] - p[k], v = p[(k + 2) % 3] - p[k];
      const double lu = glm::length(u), lv = glm::length(v);
      if (lu > 0 && lv > 0)
        add_uniform(d.angle_histogram,
                    std::acos(std::clamp(glm::dot(u, v) / (lu * lv), -1.0, 1.0)) * 180.0 /
                        std::numbers::pi);
    }
  }
}

// Chordal deviation, and edge lengths in the size metric, when the mesh can be put on
// the model's faces.
void measure_against_model(CheckData& d, const SurfaceMesh& m, const geom::Model& model,
                           const CheckOptions& opt) {
  bool ids_ok = true;
  for (geom::Id f : m.triangle_face)
    ids_ok = ids_ok && f >= 0 && static_cast<std::size_t>(f) < model.faces.size();
  if (m.triangle_uv.size() != m.triangles.size())
    d.chordal_unavailable = "the mesh has no (u,v) per triangle corner";
  else if (!ids_ok)
    d.chordal_unavailable = "the mesh's face ids do not all name faces of the model";
  else
    d.chordal = surface::measure_chordal(m, model, opt.threads);
  if (opt.size) {
    if (!d.chordal_unavailable.empty())
      d.metric_unavailable = d.chordal_unavailable;
    else
      d.metric_edge_lengths = metric_lengths(m, model, *opt.size);
  }
}

}  // namespace

CheckData check_mesh(const SurfaceMesh& m, const geom::Model* model, const CheckOptions& opt) {
  CheckData d;
  d.points = m.points.size();
  d.triangles = m.triangles.size();
  d.segments = m.segments.size();
  surface::TopologyOptions to;
  to.max_list = opt.max_list;
  d.topology = surface::check_topology(m, to);
  const EdgeTable e = edge_table(m);
  d.components = components(m, e);
  if (model) d.free_edges_on_open_model_edges = free_on_open_model_edges(m, *model, e);
  if (model) d.solids = solid_topology(m, *model);
  if (opt.self_intersections) check_intersections(d, m, model, opt);
  measure_shape(d, m, model, opt);
  measure_edge_distribution(d, m, e);
  shape_histograms(d, m);
  d.chordal_tolerance = opt.chordal_tolerance;
  if (model) measure_against_model(d, m, *model, opt);
  return d;
}

static nlohmann::json quality_json(const surface::QualityReport& q) {
  nlohmann::json j = {{"share_Q_lt_1_5", q.share_Q_lt_1_5},
                      {"share_Q_lt_2", q.share_Q_lt_2},
                      {"share_Q_lt_3", q.share_Q_lt_3},
                      {"flat", q.flat},
                      {"q_min", q.q_min},
                      {"q_p1", q.q_p1},
                      {"q_p5", q.q_p5},
                      {"q_p50", q.q_p50},
                      {"q_mean", q.q_mean},
                      {"Q_p50", q.Q_p50},
                      {"Q_p95", q.Q_p95},
                      {"Q_p99", q.Q_p99},
                      {"Q_max", q.Q_max},
                      {"min_angle_deg", q.min_angle_deg},
                      {"max_angle_deg", q.max_angle_deg},
                      {"bad_at_corners", q.bad_at_corners},
                      {"bad_at_acute_corners", q.bad_at_acute_corners},
                      {"smallest_bad_corner_deg", q.smallest_corner_deg},
                      {"Q_over_10", q.Q_over_10},
                      {"bad_away_from_corners", q.bad_away_from_corners},
                      {"bad_in_narrow_gaps", q.bad_in_narrow_gaps},
                      {"widest_narrow_gap", q.widest_narrow_gap}};
  nlohmann::json bad = nlohmann::json::array();
  for (const auto& b : q.bad_list)
    bad.push_back({{"triangle", b.triangle}, {"face", b.face}, {"Q", b.Q}});
  j["bad_list"] = bad;
  return j;
}

nlohmann::json report_json(const CheckData& d) {
  nlohmann::json j;
  j["counts"] = {{"points", d.points}, {"triangles", d.triangles}, {"segments", d.segments}};
  j["quality"] = quality_json(d.quality);

  const surface::TopologyReport& t = d.topology;
  nlohmann::json topo = {{"edges", t.edges},
                         {"free_edges", t.free_edges},
                         {"non_manifold_edges", t.non_manifold_edges},
                         {"inconsistent_edges", t.inconsistent_edges},
                         {"orientation_consistent", t.inconsistent_edges == 0},
                         {"degenerate_triangles", t.degenerate_triangles},
                         {"unreferenced_points", t.unreferenced_points},
                         {"close_points", t.close_points.pairs},
                         {"euler_characteristic", t.euler_characteristic},
                         {"components", d.components},
                         {"watertight", t.watertight()}};
  auto edge_list = [](const std::vector<surface::EdgeIssue>& l) {
    nlohmann::json a = nlohmann::json::array();
    for (const auto& e : l) a.push_back({{"a", e.a}, {"b", e.b}, {"faces", e.faces}});
    return a;
  };
  topo["free_list"] = edge_list(t.free_list);
  topo["non_manifold_list"] = edge_list(t.non_manifold_list);
  topo["inconsistent_list"] = edge_list(t.inconsistent_list);
  if (d.free_edges_on_open_model_edges)
    topo["free_edges_on_open_model_edges"] = *d.free_edges_on_open_model_edges;
  if (!d.solids.empty()) {
    nlohmann::json so = nlohmann::json::array();
    std::size_t not_watertight = 0;
    for (const auto& s : d.solids) {
      nlohmann::json one = {{"solid", s.solid},
                            {"closed", s.closed},
                            {"triangles", s.triangles},
                            {"free_edges", s.free_edges},
                            {"non_manifold_edges", s.non_manifold_edges},
                            {"faces", s.faces}};
      if (s.self_intersections) one["self_intersections"] = *s.self_intersections;
      if (s.self_intersections_in_model)
        one["self_intersections_in_model"] = *s.self_intersections_in_model;
      so.push_back(one);
      not_watertight += s.closed && (s.free_edges > 0 || s.non_manifold_edges > 0);
    }
    topo["solids"] = so;
    topo["closed_solids_not_watertight"] = not_watertight;
  }
  if (d.intersections) {
    topo["self_intersections"] = d.intersections->intersecting_pairs;
    nlohmann::json pairs = nlohmann::json::array();
    for (const auto& p : d.intersections->pairs)
      pairs.push_back({{"t0", p.t0}, {"f0", p.f0}, {"t1", p.t1}, {"f1", p.f1}});
    topo["self_intersection_list"] = pairs;
    if (d.intersections_in_model) topo["self_intersections_in_model"] = *d.intersections_in_model;
    if (d.intersections_in_closed_solids) {
      topo["self_intersections_in_closed_solids"] = *d.intersections_in_closed_solids;
      topo["self_intersections_in_closed_solids_in_model"] =
          d.intersections_in_closed_solids_in_model.value_or(0);
    }
  }
  j["topology"] = topo;

  const surface::EdgeLengthReport& el = d.edge_lengths;
  j["edge_length_distribution"] = {{"edges", el.edges},
                                   {"median", d.median_edge},
                                   {"min", el.min * d.median_edge},
                                   {"max", el.max * d.median_edge},
                                   {"mean", el.mean * d.median_edge},
                                   {"share_within_sqrt2_of_median", el.unit_share}};
  if (d.metric_edge_lengths) {
    j["metric_edge_lengths"] = edge_length_json(*d.metric_edge_lengths);
    j["metric_edge_lengths"]["metric"] = kSizeFieldMetricName;
  } else if (!d.metric_unavailable.empty())
    j["metric_edge_lengths"] = {{"unavailable", d.metric_unavailable}};
  if (d.chordal) {
    const surface::ChordalReport& ch = *d.chordal;
    const double tol = d.chordal_tolerance;
    j["chordal"] = {{"max", ch.max},
                    {"mean", ch.mean},
                    {"tolerance", tol},
                    {"within_tolerance", tol > 0 ? ch.max <= tol : true},
                    {"samples", ch.samples},
                    {"skipped_triangles", ch.skipped_triangles},
                    {"not_converged", ch.not_converged},
                    {"worst_face", ch.worst.face},
                    {"worst_point", {ch.worst.x.x, ch.worst.x.y, ch.worst.x.z}}};
  } else if (!d.chordal_unavailable.empty()) {
    j["chordal"] = {{"unavailable", d.chordal_unavailable}};
  }
  j["histograms"] = {{"q", histogram_json(d.q_histogram)},
                     {"angle_deg", histogram_json(d.angle_histogram)},
                     {"edge_length_over_median", histogram_json(d.edge_histogram)}};
  // JSON has no infinity: the last edge bin's open end is written as null.
  j["histograms"]["edge_length_over_median"]["hi"] = nullptr;
  return j;
}

std::string attach_uv(SurfaceMesh& m, const geom::Model& model) {
  const std::size_t nt = m.triangles.size();
  m.triangle_uv.assign(nt, {geom::Vec2(0.0), geom::Vec2(0.0), geom::Vec2(0.0)});
  std::vector<std::vector<std::size_t>> by_face(model.faces.size());
  for (std::size_t t = 0; t < nt; ++t) {
    const geom::Id f = m.triangle_face[t];
    if (f < 0 || static_cast<std::size_t>(f) >= model.faces.size())
      return "triangle " + std::to_string(t) + " is on face " + std::to_string(f) +
             ", which the model (" + std::to_string(model.faces.size()) + " faces) does not have";
    by_face[static_cast<std::size_t>(f)].push_back(t);
  }
  constexpr int kGrid = 48;
  for (std::size_t f = 0; f < model.faces.size(); ++f) {
    const geom::Face& face = model.faces[f];
    if (by_face[f].empty() || !face.surface) continue;
    const geom::Surface& s = *face.surface;
    geom::Box2 box = face.uv_box;
    if (!(box.u.hi > box.u.lo && box.v.hi > box.v.lo)) box = s.bounds();
    // Start points: the nearest of a grid of sigma samples over the face's box.
    std::vector<geom::Vec2> guv;
    std::vector<geom::Vec3> gp;
    for (int i = 0; i <= kGrid; ++i)
      for (int k = 0; k <= kGrid; ++k) {
        const geom::Vec2 uv(box.u.at(double(i) / kGrid), box.v.at(double(k) / kGrid));
        guv.push_back(uv);
        gp.push_back(s.eval(uv.x, uv.y).p);
      }
    geom::Box3 b3;
    for (const auto& p : gp) b3.add(p);
    const double scale = std::max(b3.diagonal(), 1e-12);
    std::unordered_map<NodeId, geom::Vec2> uv_of;
    for (std::size_t t : by_face[f])
      for (NodeId v : m.triangles[t]) {
        if (uv_of.count(v)) continue;
        const geom::Vec3& x = m.points[static_cast<std::size_t>(v)];
        std::size_t best = 0;
        double bd = std::numeric_limits<double>::infinity();
        for (std::size_t g = 0; g < gp.size(); ++g) {
          const double dd = glm::dot(gp[g] - x, gp[g] - x);
          if (dd < bd) bd = dd, best = g;
        }
        uv_of[v] = geom::project_to_surface(s, x, guv[best], box, scale / kGrid).uv;
      }
    const double pu = s.u_periodic() ? s.u_period() : 0.0, pv = s.v_periodic() ? s.v_period() : 0.0;
    for (std::size_t t : by_face[f]) {
      auto& uv = m.triangle_uv[t];
      for (int k = 0; k < 3; ++k) {
        uv[k] = uv_of[m.triangles[t][k]];
        if (k == 0) continue;
        // The same period as corner 0: a triangle across a seam must not span the domain.
        if (pu > 0) uv[k].x -= pu * std::round((uv[k].x - uv[0].x) / pu);
        if (pv > 0) uv[k].y -= pv * std::round((uv[k].y - uv[0].y) / pv);
      }
    }
  }
  return "";
}

nlohmann::json tet_report_json(const surface::TetMesh& v) {
  auto quality = [](const surface::TetQualityReport& q) {
    return nlohmann::json{
        {"tets", q.tets},
        {"inverted", q.inverted},
        {"volume", q.volume},
        {"min_dihedral_deg",
         {{"min", q.dihedral_min}, {"p01", q.dihedral_p1}, {"median", q.dihedral_p50}}},
        {"radius_edge",
         {{"max", q.radius_edge_max}, {"p99", q.radius_edge_p99}, {"median", q.radius_edge_p50}}}};
  };
  nlohmann::json j = quality(surface::measure_tet_quality(v));
  j["points"] = v.points.size();
  j["interior_points"] = v.points.size() - v.surface_points;
  std::vector<geom::Id> solids(v.tet_solid.begin(), v.tet_solid.end());
  std::sort(solids.begin(), solids.end());
  solids.erase(std::unique(solids.begin(), solids.end()), solids.end());
  nlohmann::json per = nlohmann::json::array();
  for (geom::Id s : solids) {
    nlohmann::json one = quality(surface::measure_tet_quality(v, s));
    one["solid"] = s;
    per.push_back(one);
  }
  j["solids"] = per;
  return j;
}

}  // namespace uvmesh::io
