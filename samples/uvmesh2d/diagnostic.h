// uvmesh::cli2d -- diagnostics returned by the 2D readers and writers.
//
// Library code never prints: a reader returns a Diagnostic naming the file and the line
// (1-based; 0 when the problem is not tied to a line) and main() decides what to do.
//
// Usage:
//   uvmesh::cli2d::PolyRead r = uvmesh::cli2d::read_poly("in.poly");
//   if (!r.ok()) std::cerr << r.error->str() << '\n';   // "in.poly:12: segment 3 ..."
#pragma once

#include <string>

namespace uvmesh::cli2d {

struct Diagnostic {
  std::string file;     // as given by the caller (not made absolute)
  int line = 0;         // 1-based; 0 = the whole file (or no file at all)
  std::string message;  // one sentence, no trailing period, no file/line prefix

  // "file:line: message", "file: message" or "message": the compiler convention, so that
  // editors and CI logs can jump to the line.
  std::string str() const {
    std::string s;
    if (!file.empty()) {
      s += file;
      if (line > 0) s += ':' + std::to_string(line);
      s += ": ";
    }
    return s + message;
  }
};

}  // namespace uvmesh::cli2d
