// Text pre-scan of STEP / IGES / BREP files (see prescan.h). Linear in the file size.
#include "uvmesh/io/prescan.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <unordered_set>
#include <vector>

namespace uvmesh::io {
namespace {

std::string lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return std::tolower(c); });
  return r;
}

bool is_nonfinite_word(std::string_view w) {
  if (!w.empty() && (w[0] == '+' || w[0] == '-')) w.remove_prefix(1);
  const std::string l = lower(w);
  return l == "nan" || l == "inf" || l == "infinity" || l.rfind("nan(", 0) == 0;
}

// Parses a number at s[i..]; returns chars consumed (0 if none) and the value.
std::size_t parse_number(std::string_view s, std::size_t i, double& value, bool& overflow) {
  std::size_t j = i;
  if (j < s.size() && (s[j] == '+' || s[j] == '-')) ++j;
  const std::size_t digits_start = j;
  while (j < s.size() && (std::isdigit(static_cast<unsigned char>(s[j])) || s[j] == '.')) ++j;
  if (j == digits_start) return 0;
  if (j < s.size() && (s[j] == 'E' || s[j] == 'e' || s[j] == 'D' || s[j] == 'd')) {
    std::size_t k = j + 1;
    if (k < s.size() && (s[k] == '+' || s[k] == '-')) ++k;
    const std::size_t e0 = k;
    while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k]))) ++k;
    if (k > e0) j = k;
  }
  std::string tok(s.substr(i, j - i));
  std::replace(tok.begin(), tok.end(), 'D', 'E');  // IGES may use Fortran exponents
  std::replace(tok.begin(), tok.end(), 'd', 'E');
  errno = 0;
  value = std::strtod(tok.c_str(), nullptr);
  overflow = (errno == ERANGE && std::isinf(value)) || !std::isfinite(value);
  return j - i;
}

std::string fmt_num(double v) {
  std::ostringstream os;
  os << v;
  return os.str();
}

// ---------------------------------------------------------------------------- STEP

// ISO 10303-21 lets a comment stand wherever whitespace may (section 5.6 of the 2016
// edition): before the header, between and inside statements. A UTF-8 byte-order mark
// is what Windows editors put before a file they saved; it is not part of the text.
constexpr std::string_view kUtf8Bom = "\xEF\xBB\xBF";

bool starts_with_bom(std::string_view t) {
  return t.substr(0, kUtf8Bom.size()) == kUtf8Bom;
}

std::string_view without_bom(std::string_view t) {
  return starts_with_bom(t) ? t.substr(kUtf8Bom.size()) : t;
}

// 1-based line of offset pos (LF or CRLF line ends).
long line_at(std::string_view t, std::size_t pos) {
  return 1 + static_cast<long>(std::count(t.begin(), t.begin() + std::min(pos, t.size()), '\n'));
}

// Skips whitespace and comments from i. False when a comment is never closed (i is then
// at its "/*").
bool skip_blank(std::string_view t, std::size_t& i) {
  while (i < t.size()) {
    if (std::isspace(static_cast<unsigned char>(t[i]))) {
      ++i;
    } else if (t.compare(i, 2, "/*") == 0) {
      const std::size_t j = t.find("*/", i + 2);
      if (j == std::string_view::npos) return false;
      i = j + 2;
    } else {
      break;
    }
  }
  return true;
}

enum class Stmt { Closed, Eof, OpenComment };

