// Length-unit names and factors (io/units.h; no OCC).
#include <catch2/catch.hpp>

#include "uvmesh/io/units.h"

using namespace uvmesh::io;

TEST_CASE("units: STEP, IGES and command-line spellings map to one canonical name", "[io][units]") {
  CHECK(canonical_length_unit("millimetre") == "mm");
  CHECK(canonical_length_unit("MILLIMETRE") == "mm");
  CHECK(canonical_length_unit("centimetre") == "cm");
  CHECK(canonical_length_unit("metre") == "m");
  CHECK(canonical_length_unit("meter") == "m");
  CHECK(canonical_length_unit("INCH") == "inch");
  CHECK(canonical_length_unit("IN") == "inch");
  CHECK(canonical_length_unit("'inches'") == "inch");
  CHECK(canonical_length_unit("FOOT") == "ft");
  CHECK(canonical_length_unit("UIN") == "uin");
  CHECK(canonical_length_unit("micro metre") == "um");
  CHECK(canonical_length_unit("KM") == "km");
  CHECK(canonical_length_unit("furlong").empty());
  CHECK(canonical_length_unit("").empty());
}

TEST_CASE("units: factors are the exact definitions", "[io][units]") {
  CHECK(length_unit_mm("mm") == 1.0);
  CHECK(length_unit_mm("cm") == 10.0);
  CHECK(length_unit_mm("m") == 1000.0);
  CHECK(length_unit_mm("inch") == 25.4);
  CHECK(length_unit_mm("ft") == 304.8);
  CHECK(length_unit_mm("mil") == 0.0254);
  CHECK(length_unit_mm("mi") == 1609344.0);
  CHECK(length_unit_m("cm") == 0.01);
  CHECK(length_unit_m("km") == 1000.0);
  CHECK(length_unit_mm("furlong") == 0.0);
  CHECK(known_length_units().find("inch") != std::string::npos);
}
