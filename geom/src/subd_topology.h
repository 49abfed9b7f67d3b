// Private to uvmesh::geom's OpenSubdiv back end: checks of a cage's topology and tags
// before OpenSubdiv builds it (inputs that OpenSubdiv 3.5 would read out of bounds), and
// the collection of OpenSubdiv's messages while a model is built.
#pragma once

#include <opensubdiv/far/topologyLevel.h>

#include <string>
#include <vector>

#include "uvmesh/geom/subd.h"

namespace uvmesh::geom::subd_detail {

namespace Far = OpenSubdiv::Far;

// OpenSubdiv's error and warning callbacks (process-global) collect into `list` for the
// lifetime of the object, so that the library does not print.
struct FarMessages {
  std::vector<std::string> list;
  FarMessages();
  ~FarMessages();
  FarMessages(const FarMessages&) = delete;
  FarMessages& operator=(const FarMessages&) = delete;
};

// "SOURCE:LINE: ", the prefix of a message about an OBJ line.
std::string line_ref(const SubdCage& c, int line);
// The first problem with the cage's crease, corner and hole tags, or "".
std::string check_tags(const SubdCage& c, const Far::TopologyLevel& lvl);
// The first face that runs along an edge and straight back, or "".
std::string check_folded_faces(const SubdCage& c);

}  // namespace uvmesh::geom::subd_detail
