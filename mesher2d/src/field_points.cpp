// Stage 6 of mesher2d: field points by edge saturation (§7.3.5, §7.5.2), with the
// anisotropic kernel (§7.6.1) for a metric field. A uniform field first gets the
// equilateral lattice (lattice.cpp).
#include "field_points.h"

#include <algorithm>
#include <cmath>

namespace uvmesh::m2d::detail {

namespace {

// Saturation skips the full sampling of an edge whose metric lengths at both ends and at
// the midpoint, and their Simpson mean, are under this (margin under sqrt2).
constexpr double kSkipSample = 1.25;
// Saturation waves stop when no edge is longer than sqrt2 or after this many waves.
constexpr int kMaxWaves = 200;

std::uint64_t edge_key(VertId a, VertId b) {
  return static_cast<std::uint64_t>(std::min(a, b)) << 32 |
         static_cast<std::uint32_t>(std::max(a, b));
}

// The kernel's field-point filter (InsertParams::min_dist, with vertex_metrics) applied
// to the three vertices of triangle t.
bool too_close_to_corner(const Triangulation& tri, TriId t, Vec2 p, const InsertParams& prm) {
  for (int i = 0; i < 3; ++i) {
    const VertId a = tri.vertex(t, i);
    if (filter_too_close(prm, a, tri.point(a), p)) return true;
  }
  return false;
}

}  // namespace

// Every vertex's metric, and the boundary size ratios (Options::boundary_gradation).
void FieldPoints::init_vertex_metrics() {
  const std::size_t nv = ms.tri.points().size();
  ms.vm.resize(nv);
  for (std::size_t v = 4; v < nv; ++v) ms.vm[v] = ms.metric(ms.tri.point(v).x, ms.tri.point(v).y);
  ms.vm[0] = ms.vm[1] = ms.vm[2] = ms.vm[3] = ms.m_uniform;
  ms.rs.assign(nv, 1.0);
  from_boundary = ms.opt.boundary_gradation > 1 && ms.size.kind != SizeSpec::Kind::Uniform;
  if (!from_boundary) return;
  // A boundary vertex whose constrained edges are shorter than unit in the field
  // gets that length as its size ratio: its metric is scaled by 1 / ratio^2.
  for (TriId t = 0; t < ms.tri.num_tris(); ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      const std::int32_t sg = ms.tri.constraint(3 * t + i);
      if (sg == kNone || ms.segs[sg].marker < 0) continue;
      const VertId a = ms.tri.vertex(t, next3(i)), b = ms.tri.vertex(t, prev3(i));
      const double l = ms.edge_length(a, b);
      if (l < 1)
        ms.rs[a] = std::min(ms.rs[a], std::max(l, 1e-6)),
        ms.rs[b] = std::min(ms.rs[b], std::max(l, 1e-6));
    }
  }
  for (std::size_t v = 4; v < nv; ++v)
    if (ms.rs[v] < 1) ms.vm[v] = scaled(ms.vm[v], 1.0 / (ms.rs[v] * ms.rs[v]));
}

// The triangles around the vertices the last wave inserted, and their neighbours: sorted
// for saturation (the full scan's order, see FieldPoints), in the order the points were
// inserted for the fronts (along the front, as the last wave went; a sort of the set was
// a twentieth of the front waves' time).
void FieldPoints::scan_set() {
  const TriId nt = ms.tri.num_tris();
  scan.clear();
  if (tmark.size() < static_cast<std::size_t>(nt)) tmark.resize(nt, 0);
  ++tepoch;
  auto take = [&](TriId t) {
    if (tmark[t] == tepoch) return;
    tmark[t] = tepoch;
    scan.push_back(t);
  };
  for (const VertId v : born)
    ms.for_ball(v, [&](TriId t) {
      take(t);
      for (int i = 0; i < 3; ++i)
        if (ms.tri.twin(3 * t + i) != kNone) take(ms.tri.twin(3 * t + i) / 3);
    });
  if (!ms.fronts_used) std::sort(scan.begin(), scan.end());
}

void FieldPoints::wave_candidates(bool subset) {
  const TriId nt = ms.tri.num_tris();
  const TriId nscan = subset ? static_cast<TriId>(scan.size()) : nt;
  for (TriId st = 0; st < nscan; ++st) {
    const TriId t = subset ? scan[st] : st;
    // The vertices of the triangles a few steps ahead are fetched now: triangle slots
    // are reused by later insertions, so a triangle's vertices lie anywhere in the
    // vertex array, and these loads were nearly half of the uniform field's scan.
    if (st + 8 < nscan) {
      const TriId ta = subset ? scan[st + 8] : st + 8;
      for (int k = 0; k < 3; ++k) {
        const VertId w = ms.tri.vertex(ta, k);
        if (w >= 0) __builtin_prefetch(&ms.tri.point(w));
      }
      // And the analysed-edge slots of its edges: the set outgrows the cache, and its
      // lookups were the costliest line of the anisotropic scan.
      if (use_analysed)
        for (int k = 0; k < 3; ++k) {
          const VertId a = ms.tri.vertex(ta, k), b = ms.tri.vertex(ta, (k + 1) % 3);
          analysed.prefetch(edge_key(a, b));
        }
    }
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) edge_candidates(t, i);
  }
}