// Accumulates one statement of t from i up to ';' outside strings and comments (strings
// become a '' placeholder, a comment a space, line breaks are dropped). Eof when the text
// ends first; OpenComment (i at its "/*") when a comment is never closed.
Stmt next_statement(std::string_view t, std::size_t& i, std::string& stmt) {
  stmt.clear();
  while (i < t.size()) {
    const char c = t[i];
    if (c == '\'') {  // string, '' is an escaped quote
      std::size_t j = i + 1;
      while (j < t.size()) {
        if (t[j] == '\'') {
          if (j + 1 < t.size() && t[j + 1] == '\'') {
            j += 2;
            continue;
          }
          break;
        }
        ++j;
      }
      stmt += "''";  // keep a placeholder, drop the content
      i = j + 1;
      continue;
    }
    if (c == '/' && i + 1 < t.size() && t[i + 1] == '*') {
      const std::size_t j = t.find("*/", i + 2);
      if (j == std::string_view::npos) return Stmt::OpenComment;
      stmt += ' ';  // a comment separates tokens like whitespace
      i = j + 2;
      continue;
    }
    ++i;
    if (c == ';') return Stmt::Closed;
    if (c != '\n' && c != '\r') stmt += c;
  }
  return Stmt::Eof;
}

// stmt without the spaces and tabs around it.
std::string_view trimmed(const std::string& stmt) {
  const auto b = stmt.find_first_not_of(" \t");
  if (b == std::string::npos) return {};
  const auto e = stmt.find_last_not_of(" \t");
  return std::string_view(stmt).substr(b, e + 1 - b);
}

// A keyword statement: exactly `kw`, or `kw` followed by parameters ("DATA('x',(...))").
bool is_keyword(std::string_view s, std::string_view kw) {
  if (s.substr(0, kw.size()) != kw) return false;
  const std::string_view rest = s.substr(kw.size());
  const auto b = rest.find_first_not_of(" \t");
  return b == std::string_view::npos || rest[b] == '(';
}

// Up to 40 characters of the line from pos, for a message.
std::string line_text(std::string_view t, std::size_t pos) {
  const std::string_view rest = t.substr(std::min(pos, t.size()));
  return std::string(rest.substr(0, std::min<std::size_t>(40, rest.find_first_of("\r\n"))));
}

std::string unclosed_comment(std::string_view t, std::size_t at) {
  return "unterminated comment: the '/*' at line " + std::to_string(line_at(t, at)) +
         " is never closed by '*/'";
}

// A word at s[j..] (letters, digits, '_' and, with dash, '-'); returns its end.
std::size_t word_end(std::string_view s, std::size_t j, bool dash) {
  std::size_t m = j;
  while (m < s.size() &&
         (std::isalnum(static_cast<unsigned char>(s[m])) || s[m] == '_' || (dash && s[m] == '-')))
    ++m;
  return m;
}

// The parameters of entity #id (s from its '=' at eq): references go to refs; numbers
// must be finite, and a CARTESIAN_POINT's within the accepted magnitude. "" or the error.
std::string scan_step_parameters(std::string_view s, std::size_t eq, long long id, bool point,
                                 const PrescanOptions& opt,
                                 std::vector<std::pair<long long, long long>>& refs) {
  for (std::size_t j = eq + 1; j < s.size();) {
    const char c = s[j];
    if (c == '#') {
      long long ref = 0;
      std::size_t m = j + 1;
      while (m < s.size() && std::isdigit(static_cast<unsigned char>(s[m])))
        ref = ref * 10 + (s[m++] - '0');
      if (m > j + 1) refs.emplace_back(id, ref);
      j = m;
    } else if (c == '.') {  // enumeration .NAME. or a number like .5
      if (j + 1 < s.size() && std::isalpha(static_cast<unsigned char>(s[j + 1]))) {
        const std::size_t m = s.find('.', j + 1);
        j = (m == std::string_view::npos) ? s.size() : m + 1;
      } else {
        double v = 0;
        bool of = false;
        const std::size_t n = parse_number(s, j, v, of);
        j += std::max<std::size_t>(n, 1);
      }
    } else if (std::isdigit(static_cast<unsigned char>(c)) || c == '-' || c == '+') {
      double v = 0;
      bool of = false;
      const std::size_t n = parse_number(s, j, v, of);
      if (n == 0) {
        // A sign before a word: "-NaN", "+INF".
        const std::size_t m = word_end(s, j + 1, false);
        if (is_nonfinite_word(s.substr(j, m - j)))
          return "entity #" + std::to_string(id) + " has a non-finite number '" +
                 std::string(s.substr(j, m - j)) + "'";
        j = m;
        continue;
      }
      if (of)
        return "entity #" + std::to_string(id) + " has a number that overflows a double ('" +
               std::string(s.substr(j, n)) + "')";
      if (point && std::abs(v) > opt.max_abs_coordinate)
        return "CARTESIAN_POINT #" + std::to_string(id) + " has coordinate " + fmt_num(v) +
               ", beyond the accepted magnitude " + fmt_num(opt.max_abs_coordinate) +
               " (corrupted coordinate?)";
      j += n;
    } else if (std::isalpha(static_cast<unsigned char>(c)) || c == '_') {
      const std::size_t m = word_end(s, j, true);
      std::size_t after = m;
      while (after < s.size() && s[after] == ' ') ++after;
      const bool is_type = after < s.size() && s[after] == '(';
      if (!is_type && is_nonfinite_word(s.substr(j, m - j)))
        return "entity #" + std::to_string(id) + " has a non-finite number '" +
               std::string(s.substr(j, m - j)) + "'";
      j = m;
    } else {
      ++j;
    }
  }
  return {};
}

