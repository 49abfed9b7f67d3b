// Private to uvmesh::geom (and its tests): where a patch of a subdivision Model comes
// from, and the coordinates of its (u,v) domain. Plain C++, no OpenSubdiv.
#pragma once

#include <memory>
#include <vector>

#include "uvmesh/geom/subd.h"

namespace uvmesh::geom {

/// The plane of a projected patch's domain (SubdPatch::plane): the (u,v) of a 3D point p
/// is ((p - o) . x, (p - o) . y) / ext (x, y orthonormal).
struct SubdPlane {
  Vec3 o{0.0}, x{1.0, 0.0, 0.0}, y{0.0, 1.0, 0.0};
  double ext = 1.0;
  Vec2 map(const Vec3& p) const { return Vec2(glm::dot(p - o, x), glm::dot(p - o, y)) / ext; }
  Vec2 dir(const Vec3& d) const { return Vec2(glm::dot(d, x), glm::dot(d, y)) / ext; }
};

/// Where a patch (a Model face) comes from. Its (u,v) maps to the base face's
/// OpenSubdiv parameterization as face_uv = origin + scale * (u,v) (identity for whole
/// faces; the quadrangulated sub-face `subface` of an n-gon otherwise).
struct SubdPatch {
  Id base_face = kNone;
  int subface = -1;   ///< -1: the whole base face
  int face_size = 0;  ///< vertices of the base face
  Vec2 origin{0.0, 0.0};
  double scale = 1.0;
  /// A whole Catmull-Clark n-gon (n != 4) as one patch: its (u,v) domain is the polygon
  /// of the face's limit points flattened (CCW): corner k (the face's k-th vertex) at
  /// polygon[2k], the limit point of the middle of side k (OpenSubdiv's sub-face corner)
  /// at polygon[2k+1], the limit point of the face centre at `centre`. The quad (corner
  /// k, side point k, centre, side point k-1) maps bilinearly onto OpenSubdiv's sub-face
  /// k (ngon_domain_point). origin and scale are then unused. Empty for other patches.
  std::vector<Vec2> polygon;
  Vec2 centre{0.0, 0.0};
  /// A patch at a vertex of high valence (subd_surface.h, kProjectValence) whose
  /// (u,v) domain is the projection of its limit surface on `plane`: the Model face's
  /// sigma(w) is unprojected(z) where plane.map(unprojected(z)) = w (Newton). The
  /// coordinates above (polygon, origin, scale) are those of `unprojected`. Null for
  /// other patches.
  std::shared_ptr<const Surface> unprojected;
  SubdPlane plane;
};

/// The (u,v) of patch P's Model face at OpenSubdiv-side coordinates st in [0,1]^2 of
/// its quad q (q = 0 for a patch of one (sub-)face; the sub-face for an n-gon patch on
/// its polygon): through ngon_domain_point for n-gon patches, then through the
/// projection for projected patches.
Vec2 subd_patch_domain_point(const SubdPatch& P, int q, Vec2 st);

/// Point of an n-gon patch's domain (SubdPatch::polygon) at normalized coordinates st
/// in [0,1]^2 of OpenSubdiv's sub-face k, and the inverse (Newton; also a little
/// outside the quad).
Vec2 ngon_domain_point(const std::vector<Vec2>& polygon, Vec2 centre, int k, Vec2 st);
Vec2 ngon_subface_coords(const std::vector<Vec2>& polygon, Vec2 centre, int k, Vec2 uv);

}  // namespace uvmesh::geom
