// Pre-scan of STEP / IGES / BREP text: each rejected defect inline, with why it matters.
#include <catch2/catch.hpp>
#include <string>

#include "uvmesh/io/prescan.h"

using namespace uvmesh::io;

namespace {

std::string step(const std::string& data) {
  return "ISO-10303-21;\nHEADER;\nFILE_NAME('x','',(''),(''),'','','');\nENDSEC;\nDATA;\n" + data +
         "ENDSEC;\nEND-ISO-10303-21;\n";
}
const std::string kGood =
    "#1=CARTESIAN_POINT('',(0.,1.5,-2.E1));\n#2=DIRECTION('',(0.,0.,1.));\n#3=AXIS2_PLACEMENT_3D(''"
    ",#1,#2,$);\n"
    "#4=PLANE('it''s; a plane',#3);\n";

PrescanResult scan(const std::string& text, CadFormat f = CadFormat::Step) {
  return prescan_text(text, f, PrescanOptions{});
}

std::string iges_line(const std::string& body, char section, int seq) {
  std::string l = body;
  l.resize(72, ' ');
  l += section;
  std::string n = std::to_string(seq);
  l += std::string(7 - n.size(), ' ') + n;
  return l + "\n";
}

}  // namespace

TEST_CASE("prescan: format sniffing and extensions", "[io][prescan]") {
  CHECK(sniff_format("ISO-10303-21;\nHEADER;") == CadFormat::Step);
  CHECK(sniff_format("DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\n") ==
        CadFormat::Brep);
  CHECK(sniff_format(iges_line("start", 'S', 1)) == CadFormat::Iges);
  CHECK(sniff_format(std::string("\x89PNG\r\n\x1a\n", 8)) == CadFormat::Unknown);
  CHECK(format_from_extension("a/b.STP") == CadFormat::Step);
  CHECK(format_from_extension("a.iges") == CadFormat::Iges);
  CHECK(format_from_extension("x.rle") == CadFormat::Brep);
  CHECK(format_from_extension("dir.step/file") == CadFormat::Unknown);
}

TEST_CASE("prescan: a well-formed STEP file passes; strings may hold ';' and quotes",
          "[io][prescan]") {
  const PrescanResult r = scan(step(kGood));
  INFO(r.error);
  CHECK(r.ok);
  CHECK(r.step_entities == 4);
  CHECK(r.dangling_references == 0);
}

TEST_CASE("prescan: NaN, infinite and overflowing STEP coordinates are rejected", "[io][prescan]") {
  // A NaN coordinate crashes a plain OCC STEP import: it must never reach OCC.
  for (const std::string bad : {"NaN", "-nan", "INF", "1.E400"}) {
    INFO(bad);
    const PrescanResult r = scan(step("#1=CARTESIAN_POINT('',(0.," + bad + ",1.));\n"));
    CHECK_FALSE(r.ok);
    CHECK(r.error.find("#1") != std::string::npos);
  }
  // A huge but finite coordinate (synth_huge_coord.step has 1.E300) is rejected too.
  const PrescanResult h = scan(step("#7=CARTESIAN_POINT('',(1.E300,0.,0.));\n"));
  CHECK_FALSE(h.ok);
  CHECK(h.error.find("CARTESIAN_POINT #7") != std::string::npos);
  // ... but large numbers elsewhere (knots, weights) are not coordinates.
  CHECK(scan(step("#1=B_SPLINE_CURVE_WITH_KNOTS('',1,(),.UNSPECIFIED.,.F.,.F.,(2),(1.E20,2.E20),."
                  "UNSPECIFIED.);\n"))
            .ok);
}

TEST_CASE("prescan: truncation and dangling references", "[io][prescan]") {
  std::string t = step(kGood);
  t = t.substr(0, t.find("#4=") + 10);  // cut inside a statement
  const PrescanResult r = scan(t);
  CHECK_FALSE(r.ok);
  CHECK(r.error.find("truncated") != std::string::npos);
  // No END-ISO line after complete statements: still truncated.
  std::string t2 = step(kGood);
  t2 = t2.substr(0, t2.find("ENDSEC;\nEND-ISO"));
  CHECK(scan(t2).error.find("truncated") != std::string::npos);
  // A reference to an entity defined nowhere, in an otherwise clean file: an error.
  const PrescanResult d =
      scan(step(kGood + "#5=ADVANCED_FACE('',(#6),#999,.T.);\n#6=FACE_BOUND('',#3,.T.);\n"));
  CHECK_FALSE(d.ok);
  CHECK(d.error.find("#5 references #999") != std::string::npos);
  // With garbled statements (OCC bug 32314's file) they are warnings: partial import.
  const PrescanResult g = scan(step(kGood + "th0.,1.));\n#5=PLANE('',#77);\n"));
  CHECK(g.ok);
  CHECK(g.malformed_statements == 1);
  CHECK(g.dangling_references == 1);
  CHECK(g.warnings.size() == 2);
}

