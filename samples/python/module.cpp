// uvmesh._uvmesh: the compiled half of the Python module (uvmesh/__init__.py is the
// other: keyword signatures, typed exceptions, meshio).
//
// Everything a call needs lives in the objects it returns: no module state, no signal
// handlers (OCC's are process-wide and break threads), nothing printed. Reading, meshing,
// checking and writing run with the GIL released, so two threads mesh two models at once;
// the arrays are views of the C++ vectors, kept alive by the Mesh they came from.
#include <pybind11/functional.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>
#include <pybind11/stl/filesystem.h>

#include <chrono>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "uvmesh/geom/curve.h"
#include "uvmesh/geom/surface.h"
#include "uvmesh/io/job.h"
#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/io/report.h"
#include "uvmesh/surface/tet_mesh.h"

namespace py = pybind11;
using namespace uvmesh;

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// ---- keyword options -> io::MeshJobOptions (the one definition of the defaults: a
// keyword left out keeps MeshJobOptions' value).

using Setter = std::function<void(io::MeshJobOptions&, py::handle)>;

std::map<geom::Id, double> id_sizes(py::handle v) {
  std::map<geom::Id, double> m;
  for (auto [k, h] : v.cast<py::dict>()) m[k.cast<geom::Id>()] = h.cast<double>();
  return m;
}

// Options that change how a file is read: only where a path is given.
const std::map<std::string, Setter>& read_setters() {
  // threads is also a meshing option (mesh_setters): a path given to mesh() is read with
  // the threads it meshes with, as the CLI does.
  static const std::map<std::string, Setter> s = {
      {"heal", [](auto& o, py::handle v) { o.read.heal = v.cast<bool>(); }},
      {"units", [](auto& o, py::handle v) { o.read.units = v.cast<std::string>(); }},
      {"conform", [](auto& o, py::handle v) { o.read.conform = v.cast<bool>(); }},
      {"any_extension", [](auto& o, py::handle v) { o.read.trust_content = v.cast<bool>(); }},
      {"partial", [](auto& o, py::handle v) { o.read.allow_partial = v.cast<bool>(); }},
      {"check", [](auto& o, py::handle v) { o.read.check_validity = v.cast<bool>(); }},
      {"sew_tol", [](auto& o, py::handle v) { o.read.sew_rel_tol = v.cast<double>(); }},
      {"sew_max_tol", [](auto& o, py::handle v) { o.read.sew_max_rel_tol = v.cast<double>(); }},
      {"scheme", [](auto& o, py::handle v) { o.scheme = v.cast<std::string>(); }},
      {"boundary_interp", [](auto& o, py::handle v) { o.boundary_interp = v.cast<std::string>(); }},
      {"threads", [](auto& o, py::handle v) { o.threads = v.cast<int>(); }},
  };
  return s;
}

const std::map<std::string, Setter>& mesh_setters() {
  static const std::map<std::string, Setter> s = {
      {"hmax", [](auto& o, py::handle v) { o.hmax = v.cast<double>(); }},
      {"hmax_rel", [](auto& o, py::handle v) { o.hmax_rel = v.cast<double>(); }},
      {"hmin", [](auto& o, py::handle v) { o.hmin = v.cast<double>(); }},
      {"chordal", [](auto& o, py::handle v) { o.chordal = v.cast<double>(); }},
      {"angle", [](auto& o, py::handle v) { o.angle_deg = v.cast<double>(); }},
      {"grad", [](auto& o, py::handle v) { o.grad = v.cast<double>(); }},
      {"aniso", [](auto& o, py::handle v) { o.aniso = v.cast<double>(); }},
      {"min_feature", [](auto& o, py::handle v) { o.min_feature = v.cast<double>(); }},
      {"feature_angle", [](auto& o, py::handle v) { o.feature_angle_deg = v.cast<double>(); }},
      {"keep_topology", [](auto& o, py::handle v) { o.keep_topology = v.cast<bool>(); }},
      {"face_sizes", [](auto& o, py::handle v) { o.face_size = id_sizes(v); }},
      {"edge_sizes", [](auto& o, py::handle v) { o.edge_size = id_sizes(v); }},
      {"size_file", [](auto& o, py::handle v) { o.size_file = v.cast<std::string>(); }},
      {"threads", [](auto& o, py::handle v) { o.threads = v.cast<int>(); }},
      {"face_time_limit", [](auto& o, py::handle v) { o.face_time_limit = v.cast<double>(); }},
      {"optimize3d", [](auto& o, py::handle v) { o.optimize3d = v.cast<bool>(); }},
      {"frontal", [](auto& o, py::handle v) { o.frontal = v.cast<bool>(); }},
      {"self_intersections", [](auto& o, py::handle v) { o.self_intersections = v.cast<bool>(); }},
      {"volume", [](auto& o, py::handle v) { o.volume = v.cast<bool>(); }},
  };
  return s;
}

