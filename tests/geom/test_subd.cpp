// OpenSubdiv back end: OBJ cage parsing and its errors, limit-surface patches against
// finite differences, shared patch boundaries (same t, same point on every side), model
// topology (closed cages closed, holes, boundary interpolation, non-manifold cages).
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "fd_check.h"
#include "subd_patch.h"  // private to geom: SubdPatch, the patch domains
#include "uvmesh/geom/subd.h"

using namespace uvmesh;
using geom::Vec2;
using geom::Vec3;

namespace {

std::string cage_path(const std::string& name) {
  return std::string(UVMESH_SHARED_DATA) + "/subd/" + name;
}

geom::SubdCageResult parse(const std::string& text, const std::string& name = "mem.obj") {
  std::istringstream in(text);
  return geom::parse_obj_cage(in, name);
}

geom::SubdModelResult build(const std::string& text, const geom::SubdOptions& o = {}) {
  auto c = parse(text);
  INFO(c.error);
  REQUIRE(c.ok);
  return geom::model_from_cage(c.cage, o);
}

const char* kCube =
    "v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 -1\nv 1 -1 -1\n"
    "f 1 2 4 3\nf 3 4 6 5\nf 5 6 8 7\nf 7 8 2 1\nf 2 8 6 4\nf 7 1 3 5\n";

const std::vector<std::string> kCages = {
    "catmark_car.obj",           "catmark_chaikin0.obj",   "catmark_cube.obj",
    "catmark_cube_creases1.obj", "catmark_helmet.obj",     "catmark_nonman_edges.obj",
    "catmark_pawn.obj",          "catmark_pole64.obj",     "catmark_tent_creases1.obj",
    "catmark_torus.obj",         "loop_cube_creases1.obj", "loop_icosahedron.obj"};

bool closed_cage(const std::string& n) {
  return n == "catmark_chaikin0.obj" || n == "catmark_cube.obj" ||
         n == "catmark_cube_creases1.obj" || n == "catmark_torus.obj" ||
         n == "loop_cube_creases1.obj" || n == "loop_icosahedron.obj";
}

}  // namespace

TEST_CASE("subd OBJ: vertices, faces, negative indices, tags", "[geom][subd]") {
  const auto r = parse(
      "# comment\nv 0 0 0\nv 1 0 0\nvt 0 0\nv 1 1 0\nvn 0 0 1\nv 0 1 0\n"
      "f 1/1 2//1 3/1/1 4\nf -4 -3 -2\n"
      "t crease 3/1/0 0 1 2 2.5\nt corner 1/1/0 3 4.0\nt hole 1/0/0 1\n"
      "t interpolateboundary 1/0/0 2\nt creasemethod 0/0/1 chaikin\nt facevaryingpropagatecorners "
      "1/0/0 1\n");
  INFO(r.error);
  REQUIRE(r.ok);
  const auto& c = r.cage;
  CHECK(c.points.size() == 4);
  CHECK(c.face_sizes == std::vector<int>{4, 3});
  CHECK(c.face_verts == std::vector<int>{0, 1, 2, 3, 0, 1, 2});
  CHECK(c.face_lines == std::vector<int>{8, 9});
  REQUIRE(c.creases.size() == 2);  // a chain of three vertices: two edges
  CHECK((c.creases[1].a == 1 && c.creases[1].b == 2 && c.creases[1].sharpness == 2.5f));
  REQUIRE(c.corners.size() == 1);
  CHECK(c.corners[0].v == 3);
  REQUIRE(c.holes.size() == 1);
  CHECK(c.holes[0].face == 1);
  CHECK(c.interpolate_boundary == 2);
  CHECK(c.chaikin);
  CHECK(c.warnings.size() == 1);  // the unknown tag is reported, not fatal
}

