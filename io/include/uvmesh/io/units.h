// Length units of CAD files (plain C++, no OpenCASCADE).
//
//   io::canonical_length_unit("CENTIMETRE")  -> "cm"     (STEP, IGES and command-line spellings)
//   io::canonical_length_unit("furlong")     -> ""       (unknown)
//   io::length_unit_mm("inch")               -> 25.4     (millimetres per unit; 0 when unknown)
//   io::length_unit_m("cm")                  -> 0.01     (metres per unit; 0 when unknown)
//
// Canonical names: "um", "mm", "cm", "dm", "m", "km", "uin", "mil", "inch", "ft", "mi" --
// the units of IGES' unit flag and of STEP's SI prefixes / usual conversion-based units.
#pragma once

#include <string>
#include <string_view>

namespace uvmesh::io {

/// Canonical name of a length unit spelled as in a STEP file ("millimetre", "INCH", "metre"),
/// an IGES global section ("IN", "MM", "UIN") or on a command line ("mm", "inches", "meter").
/// Case, spaces, dots and underscores are ignored. "" when the name is not a known unit.
std::string canonical_length_unit(std::string_view name);

/// Millimetres per unit of a unit name (any spelling canonical_length_unit accepts); 0 when
/// unknown.
double length_unit_mm(std::string_view name);

/// Metres per unit; 0 when unknown.
double length_unit_m(std::string_view name);

/// The canonical names, for help texts: "um, mm, cm, dm, m, km, uin, mil, inch, ft, mi".
std::string known_length_units();

}  // namespace uvmesh::io