// Applies the keywords (None: the default); TypeError for an unknown keyword or a value
// of the wrong type, ValueError (the CLI's message) for a bad value.
void apply_options(io::MeshJobOptions& o, const py::dict& kw, bool reading, bool meshing) {
  for (auto [k, v] : kw) {
    if (v.is_none()) continue;
    const std::string key = k.cast<std::string>();
    const Setter* set = nullptr;
    if (reading && read_setters().count(key)) set = &read_setters().at(key);
    if (meshing && mesh_setters().count(key)) set = &mesh_setters().at(key);
    if (!set) {
      if (!reading && read_setters().count(key))
        throw py::value_error(key +
                              "= applies when reading a file: pass a path, or give it to "
                              "uvmesh.read()");
      throw py::type_error("unexpected keyword argument '" + key + "'");
    }
    try {
      (*set)(o, v);
    } catch (const py::cast_error&) {
      throw py::type_error(key + "=: wrong type " + std::string(py::str(v.get_type())));
    }
  }
  // Python callers get no OCC signal handlers: they are process-wide.
  o.read.install_signal_handlers = false;
  if (std::string e = io::check_options(o); !e.empty()) throw py::value_error(e);
}

// ---- Model

struct Model {
  std::shared_ptr<const io::ReadResult> rr;
  std::string path;
  double read_seconds = 0;
};

// (Model or None, error): the Python side raises CadReadError with the error.
py::tuple read_path(const std::string& path, const py::dict& kw) {
  io::MeshJobOptions o;
  apply_options(o, kw, true, false);
  auto rr = std::make_shared<io::ReadResult>();
  const auto t0 = Clock::now();
  {
    py::gil_scoped_release nogil;
    *rr = io::read_model(path, o);
  }
  if (!rr->ok) return py::make_tuple(py::none(), rr->error);
  return py::make_tuple(Model{rr, path, since(t0)}, py::none());
}

py::list face_list(const geom::Model& m) {
  py::list l;
  for (std::size_t i = 0; i < m.faces.size(); ++i) {
    const geom::Face& f = m.faces[i];
    l.append(py::dict(py::arg("id") = i, py::arg("kind") = std::string(geom::to_string(f.kind)),
                      py::arg("name") = f.name, py::arg("degenerate") = f.degenerate));
  }
  return l;
}

py::list edge_list(const geom::Model& m) {
  py::list l;
  for (std::size_t i = 0; i < m.edges.size(); ++i) {
    const geom::Edge& e = m.edges[i];
    const std::string kind = e.curve ? std::string(geom::to_string(e.curve->kind())) : "none";
    l.append(py::dict(py::arg("id") = i, py::arg("kind") = kind,
                      py::arg("vertices") = py::make_tuple(e.v0, e.v1),
                      py::arg("length") = e.length, py::arg("degenerate") = e.degenerate));
  }
  return l;
}

py::list solid_list(const geom::Model& m) {
  py::list l;
  for (std::size_t i = 0; i < m.solids.size(); ++i) {
    std::vector<geom::Id> faces;
    for (geom::Id s : m.solids[i].shells)
      faces.insert(faces.end(), m.shells[s].faces.begin(), m.shells[s].faces.end());
    l.append(
        py::dict(py::arg("id") = i, py::arg("name") = m.solids[i].name, py::arg("faces") = faces));
  }
  return l;
}

py::list healing_list(const io::ReadReport& r) {
  py::list l;
  for (const io::HealStep& h : r.healing)
    l.append(py::dict(py::arg("name") = h.name, py::arg("applied") = h.applied,
                      py::arg("detail") = h.detail));
  return l;
}