TEST_CASE("subd OBJ: malformed input gives one message naming the file and line", "[geom][subd]") {
  const std::string v4 = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\n";
  const std::vector<std::pair<std::string, std::string>> bad = {
      {v4 + "f 1 2 9\n", "bad.obj:5: face references vertex 9"},
      {v4 + "f 1 2 0\n", "bad.obj:5: face index 0"},
      {v4 + "f 1 -7 2\n", "bad.obj:5: face index -7"},
      {v4 + "f 1 x 2\n", "bad.obj:5: malformed face index"},
      {v4 + "f 1 2\n", "bad.obj:5: a face needs at least 3"},
      {"v 0 0 0\nv nan 0 0\n", "bad.obj:2: vertex coordinate is not finite"},
      {"v 0 0 0\nv 1 inf 0\n", "bad.obj:2: vertex coordinate is not finite"},
      {"v 0 0\n", "bad.obj:1: expected 'v x y z'"},
      {"v 0 0 zz\n", "bad.obj:1: malformed vertex coordinate"},
      {v4 + "f 1 2 3\nt crease 2/1 0 1 3\n", "bad.obj:6: malformed tag counts"},
      {v4 + "f 1 2 3\nt crease 2/1/0 0 1\n", "bad.obj:6: tag 'crease' announces 3"},
      {v4 + "f 1 2 3\nt crease 2/1/0 0 -1 3\n", "bad.obj:6: negative index"},
      {v4 + "f 1 2 3\nt interpolateboundary 1/0/0 7\n", "bad.obj:6: interpolateboundary"},
      {v4, "bad.obj:4: no faces"},
  };
  for (const auto& [text, want] : bad) {
    INFO(text);
    const auto r = parse(text, "bad.obj");
    CHECK(!r.ok);
    CHECK(r.error.rfind(want, 0) == 0);
    CHECK(r.error.find('\n') == std::string::npos);
  }
  // The same through a file on disk (read_subd names the path).
  const auto path = std::filesystem::temp_directory_path() / "uvmesh_test_subd_bad.obj";
  { std::ofstream(path) << v4 << "f 1 2 3 5\n"; }
  const auto r = geom::read_subd(path.string(), {});
  std::filesystem::remove(path);
  CHECK(!r.ok);
  CHECK(r.error.rfind(path.string() + ":5: face references vertex 5", 0) == 0);
  CHECK(!geom::read_subd("/nonexistent/cage.obj", {}).ok);
}

TEST_CASE("subd model: tags naming missing vertices, edges or faces are errors", "[geom][subd]") {
  const std::string cube(kCube);
  auto err = [&](const std::string& tail) {
    auto c = parse(cube + tail, "t.obj");
    REQUIRE(c.ok);
    const auto r = geom::model_from_cage(c.cage, {});
    CHECK(!r.ok);
    return r.error;
  };
  CHECK(err("t crease 2/1/0 0 8 1.0\n").rfind("t.obj:15: crease names vertex 8", 0) == 0);
  CHECK(err("t crease 2/1/0 0 5 1.0\n")
            .rfind("t.obj:15: crease names vertices 0 and 5 which share no edge", 0) == 0);
  CHECK(err("t corner 1/1/0 12 1.0\n").rfind("t.obj:15: corner names vertex 12", 0) == 0);
  CHECK(err("t hole 1/0/0 6\n").rfind("t.obj:15: hole names face 6", 0) == 0);
  // Loop needs triangles.
  geom::SubdOptions o;
  o.scheme = geom::SubdScheme::Loop;
  auto c = parse(cube, "t.obj");
  const auto r = geom::model_from_cage(c.cage, o);
  CHECK(!r.ok);
  CHECK(r.error.rfind("t.obj:9: the Loop scheme needs triangles", 0) == 0);
}

