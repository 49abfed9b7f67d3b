// uvmesh::surface::SurfaceMesh -- the conforming triangle mesh of a whole model, the
// product of the surface stage and the input of every writer and checker.
//
//   surface::MeshResult r = surface::mesh_model(model, opts);
//   const surface::SurfaceMesh& m = r.mesh;
//   for (std::size_t t = 0; t < m.triangles.size(); ++t) {
//     auto [a, b, c] = m.triangles[t];           // indices into m.points, outward order
//     geom::Id face = m.triangle_face[t];        // CAD face id (model.faces index)
//   }
//
// Classification (what Gmsh calls the entity of a node): every vertex lies on exactly one
// model entity of the lowest dimension containing it -- a model vertex (dim 0), the
// interior of a model edge (dim 1) or the interior of a face (dim 2). Edge nodes are
// owned by the model edge, so two faces sharing an edge share its nodes by index
// (docs/ARCHITECTURE.md, Contracts: conformity by construction, never by a merge
// tolerance).
//
// Ordering (deterministic, independent of the thread count): model-vertex nodes in
// vertex id order, then edge-interior nodes edge by edge in curve-parameter order, then
// face-interior nodes face by face; triangles face by face.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "uvmesh/geom/types.h"

namespace uvmesh::surface {

using NodeId = std::int32_t;

struct SurfaceMesh {
  std::vector<geom::Vec3> points;
  /// Model entity each point is classified on: dim 0 (model vertex id), 1 (edge id),
  /// 2 (face id).
  std::vector<std::int8_t> point_dim;
  std::vector<geom::Id> point_entity;
  /// Parameter of an edge node on its model edge's 3D curve (dim 1), else 0.
  std::vector<double> point_t;

  /// Triangles, oriented with their face's material side (outward for solids).
  std::vector<std::array<NodeId, 3>> triangles;
  std::vector<geom::Id> triangle_face;
  /// (u,v) of each triangle corner on its face's surface (a seam or pole node has a
  /// different (u,v) in each triangle that uses it).
  std::vector<std::array<geom::Vec2, 3>> triangle_uv;

  /// The 1D mesh of every model edge: segments in curve-parameter order.
  struct Segment {
    NodeId a = 0, b = 0;
    geom::Id edge = geom::kNone;
  };
  std::vector<Segment> segments;

  std::size_t num_points() const { return points.size(); }
  std::size_t num_triangles() const { return triangles.size(); }
};

}  // namespace uvmesh::surface