void bind_model(py::module_& m) {
  py::class_<Model>(m, "Model", "A CAD model or subdivision cage read by uvmesh.read().")
      .def_property_readonly("path", [](const Model& s) { return s.path; })
      .def_property_readonly("format", [](const Model& s) { return s.rr->model.format; })
      .def_property_readonly("units", [](const Model& s) { return s.rr->model.units; })
      .def_property_readonly("counts",
                             [](const Model& s) {
                               const geom::Model& g = s.rr->model;
                               return py::dict(py::arg("faces") = g.faces.size(),
                                               py::arg("edges") = g.edges.size(),
                                               py::arg("vertices") = g.vertices.size(),
                                               py::arg("shells") = g.shells.size(),
                                               py::arg("solids") = g.solids.size());
                             })
      .def_property_readonly("faces", [](const Model& s) { return face_list(s.rr->model); })
      .def_property_readonly("edges", [](const Model& s) { return edge_list(s.rr->model); })
      .def_property_readonly("solids", [](const Model& s) { return solid_list(s.rr->model); })
      .def_property_readonly("bbox",
                             [](const Model& s) {
                               const geom::Box3& b = s.rr->model.bbox;
                               return py::make_tuple(py::make_tuple(b.lo.x, b.lo.y, b.lo.z),
                                                     py::make_tuple(b.hi.x, b.hi.y, b.hi.z));
                             })
      .def_property_readonly("warnings", [](const Model& s) { return s.rr->report.warnings; })
      .def_property_readonly("healing", [](const Model& s) { return healing_list(s.rr->report); })
      .def_property_readonly("read_seconds", [](const Model& s) { return s.read_seconds; })
      .def("__repr__", [](const Model& s) {
        return "<uvmesh.Model '" + s.path + "': " + std::to_string(s.rr->model.faces.size()) +
               " faces, " + std::to_string(s.rr->model.solids.size()) + " solids>";
      });
}

// ---- Mesh

struct Mesh {
  std::shared_ptr<const io::ReadResult> rr;
  std::string model_path;
  double read_seconds = 0;
  io::MeshJobOptions options;  // without its progress hook
  io::MeshRun run;
  std::optional<std::string> report;  // JSON, made on first use
  std::mutex report_mu;               // two threads asking for it at once make it once
  std::string written;                // the last path written
  double write_seconds = 0;
};

// The Python progress callback behind MeshJobOptions::progress: called from TBB workers,
// it takes the GIL; the first exception it raises is kept, later calls are skipped, and
// mesh() raises it once meshing is over (the mesher has no way to stop early).
struct Progress {
  py::function fn;
  std::optional<py::error_already_set> error;
  void operator()(int done, int total) {
    py::gil_scoped_acquire gil;
    if (error) return;
    try {
      fn(done, total);
    } catch (py::error_already_set& e) {
      error = std::move(e);
    }
  }
};

std::unique_ptr<Mesh> mesh_model(const Model& model, const py::dict& kw,
                                 const py::object& progress) {
  auto out = std::make_unique<Mesh>();
  io::MeshJobOptions& o = out->options;
  apply_options(o, kw, false, true);
  out->rr = model.rr, out->model_path = model.path, out->read_seconds = model.read_seconds;
  Progress hook;
  if (!progress.is_none()) {
    if (!PyCallable_Check(progress.ptr())) throw py::type_error("progress= must be callable");
    hook.fn = progress.cast<py::function>();
    o.progress = [&hook](int done, int total) { hook(done, total); };
  }
  {
    py::gil_scoped_release nogil;
    out->run = io::mesh_job(out->rr->model, o);
  }
  o.progress = nullptr;  // it points at `hook`, gone when this call returns
  out->run.asked.progress = nullptr;
  if (hook.error) throw std::move(*hook.error);
  if (!out->run.error.empty()) throw py::value_error(out->run.error);
  return out;
}

// A read-only view of `n` rows of `cols` values of type T starting at `first`, `stride`
// bytes apart, owned by `owner` (the Mesh).
template <class T>
py::array view(const void* first, std::size_t n, std::size_t cols, std::size_t stride,
               py::handle owner) {
  std::vector<py::ssize_t> shape{static_cast<py::ssize_t>(n)},
      strides{static_cast<py::ssize_t>(stride)};
  if (cols > 1) shape.push_back(static_cast<py::ssize_t>(cols)), strides.push_back(sizeof(T));
  // An empty vector may have no storage; numpy still wants a pointer to view.
  static const T none[3] = {};
  py::array a(py::dtype::of<T>(), shape, strides, n ? static_cast<const T*>(first) : none, owner);
  // Read-only: the mesh's arrays describe one mesh together (indices into points).
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

using Segment = surface::SurfaceMesh::Segment;
static_assert(sizeof(geom::Vec3) == 3 * sizeof(double));
static_assert(sizeof(std::array<surface::NodeId, 3>) == 3 * sizeof(std::int32_t));
static_assert(sizeof(Segment) == 3 * sizeof(std::int32_t) && offsetof(Segment, edge) == 8);

// A property: the view of one of the mesh's vectors (`cols` values of T per element, from
// the element's start; a segment's two nodes, not its curve id).
template <class T, class V>
auto vector_view(std::vector<V> surface::SurfaceMesh::*member, std::size_t cols) {
  return [member, cols](py::object self) {
    const std::vector<V>& v = self.cast<const Mesh&>().run.result.mesh.*member;
    return view<T>(v.data(), v.size(), cols, sizeof(V), self);
  };
}

static_assert(sizeof(std::array<surface::NodeId, 4>) == 4 * sizeof(std::int32_t));
static_assert(sizeof(geom::Id) == sizeof(std::int32_t));

// The same for the tetrahedral mesh of volume=True (empty arrays without it).
template <class T, class V>
auto tet_view(std::vector<V> surface::TetMesh::*member, std::size_t cols) {
  return [member, cols](py::object self) {
    const std::vector<V>& v = self.cast<const Mesh&>().run.volume.mesh.*member;
    return view<T>(v.data(), v.size(), cols, sizeof(V), self);
  };
}

const std::string& report_of(Mesh& s) {
  py::gil_scoped_release nogil;  // before the lock: its holder may wait for the GIL
  std::lock_guard<std::mutex> lock(s.report_mu);
  if (!s.report) {
    // "total" = reading + meshing + writing + the checks, as in a CLI run.
    const auto start =
        Clock::now() - std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(
                           s.read_seconds + s.run.seconds + s.write_seconds));
    s.report = io::mesh_report(s.options, *s.rr, s.run,
                               {s.model_path, s.written, start, s.read_seconds, s.write_seconds})
                   .dump();
  }
  return *s.report;
}

