// Text pre-scan of CAD files, before OpenCASCADE sees them (no OCC here). Detects the
// format from the content, and rejects what crashes, hangs or silently corrupts an OCC
// import: empty or truncated files, binary garbage, NaN / infinite / huge coordinates,
// STEP references to undefined entities, IGES files missing a section. STEP text may
// carry what ISO 10303-21 treats as whitespace (comments anywhere, blank lines, CRLF line
// ends) and a UTF-8 byte-order mark; IGES records are fixed-column (CRLF ends accepted).
//
//   io::PrescanResult p = io::prescan_file("part.stp", {});
//   if (!p.ok) std::cerr << p.error;      // e.g. "entity #14 references undefined #999999"
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace uvmesh::io {

enum class CadFormat { Unknown, Step, Iges, Brep };
std::string_view to_string(CadFormat f);

/// Format from the file name's extension (case-insensitive).
CadFormat format_from_extension(const std::string& path);
/// Format from the first bytes of the content.
CadFormat sniff_format(std::string_view head);

struct PrescanOptions {
  double max_abs_coordinate = 1e12;  ///< see ReadOptions::max_abs_coordinate
  /// Dangling STEP references are an error in a file whose statements all parse (the file
  /// is inconsistent); true = import what can be resolved, with a warning. In a file with
  /// garbled statements they are always warnings (the damage is already visible).
  bool allow_dangling_references = false;
};

struct PrescanResult {
  bool ok = false;
  std::string error;  ///< without the file name
  CadFormat content = CadFormat::Unknown;
  int step_entities = 0;
  int step_brep_faces = 0;         ///< ADVANCED_FACE / FACE_SURFACE instances
  int step_tessellated_faces = 0;  ///< (COMPLEX_)TRIANGULATED_FACE / TESSELLATED_* instances
  int malformed_statements = 0;    ///< STEP statements that are not '#id = ...' (skipped)
  int dangling_references = 0;     ///< references to entities defined nowhere
  /// The file begins with a UTF-8 byte-order mark (prescan_file; skipped by the scan, and
  /// by read_cad before OCC, whose STEP reader rejects it).
  bool utf8_bom = false;
  std::vector<std::string> warnings;
};

/// Scans text already in memory (the file's content) of the given format.
PrescanResult prescan_text(std::string_view text, CadFormat fmt, const PrescanOptions& opt);
/// Reads the file, sniffs its format and scans it. `error` is set for unreadable files.
PrescanResult prescan_file(const std::string& path, const PrescanOptions& opt);

}  // namespace uvmesh::io
