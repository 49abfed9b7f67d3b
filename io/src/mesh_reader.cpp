// Mesh readers (mesh_reader.h). The whole file is read into memory and parsed by two
// cursors (mesh_parse.h) that throw ParseError, caught once in read_mesh_data and turned
// into "<path>: <where>: <problem>"; nothing else in uvmesh::io throws. The formats:
// Gmsh (mesh_reader_gmsh.cpp), Medit, STL, OBJ, PLY (mesh_reader_formats.cpp), Draco
// (draco_io.cpp).
#include "uvmesh/io/mesh_reader.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <new>
#include <string>

#include "draco_io.h"
#include "mesh_parse.h"

namespace uvmesh::io {

namespace {

using namespace detail;

// ----------------------------------------------------------------------------- Draco

void read_drc(const std::string& data, MeshReadResult& r) {
  bool face_ids = false;
  if (std::string why = detail::decode_drc(data.data(), data.size(), r.mesh, face_ids);
      !why.empty())
    fail(why);
  r.binary = true;
  r.has_face_ids = face_ids;
  classify_from_elements(r.mesh, {});
}

bool readable(MeshFormat f) {
  return f == MeshFormat::Msh41 || f == MeshFormat::Msh22 || f == MeshFormat::Medit ||
         f == MeshFormat::Meshb || f == MeshFormat::Stl || f == MeshFormat::Obj ||
         f == MeshFormat::Ply || f == MeshFormat::Drc;
}

}  // namespace

std::string readable_mesh_extensions() {
  return ".msh, .mesh, .meshb, .stl, .obj, .ply, .drc";
}

MeshReadResult read_mesh(const std::string& path, const MeshReadOptions& opts) {
  MeshReadResult r;
  const std::optional<MeshFormat> fmt = opts.format ? opts.format : format_from_path(path);
  if (!fmt || !readable(*fmt)) {
    r.error = path + ": not a mesh format read here (known: " + readable_mesh_extensions() + ")";
    return r;
  }
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    r.error = path + ": is a directory";
    return r;
  }
  std::string data;
  {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
      r.error = path + ": cannot open: " + std::strerror(errno);
      return r;
    }
    // One read of the whole file (meshes reach hundreds of MB; a character iterator is
    // several times slower).
    in.seekg(0, std::ios::end);
    const std::streamoff size = in.tellg();
    in.seekg(0, std::ios::beg);
    if (size > 0) {
      data.resize(static_cast<std::size_t>(size));
      in.read(data.data(), size);
    }
    if (in.bad() || (size > 0 && in.gcount() != size)) {
      r.error = path + ": read error";
      return r;
    }
  }
  return read_mesh_data(data, *fmt, path);
}

MeshReadResult read_mesh_data(const std::string& data, MeshFormat format, const std::string& path) {
  MeshReadResult r;
  if (!readable(format)) {
    r.error = path + ": not a mesh format read here (known: " + readable_mesh_extensions() + ")";
    return r;
  }
  if (data.empty()) {
    r.error = path + ": the file is empty";
    return r;
  }
  r.format = format;
  try {
    switch (format) {
      case MeshFormat::Msh41:
      case MeshFormat::Msh22:
        read_msh(data, r);
        break;
      case MeshFormat::Medit:
        read_medit_ascii(data, r);
        break;
      case MeshFormat::Meshb:
        read_meshb(data, r);
        break;
      case MeshFormat::Stl:
        read_stl(data, r);
        break;
      case MeshFormat::Obj:
        read_obj(data, r);
        break;
      case MeshFormat::Ply:
        read_ply(data, r);
        break;
      case MeshFormat::Drc:
        read_drc(data, r);
        break;
      default:
        break;
    }
  } catch (const ParseError& e) {
    r = MeshReadResult{};
    r.error = path + ": " + e.what;
    return r;
  } catch (const std::bad_alloc&) {
    r = MeshReadResult{};
    r.error = path + ": out of memory while reading (corrupt counts?)";
    return r;
  }
  if (r.mesh.triangles.empty()) {
    r = MeshReadResult{};
    r.error = path + ": no triangles in the file";
    return r;
  }
  if (r.skipped_elements > 0)
    r.warnings.push_back(std::to_string(r.skipped_elements) +
                         " elements other than points, lines and triangles were skipped");
  r.ok = true;
  return r;
}

}  // namespace uvmesh::io
