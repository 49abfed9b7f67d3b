// Triangle .poly reader: numbering, comments, attributes, markers, holes, regions, .node
// files, and every error path with its line number.
#include <catch2/catch.hpp>
#include <sstream>

#include "cli2d_test_util.h"
#include "uvmesh2d/poly.h"

using uvmesh::cli2d::parse_poly;
using uvmesh::cli2d::PolyRead;

namespace {

PolyRead parse(const std::string& text, const uvmesh::cli2d::FileOpener& opener = {}) {
  std::istringstream in(text);
  return parse_poly(in, "t.poly", opener);
}

// The error of a parse that must fail, as "file:line: message".
std::string error_of(const std::string& text) {
  PolyRead r = parse(text);
  REQUIRE_FALSE(r.ok());
  return r.error->str();
}

const char* kSquare0 =
    "4 2 0 1\n"
    "0 0 0 5\n"
    "1 1 0 6\n"
    "2 1 1 7\n"
    "3 0 1 8\n"
    "4 1\n"
    "0 0 1 1\n"
    "1 1 2 2\n"
    "2 2 3 3\n"
    "3 3 0 4\n"
    "0\n";

}  // namespace

TEST_CASE("poly: 0-based square with markers", "[cli2d][poly]") {
  PolyRead r = parse(kSquare0);
  REQUIRE(r.ok());
  const auto& p = r.poly;
  CHECK(p.first_index == 0);
  REQUIRE(p.pslg.points.size() == 4);
  CHECK(p.pslg.points[2].x == 1.0);
  CHECK(p.pslg.points[2].y == 1.0);
  CHECK(p.pslg.point_markers == std::vector<int>{5, 6, 7, 8});
  REQUIRE(p.pslg.segments.size() == 4);
  CHECK(p.pslg.segments[3].a == 3);
  CHECK(p.pslg.segments[3].b == 0);
  CHECK(p.pslg.segments[3].marker == 4);
  CHECK(p.has_node_markers);
  CHECK(p.has_segment_markers);
  CHECK(p.pslg.holes.empty());
  CHECK(p.pslg.regions.empty());
  CHECK(p.node_lines == std::vector<int>{2, 3, 4, 5});
  CHECK(p.segment_lines == std::vector<int>{7, 8, 9, 10});
}

TEST_CASE("poly: 1-based numbering is detected from the first node", "[cli2d][poly]") {
  PolyRead r = parse(
      "3 2 0 0\n"
      "1 0 0\n"
      "2 1 0\n"
      "3 0 1\n"
      "3 0\n"
      "1 1 2\n"
      "2 2 3\n"
      "3 3 1\n"
      "0\n");
  REQUIRE(r.ok());
  CHECK(r.poly.first_index == 1);
  REQUIRE(r.poly.pslg.segments.size() == 3);
  CHECK(r.poly.pslg.segments[0].a == 0);  // stored 0-based
  CHECK(r.poly.pslg.segments[0].b == 1);
  CHECK(r.poly.pslg.segments[2].a == 2);
  CHECK(r.poly.pslg.segments[2].b == 0);
  CHECK(r.poly.pslg.point_markers.empty());  // no markers in the file
  CHECK(r.poly.pslg.segments[1].marker == 0);
  CHECK(r.poly.describe_segment(2) == "segment 3 (t.poly:8)");
  CHECK(r.poly.describe_node(0) == "node 1 (t.poly:2)");
}

TEST_CASE("poly: comments anywhere, blank lines, tabs and CRLF", "[cli2d][poly]") {
  PolyRead r = parse(
      "# a comment before the header\n"
      "\n"
      "3\t2 0 0   # header with a comment\r\n"
      "   # indented comment line\n"
      "0 0 0\r\n"
      "1 +1.5e0 0#no space before the comment\n"
      "\n"
      "2 0 -.5\n"
      "3 0 # segments\n"
      "0 0 1\n"
      "1 1 2\n"
      "2 2 0\n"
      "0 # holes\n"
      "# trailing comment\n");
  REQUIRE(r.ok());
  REQUIRE(r.poly.pslg.points.size() == 3);
  CHECK(r.poly.pslg.points[1].x == 1.5);
  CHECK(r.poly.pslg.points[2].y == -0.5);
  CHECK(r.poly.node_lines == std::vector<int>{5, 6, 8});
}

