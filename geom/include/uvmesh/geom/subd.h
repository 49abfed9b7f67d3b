// OpenSubdiv back end of uvmesh::geom: OBJ control cages and their subdivision limit
// surface as a Model, so that they are meshed by the same pipeline as CAD models.
// Available when uvmesh is built with OpenSubdiv (the macro UVMESH_HAVE_OSD is then
// defined); the OBJ parser itself needs nothing but the standard library.
//
//   geom::SubdOptions o;                          // scheme auto, boundary from the file
//   geom::SubdModelResult r = geom::read_subd("cage.obj", o);
//   if (!r.ok) std::cerr << r.error;              // "cage.obj:12: face references vertex 9 ..."
//   surface::mesh_model(r.model, opts);
//
// The Model. Every base face with a limit surface is one patch: Catmull-Clark quads and
// Loop triangles on their unit (u,v) square or triangle; a Catmull-Clark face with n != 4
// sides on the flattened polygon of its limit points, pieced from OpenSubdiv's n
// quadrangulated sub-faces. An n-gon that repeats a vertex, or whose
// flattened polygon does not split into convex quads, is n patches instead, one per
// sub-face. Each patch is a
// geom::Face whose Surface evaluates OpenSubdiv's limit surface (Bfr::Surface) with first
// and second derivatives. Patch boundaries are model edges shared by the patches on both
// sides: their 3D curve is the limit curve, their pcurves are straight lines in each
// patch's (u,v) and the curve parameter t is the same on every side (t in [0,1] along a
// base edge from its first to its second vertex, split at 1/2 where a sub-face patch uses
// half of it; t in [0,1] from an edge midpoint to the face centre on the spokes between
// sub-face patches). Base vertices, the limit points of the middles of n-gon sides, and
// the centres of n-gons made of sub-face patches are model vertices. So creases and sharp corners,
// which lie on base edges and vertices, are model edges and vertices and become mesh edges and
// vertices.
//
// Faces without a limit surface (holes, and faces on a boundary with boundary
// interpolation "none") are not in the Model (SubdModelResult::dropped_faces). A
// connected set of patches whose every edge has two uses is a closed shell and a solid;
// its faces are flagged reversed when the cage is oriented inward, so the mesh is
// outward.
//
// Thread safety: building installs OpenSubdiv's (process-global) error callbacks for the
// time of the call, so build models from one thread at a time. Evaluating the surfaces
// of a built model is read-only and may run from any number of threads.
#pragma once

#include <array>
#include <iosfwd>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "uvmesh/geom/model.h"

namespace uvmesh::geom {

enum class SubdScheme { Auto, CatmullClark, Loop };
/// OpenSubdiv's Sdc::Options::VtxBoundaryInterpolation; FromFile: the cage's
/// `t interpolateboundary` tag, else EdgeOnly (what OpenSubdiv's own OBJ tools assume).
enum class SubdBoundary { FromFile, None, EdgeOnly, EdgeAndCorner };

/// "catmark", "loop", "auto"; the boundary names are OpenSubdiv's: "none", "edge-only",
/// "edge-and-corner" (and "file"). parse_* return false for an unknown name.
bool parse_subd_scheme(const std::string& s, SubdScheme& out);
bool parse_subd_boundary(const std::string& s, SubdBoundary& out);
std::string_view to_string(SubdScheme s);
std::string_view to_string(SubdBoundary b);

/// An OBJ control cage as read, indices 0-based. Lines are the OBJ line numbers (for
/// messages about what was read).
struct SubdCage {
  std::string source;
  std::vector<Vec3> points;
  std::vector<int> face_sizes;
  std::vector<int> face_verts;
  std::vector<int> face_lines;
  struct Crease {
    int a = 0, b = 0;
    float sharpness = 0;
    int line = 0;
  };
  struct Corner {
    int v = 0;
    float sharpness = 0;
    int line = 0;
  };
  struct Hole {
    int face = 0;
    int line = 0;
  };
  std::vector<Crease> creases;
  std::vector<Corner> corners;
  std::vector<Hole> holes;
  int interpolate_boundary = -1;      ///< `t interpolateboundary`: 0, 1, 2; -1 when absent
  bool chaikin = false;               ///< `t creasemethod ... chaikin`
  std::vector<std::string> warnings;  ///< tags and statements that were ignored
};

struct SubdCageResult {
  bool ok = false;
  std::string error;  ///< "NAME:LINE: what is wrong" (one message)
  SubdCage cage;
};

/// Parses OBJ text: `v`, `f` (1-based or negative indices, v/vt/vn forms), `t` tags
/// (crease, corner, hole, interpolateboundary, creasemethod; 0-based indices). vt, vn,
/// g, o, s, usemtl, mtllib, l are ignored. `name` prefixes messages.
SubdCageResult parse_obj_cage(std::istream& in, const std::string& name);
SubdCageResult read_obj_cage(const std::string& path);

struct SubdOptions {
  SubdScheme scheme = SubdScheme::Auto;  ///< Auto: Loop when every face is a triangle
  SubdBoundary boundary = SubdBoundary::FromFile;
  /// Bfr::SurfaceFactory approximation levels of irregular patches (OpenSubdiv's
  /// defaults: 2 where smooth, 6 around sharp features).
  int approx_level_smooth = 2;
  int approx_level_sharp = 6;
};

/// Where each Model face comes from (private: geom/src/subd_patch.h, read by the tests).
struct SubdPatch;

struct SubdModelResult {
  bool ok = false;
  std::string error;
  Model model;
  /// Where each patch comes from, indexed by model face id (the type is private to geom,
  /// geom/src/subd_patch.h: the tests read it).
  std::shared_ptr<const std::vector<SubdPatch>> patches;
  std::vector<Id> cage_vertex;           ///< model vertex of each cage vertex (kNone: in no patch)
  SubdScheme scheme = SubdScheme::Auto;  ///< the scheme used (never Auto)
  SubdBoundary boundary = SubdBoundary::FromFile;  ///< the interpolation used (never FromFile)
  std::vector<Id> dropped_faces;  ///< base faces without a limit surface (holes, boundary none)
  int non_manifold_edges = 0;     ///< base edges with three or more faces (kept, sharp)
  std::vector<std::string> warnings;
};

/// True when this build has the OpenSubdiv back end.
bool have_opensubdiv();

/// Builds the limit-surface Model of a cage. Errors (scheme and faces disagree, a tag
/// naming a vertex, edge or face that does not exist, OpenSubdiv rejecting the
/// topology) come back in `error`, naming the OBJ line.
SubdModelResult model_from_cage(const SubdCage& cage, const SubdOptions& opt);
/// read_obj_cage + model_from_cage.
SubdModelResult read_subd(const std::string& path, const SubdOptions& opt);

}  // namespace uvmesh::geom
