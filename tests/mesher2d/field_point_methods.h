// Tests that hold for every field-point method (Options::field_points) run in each: a
// Catch2 generator over the methods, and their names for the failure messages.
#pragma once

#include <catch2/catch.hpp>
#include <string>

#include "uvmesh/mesher2d/check.h"
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

// The mesh of in, required Ok and accepted by the checker (refined: not Delaunay).
inline uvmesh::m2d::Result mesh_valid(const uvmesh::m2d::Pslg& in, const uvmesh::m2d::SizeSpec& s,
                                      const uvmesh::m2d::Options& o) {
  uvmesh::m2d::Result r = uvmesh::m2d::mesh(in, s, o);
  INFO("status: " << r.status.message);
  REQUIRE(r.ok());
  const uvmesh::m2d::CheckReport rep = uvmesh::m2d::check(r.mesh, in, {.delaunay = false});
  INFO((rep.ok() ? std::string() : rep.errors.front()));
  REQUIRE(rep.ok());
  return r;
}

// The two meshes are the same, bit for bit (vertices, then triangles).
inline void require_same_mesh(const uvmesh::m2d::Mesh& a, const uvmesh::m2d::Mesh& b) {
  REQUIRE(a.vertices.size() == b.vertices.size());
  REQUIRE(a.triangles == b.triangles);
  bool same = true;
  for (std::size_t v = 0; v < a.vertices.size(); ++v)
    same = same && a.vertices[v].x == b.vertices[v].x && a.vertices[v].y == b.vertices[v].y;
  CHECK(same);
}
