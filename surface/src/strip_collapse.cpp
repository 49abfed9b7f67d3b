// Strips narrower than the proximity floor, collapsed onto one curve. A face bounded by
// two edges between the same two vertices (a lens), no more than proximity_floor() --
// or the two edges' tolerance floor, when larger -- apart anywhere, is narrower than
// any gap the sizes resolve (BoundaryCaps::cap): meshed, it can only be a row of slivers
// across its width (a planar step a few micrometres wide and centimetres long, against a
// floor several times its width, gave triangles of Q in the hundreds). Resolving it
// instead would need elements as small as the width along the whole strip, graded over
// both faces beside it: tens of thousands of triangles for a feature the sizes were told
// to ignore. So the strip is not meshed, and its two edges become one polyline: the edge
// with more nodes keeps them (primary), the other (secondary) takes the same global nodes
// at the parameters of its own curve closest to them, so the faces on either side meet
// along it by index and the solid stays closed. The geometric error is the strip's
// width, below hmin / 100 and a tenth of the chordal tolerance. Only a two-edge strip
// whose edges each bound one other face, two different ones, is collapsed: a strip
// with end edges, or a slit of one face, would need more than one edge identified.
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "model_run.h"

namespace uvmesh::surface::detail {

namespace {

// Parameter of c in [lo, hi] closest to x: the best of 64 samples, then golden-section
// search between its two neighbours (the curves this is used on are within a fraction of
// a segment of x, so the distance is unimodal there).
double closest_param(const geom::Curve& c, double lo, double hi, const geom::Vec3& x) {
  constexpr int kSamples = 64;
  int best = 0;
  double dbest = std::numeric_limits<double>::infinity();
  for (int k = 0; k <= kSamples; ++k) {
    const double d = glm::length(c.point(lo + (hi - lo) * k / kSamples) - x);
    if (d < dbest) dbest = d, best = k;
  }
  double a = lo + (hi - lo) * std::max(0, best - 1) / kSamples,
         b = lo + (hi - lo) * std::min(kSamples, best + 1) / kSamples;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  for (int it = 0; it < 60 && b - a > 1e-15 * std::max(1.0, std::abs(b)); ++it) {
    const double t1 = b - g * (b - a), t2 = a + g * (b - a);
    if (glm::length(c.point(t1) - x) < glm::length(c.point(t2) - x))
      b = t2;
    else
      a = t1;
  }
  return 0.5 * (a + b);
}

// Largest distance from points of a's curve to b's curve (33 samples, ends included).
double one_sided_distance(const geom::Edge& a, const geom::Edge& b) {
  double d = 0;
  for (int k = 0; k <= 32; ++k) {
    const geom::Vec3 x = a.curve->point(a.range.at(k / 32.0));
    d = std::max(
        d, glm::length(b.curve->point(closest_param(*b.curve, b.range.lo, b.range.hi, x)) - x));
  }
  return d;
}

// Scratch of the step: the faces around each edge, the edges already in a strip.
struct StripScan {
  double floor = 0;  ///< proximity_floor() of the sizes
  std::vector<std::vector<geom::Id>> faces_of;
  std::vector<char> involved;
};

StripScan scan_faces(const ModelRun& run) {
  StripScan s;
  s.floor = proximity_floor(run.spec, std::max(run.m.bbox.diagonal(), 1e-300), run.feature);
  s.faces_of.resize(run.ne);
  for (std::size_t f = 0; f < run.nf; ++f)
    for (const geom::Loop& l : run.m.faces[f].loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.edge >= 0)
          s.faces_of[static_cast<std::size_t>(u.edge)].push_back(static_cast<geom::Id>(f));
  s.involved.assign(run.ne, 0);
  return s;
}

// The two edges of face f when its shape is a strip's: one loop of two distinct,
// non-internal, evaluable edges between the same two distinct vertices.
bool strip_shape(const ModelRun& run, const StripScan& s, std::size_t f, std::size_t& ea,
                 std::size_t& eb) {
  const geom::Face& face = run.m.faces[f];
  if (face.degenerate || !run.face_error[f].empty() || run.twin_of[f] != geom::kNone ||
      face.loops.size() != 1)
    return false;
  const auto& uses = face.loops[0].uses;
  if (uses.size() != 2 || uses[0].internal || uses[1].internal) return false;
  ea = static_cast<std::size_t>(uses[0].edge), eb = static_cast<std::size_t>(uses[1].edge);
  if (ea == eb || s.involved[ea] || s.involved[eb] || !run.edge_error[ea].empty() ||
      !run.edge_error[eb].empty())
    return false;
  const geom::Edge &a = run.m.edges[ea], &b = run.m.edges[eb];
  return !(a.degenerate || b.degenerate || !a.curve || !b.curve || a.v0 == geom::kNone ||
           a.v1 == geom::kNone || a.v0 == a.v1 ||
           !((a.v0 == b.v0 && a.v1 == b.v1) || (a.v0 == b.v1 && a.v1 == b.v0)));
}

// The face other than f around edge e, and how many others there are (-1 when f is not
// among the edge's faces exactly once).
std::pair<geom::Id, int> other_face(const StripScan& s, std::size_t e, std::size_t f) {
  geom::Id o = geom::kNone;
  int n = 0;
  for (geom::Id g : s.faces_of[e])
    if (g != static_cast<geom::Id>(f)) o = g, ++n;
  return std::pair{o, n + 1 == static_cast<int>(s.faces_of[e].size()) ? n : -1};
}

// Face f, a strip of edges ea and eb between faces oa and ob, `width` wide: collapsed.
void collapse(ModelRun& run, StripScan& s, std::size_t f, std::size_t ea, std::size_t eb,
              geom::Id oa, geom::Id ob, double width, double gap_floor) {
  const bool a_first = run.edges[ea].t.size() > run.edges[eb].t.size() ||
                       (run.edges[ea].t.size() == run.edges[eb].t.size() && ea < eb);
  const std::size_t pe = a_first ? ea : eb, se = a_first ? eb : ea;
  run.primary_of[se] = static_cast<geom::Id>(pe);
  s.involved[ea] = s.involved[eb] = 1;
  run.collapsed[f] = 1;
  std::ostringstream os;
  os << "a strip between edges " << pe << " and " << se << " at most " << width
     << " wide, narrower than the proximity floor " << gap_floor
     << (gap_floor > s.floor ? " (the edges' tolerances)"
         : run.feature > 0   ? " (the feature size)"
                             : " (hmin / 100)")
     << ": edge " << se << " takes the nodes of edge " << pe << ", faces " << (a_first ? ob : oa)
     << " and " << (a_first ? oa : ob) << " meet there";
  run.res.collapsed.push_back({static_cast<geom::Id>(f), os.str()});
}

// Face f is a strip to collapse (see the file comment): collapses it.
void try_collapse(ModelRun& run, StripScan& s, std::size_t f) {
  const geom::Model& m = run.m;
  std::size_t ea = 0, eb = 0;
  if (!strip_shape(run, s, f, ea, eb)) return;
  const geom::Edge &a = m.edges[ea], &b = m.edges[eb];
  // Each edge: this face and exactly one other, and the two others differ.
  const auto [oa, na] = other_face(s, ea, f);
  const auto [ob, nb] = other_face(s, eb, f);
  if (na != 1 || nb != 1 || oa == ob || run.collapsed[static_cast<std::size_t>(oa)] ||
      run.collapsed[static_cast<std::size_t>(ob)])
    return;
  double width = 0;
  try {
    width = std::max(one_sided_distance(a, b), one_sided_distance(b, a));
  } catch (...) {
    return;
  }
  // The narrowest gap the sizes resolve between these two edges is BoundaryCaps' gap
  // floor: the proximity floor, or the two edges' tolerance floor when that is larger
  // (a gap inside the tolerance tubes is not refined at all, kGapToleranceFactor).
  const double gap_floor =
      std::max(s.floor, kGapToleranceFactor * (gap_tolerance(m, static_cast<geom::Id>(ea)) +
                                               gap_tolerance(m, static_cast<geom::Id>(eb))));
  // The faces beside the strip then meet at its primary edge, up to `width` off the
  // secondary's face: with a chordal tolerance, only a strip much narrower than it
  // (a tenth: the chords along the primary may use 0.9 of it, see the 1D repair).
  const double chordal_tol = run.opt.size.chordal_tol;
  if (!(width <= gap_floor) || (chordal_tol > 0 && !(width <= 0.1 * chordal_tol))) return;
  collapse(run, s, f, ea, eb, oa, ob, width, gap_floor);
}

}  // namespace

void collapse_strips(ModelRun& run) {
  StripScan s = scan_faces(run);
  for (std::size_t f = 0; f < run.nf; ++f) try_collapse(run, s, f);
  sync_secondaries(run);
}

// The secondary's parameters: those of its curve closest to the primary's nodes, in
// its own direction (again after a crossing round refined the primary).
void sync_secondaries(ModelRun& run) {
  for (std::size_t se = 0; se < run.ne; ++se) {
    if (run.primary_of[se] == geom::kNone) continue;
    const auto pe = static_cast<std::size_t>(run.primary_of[se]);
    const geom::Edge &P = run.m.edges[pe], &S = run.m.edges[se];
    const bool same = P.v0 == S.v0;
    const std::vector<double>& tp = run.edges[pe].t;
    const std::size_t n = tp.size();
    std::vector<double> ts(n);
    ts.front() = S.range.lo;
    ts.back() = S.range.hi;
    double lo = S.range.lo;
    for (std::size_t i = 1; i + 1 < n; ++i) {
      const geom::Vec3 x = P.curve->point(tp[same ? i : n - 1 - i]);
      // Searched beyond the previous node only, so the parameters increase.
      ts[i] = closest_param(*S.curve, lo, S.range.hi, x);
      lo = ts[i];
    }
    run.edges[se].t = std::move(ts);
  }
}

}  // namespace uvmesh::surface::detail