TEST_CASE("prescan: tessellated-only STEP content is counted", "[io][prescan]") {
  const PrescanResult r = scan(step(
      "#1=COMPLEX_TRIANGULATED_FACE('',#2,3,(),$,(),(),());\n#2=COORDINATES_LIST('',0,());\n"));
  CHECK(r.ok);
  CHECK(r.step_tessellated_faces == 1);
  CHECK(r.step_brep_faces == 0);
}

TEST_CASE("prescan: IGES sections and numbers", "[io][prescan]") {
  std::string ok = iges_line("start", 'S', 1) + iges_line("1H,,1H;;", 'G', 1) +
                   iges_line("     110       1", 'D', 1) + iges_line("     110       0", 'D', 2) +
                   iges_line("110,0.,0.,0.,1.,1.,1.;", 'P', 1) +
                   iges_line("S      1G      1D      2P      1", 'T', 1);
  CHECK(scan(ok, CadFormat::Iges).ok);
  std::string no_p = ok;
  no_p.erase(no_p.find("110,0."), 81);
  const PrescanResult r = scan(no_p, CadFormat::Iges);
  CHECK_FALSE(r.ok);
  CHECK(r.error.find("Parameter Data (P) section is missing") != std::string::npos);
  std::string nan = ok;
  nan.replace(nan.find("1.,1.,1.;"), 9, "NaN,1.,1;");  // same width: column 73 stays
  CHECK(scan(nan, CadFormat::Iges).error.find("non-finite") != std::string::npos);
  CHECK(
      scan("just some text\nthat is not IGES\n", CadFormat::Iges).error.find("not an IGES file") !=
      std::string::npos);
}

TEST_CASE("prescan: BREP numbers must be finite", "[io][prescan]") {
  const std::string head =
      "DBRep_DrawableShape\n\nCASCADE Topology V1, (c) Matra-Datavision\nLocations 0\n";
  CHECK(scan(head + "Curves 1\n1 0 0 0 1 0 0\n", CadFormat::Brep).ok);
  CHECK(scan(head + "Curves 1\n1 0 nan 0 1 0 0\n", CadFormat::Brep).error.find("line 6") !=
        std::string::npos);
  CHECK_FALSE(scan(head + "Curves 1\n1 0 1e999 0 1 0 0\n", CadFormat::Brep).ok);
}

TEST_CASE("prescan: STEP comments, byte-order mark, blank lines and CRLF are whitespace",
          "[io][prescan]") {
  const std::string bom = "\xEF\xBB\xBF";
  CHECK(sniff_format("/* c */\nISO-10303-21;") == CadFormat::Step);
  CHECK(sniff_format(bom + "\r\n\r\n/* a */ /* b\n */ISO-10303-21;") == CadFormat::Step);
  CHECK(sniff_format("/* never closed ISO-10303-21;") == CadFormat::Unknown);
  CHECK(sniff_format("/* c */ garbage ISO-10303-21;") == CadFormat::Unknown);
  const std::string crlf_good =
      "#1=CARTESIAN_POINT('',(0.,/* y */1.5,-2.E1));\r\n"
      "/* #9=PLANE('',#99); */\r\n#2=DIRECTION('',(0.,0.,1.));\r\n";
  const PrescanResult r = scan(bom + "/* head */\r\n" + step(crlf_good));
  INFO(r.error);
  CHECK(r.ok);
  CHECK(r.step_entities == 2);
  CHECK(r.dangling_references == 0);  // #99 is in a comment
  // A comment separates tokens: '1./**/2.' is two numbers, as in the standard.
  CHECK(scan(step("#1=CARTESIAN_POINT('',(1./**/2.E400));\n")).error.find("overflows") !=
        std::string::npos);
  CHECK(scan(step("#1=PLANE('',#2);\n/* never closed\n")).error.find("unterminated comment") !=
        std::string::npos);
  CHECK(scan("/* c */ nonsense;\n" + step(kGood)).error.find("not a STEP file: line 1") !=
        std::string::npos);
}

TEST_CASE("prescan: IGES accepts CRLF line ends, not a byte-order mark", "[io][prescan]") {
  std::string ok = iges_line("start", 'S', 1) + iges_line("1H,,1H;;", 'G', 1) +
                   iges_line("     110       1", 'D', 1) + iges_line("     110       0", 'D', 2) +
                   iges_line("110,0.,0.,0.,1.,1.,1.;", 'P', 1) +
                   iges_line("S      1G      1D      2P      1", 'T', 1);
  std::string crlf;
  for (const char c : ok) crlf += c == '\n' ? std::string("\r\n") : std::string(1, c);
  CHECK(sniff_format(crlf) == CadFormat::Iges);
  CHECK(scan(crlf, CadFormat::Iges).ok);
  // Fixed-column records: a byte-order mark shifts column 73 of the first line.
  CHECK(sniff_format("\xEF\xBB\xBF" + ok) == CadFormat::Unknown);
}
