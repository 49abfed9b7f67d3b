// Writers for the whole-model surface mesh. Formats, as written here:
//  - Gmsh MSH 4.1 ASCII: Gmsh reference manual, section "MSH file format" (version 4.1):
//    $MeshFormat, $Entities, $Nodes and $Elements in entity blocks.
//  - Medit: Frey, "MEDIT: an interactive mesh visualization software" (INRIA RT-0253),
//    the keyword format also read by MMG, TetGen and Gmsh (MeshVersionFormatted 2 stores
//    double-precision coordinates).
//  - STL: 3D Systems' StereoLithography Interface Specification (binary: 80-byte header,
//    uint32 count, 50-byte little-endian records).
//  - OBJ: Wavefront "Object Files (.obj)" appendix B1 (v, f, g statements).
//  - VTK legacy: "The VTK User's Guide", section "VTK File Formats", simple legacy
//    formats (binary data big-endian; int is 4 bytes).
//
// Output goes through one fixed buffer (Sink) filled with std::to_chars and handed to
// write(2) in 1 MiB chunks: meshes reach millions of triangles, and a stream insertion
// per number is several times slower than this for the same bytes.
#include "uvmesh/io/mesh_writer.h"

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <system_error>
#include <tuple>
#include <vector>

#include "draco_io.h"

namespace uvmesh::io {

namespace {

using surface::NodeId;
using surface::SurfaceMesh;

// ----------------------------------------------------------------------------- output

// Every format here numbers nodes and entities from 1 (Gmsh tags, Medit and OBJ indices).
template <class Index>
constexpr std::int64_t one_based(Index index) {
  return static_cast<std::int64_t>(index) + 1;
}

// Buffered writer on a file descriptor. It never throws and never prints: the first
// failing write(2) is remembered in error() and every later call is a no-op, so format
// writers can run straight through and the caller checks once at the end.
class Sink {
 public:
  explicit Sink(int fd) : fd_(fd), buf_(new char[kCap]) {}

  int error() const { return err_; }

  void put(std::string_view s) {
    if (s.size() > kCap) {
      flush();
      write_all(s.data(), s.size());
      return;
    }
    room(s.size());
    std::memcpy(buf_.get() + pos_, s.data(), s.size());
    pos_ += s.size();
  }
  void put(char c) {
    room(1);
    buf_[pos_++] = c;
  }
  // Shortest decimal form that reads back to the same double (std::to_chars without a
  // precision), i.e. as exact as %.17g and usually much shorter.
  void num(double v) {
    room(kNumMax);
    pos_ = static_cast<std::size_t>(std::to_chars(buf_.get() + pos_, buf_.get() + kCap, v).ptr -
                                    buf_.get());
  }
  void num(std::int64_t v) {
    room(kNumMax);
    pos_ = static_cast<std::size_t>(std::to_chars(buf_.get() + pos_, buf_.get() + kCap, v).ptr -
                                    buf_.get());
  }
  void num(int v) { num(static_cast<std::int64_t>(v)); }
  void num(std::size_t v) { num(static_cast<std::int64_t>(v)); }
  // Integers separated by spaces, then a newline: the count and block-header lines.
  void line(std::initializer_list<std::int64_t> values) {
    const char* sep = "";
    for (std::int64_t v : values) {
      put(sep);
      num(v);
      sep = " ";
    }
    put('\n');
  }
  // "x y z", the common record part.
  void xyz(const geom::Vec3& p) {
    num(p.x);
    put(' ');
    num(p.y);
    put(' ');
    num(p.z);
  }
  void raw(const void* p, std::size_t n) { put(std::string_view(static_cast<const char*>(p), n)); }

  // Hands the buffer to the kernel. Also called by room() when full.
  void flush() {
    if (pos_ > 0) write_all(buf_.get(), pos_);
    pos_ = 0;
  }

 private:
  static constexpr std::size_t kCap = std::size_t{1} << 20;
  static constexpr std::size_t kNumMax = 32;  // longest to_chars output of a double is 24

  void room(std::size_t n) {
    if (pos_ + n > kCap) flush();
  }
  void write_all(const char* p, std::size_t n) {
    while (n > 0 && err_ == 0) {
      const ssize_t w = ::write(fd_, p, n);
      if (w < 0) {
        if (errno == EINTR) continue;
        err_ = errno;
      } else if (w == 0) {
        err_ = EIO;  // no progress and no errno: do not spin
      } else {
        p += w;
        n -= static_cast<std::size_t>(w);
      }
    }
  }

  int fd_;
  std::unique_ptr<char[]> buf_;
  std::size_t pos_ = 0;
  int err_ = 0;
};

// Binary numbers in a fixed byte order, whatever the host's.
template <class T>
void put_le(Sink& out, T v) {
  auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::big) std::reverse(bits.begin(), bits.end());
  out.raw(bits.data(), bits.size());
}

template <class T>
void put_be(Sink& out, T v) {
  auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
  if constexpr (std::endian::native == std::endian::little) std::reverse(bits.begin(), bits.end());
  out.raw(bits.data(), bits.size());
}

// The numbers of a record in .msh 4.1 (and other formats with an ASCII and a binary
// form of the same records): ASCII separates them with spaces and ends the record with a
// newline; binary writes them little-endian back to back (Gmsh's binary files are in the
// writer's byte order, and it reads the endianness marker 1 written in $MeshFormat).
class Record {
 public:
  Record(Sink& out, bool binary) : out_(out), binary_(binary) {}
  bool binary() const { return binary_; }
  Record& i(std::int64_t v) {  // a C int (tags, dims, types)
    if (binary_)
      put_le(out_, static_cast<std::int32_t>(v));
    else
      text(v);
    return *this;
  }
  Record& z(std::int64_t v) {  // a size_t (counts, node and element tags)
    if (binary_)
      put_le(out_, static_cast<std::uint64_t>(v));
    else
      text(v);
    return *this;
  }
  Record& d(double v) {
    if (binary_)
      put_le(out_, v);
    else
      text(v);
    return *this;
  }
  Record& xyz(const geom::Vec3& p) { return d(p.x).d(p.y).d(p.z); }
  void end() {
    if (!binary_) out_.put('\n');
    first_ = true;
  }

