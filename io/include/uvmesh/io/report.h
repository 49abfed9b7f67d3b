// uvmesh::io quality report -- the one JSON report that `uvmesh check MESH` prints and
// `uvmesh mesh --report` writes (the mesh command adds what only it knows: sizes, times,
// failed faces, unit edges in the mesher's metric). The measures themselves are the
// surface stage's 3D checks (surface/check3d.h); this file only gathers and formats them.
//
//   io::CheckData d = io::check_mesh(mesh, &model, {});
//   nlohmann::json j = io::report_json(d);
//   std::string svg = io::histogram_svg(d.q_histogram, "shape quality q", "q");
//
// JSON sections: counts, quality (Q and q percentiles, angles, bad triangles), topology
// (free / non-manifold / inconsistently oriented edges, components, Euler characteristic,
// close points, self-intersections), edge_length_distribution (3D lengths relative to the
// median edge), metric_edge_lengths (with a model and sizes), chordal (against the model,
// when given), histograms.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/surface_mesh.h"
#include "uvmesh/surface/tet_mesh.h"

namespace uvmesh::io {

/// What the report's metric_edge_lengths measures against: the size field of the meshing
/// size (surface::MeshResult::size, the user's sizes with the chordal safety applied) at
/// the mesh's vertices, without the sizes the boundary imposed (compare
/// surface::kFaceMetricName).
inline constexpr const char* kSizeFieldMetricName =
    "size field: the meshing size's field at the vertices, without boundary sizes";

struct CheckOptions {
  int threads = 0;  ///< 0 = all cores (self-intersections, chordal)
  bool self_intersections = true;
  int max_list = 20;               ///< cap of every list in the report
  double chordal_tolerance = 0.0;  ///< 0 = no bound to compare with
  /// With a model: edge lengths in the metric of these sizes (the unit mesh measure,
  /// docs/ARCHITECTURE.md), each node's metric from its face's param::FaceSizeField. For a
  /// mesh of surface::mesh_model, the sizes it meshed with: MeshResult::size (its chordal
  /// tolerance divided by MeshOptions::chordal_safety). This is the size field alone: the 2D mesher
  /// also grades sizes away from short boundary segments (small holes, fillets), so edges near such
  /// features count as short here while the mesher's own per-face measure
  /// (`uvmesh mesh --report`: unit_edge_share) counts them as unit.
  std::optional<param::SizeSpec> size;
};

/// Counts per bin; bin i covers [lo[i], lo[i+1]), the last bin ends at `hi`.
struct Histogram {
  std::vector<double> lo;
  double hi = 0;
  std::vector<std::size_t> count;
};

struct CheckData {
  std::size_t points = 0, triangles = 0, segments = 0;
  surface::TopologyReport topology;
  std::size_t components = 0;  ///< edge-connected components of the non-degenerate triangles
  /// Free mesh edges lying on model edges used by at most one face (open shells: expected);
  /// set only with a model.
  std::optional<std::size_t> free_edges_on_open_model_edges;
  /// Per solid of the model (with a model): the triangles of the faces of its shells,
  /// checked on their own. In a conforming assembly an interface face bounds two solids
  /// and its edges are non-manifold in the whole mesh, yet every solid must be closed and
  /// manifold by itself (what a volume mesher meshing it needs).
  struct SolidTopology {
    geom::Id solid = geom::kNone;
    bool closed = false;  ///< every shell of the solid is closed in the model
    std::size_t triangles = 0, free_edges = 0, non_manifold_edges = 0;
    std::vector<geom::Id> faces;  ///< the faces of its shells, ascending
    /// Intersecting pairs with both triangles on this solid's faces (with the
    /// self-intersection search), and how many of them the model's surfaces share. A
    /// stray sheet crossing the solid, or a second solid overlapping it, is not counted
    /// here: the solid's own surface, what a volume mesher fills, is what must not
    /// intersect itself.
    std::optional<std::size_t> self_intersections, self_intersections_in_model;
  };
  std::vector<SolidTopology> solids;
  std::optional<surface::IntersectionReport> intersections;
  /// With a model: how many of the intersecting pairs lie where the model's own surfaces
  /// intersect (surface::pairs_intersecting_in_model): an input defect the mesh follows.
  std::optional<std::size_t> intersections_in_model;
  /// With a model that has solids: the intersecting pairs whose two triangles both lie on
  /// faces of closed solids (the same solid or two of them), and how many of those the
  /// model shares. The other pairs involve a face outside every closed solid: a sheet or
  /// an open shell of the file.
  std::optional<std::size_t> intersections_in_closed_solids,
      intersections_in_closed_solids_in_model;
  surface::QualityReport quality;
  double median_edge = 0;                  ///< 3D length of the median unique edge
  surface::EdgeLengthReport edge_lengths;  ///< lengths / median_edge (bins: check3d.h)
  /// Lengths in the size metric (CheckOptions::size); unit = in [1/sqrt2, sqrt2].
  std::optional<surface::EdgeLengthReport> metric_edge_lengths;
  std::string metric_unavailable;  ///< why not, although a model and sizes were given
  std::optional<surface::ChordalReport> chordal;
  std::string chordal_unavailable;  ///< why chordal is not measured although a model was given
  double chordal_tolerance = 0;
  Histogram q_histogram;      ///< q = 1/Q of every triangle, 20 bins on [0, 1]
  Histogram angle_histogram;  ///< every triangle angle, 18 bins of 10 degrees
  Histogram edge_histogram;   ///< edge length / median (log2 half-octave bins)
};

/// Runs every check on m. With a model, chordal deviation is measured when the mesh
/// carries (u,v) per triangle corner (attach_uv supplies them for a mesh read from a
/// file) and its face ids name the model's faces.
CheckData check_mesh(const surface::SurfaceMesh& m, const geom::Model* model,
                     const CheckOptions& opt = {});

/// The report of check_mesh as JSON (see the file comment for the sections).
nlohmann::json report_json(const CheckData& d);

/// Fills m.triangle_uv for a mesh read from a file, so that chordal deviation and the
/// (u,v) picture of a face can be computed: each node of a face is projected on that
/// face's surface (geom::project_to_surface) from the nearest point of a sampling grid
/// of the face's (u,v) box; in periodic directions a triangle's corners are moved to the
/// same period as its first corner. Returns "" or why it could not (a face id the model
/// does not have). Faces without a surface keep (0,0).
std::string attach_uv(surface::SurfaceMesh& m, const geom::Model& model);

/// The report's "volume" section for tetrahedra (surface::fill_solids): counts and the
/// distribution of the minimum dihedral angle and of the radius-edge ratio
/// (surface::measure_tet_quality, tet_mesh.h), in total and per solid ("solids": one entry
/// per solid that has tetrahedra, in id order).
nlohmann::json tet_report_json(const surface::TetMesh& v);

/// An SVG bar chart of a histogram (self-contained, no scripts or external fonts).
std::string histogram_svg(const Histogram& h, const std::string& title, const std::string& x_label);

/// An SVG picture of one face's mesh in its (u,v) domain, triangles shaded by shape
/// quality q (red = poor). Needs m.triangle_uv; "" when the face has no triangles.
std::string face_uv_svg(const surface::SurfaceMesh& m, geom::Id face);

}  // namespace uvmesh::io
