// Gmsh writers of the whole-model surface mesh (mesh_formats.h):
//  - MSH 4.1 ASCII and binary: Gmsh reference manual, section "MSH file format" (version
//    4.1): $MeshFormat, $Entities, $Nodes and $Elements in entity blocks.
//  - MSH 2.2, the legacy format: one node list, one element list.
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>
#include <tuple>
#include <vector>

#include "mesh_formats.h"

namespace uvmesh::io::detail {

using surface::NodeId;
using surface::SurfaceMesh;

// ----------------------------------------------------------------------------- Gmsh 4.1

Physicals physicals(const geom::Model* model, const Counts& c, bool on) {
  Physicals p;
  if (!on || !model) return p;
  p.solids = true;
  for (std::size_t s = 0; s < model->solids.size(); ++s)
    p.solid_names.push_back(model->solids[s].name.empty() ? "solid_" + std::to_string(s + 1)
                                                          : model->solids[s].name);
  p.face_group.assign(c.faces, 0);
  std::map<std::string, std::int64_t> tag_of;
  for (std::size_t f = 0; f < model->faces.size() && f < c.faces; ++f) {
    const std::string& name = model->faces[f].name;
    if (name.empty()) continue;
    auto [it, fresh] = tag_of.emplace(name, static_cast<std::int64_t>(p.face_names.size()) + 1);
    if (fresh) p.face_names.push_back(name);
    p.face_group[f] = it->second;
  }
  if (!p.face_names.empty() || !model->solids.empty()) {
    const auto unnamed = static_cast<std::int64_t>(p.face_names.size()) + 1;
    bool any = false;
    for (std::int64_t& g : p.face_group)
      if (g == 0) g = unnamed, any = true;
    if (any) p.face_names.push_back("unnamed_faces");
    p.curve_group = p.point_group = 1;
  }
  return p;
}

namespace {

// A name inside the double quotes of $PhysicalNames: Gmsh reads up to the next quote and
// the line end, so both are replaced.
std::string quoted_name(const std::string& name) {
  std::string q;
  for (char ch : name) q += (ch == '"' || ch == '\n' || ch == '\r') ? '_' : ch;
  return '"' + q + '"';
}

// $PhysicalNames (ASCII in binary files too) for the named surface groups and the volume
// groups of the written volumes (volume_tags: the solid tags written, in order).
void write_physical_names(Sink& out, const Physicals& p,
                          const std::vector<std::int64_t>& volume_tags) {
  std::vector<std::tuple<int, std::int64_t, std::string>> groups;
  if (p.point_group > 0) groups.emplace_back(0, p.point_group, "model_vertices");
  if (p.curve_group > 0) groups.emplace_back(1, p.curve_group, "model_edges");
  for (std::size_t g = 0; g < p.face_names.size(); ++g)
    groups.emplace_back(2, static_cast<std::int64_t>(g) + 1, p.face_names[g]);
  if (p.solids)
    for (std::int64_t t : volume_tags)
      groups.emplace_back(3, t, p.solid_names[static_cast<std::size_t>(t - 1)]);
  if (groups.empty()) return;
  out.put("$PhysicalNames\n");
  out.num(groups.size());
  out.put('\n');
  for (const auto& [dim, tag, name] : groups) {
    out.num(dim);
    out.put(' ');
    out.num(tag);
    out.put(' ');
    out.put(quoted_name(name));
    out.put('\n');
  }
  out.put("$EndPhysicalNames\n");
}

// Nodes grouped by entity: keys are vertices, then edges, then faces, so iterating the
// keys in order gives Gmsh's usual dimension-then-tag block order.
struct NodeGroups {
  Buckets b;
  std::size_t base[3];
  std::size_t key(int dim, std::size_t id) const { return base[dim] + id; }
};

// A volume (model only): a solid with the written faces of its shells.
struct Volume {
  std::int64_t tag;
  geom::Box3 box;
  std::vector<std::int64_t> surfaces;
};

// What a .msh 4.1 file says about the mesh's entities, gathered before writing: nodes
// and elements grouped by entity, boxes, bounding entities.
struct Msh41Layout {
  Msh41Layout(const SurfaceMesh& mesh, const geom::Model* mdl, const Counts& counts,
              const surface::TetMesh* volume)
      : m(mesh), model(mdl), c(counts), vol(volume) {}
  const SurfaceMesh& m;
  const geom::Model* model;
  const Counts& c;
  const surface::TetMesh* vol;  // null: surface only
  NodeGroups ng;
  // With tetrahedra: interior nodes (index - surface points) and tetrahedra per solid.
  Buckets interior, tets;
  std::size_t solids = 0;
  Buckets segs, tris;
  std::vector<geom::Box3> curve_box, surface_box;
  std::vector<std::vector<std::int64_t>> curve_points, surface_curves;
  std::vector<Volume> volumes;
  // An entity is written when it carries nodes or elements, so that every tag the file
  // mentions (bounding entities included) is defined in it.
  bool has_point(std::size_t v) const { return ng.b.size(ng.key(0, v)) > 0; }
  bool has_curve(std::size_t e) const { return ng.b.size(ng.key(1, e)) > 0 || segs.size(e) > 0; }
  bool has_surface(std::size_t f) const { return ng.b.size(ng.key(2, f)) > 0 || tris.size(f) > 0; }
};

std::int64_t i64(std::size_t v) {
  return static_cast<std::int64_t>(v);
}

void group_by_entity(Msh41Layout& L) {
  const SurfaceMesh& m = L.m;
  const Counts& c = L.c;
  NodeGroups& ng = L.ng;
  ng.base[0] = 0;
  ng.base[1] = c.vertices;
  ng.base[2] = c.vertices + c.edges;
  ng.b = bucket(m.points.size(), c.vertices + c.edges + c.faces, [&](std::size_t i) {
    return ng.key(m.point_dim[i], static_cast<std::size_t>(m.point_entity[i]));
  });
  L.segs = bucket(m.segments.size(), c.edges,
                  [&](std::size_t s) { return static_cast<std::size_t>(m.segments[s].edge); });
  L.tris = bucket(m.triangles.size(), c.faces,
                  [&](std::size_t t) { return static_cast<std::size_t>(m.triangle_face[t]); });
  if (!L.vol) return;
  const surface::TetMesh& v = *L.vol;
  for (geom::Id s : v.interior_point_solid)
    L.solids = std::max(L.solids, static_cast<std::size_t>(s) + 1);
  for (geom::Id s : v.tet_solid) L.solids = std::max(L.solids, static_cast<std::size_t>(s) + 1);
  L.interior = bucket(v.interior_point_solid.size(), L.solids, [&](std::size_t i) {
    return static_cast<std::size_t>(v.interior_point_solid[i]);
  });
  L.tets = bucket(v.tets.size(), L.solids,
                  [&](std::size_t t) { return static_cast<std::size_t>(v.tet_solid[t]); });
}

// Bounding boxes from the mesh (the file describes the mesh; a model's curves need not
// give boxes cheaply): an entity's own nodes plus the nodes of its elements.
void entity_boxes(Msh41Layout& L) {
  const SurfaceMesh& m = L.m;
  std::vector<geom::Box3>&curve_box = L.curve_box, &surface_box = L.surface_box;
  curve_box.assign(L.c.edges, {});
  surface_box.assign(L.c.faces, {});
  for (std::size_t i = 0; i < m.points.size(); ++i) {
    if (m.point_dim[i] == 1)
      curve_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
    if (m.point_dim[i] == 2)
      surface_box[static_cast<std::size_t>(m.point_entity[i])].add(m.points[i]);
  }
  for (const auto& s : m.segments) {
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.a)]);
    curve_box[static_cast<std::size_t>(s.edge)].add(m.points[static_cast<std::size_t>(s.b)]);
  }
  for (std::size_t t = 0; t < m.triangles.size(); ++t)
    for (NodeId v : m.triangles[t])
      surface_box[static_cast<std::size_t>(m.triangle_face[t])].add(
          m.points[static_cast<std::size_t>(v)]);
}