// What the STEP scan keeps across statements.
struct StepScan {
  std::unordered_set<long long> defined;
  std::vector<std::pair<long long, long long>> refs;  // (from entity, to entity)
};

// One entity statement s ("#id = ..."): counted, its parameters scanned. "" or the error.
std::string scan_step_entity(std::string_view s, const PrescanOptions& opt, StepScan& st,
                             PrescanResult& r) {
  // Defined id.
  std::size_t k = 1;
  long long id = 0;
  while (k < s.size() && std::isdigit(static_cast<unsigned char>(s[k])))
    id = id * 10 + (s[k++] - '0');
  st.defined.insert(id);
  ++r.step_entities;
  const bool point = s.find("CARTESIAN_POINT") != std::string_view::npos;
  if (s.find("ADVANCED_FACE") != std::string_view::npos ||
      s.find("FACE_SURFACE") != std::string_view::npos)
    ++r.step_brep_faces;
  if (s.find("TRIANGULATED_FACE") != std::string_view::npos ||
      s.find("TESSELLATED_FACE") != std::string_view::npos)
    ++r.step_tessellated_faces;
  // Parameters: references, numbers, stray words.
  const std::size_t eq = s.find('=', k);
  if (eq == std::string_view::npos) {
    ++r.malformed_statements;
    if (r.warnings.size() < 5)
      r.warnings.push_back("malformed STEP entity #" + std::to_string(id) + " (no '=')");
    return {};
  }
  return scan_step_parameters(s, eq, id, point, opt, st.refs);
}

// A reference to an entity that is defined nowhere. In an otherwise well-formed file
// that is an inconsistency OCC would paper over by dropping faces silently: an error.
// When statements were garbled, dangling references are the visible consequence of
// that damage: the import goes on (OCC skips what it cannot resolve) and says so.
std::string check_dangling(const StepScan& st, const PrescanOptions& opt, PrescanResult& r) {
  int dangling = 0;
  std::string first;
  for (const auto& [from, to] : st.refs)
    if (!st.defined.count(to)) {
      if (dangling++ == 0)
        first = "entity #" + std::to_string(from) + " references #" + std::to_string(to) +
                ", which is not defined";
    }
  r.dangling_references = dangling;
  if (dangling > 0) {
    if (r.malformed_statements == 0 && !opt.allow_dangling_references)
      return "dangling reference: " + first;
    r.warnings.push_back(std::to_string(dangling) + " dangling references (first: " + first +
                         "); what depends on them is not imported");
  }
  return {};
}