 private:
  template <class T>
  void text(T v) {
    if (!first_) out_.put(' ');
    first_ = false;
    out_.num(v);
  }
  Sink& out_;
  bool binary_;
  bool first_ = true;
};

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

// ----------------------------------------------------------------------------- grouping

// Stable counting sort of items 0..n-1 by a dense key in [0, num_keys): order lists the
// items key by key (each key's items in their original order), and the items of key k
// are order[first[k]] .. order[first[k+1]-1]. Used to group nodes by entity and elements
// by edge or face in O(n), keeping the mesh's own order within a group.
struct Buckets {
  std::vector<std::size_t> first;
  std::vector<std::int32_t> order;
  std::size_t size(std::size_t k) const { return first[k + 1] - first[k]; }
  template <class F>
  void each(std::size_t k, F f) const {
    for (std::size_t i = first[k]; i < first[k + 1]; ++i) f(static_cast<std::size_t>(order[i]));
  }
};

template <class KeyFn>
Buckets bucket(std::size_t n, std::size_t num_keys, KeyFn key) {
  Buckets b;
  b.first.assign(num_keys + 1, 0);
  for (std::size_t i = 0; i < n; ++i) ++b.first[key(i) + 1];
  for (std::size_t k = 0; k < num_keys; ++k) b.first[k + 1] += b.first[k];
  std::vector<std::size_t> next(b.first.begin(), b.first.end() - 1);
  b.order.resize(n);
  for (std::size_t i = 0; i < n; ++i) b.order[next[key(i)]++] = static_cast<std::int32_t>(i);
  return b;
}

// ----------------------------------------------------------------------------- validation

// Entity counts of the mesh: one past the largest id of each kind it mentions, at least
// the model's counts when there is a model.
struct Counts {
  std::size_t vertices = 0, edges = 0, faces = 0;
};

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

// ----------------------------------------------------------------------------- Gmsh 4.1

// Physical groups: a solver addresses boundary conditions and materials through them.
// Volume group per solid (tag = solid id + 1); surface groups per distinct face name
// (tags 1.. in order of first appearance), so that faces a CAD user named alike (e.g.
// "inlet") form one group. Once the file has any physical group, every element must be
// in one: Gmsh re-saves only grouped elements (Mesh.SaveAll off, its default), and meshio
// rejects a file where some element blocks have physical tags and others not. So with
// named faces or a solid, the unnamed faces form "unnamed_faces", and the model edges
// and vertices one group each. (A solid's volume group alone left every triangle
// ungrouped: `gmsh part.msh -0 -o copy.msh` wrote an empty mesh.)
struct Physicals {
  std::vector<std::int64_t> face_group;           ///< per face: its surface group tag, 0 for none
  std::vector<std::string> face_names;            ///< surface group tag - 1 -> name
  std::int64_t curve_group = 0, point_group = 0;  ///< the catch-all tags (0: none)
  bool solids = false;                            ///< one volume group per written volume
  std::vector<std::string> solid_names;           ///< per solid id
};

Physicals physicals(const geom::Model* model, const Counts& c, bool on) {
  Physicals p;
  if (!on || !model) return p;
  p.solids = true;
  for (std::size_t s = 0; s < model->solids.size(); ++s)
    p.solid_names.push_back(model->solids[s].name.empty() ? "solid_" + std::to_string(s + 1)
                                                          : model->solids[s].name);
  p.face_group.assign(c.faces, 0);
  std::map<std::string, std::int64_t> tag_of;
  for (std::size_t f = 0; f < model->faces.size() && f < c.faces; ++f) {
    const std::string& name = model->faces[f].name;
    if (name.empty()) continue;
    auto [it, fresh] = tag_of.emplace(name, static_cast<std::int64_t>(p.face_names.size()) + 1);
    if (fresh) p.face_names.push_back(name);
    p.face_group[f] = it->second;
  }
  if (!p.face_names.empty() || !model->solids.empty()) {
    const auto unnamed = static_cast<std::int64_t>(p.face_names.size()) + 1;
    bool any = false;
    for (std::int64_t& g : p.face_group)
      if (g == 0) g = unnamed, any = true;
    if (any) p.face_names.push_back("unnamed_faces");
    p.curve_group = p.point_group = 1;
  }
  return p;
}

// A name inside the double quotes of $PhysicalNames: Gmsh reads up to the next quote and
// the line end, so both are replaced.
std::string quoted_name(const std::string& name) {
  std::string q;
  for (char ch : name) q += (ch == '"' || ch == '\n' || ch == '\r') ? '_' : ch;
  return '"' + q + '"';
}

// $PhysicalNames (ASCII in binary files too) for the named surface groups and the volume
// groups of the written volumes (volume_tags: the solid tags written, in order).
void write_physical_names(Sink& out, const Physicals& p,
                          const std::vector<std::int64_t>& volume_tags) {
  std::vector<std::tuple<int, std::int64_t, std::string>> groups;
  if (p.point_group > 0) groups.emplace_back(0, p.point_group, "model_vertices");
  if (p.curve_group > 0) groups.emplace_back(1, p.curve_group, "model_edges");
  for (std::size_t g = 0; g < p.face_names.size(); ++g)
    groups.emplace_back(2, static_cast<std::int64_t>(g) + 1, p.face_names[g]);
  if (p.solids)
    for (std::int64_t t : volume_tags)
      groups.emplace_back(3, t, p.solid_names[static_cast<std::size_t>(t - 1)]);
  if (groups.empty()) return;
  out.put("$PhysicalNames\n");
  out.num(groups.size());
  out.put('\n');
  for (const auto& [dim, tag, name] : groups) {
    out.num(dim);
    out.put(' ');
    out.num(tag);
    out.put(' ');
    out.put(quoted_name(name));
    out.put('\n');
  }
  out.put("$EndPhysicalNames\n");
}

// Nodes grouped by entity: keys are vertices, then edges, then faces, so iterating the
// keys in order gives Gmsh's usual dimension-then-tag block order.
struct NodeGroups {
  Buckets b;
  std::size_t base[3];
  std::size_t key(int dim, std::size_t id) const { return base[dim] + id; }
};

void write_msh41(Sink& out, const SurfaceMesh& m, const geom::Model* model, const Counts& c,
                 const Physicals& phys, bool binary) {
  const std::size_t np = m.points.size();
  NodeGroups ng;
  ng.base[0] = 0;
  ng.base[1] = c.vertices;
  ng.base[2] = c.vertices + c.edges;
  ng.b = bucket(np, c.vertices + c.edges + c.faces, [&](std::size_t i) {
    return ng.key(m.point_dim[i], static_cast<std::size_t>(m.point_entity[i]));
  });
  const Buckets segs = bucket(m.segments.size(), c.edges, [&](std::size_t s) {
    return static_cast<std::size_t>(m.segments[s].edge);
  });
  const Buckets tris = bucket(m.triangles.size(), c.faces, [&](std::size_t t) {
    return static_cast<std::size_t>(m.triangle_face[t]);
  });

  // An entity is written when it carries nodes or elements, so that every tag the file
  // mentions (bounding entities included) is defined in it.
  auto has_point = [&](std::size_t v) { return ng.b.size(ng.key(0, v)) > 0; };
  auto has_curve = [&](std::size_t e) { return ng.b.size(ng.key(1, e)) > 0 || segs.size(e) > 0; };
  auto has_surface = [&](std::size_t f) { return ng.b.size(ng.key(2, f)) > 0 || tris.size(f) > 0; };

  // Bounding boxes from the mesh (the file describes the mesh; a model's curves need not
  // give boxes cheaply): an entity's own nodes plus the nodes of its elements.
  std::vector<geom::Box3> curve_box(c.edges), surface_box(c.faces);
  for (std::size_t i = 0; i < np; ++i) {
    if (m.point_dim[i] == 1)
      curve_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
    if (m.point_dim[i] == 2)
      surface_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
  }
  for (const auto& s : m.segments) {
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.a)]);
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.b)]);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (NodeId v : m.triangles[t])
      surface_box[static_cast<std::size_t>(m.triangle_face[t])].add(
          m.points[static_cast<std::size_t>(v)]);

  // Bounding points of each curve, begin vertex +tag and end vertex -tag (Gmsh's own
  // convention in its MSH4 entity writer; a closed curve lists its vertex twice). With a
  // model, the edge's v0/v1; without, the model-vertex nodes at the ends of its segment
  // chain (segments are in curve-parameter order).
  std::vector<std::vector<std::int64_t>> curve_points(c.edges);
  for (std::size_t e = 0; e < c.edges; ++e) {
    if (!has_curve(e)) continue;
    auto add = [&](geom::Id v, int sign) {
      if (v >= 0 && static_cast<std::size_t>(v) < c.vertices &&
          has_point(static_cast<std::size_t>(v)))
        curve_points[e].push_back(sign * one_based(v));
    };
    if (model) {
      add(model->edges[e].v0, 1);
      add(model->edges[e].v1, -1);
    } else if (segs.size(e) > 0) {
      auto vertex_of = [&](NodeId n) {
        const auto i = static_cast<std::size_t>(n);
        return m.point_dim[i] == 0 ? m.point_entity[i] : geom::kNone;
      };
      add(vertex_of(m.segments[static_cast<std::size_t>(segs.order[segs.first[e]])].a), 1);
      add(vertex_of(m.segments[static_cast<std::size_t>(segs.order[segs.first[e + 1] - 1])].b), -1);
    }
  }

  // Bounding curves of each surface (model only): every edge its loops use, once, signed
  // by the direction of the use relative to the written triangles. Loops run with the
  // surface's natural normal and the mesh flips reversed faces (geom/model.h), so a use
  // runs against the triangles (negative) when exactly one of use.reversed and
  // face.reversed holds.
  std::vector<std::vector<std::int64_t>> surface_curves(c.faces);
  if (model) {
    std::vector<char> seen(c.edges, 0);
    for (std::size_t f = 0; f < c.faces; ++f) {
      if (!has_surface(f)) continue;
      const geom::Face& face = model->faces[f];
      for (const geom::Loop& loop : face.loops)
        for (const geom::EdgeUse& use : loop.uses) {
          if (use.edge < 0 || static_cast<std::size_t>(use.edge) >= c.edges) continue;
          const auto e = static_cast<std::size_t>(use.edge);
          if (seen[e] || !has_curve(e)) continue;  // a seam is listed once
          seen[e] = 1;
          const int sign = use.reversed != face.reversed ? -1 : 1;
          surface_curves[f].push_back(sign * one_based(e));
        }
      for (std::int64_t t : surface_curves[f]) seen[static_cast<std::size_t>(std::abs(t) - 1)] = 0;
    }
  }

  // Volumes (model only): each solid with the written faces of its shells. Triangles
  // are oriented outward for solids, and a discrete surface's orientation is its
  // triangles', so every bounding surface is listed with +.
  struct Volume {
    std::int64_t tag;
    geom::Box3 box;
    std::vector<std::int64_t> surfaces;
  };
  std::vector<Volume> volumes;
  if (model) {
    for (std::size_t s = 0; s < model->solids.size(); ++s) {
      Volume vol{one_based(s), {}, {}};
      for (geom::Id sh : model->solids[s].shells) {
        if (sh < 0 || static_cast<std::size_t>(sh) >= model->shells.size()) continue;
        for (geom::Id f : model->shells[static_cast<std::size_t>(sh)].faces) {
          if (f < 0 || static_cast<std::size_t>(f) >= c.faces ||
              !has_surface(static_cast<std::size_t>(f)))
            continue;
          vol.surfaces.push_back(one_based(f));
          vol.box.add(surface_box[static_cast<std::size_t>(f)]);
        }
      }
      if (!vol.surfaces.empty()) volumes.push_back(std::move(vol));
    }
  }

  std::size_t n_points = 0, n_curves = 0, n_surfaces = 0;
  for (std::size_t v = 0; v < c.vertices; ++v) n_points += has_point(v);
  for (std::size_t e = 0; e < c.edges; ++e) n_curves += has_curve(e);
  for (std::size_t f = 0; f < c.faces; ++f) n_surfaces += has_surface(f);

  auto i64 = [](std::size_t v) { return static_cast<std::int64_t>(v); };
  Record r(out, binary);
  out.put(binary ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n");
  if (binary) {
    put_le(out, std::int32_t{1});  // endianness marker
    out.put('\n');
  }
  out.put("$EndMeshFormat\n");
  std::vector<std::int64_t> volume_tags;
  for (const Volume& vol : volumes) volume_tags.push_back(vol.tag);
  write_physical_names(out, phys, volume_tags);
  out.put("$Entities\n");
  r.z(i64(n_points)).z(i64(n_curves)).z(i64(n_surfaces)).z(i64(volumes.size())).end();
  // Curve / surface / volume record: tag, bbox, physical tags, the bounding entities.
  auto entity = [&](std::int64_t tag, const geom::Box3& box, std::int64_t physical,
                    const std::vector<std::int64_t>& bounding) {
    r.i(tag).xyz(box.lo).xyz(box.hi).z(physical > 0 ? 1 : 0);
    if (physical > 0) r.i(physical);
    r.z(i64(bounding.size()));
    for (std::int64_t t : bounding) r.i(t);
    r.end();
  };
  // Point: tag x y z numPhysicalTags physicalTags.
  for (std::size_t v = 0; v < c.vertices; ++v) {
    if (!has_point(v)) continue;
    r.i(one_based(v)).xyz(m.points[static_cast<std::size_t>(ng.b.order[ng.b.first[ng.key(0, v)]])]);
    r.z(phys.point_group > 0 ? 1 : 0);
    if (phys.point_group > 0) r.i(phys.point_group);
    r.end();
  }
  for (std::size_t e = 0; e < c.edges; ++e)
    if (has_curve(e)) entity(one_based(e), curve_box[e], phys.curve_group, curve_points[e]);
  for (std::size_t f = 0; f < c.faces; ++f)
    if (has_surface(f))
      entity(one_based(f), surface_box[f], phys.face_group.empty() ? 0 : phys.face_group[f],
             surface_curves[f]);
  for (const Volume& vol : volumes)
    entity(vol.tag, vol.box, phys.solids ? vol.tag : 0, vol.surfaces);
  if (binary) out.put('\n');
  out.put("$EndEntities\n");

  // $Nodes: numBlocks numNodes minTag maxTag, then per block "dim tag parametric n",
  // the n node tags, the n coordinate lines. Node tag = index + 1 whatever the block order.
  const std::size_t num_keys = ng.b.first.size() - 1;
  std::size_t node_blocks = 0;
  for (std::size_t k = 0; k < num_keys; ++k) node_blocks += ng.b.size(k) > 0;
  out.put("$Nodes\n");
  r.z(i64(node_blocks)).z(i64(np)).z(np > 0 ? 1 : 0).z(i64(np)).end();
  for (int dim = 0; dim < 3; ++dim) {
    const std::size_t n_ent = dim == 0 ? c.vertices : dim == 1 ? c.edges : c.faces;
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = ng.key(dim, id);
      if (ng.b.size(k) == 0) continue;
      r.i(dim).i(one_based(id)).i(0).z(i64(ng.b.size(k))).end();  // parametric = 0
      ng.b.each(k, [&](std::size_t i) { r.z(one_based(i)).end(); });
      ng.b.each(k, [&](std::size_t i) { r.xyz(m.points[i]).end(); });
    }
  }
  if (binary) out.put('\n');
  out.put("$EndNodes\n");

  // $Elements: a point element (type 15) per model-vertex node, 2-node lines (type 1)
  // per curve, 3-node triangles (type 2) per surface; tags 1..N in that order.
  std::size_t vertex_nodes = ng.b.first[ng.base[1]];
  std::size_t elem_blocks = 0;
  for (std::size_t v = 0; v < c.vertices; ++v) elem_blocks += has_point(v);
  for (std::size_t e = 0; e < c.edges; ++e) elem_blocks += segs.size(e) > 0;
  for (std::size_t f = 0; f < c.faces; ++f) elem_blocks += tris.size(f) > 0;
  const std::size_t n_elems = vertex_nodes + m.segments.size() + m.triangles.size();
  out.put("$Elements\n");
  r.z(i64(elem_blocks)).z(i64(n_elems)).z(n_elems > 0 ? 1 : 0).z(i64(n_elems)).end();
  // One block per entity that has elements: "dim tag type n", then n records
  // "elementTag nodeTag...". Element tags run on across blocks.
  std::int64_t tag = 1;
  auto blocks = [&](int dim, int type, const Buckets& b, std::size_t key0, std::size_t n_ent,
                    auto nodes_of) {
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = key0 + id;
      if (b.size(k) == 0) continue;
      r.i(dim).i(one_based(id)).i(type).z(i64(b.size(k))).end();
      b.each(k, [&](std::size_t i) {
        r.z(tag++);
        nodes_of(i);
        r.end();
      });
    }
  };
  blocks(0, 15, ng.b, ng.base[0], c.vertices, [&](std::size_t i) { r.z(one_based(i)); });
  blocks(1, 1, segs, 0, c.edges,
         [&](std::size_t s) { r.z(one_based(m.segments[s].a)).z(one_based(m.segments[s].b)); });
  blocks(2, 2, tris, 0, c.faces, [&](std::size_t t) {
    for (NodeId v : m.triangles[t]) r.z(one_based(v));
  });
  if (binary) out.put('\n');
  out.put("$EndElements\n");
}

