// Writers for the whole-model surface mesh: write_mesh validates the mesh, checks the
// format's limits, and writes into a temporary file beside the target that is renamed
// over it once complete. The formats: Gmsh (mesh_writer_gmsh.cpp), Medit, TetGen, PLY,
// STL, OBJ, VTK (mesh_writer_formats.cpp), Draco (draco_io.cpp).
#include "uvmesh/io/mesh_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <limits>
#include <string>
#include <system_error>
#include <vector>

#include "draco_io.h"
#include "mesh_formats.h"

namespace uvmesh::io {

bool carries_tetrahedra(MeshFormat f) {
  return f == MeshFormat::Msh41 || f == MeshFormat::Msh22 || f == MeshFormat::Medit ||
         f == MeshFormat::Vtu;
}

namespace {

using namespace detail;
using surface::NodeId;
using surface::SurfaceMesh;

// The temporary file beside the target: created exclusively (a unique name per process
// and call, O_EXCL turns a clash into a retry rather than a clobber), renamed over the
// target by commit(), removed by the destructor otherwise. Being in the same directory
// keeps the rename on one file system, where it is atomic (POSIX rename(2)).
class TempFile {
 public:
  ~TempFile() {
    if (fd_ >= 0) ::close(fd_);
    if (!tmp_.empty()) ::unlink(tmp_.c_str());
  }

  // Returns "" or the reason the file could not be created.
  std::string open(const std::string& dest) {
    static std::atomic<unsigned> counter{0};
    for (int attempt = 0; attempt < 100; ++attempt) {
      std::string tmp =
          dest + ".tmp-" + std::to_string(::getpid()) + "-" + std::to_string(counter.fetch_add(1));
      // 0666: the umask applies as for any new file.
      const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0) {
        fd_ = fd;
        tmp_ = std::move(tmp);
        return "";
      }
      if (errno != EEXIST)
        return std::string("cannot create a file there: ") + std::strerror(errno);
    }
    return "cannot find a free temporary file name beside it";
  }

  int fd() const { return fd_; }

  // Closes and renames over dest. Returns "" or the reason; on failure the destructor
  // removes the temporary file.
  std::string commit(const std::string& dest) {
    const int fd = fd_;
    fd_ = -1;
    // close(2) can report a deferred write error (NFS, quotas): the file is not complete.
    if (::close(fd) != 0) return std::string("cannot finish writing: ") + std::strerror(errno);
    std::error_code ec;
    std::filesystem::rename(tmp_, dest, ec);
    if (ec) return "cannot move the finished file into place: " + ec.message();
    tmp_.clear();
    return "";
  }

 private:
  int fd_ = -1;
  std::string tmp_;
};

// ----------------------------------------------------------------------------- validation

// Tetrahedra must extend the surface mesh: its points first and unchanged, every index in
// range, every solid id one the file can name.
std::string validate_volume(const SurfaceMesh& m, const geom::Model* model,
                            const surface::TetMesh& v) {
  const std::size_t np = v.points.size();
  if (np > static_cast<std::size_t>(std::numeric_limits<NodeId>::max()))
    return "too many points for 32-bit node ids";
  if (v.surface_points != m.points.size() || np < m.points.size() ||
      !std::equal(m.points.begin(), m.points.end(), v.points.begin()))
    return "invalid volume mesh: its points do not start with the surface mesh's";
  if (v.interior_point_solid.size() != np - m.points.size() || v.tet_solid.size() != v.tets.size())
    return "invalid volume mesh: array sizes disagree";
  const std::size_t solids = model ? model->solids.size() : std::numeric_limits<std::size_t>::max();
  auto solid_ok = [&](geom::Id s) { return s >= 0 && static_cast<std::size_t>(s) < solids; };
  for (geom::Id s : v.interior_point_solid)
    if (!solid_ok(s)) return "invalid volume mesh: an interior point has no valid solid";
  for (std::size_t t = 0; t < v.tets.size(); ++t) {
    for (NodeId n : v.tets[t])
      if (n < 0 || static_cast<std::size_t>(n) >= np)
        return "invalid volume mesh: tetrahedron " + std::to_string(t) +
               " has a node index out of range";
    if (!solid_ok(v.tet_solid[t]))
      return "invalid volume mesh: tetrahedron " + std::to_string(t) + " has no valid solid";
  }
  return "";
}

std::string validate(const SurfaceMesh& m, const geom::Model* model, Counts& c) {
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  if (np > static_cast<std::size_t>(std::numeric_limits<NodeId>::max()))
    return "too many points for 32-bit node ids";
  if (m.point_dim.size() != np || m.point_entity.size() != np)
    return "invalid mesh: " + std::to_string(np) + " points but " +
           std::to_string(m.point_dim.size()) + " point_dim and " +
           std::to_string(m.point_entity.size()) + " point_entity entries";
  if (m.triangle_face.size() != nt)
    return "invalid mesh: " + std::to_string(nt) + " triangles but " +
           std::to_string(m.triangle_face.size()) + " triangle_face entries";
  if (model) {
    c.vertices = model->vertices.size();
    c.edges = model->edges.size();
    c.faces = model->faces.size();
  }
  std::size_t* count_of[3] = {&c.vertices, &c.edges, &c.faces};
  auto note = [](std::size_t& n, geom::Id id) {
    n = std::max(n, static_cast<std::size_t>(id) + 1);
  };
  for (std::size_t i = 0; i < np; ++i) {
    const geom::Vec3& p = m.points[i];
    if (!std::isfinite(p.x) || !std::isfinite(p.y) || !std::isfinite(p.z))
      return "invalid mesh: point " + std::to_string(i) + " has a non-finite coordinate";
    const int d = m.point_dim[i];
    if (d < 0 || d > 2 || m.point_entity[i] < 0)
      return "invalid mesh: point " + std::to_string(i) + " is classified on dimension " +
             std::to_string(d) + ", entity " + std::to_string(m.point_entity[i]);
    note(*count_of[d], m.point_entity[i]);
  }
  auto node_ok = [np](NodeId v) { return v >= 0 && static_cast<std::size_t>(v) < np; };
  for (std::size_t t = 0; t < nt; ++t) {
    const auto& tri = m.triangles[t];
    if (!node_ok(tri[0]) || !node_ok(tri[1]) || !node_ok(tri[2]))
      return "invalid mesh: triangle " + std::to_string(t) + " has a node index out of range";
    if (m.triangle_face[t] < 0)
      return "invalid mesh: triangle " + std::to_string(t) + " has no face";
    note(c.faces, m.triangle_face[t]);
  }
  for (std::size_t s = 0; s < m.segments.size(); ++s) {
    const auto& seg = m.segments[s];
    if (!node_ok(seg.a) || !node_ok(seg.b) || seg.edge < 0)
      return "invalid mesh: segment " + std::to_string(s) +
             " has a node index out of range or no edge";
    note(c.edges, seg.edge);
  }
  if (model && (c.vertices > model->vertices.size() || c.edges > model->edges.size() ||
                c.faces > model->faces.size()))
    return "the mesh refers to model entities the model does not have (" +
           std::to_string(c.vertices) + " vertices, " + std::to_string(c.edges) + " edges, " +
           std::to_string(c.faces) + " faces needed; the model has " +
           std::to_string(model->vertices.size()) + ", " + std::to_string(model->edges.size()) +
           ", " + std::to_string(model->faces.size()) + ")";
  return "";
}

}  // namespace

