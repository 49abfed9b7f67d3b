// Model statistics on a hand-built model: a closed cylinder side (one face with a seam)
// plus a loose planar face, so that seams, free edges, non-manifold edges and short
// edges are all exercised without OCC.
#include <catch2/catch.hpp>

#include <numbers>

#include "uvmesh/geom/analytic.h"
#include "uvmesh/geom/model.h"

using namespace uvmesh;
using geom::Vec2;
using geom::Vec3;

namespace {
const double kPi = std::numbers::pi;

geom::Model cylinder_model() {
  geom::Model m;
  m.vertices = {{{1, 0, 0}, 1e-7}, {{1, 0, 2}, 1e-7}};
  const geom::Frame bottom;
  geom::Frame topf;
  topf.origin = {0, 0, 2};
  geom::Edge e0{geom::make_circle(bottom, 1.0), {0, 2 * kPi}, 0, 0, false, 1e-7, 2 * kPi};
  geom::Edge e1{geom::make_circle(topf, 1.0), {0, 2 * kPi}, 1, 1, false, 1e-7, 2 * kPi};
  geom::Edge seam{geom::make_line({1, 0, 0}, {0, 0, 1}, {0, 2}), {0, 2}, 0, 1, false, 1e-7, 2.0};
  m.edges = {e0, e1, seam};
  geom::Face f;
  f.surface = geom::make_cylinder(bottom, 1.0, {0, 2});
  f.kind = geom::SurfaceKind::Cylinder;
  f.uv_box = {{0, 2 * kPi}, {0, 2}};
  geom::Loop l;
  l.outer = true;
  l.uses = {
      {0, false, geom::make_line2({0, 0}, {1, 0}, {0, 2 * kPi}), {0, 2 * kPi}, false},
      {2, false, geom::make_line2({2 * kPi, 0}, {0, 1}, {0, 2}), {0, 2}, true},
      {1, true, geom::make_line2({0, 2}, {1, 0}, {0, 2 * kPi}), {0, 2 * kPi}, false},
      {2, true, geom::make_line2({0, 0}, {0, 1}, {0, 2}), {0, 2}, true},
  };
  f.loops = {l};
  m.faces = {f};
  m.shells = {{{0}, false}};
  m.bbox.add(Vec3(-1, -1, 0));
  m.bbox.add(Vec3(1, 1, 2));
  return m;
}
}  // namespace

TEST_CASE("stats: seam, free edges and kinds of a cylinder side", "[geom][model]") {
  const geom::Model m = cylinder_model();
  const geom::ModelStats s = geom::compute_stats(m);
  CHECK(s.faces == 1);
  CHECK(s.edges == 3);
  CHECK(s.seam_edges == 1);
  CHECK(s.faces_with_seams == 1);
  CHECK(s.free_edges == 2);  // the two circles; the seam is not free
  CHECK(s.non_manifold_edges == 0);
  CHECK(s.surface_kinds.at("cylinder") == 1);
  CHECK(s.curve_kinds.at("circle") == 2);
  CHECK(s.curve_kinds.at("line") == 1);
  CHECK(s.open_shells == 1);
  CHECK(s.vertex_gaps == 0);
  CHECK(s.short_edges == 0);
  // Every pcurve lies on the edge's 3D curve through sigma (same parameter).
  for (const geom::Loop& l : m.faces[0].loops)
    for (const geom::EdgeUse& u : l.uses)
      for (double t : {u.range.lo, u.range.mid(), u.range.hi}) {
        const Vec2 uv = u.pcurve->point(t);
        CHECK(glm::length(m.faces[0].surface->point(uv.x, uv.y) - m.edges[u.edge].curve->point(t)) < 1e-12);
      }
}

TEST_CASE("stats: non-manifold, degenerate, short edges and vertex gaps", "[geom][model]") {
  geom::Model m = cylinder_model();
  // Three more faces sharing edge 2 (the seam line) make it non-manifold.
  for (int k = 0; k < 2; ++k) {
    geom::Face f;
    f.kind = geom::SurfaceKind::Plane;
    geom::Loop l;
    l.uses = {{2, false, nullptr, {0, 2}, false}};
    f.loops = {l};
    m.faces.push_back(f);
  }
  // A degenerate edge and a very short edge.
  m.edges.push_back({nullptr, {0, 1}, 0, 0, true, 1e-7, 0.0});
  m.edges.push_back(
      {geom::make_line({1, 0, 0}, {0, 0, 1}, {0, 1e-4}), {0, 1e-4}, geom::kNone, geom::kNone, false, 1e-7, 1e-4});
  // Corrupt vertex 1: far from the ends of the edges it bounds.
  m.vertices[1].p = {1e6, 0, 2};
  const geom::ModelStats s = geom::compute_stats(m);
  CHECK(s.non_manifold_edges == 1);
  CHECK(s.degenerate_edges == 1);
  CHECK(s.short_edges == 1);  // 1e-4 < 1e-3 * diagonal (3)
  CHECK(s.vertex_gaps >= 2);  // both ends of the top circle
  CHECK(s.max_vertex_gap > 9e5);
}
