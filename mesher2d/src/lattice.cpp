// Field points of a uniform field on the equilateral lattice of side h (stage 6 of
// mesher2d, before the saturation waves of field_points.cpp).
#include <algorithm>
#include <cmath>

#include "mesh_state.h"

namespace uvmesh::m2d::detail {

namespace {

// A deterministic pseudo-random offset in [-1e-6, 1e-6) from z (see Lattice::run).
double jitter(std::uint64_t z) {
  return unit_jitter(z) * 1e-6;
}

// The lattice insertion and its state: the domain's bounding box and area, the lattice
// spacing, the insertion parameters and the walk's hint.
struct Lattice {
  explicit Lattice(MeshState& ms_) : ms(ms_) {}
  void run(bool aniso);
  void measure_domain();
  bool try_insert(Vec2 p, TriId from);
  void boundary_layer();
  // Lattice point k = j nx + i. Made again from k when it is inserted rather than read
  // back from the array the order was computed on: in insertion order that read was a
  // cache miss per point, 6% of the whole uniform-field mesher's time at 1e6 triangles.
  Vec2 lattice_point(std::int64_t k) const {
    const std::int64_t j = k / nx, i = k - j * nx;
    const auto u = static_cast<std::uint64_t>(k);
    return Vec2{xmin + (static_cast<double>(i) + ((j & 1) ? 0.5 : 0.0) + jitter(2 * u)) * h,
                ymin + (static_cast<double>(j) + 0.5) * dy + jitter(2 * u + 1) * h};
  }