// ----------------------------------------------------------------------------- API

// ----------------------------------------------------------------------------- API

namespace {

struct FormatInfo {
  MeshFormat format;
  std::string_view name, extension;
};

constexpr FormatInfo kFormats[] = {
    {MeshFormat::Msh41, "msh41", ".msh"},   {MeshFormat::Msh22, "msh22", ".msh"},
    {MeshFormat::Medit, "medit", ".mesh"},  {MeshFormat::Meshb, "meshb", ".meshb"},
    {MeshFormat::Stl, "stl", ".stl"},       {MeshFormat::Obj, "obj", ".obj"},
    {MeshFormat::Ply, "ply", ".ply"},       {MeshFormat::Vtk, "vtk", ".vtk"},
    {MeshFormat::Vtu, "vtu", ".vtu"},       {MeshFormat::Poly, "poly", ".poly"},
    {MeshFormat::Smesh, "smesh", ".smesh"}, {MeshFormat::Drc, "drc", ".drc"},
    {MeshFormat::Glb, "glb", ".glb"},
};

}  // namespace

std::optional<MeshFormat> format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  for (const FormatInfo& f : kFormats)  // the first one per extension: .msh is 4.1
    if (f.extension == ext) return f.format;
  return std::nullopt;
}

std::optional<MeshFormat> format_from_name(std::string_view name) {
  for (const FormatInfo& f : kFormats)
    if (f.name == name) return f.format;
  return std::nullopt;
}

std::string known_mesh_extensions() {
  std::string s;
  for (const FormatInfo& f : kFormats)
    if (s.find(std::string(f.extension) + ",") == std::string::npos && !s.ends_with(f.extension))
      s += (s.empty() ? "" : ", ") + std::string(f.extension);
  return s;
}

std::string known_format_names() {
  std::string s;
  for (const FormatInfo& f : kFormats) s += (s.empty() ? "" : ", ") + std::string(f.name);
  return s;
}

std::string_view format_name(MeshFormat fmt) {
  for (const FormatInfo& f : kFormats)
    if (f.format == fmt) return f.name;
  return "?";
}

