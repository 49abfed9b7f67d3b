// Model-reading flags shared by the `info` and `mesh` subcommands.
#pragma once

#include <CLI/CLI.hpp>
#include <cmath>
#include <string>

#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/units.h"

namespace uvmesh::cli {

// A size or tolerance: finite and > 0. CLI::PositiveNumber lets NaN through (every
// comparison with it is false) and prints DBL_MAX in full when it rejects a value.
inline CLI::Validator finite_positive() {
  return CLI::Validator(
      [](std::string& s) {
        double v = 0;
        std::size_t used = 0;
        try {
          v = std::stod(s, &used);
        } catch (...) {
          used = 0;
        }
        return used == s.size() && std::isfinite(v) && v > 0
                   ? std::string()
                   : "expected a finite number > 0, found '" + s + "'";
      },
      "X>0");
}

struct ReadFlags {
  std::string model;
  bool no_heal = false;
  bool conform = false;
  bool any_extension = false;
  bool partial = false;
  bool no_check = false;
  double sew_rel_tol = 1e-6;
  double sew_max_rel_tol = 1e-4;
  std::string units;  // "" = the file's own unit
};

inline void add_read_flags(CLI::App* cmd, ReadFlags& f) {
  cmd->add_option("MODEL", f.model,
                  "STEP (.step/.stp), IGES (.igs/.iges) or BREP (.brep) file; `mesh` also takes an "
                  "OBJ subdivision cage (.obj)")
      ->required();
  cmd->add_flag("--no-heal", f.no_heal, "use the model exactly as read (no ShapeFix, no sewing)");
  if (cmd->get_name() == "mesh") {
    // Meshing an assembly of touching solids without imprinting them gives two different
    // triangulations of every interface (intersecting, and rejected by volume meshers as
    // duplicated facets): `mesh` makes models with two or more solids conforming unless
    // told not to. `info` describes the file as it is.
    f.conform = true;
    cmd->add_flag(
        "--conform,!--no-conform", f.conform,
        "make an assembly of two or more solids conforming: touching solids are imprinted "
        "(general fuse); default on for `mesh`, --no-conform keeps the solids as they are");
  } else {
    cmd->add_flag("--conform", f.conform,
                  "make an assembly conforming: touching solids are imprinted (general fuse)");
  }
  cmd->add_flag("--any-extension", f.any_extension, "read by content when the extension disagrees");
  cmd->add_flag("--no-check", f.no_check,
                "skip OCC's per-face validity check (BRepCheck), the slowest part of a load");
  cmd->add_flag("--partial", f.partial,
                "import what can be resolved from a STEP file with dangling references");
  cmd->add_option("--sew-tol", f.sew_rel_tol,
                  "sewing tolerance relative to the bounding-box diagonal")
      ->check(finite_positive());
  cmd->add_option("--sew-max-tol", f.sew_max_rel_tol,
                  "while free edges remain, sewing is retried at tenfold tolerances up to this one "
                  "(relative to the diagonal; at most a tenth of the shortest edge); default 1e-4, "
                  "equal to --sew-tol to sew once")
      ->check(finite_positive());
  cmd->add_option("--units", f.units,
                  "convert coordinates to this length unit (" + uvmesh::io::known_length_units() +
                      "); default: keep the unit the file declares (BREP files have none)")
      ->check(CLI::Validator(
          [](std::string& s) {
            return uvmesh::io::canonical_length_unit(s).empty()
                       ? "unknown length unit '" + s +
                             "' (known: " + uvmesh::io::known_length_units() + ")"
                       : std::string();
          },
          "UNIT"));
}

inline uvmesh::io::ReadOptions read_options(const ReadFlags& f) {
  uvmesh::io::ReadOptions o;
  o.heal = !f.no_heal;
  o.conform = f.conform;
  o.trust_content = f.any_extension;
  o.sew_rel_tol = f.sew_rel_tol;
  o.sew_max_rel_tol = f.sew_max_rel_tol;
  o.allow_partial = f.partial;
  o.check_validity = !f.no_check;
  o.units = f.units;
  return o;
}

}  // namespace uvmesh::cli
