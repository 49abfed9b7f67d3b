// uvmesh::cli2d -- small text helpers shared by the 2D readers and writers (internal to the
// uvmesh_cli2d library, but public so that fuzzers can reach them).
//
// Numbers are parsed with std::from_chars (locale independent, no exceptions, exact
// round trip) and written with std::to_chars (shortest representation that reads back to
// the same double), so that writing then reading a mesh is bit-exact.
#pragma once

#include <cstdint>
#include <istream>
#include <optional>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

namespace uvmesh::cli2d::text {

// Writers build their text in a string buffer and write it out in chunks of about
// kFlushBytes; flush_buffer writes and clears b when it is that full, or always if force.
inline constexpr std::size_t kFlushBytes = (1u << 20) - 512;
inline void flush_buffer(std::ostream& out, std::string& b, bool force) {
  if (force || b.size() > kFlushBytes) {
    out.write(b.data(), static_cast<std::streamsize>(b.size()));
    b.clear();
  }
}

// A whole-token integer: optional sign, decimal digits. nullopt for anything else
// ("1.0", "3x", "", out of range for int64).
std::optional<std::int64_t> parse_int(std::string_view s);

// A whole-token real number: decimal or scientific, optional sign; "inf" and "nan" are
// parsed (callers reject them with a message that says so). nullopt for anything else.
std::optional<double> parse_double(std::string_view s);

// Line-oriented reader for formats where one record is one line (Triangle's .poly and
// .node): strips '#' comments (anywhere on a line) and skips blank lines.
class LineReader {
 public:
  explicit LineReader(std::istream& in) : in_(in) {}
  // Next line with content, split at white space (space, tab, CR). Returns
  // false at end of input. line() is the 1-based number of the line returned.
  bool next(std::vector<std::string_view>& fields);
  int line() const { return line_; }

 private:
  std::istream& in_;
  std::string buf_;
  int line_ = 0;
};

// Token reader for free-form formats (Medit .mesh / .sol): white-space separated tokens,
// '#' comments to the end of the line, each token with the line it came from.
class TokenReader {
 public:
  explicit TokenReader(std::istream& in) : in_(in) {}
  // Next token, or false at end of input. line() is the line of the token returned (or
  // of the last line read at end of input).
  bool next(std::string& token);
  int line() const { return line_; }

 private:
  bool fill();
  std::istream& in_;
  std::string buf_;
  std::size_t pos_ = 0;
  int line_ = 0;
  bool have_line_ = false;
};

// Appends the shortest decimal form of v that reads back to v exactly.
void append_double(std::string& out, double v);
// Appends v with a fixed number of decimals (for pictures, where exactness is not needed).
void append_fixed(std::string& out, double v, int decimals);
void append_int(std::string& out, std::int64_t v);

// Lower-case extension with its dot (".mesh"), or "" when the file name has none.
std::string extension(std::string_view path);

// A field as shown in a message, quoted: at most 40 bytes, control and non-ASCII bytes
// as \xNN, so that a binary file gives one readable line, not raw bytes on a terminal.
std::string quoted(std::string_view s);

}  // namespace uvmesh::cli2d::text
