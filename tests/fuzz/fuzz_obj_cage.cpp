// libFuzzer target: OBJ subdivision cage text -> uvmesh::geom::parse_obj_cage and, for
// small cages that parse, model_from_cage (OpenSubdiv Bfr limit patches), which is what
// `uvmesh mesh cage.obj` runs on a file from anywhere. The scheme and boundary rule come
// from the input's length. A finding is a crash, a sanitizer report or a hang.
#include <cstdint>
#include <sstream>
#include <string>

#include "uvmesh/geom/subd.h"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size > 8192) return 0;
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  const uvmesh::geom::SubdCageResult c = uvmesh::geom::parse_obj_cage(in, "fuzz.obj");
  if (!c.ok || c.cage.points.size() > 200 || c.cage.face_sizes.size() > 100) return 0;
  uvmesh::geom::SubdOptions o;
  static constexpr uvmesh::geom::SubdScheme kSchemes[] = {uvmesh::geom::SubdScheme::Auto,
                                                          uvmesh::geom::SubdScheme::CatmullClark,
                                                          uvmesh::geom::SubdScheme::Loop};
  static constexpr uvmesh::geom::SubdBoundary kBoundaries[] = {
      uvmesh::geom::SubdBoundary::FromFile, uvmesh::geom::SubdBoundary::None,
      uvmesh::geom::SubdBoundary::EdgeOnly, uvmesh::geom::SubdBoundary::EdgeAndCorner};
  o.scheme = kSchemes[size % 3];
  o.boundary = kBoundaries[(size / 3) % 4];
  const uvmesh::geom::SubdModelResult m = uvmesh::geom::model_from_cage(c.cage, o);
  (void)m;
  return 0;
}
