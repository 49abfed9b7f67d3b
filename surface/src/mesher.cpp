// mesh_model: the three stages of the data flow in docs/ARCHITECTURE.md -- curves first,
// faces in parallel, stitch by index -- with per-face failure isolation. The steps live in
// their own files (model_run.h lists them); this file holds the size fields, the edge
// checks and the list of steps.
#include "uvmesh/surface/mesher.h"

#include <algorithm>
#include <numbers>
#include <sstream>

#include "model_run.h"

namespace uvmesh::surface {

param::SizeSpec default_size(const geom::Model& m) {
  const double D = m.bbox.diagonal() > 0 ? m.bbox.diagonal() : 1.0;
  param::SizeSpec s;
  s.hmax = D / 20;
  // D/1000: an assembly full of small fillets at D/5000 gave over ten million triangles
  // by default.
  s.hmin = D / 1000;
  s.angle_tol = 18.0 * std::numbers::pi / 180.0;  // 20 elements per 2 pi
  s.chordal_tol = D / 1000;
  s.gradation = 1.3;
  // Isotropic by default: the triangles are judged by their 3D shape (docs/ARCHITECTURE.md,
  // Q_K), as volume meshers need; anisotropic curvature sizes are an option.
  s.isotropic = true;
  return s;
}

param::SizeSpec meshing_size(const MeshOptions& opt) {
  // The chordal tolerance sizes elements with a safety factor (MeshOptions doc); the
  // report measures the deviation against the tolerance the user asked for.
  param::SizeSpec spec = opt.size;
  if (spec.chordal_tol > 0 && opt.chordal_safety > 1) spec.chordal_tol /= opt.chordal_safety;
  // A feature size above hmin floors the curvature and gradation sizes too: a fillet
  // narrower than it is an entity to absorb, not a curvature to follow.
  if (!opt.keep_topology && opt.min_feature > spec.hmin)
    spec.hmin = std::min(opt.min_feature, spec.hmax);
  return spec;
}

MeshOptions effective_options(const geom::Model& m, const MeshOptions& opt) {
  // A subdivision cage has no CAD artefacts: its creases are features the user gave at
  // any dihedral angle, never merged, and its limit surface keeps every entity.
  MeshOptions o = opt;
  if (m.format == "obj") o.keep_topology = true;
  return o;
}

double feature_size(const MeshOptions& opt, const geom::Box3& bbox) {
  if (opt.keep_topology) return 0.0;
  if (opt.min_feature > 0) return opt.min_feature;
  const double D = bbox.empty() || !(bbox.diagonal() > 0) ? 1.0 : bbox.diagonal();
  const double hmin = opt.size.hmin > 0 ? opt.size.hmin : 1e-3 * D;
  // The model's thinnest extent (its box's smallest side; the next one for a planar
  // model) bounds the scale of its shape: on a slender part, D/1000 is a large share of
  // its cross-section, and the holes and fillets across it are features, not artefacts.
  if (bbox.empty()) return hmin;
  double e[3] = {bbox.hi.x - bbox.lo.x, bbox.hi.y - bbox.lo.y, bbox.hi.z - bbox.lo.z};
  std::sort(e, e + 3);
  const double thin = e[0] > 1e-4 * D ? e[0] : e[1];  // a planar model: its box is flat
  return std::min(hmin, thin / kFeatureShare);
}

double MeshResult::unit_edge_share() const {
  std::int64_t e = 0, u = 0;
  for (const FaceStats& f : faces) e += f.edges, u += f.unit_edges;
  return e > 0 ? static_cast<double>(u) / static_cast<double>(e) : 0.0;
}

namespace detail {

ModelRun::ModelRun(const geom::Model& model, const MeshOptions& options)
    : m(model),
      opt(options),
      nf(model.faces.size()),
      ne(model.edges.size()),
      nv(model.vertices.size()),
      feature(feature_size(options, model.bbox)),
      arena(options.threads > 0 ? options.threads : tbb::this_task_arena::max_concurrency()),
      spec(res.size),
      face_error(nf),
      fields(nf),
      field_ptr(nf),
      twin_of(nf, geom::kNone),
      collapsed(nf, 0),
      on_face(ne, 0),
      edges(ne),
      edge_error(ne),
      primary_of(ne, geom::kNone) {
  res.size = meshing_size(opt);
}

void ModelRun::build_field(std::size_t f) {
  const geom::Face& face = m.faces[f];
  if (face.degenerate) return;  // not meshed (geom::Face::degenerate); no field, no error
  if (!face.surface) {
    face_error[f] =
        "the face has no surface (kind " + std::string(geom::to_string(face.kind)) + ")";
    return;
  }
  try {
    fields[f] = std::make_unique<param::FaceSizeField>(*face.surface, face.uv_box, spec,
                                                       static_cast<geom::Id>(f));
  } catch (...) {
    face_error[f] = "the surface could not be evaluated on its parameter box";
  }
}

}  // namespace detail

namespace {

using detail::Clock;
using detail::ModelRun;
using detail::seconds_since;

// ---- 0. per-face background size fields (§7.5.1), gradated on their grids.
void build_size_fields(ModelRun& run) {
  // Deterministic: a field freed after its face is meshed is built again, identical, when
  // a crossing round meshes the faces again (stage 2).
  detail::parallel_indices(run.arena, run.nf, [&](std::size_t f) { run.build_field(f); });
  for (std::size_t f = 0; f < run.nf; ++f) run.field_ptr[f] = run.fields[f].get();
}

void mark_edges_on_faces(ModelRun& run) {
  for (const geom::Face& face : run.m.faces)
    for (const geom::Loop& l : face.loops)
      for (const geom::EdgeUse& u : l.uses)
        if (u.edge >= 0 && static_cast<std::size_t>(u.edge) < run.ne)
          run.on_face[static_cast<std::size_t>(u.edge)] = 1;
}

// An edge whose two ends are one model vertex although its curve's ends are farther
// apart than the edge's own tolerance is closed by the vertex's tolerance alone: its
// last node is that vertex, and the faces along it fold at the scale of the gap (short
// edges whose vertex got a tolerance as large as the edges themselves give pairs of
// self-intersecting triangles there). The OCC import splits such a vertex in two
// (geom::split_vertices_closing_open_edges); one it could not split (the split would
// open a loop, or an edge end is about as near to both ends of the curve) is still
// closed here, and the mesh cannot follow both: say so.
void warn_edges_closed_by_vertex(ModelRun& run) {
  const geom::Model& m = run.m;
  for (std::size_t e = 0; e < run.ne; ++e) {
    const geom::Edge& ed = m.edges[e];
    if (!run.on_face[e] || ed.degenerate || !ed.curve || ed.v0 != ed.v1 || ed.v0 == geom::kNone)
      continue;
    try {
      const double gap = glm::length(ed.curve->point(ed.range.hi) - ed.curve->point(ed.range.lo));
      if (!(gap > ed.tol)) continue;
      std::ostringstream os;
      os << "edge " << e << ": both ends are vertex " << ed.v0 << " (tolerance "
         << m.vertices[static_cast<std::size_t>(ed.v0)].tol << ") but its curve's ends are " << gap
         << " apart (edge length " << ed.length << ", tolerance " << ed.tol
         << "): the mesh closes it at the vertex, and the faces along it may fold there";
      run.res.warnings.push_back(os.str());
    } catch (...) {
      // An edge whose curve cannot be evaluated fails in the discretization below.
    }
  }
}

}  // namespace

MeshResult mesh_model(const geom::Model& m, const MeshOptions& options) {
  const auto t_all = Clock::now();
  const MeshOptions opt = effective_options(m, options);
  ModelRun run(m, opt);

  auto t0 = Clock::now();
  build_size_fields(run);
  detail::find_twin_faces(run);
  run.res.stages.push_back({"size fields", seconds_since(t0)});

  mark_edges_on_faces(run);
  warn_edges_closed_by_vertex(run);

  // ---- 1. curves: every edge once (the stage's time ends with the first numbering).
  t0 = Clock::now();
  detail::mesh_curves(run);
  detail::collapse_strips(run);

  // ---- 2. faces, in parallel, again while (u,v) boundaries cross.
  run.res.stages.push_back({"faces", detail::mesh_faces(run, t0)});

  // ---- 3. stitch.
  detail::stitch(run);

  // ---- 4. simplify: entities below the feature size absorbed (simplify3d.h).
  t0 = Clock::now();
  detail::simplify(run);
  run.res.stages.push_back({"simplify", seconds_since(t0)});
  run.res.stages.push_back({"total", seconds_since(t_all)});
  return std::move(run.res);
}

}  // namespace uvmesh::surface
