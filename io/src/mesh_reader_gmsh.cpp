// Gmsh mesh reader (mesh_parse.h): MSH 4.1 (ASCII and binary) and 2.2, Gmsh reference
// manual, "MSH file format" (4.1 and the legacy 2.2 appendix).
#include <cstdint>
#include <map>
#include <string>
#include <string_view>
#include <vector>

#include "mesh_parse.h"

namespace uvmesh::io::detail {

namespace {

// Nodes per element of the MSH element types a surface-mesh file may hold; -1 unknown.
int msh_nodes_of_type(std::int64_t type) {
  switch (type) {
    case 1:
      return 2;  // line
    case 2:
      return 3;  // triangle
    case 3:
      return 4;  // quadrangle
    case 4:
      return 4;  // tetrahedron
    case 5:
      return 8;  // hexahedron
    case 6:
      return 6;  // prism
    case 7:
      return 5;  // pyramid
    case 8:
      return 3;  // 3-node line
    case 9:
      return 6;  // 6-node triangle
    case 10:
      return 9;  // 9-node quadrangle
    case 11:
      return 10;  // 10-node tetrahedron
    case 15:
      return 1;  // point
    case 16:
      return 8;  // 8-node quadrangle
    default:
      return -1;
  }
}

// ----------------------------------------------------------------------------- Gmsh

// Skips a section's body up to and including its "$End..." line (sections this reader
// does not need; binary bodies contain no line that starts with "$End").
void skip_msh_section(Text& t, std::string_view name) {
  const std::string end = "$End" + std::string(name.substr(1));
  while (true) {
    if (t.pos() >= t.end())
      fail(t.where() + ": file ends inside section " + std::string(name) + " (truncated?)");
    const std::string_view l = t.rest_of_line();
    if (l == end) return;
  }
}

void read_physical_names(Text& t, MeshReadResult& r) {
  const std::int64_t n = t.count("the number of physical names");
  for (std::int64_t i = 0; i < n; ++i) {
    MeshReadResult::Physical p;
    p.dim = static_cast<int>(t.integer("a physical group dimension"));
    p.tag = static_cast<int>(t.integer("a physical group tag"));
    std::string_view name = t.rest_of_line();
    if (name.size() >= 2 && name.front() == '"' && name.back() == '"')
      name = name.substr(1, name.size() - 2);
    p.name = std::string(name);
    r.physicals.push_back(std::move(p));
  }
  t.expect("$EndPhysicalNames");
}

// A section other than the ones a format's reader parses itself: physical names are
// kept, other sections skipped, anything else is an error.
void other_msh_section(Text& t, std::string_view sec, MeshReadResult& r, const char* known) {
  if (sec == "$PhysicalNames") {
    read_physical_names(t, r);
  } else if (!sec.empty() && sec[0] == '$') {
    t.rest_of_line();
    skip_msh_section(t, sec);
  } else {
    fail(t.where() + ": expected a section (" + known + "), found '" +
         std::string(sec.substr(0, 40)) + "'");
  }
}

void read_msh22(Text& t, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  NodeMap nodes;
  ElementSink sink{m, r, {}};
  bool have_nodes = false;
  while (!t.at_end()) {
    const std::string_view sec = t.token();
    if (sec == "$Nodes") {
      const std::int64_t n = t.count("the number of nodes");
      nodes.reserve(bounded(n));
      m.points.reserve(bounded(n));
      for (std::int64_t i = 0; i < n; ++i) {
        const std::int64_t tag = t.integer("a node tag");
        nodes.add(tag, static_cast<NodeId>(m.points.size()), t.where());
        const double x = t.real("x"), y = t.real("y"), z = t.real("z");
        m.points.emplace_back(x, y, z);
      }
      t.expect("$EndNodes");
      have_nodes = true;
    } else if (sec == "$Elements") {
      if (!have_nodes) fail(t.where() + ": $Elements before $Nodes");
      const std::int64_t n = t.count("the number of elements");
      for (std::int64_t i = 0; i < n; ++i) {
        t.integer("an element tag");
        const std::int64_t type = t.integer("an element type");
        const int nn = msh_nodes_of_type(type);
        if (nn < 0) fail(t.where() + ": unknown element type " + std::to_string(type));
        const std::int64_t ntags = t.count("the number of element tags", 100);
        std::int64_t tags[2] = {0, 0};
        for (std::int64_t k = 0; k < ntags; ++k) {
          const std::int64_t v = t.integer("an element tag value");
          if (k < 2) tags[k] = v;
        }
        // tags: physical, elementary (a single tag is taken as the entity).
        const std::int64_t entity = ntags >= 2 ? tags[1] : tags[0];
        NodeId nd[10];
        for (int k = 0; k < nn; ++k) nd[k] = nodes.at(t.integer("an element node"), t.where());
        sink.element(type, nd, entity_id(entity));
      }
      t.expect("$EndElements");
    } else {
      other_msh_section(t, sec, r, "$Nodes, $Elements, ...");
    }
  }
  if (!have_nodes) fail("no $Nodes section");
  r.has_face_ids = true;
  classify_from_elements(m, sink.point_elements);
}

// MSH 4.1, ASCII or binary: the same records, read through one of the two cursors.
class MshIn {
 public:
  MshIn(Text& t, Bytes* b) : t_(t), b_(b) {}
  std::string where() const { return b_ ? b_->where() : t_.where(); }
  std::int64_t i(const char* what) { return b_ ? b_->get<std::int32_t>(what) : t_.integer(what); }
  std::int64_t z(const char* what) {
    if (!b_) return t_.count(what, std::numeric_limits<std::int64_t>::max());
    const std::uint64_t v = b_->get<std::uint64_t>(what);
    if (v > static_cast<std::uint64_t>(std::numeric_limits<std::int64_t>::max()))
      fail(where() + ": " + what + " out of range");
    return static_cast<std::int64_t>(v);
  }
  std::int64_t count(const char* what) {
    const std::int64_t n = z(what);
    if (n > std::numeric_limits<std::int32_t>::max())
      fail(where() + ": " + std::string(what) + " " + std::to_string(n) + " is out of range");
    return n;
  }
  double d(const char* what) { return b_ ? b_->real(what) : t_.real(what); }
  // Back to text at the end of a binary section: the "$End..." line follows a newline.
  void end_section(std::string_view end_word) {
    if (b_) {
      t_.seek(b_->pos());
    }
    t_.expect(end_word);
  }
  void begin_section() {
    if (b_) {
      t_.skip_newline();  // the section name's line end
      b_->seek(t_.pos());
    }
  }