// OCCT 7.6's STEP lexer knows the section keywords only with their ';' attached
// ("DATA;"): "DATA ;" or "ENDSEC /* c */;" fails its parse (measured on all five), although
// the standard allows the space. Such a file is refused with the line rather than passed
// on to a reader that rejects it without saying why. stmt (trimmed) ended at t[i - 1].
std::string glued_keyword_error(std::string_view t, std::size_t i, std::string_view stmt) {
  for (const std::string_view kw : {"ISO-10303-21", "HEADER", "ENDSEC", "DATA", "END-ISO-10303-21"})
    if (stmt == kw && (i < kw.size() + 1 || t.compare(i - 1 - kw.size(), kw.size(), kw) != 0))
      return "line " + std::to_string(line_at(t, i - 1)) + ": space or comment between '" +
             std::string(kw) + "' and its ';', which OpenCASCADE's STEP reader rejects (write '" +
             std::string(kw) + ";')";
  return {};
}

// The header, from the text's start: "ISO-10303-21;", the HEADER section, up to the DATA
// keyword; i ends after DATA's ';'. Comments and a byte-order mark are skipped (they are
// not content). "" or the error.
std::string scan_step_header(std::string_view t, std::size_t& i) {
  i = starts_with_bom(t) ? kUtf8Bom.size() : 0;
  std::string stmt;
  std::size_t start = i;
  Stmt st = next_statement(t, i, stmt);
  if (st == Stmt::OpenComment) return unclosed_comment(t, i);
  if (st != Stmt::Closed || trimmed(stmt) != "ISO-10303-21") {
    skip_blank(t, start);
    return "not a STEP file: line " + std::to_string(line_at(t, start)) + " begins with '" +
           line_text(t, start) + "' instead of ISO-10303-21;";
  }
  for (;;) {
    if (std::string e = glued_keyword_error(t, i, trimmed(stmt)); !e.empty()) return e;
    if (is_keyword(trimmed(stmt), "DATA")) return {};
    st = next_statement(t, i, stmt);
    if (st == Stmt::OpenComment) return unclosed_comment(t, i);
    if (st == Stmt::Eof) return "STEP file has no DATA section";
  }
}

PrescanResult scan_step(std::string_view t, const PrescanOptions& opt) {
  PrescanResult r;
  r.content = CadFormat::Step;
  auto fail = [&](std::string msg) {
    r.ok = false;
    r.error = std::move(msg);
    return r;
  };
  std::size_t i = 0;
  if (std::string e = scan_step_header(t, i); !e.empty()) return fail(e);
  StepScan st;
  std::string stmt;
  bool ended = false;
  while (i < t.size()) {
    std::size_t start = i;
    const Stmt closed = next_statement(t, i, stmt);
    if (closed == Stmt::OpenComment) return fail(unclosed_comment(t, i));
    const std::string_view s = trimmed(stmt);
    if (s.empty()) {
      if (closed == Stmt::Eof) break;
      continue;
    }
    if (closed == Stmt::Eof) {
      skip_blank(t, start);
      return fail("truncated: the file ends inside the statement of line " +
                  std::to_string(line_at(t, start)) +
                  " in the DATA section (no END-ISO-10303-21;)");
    }
    if (std::string e = glued_keyword_error(t, i, s); !e.empty()) return fail(e);
    if (s.rfind("ENDSEC", 0) == 0) continue;
    if (s.rfind("END-ISO-10303-21", 0) == 0) {
      ended = true;
      break;
    }
    if (is_keyword(s, "DATA")) continue;  // a second DATA section
    if (s[0] != '#') {
      // OCC skips a garbled statement and reports the entities it could not read; so do
      // we (OCC bug 32314's "corrupted" file has such lines and still loads).
      ++r.malformed_statements;
      if (r.warnings.size() < 5)
        r.warnings.push_back("malformed STEP statement skipped: '" + std::string(s.substr(0, 60)) +
                             "'");
      continue;
    }
    if (std::string e = scan_step_entity(s, opt, st, r); !e.empty()) return fail(e);
  }
  if (!ended)
    return fail("truncated: no END-ISO-10303-21; after the DATA section (" +
                std::to_string(r.step_entities) + " entities read)");
  if (std::string e = check_dangling(st, opt, r); !e.empty()) return fail(e);
  r.ok = true;
  return r;
}