// ----------------------------------------------------------------------------- Gmsh 2.2

// The legacy format many solvers still read: one node list, one element list whose
// records carry "physical elementary" tags. No volume elements exist in a surface mesh,
// so the solids' groups cannot appear (they need the 4.1 entities).
void write_msh22(Sink& out, const SurfaceMesh& m, Physicals phys) {
  out.put("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  phys.solids = false;
  write_physical_names(out, phys, {});
  out.put("$Nodes\n");
  out.num(m.points.size());
  out.put('\n');
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    out.num(one_based(i));
    out.put(' ');
    out.xyz(m.points[i]);
    out.put('\n');
  }
  out.put("$EndNodes\n$Elements\n");
  std::size_t n_vertices = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i) n_vertices += m.point_dim[i] == 0;
  out.num(n_vertices + m.segments.size() + m.triangles.size());
  out.put('\n');
  std::int64_t tag = 1;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    if (m.point_dim[i] == 0)
      out.line({tag++, 15, 2, phys.point_group, one_based(m.point_entity[i]), one_based(i)});
  for (const auto& sg : m.segments)
    out.line({tag++, 1, 2, phys.curve_group, one_based(sg.edge), one_based(sg.a), one_based(sg.b)});
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto f = static_cast<std::size_t>(m.triangle_face[t]);
    const auto& tri = m.triangles[t];
    out.line({tag++, 2, 2, phys.face_group.empty() ? 0 : phys.face_group[f], one_based(f),
              one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
  }
  out.put("$EndElements\n");
}