// The candidates of edge i of triangle t (§7.5.2): points at unit spacing in the metric
// along the edge. A uniform field needs no sampling; any other is sampled along the edge
// (eq. 7.10).
void FieldPoints::edge_candidates(TriId t, int i) {
  if (ms.tri.constraint(3 * t + i) != kNone) return;
  const std::int32_t g = ms.tri.twin(3 * t + i);
  if (g / 3 < t) return;  // each edge once (both sides are in the domain)
  const VertId a = ms.tri.vertex(t, next3(i)), b = ms.tri.vertex(t, prev3(i));
  const Vec2 pa = ms.tri.point(a), pb = ms.tri.point(b);
  const Vec2 d{pb.x - pa.x, pb.y - pa.y};
  if (ms.size.kind == SizeSpec::Kind::Uniform) {
    // Squared length first: after the lattice nearly every edge is short, and
    // a scan is one pass over all the triangles per wave.
    const Metric2& mu = ms.m_uniform;
    if (!(mu.m11 * d.x * d.x + 2 * mu.m12 * d.x * d.y + mu.m22 * d.y * d.y > 1.99)) return;
    const double L = length(ms.m_uniform, d);
    if (!(L > measures::kUnitMax)) return;
    const int n = std::max(2, static_cast<int>(std::lround(L)));
    for (int k = 1; k < n; ++k)
      cands.push_back({{pa.x + d.x * k / n, pa.y + d.y * k / n}, a, k > 1});
    return;
  }
  if (!(ms.edge_length(a, b) > 0.5)) return;  // short even with a bump in between
  if (!from_boundary) {
    // An edge analysed in an earlier wave gives the same candidates again (its
    // ends never move during refinement and the field is fixed), and those were
    // inserted or rejected by the filter, which only gets stricter as vertices
    // are added: it is not analysed again. Without this every wave re-sampled
    // the whole mesh (a thin ring-shaped metric: 10 k edges and 110 k field evaluations
    // per wave in the middle waves, for a few dozen insertions).
    if (!analysed.insert(edge_key(a, b))) return;
  }
  const double ra = ms.rs[a], rb = ms.rs[b];
  if (!(ra < 1) && !(rb < 1)) {
    // Saturated edges are most of the mesh after the first waves: three samples
    // (the ends and the midpoint, Simpson's rule) settle them with one field
    // evaluation instead of the 3-7 of the full sampling. Only an edge short at
    // all three, with a length estimate well under sqrt2, is skipped.
    const double la = length(ms.vm[a], d), lb = length(ms.vm[b], d);
    if (la < kSkipSample && lb < kSkipSample) {
      const double lm = length(ms.metric(pa.x + 0.5 * d.x, pa.y + 0.5 * d.y), d);
      if (lm < kSkipSample && (la + 4 * lm + lb) / 6 < kSkipSample) return;
    }
  }
  const double L = es.sample(pa, pb, ms.vm[a], ms.vm[b], ra, rb);
  if (!(L > measures::kUnitMax)) return;
  const int n = std::max(2, static_cast<int>(std::lround(L)));
  bool first = true;
  // Unscaled metric length of the edge, for the gradation bound of ratio_at.
  const double lu =
      (ra < 1 || rb < 1) ? 0.5 * (length(ms.vm[a], d) * ra + length(ms.vm[b], d) * rb) : 0;
  // The vertices opposite the edge bound the ratio too: a long edge leaving a
  // finely split boundary at a shallow angle passes its neighbours closer than
  // its own end, and a point placed with the ratio of the ends alone is then
  // "too close" in its own metric -- rejected wave after wave, which left fans of
  // slivers between a fine and a coarse boundary.
  const VertId oc = ms.tri.vertex(t, i), od = g != kNone ? ms.tri.apex(g) : kNone;
  auto bound = [&](VertId c, Vec2 p) {
    if (!from_boundary || c == kNone || c < 4 || !(ms.rs[c] < 1)) return 1.0;
    const Vec2 dc{p.x - ms.tri.point(c).x, p.y - ms.tri.point(c).y};
    return ms.rs[c] + (ms.opt.boundary_gradation - 1) * length(ms.vm[c], dc) * ms.rs[c];
  };
  es.split_params(n, [&](double tt) {
    const Vec2 p{pa.x + tt * d.x, pa.y + tt * d.y};
    double r = (ra < 1 || rb < 1) ? es.ratio_at(ra, rb, tt, lu) : 1.0;
    r = std::max(std::min({r, bound(oc, p), bound(od, p)}), 1e-6);
    cands.push_back({p, a, !first, r});
    first = false;
  });
}