TEST_CASE("subd model: schemes, holes, boundary interpolation", "[geom][subd]") {
  {
    const auto r = build(kCube);
    REQUIRE(r.ok);
    CHECK(r.scheme == geom::SubdScheme::CatmullClark);
    CHECK(r.model.faces.size() == 6);
    CHECK(r.model.edges.size() == 12);
    CHECK(r.model.vertices.size() == 8);
    REQUIRE(r.model.shells.size() == 1);
    CHECK(r.model.shells[0].closed);
    CHECK(r.model.solids.size() == 1);
    const auto st = geom::compute_stats(r.model);
    CHECK(st.free_edges == 0);
    CHECK(st.vertex_gaps == 0);
    for (const auto& f : r.model.faces) CHECK(!f.reversed);
  }
  {
    // The same cube turned inside out: the patches are flagged reversed.
    std::string inv;
    std::istringstream in(kCube);
    for (std::string l; std::getline(in, l);) {
      if (l[0] == 'f') {
        std::istringstream ls(l.substr(2));
        std::vector<std::string> t;
        for (std::string x; ls >> x;) t.push_back(x);
        l = "f";
        for (auto it = t.rbegin(); it != t.rend(); ++it) l += " " + *it;
      }
      inv += l + "\n";
    }
    const auto r = build(inv);
    REQUIRE(r.ok);
    for (const auto& f : r.model.faces) CHECK(f.reversed);
  }
  {
    const auto r = build(std::string(kCube) + "t hole 1/0/0 2\n");
    REQUIRE(r.ok);
    CHECK(r.dropped_faces == std::vector<geom::Id>{2});
    CHECK(r.model.faces.size() == 5);
    CHECK(!r.model.shells[0].closed);
    CHECK(r.model.solids.empty());
    CHECK(geom::compute_stats(r.model).free_edges == 4);
  }
  {
    // A 3x3 grid of quads: with boundary interpolation "none" only the centre face has
    // a limit surface; with "edge-only" all nine have one.
    std::string g;
    for (int j = 0; j < 4; ++j)
      for (int i = 0; i < 4; ++i) g += "v " + std::to_string(i) + " " + std::to_string(j) + " 0\n";
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const int a = j * 4 + i + 1;
        g += "f " + std::to_string(a) + " " + std::to_string(a + 1) + " " + std::to_string(a + 5) +
             " " + std::to_string(a + 4) + "\n";
      }
    geom::SubdOptions o;
    o.boundary = geom::SubdBoundary::None;
    auto r = build(g, o);
    REQUIRE(r.ok);
    CHECK(r.model.faces.size() == 1);
    CHECK(r.dropped_faces.size() == 8);
    o.boundary = geom::SubdBoundary::EdgeOnly;
    r = build(g, o);
    REQUIRE(r.ok);
    CHECK(r.model.faces.size() == 9);
    CHECK(geom::compute_stats(r.model).free_edges == 12);
    // Planar cage, planar limit.
    for (const auto& f : r.model.faces) CHECK(std::abs(f.surface->point(0.3, 0.7).z) < 1e-14);
  }
}