// ----------------------------------------------------------------------------- Medit

void write_medit(Sink& out, const SurfaceMesh& m) {
  out.put("MeshVersionFormatted 2\n\nDimension 3\n\nVertices\n");
  out.num(m.points.size());
  out.put('\n');
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    out.xyz(m.points[i]);
    out.put(' ');
    out.num(one_based(m.point_entity[i]));
    out.put('\n');
  }
  // Empty sections are left out: some readers reject a keyword followed by 0.
  if (!m.segments.empty()) {
    out.put("\nEdges\n");
    out.num(m.segments.size());
    out.put('\n');
    for (const auto& s : m.segments) out.line({one_based(s.a), one_based(s.b), one_based(s.edge)});
  }
  if (!m.triangles.empty()) {
    out.put("\nTriangles\n");
    out.num(m.triangles.size());
    out.put('\n');
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      out.line(
          {one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), one_based(m.triangle_face[t])});
    }
  }
  out.put("\nEnd\n");
}

// Binary Medit, as libMeshb writes it (version 3): int32 code 1 (the reader's byte-order
// check), int32 version, then keywords "int32 code, int64 position of the next keyword,
// [int32 count], records". Version 3 = double reals, 32-bit integers, 64-bit positions,
// so a file may pass 2 GiB.
void write_meshb(Sink& out, const SurfaceMesh& m) {
  constexpr std::int32_t kDimension = 3, kVertices = 4, kEdges = 5, kTriangles = 6, kEnd = 54;
  std::int64_t pos = 8;  // bytes written so far: the code and the version
  put_le(out, std::int32_t{1});
  put_le(out, std::int32_t{3});
  auto keyword = [&](std::int32_t code, std::int64_t payload) {
    pos += 4 + 8 + payload;
    put_le(out, code);
    put_le(out, code == kEnd ? std::int64_t{0} : pos);
  };
  keyword(kDimension, 4);
  put_le(out, std::int32_t{3});
  const auto np = static_cast<std::int64_t>(m.points.size());
  keyword(kVertices, 4 + np * (3 * 8 + 4));
  put_le(out, static_cast<std::int32_t>(np));
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    put_le(out, m.points[i].x);
    put_le(out, m.points[i].y);
    put_le(out, m.points[i].z);
    put_le(out, static_cast<std::int32_t>(one_based(m.point_entity[i])));
  }
  if (!m.segments.empty()) {
    keyword(kEdges, 4 + static_cast<std::int64_t>(m.segments.size()) * 12);
    put_le(out, static_cast<std::int32_t>(m.segments.size()));
    for (const auto& sg : m.segments)
      for (std::int64_t v : {one_based(sg.a), one_based(sg.b), one_based(sg.edge)})
        put_le(out, static_cast<std::int32_t>(v));
  }
  if (!m.triangles.empty()) {
    keyword(kTriangles, 4 + static_cast<std::int64_t>(m.triangles.size()) * 16);
    put_le(out, static_cast<std::int32_t>(m.triangles.size()));
    for (std::size_t t = 0; t < m.triangles.size(); ++t) {
      const auto& tri = m.triangles[t];
      for (std::int64_t v :
           {one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), one_based(m.triangle_face[t])})
        put_le(out, static_cast<std::int32_t>(v));
    }
  }
  keyword(kEnd, 0);
}

