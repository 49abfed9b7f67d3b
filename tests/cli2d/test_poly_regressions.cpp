// Regression tests of uvmesh2d's .poly reader for bugs found by the bad-input scripts and
// the fuzzers (tests/fuzz). Names start with "robust:" (`ctest -R robust`).
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "uvmesh2d/poly.h"

namespace {

uvmesh::cli2d::PolyRead parse_poly(const std::string& text) {
  std::istringstream in(text);
  return uvmesh::cli2d::parse_poly(in, "domain.poly");
}

}  // namespace

TEST_CASE("robust: binary bytes in a .poly field are escaped in the one-line message",
          "[robust][poly]") {
  // Raw bytes (newlines, escape sequences) went to the terminal inside the message.
  const auto r = parse_poly("\x01\x1b[2J\xff\n");
  REQUIRE_FALSE(r.ok());
  const std::string msg = r.error->str();
  CHECK(msg == "domain.poly:1: number of nodes: '\\x01\\x1b[2J\\xff' is not an integer");
  CHECK(msg.find('\n') == std::string::npos);
}