TEST_CASE("subd model: every corpus cage, patches and shared boundaries", "[geom][subd]") {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(0.02, 0.98);
  for (const std::string& name : kCages) {
    INFO(name);
    const auto r = geom::read_subd(cage_path(name), {});
    INFO(r.error);
    REQUIRE(r.ok);
    const geom::Model& m = r.model;
    CHECK(r.scheme ==
          (name.rfind("loop", 0) == 0 ? geom::SubdScheme::Loop : geom::SubdScheme::CatmullClark));
    REQUIRE(!m.faces.empty());
    CHECK(r.patches->size() == m.faces.size());
    const double D = m.bbox.diagonal();
    REQUIRE(D > 0);
    const bool loop = r.scheme == geom::SubdScheme::Loop;

    // Derivatives against finite differences on a sample of patches.
    int checked = 0;
    double worst = 0, worst_first = 0;
    for (std::size_t f = 0; f < m.faces.size();
         f += std::max<std::size_t>(1, m.faces.size() / 60)) {
      const geom::Surface& s = *m.faces[f].surface;
      const geom::SubdPatch& P = (*r.patches)[f];
      for (int k = 0; k < 6; ++k) {
        double u = U(rng), v = U(rng);
        if (loop && u + v > 0.96) u *= 0.5, v *= 0.5;
        if (!P.polygon.empty()) {
          // An n-gon patch: a point well inside one of its quads (sigma's derivatives
          // jump across the spokes between them), in the patch's domain (projected at a
          // high-valence vertex).
          const Vec2 x = geom::subd_patch_domain_point(P, k % P.face_size, {u, v});
          u = x.x, v = x.y;
        }
        const double err = test::surface_fd_error(s, u, v, 1e-5, 1e-5, D);
        worst = std::max(worst, err);
        ++checked;
        // eval_first (the induced metric's evaluation, without second derivatives) is
        // eval's point, and its first derivatives to 1e-4 of their length (one-sided
        // differences near extraordinary vertices).
        const geom::SurfacePoint e2 = s.eval(u, v), e1 = s.eval_first(u, v);
        CHECK(glm::length(e1.p - e2.p) <= 1e-14 * D);
        worst_first = std::max({worst_first, glm::length(e1.du - e2.du) / glm::length(e2.du),
                                glm::length(e1.dv - e2.dv) / glm::length(e2.dv)});
      }
      // Corners (extraordinary vertices included) evaluate to finite values ((0,0) is
      // corner 0 of an n-gon patch too).
      const auto e = s.eval(0.0, 0.0);
      CHECK(std::isfinite(glm::dot(e.duu + e.duv + e.dvv, Vec3(1.0))));
      CHECK(glm::length(glm::cross(e.du, e.dv)) > 0.0);
    }
    CHECK(checked > 0);
    // Central differences with h = 1e-5: O(h^2) truncation plus rounding of ~1e-16/h^2
    // on the second derivatives; piecewise (irregular) patches add their seams.
    CHECK(worst < 1e-8);
    CHECK(worst_first <= 1e-4);

    // Shared edges: every use of an edge gives the edge's curve point at the same t.
    double gap = 0, vgap = 0;
    int multi = 0;
    for (const auto& f : m.faces)
      for (const auto& l : f.loops)
        for (const auto& u : l.uses) {
          const geom::Edge& ed = m.edges[u.edge];
          if (ed.degenerate) {
            // Collapsed to its vertex: the whole side of the patch maps there.
            CHECK(f.surface->singular_sides() != 0u);
            continue;
          }
          for (int k = 0; k <= 8; ++k) {
            const double t = ed.range.at(k / 8.0);
            const Vec2 uv = u.pcurve->point(t);
            gap = std::max(gap, glm::length(f.surface->point(uv.x, uv.y) - ed.curve->point(t)));
          }
          vgap = std::max(vgap, glm::length(ed.curve->point(ed.range.lo) - m.vertices[ed.v0].p));
          vgap = std::max(vgap, glm::length(ed.curve->point(ed.range.hi) - m.vertices[ed.v1].p));
        }
    for (const auto& faces : geom::edge_faces(m)) multi += faces.size() >= 2;
    CHECK(multi > 0);
    CHECK(gap <= 1e-12 * D);
    CHECK(vgap <= 1e-12 * D);
    // Loops are closed chains in (u,v), CCW (positive area).
    for (const auto& f : m.faces) {
      double area = 0;
      for (const auto& u : f.loops[0].uses) {
        const Vec2 a = u.pcurve->point(u.reversed ? u.range.hi : u.range.lo);
        const Vec2 b = u.pcurve->point(u.reversed ? u.range.lo : u.range.hi);
        area += a.x * b.y - a.y * b.x;
      }
      CHECK(area > 0.0);
    }

    const auto st = geom::compute_stats(m);
    if (closed_cage(name)) {
      CHECK(st.free_edges == 0);
      CHECK(m.solids.size() >= 1);
      for (const auto& sh : m.shells) CHECK(sh.closed);
    }
    if (name == "catmark_nonman_edges.obj") {
      CHECK(r.non_manifold_edges > 0);
      CHECK(st.non_manifold_edges > 0);
    } else {
      CHECK(st.non_manifold_edges == 0);
    }
  }
}

TEST_CASE("subd model: a Catmull-Clark n-gon is one patch on its flattened limit polygon",
          "[geom][subd]") {
  // catmark_pole64: 64 triangles around a valence-64 pole, 64 quads. Each triangle was 3
  // sub-face patches whose spokes, as mesh edges, cut 5-16 degree corners into the thin
  // triangles (a third of the triangles of the mesh had Q >= 1.5); it is one patch now.
  const auto r = geom::read_subd(cage_path("catmark_pole64.obj"), {});
  REQUIRE(r.ok);
  CHECK(r.model.faces.size() == 128);
  int ngons = 0;
  double gap = 0, back = 0;
  for (std::size_t f = 0; f < r.patches->size(); ++f) {
    const geom::SubdPatch& P = (*r.patches)[f];
    if (P.face_size != 3) continue;
    ++ngons;
    REQUIRE(P.polygon.size() == 6);
    CHECK(P.subface == -1);
    const geom::Surface& s = *r.model.faces[f].surface;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j <= 10; ++j) {
        // Spoke k seen from sub-face k (s = 1) and from sub-face k+1 (t = 1): one (u,v)
        // segment, and sigma continuous across it.
        const Vec2 a = geom::subd_patch_domain_point(P, k, {1.0, j / 10.0});
        const Vec2 b = geom::subd_patch_domain_point(P, (k + 1) % 3, {j / 10.0, 1.0});
        CHECK(glm::length(a - b) < 1e-12);
        const Vec2 nrm = glm::normalize(Vec2(P.centre.y - a.y, a.x - P.centre.x)) * 1e-9;
        if (j < 10)
          gap = std::max(gap, glm::length(s.point(a.x + nrm.x, a.y + nrm.y) -
                                          s.point(a.x - nrm.x, a.y - nrm.y)));
        const Vec2 st = geom::ngon_subface_coords(
            P.polygon, P.centre, k,
            geom::ngon_domain_point(P.polygon, P.centre, k, {0.3, j / 10.0}));
        back = std::max(back, glm::length(st - Vec2(0.3, j / 10.0)));
      }
  }
  CHECK(ngons == 64);
  CHECK(gap < 1e-7 * r.model.bbox.diagonal());
  CHECK(back < 1e-12);
}