TEST_CASE("poly: node attributes, holes and regions with and without maximum area",
          "[cli2d][poly]") {
  PolyRead r = parse(
      "4 2 2 1\n"
      "0 0 0 10 20 1\n"
      "1 4 0 11 21 1\n"
      "2 4 4 12 22 1\n"
      "3 0 4 13 23 1\n"
      "4 0\n"
      "0 0 1\n"
      "1 1 2\n"
      "2 2 3\n"
      "3 3 0\n"
      "1\n"
      "0 2 2\n"
      "2\n"
      "0 1 1 3.5\n"
      "1 3 3 -2 0.25\n");
  REQUIRE(r.ok());
  const auto& p = r.poly;
  CHECK(p.node_attribute_count == 2);
  CHECK(p.node_attributes == std::vector<double>{10, 20, 11, 21, 12, 22, 13, 23});
  CHECK(p.pslg.point_markers == std::vector<int>{1, 1, 1, 1});
  CHECK_FALSE(p.has_segment_markers);
  REQUIRE(p.pslg.holes.size() == 1);
  CHECK(p.pslg.holes[0].x == 2);
  REQUIRE(p.pslg.regions.size() == 2);
  CHECK(p.pslg.regions[0].attribute == 3.5);
  CHECK(p.pslg.regions[1].seed.x == 3);
  CHECK(p.pslg.regions[1].attribute == -2);
  CHECK(p.region_max_area == std::vector<double>{-1, 0.25});
  CHECK(p.region_lines == std::vector<int>{14, 15});
  CHECK(p.hole_lines == std::vector<int>{12});
}

TEST_CASE("poly: header fields after the count are optional, as in Triangle", "[cli2d][poly]") {
  PolyRead r = parse("3\n0 0 0\n1 1 0\n2 0 1\n0\n0\n");
  REQUIRE(r.ok());
  CHECK(r.poly.pslg.points.size() == 3);
  CHECK(r.poly.pslg.segments.empty());
}

TEST_CASE("poly: 0 nodes reads the .node file of the same name", "[cli2d][poly]") {
  std::string asked;
  auto opener = [&](const std::string& path) -> std::unique_ptr<std::istream> {
    asked = path;
    return std::make_unique<std::istringstream>(
        "# the nodes\n3 2 1 1\n1 0 0 9 1\n2 1 0 9 2\n3 0 1 9 3\n");
  };
  PolyRead r = parse("0 2 0 0\n3 0\n1 1 2\n2 2 3\n3 3 1\n0\n", opener);
  REQUIRE(r.ok());
  CHECK(asked == "t.node");
  CHECK(r.poly.first_index == 1);
  CHECK(r.poly.node_file == "t.node");
  CHECK(r.poly.pslg.point_markers == std::vector<int>{1, 2, 3});
  CHECK(r.poly.node_attributes == std::vector<double>{9, 9, 9});
  CHECK(r.poly.pslg.segments.size() == 3);

  // Errors in the .node file name the .node file.
  auto bad = [&](const std::string&) -> std::unique_ptr<std::istream> {
    return std::make_unique<std::istringstream>("3 2 0 0\n1 0 0\n2 1 x\n3 0 1\n");
  };
  PolyRead rb = parse("0 2 0 0\n0 0\n0\n", bad);
  REQUIRE_FALSE(rb.ok());
  CHECK(rb.error->str() == "t.node:3: node 2 y coordinate: 'x' is not a number");

  // No .node file: the PSLG is empty.
  PolyRead rn = parse("0 2 0 0\n0 0\n0\n",
                      [](const std::string&) { return std::unique_ptr<std::istream>(); });
  REQUIRE_FALSE(rn.ok());
  CHECK(rn.error->line == 1);
  CHECK_THAT(rn.error->message, Catch::Contains("PSLG is empty") && Catch::Contains("t.node"));
}