// Writes the mesh; ValueError for a bad format or encoding, OSError when the file cannot
// be written (the writers' message).
void write(Mesh& s, const std::filesystem::path& file, const std::optional<std::string>& format,
           bool ascii, bool binary, std::optional<bool> physical_groups,
           std::optional<int> draco_bits, std::optional<int> draco_level, bool glb_per_face) {
  const std::string path = file.string();
  io::WriteOptions wo;
  if (format) {
    wo.format = io::format_from_name(*format);
    if (!wo.format)
      throw py::value_error("unknown format '" + *format + "' (known: " + io::known_format_names() +
                            ")");
  } else if (!io::format_from_path(path)) {
    throw py::value_error(path + ": unknown mesh extension (known: " + io::known_mesh_extensions() +
                          ")");
  }
  if (s.run.volume.requested) {
    const io::MeshFormat fmt = wo.format ? *wo.format : *io::format_from_path(path);
    if (!io::carries_tetrahedra(fmt))
      throw py::value_error(path + ": a mesh with tetrahedra is written to .msh, .mesh or .vtu");
  }
  if (ascii && binary) throw py::value_error("ascii and binary exclude each other");
  wo.encoding = ascii ? io::Encoding::Ascii : binary ? io::Encoding::Binary : io::Encoding::Default;
  if (physical_groups) wo.physical_groups = *physical_groups;
  if (draco_bits) wo.draco_bits = *draco_bits;
  if (draco_level) wo.draco_level = *draco_level;
  if (glb_per_face) wo.glb_groups = io::GlbGroups::Face;
  io::WriteResult wr;
  const auto t0 = Clock::now();
  {
    py::gil_scoped_release nogil;
    if (s.run.volume.requested) wo.volume = &s.run.volume.mesh;
    wr = io::write_mesh(s.run.result.mesh, &s.rr->model, path, wo);
  }
  if (!wr.ok) {
    PyErr_SetString(PyExc_OSError, wr.error.c_str());
    throw py::error_already_set();
  }
  std::lock_guard<std::mutex> lock(s.report_mu);
  s.written = path;  // the report names it, as --report names -o
  s.write_seconds = since(t0);
  s.report.reset();
}

py::list failures(const std::vector<surface::FaceFailure>& v) {
  py::list l;
  for (const auto& f : v) l.append(py::make_tuple(f.face, f.reason));
  return l;
}