namespace {
// Length of sigma along the straight (u,v) segment a-b (200 chords) over the 3D chord
// |sigma(b) - sigma(a)|: 1 when the segment maps to a straight 3D segment.
double arc_over_chord(const geom::Surface& s, Vec2 a, Vec2 b) {
  constexpr int n = 200;
  double len = 0;
  geom::Vec3 prev = s.point(a.x, a.y);
  for (int i = 1; i <= n; ++i) {
    const Vec2 x = a + (b - a) * (double(i) / n);
    const geom::Vec3 q = s.point(x.x, x.y);
    len += glm::length(q - prev);
    prev = q;
  }
  return len / glm::length(s.point(b.x, b.y) - s.point(a.x, a.y));
}
}  // namespace

TEST_CASE(
    "subd model: catmark_pole64 patches at the valence-64 pole are projected and straight (u,v) "
    "segments across them nearly straight in 3D",
    "[geom][subd]") {
  // OpenSubdiv's sub-face parameterization at the pole bends the lines s + t = c toward
  // the pole: the straight segment between (0.4, 0) and (0, 0.4) of the pole's sub-face
  // maps to a curve ~9x longer than its chord, so the induced metric varied 6x across
  // one element and mesher2d split every edge across the strips (Q < 1.5 on 0.90 of the
  // triangles). In the projected domain (SubdPatch::unprojected) it is nearly straight.
  const auto r = geom::read_subd(cage_path("catmark_pole64.obj"), {});
  REQUIRE(r.ok);
  int projected = 0;
  double worst_new = 0, worst_old = 0, back = 0;
  for (std::size_t f = 0; f < r.patches->size(); ++f) {
    const geom::SubdPatch& P = (*r.patches)[f];
    if (P.face_size != 3) {
      CHECK(!P.unprojected);  // quads at valence-4 vertices keep OpenSubdiv's domain
      continue;
    }
    REQUIRE(P.unprojected);
    ++projected;
    const geom::Surface& s = *r.model.faces[f].surface;
    for (int k = 0; k < 3; ++k) {
      for (double c : {0.1, 0.4}) {
        worst_new =
            std::max(worst_new, arc_over_chord(s, geom::subd_patch_domain_point(P, k, {c, 0.0}),
                                               geom::subd_patch_domain_point(P, k, {0.0, c})));
        worst_old = std::max(
            worst_old, arc_over_chord(*P.unprojected,
                                      geom::ngon_domain_point(P.polygon, P.centre, k, {c, 0.0}),
                                      geom::ngon_domain_point(P.polygon, P.centre, k, {0.0, c})));
      }
      // The domain is the projection: sigma(w) projects back to w.
      const Vec2 w = geom::subd_patch_domain_point(P, k, {0.3, 0.6});
      back = std::max(back, glm::length(P.plane.map(s.point(w.x, w.y)) - w));
    }
  }
  INFO("arc/chord across the strips: projected " << worst_new << ", OpenSubdiv's domain "
                                                 << worst_old);
  CHECK(projected == 64);
  CHECK(worst_old > 3.0);
  CHECK(worst_new < 1.1);
  CHECK(back < 1e-12);
}
