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
        CHECK(glm::length(m.faces[0].surface->point(uv.x, uv.y) - m.edges[u.edge].curve->point(t)) <
              1e-12);
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
  m.edges.push_back({geom::make_line({1, 0, 0}, {0, 0, 1}, {0, 1e-4}),
                     {0, 1e-4},
                     geom::kNone,
                     geom::kNone,
                     false,
                     1e-7,
                     1e-4});
  // Corrupt vertex 1: far from the ends of the edges it bounds.
  m.vertices[1].p = {1e6, 0, 2};
  const geom::ModelStats s = geom::compute_stats(m);
  CHECK(s.non_manifold_edges == 1);
  CHECK(s.degenerate_edges == 1);
  CHECK(s.short_edges == 1);  // 1e-4 < 1e-3 * diagonal (3)
  CHECK(s.vertex_gaps >= 2);  // both ends of the top circle
  CHECK(s.max_vertex_gap > 9e5);
}

namespace {
// A planar strip 4 x 0.1 (u along x, v along y) whose two short sides are each closed
// by one vertex of tolerance 0.1, as occt_caxif_k1's STEP file gives them: vertex 0 at
// P = (0,0,0) also ends the short edge 3 at P' = (0,0.1,0), vertex 1 at Q' = (4,0.1,0)
// also ends the short edge 1 at Q = (4,0,0).
geom::Model strip_closed_by_tolerance() {
  geom::Model m;
  m.vertices = {{{0, 0, 0}, 0.1}, {{4, 0.1, 0}, 0.1}};
  auto line = [](Vec3 a, Vec3 b) {
    const double len = glm::length(b - a);
    return geom::make_line(a, (b - a) / len, {0, len});
  };
  const Vec3 P(0, 0, 0), Pp(0, 0.1, 0), Q(4, 0, 0), Qp(4, 0.1, 0);
  m.edges = {{line(P, Q), {0, 4}, 0, 1, false, 1e-7, 4.0},
             {line(Q, Qp), {0, 0.1}, 1, 1, false, 1e-7, 0.1},
             {line(Qp, Pp), {0, 4}, 1, 0, false, 1e-7, 4.0},
             {line(Pp, P), {0, 0.1}, 0, 0, false, 1e-7, 0.1}};
  geom::Face f;
  f.surface = geom::make_plane(geom::Frame{}, {{0, 4}, {0, 0.1}});
  f.kind = geom::SurfaceKind::Plane;
  f.uv_box = {{0, 4}, {0, 0.1}};
  geom::Loop l;
  l.outer = true;
  l.uses = {{0, false, geom::make_line2({0, 0}, {1, 0}, {0, 4}), {0, 4}, false},
            {1, false, geom::make_line2({4, 0}, {0, 1}, {0, 0.1}), {0, 0.1}, false},
            {2, false, geom::make_line2({4, 0.1}, {-1, 0}, {0, 4}), {0, 4}, false},
            {3, false, geom::make_line2({0, 0.1}, {0, -1}, {0, 0.1}), {0, 0.1}, false}};
  f.loops = {l};
  m.faces = {f};
  m.shells = {{{0}, false}};
  m.bbox.add(Vec3(0, 0, 0));
  m.bbox.add(Vec3(4, 0.1, 0));
  return m;
}
}  // namespace

TEST_CASE(
    "split vertices: an edge closed by its vertex's tolerance alone gets two vertices "
    "(occt_caxif_k1)",
    "[geom][model]") {
  geom::Model m = strip_closed_by_tolerance();
  CHECK(geom::split_vertices_closing_open_edges(m) == 2);
  REQUIRE(m.vertices.size() == 4);
  REQUIRE(m.vertex_splits.size() == 2);
  CHECK(m.vertex_splits[0].vertex == 2);
  CHECK(m.vertex_splits[0].from == 0);
  CHECK(m.vertex_splits[1].vertex == 3);
  CHECK(m.vertex_splits[1].from == 1);
  CHECK(m.vertex_splits[0].reason.find("edge 3") != std::string::npos);
  // Every edge open, every vertex at the curve ends it bounds, the loop chained.
  for (const geom::Edge& e : m.edges) {
    CHECK(e.v0 != e.v1);
    CHECK(glm::length(m.vertices[static_cast<std::size_t>(e.v0)].p - e.curve->point(e.range.lo)) <
          1e-12);
    CHECK(glm::length(m.vertices[static_cast<std::size_t>(e.v1)].p - e.curve->point(e.range.hi)) <
          1e-12);
  }
  for (std::size_t k = 0; k < 4; ++k) CHECK(m.edges[k].v1 == m.edges[(k + 1) % 4].v0);
  // The tolerances shrink to what the vertices now need (the edges' own).
  for (const geom::Vertex& v : m.vertices) CHECK(v.tol == Approx(1e-7));
  CHECK(geom::compute_stats(m).vertex_gaps == 0);
  // Idempotent.
  CHECK(geom::split_vertices_closing_open_edges(m) == 0);
}

TEST_CASE("split vertices: closed curves, and loops that would open, are left alone",
          "[geom][model]") {
  // Circles closed within their tolerance.
  geom::Model c = cylinder_model();
  CHECK(geom::split_vertices_closing_open_edges(c) == 0);
  CHECK(c.vertices.size() == 2);
  // A loop made of the open edge alone: splitting would open the loop.
  geom::Model m = strip_closed_by_tolerance();
  m.faces[0].loops[0].uses = {m.faces[0].loops[0].uses[3]};
  m.edges.resize(4);
  m.edges[0].v0 = m.edges[0].v1 = m.edges[2].v0 = m.edges[2].v1 = geom::kNone;
  m.edges[1].v0 = m.edges[1].v1 = geom::kNone;
  CHECK(geom::split_vertices_closing_open_edges(m) == 0);
  CHECK(m.edges[3].v0 == 0);
  CHECK(m.edges[3].v1 == 0);
  CHECK(m.vertices[0].tol == 0.1);
}
