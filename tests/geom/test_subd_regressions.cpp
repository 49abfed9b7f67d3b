// Regression tests of the OBJ cage reader and the OpenSubdiv back end for bugs found by the
// bad-input scripts and the fuzzers (tests/fuzz): each case is the smallest input that
// showed the bug, and what the reader must answer now. Names start with "robust:" so that
// `ctest -R robust` selects them with the other regression tests.
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "uvmesh/geom/subd.h"

namespace {

uvmesh::geom::SubdCageResult parse_cage(const std::string& text) {
  std::istringstream in(text);
  return uvmesh::geom::parse_obj_cage(in, "cage.obj");
}

std::string data_file(const std::string& name) {
  return std::string(UVMESH_SOURCE_DIR) + "/tests/geom/data/" + name;
}

const std::string kTet = "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 2 3\nf 1 3 4\nf 1 4 2\nf 2 4 3\n";

}  // namespace

TEST_CASE("robust: OBJ tag counts near INT_MAX do not overflow the argument count",
          "[robust][subd]") {
  // The three counts were summed in int: 2147483647 + 1 is undefined behaviour (UBSan) and
  // the message announced -2147483648 arguments.
  const auto r = parse_cage(kTet + "t crease 2147483647/1/0 1\n");
  REQUIRE_FALSE(r.ok);
  CHECK(r.error == "cage.obj:9: tag 'crease' announces 2147483648 arguments but has 1");
  const auto r3 = parse_cage(kTet + "t corner 2147483647/2147483647/2147483647 1\n");
  REQUIRE_FALSE(r3.ok);
  CHECK_THAT(r3.error, Catch::Contains("announces 6442450941 arguments"));
}

TEST_CASE("robust: OBJ vertex coordinates beyond 1e12 are rejected like the CAD readers'",
          "[robust][subd]") {
  // 1e300 was accepted; every face then failed in the mesher ("metric not SPD") and an
  // empty mesh was written.
  const auto r = parse_cage("v 0 0 0\nv 1e300 0 0\nv 0 1 0\nf 1 2 3\n");
  REQUIRE_FALSE(r.ok);
  CHECK(r.error ==
        "cage.obj:2: vertex coordinate 1e300 is beyond the accepted magnitude 1e12 (corrupted "
        "coordinate?)");
  CHECK(parse_cage("v 0 0 0\nv -1e12 0 0\nv 0 1 0\nf 1 2 3\n").ok);  // the bound itself is fine
}

TEST_CASE("robust: an empty OBJ cage says so instead of 'line 0: no faces'", "[robust][subd]") {
  const auto r = parse_cage("");
  REQUIRE_FALSE(r.ok);
  CHECK(r.error == "cage.obj: the file is empty");
  const auto c = parse_cage("# only a comment\n");
  REQUIRE_FALSE(c.ok);
  CHECK(c.error == "cage.obj:1: no faces");
}

