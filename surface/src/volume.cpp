// The volume stage (volume.h): each closed solid's triangles, oriented outward, are handed
// to Netgen's nglib, and the tetrahedra it returns are checked against them before they
// are accepted.
#include "uvmesh/surface/volume.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <exception>
#include <map>
#include <mutex>
#include <optional>
#include <ostream>
#include <set>
#include <streambuf>

#include "uvmesh/surface/check3d.h"

namespace nglib {
#include <nglib.h>
}

// Netgen's message streams and verbosity (libmesh, declared in its msghandler.hpp, which
// nglib's packaged headers do not ship). Ng_Init points the streams at std::cout and
// std::cerr; they are pointed at a null stream while uvmesh runs Netgen, because library
// code never prints.
namespace netgen {
extern int printmessage_importance;
extern std::ostream* mycout;
extern std::ostream* myerr;
}  // namespace netgen

namespace uvmesh::surface {

namespace {

using Tri = std::array<NodeId, 3>;

std::string solid_label(const geom::Model& model, geom::Id s) {
  std::string label = "solid " + std::to_string(s + 1);
  const std::string& name = model.solids[static_cast<std::size_t>(s)].name;
  if (!name.empty()) label += " \"" + name + "\"";
  return label;
}

std::pair<NodeId, NodeId> undirected(NodeId a, NodeId b) {
  return {std::min(a, b), std::max(a, b)};
}

// The solid's triangles oriented outward, or why they cannot be. An interface face is
// oriented for one of its two solids only, so orientation is decided per solid: faces are
// flipped as a whole until every edge is traversed once in each direction, then each
// connected shell is turned so that the largest one encloses a positive volume and the
// others (voids) a negative one.
std::optional<std::vector<Tri>> orient_outward(const SurfaceMesh& m, const SolidSurface& ss,
                                               std::string& why) {
  std::map<geom::Id, std::size_t> face_index;
  for (geom::Id f : ss.faces) face_index.emplace(f, face_index.size());
  // edge -> (local face, same direction as (a<b)?) for each use
  std::map<std::pair<NodeId, NodeId>, std::vector<std::pair<std::size_t, bool>>> uses;
  for (TriId t : ss.triangles) {
    const Tri& tri = m.triangles[static_cast<std::size_t>(t)];
    const std::size_t f = face_index.at(m.triangle_face[static_cast<std::size_t>(t)]);
    for (int i = 0; i < 3; ++i) {
      const NodeId a = tri[static_cast<std::size_t>(i)],
                   b = tri[static_cast<std::size_t>((i + 1) % 3)];
      uses[undirected(a, b)].push_back({f, a < b});
    }
  }
  const std::size_t nf = face_index.size();
  std::vector<std::vector<std::pair<std::size_t, int>>> adj(nf);  // neighbour, must differ?
  for (const auto& [e, u] : uses) {
    if (u.size() != 2) {
      why = "edge used by " + std::to_string(u.size()) + " triangles";
      return std::nullopt;
    }
    // Same direction twice: the two faces need opposite flips (or, within one face, the
    // face's own triangles disagree: no flip of the face can fix that).
    const int differ = u[0].second == u[1].second ? 1 : 0;
    if (u[0].first == u[1].first) {
      if (differ) {
        why = "face " + std::to_string(ss.faces[u[0].first] + 1) + " is not consistently oriented";
        return std::nullopt;
      }
      continue;
    }
    adj[u[0].first].push_back({u[1].first, differ});
    adj[u[1].first].push_back({u[0].first, differ});
  }
  std::vector<int> flip(nf, -1), component(nf, -1);
  int components = 0;
  for (std::size_t seed = 0; seed < nf; ++seed) {
    if (flip[seed] >= 0) continue;
    std::vector<std::size_t> stack = {seed};
    flip[seed] = 0;
    component[seed] = components;
    while (!stack.empty()) {
      const std::size_t f = stack.back();
      stack.pop_back();
      for (auto [g, differ] : adj[f]) {
        const int want = flip[f] ^ differ;
        if (flip[g] < 0) {
          flip[g] = want;
          component[g] = components;
          stack.push_back(g);
        } else if (flip[g] != want) {
          why = "its faces cannot be oriented consistently (not a closed orientable surface)";
          return std::nullopt;
        }
      }
    }
    ++components;
  }
  std::vector<Tri> out;
  std::vector<int> out_component;
  std::vector<double> volume(static_cast<std::size_t>(components), 0.0);
  for (TriId t : ss.triangles) {
    Tri tri = m.triangles[static_cast<std::size_t>(t)];
    const std::size_t f = face_index.at(m.triangle_face[static_cast<std::size_t>(t)]);
    if (flip[f]) std::swap(tri[1], tri[2]);
    const geom::Vec3 o(0.0);
    volume[static_cast<std::size_t>(component[f])] += tet_volume(
        o, m.points[static_cast<std::size_t>(tri[0])], m.points[static_cast<std::size_t>(tri[1])],
        m.points[static_cast<std::size_t>(tri[2])]);
    out.push_back(tri);
    out_component.push_back(component[f]);
  }
  std::size_t outer = 0;
  for (std::size_t c = 1; c < volume.size(); ++c)
    if (std::abs(volume[c]) > std::abs(volume[outer])) outer = c;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const double v = volume[static_cast<std::size_t>(out_component[i])];
    const bool is_outer = static_cast<std::size_t>(out_component[i]) == outer;
    if ((is_outer && v < 0) || (!is_outer && v > 0)) std::swap(out[i][1], out[i][2]);
  }
  return out;
}

struct NullBuffer : std::streambuf {
  int overflow(int c) override { return c; }
};

// Netgen's global state (see volume.h): one session at a time.
std::mutex& netgen_mutex() {
  static std::mutex m;
  return m;
}

struct NetgenOutput {
  std::vector<geom::Vec3> points;        // Netgen's points, in its order
  std::vector<std::array<int, 4>> tets;  // 0-based into points
  std::string error;
};

// One Netgen session for one solid: `local` points (1-based in Netgen in this order) and
// the outward triangles in local indices.
NetgenOutput run_netgen(const std::vector<geom::Vec3>& local, const std::vector<Tri>& tris,
                        const VolumeOptions& opts) {
  NetgenOutput out;
  std::lock_guard<std::mutex> lock(netgen_mutex());
  NullBuffer null_buffer;
  std::ostream null_stream(&null_buffer);
  const int old_importance = netgen::printmessage_importance;
  nglib::Ng_Init();
  std::ostream* const old_cout = netgen::mycout;
  std::ostream* const old_cerr = netgen::myerr;
  netgen::mycout = &null_stream;
  netgen::myerr = &null_stream;
  netgen::printmessage_importance = 0;
  nglib::Ng_Mesh* mesh = nglib::Ng_NewMesh();
  try {
    for (const geom::Vec3& p : local) {
      double x[3] = {p.x, p.y, p.z};
      nglib::Ng_AddPoint(mesh, x);
    }
    for (const Tri& t : tris) {
      int pi[3] = {t[0] + 1, t[1] + 1, t[2] + 1};
      nglib::Ng_AddSurfaceElement(mesh, nglib::NG_TRIG, pi);
    }
    nglib::Ng_Meshing_Parameters mp;
    if (opts.hmax > 0) {
      mp.maxh = opts.hmax;
      nglib::Ng_RestrictMeshSizeGlobal(mesh, opts.hmax);
    }
    mp.grading = opts.grading;
    mp.optsteps_3d = opts.optimize_steps;
    mp.optvolmeshenable = opts.optimize_steps > 0 ? 1 : 0;
    const nglib::Ng_Result r = nglib::Ng_GenerateVolumeMesh(mesh, &mp);
    if (r != nglib::NG_OK) {
      out.error =
          "Netgen's volume mesher failed (Ng_Result " + std::to_string(static_cast<int>(r)) + ")";
    } else {
      const int np = nglib::Ng_GetNP(mesh), ne = nglib::Ng_GetNE(mesh);
      out.points.resize(static_cast<std::size_t>(np));
      for (int i = 0; i < np; ++i) {
        double x[3];
        nglib::Ng_GetPoint(mesh, i + 1, x);
        out.points[static_cast<std::size_t>(i)] = {x[0], x[1], x[2]};
      }
      for (int e = 0; e < ne; ++e) {
        int pi[10];
        if (nglib::Ng_GetVolumeElement(mesh, e + 1, pi) != nglib::NG_TET) {
          out.error = "Netgen returned a volume element that is not a tetrahedron";
          break;
        }
        out.tets.push_back({pi[0] - 1, pi[1] - 1, pi[2] - 1, pi[3] - 1});
      }
    }
  } catch (const std::exception& e) {
    out.error = std::string("Netgen's volume mesher failed: ") + e.what();
  } catch (...) {
    out.error = "Netgen's volume mesher failed (unknown exception)";
  }
  nglib::Ng_DeleteMesh(mesh);
  nglib::Ng_Exit();
  netgen::mycout = old_cout;
  netgen::myerr = old_cerr;
  netgen::printmessage_importance = old_importance;
  return out;
}

// Whether Netgen's tetrahedra keep the surface: the input points first and unchanged, every
// index valid, no flat tetrahedron, and the faces used by exactly one tetrahedron are
// exactly the input triangles (as oriented vertex sets), no face used by three or more.
// Orients every tetrahedron positively. "" when accepted.
std::string verify(const std::vector<geom::Vec3>& local, const std::vector<Tri>& tris,
                   NetgenOutput& ng) {
  if (ng.points.size() < local.size()) return "Netgen returned fewer points than it was given";
  for (std::size_t i = 0; i < local.size(); ++i)
    if (ng.points[i] != local[i])
      return "Netgen moved surface point " + std::to_string(i + 1) + " of the solid";
  if (ng.tets.empty()) return "Netgen returned no tetrahedra";
  std::map<std::array<int, 3>, int> faces;
  for (auto& t : ng.tets) {
    for (int k : t)
      if (k < 0 || static_cast<std::size_t>(k) >= ng.points.size())
        return "Netgen returned a tetrahedron with an invalid point index";
    const double v = tet_volume(
        ng.points[static_cast<std::size_t>(t[0])], ng.points[static_cast<std::size_t>(t[1])],
        ng.points[static_cast<std::size_t>(t[2])], ng.points[static_cast<std::size_t>(t[3])]);
    if (v == 0.0) return "Netgen returned a flat tetrahedron";
    if (v < 0) std::swap(t[2], t[3]);
    static constexpr int kFace[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
    for (const auto& f : kFace) {
      std::array<int, 3> key = {t[static_cast<std::size_t>(f[0])],
                                t[static_cast<std::size_t>(f[1])],
                                t[static_cast<std::size_t>(f[2])]};
      std::sort(key.begin(), key.end());
      ++faces[key];
    }
  }
  std::set<std::array<int, 3>> boundary;
  for (const auto& [k, c] : faces) {
    if (c > 2) return "a face of Netgen's tetrahedra is used by three or more of them";
    if (c == 1) boundary.insert(k);
  }
  std::set<std::array<int, 3>> input;
  for (const Tri& t : tris) {
    std::array<int, 3> key = {t[0], t[1], t[2]};
    std::sort(key.begin(), key.end());
    input.insert(key);
  }
  if (boundary != input)
    return "the boundary of Netgen's tetrahedra is not the solid's surface mesh (" +
           std::to_string(boundary.size()) + " boundary faces for " + std::to_string(input.size()) +
           " triangles)";
  return "";
}

// Fills one solid into `res`, or records why not.
void fill_one(const geom::Model& model, const SurfaceMesh& m, geom::Id s, const VolumeOptions& opts,
              VolumeResult& res) {
  const auto t0 = std::chrono::steady_clock::now();
  auto fail = [&](const std::string& reason) {
    res.failed.push_back(
        {s, model.solids[static_cast<std::size_t>(s)].name, solid_label(model, s) + ": " + reason});
  };
  const SolidSurface ss = solid_surface(m, model, s);
  if (ss.triangles.empty()) return fail("no triangles on its faces");
  if (!ss.watertight()) {
    if (!ss.closed) return fail("a shell of it is open in the model (surface not closed)");
    return fail("surface not closed: " + std::to_string(ss.free_edges) + " free edges, " +
                std::to_string(ss.non_manifold_edges) + " non-manifold edges");
  }
  std::string why;
  const std::optional<std::vector<Tri>> outward = orient_outward(m, ss, why);
  if (!outward) return fail("surface not closed: " + why);
  // Local numbering: the solid's nodes in ascending global order.
  std::map<NodeId, int> to_local;
  for (const Tri& t : *outward)
    for (NodeId n : t) to_local.emplace(n, 0);
  std::vector<NodeId> to_global;
  std::vector<geom::Vec3> local;
  for (auto& [g, l] : to_local) {
    l = static_cast<int>(to_global.size());
    to_global.push_back(g);
    local.push_back(m.points[static_cast<std::size_t>(g)]);
  }
  std::vector<Tri> tris;
  for (const Tri& t : *outward) tris.push_back({to_local[t[0]], to_local[t[1]], to_local[t[2]]});
  NetgenOutput ng = run_netgen(local, tris, opts);
  if (!ng.error.empty()) return fail(ng.error);
  const std::string bad = verify(local, tris, ng);
  if (!bad.empty()) return fail(bad);
  TetMesh& v = res.mesh;
  const auto first_new = static_cast<NodeId>(v.points.size());
  for (std::size_t i = local.size(); i < ng.points.size(); ++i) {
    v.points.push_back(ng.points[i]);
    v.interior_point_solid.push_back(s);
  }
  auto global = [&](int k) {
    return static_cast<std::size_t>(k) < local.size()
               ? to_global[static_cast<std::size_t>(k)]
               : first_new + static_cast<NodeId>(static_cast<std::size_t>(k) - local.size());
  };
  for (const auto& t : ng.tets) {
    v.tets.push_back({global(t[0]), global(t[1]), global(t[2]), global(t[3])});
    v.tet_solid.push_back(s);
  }
  const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  res.solids.push_back({s, tris.size(), ng.tets.size(), ng.points.size() - local.size(), secs});
}

}  // namespace

VolumeResult fill_solids(const geom::Model& model, const SurfaceMesh& mesh,
                         const VolumeOptions& opts) {
  VolumeResult res;
  res.mesher = "netgen nglib";
  res.mesh.points = mesh.points;
  res.mesh.surface_points = mesh.points.size();
  std::vector<geom::Id> which = opts.solids;
  if (which.empty())
    for (std::size_t s = 0; s < model.solids.size(); ++s) which.push_back(static_cast<geom::Id>(s));
  for (geom::Id s : which) {
    if (s < 0 || static_cast<std::size_t>(s) >= model.solids.size()) {
      res.failed.push_back({s, "", "solid " + std::to_string(s + 1) + ": no such solid"});
      continue;
    }
    fill_one(model, mesh, s, opts, res);
  }
  return res;
}

}  // namespace uvmesh::surface
