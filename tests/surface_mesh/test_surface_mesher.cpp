// End-to-end tests of surface::mesh_model on a representative subset of the corpus
// (the whole corpus runs in scripts/corpus.sh): success, conformity by construction
// (closed solids watertight, consistently oriented, no self-intersection), shape, unit
// edges, chordal deviation against the exact surfaces, failure isolation, and identical
// output for any thread count.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdlib>
#include <map>
#include <set>
#include <string>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/report.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;

namespace {

std::string data(const std::string& rel) {
  return std::string(UVMESH_SHARED_DATA) + "/" + rel;
}

geom::Model load(const std::string& path, bool conform = false) {
  io::ReadOptions ro;
  ro.conform = conform;
  io::ReadResult rr = io::read_cad(path, ro);
  INFO(rr.error);
  REQUIRE(rr.ok);
  return std::move(rr.model);
}

// As `uvmesh mesh` reads it: an assembly made conforming (general fuse).
geom::Model load_conforming(const std::string& path) {
  return load(path, true);
}

surface::MeshOptions defaults(const geom::Model& m, int threads = 1) {
  surface::MeshOptions o;
  o.size = surface::default_size(m);
  o.threads = threads;
  return o;
}

// Every CAD entity kept (--keep-topology): the regression tests of mechanisms that only
// act without a feature size (proximity down to hmin / 100, strips below that floor
// collapsed onto one curve, faces triangulated from their boundary). With the default
// feature size these models' narrow faces are absorbed instead; what that still leaves
// is measured by scripts/corpus.sh and bench/surface/results.md.
surface::MeshOptions kept(surface::MeshOptions o) {
  o.keep_topology = true;
  return o;
}

// hmax D/40 and a curvature angle of 30 degrees: the README's second size set.
surface::MeshOptions d40_angle30(const geom::Model& m) {
  surface::MeshOptions o = defaults(m);
  o.size.hmax = m.bbox.diagonal() / 40;
  o.size.angle_tol = 30 * 3.14159265358979323846 / 180;
  return o;
}

// The acceptance on one model: every face meshed, watertight where the model is
// closed, no self-intersection, shape and size targets, chordal tolerance. Returns the
// shape measures.
surface::QualityReport accept(const std::string& file, bool closed,
                              const surface::MeshOptions* opt_in = nullptr) {
  INFO(file);
  const geom::Model m = load(file);
  const surface::MeshOptions o = opt_in ? *opt_in : defaults(m);
  const surface::MeshResult r = surface::mesh_model(m, o);
  for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
  CHECK(r.failed.empty());
  REQUIRE(!r.mesh.triangles.empty());

  const surface::TopologyReport t = surface::check_topology(r.mesh);
  CHECK(t.non_manifold_edges == 0);
  CHECK(t.inconsistent_edges == 0);
  CHECK(t.degenerate_triangles == 0);
  CHECK(t.unreferenced_points == 0);
  CHECK(t.close_points.pairs == 0);
  if (closed) CHECK(t.free_edges == 0);

  const surface::IntersectionReport si = surface::find_self_intersections(r.mesh, 5, 1);
  for (const auto& p : si.pairs)
    UNSCOPED_INFO("triangles " << p.t0 << " (face " << p.f0 << ") x " << p.t1 << " (face " << p.f1
                               << ")");
  CHECK(si.intersecting_pairs == 0);

  // Bad triangles across gaps of the CAD face narrower than the proximity floor, or than
  // the two edges' CAD tolerances, are the report's exceptions
  // (QualityReport::bad_in_narrow_gaps), as uvmesh mesh --report counts.
  const std::vector<double> edge_gap = surface::edge_gap_floors(m);
  const surface::QualityReport q = surface::measure_quality(
      r.mesh, 5, surface::proximity_floor(o.size, m.bbox.diagonal(), 0.0), &edge_gap);
  CHECK(q.share_Q_lt_1_5 >= 0.95);
  for (const auto& b : q.bad_list)
    UNSCOPED_INFO("Q " << b.Q << " triangle " << b.triangle << " face " << b.face);
  CHECK(q.bad_away_from_corners == 0);

  CHECK(r.unit_edge_share() >= 0.90);

  const surface::ChordalReport ch = surface::measure_chordal(r.mesh, m, 1);
  if (o.size.chordal_tol > 0) CHECK(ch.max <= o.size.chordal_tol);
  // A few projections from the interpolated (u,v) do not converge next to seams (the
  // starting point is on the other side of the period); they are counted, not hidden.
  CHECK(ch.not_converged <= ch.samples / 200);
  return q;
}

// The report's per-solid topology: every solid of an assembly closed and manifold on its
// own, although interface edges carry three faces in the whole mesh.
void check_solids_closed(const surface::SurfaceMesh& mesh, const geom::Model& m,
                         std::size_t solids) {
  io::CheckOptions co;
  co.self_intersections = false;
  co.threads = 1;
  const io::CheckData d = io::check_mesh(mesh, &m, co);
  REQUIRE(d.solids.size() == solids);
  for (const auto& s : d.solids) {
    CHECK(s.closed);
    CHECK(s.triangles > 0);
    CHECK(s.free_edges == 0);
    CHECK(s.non_manifold_edges == 0);
  }
}

}  // namespace