// Bounding points of each curve, begin vertex +tag and end vertex -tag (Gmsh's own
// convention in its MSH4 entity writer; a closed curve lists its vertex twice). With a
// model, the edge's v0/v1; without, the model-vertex nodes at the ends of its segment
// chain (segments are in curve-parameter order).
void curve_bounding_points(Msh41Layout& L) {
  const SurfaceMesh& m = L.m;
  const Counts& c = L.c;
  const Buckets& segs = L.segs;
  L.curve_points.assign(c.edges, {});
  for (std::size_t e = 0; e < c.edges; ++e) {
    if (!L.has_curve(e)) continue;
    auto add = [&](geom::Id v, int sign) {
      if (v >= 0 && static_cast<std::size_t>(v) < c.vertices &&
          L.has_point(static_cast<std::size_t>(v)))
        L.curve_points[e].push_back(sign * one_based(v));
    };
    if (L.model) {
      add(L.model->edges[e].v0, 1);
      add(L.model->edges[e].v1, -1);
    } else if (segs.size(e) > 0) {
      auto vertex_of = [&](NodeId n) {
        const auto i = static_cast<std::size_t>(n);
        return m.point_dim[i] == 0 ? m.point_entity[i] : geom::kNone;
      };
      add(vertex_of(m.segments[static_cast<std::size_t>(segs.order[segs.first[e]])].a), 1);
      add(vertex_of(m.segments[static_cast<std::size_t>(segs.order[segs.first[e + 1] - 1])].b), -1);
    }
  }
}