// Inserts the wave's candidates through the field-point filter.
FieldPoints::Next FieldPoints::insert_candidates() {
  std::int64_t inserted = 0;
  VertId last_v = kNone;
  std::size_t since_check = 0;
  for (const Cand& c : cands) {
    if (++since_check == 4096) {
      since_check = 0;
      if (ms.over_time("refinement")) return Next::Stop;
    }
    if (static_cast<std::int64_t>(ms.tri.points().size()) >= ms.opt.max_vertices) {
      ms.res.status.code = StatusCode::Incomplete;
      ms.res.status.message =
          "refinement stopped at max_vertices = " + std::to_string(ms.opt.max_vertices);
      return Next::Stop;
    }
    InsertParams prm;
    prm.m = ms.metric(c.p.x, c.p.y);
    if (c.r < 1) prm.m = scaled(prm.m, 1.0 / (c.r * c.r));
    prm.use_metric = aniso;
    prm.min_dist = kFilterDist;
    if (from_boundary) prm.vertex_metrics = ms.vm.data(), prm.num_vertex_metrics = ms.vm.size();
    // Walk from the previous candidate of the same edge when there is one: on the
    // long edges of the first waves the edge's end can be far away.
    const TriId hint =
        c.chained && last_v != kNone ? ms.tri.vertex_tri(last_v) : ms.tri.vertex_tri(c.hint);
    // The field-point filter first on the vertices of the triangle holding the point
    // (they are cavity vertices, which the kernel's filter checks): most candidates
    // are rejected there without building a cavity.
    double o[3];
    const TriId t0 = ms.tri.locate(c.p, hint, o);
    const bool off_region =
        c.region != kNone && (t0 == kNone || !ms.in_domain(t0) || ms.tri.tag(t0) != c.region);
    if (off_region || (t0 != kNone && too_close_to_corner(ms.tri, t0, c.p, prm))) {
      last_v = ms.tri.vertex(t0, 0);  // the next candidate of the edge walks from here
      ++ms.res.stats.field_points_rejected;
      continue;
    }
    const auto r = t0 != kNone ? ms.tri.insert_point_located(c.p, t0, o, prm)
                               : ms.tri.insert_point(c.p, hint, prm);
    last_v = r.v;
    if (r.status == InsertStatus::Inserted) {
      born.push_back(r.v);
      ms.vm.push_back(prm.m);
      ms.rs.push_back(c.r);
      ms.fixed.push_back(0);
      ms.vmark.push_back(0);
      ++inserted;
    } else {
      ++ms.res.stats.field_points_rejected;
    }
  }
  ms.res.stats.field_points_inserted += inserted;
  return inserted == 0 ? Next::Done : Next::Wave;
}

// Waves of candidates (made by the given member) inserted through the filter, until a
// wave makes none or inserts none; count gets the number of waves run. False when
// refinement was stopped (time limit, max_vertices).
bool FieldPoints::waves(void (FieldPoints::*candidates)(bool), int max_waves, int& count) {
  for (int wave = 0; wave < max_waves && !ms.field_error; ++wave) {
    cands.clear();
    const bool subset = wave > 0;
    if (subset) scan_set();
    born.clear();
    (this->*candidates)(subset);
    if (cands.empty()) break;
    if (ms.over_time("refinement")) return false;
    const Next next = insert_candidates();
    count = wave + 1;
    if (next != Next::Wave) return next == Next::Done;
  }
  return true;
}

// The saturation waves (§7.5.2) until no edge is longer than sqrt2.
bool FieldPoints::saturation_waves() {
  use_analysed = !from_boundary && ms.size.kind != SizeSpec::Kind::Uniform;
  return waves(&FieldPoints::wave_candidates, kMaxWaves, ms.res.stats.saturation_waves);
}

void FieldPoints::run() {
  init_vertex_metrics();
  aniso = ms.size.kind == SizeSpec::Kind::Metric && ms.opt.anisotropic_kernel;
  if (ms.opt.field_points == FieldPointMethod::Frontal) {
    ms.fronts_used = true;
    if (!front_waves()) return;
  } else if (ms.size.kind == SizeSpec::Kind::Uniform) {
    lattice_points(ms, aniso);
  }
  saturation_waves();
}

void insert_field_points(MeshState& ms) {
  FieldPoints fp(ms);
  fp.run();
}

}  // namespace uvmesh::m2d::detail
