// Output flags of `uvmesh mesh`: format and encoding overrides, Draco settings.
#pragma once

#include <CLI/CLI.hpp>
#include <string>

#include "uvmesh/io/mesh_writer.h"

namespace uvmesh::cli {

struct WriteFlags {
  std::string format;  ///< short name, "" = from the extension
  bool ascii = false, binary = false;
  bool no_physical = false;
  int draco_bits = 14, draco_level = 7;
  bool glb_per_face = false;
};

inline void add_write_flags(CLI::App* cmd, WriteFlags& f) {
  cmd->add_option("--format", f.format,
                  "output format instead of the extension's (" + io::known_format_names() + ")")
      ->check(CLI::Validator(
          [](std::string& s) {
            return io::format_from_name(s)
                       ? std::string()
                       : "unknown format '" + s + "' (known: " + io::known_format_names() + ")";
          },
          "FORMAT"));
  auto* a =
      cmd->add_flag("--ascii", f.ascii, "ASCII form of a format that has both (.stl, .ply, .vtu)");
  cmd->add_flag("--binary", f.binary, "binary form of a format that has both (.msh 4.1, .vtk)")
      ->excludes(a);
  cmd->add_flag("--no-physical", f.no_physical,
                ".msh: no physical groups (per solid, per named face)");
  cmd->add_option("--draco-bits", f.draco_bits,
                  ".drc/.glb: position quantization bits (default 14)")
      ->check(CLI::Range(1, 30));
  cmd->add_option("--draco-level", f.draco_level,
                  ".drc/.glb: compression level 0..10 (default 7; 10 smallest)")
      ->check(CLI::Range(0, 10));
  cmd->add_flag("--glb-per-face", f.glb_per_face,
                ".glb: one glTF mesh per CAD face (default: one per solid)");
}

inline io::WriteOptions write_options(const WriteFlags& f) {
  io::WriteOptions o;
  if (!f.format.empty()) o.format = io::format_from_name(f.format);
  o.encoding = f.ascii    ? io::Encoding::Ascii
               : f.binary ? io::Encoding::Binary
                          : io::Encoding::Default;
  o.physical_groups = !f.no_physical;
  o.draco_bits = f.draco_bits;
  o.draco_level = f.draco_level;
  o.glb_groups = f.glb_per_face ? io::GlbGroups::Face : io::GlbGroups::Solid;
  return o;
}

}  // namespace uvmesh::cli