void bind_mesh(py::module_& m) {
  py::class_<Mesh>(m, "Mesh", "A surface mesh made by uvmesh.mesh().")
      .def_property_readonly("points", vector_view<double>(&surface::SurfaceMesh::points, 3))
      .def_property_readonly("triangles",
                             vector_view<std::int32_t>(&surface::SurfaceMesh::triangles, 3))
      .def_property_readonly("face_ids",
                             vector_view<std::int32_t>(&surface::SurfaceMesh::triangle_face, 1))
      .def_property_readonly("edges", vector_view<std::int32_t>(&surface::SurfaceMesh::segments, 2))
      .def_property_readonly("edge_curve_ids",
                             [](py::object self) {
                               const auto& s = self.cast<const Mesh&>().run.result.mesh.segments;
                               return view<std::int32_t>(s.empty() ? nullptr : &s[0].edge, s.size(),
                                                         1, sizeof(Segment), self);
                             })
      .def_property_readonly("point_dims",
                             vector_view<std::int8_t>(&surface::SurfaceMesh::point_dim, 1))
      .def_property_readonly("point_entities",
                             vector_view<std::int32_t>(&surface::SurfaceMesh::point_entity, 1))
      .def_property_readonly("tets", tet_view<std::int32_t>(&surface::TetMesh::tets, 4))
      .def_property_readonly("tet_solids", tet_view<std::int32_t>(&surface::TetMesh::tet_solid, 1))
      .def_property_readonly("volume_points", tet_view<double>(&surface::TetMesh::points, 3))
      .def_property_readonly("failed_solids", [](const Mesh& s) { return s.run.volume.failed; })
      .def_property_readonly("_report_json", [](Mesh& s) { return report_of(s); })
      .def_property_readonly("failed_faces",
                             [](const Mesh& s) { return failures(s.run.result.failed); })
      .def_property_readonly("degenerate_faces",
                             [](const Mesh& s) { return failures(s.run.result.degenerate); })
      .def_property_readonly("collapsed_faces",
                             [](const Mesh& s) { return failures(s.run.result.collapsed); })
      .def_property_readonly("warnings", [](const Mesh& s) { return s.run.result.warnings; })
      .def_property_readonly("model",
                             [](const Mesh& s) {
                               return Model{s.rr, s.model_path, s.read_seconds};
                             })
      .def("write", &write, py::arg("path"), py::kw_only(), py::arg("format") = py::none(),
           py::arg("ascii") = false, py::arg("binary") = false,
           py::arg("physical_groups") = py::none(), py::arg("draco_bits") = py::none(),
           py::arg("draco_level") = py::none(), py::arg("glb_per_face") = false,
           "Writes the mesh in any format `uvmesh mesh -o` writes (from the extension, or "
           "format=).")
      .def("__repr__", [](const Mesh& s) {
        return "<uvmesh.Mesh: " + std::to_string(s.run.result.mesh.points.size()) + " points, " +
               std::to_string(s.run.result.mesh.triangles.size()) + " triangles>";
      });
}

// uvmesh.tet_quality(): the report's volume quality (io::tet_report_json, the measures of
// surface/tet_mesh.h) of any tetrahedra, e.g. another mesher's, so that a comparison uses
// the one definition of the measures rather than a copy of them.
std::string tet_quality(
    const py::array_t<double, py::array::c_style | py::array::forcecast>& points,
    const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& tets,
    const py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>& solids) {
  if (points.ndim() != 2 || points.shape(1) != 3)
    throw py::value_error("points must be an N x 3 array");
  if (tets.ndim() != 2 || tets.shape(1) != 4) throw py::value_error("tets must be an M x 4 array");
  if (solids.ndim() != 1 || solids.shape(0) != tets.shape(0))
    throw py::value_error("tet_solids must have one entry per tetrahedron");
  surface::TetMesh v;
  const auto p = points.unchecked<2>();
  for (py::ssize_t i = 0; i < p.shape(0); ++i) v.points.push_back({p(i, 0), p(i, 1), p(i, 2)});
  v.surface_points = v.points.size();
  const auto t = tets.unchecked<2>();
  const auto s = solids.unchecked<1>();
  for (py::ssize_t i = 0; i < t.shape(0); ++i) {
    std::array<surface::NodeId, 4> k{};
    for (int j = 0; j < 4; ++j) {
      if (t(i, j) < 0 || t(i, j) >= p.shape(0))
        throw py::value_error("tetrahedron " + std::to_string(i) +
                              " has a point index out of range");
      k[j] = static_cast<surface::NodeId>(t(i, j));
    }
    v.tets.push_back(k);
    v.tet_solid.push_back(static_cast<geom::Id>(s(i)));
  }
  py::gil_scoped_release nogil;
  return io::tet_report_json(v).dump();
}

}  // namespace

PYBIND11_MODULE(_uvmesh, m) {
  m.doc() = "uvmesh's compiled core; use the `uvmesh` package.";
  bind_model(m);
  bind_mesh(m);
  m.def("_read", &read_path, py::arg("path"), py::arg("options"));
  m.def("_mesh", &mesh_model, py::arg("model"), py::arg("options"), py::arg("progress"));
  m.def("_read_keywords", [] {
    std::vector<std::string> k;
    for (const auto& [key, set] : read_setters()) k.push_back(key);
    return k;
  });
  m.def("_mesh_extensions", &io::known_mesh_extensions);
  m.def("_tet_quality", &tet_quality, py::arg("points"), py::arg("tets"), py::arg("tet_solids"));
}