// ---------------------------------------------------------------------------- IGES
PrescanResult scan_iges(std::string_view t, const PrescanOptions&) {
  PrescanResult r;
  r.content = CadFormat::Iges;
  int count[5] = {0, 0, 0, 0, 0};  // S G D P T
  const std::string letters = "SGDPT";
  int bad_lines = 0, lines = 0;
  std::size_t i = 0;
  while (i < t.size()) {
    std::size_t e = t.find('\n', i);
    if (e == std::string_view::npos) e = t.size();
    std::string_view line = t.substr(i, e - i);
    i = e + 1;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (line.empty()) continue;
    ++lines;
    if (line.size() < 73) {
      ++bad_lines;
      continue;
    }
    const auto k = letters.find(line[72]);
    if (k == std::string::npos) {
      ++bad_lines;
      continue;
    }
    ++count[k];
    if (line[72] == 'P') {
      // Free-format parameters in columns 1-64: numbers and Hollerith strings.
      std::string_view p = line.substr(0, std::min<std::size_t>(64, line.size()));
      std::size_t j = 0;
      while (j < p.size()) {
        while (j < p.size() && (p[j] == ',' || p[j] == ';' || p[j] == ' ')) ++j;
        std::size_t m = j;
        while (m < p.size() && p[m] != ',' && p[m] != ';' && p[m] != ' ') ++m;
        if (m > j && is_nonfinite_word(p.substr(j, m - j)))
          return r.error = "IGES parameter line " + std::to_string(lines) +
                           " has a non-finite number '" + std::string(p.substr(j, m - j)) + "'",
                 r;
        j = m;
      }
    }
  }
  if (lines == 0 || bad_lines * 10 > lines)
    return r.error = "not an IGES file: " + std::to_string(bad_lines) + " of " +
                     std::to_string(lines) +
                     " lines lack the section letter (S, G, D, P, T) in column 73",
           r;
  const char* names[5] = {"Start (S)", "Global (G)", "Directory Entry (D)", "Parameter Data (P)",
                          "Terminate (T)"};
  for (int k = 2; k < 5; ++k)
    if (count[k] == 0) return r.error = std::string("IGES ") + names[k] + " section is missing", r;
  r.ok = true;
  return r;
}

// ---------------------------------------------------------------------------- BREP
PrescanResult scan_brep(std::string_view t, const PrescanOptions&) {
  PrescanResult r;
  r.content = CadFormat::Brep;
  // Whitespace-separated tokens; numbers must be finite.
  std::size_t i = 0;
  long line = 1;
  while (i < t.size()) {
    while (i < t.size() && std::isspace(static_cast<unsigned char>(t[i]))) {
      if (t[i] == '\n') ++line;
      ++i;
    }
    std::size_t j = i;
    while (j < t.size() && !std::isspace(static_cast<unsigned char>(t[j]))) ++j;
    if (j > i) {
      const std::string_view tok = t.substr(i, j - i);
      if (is_nonfinite_word(tok))
        return r.error = "BREP line " + std::to_string(line) + " has a non-finite number '" +
                         std::string(tok) + "'",
               r;
      const char c = tok[0];
      if (std::isdigit(static_cast<unsigned char>(c)) ||
          ((c == '-' || c == '+') && tok.size() > 1)) {
        double v = 0;
        bool of = false;
        if (parse_number(tok, 0, v, of) > 0 && of)
          return r.error = "BREP line " + std::to_string(line) +
                           " has a number that overflows a double ('" + std::string(tok) + "')",
                 r;
      }
    }
    i = j;
  }
  r.ok = true;
  return r;
}

}  // namespace

std::string_view to_string(CadFormat f) {
  switch (f) {
    case CadFormat::Step:
      return "step";
    case CadFormat::Iges:
      return "iges";
    case CadFormat::Brep:
      return "brep";
    default:
      return "unknown";
  }
}

CadFormat format_from_extension(const std::string& path) {
  const auto dot = path.find_last_of('.');
  const auto slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash))
    return CadFormat::Unknown;
  const std::string ext = lower(path.substr(dot + 1));
  if (ext == "step" || ext == "stp" || ext == "p21") return CadFormat::Step;
  if (ext == "igs" || ext == "iges") return CadFormat::Iges;
  if (ext == "brep" || ext == "brp" || ext == "rle") return CadFormat::Brep;
  return CadFormat::Unknown;
}

