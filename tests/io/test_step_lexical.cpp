// STEP lexical tolerance (issue 21): ISO 10303-21 lets comments stand wherever whitespace
// may; Windows tools add a UTF-8 byte-order mark and CRLF line ends. Each class of variant
// is built from the bundled bracket.step, must pass the pre-scan and read (io::read_cad)
// to the original's face count. Real garbage still gives a clear error naming the file.
#include <catch2/catch.hpp>
#include <fstream>
#include <sstream>
#include <string>

#include "mesh_test_util.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/prescan.h"

using namespace uvmesh;
using uvmesh_test::TempDir;

namespace {

const std::string kBom = "\xEF\xBB\xBF";

std::string bracket_text() {
  std::ifstream in(std::string(UVMESH_SOURCE_DIR) + "/samples/data/bracket.step", std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  REQUIRE(s.str().rfind("ISO-10303-21;", 0) == 0);
  return s.str();
}

// text with the first occurrence of `what` replaced by `with` (which must exist).
std::string replaced(std::string text, const std::string& what, const std::string& with) {
  const std::size_t at = text.find(what);
  REQUIRE(at != std::string::npos);
  return text.replace(at, what.size(), with);
}

std::string crlf(const std::string& text) {
  std::string r;
  for (const char c : text) r += c == '\n' ? std::string("\r\n") : std::string(1, c);
  return r;
}

std::string write(const TempDir& dir, const std::string& name, const std::string& text) {
  const std::string path = dir.file(name);
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::size_t faces_of(const std::string& path) {
  const io::ReadResult r = io::read_cad(path);
  INFO(r.error);
  REQUIRE(r.ok);
  return r.model.faces.size();
}

// The variant pre-scans like the original (same entity and face counts) and reads to the
// original's face count.
void check_variant(const std::string& name, const std::string& text) {
  TempDir dir("step_lexical");
  const std::string orig = write(dir, "orig.step", bracket_text());
  const std::string path = write(dir, name + ".step", text);
  const io::PrescanResult p0 = io::prescan_file(orig, {});
  const io::PrescanResult p = io::prescan_file(path, {});
  INFO(name << ": " << p.error);
  REQUIRE(p.ok);
  CHECK(p.content == io::CadFormat::Step);
  CHECK(p.step_entities == p0.step_entities);
  CHECK(p.step_brep_faces == p0.step_brep_faces);
  CHECK(p.malformed_statements == 0);
  const std::size_t want = faces_of(orig);
  CHECK(want > 0);
  CHECK(faces_of(path) == want);
  CHECK(dir.entries().size() == 2);  // nothing left behind (no temp copy)
}

// The variant is refused: the error names the file and contains `what`.
void check_refused(const std::string& name, const std::string& text, const std::string& what) {
  TempDir dir("step_lexical_bad");
  const std::string path = write(dir, name + ".step", text);
  const io::ReadResult r = io::read_cad(path);
  INFO(r.error);
  CHECK_FALSE(r.ok);
  CHECK(r.error.rfind(path + ": ", 0) == 0);
  CHECK(r.error.find(what) != std::string::npos);
}

}  // namespace

TEST_CASE("step lexical: a one-line comment before the header", "[io][step_lexical]") {
  check_variant("comment_line", "/* exported by some CAD system */\n" + bracket_text());
}

TEST_CASE("step lexical: a multi-line comment before the header", "[io][step_lexical]") {
  check_variant("comment_block",
                "/*\n * licence text\n * ISO-10303-21; DATA; #1 = X();\n */\n" + bracket_text());
}

TEST_CASE("step lexical: comments between and inside header entities", "[io][step_lexical]") {
  std::string t = replaced(bracket_text(), "\nDATA;", "\nDATA; /* after the keyword */");
  t = replaced(t, "FILE_NAME(", "/* between; DATA; */\nFILE_NAME(");
  t = replaced(t, "('Open CASCADE Model')", "( /* inside */ 'Open CASCADE Model')");
  check_variant("comment_header", t);
}

TEST_CASE("step lexical: comments in the DATA section between and inside entities",
          "[io][step_lexical]") {
  std::string t = replaced(bracket_text(), "#3 = ", "/* #999 = ADVANCED_FACE(#998); */\n#3 = ");
  t = replaced(t, "#17 = ADVANCED_FACE(", "#17 = /* a face */ ADVANCED_FACE(");
  t = replaced(t, "END-ISO-10303-21;", "/* last */ END-ISO-10303-21;");
  check_variant("comment_data", t);
}

TEST_CASE("step lexical: a UTF-8 byte-order mark", "[io][step_lexical]") {
  check_variant("bom", kBom + bracket_text());
}

TEST_CASE("step lexical: leading blank lines", "[io][step_lexical]") {
  check_variant("blank_lines", "\n\n  \t\n" + bracket_text());
}

TEST_CASE("step lexical: CRLF line ends", "[io][step_lexical]") {
  check_variant("crlf", crlf(bracket_text()));
}

TEST_CASE("step lexical: byte-order mark, CRLF and comments together", "[io][step_lexical]") {
  const std::string t = replaced(bracket_text(), "#3 = ", "/* in data */\n#3 = ");
  check_variant("combined", kBom + crlf("/* header\n comment */\n\n" + t));
}

TEST_CASE("step lexical: an unterminated comment is refused with its line", "[io][step_lexical]") {
  check_refused("open_leading", "\n/* never closed\n" + bracket_text().substr(0, 200),
                "unterminated comment: the '/*' at line 2");
  const std::string t = bracket_text();
  check_refused("open_data", replaced(t, "#3 = ", "/* never closed\n#3 = "),
                "unterminated comment");
}

TEST_CASE("step lexical: a comment followed by garbage is refused", "[io][step_lexical]") {
  check_refused("comment_garbage", "/* looks like STEP */\n\x01\x02garbage\n" + bracket_text(),
                "not a CAD file: after the leading comment, line 2");
}

TEST_CASE("step lexical: a byte-order mark followed by nothing is refused", "[io][step_lexical]") {
  check_refused("bom_only", kBom, "empty: it holds only a UTF-8 byte-order mark");
  check_refused("bom_blank", kBom + "\r\n\r\n", "empty");
}

TEST_CASE("step lexical: a section keyword apart from its ';' is refused with its line",
          "[io][step_lexical]") {
  // The standard allows it; OCCT 7.6's reader rejects it (its lexer knows "DATA;" only).
  const std::string t = bracket_text();
  check_refused("data_apart", replaced(t, "\nDATA;", "\nDATA /* c */ ;"),
                "line 8: space or comment between 'DATA' and its ';'");
  check_refused("endsec_apart", replaced(t, "ENDSEC;\nEND-ISO", "ENDSEC ;\nEND-ISO"),
                "between 'ENDSEC' and its ';'");
}
