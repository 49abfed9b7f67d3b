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
#include <memory>
#include <system_error>
#include <vector>

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
      std::string tmp = dest + ".tmp-" + std::to_string(::getpid()) + "-" +
                        std::to_string(counter.fetch_add(1));
      // 0666: the umask applies as for any new file.
      const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
      if (fd >= 0) {
        fd_ = fd;
        tmp_ = std::move(tmp);
        return "";
      }
      if (errno != EEXIST) return std::string("cannot create a file there: ") + std::strerror(errno);
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
  auto note = [](std::size_t& n, geom::Id id) { n = std::max(n, static_cast<std::size_t>(id) + 1); };
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
      return "invalid mesh: segment " + std::to_string(s) + " has a node index out of range or no edge";
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

// Nodes grouped by entity: keys are vertices, then edges, then faces, so iterating the
// keys in order gives Gmsh's usual dimension-then-tag block order.
struct NodeGroups {
  Buckets b;
  std::size_t base[3];
  std::size_t key(int dim, std::size_t id) const { return base[dim] + id; }
};

void write_msh41(Sink& out, const SurfaceMesh& m, const geom::Model* model, const Counts& c) {
  const std::size_t np = m.points.size();
  NodeGroups ng;
  ng.base[0] = 0;
  ng.base[1] = c.vertices;
  ng.base[2] = c.vertices + c.edges;
  ng.b = bucket(np, c.vertices + c.edges + c.faces,
                [&](std::size_t i) { return ng.key(m.point_dim[i], static_cast<std::size_t>(m.point_entity[i])); });
  const Buckets segs = bucket(m.segments.size(), c.edges,
                              [&](std::size_t s) { return static_cast<std::size_t>(m.segments[s].edge); });
  const Buckets tris = bucket(m.triangles.size(), c.faces,
                              [&](std::size_t t) { return static_cast<std::size_t>(m.triangle_face[t]); });

  // An entity is written when it carries nodes or elements, so that every tag the file
  // mentions (bounding entities included) is defined in it.
  auto has_point = [&](std::size_t v) { return ng.b.size(ng.key(0, v)) > 0; };
  auto has_curve = [&](std::size_t e) { return ng.b.size(ng.key(1, e)) > 0 || segs.size(e) > 0; };
  auto has_surface = [&](std::size_t f) { return ng.b.size(ng.key(2, f)) > 0 || tris.size(f) > 0; };

  // Bounding boxes from the mesh (the file describes the mesh; a model's curves need not
  // give boxes cheaply): an entity's own nodes plus the nodes of its elements.
  std::vector<geom::Box3> curve_box(c.edges), surface_box(c.faces);
  for (std::size_t i = 0; i < np; ++i) {
    if (m.point_dim[i] == 1) curve_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
    if (m.point_dim[i] == 2) surface_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
  }
  for (const auto& s : m.segments) {
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.a)]);
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.b)]);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (NodeId v : m.triangles[t])
      surface_box[static_cast<std::size_t>(m.triangle_face[t])].add(m.points[static_cast<std::size_t>(v)]);

  // Bounding points of each curve, begin vertex +tag and end vertex -tag (Gmsh's own
  // convention in its MSH4 entity writer; a closed curve lists its vertex twice). With a
  // model, the edge's v0/v1; without, the model-vertex nodes at the ends of its segment
  // chain (segments are in curve-parameter order).
  std::vector<std::vector<std::int64_t>> curve_points(c.edges);
  for (std::size_t e = 0; e < c.edges; ++e) {
    if (!has_curve(e)) continue;
    auto add = [&](geom::Id v, int sign) {
      if (v >= 0 && static_cast<std::size_t>(v) < c.vertices && has_point(static_cast<std::size_t>(v)))
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
          if (f < 0 || static_cast<std::size_t>(f) >= c.faces || !has_surface(static_cast<std::size_t>(f))) continue;
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
  out.put("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Entities\n");
  out.line({i64(n_points), i64(n_curves), i64(n_surfaces), i64(volumes.size())});
  // Curve / surface / volume line: tag, bbox, no physical tags, the bounding entities.
  auto entity = [&](std::int64_t tag, const geom::Box3& box, const std::vector<std::int64_t>& bounding) {
    out.num(tag);
    out.put(' ');
    out.xyz(box.lo);
    out.put(' ');
    out.xyz(box.hi);
    out.put(" 0 ");
    out.num(bounding.size());
    for (std::int64_t t : bounding) {
      out.put(' ');
      out.num(t);
    }
    out.put('\n');
  };
  // Point: tag x y z numPhysicalTags.
  for (std::size_t v = 0; v < c.vertices; ++v) {
    if (!has_point(v)) continue;
    out.num(one_based(v));
    out.put(' ');
    out.xyz(m.points[static_cast<std::size_t>(ng.b.order[ng.b.first[ng.key(0, v)]])]);
    out.put(" 0\n");
  }
  for (std::size_t e = 0; e < c.edges; ++e)
    if (has_curve(e)) entity(one_based(e), curve_box[e], curve_points[e]);
  for (std::size_t f = 0; f < c.faces; ++f)
    if (has_surface(f)) entity(one_based(f), surface_box[f], surface_curves[f]);
  for (const Volume& vol : volumes) entity(vol.tag, vol.box, vol.surfaces);
  out.put("$EndEntities\n");

  // $Nodes: numBlocks numNodes minTag maxTag, then per block "dim tag parametric n",
  // the n node tags, the n coordinate lines. Node tag = index + 1 whatever the block order.
  const std::size_t num_keys = ng.b.first.size() - 1;
  std::size_t node_blocks = 0;
  for (std::size_t k = 0; k < num_keys; ++k) node_blocks += ng.b.size(k) > 0;
  out.put("$Nodes\n");
  out.line({i64(node_blocks), i64(np), np > 0 ? 1 : 0, i64(np)});
  for (int dim = 0; dim < 3; ++dim) {
    const std::size_t n_ent = dim == 0 ? c.vertices : dim == 1 ? c.edges : c.faces;
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = ng.key(dim, id);
      if (ng.b.size(k) == 0) continue;
      out.line({dim, one_based(id), 0, i64(ng.b.size(k))});  // parametric = 0
      ng.b.each(k, [&](std::size_t i) {
        out.num(one_based(i));
        out.put('\n');
      });
      ng.b.each(k, [&](std::size_t i) {
        out.xyz(m.points[i]);
        out.put('\n');
      });
    }
  }
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
  out.line({i64(elem_blocks), i64(n_elems), n_elems > 0 ? 1 : 0, i64(n_elems)});
  // One block per entity that has elements: "dim tag type n", then n lines
  // "elementTag nodeTag...". Element tags run on across blocks.
  std::int64_t tag = 1;
  auto node = [&](std::size_t v) {
    out.put(' ');
    out.num(one_based(v));
  };
  auto blocks = [&](int dim, int type, const Buckets& b, std::size_t key0, std::size_t n_ent,
                    auto nodes_of) {
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = key0 + id;
      if (b.size(k) == 0) continue;
      out.line({dim, one_based(id), type, i64(b.size(k))});
      b.each(k, [&](std::size_t i) {
        out.num(tag++);
        nodes_of(i);
        out.put('\n');
      });
    }
  };
  blocks(0, 15, ng.b, ng.base[0], c.vertices, [&](std::size_t i) { node(i); });
  blocks(1, 1, segs, 0, c.edges, [&](std::size_t s) {
    node(static_cast<std::size_t>(m.segments[s].a));
    node(static_cast<std::size_t>(m.segments[s].b));
  });
  blocks(2, 2, tris, 0, c.faces, [&](std::size_t t) {
    for (NodeId v : m.triangles[t]) node(static_cast<std::size_t>(v));
  });
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
      out.line({one_based(tri[0]), one_based(tri[1]), one_based(tri[2]), one_based(m.triangle_face[t])});
    }
  }
  out.put("\nEnd\n");
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
  const Buckets tris = bucket(m.triangles.size(), c.faces,
                              [&](std::size_t t) { return static_cast<std::size_t>(m.triangle_face[t]); });
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

}  // namespace