// fuzz_obj_cage finding: OpenSubdiv 3.5 (Debian's libosdCPU) reads out of bounds in
// Vtr::internal::Level::findEdge while Bfr builds the irregular patch of a 7-gon that
// uses vertex 1 three times and runs along the edge 1-4 and back ("4 1 1 4"), next to a
// triangle (a crash inside OpenSubdiv, reached through model_from_cage; the cage parses).
// model_from_cage now rejects a face that runs along an edge and back (x y y x) before
// OpenSubdiv sees it; faces that repeat a vertex otherwise still go to OpenSubdiv.
TEST_CASE(
    "robust: OBJ cage that crashes OpenSubdiv's findEdge is rejected by line (fuzz finding 3)",
    "[robust][subd]") {
  const uvmesh::geom::SubdCageResult c =
      uvmesh::geom::read_obj_cage(data_file("fuzz_osd_findedge_crash.obj"));
  REQUIRE(c.ok);
  uvmesh::geom::SubdOptions o;
  o.scheme = uvmesh::geom::SubdScheme::CatmullClark;
  o.boundary = uvmesh::geom::SubdBoundary::EdgeOnly;
  const uvmesh::geom::SubdModelResult m = uvmesh::geom::model_from_cage(c.cage, o);
  REQUIRE_FALSE(m.ok);
  CHECK_THAT(m.error, Catch::EndsWith(
                          "fuzz_osd_findedge_crash.obj:6: face 1 runs along the edge 4-1 and back "
                          "(vertices 4 1 1 4 in a row): a folded face, which OpenSubdiv 3.5 cannot "
                          "evaluate"));
  // The same fold in any rotation of the face, and with the triangle gone.
  for (const char* f :
       {"f 1 3 2\nf 1 1 4 3 1 2 4\n", "f 1 3 2\nf 4 3 1 2 4 1 1\n", "f 1 2 4 1 1 4 3\n"}) {
    INFO(f);
    const auto r = parse_cage(std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n") + f);
    REQUIRE(r.ok);
    CHECK_THAT(uvmesh::geom::model_from_cage(r.cage, o).error, Catch::Contains("and back"));
  }
  // Repeated vertices that are not a fold stay with OpenSubdiv (catmark_nonman_edges has
  // "x y x z" and "x x y z" faces; "x x y y" has two distinct vertices and no patch).
  for (const char* f :
       {"f 1 3 2\nf 1 2 4 1 4 3\n", "f 1 3 2\nf 1 2 4 4 3\n", "f 1 3 2\nf 2 2 4 4\n"}) {
    INFO(f);
    const auto r = parse_cage(std::string("v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n") + f);
    REQUIRE(r.ok);
    const auto mm = uvmesh::geom::model_from_cage(r.cage, o);
    CHECK(mm.ok);
    CHECK_THAT(mm.error, !Catch::Contains("and back"));
  }
}

TEST_CASE(
    "robust: obj_cage_crease_next_to_valence_2_vertex (fuzz finding: OpenSubdiv findEdge crash)",
    "[robust][subd]") {
  // fuzz_obj_cage, session 7: four quads of a broken cube in which faces 0 and 3 share
  // both edges of vertex 0 (an interior vertex of valence 2), and a crease on edge 0-1.
  // OpenSubdiv 3.5's Bfr read out of bounds in Vtr::Level::findEdge (SEGV, also in the
  // Release CLI). No face repeats a vertex, so the folded-face check did not apply.
  const std::string cube =
      "v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 -1\nv 1 -1 -1\n"
      "f 1 2 4 7\nf 3 4 6 5\nf 5 6 8 7\nf 7 8 2 1\n";
  for (auto b : {uvmesh::geom::SubdBoundary::EdgeOnly, uvmesh::geom::SubdBoundary::EdgeAndCorner}) {
    uvmesh::geom::SubdOptions o;
    o.scheme = uvmesh::geom::SubdScheme::CatmullClark;
    o.boundary = b;
    // The three creases that crashed, and one on another edge of face 0 (refused too).
    for (const char* e : {"0 1", "0 6", "6 7", "1 3"}) {
      INFO(e);
      const auto r = parse_cage(cube + "t crease 2/1/0 " + e + " 3.0\n");
      REQUIRE(r.ok);
      const auto m = uvmesh::geom::model_from_cage(r.cage, o);
      REQUIRE_FALSE(m.ok);
      CHECK_THAT(m.error,
                 Catch::Contains(":13: crease on edge") &&
                     Catch::Contains("touches face 0, which folds onto face 3 at vertex 0"));
    }
    // Without the crease, or with it away from those two faces, the cage is meshed.
    for (const std::string tail : {"", "t crease 2/1/0 4 5 3.0\n"}) {
      INFO(tail);
      const auto r = parse_cage(cube + tail);
      REQUIRE(r.ok);
      const auto m = uvmesh::geom::model_from_cage(r.cage, o);
      CHECK(m.ok);
    }
  }
}

TEST_CASE(
    "robust: obj_cage_crease_at_nonmanifold_valence_2_fan (fuzz finding: OpenSubdiv findEdge "
    "crash)",
    "[robust][subd]") {
  // fuzz_obj_cage, session 8: a cube whose six quads are wired so that faces 0 and 3
  // share both edges of vertex 0, while a third face (5) touches vertex 0 as a second
  // fan. Vertex 0 has three faces and four edges, so the valence test of
  // obj_cage_crease_next_to_valence_2_vertex missed it; OpenSubdiv 3.5 crashed the same
  // way (SEGV in Vtr::Level::findEdge, also in the Release CLI) for creases on 0-1, 0-6
  // and 6-7.
  const std::string cube =
      "v -1 -1 1\nv 1 -1 1\nv -1 1 1\nv 1 1 1\nv -1 1 -1\nv 1 1 -1\nv -1 -1 -1\nv 1 -1 -1\n"
      "f 1 2 4 7\nf 3 4 6 5\nf 5 6 8 7\nf 7 8 2 1\nf 2 8 6 3\nf 4 1 3 5\n";
  uvmesh::geom::SubdOptions o;
  o.scheme = uvmesh::geom::SubdScheme::CatmullClark;
  for (const char* e : {"0 1", "0 6", "6 7"}) {
    INFO(e);
    const auto r = parse_cage(cube + "t crease 2/1/0 " + e + " 3.0\n");
    REQUIRE(r.ok);
    const auto m = uvmesh::geom::model_from_cage(r.cage, o);
    REQUIRE_FALSE(m.ok);
    CHECK_THAT(m.error, Catch::Contains(":15: crease on edge") &&
                            Catch::Contains("folds onto face") && Catch::Contains("at vertex 0"));
  }
  // Away from the two folded faces the crease is kept and the cage is meshed.
  for (const std::string tail : {"", "t crease 2/1/0 4 5 3.0\n"}) {
    INFO(tail);
    const auto r = parse_cage(cube + tail);
    REQUIRE(r.ok);
    CHECK(uvmesh::geom::model_from_cage(r.cage, o).ok);
  }
}
