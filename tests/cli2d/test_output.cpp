// PendingOutput: outputs appear only on commit; errors leave nothing behind.
#include <catch2/catch.hpp>

#include "cli2d_test_util.h"
#include "uvmesh2d/output.h"

using namespace uvmesh::cli2d;

TEST_CASE("output: format from the extension", "[cli2d][output]") {
  CHECK(output_format("a.mesh") == OutputFormat::Medit);
  CHECK(output_format("dir.x/A.MSH") == OutputFormat::Gmsh22);
  CHECK(output_format("pic.Svg") == OutputFormat::Svg);
  CHECK_FALSE(output_format("a.vtk").has_value());
  CHECK_FALSE(output_format("mesh").has_value());
  CHECK_FALSE(output_format("dir.mesh/file").has_value());
  CHECK_FALSE(output_format(".mesh").has_value());  // a hidden file, no extension
}

TEST_CASE("output: commit publishes, destruction without commit leaves nothing",
          "[cli2d][output]") {
  cli2d_test::ScratchDir dir("output");
  {
    PendingOutput o;
    REQUIRE_FALSE(o.open(dir / "a.mesh"));
    o.stream() << "hello";
    CHECK(dir.files().size() == 1);  // the temporary
    CHECK_FALSE(cli2d_test::fs::exists(dir / "a.mesh"));
    REQUIRE_FALSE(o.commit());
  }
  CHECK(cli2d_test::read_file(dir / "a.mesh") == "hello");
  CHECK(dir.files() == std::vector<std::string>{"a.mesh"});
  {
    PendingOutput o;
    REQUIRE_FALSE(o.open(dir / "a.mesh"));
    o.stream() << "replaced?";
  }  // no commit
  CHECK(cli2d_test::read_file(dir / "a.mesh") == "hello");
  CHECK(dir.files() == std::vector<std::string>{"a.mesh"});
  {
    PendingOutput o;
    REQUIRE_FALSE(o.open(dir / "a.mesh"));
    o.stream() << "new";
    REQUIRE_FALSE(o.commit());
    o.undo_commit();
  }
  CHECK(dir.files().empty());
}

TEST_CASE("output: unwritable destinations fail at open", "[cli2d][output][errors]") {
  cli2d_test::ScratchDir dir("output-bad");
  PendingOutput a;
  auto e = a.open(dir / "no/such/dir/out.mesh");
  REQUIRE(e);
  CHECK_THAT(e->str(), Catch::StartsWith(dir / "no/such/dir/out.mesh: cannot write here: "));
  PendingOutput b;
  cli2d_test::fs::create_directory(dir / "sub.mesh");
  auto d = b.open(dir / "sub.mesh");
  REQUIRE(d);
  CHECK(d->str() == dir / "sub.mesh" + ": is a directory");
  CHECK(dir.files() == std::vector<std::string>{"sub.mesh"});
}