// ----------------------------------------------------------------------------- API

std::optional<MeshFormat> format_from_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return static_cast<char>(std::tolower(ch)); });
  if (ext == ".msh") return MeshFormat::Msh41;
  if (ext == ".mesh") return MeshFormat::Medit;
  if (ext == ".stl") return MeshFormat::Stl;
  if (ext == ".obj") return MeshFormat::Obj;
  if (ext == ".vtk") return MeshFormat::Vtk;
  return std::nullopt;
}

std::string known_mesh_extensions() { return ".msh, .mesh, .stl, .obj, .vtk"; }

std::string_view format_name(MeshFormat f) {
  switch (f) {
    case MeshFormat::Msh41: return "msh41";
    case MeshFormat::Medit: return "medit";
    case MeshFormat::Stl: return "stl";
    case MeshFormat::Obj: return "obj";
    case MeshFormat::Vtk: return "vtk";
  }
  return "?";
}

WriteResult write_mesh(const surface::SurfaceMesh& m, const geom::Model* model,
                       const std::string& path, const WriteOptions& opts) {
  auto fail = [&](const std::string& why) { return WriteResult{false, path + ": " + why}; };

  const std::optional<MeshFormat> fmt = opts.format ? opts.format : format_from_path(path);
  if (!fmt) return fail("unknown mesh file extension (known: " + known_mesh_extensions() + ")");
  const bool binary = opts.encoding == Encoding::Binary ||
                      (opts.encoding == Encoding::Default && *fmt == MeshFormat::Stl);
  if (binary && *fmt != MeshFormat::Stl && *fmt != MeshFormat::Vtk)
    return fail("binary encoding is written for STL and VTK only, not " +
                std::string(format_name(*fmt)));
  // Legacy VTK and binary STL count in 32 bits.
  if (*fmt == MeshFormat::Vtk && 4 * m.triangles.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
    return fail("too many triangles for legacy VTK (32-bit sizes)");
  if (*fmt == MeshFormat::Stl && m.triangles.size() > std::numeric_limits<std::uint32_t>::max())
    return fail("too many triangles for STL (32-bit count)");

  Counts counts;
  if (std::string why = validate(m, model, counts); !why.empty()) return fail(why);

  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) return fail("is a directory");

  TempFile tmp;
  if (std::string why = tmp.open(path); !why.empty()) return fail(why);
  Sink out(tmp.fd());
  switch (*fmt) {
    case MeshFormat::Msh41: write_msh41(out, m, model, counts); break;
    case MeshFormat::Medit: write_medit(out, m); break;
    case MeshFormat::Stl:
      if (binary) write_stl_binary(out, m);
      else write_stl_ascii(out, m);
      break;
    case MeshFormat::Obj: write_obj(out, m, counts); break;
    case MeshFormat::Vtk: write_vtk(out, m, binary); break;
  }
  out.flush();
  if (out.error() != 0) return fail(std::string("write failed: ") + std::strerror(out.error()));
  if (std::string why = tmp.commit(path); !why.empty()) return fail(why);
  return {true, ""};
}

}  // namespace uvmesh::io