// ----------------------------------------------------------------------------- TetGen

// .poly (TetGen manual, section 5.2.2) and .smesh (5.2.3): node list with index base 1,
// then facets with boundary markers (face id + 1, so a volume mesh keeps the CAD face of
// each boundary triangle), then zero holes and zero regions. A .poly facet is a list of
// polygons; here each is one triangle.
void write_tetgen(Sink& out, const SurfaceMesh& m, bool smesh) {
  out.put(smesh ? "# uvmesh surface mesh (TetGen .smesh)\n"
                : "# uvmesh surface mesh (TetGen .poly)\n");
  out.line({static_cast<std::int64_t>(m.points.size()), 3, 0, 0});
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    out.num(one_based(i));
    out.put(' ');
    out.xyz(m.points[i]);
    out.put('\n');
  }
  out.line({static_cast<std::int64_t>(m.triangles.size()), 1});
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    const std::int64_t marker = one_based(m.triangle_face[t]);
    if (smesh) {
      out.line({3, one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), marker});
    } else {
      out.line({1, 0, marker});
      out.line({3, one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
    }
  }
  out.put("0\n0\n");  // holes, regions
}

// ----------------------------------------------------------------------------- PLY

// PLY (Turk's format as in the Stanford repository): double coordinates so that binary
// and ASCII files round-trip exactly; the face list count is a uchar, indices int. The
// CAD face id is an extra face property in ASCII files only: meshio 7 (a reference
// reader here) cannot read a binary face element holding anything but the index list.
void write_ply(Sink& out, const SurfaceMesh& m, bool binary) {
  out.put(binary ? "ply\nformat binary_little_endian 1.0\n" : "ply\nformat ascii 1.0\n");
  out.put("comment uvmesh surface mesh, face_id = CAD face\nelement vertex ");
  out.num(m.points.size());
  out.put("\nproperty double x\nproperty double y\nproperty double z\nelement face ");
  out.num(m.triangles.size());
  out.put(binary ? "\nproperty list uchar int vertex_indices\nend_header\n"
                 : "\nproperty list uchar int vertex_indices\nproperty int face_id\nend_header\n");
  for (const geom::Vec3& p : m.points) {
    if (binary) {
      put_le(out, p.x);
      put_le(out, p.y);
      put_le(out, p.z);
    } else {
      out.xyz(p);
      out.put('\n');
    }
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto& tri = m.triangles[t];
    if (binary) {
      put_le(out, std::uint8_t{3});
      for (NodeId v : tri) put_le(out, static_cast<std::int32_t>(v));
    } else {
      out.line({3, tri[0], tri[1], tri[2], m.triangle_face[t]});
    }
  }
}