TEST_CASE("poly: read_poly on a missing file", "[cli2d][poly]") {
  PolyRead r = uvmesh::cli2d::read_poly("/nonexistent/dir/missing.poly");
  REQUIRE_FALSE(r.ok());
  CHECK(r.error->str() == "/nonexistent/dir/missing.poly: cannot open the file for reading");
}

TEST_CASE("poly: the bundled samples read", "[cli2d][poly]") {
  PolyRead a = uvmesh::cli2d::read_poly(cli2d_test::sample("square_hole.poly"));
  REQUIRE(a.ok());
  CHECK(a.poly.first_index == 1);
  CHECK(a.poly.pslg.points.size() == 68);
  CHECK(a.poly.pslg.segments.size() == 68);
  CHECK(a.poly.pslg.holes.size() == 1);
  PolyRead b = uvmesh::cli2d::read_poly(cli2d_test::sample("two_regions.poly"));
  REQUIRE(b.ok());
  CHECK(b.poly.first_index == 0);
  CHECK(b.poly.node_attribute_count == 1);
  CHECK(b.poly.pslg.regions.size() == 2);
  CHECK(b.poly.region_max_area[1] == 0.002);
  PolyRead c = uvmesh::cli2d::read_poly(cli2d_test::sample("key.poly"));
  REQUIRE(c.ok());
  CHECK(c.poly.pslg.holes.size() == 1);
  CHECK(c.poly.pslg.segments.size() == c.poly.pslg.points.size());  // two closed loops
}