// Bounding curves of each surface (model only): every edge its loops use, once, signed
// by the direction of the use relative to the written triangles. Loops run with the
// surface's natural normal and the mesh flips reversed faces (geom/model.h), so a use
// runs against the triangles (negative) when exactly one of use.reversed and
// face.reversed holds.
void surface_bounding_curves(Msh41Layout& L) {
  const Counts& c = L.c;
  std::vector<std::vector<std::int64_t>>& surface_curves = L.surface_curves;
  surface_curves.assign(c.faces, {});
  if (!L.model) return;
  std::vector<char> seen(c.edges, 0);
  for (std::size_t f = 0; f < c.faces; ++f) {
    if (!L.has_surface(f)) continue;
    const geom::Face& face = L.model->faces[f];
    for (const geom::Loop& loop : face.loops)
      for (const geom::EdgeUse& use : loop.uses) {
        if (use.edge < 0 || static_cast<std::size_t>(use.edge) >= c.edges) continue;
        const auto e = static_cast<std::size_t>(use.edge);
        if (seen[e] || !L.has_curve(e)) continue;  // a seam is listed once
        seen[e] = 1;
        const int sign = use.reversed != face.reversed ? -1 : 1;
        surface_curves[f].push_back(sign * one_based(e));
      }
    for (std::int64_t t : surface_curves[f]) seen[static_cast<std::size_t>(std::abs(t) - 1)] = 0;
  }
}

// Volumes (model only): each solid with the written faces of its shells. Triangles
// are oriented outward for solids, and a discrete surface's orientation is its
// triangles', so every bounding surface is listed with +.
void solid_volumes(Msh41Layout& L) {
  const geom::Model* model = L.model;
  if (!model) return;
  for (std::size_t s = 0; s < model->solids.size(); ++s) {
    Volume vol{one_based(s), {}, {}};
    for (geom::Id sh : model->solids[s].shells) {
      if (sh < 0 || static_cast<std::size_t>(sh) >= model->shells.size()) continue;
      for (geom::Id f : model->shells[static_cast<std::size_t>(sh)].faces) {
        if (f < 0 || static_cast<std::size_t>(f) >= L.c.faces ||
            !L.has_surface(static_cast<std::size_t>(f)))
          continue;
        vol.surfaces.push_back(one_based(f));
        vol.box.add(L.surface_box[static_cast<std::size_t>(f)]);
      }
    }
    if (!vol.surfaces.empty()) L.volumes.push_back(std::move(vol));
  }
}

