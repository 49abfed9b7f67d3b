// Stage 6 of mesher2d, Options::field_points == Frontal: the combined advancing-front-
// Delaunay method of §7.4.3 (after Rebay; Frey, Borouchaki and George). The mesh stays a
// Delaunay triangulation throughout (the kernel of §7.3.2, anisotropic as in §7.6.1); only
// the choice of the points is frontal: each wave places, on every edge of the front, the
// point that makes a unit equilateral triangle with it in the metric.
#include <algorithm>
#include <cmath>

#include "field_points.h"

namespace uvmesh::m2d::detail {

namespace {

// A triangle is accepted when its circumradius in the metric is at most this. The unit
// equilateral triangle has 1/sqrt3 = 0.577; a triangle whose edges are all at the unit
// mesh's upper bound sqrt2 has 0.816. Only nearly unit equilateral triangles are
// accepted (0.58 passes the equilateral with edges up to 1.005), so that the front goes
// on from unit triangles only: a looser bound lets the front go on from the distorted
// triangles where fronts meet, and the next wave's points inherit their distortion, which
// the optimization (fixed-topology relocation, local repair) does not undo
// (bench/results.md).
constexpr double kAcceptRadius = 0.58;
// Height of the unit equilateral triangle on a unit edge.
constexpr double kEquilateralHeight = 0.8660254037844386;
// The front point stays strictly inside the active triangle's circumdisk (§7.4.3): its
// height over the edge is at most this share of the disk's extent along the normal.
constexpr double kInsideDisk = 0.98;
// Front waves stop when a wave inserts nothing; this only bounds a run that would not
// (every wave inserts at least one point, and max_vertices bounds those).
constexpr int kMaxFrontWaves = 1 << 20;

// Circumcentre of triangle abc (counter-clockwise, area2 > 0) and its circumradius.
struct Disk {
  Vec2 o;
  double r;
};
Disk circumdisk(Vec2 a, Vec2 b, Vec2 c) {
  const double bx = b.x - a.x, by = b.y - a.y, cx = c.x - a.x, cy = c.y - a.y;
  const double d = 2 * (bx * cy - by * cx);
  const double b2 = bx * bx + by * by, c2 = cx * cx + cy * cy;
  const double ox = (cy * b2 - by * c2) / d, oy = (bx * c2 - cx * b2) / d;
  return {{a.x + ox, a.y + oy}, std::sqrt(ox * ox + oy * oy)};
}

// The optimal point of edge ab (§7.4.3) in a frame where the metric is Euclidean: on the
// perpendicular bisector of ab, on the side of c, at the height that makes its distance
// to a and b one (the unit equilateral triangle on a unit edge; at least half the edge,
// a right angle, on an edge longer than sqrt2), clipped inside the circumdisk of abc.
// Returns false when abc is degenerate in the frame.
bool optimal_point(Vec2 a, Vec2 b, Vec2 c, Vec2& p) {
  const double ex = b.x - a.x, ey = b.y - a.y, L = std::sqrt(ex * ex + ey * ey);
  const double area2 = ex * (c.y - a.y) - ey * (c.x - a.x);
  if (!(L > 0) || !(area2 > 0)) return false;
  const double half = 0.5 * L;
  const Vec2 mid{a.x + 0.5 * ex, a.y + 0.5 * ey}, n{-ey / L, ex / L};  // n: toward c
  double height = std::max(std::sqrt(std::max(1 - half * half, 0.0)), half);
  if (std::abs(L - 1) < 1e-12) height = kEquilateralHeight;
  const Disk dk = circumdisk(a, b, c);
  const double q = (dk.o.x - mid.x) * n.x + (dk.o.y - mid.y) * n.y;  // centre along n
  height = std::min(height, kInsideDisk * (q + dk.r));
  if (!(height > 0)) return false;
  p = {mid.x + height * n.x, mid.y + height * n.y};
  return true;
}

// Front points are moved by up to this share of the unit size (unit_jitter): rows of
// front points on a straight boundary are collinear and cocircular by construction, and
// such ties go to the exact arithmetic of the predicates (as the lattice's, lattice.cpp);
// the offset makes the floating-point filter decide, while the predicates stay exact.
constexpr double kJitter = 1e-6;

}  // namespace

// Accepted (§7.4.3): the circumradius of t in the mean of its vertex metrics (Euclidean
// over h for a uniform field) is that of a unit triangle, within kAcceptRadius.
bool FieldPoints::accepted(TriId t) const {
  if (acc_mark[t] == acc_epoch) return acc_value[t];
  const VertId a = ms.tri.vertex(t, 0), b = ms.tri.vertex(t, 1), c = ms.tri.vertex(t, 2);
  Vec2 pa = ms.tri.point(a), pb = ms.tri.point(b), pc = ms.tri.point(c);
  double radius = kAcceptRadius * ms.h_uniform;  // Euclidean for a uniform field
  if (ms.size.kind != SizeSpec::Kind::Uniform) {
    const MetricFrame f(mean3(ms.vm[a], ms.vm[b], ms.vm[c]));
    pa = f(pa), pb = f(pb), pc = f(pc), radius = kAcceptRadius;
  }
  const double ab2 = (pb.x - pa.x) * (pb.x - pa.x) + (pb.y - pa.y) * (pb.y - pa.y),
               bc2 = (pc.x - pb.x) * (pc.x - pb.x) + (pc.y - pb.y) * (pc.y - pb.y),
               ca2 = (pa.x - pc.x) * (pa.x - pc.x) + (pa.y - pc.y) * (pa.y - pc.y);
  const double area2 = (pb.x - pa.x) * (pc.y - pa.y) - (pb.y - pa.y) * (pc.x - pa.x);
  // R = ab bc ca / (2 area2) <= radius, squared, without a root or a division.
  const double lim = 2 * radius * area2;
  const bool ok = area2 > 0 && ab2 * bc2 * ca2 <= lim * lim;
  acc_mark[t] = acc_epoch;
  acc_value[t] = ok;
  return ok;
}

// Edge i of the unaccepted triangle t is on the front when the other side is accepted,
// outside the domain, across a constraint or the box border (§7.4.3: the boundary counts
// as accepted on the outside).
bool FieldPoints::front_edge(TriId t, int i) const {
  const std::int32_t h = 3 * t + i, g = ms.tri.twin(h);
  if (ms.tri.constraint(h) != kNone || g == kNone) return true;
  const TriId u = g / 3;
  return !ms.in_domain(u) || accepted(u);
}

// The boundary size ratio at p bounded by vertex c's (Options::boundary_gradation): it
// grows back at the gradation rate with the metric distance from c, as in saturation.
double FieldPoints::front_ratio(VertId c, Vec2 p) const {
  if (!from_boundary || c < 4 || !(ms.rs[c] < 1)) return 1.0;
  const Vec2 d{p.x - ms.tri.point(c).x, p.y - ms.tri.point(c).y};
  return ms.rs[c] + (ms.opt.boundary_gradation - 1) * length(ms.vm[c], d) * ms.rs[c];
}

// The candidate of front edge i of t: the optimal point in the metric at the edge (the
// mean of its end metrics), then once more in the mean of that and the metric at the
// point (§7.4.3: the point is checked in its own metric; the mean moves it halfway to
// what that metric asks). Each computation stays inside t's circumdisk in its frame.
void FieldPoints::front_point(TriId t, int i) {
  const VertId a = ms.tri.vertex(t, next3(i)), b = ms.tri.vertex(t, prev3(i)),
               c = ms.tri.vertex(t, i);
  const Vec2 pa = ms.tri.point(a), pb = ms.tri.point(b), pc = ms.tri.point(c);
  const bool uniform = ms.size.kind == SizeSpec::Kind::Uniform;
  const Metric2 me = uniform ? ms.m_uniform : mix(ms.vm[a], ms.vm[b], 0.5);
  auto place = [&](const Metric2& m, Vec2& p) {
    const MetricFrame f(m);
    Vec2 q;
    if (!optimal_point(f(pa), f(pb), f(pc), q)) return false;
    const auto z = 2 * static_cast<std::uint64_t>(ms.tri.num_verts() + cands.size());
    p = f.inv({q.x + kJitter * unit_jitter(z), q.y + kJitter * unit_jitter(z + 1)});
    return true;
  };
  Vec2 p;
  if (!place(me, p)) return;
  double r = 1;
  if (!uniform) {
    r = std::max(std::min({front_ratio(a, p), front_ratio(b, p), front_ratio(c, p), 1.0}), 1e-6);
    Metric2 mp = ms.metric(p.x, p.y);
    if (r < 1) mp = scaled(mp, 1.0 / (r * r));
    if (!place(mix(me, mp, 0.5), p)) return;
  }
  cands.push_back({p, a, false, r, ms.tri.tag(t)});
}

// The wave's candidates: every front edge of every unaccepted triangle of the domain (in
// the scan set after the first wave: a triangle away from the last wave's points has the
// same neighbours and the same acceptance, so its candidates were tried already).
void FieldPoints::front_candidates(bool subset) {
  // Acceptance is computed once per triangle and wave (a triangle is seen from its three
  // neighbours); no triangle changes while the candidates are made.
  const TriId nt = ms.tri.num_tris();
  if (acc_mark.size() < static_cast<std::size_t>(nt)) acc_mark.resize(nt, 0), acc_value.resize(nt);
  ++acc_epoch;
  const TriId nscan = subset ? static_cast<TriId>(scan.size()) : nt;
  for (TriId st = 0; st < nscan; ++st) {
    const TriId t = subset ? scan[st] : st;
    if (!ms.in_domain(t) || accepted(t)) continue;
    for (int i = 0; i < 3; ++i)
      if (front_edge(t, i)) front_point(t, i);
  }
}

// Front waves until a wave inserts nothing; false when refinement was stopped (time
// limit, max_vertices) and the saturation waves must not run.
bool FieldPoints::front_waves() {
  return waves(&FieldPoints::front_candidates, kMaxFrontWaves, ms.res.stats.frontal_waves);
}

}  // namespace uvmesh::m2d::detail