TEST_CASE("surface mesher: bundled bracket (planes, cylinders, fillets, holes)", "[surface]") {
  accept(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step", true);
}

TEST_CASE("surface mesher: tetrahedron", "[surface]") {
  accept(data("cad/axom_tet.step"), true);
}

TEST_CASE("surface mesher: two cubes sharing a face (non-manifold interface)", "[surface]") {
  // The shared face is used by both solids: its edges carry three faces, so the check
  // is per solid in spirit; here: meshed, conforming, no intersections.
  // The file holds the interface twice (one face per cube, on separate edges): read
  // with --conform (general fuse) it becomes one face bounding both solids.
  io::ReadOptions ro;
  ro.conform = true;
  io::ReadResult rr = io::read_cad(data("cad/dagmc_two_cubes.stp"), ro);
  REQUIRE(rr.ok);
  const geom::Model& m = rr.model;
  CHECK(m.faces.size() == 11);
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  CHECK(r.failed.empty());
  const surface::TopologyReport t = surface::check_topology(r.mesh);
  CHECK(t.free_edges == 0);
  CHECK(t.degenerate_triangles == 0);
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
  // The interface's edges carry three faces in the whole mesh, but each solid on its
  // own is closed and manifold (the report's per-solid topology).
  CHECK(t.non_manifold_edges > 0);
  check_solids_closed(r.mesh, m, 2);
}

TEST_CASE(
    "check: a stray sheet crossing a closed solid is counted in the whole mesh, not in the solid's "
    "(nist_ctc_02)",
    "[surface]") {
  // nist_ctc_02 holds one closed solid and, in a second, open shell, one face (663) that
  // crosses the solid's face 339. The whole mesh must intersect there; the solid's own
  // triangles, which a volume mesher fills, must not.
  const geom::Model m = load(data("cad/nist_ctc_02.stp"));
  REQUIRE(m.solids.size() == 1);
  surface::MeshOptions o = defaults(m);
  o.size.hmax = m.bbox.diagonal() / 10;
  const surface::MeshResult r = surface::mesh_model(m, o);
  CHECK(r.failed.empty());
  io::CheckOptions co;
  co.threads = 1;
  const io::CheckData d = io::check_mesh(r.mesh, &m, co);
  REQUIRE(d.intersections);
  REQUIRE(d.solids.size() == 1);
  const auto& s = d.solids[0];
  CHECK(s.closed);
  CHECK(s.free_edges == 0);
  CHECK(s.non_manifold_edges == 0);
  CHECK(std::find(s.faces.begin(), s.faces.end(), 663) == s.faces.end());
  CHECK(d.intersections->intersecting_pairs > 0);
  REQUIRE(d.intersections_in_model);
  CHECK(*d.intersections_in_model > 0);
  for (const auto& p : d.intersections->pairs) CHECK((p.f0 == 663 || p.f1 == 663));
  REQUIRE(s.self_intersections);
  CHECK(*s.self_intersections == 0);
  REQUIRE(d.intersections_in_closed_solids);
  CHECK(*d.intersections_in_closed_solids == 0);
}

TEST_CASE("surface mesher: seam with an inner loop touching it (gmsh_cyl_loop_seam)", "[surface]") {
  accept(data("cad/gmsh_cyl_loop_seam.brep"), false);
}

TEST_CASE("surface mesher: periodic faces (gmsh_periodic_u, gmsh_torus1, occt_spheres)",
          "[surface]") {
  accept(data("cad/gmsh_periodic_u.step"), true);
  accept(data("cad/gmsh_torus1.brep"), true);
  accept(data("cad/occt_spheres.stp"), true);
}

TEST_CASE("surface mesher: poles (gmsh_full_sphere, occt_cone_catia)", "[surface]") {
  accept(data("cad/gmsh_full_sphere.brep"), true);
  accept(data("cad/occt_cone_catia.igs"), true);
  // gmsh_cone1 is left out: its apex fan folds across the seam and the fold is removed,
  // leaving the apex vertex out of the mesh (watertight, but the tip is cut off). Known
  // open problem, see the issue 4 closing note.
}

TEST_CASE(
    "surface mesher: an embedded (INTERNAL) crack edge is a constraint inside its face "
    "(gmsh_crack)",
    "[surface]") {
  // A cube with a half-disc crack face whose straight edge is INTERNAL to the cube's
  // side face: that face used to fail ("a boundary node lies on another edge's (u,v)
  // segment") because the edge was closed into a loop.
  const geom::Model m = load(data("cad/gmsh_crack.brep"));
  geom::Id crack_edge = geom::kNone;
  for (const geom::Face& f : m.faces)
    for (const geom::Loop& l : f.loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.internal) crack_edge = u.edge;
  REQUIRE(crack_edge != geom::kNone);
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
  CHECK(r.failed.empty());
  // Every segment of the crack edge is an edge of triangles on both sides in the face
  // embedding it, plus the crack face's own: three triangles each; nothing else is
  // non-manifold, and the only free edges are the crack face's other (free) edge.
  std::map<std::pair<surface::NodeId, surface::NodeId>, int> count;
  for (const auto& t : r.mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      const auto a = t[i], b = t[(i + 1) % 3];
      ++count[{std::min(a, b), std::max(a, b)}];
    }
  std::size_t crack_segments = 0;
  for (const auto& sg : r.mesh.segments)
    if (sg.edge == crack_edge) {
      ++crack_segments;
      CHECK(count[{std::min(sg.a, sg.b), std::max(sg.a, sg.b)}] == 3);
    }
  CHECK(crack_segments >= 2);
  const surface::TopologyReport t = surface::check_topology(r.mesh);
  CHECK(t.non_manifold_edges == crack_segments);
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
}

TEST_CASE("surface mesher: sliver faces and small features next to long edges (nist_ctc_01)",
          "[surface]") {
  // Before edges were capped by the sizes of the other edges of their faces (gradation
  // across a face, proximity), a 65-unit edge at hmax faced a face interior refined to
  // 3.4 by small features, and thin faces were spanned by single slivers: Q up to 1614.
  accept(data("cad/nist_ctc_01.stp"), true);
}

TEST_CASE("surface mesher: a thin cylindrical band, anisotropic in (u,v) as a whole (nist_ftc_11)",
          "[surface]") {
  // Face 2 is a band 1.5 tall around a radius of ~9 (u an angle, v a length): mesher2d's
  // first triangulation of its boundary was fans of edges along the boundary that no
  // field point survived (metric Q 590, 26 triangles with Q >= 3). Fixed by scaling v by
  // the face's mean anisotropy before mesher2d.
  accept(data("cad/nist_ftc_11.stp"), true);
}

TEST_CASE("surface mesher: chordal repair of triangles the size grid missed (gmsh_problem_sphere)",
          "[surface]") {
  // The curvature sizes left a deviation of 1.10 tolerance; triangles whose centroid is
  // beyond 0.9 tolerance are now split at the foot of the centroid.
  accept(data("cad/gmsh_problem_sphere.brep"), true);
}

TEST_CASE(
    "surface mesher: a sub-hmin edge next to a coarse one grades through their vertex (gmsh_block)",
    "[surface]") {
  // An edge refined below hmin by proximity met a coarse edge with a 50x jump in segment
  // length: 25 triangles with Q >= 3 (caps) in the faces around it.
  const std::string file = data("cad/gmsh_block.stp");
  const surface::MeshOptions o = kept(defaults(load(file)));
  accept(file, true, &o);
}

TEST_CASE("surface mesher: no proximity refinement inside the CAD tolerances (gmsh_crankshaft)",
          "[surface]") {
  // Edges whose pcurves end 0.009 mm from their 3D vertex (hmin 0.013 mm) were refined by
  // proximity to 0.0002 mm segments there; the surface's image of those nodes and the
  // curve's own nodes made needles of Q up to 58 (23 triangles of Q >= 3 away from
  // vertices). Gaps below the sum of the edges' tolerances no longer refine; the slivers
  // across them are the report's narrow-gap exceptions.
  const std::string file = data("cad/gmsh_crankshaft.stp");
  const surface::MeshOptions o = kept(defaults(load(file)));
  accept(file, true, &o);
}

TEST_CASE(
    "surface mesher: a face narrower than hmin but wider than its tolerances is resolved "
    "(gmsh_slender_surface)",
    "[surface]") {
  // Width 0.00038 against hmin 0.0099: with the tolerance floor at twice the sum of the
  // edges' tolerances, proximity saw no gap and the face got 121 slivers (Q<1.5: 1.7%).
  accept(data("cad/gmsh_slender_surface.brep"), false);
}

TEST_CASE("surface mesher: a (u,v) metric varying inside one grid cell (occt_terrain)",
          "[surface]") {
  // One B-spline face whose (u,v) speed varies within a cell of the 64 x 64 metric grid:
  // interpolated, the metric gave 82% unit edges and 1.8x the chordal tolerance. The grid
  // now splits cells where it disagrees with the exact metric, and the chordal repair may
  // take up to 8 rounds.
  accept(data("cad/occt_terrain.brep"), false);
}

TEST_CASE("surface mesher: caps wedged between sub-hmin features are collapsed (occt_crankarm)",
          "[surface]") {
  // Two caps of Q 3.2 next to a corner, on a boundary split below hmin by proximity: no
  // position of their free vertex helped, merging it into a neighbour does (improve3d's
  // collapse). The model also has 96 slivers across the last micrometres of tangential
  // contacts, narrower than the proximity floor: counted apart, as exceptions.
  accept(data("cad/occt_crankarm.brep"), true);
}

TEST_CASE(
    "surface mesher: a needle between interior points next to a corner is collapsed "
    "(occt_mesh_artifact)",
    "[surface]") {
  // Face 5 kept one triangle of Q 3.2 with three interior points at 0.13 hmin from a model
  // vertex. (The model's acceptance as a whole: the test on its collapsed strips below.)
  const geom::Model m = load(data("cad/occt_mesh_artifact.brep"));
  const surface::MeshOptions o = defaults(m);
  const surface::MeshResult r = surface::mesh_model(m, o);
  REQUIRE(r.failed.empty());
  const std::vector<double> edge_gap = surface::edge_gap_floors(m);
  const surface::QualityReport q = surface::measure_quality(
      r.mesh, 5, surface::proximity_floor(o.size, m.bbox.diagonal(), 0.0), &edge_gap);
  for (const auto& b : q.bad_list)
    UNSCOPED_INFO("Q " << b.Q << " triangle " << b.triangle << " face " << b.face);
  CHECK(q.bad_away_from_corners == 0);
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
}

TEST_CASE(
    "surface mesher: strips narrower than the proximity floor are collapsed onto one curve "
    "(occt_mesh_artifact)",
    "[surface]") {
  // Faces 2 and 6 are planar steps bounded by two edges between the same two vertices,
  // 7.9e-6 and at most 9.7e-6 wide (0.029 and 0.00039 long), against a proximity floor
  // of 5.1e-5 (hmin / 100, D = 5.13): meshed, they were 20 slivers of Q up to 580, and
  // the acceptance failed on Q < 1.5 (0.946 at --hmax D/40 --angle 30, 0.949 by
  // default). Now each strip's two edges share one set of nodes and the strip is not
  // meshed: the faces beside it meet along one curve, the solid stays closed. The
  // unit-edge share (0.883 at D/40) also counted chords between two boundary nodes twice.
  const std::string file = data("cad/occt_mesh_artifact.brep");
  const geom::Model m = load(file);
  surface::MeshOptions fine = kept(defaults(m));
  fine.size.hmax = m.bbox.diagonal() / 40;
  fine.size.chordal_tol = 0;
  fine.size.angle_tol = 30.0 * 3.141592653589793 / 180.0;
  for (const surface::MeshOptions& o : {kept(defaults(m)), fine}) {
    INFO("hmax " << o.size.hmax);
    accept(file, true, &o);
    const surface::MeshResult r = surface::mesh_model(m, o);
    std::set<geom::Id> collapsed;
    for (const auto& c : r.collapsed) {
      CHECK(c.reason.find("narrower than the proximity floor") != std::string::npos);
      collapsed.insert(c.face);
    }
    CHECK(collapsed == std::set<geom::Id>{2, 6});
    for (geom::Id f : {2, 6})
      CHECK(std::count(r.mesh.triangle_face.begin(), r.mesh.triangle_face.end(), f) == 0);
    check_solids_closed(r.mesh, m, 1);
  }
  // With hmin = D / 1e5 the proximity floor (5.1e-7) is below both widths, but the strips
  // still lie inside their edges' tolerance floor (vertex 2's tolerance 1.27e-5, twice),
  // where proximity sees no gap: they are collapsed all the same.
  surface::MeshOptions small = kept(defaults(m));
  small.size.hmin = m.bbox.diagonal() / 1e5;
  const surface::MeshResult r = surface::mesh_model(m, small);
  CHECK(r.failed.empty());
  std::set<geom::Id> collapsed;
  for (const auto& c : r.collapsed) {
    CHECK(c.reason.find("(the edges' tolerances)") != std::string::npos);
    collapsed.insert(c.face);
  }
  CHECK(collapsed == std::set<geom::Id>{2, 6});
  check_solids_closed(r.mesh, m, 1);
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
}

TEST_CASE("surface mesher: --hmax D/40 --angle 30 on the bracket", "[surface]") {
  const geom::Model m = load(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step");
  surface::MeshOptions o = defaults(m);
  o.size.hmax = m.bbox.diagonal() / 40;
  o.size.chordal_tol = 0;
  o.size.angle_tol = 30.0 * 3.141592653589793 / 180.0;
  accept(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step", true, &o);
}

TEST_CASE(
    "surface mesher: frontal field points (--frontal) pass the acceptance, typical triangle "
    "nearer equilateral",
    "[surface][frontal]") {
  // Edge saturation (§7.5.2) bounds the (u,v) mesh's Q_M near 1.19, and the surface's median q
  // stays at 0.94-0.98; the frontal points of §7.4.3 give unit equilateral elements in the
  // metric wherever the front is undisturbed. Both modes must pass the same acceptance.
  for (const std::string& file : {std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step",
                                  data("cad/nist_ftc_11.stp"), data("cad/gmsh_full_sphere.brep")}) {
    INFO(file);
    const geom::Model m = load(file);
    surface::MeshOptions o = defaults(m);
    o.size.hmax = m.bbox.diagonal() / 40;
    o.size.chordal_tol = 0;
    o.size.angle_tol = 30.0 * 3.141592653589793 / 180.0;
    const surface::QualityReport sat = accept(file, true, &o);
    o.frontal = true;
    const surface::QualityReport fr = accept(file, true, &o);
    CHECK(fr.q_p50 > sat.q_p50 + 0.01);
    CHECK(fr.q_p1 > sat.q_p1 - 0.02);
    CHECK(fr.Q_max < 3.0);
  }
}

TEST_CASE(
    "surface mesher: a cone cut in halves keeps its halves apart at the apex with --angle 30 alone "
    "(occt_cone_catia)",
    "[surface]") {
  // With no chordal tolerance the sizes at the apex are hmin's, and both halves of the
  // cone had the same chord through the axis -- once even the same triangle (apex, n1,
  // n2) -- each the other turned over: a non-manifold edge and coincident triangles. The
  // flatness split (face.cpp) keeps at least two edges per half turn.
  const std::string file = data("cad/occt_cone_catia.igs");
  const geom::Model m = load(file);
  for (const double hmax_rel : {1.0 / 40, 1.0 / 20}) {
    INFO("hmax = D * " << hmax_rel);
    surface::MeshOptions o = defaults(m);
    o.size.hmax = hmax_rel * m.bbox.diagonal();
    o.size.chordal_tol = 0;
    o.size.angle_tol = 30.0 * 3.141592653589793 / 180.0;
    accept(file, true, &o);
  }
}

TEST_CASE("surface mesher: a face that cannot be meshed is reported, the rest is meshed",
          "[surface]") {
  geom::Model m = load(data("cad/axom_tet.step"));
  m.faces[2].surface.reset();  // no surface: this face cannot be meshed
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  REQUIRE(r.failed.size() == 1);
  CHECK(r.failed[0].face == 2);
  CHECK(r.failed[0].reason.find("no surface") != std::string::npos);
  std::set<geom::Id> faces(r.mesh.triangle_face.begin(), r.mesh.triangle_face.end());
  CHECK(faces == std::set<geom::Id>{0, 1, 3});
  // The hole left by the failed face is visible, not hidden: its boundary is free.
  CHECK(surface::check_topology(r.mesh).free_edges > 0);
}

TEST_CASE(
    "surface mesher: a doubly closed face whose wire is not chained in (u,v) (dagmc_ball_reactor)",
    "[surface]") {
  // Face 0 is the revolution of a closed profile: one vertex, two seam edges. The wire
  // explorer returned its four uses as bottom, top, left, right; the (u,v) boundary built
  // in that order jumped across the domain and crossed itself, and the face failed.
  // Chained by (u,v) end points (occ_model.cpp, chain_loop_in_uv) it is a rectangle.
  const geom::Model m = load(data("cad/dagmc_ball_reactor.brep"));
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
  CHECK(r.failed.empty());
  CHECK(std::count(r.mesh.triangle_face.begin(), r.mesh.triangle_face.end(), geom::Id{0}) > 100);
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
  check_solids_closed(r.mesh, m, 8);
}

TEST_CASE(
    "surface mesher: faces inside the tolerance tube of their own boundary are degenerate, not "
    "meshed (occt_caxif_k1)",
    "[surface]") {
  // occt_caxif_k1 has eight faces bounded by one B-spline edge of 2.56 mm (tolerance
  // 0.046 mm) whose ends are 1.64 mm apart: an open wire around 0.0109 mm^2, a mean width
  // of 0.0085 mm. Two more are bounded by two edges going there and back (area 1.5e-21).
  // They failed ("the (u,v) curves of edge 80 and 80 cross", "no region lies to the left")
  // or, meshed from their boundary, gave needles of Q 27 and the model's worst chordal
  // deviation (1.3x the tolerance). They are now reported as degenerate, and the rest
  // passes the acceptance's face, closure and chordal checks.
  const geom::Model m = load(data("cad/occt_caxif_k1.stp"));
  const std::set<geom::Id> expected{13, 16, 29, 30, 35, 36, 41, 42, 47, 48};
  std::set<geom::Id> flagged;
  for (std::size_t f = 0; f < m.faces.size(); ++f)
    if (m.faces[f].degenerate) flagged.insert(static_cast<geom::Id>(f));
  CHECK(flagged == expected);
  surface::MeshOptions fine = defaults(m);
  fine.size.hmax = m.bbox.diagonal() / 40;
  fine.size.chordal_tol = 0;
  fine.size.angle_tol = 30 * 3.14159265358979323846 / 180;
  for (const surface::MeshOptions& o : {defaults(m), fine}) {
    const surface::MeshResult r = surface::mesh_model(m, o);
    for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
    CHECK(r.failed.empty());
    std::set<geom::Id> degenerate;
    for (const auto& d : r.degenerate) {
      CHECK(d.reason.find("within its boundary's tolerance tube") != std::string::npos);
      degenerate.insert(d.face);
    }
    CHECK(degenerate == expected);
    for (geom::Id f : expected)
      CHECK(std::count(r.mesh.triangle_face.begin(), r.mesh.triangle_face.end(), f) == 0);
    check_solids_closed(r.mesh, m, 5);
    const std::vector<double> edge_gap = surface::edge_gap_floors(m);
    const surface::QualityReport q = surface::measure_quality(
        r.mesh, 5, surface::proximity_floor(o.size, m.bbox.diagonal(), 0.0), &edge_gap);
    CHECK(q.bad_away_from_corners == 0);
    if (o.size.chordal_tol > 0)
      CHECK(surface::measure_chordal(r.mesh, m, 1).max <= o.size.chordal_tol);
  }
}

TEST_CASE(
    "surface mesher: a vertex closing open edges by its tolerance alone is split, the solids do "
    "not fold "
    "(occt_caxif_k1)",
    "[surface]") {
  // occt_caxif_k1's edges 142, 144, 204 and 206 are 1 mm curves whose two ends the file
  // gives one vertex (EDGE_CURVE #768: VERTEX_POINT #574 at both ends); the STEP reader
  // sets that vertex's tolerance to the 1 mm gap. Meshed so, each edge was closed at its
  // vertex, the edges and faces that really end at its other end were pulled 1 mm to the
  // vertex, and faces 60, 68 and 70 (and their mirror images 80, 88, 90) folded there: 19
  // pairs of intersecting triangles in solids 2 and 4, whose meshes had Euler
  // characteristic 0 instead of 2. The import now splits each of the four vertices, and
  // both solids are closed, of genus 0, without self-intersection, at the default sizes
  // and at hmax D/40, angle 30 degrees.
  const std::string file = data("cad/occt_caxif_k1.stp");
  const geom::Model m = load(file);
  REQUIRE(m.vertex_splits.size() == 4);
  std::set<geom::Id> from;
  for (const auto& s : m.vertex_splits) from.insert(s.from);
  CHECK(from == std::set<geom::Id>{86, 87, 126, 127});
  for (geom::Id e : {142, 144, 204, 206})
    CHECK(m.edges[static_cast<std::size_t>(e)].v0 != m.edges[static_cast<std::size_t>(e)].v1);
  const surface::MeshOptions fine = d40_angle30(m);
  for (const surface::MeshOptions& o : {defaults(m), fine}) {
    const surface::MeshResult r = surface::mesh_model(m, o);
    CHECK(r.failed.empty());
    for (const std::string& w : r.warnings)
      CHECK(w.find("the mesh closes it at the vertex") == std::string::npos);
    io::CheckOptions co;
    co.threads = 1;
    const io::CheckData d = io::check_mesh(r.mesh, &m, co);
    REQUIRE(d.solids.size() == 5);
    for (const auto& s : d.solids) {
      INFO("solid " << s.solid);
      CHECK(s.closed);
      CHECK(s.free_edges == 0);
      CHECK(s.non_manifold_edges == 0);
      CHECK(s.self_intersections.value_or(1) == 0);
    }
    // Genus 0: V - E + F = 2 over the triangles of each of the two solids.
    for (const auto& s : {d.solids[2], d.solids[4]}) {
      std::set<surface::NodeId> v;
      std::set<std::pair<surface::NodeId, surface::NodeId>> e;
      std::size_t f = 0;
      for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
        if (!std::binary_search(s.faces.begin(), s.faces.end(), r.mesh.triangle_face[t])) continue;
        ++f;
        const auto& T = r.mesh.triangles[t];
        for (int k = 0; k < 3; ++k) {
          v.insert(T[k]);
          e.insert(std::minmax(T[k], T[(k + 1) % 3]));
        }
      }
      CHECK(static_cast<long>(v.size()) - static_cast<long>(e.size()) + static_cast<long>(f) == 2);
    }
  }
  // Circles closed within their tolerance keep their vertex, without a warning.
  const geom::Model ring = load(data("cad/gmsh_torus1.brep"));
  CHECK(ring.vertex_splits.empty());
  for (const std::string& w : surface::mesh_model(ring, defaults(ring)).warnings)
    CHECK(w.find("the mesh closes it at the vertex") == std::string::npos);
}

TEST_CASE(
    "surface mesher: boundary segments shorter than the proximity floor do not grade the interior "
    "(occt_caxif_b1)",
    "[surface]") {
  // occt_caxif_b1 (D = 30561 mm, proximity floor 0.31 mm) has CAD edges of 0.00015 and
  // 0.0028 mm (145, 156) at corners of faces 37 and 42. The 1D sizes stop at the floor, so
  // the edges beside them start with 0.3 mm segments; the 2D mesher's boundary gradation
  // took the tiny segments' lengths as sizes and refined the interior around them down
  // to 0.001 mm, and fans of needles joined that to the 0.3 mm segments: interior
  // triangles of Q 3.8 and 3.5 (one with hmax D/40, angle 30), besides the corners'.
  const std::string file = data("cad/occt_caxif_b1.stp");
  const geom::Model m = load(file);
  const surface::MeshOptions fine = kept(d40_angle30(m));
  const std::vector<double> edge_gap = surface::edge_gap_floors(m);
  for (const surface::MeshOptions& o : {kept(defaults(m)), fine}) {
    const surface::MeshResult r = surface::mesh_model(m, o);
    CHECK(r.failed.empty());
    const surface::QualityReport q = surface::measure_quality(
        r.mesh, 5, surface::proximity_floor(o.size, m.bbox.diagonal(), 0.0), &edge_gap);
    for (const auto& b : q.bad_list)
      UNSCOPED_INFO("Q " << b.Q << " triangle " << b.triangle << " face " << b.face);
    CHECK(q.bad_away_from_corners == 0);
    CHECK(q.share_Q_lt_1_5 >= 0.98);
  }
}

TEST_CASE("surface mesher: slivers narrower than the feature size leave no needle (occt_caxif_b1)",
          "[surface][feature]") {
  // With the default feature size, two classes of sliver were left as needles (Q up to
  // 243 at D/20, 21 at D/40): a face whose two corners lie 0.01 apart with no model edge
  // between them (its boundary runs out and back), and strips meshed as a row of needles,
  // where each collapse across the strip leaves a needle about as bad as the one it
  // removes until the last one clears it. Both are absorbed now: no triangle of Q >= 3
  // that is not at a corner under 20 degrees.
  const std::string file = data("cad/occt_caxif_b1.stp");
  const geom::Model m = load(file);
  for (const surface::MeshOptions& o : {defaults(m), d40_angle30(m)}) {
    const surface::MeshResult r = surface::mesh_model(m, o);
    CHECK(r.failed.empty());
    const surface::QualityReport q = surface::measure_quality(r.mesh, 5);
    INFO("hmax " << o.size.hmax << ": Q max " << q.Q_max);
    CHECK(q.Q_over_10 == 0);
    CHECK(q.bad_away_from_corners == 0);
    CHECK(q.bad_at_corners == q.bad_at_acute_corners);
    check_solids_closed(r.mesh, m, 1);
  }
}

TEST_CASE(
    "surface mesher: strips narrower than L/2 between two sharp edges with staggered nodes leave "
    "no caps (occt_motor, nist_ctc_02)",
    "[surface][feature]") {
  // Strips 0.05-0.15 L wide whose two sharp edges have their nodes half a segment apart:
  // no node pair across is closer than L/2, so nothing collapsed, and the strip stayed a
  // row of caps and needles of Q 3.5-4.6 (45 and 48 triangles of Q >= 3 away from
  // corners). Caps whose apex is within L/2 of the edge are now split under the apex and
  // the apex collapsed there; each collapse along the row may leave a needle as bad as
  // the one it removes, up to the last.
  // The triangles these operations rewrite keep one period of (u,v) on a periodic face:
  // a vertex on a cylinder's seam took its (u,v) from either side, and the chordal check,
  // seeded there, measured 32 (the cylinder's diameter) on occt_motor's face 111.
  for (const char* name : {"cad/occt_motor.brep", "cad/nist_ctc_02.stp"}) {
    const geom::Model m = load_conforming(data(name));
    const surface::MeshOptions o = defaults(m);
    const surface::MeshResult r = surface::mesh_model(m, o);
    INFO(name);
    CHECK(r.failed.empty());
    const surface::QualityReport q = surface::measure_quality(r.mesh, 5);
    CHECK(q.Q_over_10 == 0);
    CHECK(q.bad_away_from_corners == 0);
    REQUIRE(o.size.chordal_tol > 0);
    CHECK(surface::measure_chordal(r.mesh, m, 1).max <= o.size.chordal_tol);
  }
}

TEST_CASE(
    "surface mesher: the simplify stage keeps every solid of an assembly closed on its own "
    "(caxif_as1_assembly)",
    "[surface][feature]") {
  // A triangle the simplify stage rewrites (a swap, a relocation) takes the face under its
  // centroid among its corners' faces; next to an interface it took a face of one solid
  // instead of the interface both share, and three solids lost a triangle (12, 2 and 2
  // free edges of their own). It now only takes faces that bound the same solids.
  const geom::Model m = load_conforming(data("cad/caxif_as1_assembly.stp"));
  REQUIRE(m.solids.size() >= 2);
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  CHECK(r.failed.empty());
  check_solids_closed(r.mesh, m, m.solids.size());
}

TEST_CASE(
    "surface mesher: the simplify stage makes no triangles of two solids in near contact cross "
    "(occt_motor)",
    "[surface][feature]") {
  // At hmax D/40 two collapses on faces 1 and 8 moved triangles through face 114 of the
  // next part (8 intersecting pairs, none at keep-topology), and TetGen refused the mesh.
  // Such operations are now refused and the stage run again without them.
  const geom::Model m = load_conforming(data("cad/occt_motor.brep"));
  const surface::MeshResult r = surface::mesh_model(m, d40_angle30(m));
  CHECK(r.failed.empty());
  CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
  CHECK(surface::measure_quality(r.mesh, 5).Q_over_10 == 0);
  check_solids_closed(r.mesh, m, m.solids.size());
}

TEST_CASE(
    "surface mesher: faces whose pcurves cross are triangulated from their boundary when that is "
    "valid",
    "[surface]") {
  // occt_caxif_b1: slivers between two copies of one curve whose pcurves cross. Face 63
  // gets a valid strip from its boundary nodes. Faces 58, 71, 86, 97, 251 and 273 are
  // two-edge strips 0.019-0.039 wide, below the proximity floor (0.31): they are
  // collapsed onto one curve instead (mesh_model). Before, 58 and 86 were triangulated
  // from their boundary and on 71, 97, 251 and 273, whose two curves cross in space, every
  // triangulation folded through itself, so they failed: 280 free edges and 175
  // self-intersecting pairs, now none.
  {
    const geom::Model m = load(data("cad/occt_caxif_b1.stp"));
    const surface::MeshResult r = surface::mesh_model(m, kept(defaults(m)));
    for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
    CHECK(r.failed.empty());
    CHECK(std::count(r.mesh.triangle_face.begin(), r.mesh.triangle_face.end(), geom::Id{63}) >= 1);
    std::set<geom::Id> collapsed;
    for (const auto& c : r.collapsed) collapsed.insert(c.face);
    CHECK(collapsed == std::set<geom::Id>{58, 71, 86, 97, 251, 273});
    CHECK(surface::find_self_intersections(r.mesh, 5, 1).intersecting_pairs == 0);
    check_solids_closed(r.mesh, m, 1);
  }
}

TEST_CASE("surface mesher: a face beyond the per-face time limit is reported, the run finishes",
          "[surface]") {
  const geom::Model m = load(data("cad/gmsh_cube_fillet.stp"));
  surface::MeshOptions o = defaults(m);
  o.face_time_limit = 1e-9;  // every face that needs field points exceeds it
  const surface::MeshResult r = surface::mesh_model(m, o);
  REQUIRE_FALSE(r.failed.empty());
  for (const auto& f : r.failed) CHECK(f.reason.find("time limit") != std::string::npos);
}

TEST_CASE("surface mesher: the mesh is identical for 1 and 2 threads", "[surface]") {
  const geom::Model m = load(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step");
  const surface::MeshResult a = surface::mesh_model(m, defaults(m, 1));
  const surface::MeshResult b = surface::mesh_model(m, defaults(m, 2));
  REQUIRE(a.mesh.points.size() == b.mesh.points.size());
  CHECK(a.mesh.points == b.mesh.points);
  CHECK(a.mesh.triangles == b.mesh.triangles);
  CHECK(a.mesh.triangle_face == b.mesh.triangle_face);
}

TEST_CASE("surface mesher: edge nodes are shared by index, oriented outward", "[surface]") {
  // Conformity by construction: every model-edge segment is an edge of exactly the
  // triangles of the faces around that model edge; and the closed solid's signed volume
  // is positive (outward orientation).
  const geom::Model m = load(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step");
  const surface::MeshResult r = surface::mesh_model(m, defaults(m));
  REQUIRE(r.failed.empty());
  double vol = 0;
  for (const auto& t : r.mesh.triangles) {
    const auto &a = r.mesh.points[t[0]], &b = r.mesh.points[t[1]], &c = r.mesh.points[t[2]];
    vol += glm::dot(a, glm::cross(b, c)) / 6.0;
  }
  CHECK(vol > 0);
  std::map<std::pair<int, int>, int> use;
  for (const auto& t : r.mesh.triangles)
    for (int i = 0; i < 3; ++i) {
      int x = t[i], y = t[(i + 1) % 3];
      if (x > y) std::swap(x, y);
      ++use[{x, y}];
    }
  for (const auto& s : r.mesh.segments) {
    int x = s.a, y = s.b;
    if (x > y) std::swap(x, y);
    CHECK(use[{x, y}] == 2);
  }
}
