// Regression tests of the PLY reader for bugs the mesh-reader fuzzer (tests/fuzz) found.
// Names start with "robust:" (`ctest -R robust`).
#include <catch2/catch.hpp>
#include <sstream>
#include <string>

#include "uvmesh/io/mesh_reader.h"

TEST_CASE(
    "robust: a PLY face_id beyond int's range is an error, not undefined behaviour (fuzz_mesh_ply)",
    "[robust][io]") {
  // The double was cast to int unchecked (UBSan: "2.00001e+24 is outside the range of
  // representable values of type 'int'").
  const std::string head =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty "
      "double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nproperty double "
      "face_id\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n";
  for (const char* id : {"2e24", "-3", "1.5", "nan"}) {
    INFO(id);
    const auto r = uvmesh::io::read_mesh_data(head + "3 0 1 2 " + id + "\n",
                                              uvmesh::io::MeshFormat::Ply, "f.ply");
    CHECK_FALSE(r.ok);
    CHECK_THAT(r.error, Catch::StartsWith("f.ply: line 14: "));
  }
  const auto ok =
      uvmesh::io::read_mesh_data(head + "3 0 1 2 7\n", uvmesh::io::MeshFormat::Ply, "f.ply");
  REQUIRE(ok.ok);
  CHECK(ok.mesh.triangle_face == std::vector<uvmesh::geom::Id>{7});
}

TEST_CASE(
    "robust: a PLY vertex index beyond long long's range is reported without a cast "
    "(fuzz_mesh_ply)",
    "[robust][io]") {
  // The message cast the double index to long long (UBSan: "8.88889e+19 is outside the
  // range of representable values of type 'long long'").
  const std::string ply =
      "ply\nformat ascii 1.0\nelement vertex 3\nproperty double x\nproperty double y\nproperty "
      "double z\n"
      "element face 1\nproperty list uchar double vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 8.88889e19\n";
  const auto r = uvmesh::io::read_mesh_data(ply, uvmesh::io::MeshFormat::Ply, "f.ply");
  CHECK_FALSE(r.ok);
  CHECK(r.error == "f.ply: line 13: vertex index 8.88889e+19 out of range");
}

TEST_CASE(
    "robust: a PLY element without properties is skipped, not looped over (fuzz_mesh_ply timeout)",
    "[robust][io]") {
  // "element x 1144441892" with no properties: the reader looped a billion times reading
  // nothing (a 10 s libFuzzer timeout). Such an element holds no data; a vertex or face
  // element without properties is an error (it pushed one point per entry).
  const std::string tail =
      "element vertex 3\nproperty double x\nproperty double y\nproperty double z\n"
      "element face 1\nproperty list uchar int vertex_indices\nend_header\n"
      "0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n";
  const auto r = uvmesh::io::read_mesh_data("ply\nformat ascii 1.0\nelement x 2147483647\n" + tail,
                                            uvmesh::io::MeshFormat::Ply, "f.ply");
  INFO(r.error);
  REQUIRE(r.ok);
  CHECK(r.mesh.points.size() == 3);
  CHECK(r.mesh.triangles.size() == 1);
  const auto v = uvmesh::io::read_mesh_data(
      "ply\nformat ascii 1.0\nelement vertex 2147483647\nelement face 0\nend_header\n",
      uvmesh::io::MeshFormat::Ply, "f.ply");
  CHECK_FALSE(v.ok);
  CHECK(v.error == "f.ply: line 6: element 'vertex' has 2147483647 entries but no properties");
}