// ----------------------------------------------------------------------------- STL

// Unit normal of a triangle from its corners (right-hand rule), 0 for a degenerate one.
geom::Vec3 unit_normal(const SurfaceMesh& m, const std::array<NodeId, 3>& t) {
  const geom::Vec3& a = m.points[static_cast<std::size_t>(t[0])];
  const geom::Vec3 n = glm::cross(m.points[static_cast<std::size_t>(t[1])] - a,
                                  m.points[static_cast<std::size_t>(t[2])] - a);
  const double len = glm::length(n);
  return len > 0.0 ? n / len : geom::Vec3(0.0);
}

void write_stl_binary(Sink& out, const SurfaceMesh& m) {
  // The header must not start with "solid": readers take that for ASCII STL.
  char header[80];
  std::memset(header, ' ', sizeof header);
  static constexpr std::string_view kHeader = "uvmesh binary STL surface mesh";
  std::memcpy(header, kHeader.data(), kHeader.size());
  out.raw(header, sizeof header);
  put_le(out, static_cast<std::uint32_t>(m.triangles.size()));
  auto put3 = [&](const geom::Vec3& p) {
    put_le(out, static_cast<float>(p.x));
    put_le(out, static_cast<float>(p.y));
    put_le(out, static_cast<float>(p.z));
  };
  for (const auto& t : m.triangles) {
    put3(unit_normal(m, t));
    for (NodeId v : t) put3(m.points[static_cast<std::size_t>(v)]);
    put_le(out, std::uint16_t{0});  // attribute byte count
  }
}

