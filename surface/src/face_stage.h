// Steps of stage 2, one face (face.cpp's mesh_face), shared by face.cpp,
// face_pslg.cpp, face_repair.cpp and face_from_boundary.cpp. Not installed.
#pragma once

#include <algorithm>
#include <array>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "internal.h"
#include "uvmesh/mesher2d/mesher2d.h"

namespace uvmesh::surface::detail {

/// What one face is meshed from: shared by every step of mesh_face.
struct FaceInput {
  const geom::Model& m;
  geom::Id fid;
  const geom::Face& f;
  const geom::Surface& s;
  const std::vector<EdgeNodes>& edges;
  const std::vector<geom::Vec3>& node_points;
  const param::FaceSizeField& field;
  const MeshOptions& opt;
  bool boundary_fallback;
};

/// The face's (u,v) PSLG: one point per edge node per use, in loop order, then the
/// embedded (INTERNAL) edges as open chains; the points are exact (u,v), not scaled.
struct FacePslg {
  m2d::Pslg in;
  std::vector<NodeId> gid;      ///< PSLG point -> global node
  std::vector<geom::Id> pedge;  ///< PSLG point -> model edge (for messages)
  std::vector<geom::Id> sedge;  ///< PSLG segment -> model edge
  /// PSLG point -> curve parameters of the piece of its edge starting there (NaN for a
  /// pole), so that a crossing names the pieces to split (FaceMesh::refine_at).
  std::vector<std::array<double, 2>> piece;
  std::vector<std::array<double, 2>> spiece;   ///< PSLG segment -> its piece
  std::vector<const geom::EdgeUse*> embedded;  ///< INTERNAL uses: open chains, added last
  /// The points [first, end) of one (not embedded) use, in loop order.
  struct UseSpan {
    const geom::EdgeUse* use;
    std::size_t first, end;
  };
  std::vector<UseSpan> spans;
  std::vector<std::array<std::size_t, 2>> loop_spans;  ///< per loop: its spans [lo, hi)
  /// One closed loop and nothing embedded: the boundary triangulation may apply.
  bool one_loop = false;
};

/// True when a use of the face is a degenerate edge (a pole, a cone's apex).
bool face_has_pole(const geom::Model& m, const geom::Face& f);

/// Builds the face's PSLG (face_pslg.cpp). False with `error` set when an edge has no
/// (u,v) curve.
bool build_face_pslg(const FaceInput& job, FacePslg& pslg, std::string& error);
/// Occurrences of one node closer than a millionth of the (u,v) box snapped together
/// (face_pslg.cpp).
void snap_node_copies(const geom::Box2& box, FacePslg& pslg);
/// The PSLG can go to mesher2d: at least 3 segments, finite points. Else `error`.
bool check_face_pslg(const FacePslg& pslg, std::string& error);

/// What the (u,v) boundary repair changed (face_uv_repair.cpp): the model edges whose
/// uses got projected (u,v), and the largest node-to-sigma distance before and after.
struct UvRepair {
  std::vector<geom::Id> edges;
  std::vector<geom::Id> shifted;  ///< uses moved by a period (periodic surfaces)
  double worst_before = 0, worst_after = 0;
  bool crossing = false;         ///< found where two (u,v) curves crossed
  std::string describe() const;  ///< names the edges, the distances and the repair
};
/// Recomputes the (u,v) of the boundary nodes of every use whose nodes lie farther than
/// tol_factor times its CAD tolerance from sigma at their (u,v), by projecting the 3D
/// nodes onto the surface (a continuation along the loop, seams unwrapped); `only`
/// non-empty: the uses of those edges only. Edges already in `rep` are left alone.
/// Before that (only empty), a use a whole period away from both its neighbours is
/// moved by the period. Returns the number of uses changed (added to rep).
int repair_uv_boundary(const FaceInput& job, FacePslg& pslg, const std::vector<geom::Id>& only,
                       double tol_factor, UvRepair& rep);

/// Triangulates a face from its boundary nodes alone, in 3D (face_from_boundary.cpp);
/// false with the reason in *why when the result would not be a sound disc.
bool triangulate_from_boundary(FaceMesh& out, const geom::Face& f, const geom::Surface& s,
                               const std::vector<NodeId>& gid_in,
                               const std::vector<geom::Vec2>& uv_in,
                               const std::vector<geom::Vec3>& node_points, double chordal_tol,
                               std::string* why);

/// Meshes the face in the least-squares plane of its boundary nodes, where its (u,v)
/// boundary is unusable (face_chart.cpp): lm gets the local mesh (boundary vertices the
/// global nodes, (u,v) the feet of the projections onto the surface, triangles CCW in the
/// plane, whose normal agrees with du x dv). max_normal_deg: the largest angle between
/// the surface normal and the plane's. False with the reason in why.
bool mesh_in_plane_chart(const FaceInput& job, const FacePslg& pslg, LocalMesh& lm,
                         double& max_normal_deg, std::string& why);

// A face's edges -> their (triangle, opposite corner) uses, two for an interior edge:
// records sorted by edge, then triangle and corner (the order a std::map of vectors gave,
// without a node and a vector per edge; that map was a third of the chordal repair's time).
struct EdgeUses {
  struct Use {
    int a, b;  // a < b
    std::size_t t;
    int i;
    bool operator<(const Use& o) const {
      return std::tie(a, b, t, i) < std::tie(o.a, o.b, o.t, o.i);
    }
  };
  std::vector<Use> recs;
  explicit EdgeUses(const LocalMesh& lm) {
    recs.reserve(3 * lm.tris.size());
    for (std::size_t t = 0; t < lm.tris.size(); ++t)
      for (int i = 0; i < 3; ++i) {
        const int a = lm.tris[t][(i + 1) % 3], b = lm.tris[t][(i + 2) % 3];
        recs.push_back({std::min(a, b), std::max(a, b), t, i});
      }
    std::sort(recs.begin(), recs.end());
  }
  // [first, last) of edge a-b's records.
  std::pair<std::vector<Use>::const_iterator, std::vector<Use>::const_iterator> of(int a,
                                                                                   int b) const {
    const Use key{std::min(a, b), std::max(a, b), 0, 0};
    const auto lo = std::lower_bound(recs.begin(), recs.end(), key);
    auto hi = lo;
    while (hi != recs.end() && hi->a == key.a && hi->b == key.b) ++hi;
    return {lo, hi};
  }
  // Calls f(a, b, number of uses) once per edge, in edge order.
  template <class F>
  void for_each_edge(F&& f) const {
    for (std::size_t k = 0; k < recs.size();) {
      std::size_t e = k + 1;
      while (e < recs.size() && recs[e].a == recs[k].a && recs[e].b == recs[k].b) ++e;
      f(recs[k].a, recs[k].b, e - k);
      k = e;
    }
  }
};

/// The repairs after the 3D improvement (face_repair.cpp): the chordal repair, the
/// flatness repair at apexes (faces with a pole) and the removal of folds at seams and
/// poles. Adds the splits to stats.chordal_splits.
void repair_chordal(const FaceInput& job, LocalMesh& lm, FaceStats& stats);
void repair_flat_apex(const FaceInput& job, LocalMesh& lm, FaceStats& stats);
void remove_folds(LocalMesh& lm);

}  // namespace uvmesh::surface::detail