void write_msh41_header(Sink& out, const Msh41Layout& L, const Physicals& phys, bool binary) {
  out.put(binary ? "$MeshFormat\n4.1 1 8\n" : "$MeshFormat\n4.1 0 8\n");
  if (binary) {
    put_le(out, std::int32_t{1});  // endianness marker
    out.put('\n');
  }
  out.put("$EndMeshFormat\n");
  std::vector<std::int64_t> volume_tags;
  for (const Volume& vol : L.volumes) volume_tags.push_back(vol.tag);
  write_physical_names(out, phys, volume_tags);
}

void write_msh41_entities(Sink& out, Record& r, const Msh41Layout& L, const Physicals& phys) {
  const Counts& c = L.c;
  std::size_t n_points = 0, n_curves = 0, n_surfaces = 0;
  for (std::size_t v = 0; v < c.vertices; ++v) n_points += L.has_point(v);
  for (std::size_t e = 0; e < c.edges; ++e) n_curves += L.has_curve(e);
  for (std::size_t f = 0; f < c.faces; ++f) n_surfaces += L.has_surface(f);
  out.put("$Entities\n");
  r.z(i64(n_points)).z(i64(n_curves)).z(i64(n_surfaces)).z(i64(L.volumes.size())).end();
  // Curve / surface / volume record: tag, bbox, physical tags, the bounding entities.
  auto entity = [&](std::int64_t tag, const geom::Box3& box, std::int64_t physical,
                    const std::vector<std::int64_t>& bounding) {
    r.i(tag).xyz(box.lo).xyz(box.hi).z(physical > 0 ? 1 : 0);
    if (physical > 0) r.i(physical);
    r.z(i64(bounding.size()));
    for (std::int64_t t : bounding) r.i(t);
    r.end();
  };
  // Point: tag x y z numPhysicalTags physicalTags.
  for (std::size_t v = 0; v < c.vertices; ++v) {
    if (!L.has_point(v)) continue;
    r.i(one_based(v))
        .xyz(L.m.points[static_cast<std::size_t>(L.ng.b.order[L.ng.b.first[L.ng.key(0, v)]])]);
    r.z(phys.point_group > 0 ? 1 : 0);
    if (phys.point_group > 0) r.i(phys.point_group);
    r.end();
  }
  for (std::size_t e = 0; e < c.edges; ++e)
    if (L.has_curve(e)) entity(one_based(e), L.curve_box[e], phys.curve_group, L.curve_points[e]);
  for (std::size_t f = 0; f < c.faces; ++f)
    if (L.has_surface(f))
      entity(one_based(f), L.surface_box[f], phys.face_group.empty() ? 0 : phys.face_group[f],
             L.surface_curves[f]);
  for (const Volume& vol : L.volumes)
    entity(vol.tag, vol.box, phys.solids ? vol.tag : 0, vol.surfaces);
  if (r.binary()) out.put('\n');
  out.put("$EndEntities\n");
}

