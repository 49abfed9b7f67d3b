// Tests that hold for every field-point method (Options::field_points) run in each: a
// Catch2 generator over the methods, and their names for the failure messages.
#pragma once

#include <catch2/catch.hpp>

#include "uvmesh/mesher2d/mesher2d.h"

// Runs the enclosing test case (or section) once per method.
#define FIELD_POINT_METHOD \
  GENERATE(::uvmesh::m2d::FieldPointMethod::Saturation, ::uvmesh::m2d::FieldPointMethod::Frontal)

inline const char* method_name(uvmesh::m2d::FieldPointMethod m) {
  return m == uvmesh::m2d::FieldPointMethod::Frontal ? "frontal" : "saturation";
}

// Default options with the given method.
inline uvmesh::m2d::Options method_options(uvmesh::m2d::FieldPointMethod m) {
  uvmesh::m2d::Options o;
  o.field_points = m;
  return o;
}
