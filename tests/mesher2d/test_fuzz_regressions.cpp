// Regression tests of mesher2d for the PSLGs fuzz_poly_mesh2d (tests/fuzz) found: each is
// the snapped PSLG the fuzzer met (tests/mesher2d/data), meshed as it did, with and without
// refinement; m2d::mesh answered Ok and m2d::check rejected the mesh. Names start with
// "robust:" (`ctest -R robust`).
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "field_point_methods.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh2d/poly.h"

namespace {

std::string data_file(const std::string& name) {
  return std::string(UVMESH_SOURCE_DIR) + "/tests/mesher2d/data/" + name;
}

// A mesher2d finding of fuzz_poly_mesh2d: the snapped PSLG it met, meshed as it did
// (with and without refinement). m2d::mesh answered Ok and m2d::check rejected the mesh.
void mesher2d_finding(const std::string& file, double h) {
  const uvmesh::cli2d::PolyRead pr = uvmesh::cli2d::read_poly(data_file(file));
  INFO(file);
  REQUIRE(pr.ok());
  const uvmesh::m2d::FieldPointMethod method = FIELD_POINT_METHOD;
  INFO(method_name(method));
  uvmesh::m2d::Options opt = method_options(method);
  opt.optimize = false;
  opt.max_vertices = 4000;
  for (const bool refine : {true, false}) {
    INFO("refine " << refine);
    opt.refine = refine;
    const uvmesh::m2d::Result r =
        uvmesh::m2d::mesh(pr.poly.pslg, uvmesh::m2d::SizeSpec::uniform(h), opt);
    INFO(r.status.message);
    REQUIRE(r.usable());
    uvmesh::m2d::CheckOptions co;
    co.seeds = false;
    co.delaunay = !refine;
    const uvmesh::m2d::CheckReport rep = uvmesh::m2d::check(r.mesh, pr.poly.pslg, co);
    INFO("checker: " << (rep.ok() ? std::string("ok") : rep.errors.front()));
    CHECK(rep.ok());
  }
}

}  // namespace

// The mesh was right; the checker was not. Segment 3 (2,1)-(0,1) runs through (1,1); its
// piece (2,1)-(1,1) lies between a hole (the seed at (1.5, 0)) and the exterior (the wedge
// above it is open to the right), so the checker's walk from (2,1) stopped there, accepted
// the segment as leaving the domain, and never marked the piece (1,1)-(0,1) beyond the gap,
// which it then called a constrained edge on no segment. The checker now accepts an
// unmarked constrained edge that lies on some input segment.
TEST_CASE("robust: mesher2d with duplicate points and degenerate segments (fuzz finding 1)",
          "[robust][mesher2d]") {
  mesher2d_finding("fuzz_mesher2d_duplicate_points.poly", 0.0);
}

// A mesher bug: segment 1 (0,-4)-(8,4), split at node 3 (4,0), gave the piece (4,0)-(8,4)
// that segment 3 already is. Both records of that edge stayed live; boundary
// discretization split it twice, the second time with points rounded off the first
// chain. Overlapping pieces are now merged at enforcement (one record per edge, as
// Triangle keeps one subsegment).
TEST_CASE("robust: mesher2d with a node inside a segment, overlapping segments (fuzz finding 2)",
          "[robust][mesher2d]") {
  mesher2d_finding("fuzz_mesher2d_overlapping_segments.poly", 0.37);
}
