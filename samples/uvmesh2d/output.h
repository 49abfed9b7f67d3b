// uvmesh::cli2d -- output files that appear only when complete.
//
// Usage:
//   std::optional<uvmesh::cli2d::OutputFormat> f = uvmesh::cli2d::output_format("out.msh");
//   uvmesh::cli2d::PendingOutput o;
//   if (auto e = o.open("out.msh")) ...;      // creates "out.msh.tmp-<pid>-<n>" beside it
//   write_gmsh22(o.stream(), mesh, refs);
//   if (auto e = o.commit()) ...;              // flush, check, rename over out.msh
//   // destroyed without commit (error path): the temporary is removed, out.msh untouched
//
// The temporary lives in the destination's directory so that the final rename is atomic
// (same file system) and so that an unwritable directory is detected by open(), before
// any meshing work is done.
#pragma once

#include <fstream>
#include <optional>
#include <string>

#include "uvmesh2d/diagnostic.h"

namespace uvmesh::cli2d {

enum class OutputFormat { Medit, Gmsh22, Svg };

// From the file extension (case-insensitive): .mesh, .msh, .svg; nullopt otherwise.
std::optional<OutputFormat> output_format(const std::string& path);
inline constexpr const char* kOutputExtensions = ".mesh (Medit), .msh (Gmsh 2.2), .svg (picture)";

class PendingOutput {
 public:
  PendingOutput() = default;
  PendingOutput(const PendingOutput&) = delete;
  PendingOutput& operator=(const PendingOutput&) = delete;
  PendingOutput(PendingOutput&& o) noexcept;
  PendingOutput& operator=(PendingOutput&&) = delete;
  ~PendingOutput();

  // Fails when the destination is a directory or its directory cannot be written.
  std::optional<Diagnostic> open(const std::string& dest);
  std::ostream& stream() { return out_; }
  // Flushes and closes the temporary and renames it to the destination.
  std::optional<Diagnostic> commit();
  // Removes the temporary (no-op after commit).
  void discard();
  // Removes the destination after a successful commit (used to undo a partial set of
  // outputs when a later one fails).
  void undo_commit();
  const std::string& destination() const { return dest_; }
  const std::string& temporary() const { return tmp_; }

 private:
  std::string dest_, tmp_;
  std::ofstream out_;
  bool committed_ = false;
};

}  // namespace uvmesh::cli2d