CadFormat sniff_format(std::string_view head) {
  // STEP: the header keyword after a byte-order mark, blank lines and comments.
  std::size_t i = 0;
  const std::string_view text = without_bom(head);
  if (skip_blank(text, i) && text.compare(i, 12, "ISO-10303-21") == 0) return CadFormat::Step;
  head = head.substr(0, std::min<std::size_t>(head.size(), 4096));
  if (head.find("CASCADE Topology V") != std::string_view::npos) return CadFormat::Brep;
  // IGES: a first line of (at least) 73 columns with a section letter in column 73. The
  // records are fixed-column ASCII: no byte-order mark, no leading blank line (either
  // shifts the columns); the line end (LF or CRLF) is not part of a record.
  std::size_t e = head.find('\n');
  std::string_view l = head.substr(0, e == std::string_view::npos ? head.size() : e);
  if (!l.empty() && l.back() == '\r') l.remove_suffix(1);
  if (l.size() >= 73 && (l[72] == 'S' || l[72] == 'G') &&
      std::all_of(l.begin(), l.end(), [](unsigned char c) { return c >= 32 && c < 127; }))
    return CadFormat::Iges;
  return CadFormat::Unknown;
}

PrescanResult prescan_text(std::string_view text, CadFormat fmt, const PrescanOptions& opt) {
  switch (fmt) {
    case CadFormat::Step:
      return scan_step(text, opt);
    case CadFormat::Iges:
      return scan_iges(text, opt);
    case CadFormat::Brep:
      return scan_brep(text, opt);
    default: {
      PrescanResult r;
      r.error = "unknown format";
      return r;
    }
  }
}

namespace {

// Why text of no known format was refused: a leading comment that never closes or is
// followed by something other than a STEP header, a byte-order mark before IGES records,
// or neither header at all.
std::string unknown_format_reason(std::string_view text) {
  const std::string_view body = without_bom(text);
  std::size_t i = 0;
  const bool closed = skip_blank(body, i);
  if (i == body.size())
    return starts_with_bom(text) ? "the file is empty: it holds only a UTF-8 byte-order mark"
                                 : "the file is empty: it holds only whitespace";
  if (!closed) return unclosed_comment(body, i);
  if (i > 0 && body.find("/*") < i)
    return "not a CAD file: after the leading comment, line " + std::to_string(line_at(body, i)) +
           " begins with '" + line_text(body, i) + "' instead of the STEP header ISO-10303-21;";
  if (starts_with_bom(text) && sniff_format(body) == CadFormat::Iges)
    return "an IGES file must not begin with a UTF-8 byte-order mark: its records are "
           "fixed-column ASCII (remove the first 3 bytes)";
  const bool binary = std::any_of(
      text.begin(), text.begin() + std::min<std::size_t>(text.size(), 4096), [](unsigned char c) {
        return c == 0 || (c < 32 && c != '\n' && c != '\r' && c != '\t') || c >= 127;
      });
  return std::string("not a CAD file") + (binary ? " (binary content)" : "") +
         ": neither a STEP header (ISO-10303-21;), an IGES start line (80 columns, "
         "section letter in column 73) nor an OpenCASCADE BREP header (CASCADE Topology)";
}

}  // namespace

PrescanResult prescan_file(const std::string& path, const PrescanOptions& opt) {
  PrescanResult r;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    r.error = "cannot open the file";
    return r;
  }
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.empty()) {
    r.error = "the file is empty (0 bytes)";
    return r;
  }
  const CadFormat fmt = sniff_format(text);
  if (fmt == CadFormat::Unknown) {
    r.error = unknown_format_reason(text);
    return r;
  }
  r = prescan_text(text, fmt, opt);
  r.content = fmt;
  r.utf8_bom = starts_with_bom(text);
  return r;
}

}  // namespace uvmesh::io
