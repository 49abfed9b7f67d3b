// Issue 5 acceptance: every cage of ../shared/data/subd meshed on its OpenSubdiv limit
// surface by surface::mesh_model (the CAD pipeline), then checked:
//   * closed cages: 0 free and 0 non-manifold edges, no self-intersection, and
//     `tetgen -pYQ` fills the mesh;
//   * every vertex on the limit surface at its (face, u, v) within 1e-9 of the diagonal;
//   * chordal deviation (centroids and edge midpoints) within the requested tolerance;
//   * creases (sharpness > 0 edges) and corners are mesh edges and vertices;
//   * >= 95% of the triangles with Q < 1.5.
// One line per cage is printed (the acceptance table of the closing note).
#include <unistd.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <map>
#include <set>
#include <string>

#include "subd_patch.h"  // private to geom: SubdPatch, the patch domains
#include "uvmesh/geom/subd.h"
#include "uvmesh/io/mesh_writer.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;

namespace {

std::string cage_path(const std::string& name) {
  return std::string(UVMESH_SHARED_DATA) + "/subd/" + name;
}

struct Case {
  std::string name;
  bool closed;
  // catmark_car: its limit surface crosses itself (two rings of six patches, 1214-1219
  // and 1226-1231, which share no vertex). Mesh crossings are then accepted only between
  // patches whose dense tessellations cross too (limit_patches_cross).
  bool limit_self_intersects = false;
};

const std::vector<Case> kCases = {
    {"catmark_cube.obj", true},           {"catmark_cube_creases1.obj", true},
    {"catmark_chaikin0.obj", true},       {"catmark_torus.obj", true},
    {"loop_icosahedron.obj", true},       {"loop_cube_creases1.obj", true},
    {"catmark_tent_creases1.obj", false}, {"catmark_helmet.obj", false},
    {"catmark_pole64.obj", false},        {"catmark_nonman_edges.obj", false},
    {"catmark_pawn.obj", false},          {"catmark_car.obj", false, true}};

// The limit surface of patch f sampled on an n x n grid of each of its quads (the unit
// square, or every quad of an n-gon patch's polygon, mapped to the patch's domain),
// appended to `out` as triangles.
void dense_patch(const geom::SubdModelResult& sr, geom::Id f, int n, surface::SurfaceMesh& out) {
  const geom::SubdPatch& P = (*sr.patches)[static_cast<std::size_t>(f)];
  const geom::Surface& s = *sr.model.faces[static_cast<std::size_t>(f)].surface;
  const int quads = P.polygon.empty() ? 1 : P.face_size;
  for (int q = 0; q < quads; ++q) {
    const auto base = static_cast<surface::NodeId>(out.points.size());
    for (int i = 0; i <= n; ++i)
      for (int j = 0; j <= n; ++j) {
        geom::Vec2 uv{double(i) / n, double(j) / n};
        uv = geom::subd_patch_domain_point(P, q, uv);
        out.points.push_back(s.point(uv.x, uv.y));
        out.point_dim.push_back(2);
        out.point_entity.push_back(f);
        out.point_t.push_back(0.0);
      }
    auto id = [&](int i, int j) { return base + i * (n + 1) + j; };
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j) {
        // Loop patches are triangles: the cells beyond u + v = 1 are left out.
        if (sr.scheme == geom::SubdScheme::Loop && i + j + 1 > n) continue;
        out.triangles.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
        out.triangles.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
        out.triangle_face.push_back(f);
        out.triangle_face.push_back(f);
      }
  }
}

// True when patches a and b share no model vertex and their limit surfaces, sampled
// densely (dense_patch, 64 x 64), cross each other: the mesh cannot avoid crossing there.
bool limit_patches_cross(const geom::SubdModelResult& sr, geom::Id a, geom::Id b) {
  const geom::Model& m = sr.model;
  std::set<geom::Id> va;
  for (const auto& l : m.faces[static_cast<std::size_t>(a)].loops)
    for (const auto& u : l.uses)
      va.insert(m.edges[static_cast<std::size_t>(u.edge)].v0),
          va.insert(m.edges[static_cast<std::size_t>(u.edge)].v1);
  for (const auto& l : m.faces[static_cast<std::size_t>(b)].loops)
    for (const auto& u : l.uses)
      if (va.count(m.edges[static_cast<std::size_t>(u.edge)].v0) ||
          va.count(m.edges[static_cast<std::size_t>(u.edge)].v1))
        return false;
  surface::SurfaceMesh d;
  dense_patch(sr, a, 64, d);
  dense_patch(sr, b, 64, d);
  const surface::IntersectionReport x = surface::find_self_intersections(d, 1 << 16, 2);
  for (const auto& p : x.pairs)
    if (p.f0 != p.f1) return true;
  return false;
}

