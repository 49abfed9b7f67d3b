// Length units of CAD files: names and factors.
#include "uvmesh/io/units.h"

#include <array>
#include <cctype>

namespace uvmesh::io {
namespace {

struct UnitDef {
  const char* name;
  double mm;  // millimetres per unit (exact decimal definitions: 1 inch = 25.4 mm)
  std::array<const char*, 6> aliases;
};

// Same factors as OCC's UnitsMethods (IGES unit flags 1..11) plus the decimetre (a STEP SI
// prefix). Aliases are compared after lower-casing and dropping ' ', '.', '_', '-'.
constexpr std::array<UnitDef, 11> kUnits{{
    {"um", 0.001, {"micrometre", "micrometer", "micron", "microns", "um", ""}},
    {"mm", 1.0, {"millimetre", "millimeter", "millimetres", "millimeters", "mm", ""}},
    {"cm", 10.0, {"centimetre", "centimeter", "centimetres", "centimeters", "cm", ""}},
    {"dm", 100.0, {"decimetre", "decimeter", "dm", "", "", ""}},
    {"m", 1000.0, {"metre", "meter", "metres", "meters", "m", ""}},
    {"km", 1.0e6, {"kilometre", "kilometer", "kilometres", "kilometers", "km", ""}},
    {"uin", 0.0000254, {"microinch", "microinches", "uin", "", "", ""}},
    {"mil", 0.0254, {"mil", "mils", "thou", "", "", ""}},
    {"inch", 25.4, {"inch", "inches", "in", "", "", ""}},
    {"ft", 304.8, {"foot", "feet", "ft", "", "", ""}},
    {"mi", 1609344.0, {"mile", "miles", "mi", "", "", ""}},
}};

std::string normalise(std::string_view s) {
  std::string out;
  for (const char c : s) {
    if (c == ' ' || c == '.' || c == '_' || c == '-' || c == '\'' || c == '"') continue;
    out.push_back(static_cast<char>(std::tolower(static_cast<unsigned char>(c))));
  }
  return out;
}

const UnitDef* find(std::string_view name) {
  const std::string n = normalise(name);
  if (n.empty()) return nullptr;
  for (const UnitDef& u : kUnits) {
    if (n == u.name) return &u;
    for (const char* a : u.aliases)
      if (*a && n == a) return &u;
  }
  return nullptr;
}

}  // namespace

std::string canonical_length_unit(std::string_view name) {
  const UnitDef* u = find(name);
  return u ? u->name : "";
}

double length_unit_mm(std::string_view name) {
  const UnitDef* u = find(name);
  return u ? u->mm : 0.0;
}

double length_unit_m(std::string_view name) {
  const UnitDef* u = find(name);
  return u ? u->mm / 1000.0 : 0.0;
}

std::string known_length_units() {
  std::string s;
  for (const UnitDef& u : kUnits) {
    if (!s.empty()) s += ", ";
    s += u.name;
  }
  return s;
}

}  // namespace uvmesh::io