 private:
  Text& t_;
  Bytes* b_;
};

// $Entities: counted (r.entities), otherwise skipped; the nodes carry their entity.
void read_msh41_entities(MshIn& in, MeshReadResult& r) {
  in.begin_section();
  std::int64_t n[4];
  for (auto& k : n) k = in.count("an entity count");
  for (int d = 0; d < 4; ++d) {
    r.entities[static_cast<std::size_t>(d)] = static_cast<std::size_t>(n[d]);
    for (std::int64_t e = 0; e < n[d]; ++e) {
      in.i("an entity tag");
      for (int k = 0; k < (d == 0 ? 3 : 6); ++k) in.d("an entity bounding-box coordinate");
      const std::int64_t nphys = in.count("the number of physical tags");
      for (std::int64_t k = 0; k < nphys; ++k) in.i("a physical tag");
      if (d > 0) {
        const std::int64_t nb = in.count("the number of bounding entities");
        for (std::int64_t k = 0; k < nb; ++k) in.i("a bounding entity tag");
      }
    }
  }
  in.end_section("$EndEntities");
}

// $Nodes: blocks of node tags then coordinates, classified by the block's entity.
void read_msh41_nodes(MshIn& in, NodeMap& nodes, SurfaceMesh& m) {
  in.begin_section();
  const std::int64_t blocks = in.count("the number of node blocks");
  const std::int64_t total = in.count("the number of nodes");
  in.z("the smallest node tag");
  in.z("the largest node tag");
  nodes.reserve(bounded(total));
  m.points.reserve(bounded(total));
  for (std::int64_t b = 0; b < blocks; ++b) {
    const std::int64_t dim = in.i("a node block dimension");
    const std::int64_t tag = in.i("a node block entity tag");
    const std::int64_t parametric = in.i("the parametric flag");
    const std::int64_t n = in.count("the number of nodes in the block");
    if (dim < 0 || dim > 3) fail(in.where() + ": node block of dimension " + std::to_string(dim));
    if (static_cast<std::int64_t>(m.points.size()) + n > total)
      fail(in.where() + ": the node blocks hold more nodes than the " + std::to_string(total) +
           " announced");
    const std::size_t first = m.points.size();
    for (std::int64_t k = 0; k < n; ++k) {
      const std::int64_t nt = in.z("a node tag");
      nodes.add(nt, static_cast<NodeId>(first + static_cast<std::size_t>(k)), in.where());
    }
    for (std::int64_t k = 0; k < n; ++k) {
      const double x = in.d("x"), y = in.d("y"), z = in.d("z");
      if (parametric)
        for (std::int64_t u = 0; u < std::min<std::int64_t>(dim, 2); ++u)
          in.d("a parametric coordinate");
      m.points.emplace_back(x, y, z);
      // A surface mesh has no volume nodes; a volume mesh's are put on face 0.
      m.point_dim.push_back(static_cast<std::int8_t>(std::min<std::int64_t>(dim, 2)));
      m.point_entity.push_back(dim == 3 ? 0 : entity_id(tag));
      m.point_t.push_back(0.0);
    }
  }
  if (static_cast<std::int64_t>(m.points.size()) != total)
    fail(in.where() + ": " + std::to_string(total) + " nodes announced, " +
         std::to_string(m.points.size()) + " found");
  in.end_section("$EndNodes");
}

// $Elements: blocks of one element type on one entity.
void read_msh41_elements(MshIn& in, const NodeMap& nodes, ElementSink& sink) {
  in.begin_section();
  const std::int64_t blocks = in.count("the number of element blocks");
  const std::int64_t total = in.count("the number of elements");
  in.z("the smallest element tag");
  in.z("the largest element tag");
  std::int64_t seen = 0;
  for (std::int64_t b = 0; b < blocks; ++b) {
    in.i("an element block dimension");
    const std::int64_t tag = in.i("an element block entity tag");
    const std::int64_t type = in.i("an element type");
    const std::int64_t n = in.count("the number of elements in the block");
    const int nn = msh_nodes_of_type(type);
    if (nn < 0) fail(in.where() + ": unknown element type " + std::to_string(type));
    seen += n;
    if (seen > total)
      fail(in.where() + ": the element blocks hold more elements than the " +
           std::to_string(total) + " announced");
    NodeId nd[10];
    for (std::int64_t k = 0; k < n; ++k) {
      in.z("an element tag");
      for (int j = 0; j < nn; ++j) nd[j] = nodes.at(in.z("an element node tag"), in.where());
      sink.element(type, nd, entity_id(tag));
    }
  }
  if (seen != total)
    fail(in.where() + ": " + std::to_string(total) + " elements announced, " +
         std::to_string(seen) + " found");
  in.end_section("$EndElements");
}

void read_msh41(Text& t, Bytes* bin, MeshReadResult& r) {
  SurfaceMesh& m = r.mesh;
  MshIn in(t, bin);
  NodeMap nodes;
  ElementSink sink{m, r, {}};
  bool have_nodes = false, have_elements = false;
  while (!t.at_end()) {
    const std::string_view sec = t.token();
    if (sec == "$Entities") {
      read_msh41_entities(in, r);
    } else if (sec == "$Nodes") {
      read_msh41_nodes(in, nodes, m);
      have_nodes = true;
    } else if (sec == "$Elements") {
      if (!have_nodes) fail(t.where() + ": $Elements before $Nodes");
      read_msh41_elements(in, nodes, sink);
      have_elements = true;
    } else {
      other_msh_section(t, sec, r, "$Entities, $Nodes, $Elements, ...");
    }
  }
  if (!have_nodes) fail("no $Nodes section");
  if (!have_elements) fail("no $Elements section");
  r.has_face_ids = true;
  r.classified = true;
  // Point elements name the vertex a node is classified on; the node blocks already did.
}

}  // namespace

void read_msh(const std::string& data, MeshReadResult& r) {
  Text t(data.data(), data.data() + data.size());
  t.expect("$MeshFormat");
  const std::string_view version = t.token();
  const std::int64_t file_type = t.integer("the file type (0 ASCII, 1 binary)");
  const std::int64_t size = t.integer("the data size");
  if (version != "4.1" && version != "2.2" && version != "2.1" && version != "2.0")
    fail("line 2: MSH version " + std::string(version) + " is not read (4.1 and 2.2 are)");
  if (file_type != 0 && file_type != 1) fail("line 2: file type must be 0 (ASCII) or 1 (binary)");
  if (size != 8) fail("line 2: data size " + std::to_string(size) + " is not read (8 is)");
  r.binary = file_type == 1;
  bool big = false;
  if (r.binary) {
    t.skip_newline();
    Bytes b(data.data(), t.pos(), data.data() + data.size());
    const std::int32_t one = b.get<std::int32_t>("the endianness marker");
    if (one != 1) {
      if (byteswap32(one) != 1) fail(b.where() + ": bad endianness marker in $MeshFormat");
      big = std::endian::native == std::endian::little;
    }
    t.seek(b.pos());
  }
  t.expect("$EndMeshFormat");
  if (version != "4.1") {
    if (r.binary)
      fail("binary MSH " + std::string(version) +
           " is not read (ASCII 2.2 and 4.1 ASCII/binary are)");
    r.format = MeshFormat::Msh22;
    read_msh22(t, r);
    return;
  }
  r.format = MeshFormat::Msh41;
  if (r.binary) {
    Bytes b(data.data(), t.pos(), data.data() + data.size(), big);
    read_msh41(t, &b, r);
  } else {
    read_msh41(t, nullptr, r);
  }
}

}  // namespace uvmesh::io::detail