// Runs tetgen -pYQ on the mesh written as .smesh; true when it exits 0 and writes
// tetrahedra.
bool tetgen_fills(const surface::SurfaceMesh& mesh, const geom::Model& m, const std::string& stem,
                  std::string& why) {
#ifdef UVMESH_TETGEN
  const auto dir =
      std::filesystem::temp_directory_path() / ("uvmesh_subd_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string base = (dir / stem).string();
  const io::WriteResult w = io::write_mesh(mesh, &m, base + ".smesh");
  if (!w.ok) {
    why = w.error;
    return false;
  }
  const std::string cmd =
      std::string(UVMESH_TETGEN) + " -pYQ " + base + ".smesh > " + base + ".log 2>&1";
  const int rc = std::system(cmd.c_str());
  const bool ok = rc == 0 && std::filesystem::exists(base + ".1.ele") &&
                  std::filesystem::file_size(base + ".1.ele") > 0;
  if (!ok)
    why = "tetgen exit " + std::to_string(rc) + " (" + base + ".log)";
  else
    std::filesystem::remove_all(dir);
  return ok;
#else
  (void)mesh, (void)m, (void)stem;
  why = "tetgen not found at configure time";
  return false;
#endif
}

}  // namespace

TEST_CASE("subd meshing: acceptance on every corpus cage", "[subd][corpus]") {
  // self: crossing triangle pairs within one shell; on_lim: those between patches whose
  // limit surfaces cross (limit_patches_cross, checked on catmark_car only).
  std::printf("%-28s %7s %8s %5s %5s %4s %6s %5s %9s %9s %9s %6s %7s %6s %6s %s\n", "cage",
              "patches", "tris", "free", "nonm", "self", "on_lim", "tet", "on_limit", "chordal",
              "tol", "Q<1.5", "Qmax", "creas", "corn", "seconds");
  for (const Case& c : kCases) {
    INFO(c.name);
    const geom::SubdModelResult sr = geom::read_subd(cage_path(c.name), {});
    INFO(sr.error);
    REQUIRE(sr.ok);
    const geom::Model& m = sr.model;
    const double D = m.bbox.diagonal();
    surface::MeshOptions o;
    o.size = surface::default_size(m);
    o.size.hmax = D / 25;  // moderate: the whole corpus in well under a minute
    o.threads = 2;
    const auto t0 = std::chrono::steady_clock::now();
    const surface::MeshResult r = surface::mesh_model(m, o);
    const double secs =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    for (const auto& f : r.failed) UNSCOPED_INFO("face " << f.face << ": " << f.reason);
    CHECK(r.failed.empty());
    REQUIRE(!r.mesh.triangles.empty());
    const surface::SurfaceMesh& mesh = r.mesh;

    const surface::TopologyReport topo = surface::check_topology(mesh);
    // catmark_nonman_edges.obj joins sheets of opposite orientation at its non-manifold
    // edges (as OpenSubdiv's regression shape means to): its counts are reported only.
    const bool nonman = c.name == "catmark_nonman_edges.obj";
    if (!nonman) CHECK(topo.inconsistent_edges == 0);
    CHECK(topo.degenerate_triangles == 0);
    if (c.closed) {
      CHECK(topo.free_edges == 0);
      CHECK(topo.non_manifold_edges == 0);
    }
    if (!nonman) CHECK(topo.non_manifold_edges == 0);
    // Separate pieces of a cage (the car's body panels and wheels) may cross each other
    // on the limit surface as in the cage: only crossings within one shell are errors.
    const surface::IntersectionReport si_all = surface::find_self_intersections(mesh, 1 << 20, 2);
    std::size_t self = 0, self_on_limit = 0;
    std::set<std::pair<geom::Id, geom::Id>> crossing_patches;
    for (const auto& p : si_all.pairs)
      if (m.faces[p.f0].shell == m.faces[p.f1].shell) {
        ++self;
        if (p.f0 != p.f1) crossing_patches.insert(std::minmax(p.f0, p.f1));
      }
    if (c.limit_self_intersects) {
      // Every crossing lies between two patches whose limit surfaces cross.
      std::map<std::pair<geom::Id, geom::Id>, bool> real;
      for (const auto& ab : crossing_patches)
        real[ab] = limit_patches_cross(sr, ab.first, ab.second);
      for (const auto& p : si_all.pairs)
        if (m.faces[p.f0].shell == m.faces[p.f1].shell && p.f0 != p.f1)
          self_on_limit += real[std::minmax(p.f0, p.f1)];
      CHECK(self_on_limit == self);
      CHECK(self > 0);  // the limit surface crosses itself, so does the mesh
    } else if (!nonman) {
      CHECK(self == 0);
    }
    std::string tet = "-";
    if (c.closed) {
      std::string why;
      const bool ok = tetgen_fills(mesh, m, c.name.substr(0, c.name.size() - 4), why);
      INFO(why);
      CHECK(ok);
      tet = ok ? "ok" : "FAIL";
    }

    // Every corner of every triangle on the limit surface at its (face, u, v).
    double on_limit = 0;
    for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
      const geom::Surface& s = *m.faces[mesh.triangle_face[t]].surface;
      for (int k = 0; k < 3; ++k) {
        const geom::Vec2 uv = mesh.triangle_uv[t][k];
        on_limit = std::max(on_limit,
                            glm::length(s.point(uv.x, uv.y) - mesh.points[mesh.triangles[t][k]]));
      }
    }
    CHECK(on_limit <= 1e-9 * D);

    const surface::ChordalReport ch = surface::measure_chordal(mesh, m, 2);
    INFO("worst chordal sample: face " << ch.worst.face << " uv (" << ch.worst.uv.x << ", "
                                       << ch.worst.uv.y << ")");
    // The semi-sharp crease cubes were 1.37x and 1.13x over until the chordal repair
    // (edge midpoints split in the 1D stage, triangle centroids and interior edge
    // midpoints in the face mesher).
    CHECK(ch.max <= o.size.chordal_tol);
    CHECK(ch.not_converged <= ch.samples / 200);

    // Creases and corners: the mesh has an edge along every creased base edge (its
    // model edge's 1D mesh is made of triangle edges) and a vertex at every corner.
    std::set<std::pair<int, int>> tri_edges;
    for (const auto& t : mesh.triangles)
      for (int k = 0; k < 3; ++k) tri_edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
    std::size_t seg_missing = 0;  // every 1D segment is an edge of the triangles
    for (const auto& s : mesh.segments) seg_missing += !tri_edges.count(std::minmax(s.a, s.b));
    CHECK(seg_missing == 0);
    // Creased base edges: a chain of one or two model edges (two where an n-gon split
    // the base edge) between the model vertices of the crease's ends, each meshed.
    const auto cage = geom::read_obj_cage(cage_path(c.name)).cage;
    std::vector<int> seg_count(m.edges.size(), 0);
    for (const auto& s : mesh.segments) ++seg_count[s.edge];
    std::set<std::pair<geom::Id, geom::Id>> meshed;  // model vertex pairs joined by a meshed edge
    for (std::size_t e = 0; e < m.edges.size(); ++e)
      if (seg_count[e] > 0) meshed.insert(std::minmax(m.edges[e].v0, m.edges[e].v1));
    int creases = 0, creases_found = 0;
    for (const auto& k : cage.creases) {
      if (!(k.sharpness > 0)) continue;
      const geom::Id a = sr.cage_vertex[k.a], b = sr.cage_vertex[k.b];
      if (a == geom::kNone || b == geom::kNone) continue;  // on a dropped face
      ++creases;
      bool found = meshed.count(std::minmax(a, b)) > 0;
      for (geom::Id w = 0; !found && w < static_cast<geom::Id>(m.vertices.size()); ++w)
        found = meshed.count(std::minmax(a, w)) && meshed.count(std::minmax(w, b));
      creases_found += found;
    }
    CHECK(creases_found == creases);
    std::set<geom::Id> vertex_nodes;
    for (std::size_t p = 0; p < mesh.points.size(); ++p)
      if (mesh.point_dim[p] == 0) vertex_nodes.insert(mesh.point_entity[p]);
    int corners = 0, corners_found = 0;
    for (const auto& k : cage.corners) {
      if (!(k.sharpness > 0) || sr.cage_vertex[k.v] == geom::kNone) continue;
      ++corners;
      corners_found += vertex_nodes.count(sr.cage_vertex[k.v]) > 0;
    }
    CHECK(corners_found == corners);

    const surface::QualityReport q = surface::measure_quality(mesh, 5);
    // catmark_pole64 was 0.90 (CHECK_NOFAIL) until its patches at the valence-64 pole
    // were given the projected domain (geom subd_model.cpp, ProjectedSurface).
    CHECK(q.share_Q_lt_1_5 >= 0.95);
    std::printf(
        "%-28s %7zu %8zu %5zu %5zu %4zu %6zu %5s %9.2e %9.2e %9.2e %6.3f %7.2f %6d %6d %.2f\n",
        c.name.c_str(), m.faces.size(), mesh.triangles.size(), topo.free_edges,
        topo.non_manifold_edges, self, self_on_limit, tet.c_str(), on_limit / D, ch.max,
        o.size.chordal_tol, q.share_Q_lt_1_5, q.Q_max, creases_found, corners_found, secs);
    std::fflush(stdout);
  }
}