// $Nodes: numBlocks numNodes minTag maxTag, then per block "dim tag parametric n",
// the n node tags, the n coordinate lines. Node tag = index + 1 whatever the block order.
void write_msh41_nodes(Sink& out, Record& r, const Msh41Layout& L) {
  const Counts& c = L.c;
  const NodeGroups& ng = L.ng;
  const std::size_t np = L.vol ? L.vol->points.size() : L.m.points.size();
  const std::size_t num_keys = ng.b.first.size() - 1;
  std::size_t node_blocks = 0;
  for (std::size_t k = 0; k < num_keys; ++k) node_blocks += ng.b.size(k) > 0;
  for (std::size_t s = 0; s < L.solids; ++s) node_blocks += L.interior.size(s) > 0;
  out.put("$Nodes\n");
  r.z(i64(node_blocks)).z(i64(np)).z(np > 0 ? 1 : 0).z(i64(np)).end();
  for (int dim = 0; dim < 3; ++dim) {
    const std::size_t n_ent = dim == 0 ? c.vertices : dim == 1 ? c.edges : c.faces;
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = ng.key(dim, id);
      if (ng.b.size(k) == 0) continue;
      r.i(dim).i(one_based(id)).i(0).z(i64(ng.b.size(k))).end();  // parametric = 0
      ng.b.each(k, [&](std::size_t i) { r.z(one_based(i)).end(); });
      ng.b.each(k, [&](std::size_t i) { r.xyz(L.m.points[i]).end(); });
    }
  }
  const std::size_t first_interior = L.m.points.size();
  for (std::size_t s = 0; s < L.solids; ++s) {
    if (L.interior.size(s) == 0) continue;
    r.i(3).i(one_based(s)).i(0).z(i64(L.interior.size(s))).end();
    L.interior.each(s, [&](std::size_t i) { r.z(one_based(first_interior + i)).end(); });
    L.interior.each(s, [&](std::size_t i) { r.xyz(L.vol->points[first_interior + i]).end(); });
  }
  if (r.binary()) out.put('\n');
  out.put("$EndNodes\n");
}

// $Elements: a point element (type 15) per model-vertex node, 2-node lines (type 1)
// per curve, 3-node triangles (type 2) per surface; tags 1..N in that order.
void write_msh41_elements(Sink& out, Record& r, const Msh41Layout& L) {
  const SurfaceMesh& m = L.m;
  const Counts& c = L.c;
  const NodeGroups& ng = L.ng;
  std::size_t vertex_nodes = ng.b.first[ng.base[1]];
  std::size_t elem_blocks = 0;
  for (std::size_t v = 0; v < c.vertices; ++v) elem_blocks += L.has_point(v);
  for (std::size_t e = 0; e < c.edges; ++e) elem_blocks += L.segs.size(e) > 0;
  for (std::size_t f = 0; f < c.faces; ++f) elem_blocks += L.tris.size(f) > 0;
  for (std::size_t s = 0; s < L.solids; ++s) elem_blocks += L.tets.size(s) > 0;
  const std::size_t n_elems =
      vertex_nodes + m.segments.size() + m.triangles.size() + (L.vol ? L.vol->tets.size() : 0);
  out.put("$Elements\n");
  r.z(i64(elem_blocks)).z(i64(n_elems)).z(n_elems > 0 ? 1 : 0).z(i64(n_elems)).end();
  // One block per entity that has elements: "dim tag type n", then n records
  // "elementTag nodeTag...". Element tags run on across blocks.
  std::int64_t tag = 1;
  auto blocks = [&](int dim, int type, const Buckets& b, std::size_t key0, std::size_t n_ent,
                    auto nodes_of) {
    for (std::size_t id = 0; id < n_ent; ++id) {
      const std::size_t k = key0 + id;
      if (b.size(k) == 0) continue;
      r.i(dim).i(one_based(id)).i(type).z(i64(b.size(k))).end();
      b.each(k, [&](std::size_t i) {
        r.z(tag++);
        nodes_of(i);
        r.end();
      });
    }
  };
  blocks(0, 15, ng.b, ng.base[0], c.vertices, [&](std::size_t i) { r.z(one_based(i)); });
  blocks(1, 1, L.segs, 0, c.edges,
         [&](std::size_t s) { r.z(one_based(m.segments[s].a)).z(one_based(m.segments[s].b)); });
  blocks(2, 2, L.tris, 0, c.faces, [&](std::size_t t) {
    for (NodeId v : m.triangles[t]) r.z(one_based(v));
  });
  if (L.vol)
    blocks(3, 4, L.tets, 0, L.solids, [&](std::size_t t) {
      for (NodeId v : L.vol->tets[t]) r.z(one_based(v));
    });
  if (r.binary()) out.put('\n');
  out.put("$EndElements\n");
}

}  // namespace