void write_stl_ascii(Sink& out, const SurfaceMesh& m) {
  out.put("solid uvmesh\n");
  for (const auto& t : m.triangles) {
    out.put("facet normal ");
    out.xyz(unit_normal(m, t));
    out.put("\nouter loop\n");
    for (NodeId v : t) {
      out.put("vertex ");
      out.xyz(m.points[static_cast<std::size_t>(v)]);
      out.put('\n');
    }
    out.put("endloop\nendfacet\n");
  }
  out.put("endsolid uvmesh\n");
}

// ----------------------------------------------------------------------------- OBJ

void write_obj(Sink& out, const SurfaceMesh& m, const Counts& c) {
  out.put("# uvmesh surface mesh: ");
  out.num(m.points.size());
  out.put(" vertices, ");
  out.num(m.triangles.size());
  out.put(" triangles, one group per CAD face\n");
  for (const geom::Vec3& p : m.points) {
    out.put("v ");
    out.xyz(p);
    out.put('\n');
  }
  const Buckets tris = bucket(m.triangles.size(), c.faces, [&](std::size_t t) {
    return static_cast<std::size_t>(m.triangle_face[t]);
  });
  for (std::size_t f = 0; f < c.faces; ++f) {
    if (tris.size(f) == 0) continue;
    out.put("g face_");
    out.num(f);
    out.put('\n');
    tris.each(f, [&](std::size_t t) {
      const auto& tri = m.triangles[t];
      out.put("f ");
      out.line({one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
    });
  }
}

// ----------------------------------------------------------------------------- VTK

void write_vtk(Sink& out, const SurfaceMesh& m, bool binary) {
  constexpr int kVtkTriangle = 5;
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  out.put("# vtk DataFile Version 3.0\nuvmesh surface mesh\n");
  out.put(binary ? "BINARY\n" : "ASCII\n");
  out.put("DATASET UNSTRUCTURED_GRID\nPOINTS ");
  out.num(np);
  out.put(" double\n");
  for (const geom::Vec3& p : m.points) {
    if (binary) {
      put_be(out, p.x);
      put_be(out, p.y);
      put_be(out, p.z);
    } else {
      out.xyz(p);
      out.put('\n');
    }
  }
  // Every section is one integer a line in ASCII, 4-byte big-endian ints in binary.
  auto int_value = [&](std::int64_t v, char sep) {
    if (binary) {
      put_be(out, static_cast<std::int32_t>(v));
    } else {
      out.num(v);
      out.put(sep);
    }
  };
  out.put(binary ? "\nCELLS " : "CELLS ");
  out.num(nt);
  out.put(' ');
  out.num(4 * nt);
  out.put('\n');
  for (const auto& t : m.triangles) {
    int_value(3, ' ');
    int_value(t[0], ' ');
    int_value(t[1], ' ');
    int_value(t[2], '\n');
  }
  out.put(binary ? "\nCELL_TYPES " : "CELL_TYPES ");
  out.num(nt);
  out.put('\n');
  for (std::size_t t = 0; t < nt; ++t) int_value(kVtkTriangle, '\n');
  out.put(binary ? "\nCELL_DATA " : "CELL_DATA ");
  out.num(nt);
  out.put("\nSCALARS face_id int 1\nLOOKUP_TABLE default\n");
  for (geom::Id f : m.triangle_face) int_value(f, '\n');
  if (binary) out.put('\n');
}

// VTK XML UnstructuredGrid ("VTK File Formats", XML formats): inline arrays, either
// ASCII or base64 "binary" (each array's bytes preceded by a UInt32 byte count, the count
// and the data encoded as one base64 stream, as VTK's writer does without compression).
class Base64 {
 public:
  explicit Base64(Sink& out) : out_(out) {}
  void bytes(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) {
      acc_[k_++] = b[i];
      if (k_ == 3) emit(3);
    }
  }
  template <class T>
  void le(T v) {
    auto bits = std::bit_cast<std::array<unsigned char, sizeof(T)>>(v);
    if constexpr (std::endian::native == std::endian::big) std::reverse(bits.begin(), bits.end());
    bytes(bits.data(), bits.size());
  }
  void finish() {
    if (k_ > 0) emit(k_);
  }

 private:
  void emit(int n) {
    static constexpr char kAlphabet[] =
        "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    for (int i = n; i < 3; ++i) acc_[i] = 0;
    const unsigned v = (unsigned{acc_[0]} << 16) | (unsigned{acc_[1]} << 8) | acc_[2];
    char q[4] = {kAlphabet[(v >> 18) & 63], kAlphabet[(v >> 12) & 63],
                 n > 1 ? kAlphabet[(v >> 6) & 63] : '=', n > 2 ? kAlphabet[v & 63] : '='};
    out_.raw(q, 4);
    k_ = 0;
  }
  Sink& out_;
  unsigned char acc_[3] = {0, 0, 0};
  int k_ = 0;
};

void write_vtu(Sink& out, const SurfaceMesh& m, bool binary) {
  const std::size_t np = m.points.size(), nt = m.triangles.size();
  out.put(
      "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
      "byte_order=\"LittleEndian\" header_type=\"UInt32\">\n<UnstructuredGrid>\n<Piece "
      "NumberOfPoints=\"");
  out.num(np);
  out.put("\" NumberOfCells=\"");
  out.num(nt);
  out.put("\">\n");
  // One array: n values produced by value(i, sink) in ASCII or by value(i, base64).
  auto array = [&](const char* type, const char* name, int components, std::size_t n,
                   std::size_t value_bytes, auto ascii_value, auto binary_value) {
    out.put("<DataArray type=\"");
    out.put(type);
    out.put("\" Name=\"");
    out.put(name);
    out.put("\" NumberOfComponents=\"");
    out.num(components);
    out.put(binary ? "\" format=\"binary\">\n" : "\" format=\"ascii\">\n");
    if (binary) {
      Base64 b(out);
      b.le(static_cast<std::uint32_t>(n * value_bytes));
      for (std::size_t i = 0; i < n; ++i) binary_value(i, b);
      b.finish();
      out.put('\n');
    } else {
      for (std::size_t i = 0; i < n; ++i) ascii_value(i);
    }
    out.put("</DataArray>\n");
  };
  out.put("<Points>\n");
  array(
      "Float64", "Points", 3, np, 24,
      [&](std::size_t i) {
        out.xyz(m.points[i]);
        out.put('\n');
      },
      [&](std::size_t i, Base64& b) {
        b.le(m.points[i].x);
        b.le(m.points[i].y);
        b.le(m.points[i].z);
      });
  out.put("</Points>\n<Cells>\n");
  array(
      "Int32", "connectivity", 1, nt, 12,
      [&](std::size_t t) {
        const auto& tri = m.triangles[t];
        out.line({tri[0], tri[1], tri[2]});
      },
      [&](std::size_t t, Base64& b) {
        for (NodeId v : m.triangles[t]) b.le(static_cast<std::int32_t>(v));
      });
  array(
      "Int32", "offsets", 1, nt, 4,
      [&](std::size_t t) { out.line({static_cast<std::int64_t>(3 * (t + 1))}); },
      [&](std::size_t t, Base64& b) { b.le(static_cast<std::int32_t>(3 * (t + 1))); });
  constexpr std::uint8_t kVtkTriangle = 5;
  array(
      "UInt8", "types", 1, nt, 1, [&](std::size_t) { out.line({kVtkTriangle}); },
      [&](std::size_t, Base64& b) { b.le(kVtkTriangle); });
  out.put("</Cells>\n<CellData Scalars=\"face_id\">\n");
  array(
      "Int32", "face_id", 1, nt, 4, [&](std::size_t t) { out.line({m.triangle_face[t]}); },
      [&](std::size_t t, Base64& b) { b.le(static_cast<std::int32_t>(m.triangle_face[t])); });
  out.put("</CellData>\n</Piece>\n</UnstructuredGrid>\n</VTKFile>\n");
}

}  // namespace

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

