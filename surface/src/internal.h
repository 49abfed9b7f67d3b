// Internal pieces of the surface stage, shared by curves.cpp, face.cpp, improve3d.cpp
// and mesher.cpp. Not installed.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "uvmesh/geom/model.h"
#include "uvmesh/param/size_field.h"
#include "uvmesh/surface/mesher.h"

namespace uvmesh::surface::detail {

/// Stage 1: the parameters of the nodes of each model edge (ends included).
class EdgeDiscretizer {
 public:
  EdgeDiscretizer(const geom::Model& m, const param::SizeSpec& spec,
                  const std::vector<const param::FaceSizeField*>& fields);
  void set_min_closed(int n) { min_closed_ = n; }
  /// Node parameters t_0 = lo < ... < t_n = hi on the edge's curve.
  std::vector<double> discretize(geom::Id edge) const;

 private:
  struct Adjacent {
    geom::Id face;
    const geom::Curve2* pcurve;
  };
  /// Unit edges per unit of parameter at t; `speed` receives |C'(t)|.
  double density(const geom::Edge& e, geom::Id eid, double t, double& speed) const;
  const geom::Model& m_;
  const param::SizeSpec& spec_;
  const std::vector<const param::FaceSizeField*>& fields_;
  std::vector<std::vector<Adjacent>> adj_;
  int min_closed_ = 3;
};

/// The 1D mesh of the whole model: global node ids of every edge's nodes.
struct EdgeNodes {
  std::vector<double> t;       ///< curve parameters, ends included
  std::vector<NodeId> node;    ///< global node ids, same length
};

/// A face's contribution before stitching. Corners of triangles are global node ids
/// (>= 0) for boundary nodes, or -(k + 1) for the face's own k-th interior point.
struct FaceMesh {
  std::vector<geom::Vec3> points;  ///< interior points
  std::vector<geom::Vec2> uv;      ///< their (u,v)
  std::vector<std::array<NodeId, 3>> tris;
  std::vector<std::array<geom::Vec2, 3>> tri_uv;
  std::string error;  ///< non-empty: the face failed, with the reason
  /// Edges whose (u,v) polylines crossed: refining them may let the face mesh.
  std::vector<geom::Id> refine_edges;
  FaceStats stats;
};

/// Local (u,v) mesh of one face handed to the 3D improvement: vertex positions in both
/// spaces, the global id of each vertex (for boundary vertices; -1 inside), and which
/// vertices may move.
struct LocalMesh {
  std::vector<geom::Vec2> uv;
  std::vector<geom::Vec3> p;
  std::vector<NodeId> global;  ///< >= 0 boundary node; -1 interior
  std::vector<std::array<int, 3>> tris;  ///< CCW in (u,v)
  std::vector<char> fixed;
  std::vector<double> scale;  ///< metric scale used by mesher2d (see FaceMesh::scale)
};

/// Stage 2b: swaps and smoothing judged by 3D quality, moving vertices in (u,v) so they
/// stay on the surface. Returns {swaps, moves}.
std::array<int, 2> improve3d(LocalMesh& lm, const geom::Surface& s, int passes);

/// Q_K = alpha h_max / rho (eq. 7.6) of a 3D triangle, as 1/Q in [0, 1] (0: flat).
double q3(const geom::Vec3& a, const geom::Vec3& b, const geom::Vec3& c);

/// Stage 2: one face.
FaceMesh mesh_face(const geom::Model& m, geom::Id face, const std::vector<EdgeNodes>& edges,
                   const std::vector<geom::Vec3>& node_points, const param::FaceSizeField& field,
                   const MeshOptions& opt);

}  // namespace uvmesh::surface::detail
