// The feature size (issue 21): CAD entities smaller than it set no size. Models are built
// here with OpenCASCADE's modeling API, one per class of artefact, not read from a corpus.
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <catch2/catch.hpp>
#include <gp_Pln.hxx>

#include "uvmesh/geom/occ.h"
#include "uvmesh/io/report.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;

namespace {

// Two 10 mm cubes side by side, the second raised by `step`: the fuse leaves two faces
// `step` wide and 10 mm long, and four edges `step` long.
geom::Model stepped_boxes(double step) {
  const TopoDS_Shape a = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 0), 10, 10, 10).Shape();
  const TopoDS_Shape b = BRepPrimAPI_MakeBox(gp_Pnt(10, 0, step), 10, 10, 10).Shape();
  BRepAlgoAPI_Fuse fuse(a, b);
  REQUIRE(fuse.IsDone());
  return geom::model_from_occ(fuse.Shape(), {});
}

surface::MeshOptions options(const geom::Model& m, bool keep) {
  surface::MeshOptions o;
  o.size = surface::default_size(m);
  o.size.hmax = m.bbox.diagonal() / 40;
  o.threads = 1;
  o.keep_topology = keep;
  return o;
}

void check_closed(const surface::SurfaceMesh& mesh, const geom::Model& m) {
  io::CheckOptions co;
  co.self_intersections = false;
  co.threads = 1;
  const io::CheckData d = io::check_mesh(mesh, &m, co);
  REQUIRE(!d.solids.empty());
  for (const auto& s : d.solids) {
    CHECK(s.closed);
    CHECK(s.free_edges == 0);
    CHECK(s.non_manifold_edges == 0);
  }
}

}  // namespace

TEST_CASE("feature size: a 1 um step between two boxes does not grade the mesh down to it",
          "[surface][feature]") {
  const geom::Model m = stepped_boxes(1e-3);
  const surface::MeshOptions keep = options(m, true), feat = options(m, false);
  REQUIRE(surface::feature_size(feat, m.bbox) > 1e-3);
  REQUIRE(surface::feature_size(keep, m.bbox) == 0);
  const surface::MeshResult rk = surface::mesh_model(m, keep);
  const surface::MeshResult rf = surface::mesh_model(m, feat);
  REQUIRE(rk.failed.empty());
  REQUIRE(rf.failed.empty());
  INFO("triangles: keep_topology " << rk.mesh.num_triangles() << ", feature size "
                                   << rf.mesh.num_triangles());
  // Resolved (keep_topology), the 1 um faces take elements of their width and grade the
  // faces beside them; under the feature size the count is that of the two cubes.
  CHECK(rf.mesh.num_triangles() * 3 < rk.mesh.num_triangles());
  check_closed(rf.mesh, m);
}

TEST_CASE("feature size: an open sheet narrower than it is still resolved (nothing absorbs it)",
          "[surface][feature]") {
  // A 10 x 0.005 rectangle alone, with a feature size of 0.01: its two long free edges are
  // closer than that, but the gap is the sheet's own width.
  const TopoDS_Shape sheet = BRepBuilderAPI_MakeFace(gp_Pln(), 0, 10, 0, 0.005).Shape();
  const geom::Model m = geom::model_from_occ(sheet, {});
  surface::MeshOptions o = options(m, false);
  o.min_feature = 0.01;
  REQUIRE(surface::feature_size(o, m.bbox) > 0.005);
  const surface::MeshResult r = surface::mesh_model(m, o);
  REQUIRE(r.failed.empty());
  const surface::QualityReport q = surface::measure_quality(r.mesh);
  CHECK(q.Q_max < 3);
  CHECK(r.mesh.num_triangles() > 1000);  // about 10 / 0.005 elements along it
}