WriteResult write_mesh(const surface::SurfaceMesh& m, const geom::Model* model,
                       const std::string& path, const WriteOptions& opts) {
  auto fail = [&](const std::string& why) { return WriteResult{false, path + ": " + why}; };

  const std::optional<MeshFormat> fmt = opts.format ? opts.format : format_from_path(path);
  if (!fmt) return fail("unknown mesh file extension (known: " + known_mesh_extensions() + ")");
  const MeshFormat f = *fmt;
  const bool binary_only = f == MeshFormat::Meshb || f == MeshFormat::Drc || f == MeshFormat::Glb;
  const bool has_binary = binary_only || f == MeshFormat::Msh41 || f == MeshFormat::Stl ||
                          f == MeshFormat::Ply || f == MeshFormat::Vtk || f == MeshFormat::Vtu;
  const bool binary =
      opts.encoding == Encoding::Binary ||
      (opts.encoding == Encoding::Default &&
       (binary_only || f == MeshFormat::Stl || f == MeshFormat::Ply || f == MeshFormat::Vtu));
  if (binary && !has_binary)
    return fail("there is no binary form of " + std::string(format_name(f)) + " here");
  if (binary_only && opts.encoding == Encoding::Ascii)
    return fail(std::string(format_name(f)) + " has no ASCII form");
  // Legacy VTK, VTU, binary STL, PLY and .meshb count in 32 bits.
  const std::size_t int32_max = static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max());
  if ((f == MeshFormat::Vtk || f == MeshFormat::Vtu) && 4 * m.triangles.size() > int32_max)
    return fail("too many triangles for VTK (32-bit sizes)");
  if (f == MeshFormat::Stl && m.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    return fail("too many triangles for STL (32-bit count)");
  if ((f == MeshFormat::Ply || f == MeshFormat::Meshb) && m.triangles.size() > int32_max)
    return fail("too many triangles for 32-bit indices");
  if (f == MeshFormat::Drc || f == MeshFormat::Glb) {
    if (opts.draco_bits < 1 || opts.draco_bits > 30)
      return fail("Draco quantization bits must be 1..30");
    if (opts.draco_level < 0 || opts.draco_level > 10)
      return fail("Draco compression level must be 0..10");
    if (opts.draco_normal_bits < 1 || opts.draco_normal_bits > 30)
      return fail("Draco normal bits must be 1..30");
  }

  Counts counts;
  if (std::string why = validate(m, model, counts); !why.empty()) return fail(why);

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
  switch (f) {
    case MeshFormat::Msh41:
      write_msh41(out, m, model, counts, phys, binary);
      break;
    case MeshFormat::Msh22:
      write_msh22(out, m, phys);
      break;
    case MeshFormat::Medit:
      write_medit(out, m);
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
      write_vtu(out, m, binary);
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
  out.flush();
  if (out.error() != 0) return fail(std::string("write failed: ") + std::strerror(out.error()));
  if (std::string why = tmp.commit(path); !why.empty()) return fail(why);
  return {true, ""};
}

}  // namespace uvmesh::io
