// Draco encoding and decoding for the mesh writer and reader (draco_io.cpp, the only
// translation unit that includes Draco's headers). Internal to uvmesh::io.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/surface/surface_mesh.h"

namespace uvmesh::io::detail {

/// .drc bytes of `m` (positions, normals, generic attribute "face_id"); "" or the reason.
std::string encode_drc(const surface::SurfaceMesh& m, const WriteOptions& opts,
                       std::vector<char>& bytes);

/// .glb bytes: glTF 2.0 binary with KHR_draco_mesh_compression, one mesh per solid (faces
/// outside every solid form one more mesh) or per face; "" or the reason.
std::string encode_glb(const surface::SurfaceMesh& m, const geom::Model* model,
                       const WriteOptions& opts, std::vector<char>& bytes);

/// Decodes a .drc file's bytes. Points at identical decoded positions are merged (the
/// writer splits vertices between faces; quantization maps the copies to one value).
/// triangle_face from the "face_id" attribute when present (else 0). "" or the reason.
/// The bytes are decoded in a child process first (Draco's decoder can crash on corrupt
/// data), so a corrupt file is an error here, never a crash of the caller.
std::string decode_drc(const char* data, std::size_t size, surface::SurfaceMesh& m,
                       bool& has_face_ids);

}  // namespace uvmesh::io::detail
