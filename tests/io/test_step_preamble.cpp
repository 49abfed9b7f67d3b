// STEP files as CAD systems and editors write them: comments wherever whitespace may stand
// (ISO 10303-21), a UTF-8 byte-order mark, blank lines, CRLF. Each variant of the bundled
// bracket must pre-scan as STEP and read to the same model; real garbage still fails.
#include <catch2/catch.hpp>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/prescan.h"

using namespace uvmesh;

namespace {

std::string bracket_text() {
  std::ifstream in(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step", std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string crlf(const std::string& t) {
  std::string o;
  for (char c : t) o += c == '\n' ? std::string("\r\n") : std::string(1, c);
  return o;
}

// Text with `marker` replaced by `marker + insert` once (a comment between entities).
std::string insert_after(std::string t, const std::string& marker, const std::string& insert) {
  const auto i = t.find(marker);
  REQUIRE(i != std::string::npos);
  return t.insert(i + marker.size(), insert);
}

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string path = std::string(UVMESH_BINARY_DIR) + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

}  // namespace

TEST_CASE("STEP preamble: comments, byte-order mark, blank lines and CRLF are read", "[io][step]") {
  const std::string t = bracket_text();
  const io::ReadResult ref = io::read_cad(write_temp("preamble_ref.step", t), {});
  REQUIRE(ref.ok);
  const std::size_t faces = ref.model.faces.size();
  const std::pair<const char*, std::string> variants[] = {
      {"leading comment", "/* written by a CAD system */\n" + t},
      {"multi-line comment", "/* line one\n   line two\n*/\n\n" + t},
      {"comment between header entities", insert_after(t, "HEADER;", "\n/* header note */")},
      {"comment in the DATA section", insert_after(t, "DATA;", "\n/* data note */\n")},
      {"byte-order mark", "\xEF\xBB\xBF" + t},
      {"leading blank lines", "\n\n  \n" + t},
      {"CRLF", crlf(t)},
      {"mark, comment and CRLF", "\xEF\xBB\xBF" + crlf("/* c */\n" + t)}};
  int k = 0;
  for (const auto& [what, text] : variants) {
    INFO(what);
    const std::string path = write_temp("preamble_" + std::to_string(k++) + ".step", text);
    const io::PrescanResult p = io::prescan_file(path, {});
    CHECK(p.error.empty());
    CHECK(p.content == io::CadFormat::Step);
    const io::ReadResult r = io::read_cad(path, {});
    CHECK(r.ok);
    CHECK(r.model.faces.size() == faces);
    std::remove(path.c_str());
  }
}

TEST_CASE("STEP preamble: an unterminated comment or garbage after a comment is refused",
          "[io][step]") {
  const std::string t = bracket_text();
  for (const std::string& text :
       {std::string("/* never closed\n") + t, std::string("/* c */ garbage\n") + t,
        std::string("\xEF\xBB\xBF")}) {
    const std::string path = write_temp("preamble_bad.step", text);
    const io::ReadResult r = io::read_cad(path, {});
    CHECK_FALSE(r.ok);
    CHECK_FALSE(r.error.empty());
    std::remove(path.c_str());
  }
}