namespace {

// Whether format f is written in binary, or why the request cannot be written: the
// encoding the format has, the counts its fields can hold, Draco's parameter ranges.
std::string check_format(MeshFormat f, const SurfaceMesh& m, const WriteOptions& opts,
                         bool& binary) {
  const bool binary_only = f == MeshFormat::Meshb || f == MeshFormat::Drc || f == MeshFormat::Glb;
  const bool has_binary = binary_only || f == MeshFormat::Msh41 || f == MeshFormat::Stl ||
                          f == MeshFormat::Ply || f == MeshFormat::Vtk || f == MeshFormat::Vtu;
  binary = opts.encoding == Encoding::Binary ||
           (opts.encoding == Encoding::Default &&
            (binary_only || f == MeshFormat::Stl || f == MeshFormat::Ply || f == MeshFormat::Vtu));
  if (binary && !has_binary)
    return "there is no binary form of " + std::string(format_name(f)) + " here";
  if (binary_only && opts.encoding == Encoding::Ascii)
    return std::string(format_name(f)) + " has no ASCII form";
  if (opts.volume && !carries_tetrahedra(f))
    return std::string(format_name(f)) +
           " cannot carry tetrahedra (volume meshes: .msh, .mesh or .vtu)";
  // Legacy VTK, VTU, binary STL, PLY and .meshb count in 32 bits.
  const std::size_t int32_max = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
  if ((f == MeshFormat::Vtk || f == MeshFormat::Vtu) && 4 * m.triangles.size() > int32_max)
    return "too many triangles for VTK (32-bit sizes)";
  if (f == MeshFormat::Stl && m.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    return "too many triangles for STL (32-bit count)";
  if ((f == MeshFormat::Ply || f == MeshFormat::Meshb) && m.triangles.size() > int32_max)
    return "too many triangles for 32-bit indices";
  if (f == MeshFormat::Drc || f == MeshFormat::Glb) {
    if (opts.draco_bits < 1 || opts.draco_bits > 30) return "Draco quantization bits must be 1..30";
    if (opts.draco_level < 0 || opts.draco_level > 10)
      return "Draco compression level must be 0..10";
    if (opts.draco_normal_bits < 1 || opts.draco_normal_bits > 30)
      return "Draco normal bits must be 1..30";
  }
  return "";
}

// The file's bytes in format f (Draco's already encoded in `encoded`).
void write_format(Sink& out, MeshFormat f, const SurfaceMesh& m, const geom::Model* model,
                  const Counts& counts, const Physicals& phys, bool binary,
                  const std::vector<char>& encoded, const surface::TetMesh* vol) {
  switch (f) {
    case MeshFormat::Msh41:
      write_msh41(out, m, model, counts, phys, binary, vol);
      break;
    case MeshFormat::Msh22:
      write_msh22(out, m, phys, vol);
      break;
    case MeshFormat::Medit:
      write_medit(out, m, vol);
      break;
    case MeshFormat::Meshb:
      write_meshb(out, m);
      break;
    case MeshFormat::Stl:
      if (binary)
        write_stl_binary(out, m);
      else
        write_stl_ascii(out, m);
      break;
    case MeshFormat::Obj:
      write_obj(out, m, counts);
      break;
    case MeshFormat::Ply:
      write_ply(out, m, binary);
      break;
    case MeshFormat::Vtk:
      write_vtk(out, m, binary);
      break;
    case MeshFormat::Vtu:
      write_vtu(out, m, binary, vol);
      break;
    case MeshFormat::Poly:
      write_tetgen(out, m, false);
      break;
    case MeshFormat::Smesh:
      write_tetgen(out, m, true);
      break;
    case MeshFormat::Drc:
    case MeshFormat::Glb:
      out.raw(encoded.data(), encoded.size());
      break;
  }
}

}  // namespace

WriteResult write_mesh(const surface::SurfaceMesh& m, const geom::Model* model,
                       const std::string& path, const WriteOptions& opts) {
  auto fail = [&](const std::string& why) { return WriteResult{false, path + ": " + why}; };

  const std::optional<MeshFormat> fmt = opts.format ? opts.format : format_from_path(path);
  if (!fmt) return fail("unknown mesh file extension (known: " + known_mesh_extensions() + ")");
  const MeshFormat f = *fmt;
  bool binary = false;
  if (std::string why = check_format(f, m, opts, binary); !why.empty()) return fail(why);

  Counts counts;
  if (std::string why = validate(m, model, counts); !why.empty()) return fail(why);
  if (opts.volume)
    if (std::string why = validate_volume(m, model, *opts.volume); !why.empty()) return fail(why);

  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return fail("is a directory");

  // Draco encodes in memory; the bytes then take the same atomic path as every format.
  std::vector<char> encoded;
  if (f == MeshFormat::Drc || f == MeshFormat::Glb) {
    const std::string why = f == MeshFormat::Drc ? detail::encode_drc(m, opts, encoded)
                                                 : detail::encode_glb(m, model, opts, encoded);
    if (!why.empty()) return fail(why);
  }

  TempFile tmp;
  if (std::string why = tmp.open(path); !why.empty()) return fail(why);
  Sink out(tmp.fd());
  const Physicals phys = physicals(model, counts, opts.physical_groups);
  write_format(out, f, m, model, counts, phys, binary, encoded, opts.volume);
  out.flush();
  if (out.error() != 0) return fail(std::string("write failed: ") + std::strerror(out.error()));
  if (std::string why = tmp.commit(path); !why.empty()) return fail(why);
  return {true, ""};
}

}  // namespace uvmesh::io
