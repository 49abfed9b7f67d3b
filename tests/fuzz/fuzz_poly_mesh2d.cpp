// libFuzzer target: Triangle .poly text -> uvmesh::cli2d::parse_poly -> every coordinate
// snapped to a coarse integer grid -> uvmesh::m2d::mesh -> uvmesh::m2d::check.
//
// Why snap: random doubles are in general position, and the mesher's hard cases are
// the degenerate ones (collinear points on segments, four cocircular points, duplicate
// vertices, segments through vertices). On a grid of integers in [-8, 8] most inputs are
// degenerate. Hole and region seeds go to half-integers, so that they can sit on a
// segment or strictly inside a cell.
//
// A finding is: a crash or sanitizer report; a mesh the mesher calls Ok that its own
// checker rejects; or status InternalError (the mesher's checker caught itself).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/poly.h"

namespace {

namespace m2d = uvmesh::m2d;

double snap(double x, double step) {
  const double c = std::fmin(std::fmax(x, -8.0), 8.0);
  return std::round(c / step) * step;
}

// The snapped PSLG as a .poly file (0-based, no markers): what the mesher was given, for
// a regression file and a report to mesher2d's owner.
void print_poly(const m2d::Pslg& p, std::FILE* out) {
  std::fprintf(out, "%zu 2 0 0\n", p.points.size());
  for (std::size_t i = 0; i < p.points.size(); ++i)
    std::fprintf(out, "%zu %.17g %.17g\n", i, p.points[i].x, p.points[i].y);
  std::fprintf(out, "%zu 0\n", p.segments.size());
  for (std::size_t i = 0; i < p.segments.size(); ++i)
    std::fprintf(out, "%zu %d %d\n", i, static_cast<int>(p.segments[i].a),
                 static_cast<int>(p.segments[i].b));
  std::fprintf(out, "%zu\n", p.holes.size());
  for (std::size_t i = 0; i < p.holes.size(); ++i)
    std::fprintf(out, "%zu %.17g %.17g\n", i, p.holes[i].x, p.holes[i].y);
  std::fprintf(out, "%zu\n", p.regions.size());
  for (std::size_t i = 0; i < p.regions.size(); ++i)
    std::fprintf(out, "%zu %.17g %.17g %.17g\n", i, p.regions[i].seed.x, p.regions[i].seed.y,
                 p.regions[i].attribute);
}

[[noreturn]] void finding(const char* what, const std::string& detail, const m2d::Pslg& p, double h,
                          const m2d::Options& opt) {
  std::fprintf(stderr, "fuzz_poly_mesh2d: %s: %s\n", what, detail.c_str());
  std::fprintf(
      stderr,
      "fuzz_poly_mesh2d: uniform size %g, split_crossing_segments %d, optimize %d, frontal %d, "
      "feature_size %d; the PSLG:\n",
      h, opt.split_crossing_segments ? 1 : 0, opt.optimize ? 1 : 0,
      opt.field_points == m2d::FieldPointMethod::Frontal ? 1 : 0, opt.feature_size ? 1 : 0);
  print_poly(p, stderr);
  std::abort();
}

// True when a point lies strictly inside a segment (the coordinates are small integers,
// so the cross product is exact). Overlapping collinear segments are a special case. The
// mesher returns Ok on such inputs while m2d::check rejects the mesh (finding 2,
// tests/mesher2d/data/fuzz_mesher2d_overlapping_segments.poly); the check is skipped for
// them so that the run goes on to find other things.
bool point_inside_a_segment(const m2d::Pslg& p) {
  for (const m2d::Pslg::Segment& s : p.segments) {
    const m2d::Vec2 a = p.points[static_cast<std::size_t>(s.a)],
                    b = p.points[static_cast<std::size_t>(s.b)];
    for (const m2d::Vec2& q : p.points) {
      const double cross = (b.x - a.x) * (q.y - a.y) - (b.y - a.y) * (q.x - a.x);
      const double dot = (q.x - a.x) * (b.x - a.x) + (q.y - a.y) * (b.y - a.y);
      const double len2 = (b.x - a.x) * (b.x - a.x) + (b.y - a.y) * (b.y - a.y);
      if (cross == 0 && dot > 0 && dot < len2) return true;
    }
  }
  return false;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 4096) return 0;  // small domains: many iterations per second
  const std::string text(reinterpret_cast<const char*>(data), size);
  std::istringstream in(text);
  uvmesh::cli2d::PolyRead r = uvmesh::cli2d::parse_poly(in, "fuzz.poly");
  if (!r.ok()) return 0;
  m2d::Pslg p = r.poly.pslg;
  if (p.points.size() > 64 || p.segments.size() > 128) return 0;
  for (m2d::Vec2& v : p.points) v = {snap(v.x, 1.0), snap(v.y, 1.0)};
  // Coincident points are merged here, segments renumbered: with duplicates m2d::check
  // reports edges "not on any input segment" (finding 1,
  // tests/mesher2d/data/fuzz_mesher2d_duplicate_points.poly), and every other input
  // would hit that one again.
  {
    std::map<std::pair<double, double>, m2d::VertId> first;
    std::vector<m2d::VertId> to(p.points.size());
    std::vector<m2d::Vec2> kept;
    for (std::size_t i = 0; i < p.points.size(); ++i) {
      const auto [it, added] =
          first.try_emplace({p.points[i].x, p.points[i].y}, static_cast<m2d::VertId>(kept.size()));
      if (added) kept.push_back(p.points[i]);
      to[i] = it->second;
    }
    p.points = std::move(kept);
    p.point_markers.clear();
    for (m2d::Pslg::Segment& s : p.segments)
      s.a = to[static_cast<std::size_t>(s.a)], s.b = to[static_cast<std::size_t>(s.b)];
  }
  for (m2d::Vec2& h : p.holes) h = {snap(h.x, 0.5), snap(h.y, 0.5)};
  for (m2d::Pslg::Region& g : p.regions) g.seed = {snap(g.seed.x, 0.5), snap(g.seed.y, 0.5)};

  // The size and options from the input's length, so that the corpus explores them too.
  static constexpr double kSizes[] = {0.0, 0.37, 1.0, 3.0};
  const double h = kSizes[size % 4];
  const m2d::SizeSpec size_spec = m2d::SizeSpec::uniform(h);
  m2d::Options opt;
  opt.max_vertices = 4000;  // a refinement that does not stop is found as a slow unit
  opt.split_crossing_segments = (size / 4) % 2 == 1;
  opt.optimize = (size / 8) % 2 == 0;
  // Both field-point methods (saturation, frontal), by the next bit of the length.
  opt.field_points =
      (size / 16) % 2 == 0 ? m2d::FieldPointMethod::Saturation : m2d::FieldPointMethod::Frontal;
  // The local feature size cap (uvmesh2d's default) by the next.
  opt.feature_size = (size / 32) % 2 == 1;
  const m2d::Result res = m2d::mesh(p, size_spec, opt);
  if (res.status.code == m2d::StatusCode::InternalError)
    finding("InternalError", res.status.message, p, h, opt);
  if (res.ok() && !opt.split_crossing_segments && !point_inside_a_segment(p)) {
    // Crossing segments split by the mesher are no longer the input's segments.
    // Seeds are not checked: snapped to half-integers they often sit on a segment or
    // outside the domain, where "which triangle holds it" has no right answer.
    m2d::CheckOptions co;
    co.seeds = false;
    const m2d::CheckReport rep = m2d::check(res.mesh, p, co);
    if (!rep.ok()) finding("mesh called Ok fails the checker", rep.errors.front(), p, h, opt);
  }
  return 0;
}