void write_msh41(Sink& out, const SurfaceMesh& m, const geom::Model* model, const Counts& c,
                 const Physicals& phys, bool binary, const surface::TetMesh* vol) {
  Msh41Layout L(m, model, c, vol);
  group_by_entity(L);
  entity_boxes(L);
  curve_bounding_points(L);
  surface_bounding_curves(L);
  solid_volumes(L);
  Record r(out, binary);
  write_msh41_header(out, L, phys, binary);
  write_msh41_entities(out, r, L, phys);
  write_msh41_nodes(out, r, L);
  write_msh41_elements(out, r, L);
}

// ----------------------------------------------------------------------------- Gmsh 2.2

// The legacy format many solvers still read: one node list, one element list whose
// records carry "physical elementary" tags. No volume elements exist in a surface mesh,
// so without tetrahedra the solids' groups cannot appear (they need the 4.1 entities);
// with them, each solid's tetrahedra carry its volume group.
void write_msh22(Sink& out, const SurfaceMesh& m, Physicals phys, const surface::TetMesh* vol) {
  out.put("$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
  std::vector<std::int64_t> volume_tags;
  if (vol && phys.solids) {
    std::vector<char> has(phys.solid_names.size(), 0);
    for (geom::Id s : vol->tet_solid) has[static_cast<std::size_t>(s)] = 1;
    for (std::size_t s = 0; s < has.size(); ++s)
      if (has[s]) volume_tags.push_back(one_based(s));
  } else {
    phys.solids = false;
  }
  write_physical_names(out, phys, volume_tags);
  const std::vector<geom::Vec3>& points = vol ? vol->points : m.points;
  out.put("$Nodes\n");
  out.num(points.size());
  out.put('\n');
  for (std::size_t i = 0; i < points.size(); ++i) {
    out.num(one_based(i));
    out.put(' ');
    out.xyz(points[i]);
    out.put('\n');
  }
  out.put("$EndNodes\n$Elements\n");
  std::size_t n_vertices = 0;
  for (std::size_t i = 0; i < m.points.size(); ++i) n_vertices += m.point_dim[i] == 0;
  out.num(n_vertices + m.segments.size() + m.triangles.size() + (vol ? vol->tets.size() : 0));
  out.put('\n');
  std::int64_t tag = 1;
  for (std::size_t i = 0; i < m.points.size(); ++i)
    if (m.point_dim[i] == 0)
      out.line({tag++, 15, 2, phys.point_group, one_based(m.point_entity[i]), one_based(i)});
  for (const auto& sg : m.segments)
    out.line({tag++, 1, 2, phys.curve_group, one_based(sg.edge), one_based(sg.a), one_based(sg.b)});
  for (std::size_t t = 0; t < m.triangles.size(); ++t) {
    const auto f = static_cast<std::size_t>(m.triangle_face[t]);
    const auto& tri = m.triangles[t];
    out.line({tag++, 2, 2, phys.face_group.empty() ? 0 : phys.face_group[f], one_based(f),
              one_based(tri[0]), one_based(tri[1]), one_based(tri[2])});
  }
  if (vol)
    for (std::size_t t = 0; t < vol->tets.size(); ++t) {
      const std::int64_t solid = one_based(vol->tet_solid[t]);
      const auto& tet = vol->tets[t];
      out.line({tag++, 4, 2, phys.solids ? solid : 0, solid, one_based(tet[0]), one_based(tet[1]),
                one_based(tet[2]), one_based(tet[3])});
    }
  out.put("$EndElements\n");
}

}  // namespace uvmesh::io::detail