// Every error names the file and the line (1-based, counting comment and blank lines).
TEST_CASE("poly: errors carry file and line", "[cli2d][poly][errors]") {
  SECTION("empty file") {
    CHECK(error_of("") ==
          "t.poly: unexpected end of file: expected the node header "
          "'<#nodes> <dimension> <#attributes> <#boundary markers>'");
  }
  SECTION("only comments") {
    CHECK_THAT(error_of("# nothing\n\n# here\n"),
               Catch::StartsWith("t.poly:3: unexpected end of file"));
  }
  SECTION("dimension") {
    CHECK(error_of("3 3 0 0\n") == "t.poly:1: dimension must be 2, found 3");
  }
  SECTION("marker count") {
    CHECK(error_of("3 2 0 2\n") ==
          "t.poly:1: number of node boundary markers must be 0 or 1, found 2");
  }
  SECTION("negative count") {
    CHECK(error_of("-3 2 0 0\n") == "t.poly:1: number of nodes is negative (-3)");
  }
  SECTION("huge count") {
    CHECK_THAT(error_of("99999999999 2 0 0\n"),
               Catch::Contains("t.poly:1: number of nodes is too large"));
  }
  SECTION("header with too many fields") {
    CHECK_THAT(error_of("3 2 0 0 7\n"),
               Catch::StartsWith("t.poly:1: node header: expected 1 to 4 fields"));
  }
  SECTION("first node id") {
    CHECK(error_of("3 2 0 0\n2 0 0\n") ==
          "t.poly:2: the first node id must be 0 or 1 (it fixes the numbering), found 2");
  }
  SECTION("non-consecutive node ids") {
    CHECK(error_of("3 2 0 0\n1 0 0\n3 1 0\n") ==
          "t.poly:3: node ids must be consecutive: expected node 2, found node 3");
  }
  SECTION("node id not an integer") {
    CHECK(error_of("3 2 0 0\n1.0 0 0\n") == "t.poly:2: node id: '1.0' is not an integer");
  }
  SECTION("too few fields on a node line") {
    CHECK(error_of("3 2 0 1\n# c\n1 0 0\n") ==
          "t.poly:3: node 1: expected 4 fields (<node id> <x> <y> <boundary marker>), found 3");
  }
  SECTION("too many fields on a node line") {
    CHECK(error_of("3 2 1 0\n0 0 0 1 2\n") ==
          "t.poly:2: node 0: expected 4 fields (<node id> <x> <y> 1 attribute), found 5");
  }
  SECTION("coordinate not a number") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1,5 0\n") ==
          "t.poly:3: node 1 x coordinate: '1,5' is not a number");
  }
  SECTION("NaN coordinate") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 nan\n") ==
          "t.poly:3: node 1 y coordinate is 'nan'; numbers must be finite");
  }
  SECTION("Inf coordinate") {
    CHECK(error_of("3 2 0 0\n0 -inf 0\n") ==
          "t.poly:2: node 0 x coordinate is '-inf'; numbers must be finite");
  }
  SECTION("overflowing coordinate") {
    CHECK(error_of("3 2 0 0\n0 1e999 0\n") ==
          "t.poly:2: node 0 x coordinate is '1e999'; numbers must be finite");
  }
  SECTION("NaN attribute") {
    CHECK(error_of("3 2 1 0\n0 0 0 NaN\n") ==
          "t.poly:2: node 0 attribute 1 is 'NaN'; numbers must be finite");
  }
  SECTION("marker not an integer") {
    CHECK(error_of("3 2 0 1\n0 0 0 x\n") ==
          "t.poly:2: node 0 boundary marker: 'x' is not an integer");
  }
  SECTION("truncated node section") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n") ==
          "t.poly:3: unexpected end of file: expected 3 nodes, found 2");
  }
  SECTION("missing segment header") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n") ==
          "t.poly:4: unexpected end of file: expected the segment header '<#segments> <#boundary "
          "markers>'");
  }
  SECTION("segment marker count") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n3 2\n") ==
          "t.poly:5: number of segment boundary markers must be 0 or 1, found 2");
  }
  SECTION("segment references a node out of range (the issue's example)") {
    std::string t = "40 2 0 0\n";
    for (int i = 1; i <= 40; ++i)
      t += std::to_string(i) + " " + std::to_string(i) + " " + std::to_string(i % 7) + "\n";
    t += "3 0\n1 1 2\n2 2 3\n3 3 57\n0\n";
    CHECK(error_of(t) ==
          "t.poly:45: segment 3 references node 57, but there are 40 nodes (numbered 1 to 40)");
  }
  SECTION("node 0 in a 1-based file") {
    CHECK(error_of("3 2 0 0\n1 0 0\n2 1 0\n3 0 1\n1 0\n1 0 2\n") ==
          "t.poly:6: segment 1 references node 0, but there are 3 nodes (numbered 1 to 3)");
  }
  SECTION("duplicate segment ids") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n3 0\n0 0 1\n1 1 2\n# again\n1 2 0\n0\n") ==
          "t.poly:9: segment 1 is defined twice (first at line 7)");
  }
  SECTION("degenerate segment") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 0\n0 2 2\n") ==
          "t.poly:6: segment 0 has both ends at node 2");
  }
  SECTION("segment line with a missing marker") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n1 1\n0 0 1\n") ==
          "t.poly:6: segment 0: expected 4 fields (<segment id> <node> <node> <boundary marker>), "
          "found 3");
  }
  SECTION("truncated segment section") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n2 0\n0 0 1\n") ==
          "t.poly:6: unexpected end of file: expected 2 segments, found 1");
  }
  SECTION("missing hole header") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n") ==
          "t.poly:5: unexpected end of file: expected the hole header '<#holes>'");
  }
  SECTION("hole with an infinite coordinate") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n1\n0 inf 0\n") ==
          "t.poly:7: hole 0 x coordinate is 'inf'; numbers must be finite");
  }
  SECTION("hole line with too many fields") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n1\n0 0.1 0.1 3\n") ==
          "t.poly:7: hole 0: expected 3 fields (<hole id> <x> <y>), found 4");
  }
  SECTION("region line with too few fields") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n0\n1\n0 0.1 0.1\n") ==
          "t.poly:8: region 0: expected 4 to 5 fields (<region id> <x> <y> <attribute> [<maximum "
          "area>]), found 3");
  }
  SECTION("truncated region section") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n0\n2\n0 0.1 0.1 1\n") ==
          "t.poly:8: unexpected end of file: expected 2 regions, found 1");
  }
  SECTION("content after the regions") {
    CHECK(error_of("3 2 0 0\n0 0 0\n1 1 0\n2 0 1\n0 0\n0\n0\n17\n") ==
          "t.poly:8: unexpected content after the region section");
  }
}