  MeshState& ms;
  double xmin = 1e300, ymin = 1e300, xmax = -1e300, ymax = -1e300, area2 = 0;
  double h = 0, dy = 0;
  std::int64_t nx = 0, ny = 0;
  InsertParams prm;
  TriId hint = kNone;
  std::int64_t inserted = 0;
};

// The bounding box and twice the area of the domain's triangles.
void Lattice::measure_domain() {
  const TriId nt = ms.tri.num_tris();
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    {
      const Vec2 a = ms.tri.point(ms.tri.vertex(t, 0)), b = ms.tri.point(ms.tri.vertex(t, 1)),
                 c = ms.tri.point(ms.tri.vertex(t, 2));
      area2 += (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    }
    for (int i = 0; i < 3; ++i) {
      const Vec2 p = ms.tri.point(ms.tri.vertex(t, i));
      xmin = std::min(xmin, p.x), xmax = std::max(xmax, p.x), ymin = std::min(ymin, p.y),
      ymax = std::max(ymax, p.y);
    }
  }
}

// Inserts p (walking from triangle from) when it lies in the domain and passes the filter.
bool Lattice::try_insert(Vec2 p, TriId from) {
  double o[3];
  const TriId t = ms.tri.locate(p, from, o);
  if (t == kNone) return false;
  hint = t;
  if (!ms.in_domain(t)) return false;
  const auto r = ms.tri.insert_point_located(p, t, o, prm);
  if (r.status != InsertStatus::Inserted) return false;
  hint = ms.tri.vertex_tri(r.v);
  ms.vm.push_back(ms.m_uniform);
  ms.rs.push_back(1.0);
  ms.fixed.push_back(0);
  ms.vmark.push_back(0);
  ++inserted;
  return true;
}

// First the layer along the boundary (§7.4.3, the optimal point of each boundary
// edge: the apex of the equilateral triangle on it, inside), and before it one
// point on the bisector of every corner of 90-150 degrees (two triangles of half
// the angle there; the edges' apexes near it are then filtered out): the boundary
// vertices get the valence of their angle (round(theta / 60deg)) and the lattice's
// misfit is pushed off the fixed boundary to where every vertex can move.
void Lattice::boundary_layer() {
  const TriId nt = ms.tri.num_tris();
  const VertId nv = ms.tri.num_verts();
  std::vector<VertId> nxt(nv, kNone), prv(nv, kNone);
  std::vector<char> multi(nv, 0);
  for (TriId t = 0; t < nt; ++t) {
    if (!ms.in_domain(t)) continue;
    for (int i = 0; i < 3; ++i) {
      if (ms.tri.constraint(3 * t + i) == kNone) continue;
      const VertId a = ms.tri.vertex(t, next3(i)), b = ms.tri.vertex(t, prev3(i));
      if (nxt[a] != kNone) multi[a] = 1;
      if (prv[b] != kNone) multi[b] = 1;
      nxt[a] = b;
      prv[b] = a;
    }
  }
  const auto& P = ms.tri.points();
  for (VertId v = 4; v < nv; ++v) {
    if (multi[v] || nxt[v] == kNone || prv[v] == kNone) continue;
    const Vec2 pv = P[v], pn = P[nxt[v]], pp = P[prv[v]];
    const double ux = pn.x - pv.x, uy = pn.y - pv.y, wx = pp.x - pv.x, wy = pp.y - pv.y;
    double th = std::atan2(ux * wy - uy * wx, ux * wx + uy * wy);  // from u to w, CCW
    if (th < 0) th += 2 * 3.14159265358979323846;
    if (th < 1.5 || th > 2.6) continue;  // about 86-149 degrees
    const double lu = std::hypot(ux, uy), lw = std::hypot(wx, wy);
    const double bx = ux / lu + wx / lw, by = uy / lu + wy / lw, bl = std::hypot(bx, by);
    if (!(bl > 0)) continue;
    const double r = std::min(h, 0.5 * (lu + lw));
    try_insert({pv.x + r * bx / bl, pv.y + r * by / bl}, ms.tri.vertex_tri(v));
  }
  for (VertId a = 4; a < nv; ++a) {
    const VertId b = nxt[a];
    if (b == kNone || multi[a]) continue;
    const Vec2 pa = P[a], pb = P[b];
    // Left normal of a -> b (the domain side), scaled to the height of the equilateral.
    try_insert({0.5 * (pa.x + pb.x) - 0.8660254037844386 * (pb.y - pa.y),
                0.5 * (pa.y + pb.y) + 0.8660254037844386 * (pb.x - pa.x)},
               ms.tri.vertex_tri(a));
  }
}

// The lattice in the kernel's insertion order (BRIO rounds, Hilbert order inside each,
// as the hull fast path): inserted row by row, every point's cavity held the fan of
// long thin triangles joining the last row to the far boundary (19 triangles per
// insertion on average at 5e5 points, against about 4 in this order). The set of
// points kept does not depend on the order: lattice points are h apart, beyond the
// filter distance, so only the boundary and its layer (inserted before) filter them.
// Every point is moved by a deterministic pseudo-random offset of at most 1e-6 h in
// x and in y (jitter): the exact lattice is as degenerate as a point set can be (whole
// rows on one line, every rectangle and hexagon of lattice points on one circle), and
// while it is built such quadruples meet in the cavity tests, which the floating-point
// filter cannot decide (0.35 orientation and 0.2 incircle tests per point went to the
// exact arithmetic). Offsets far above the rounding make the filter decide; the finished
// lattice triangulation is the same (an equilateral lattice has no empty circle
// through four points) and its shapes change by about 1e-6.
void Lattice::run(bool aniso) {
  measure_domain();
  if (!(xmax > xmin) || !(ymax > ymin)) return;
  h = ms.h_uniform, dy = 0.8660254037844386 * h;
  nx = static_cast<std::int64_t>((xmax - xmin) / h) + 2;
  ny = static_cast<std::int64_t>((ymax - ymin) / dy) + 2;
  // A domain filling little of its bounding box (a thin diagonal strip) would make the
  // scan mostly point location outside it: saturation alone does that case.
  if (nx * ny > ms.opt.max_vertices ||
      static_cast<double>(nx * ny) * h * dy > 8 * (0.5 * area2) + 64 * h * h)
    return;
  {
    // Room for the points to come (about the area over a lattice cell), so that the
    // arrays do not grow by reallocation while they are inserted.
    const auto nv = static_cast<std::size_t>(ms.tri.num_verts()) +
                    static_cast<std::size_t>(0.55 * area2 / (h * dy)) + 1024;
    ms.tri.reserve_huge(nv);
    ms.vm.reserve(nv), ms.rs.reserve(nv), ms.fixed.reserve(nv), ms.vmark.reserve(nv);
  }
  prm.m = ms.m_uniform;
  prm.use_metric = aniso;
  prm.min_dist = kFilterDist;
  hint = ms.tri.vertex_tri(ms.tri.num_verts() - 1);
  boundary_layer();
  std::vector<std::uint64_t> order;
  {
    std::vector<Vec2> lat(static_cast<std::size_t>(nx * ny));
    for (std::int64_t k = 0; k < nx * ny; ++k) lat[static_cast<std::size_t>(k)] = lattice_point(k);
    brio_order(lat, order);
  }
  std::size_t since_check = 0;
  for (const std::uint64_t rec : order) {
    if (++since_check == 4096) {
      since_check = 0;
      if (ms.over_time("refinement")) return;
    }
    try_insert(lattice_point(static_cast<std::int64_t>(rec & 0xFFFFFFFFu)), hint);
  }
  ms.res.stats.field_points_inserted += inserted;
  ms.lattice_used = true;
}

}  // namespace

// Field points of a uniform field on the equilateral lattice of side h: in a constant
// metric the unit mesh whose every edge has length one (§7.5.2) is that lattice, and
// all its triangles are optimal. Lattice points closer than kFilterDist to an existing
// vertex (the boundary) are dropped by the kernel's filter; the band between the
// boundary and the lattice is then filled by saturation waves and repaired by the
// optimization.
void lattice_points(MeshState& ms, bool aniso) {
  Lattice lat(ms);
  lat.run(aniso);
}

}  // namespace uvmesh::m2d::detail
