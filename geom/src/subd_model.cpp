// OpenSubdiv back end of uvmesh::geom: the limit surface of a control cage as a Model
// (see uvmesh/geom/subd.h for the layout). model_from_cage is a list of steps over one
// CageBuild state: options, topology (subd_topology.cpp checks it), the base faces'
// limit surfaces, the n-gon domains (subd_surface.cpp), model vertices and edges, the
// patches (subd_surface.h evaluates them), then box, tolerances and shells.
#include <opensubdiv/bfr/refinerSurfaceFactory.h>
#include <opensubdiv/bfr/surface.h>
#include <opensubdiv/far/topologyDescriptor.h>
#include <opensubdiv/far/topologyRefinerFactory.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "subd_patch.h"
#include "subd_surface.h"
#include "subd_topology.h"
#include "uvmesh/geom/analytic.h"
#include "uvmesh/geom/subd.h"

namespace uvmesh::geom {
namespace {

using namespace subd_detail;
namespace Sdc = OpenSubdiv::Sdc;

// One piece of a base edge (or of a spoke inside an n-gon): a model edge on [t0, t1].
struct Piece {
  Id edge = kNone;
  double t0 = 0, t1 = 1;
};

// The state shared by the steps of model_from_cage.
struct CageBuild {
  CageBuild(const SubdCage& c, const SubdOptions& o, SubdModelResult& res)
      : cage(c), opt(o), r(res), m(res.model), nf(static_cast<int>(c.face_sizes.size())) {}
  const SubdCage& cage;
  const SubdOptions& opt;
  SubdModelResult& r;
  Model& m;
  const int nf;
  bool loop = false;
  Sdc::Options so;
  std::unique_ptr<Far::TopologyRefiner> refiner;
  const Far::TopologyLevel* lvl = nullptr;
  std::vector<std::shared_ptr<BasePatch>> base;  // per base face; null: no patch
  // Catmull-Clark n-gons as one patch (NgonSurface): the flattened polygon per base face.
  std::vector<std::vector<Vec2>> poly;
  std::vector<Vec2> poly_centre;
  std::vector<SubdPlane> poly_plane;
  std::vector<char> split, used_e;  // per base edge: split at its midpoint, in a patch
  std::vector<Id> vtx_of_base, vtx_of_mid, vtx_of_center;
  std::vector<char> placed;                  // vertex position already set
  std::vector<std::array<Piece, 2>> pieces;  // [0]: [0, 1/2] or [0,1]; [1]: [1/2, 1]
  std::vector<Id> spoke_edge;                // per (n-gon, corner), flattened
  std::vector<int> spoke_base;               // first spoke of each n-gon
  std::vector<SubdPatch> patches;            // per model face
};

// ---- scheme and options
std::string choose_scheme(CageBuild& B) {
  const SubdCage& cage = B.cage;
  SubdModelResult& r = B.r;
  const bool all_tris =
      std::all_of(cage.face_sizes.begin(), cage.face_sizes.end(), [](int n) { return n == 3; });
  r.scheme = B.opt.scheme == SubdScheme::Auto
                 ? (all_tris ? SubdScheme::Loop : SubdScheme::CatmullClark)
                 : B.opt.scheme;
  B.loop = r.scheme == SubdScheme::Loop;
  if (B.loop)
    for (int f = 0; f < B.nf; ++f)
      if (cage.face_sizes[f] != 3)
        return line_ref(cage, cage.face_lines[f]) + "the Loop scheme needs triangles; face " +
               std::to_string(f) + " has " + std::to_string(cage.face_sizes[f]) + " vertices";
  if (std::string e = check_folded_faces(cage); !e.empty()) return e;
  r.boundary = B.opt.boundary;
  if (r.boundary == SubdBoundary::FromFile)
    r.boundary = cage.interpolate_boundary == 0   ? SubdBoundary::None
                 : cage.interpolate_boundary == 2 ? SubdBoundary::EdgeAndCorner
                                                  : SubdBoundary::EdgeOnly;
  Sdc::Options& so = B.so;
  so.SetVtxBoundaryInterpolation(r.boundary == SubdBoundary::None ? Sdc::Options::VTX_BOUNDARY_NONE
                                 : r.boundary == SubdBoundary::EdgeOnly
                                     ? Sdc::Options::VTX_BOUNDARY_EDGE_ONLY
                                     : Sdc::Options::VTX_BOUNDARY_EDGE_AND_CORNER);
  so.SetCreasingMethod(cage.chaikin ? Sdc::Options::CREASE_CHAIKIN : Sdc::Options::CREASE_UNIFORM);
  // Face-varying data is not used; the default would only matter for texture coordinates.
  return {};
}

// ---- topology (OpenSubdiv decides manifoldness, boundaries and sharpness)
std::string build_topology(CageBuild& B, const FarMessages& msgs) {
  const SubdCage& cage = B.cage;
  std::vector<int> crease_pairs;
  std::vector<float> crease_w, corner_w;
  std::vector<int> corner_v, holes;
  for (const auto& k : cage.creases)
    crease_pairs.insert(crease_pairs.end(), {k.a, k.b}), crease_w.push_back(k.sharpness);
  for (const auto& k : cage.corners) corner_v.push_back(k.v), corner_w.push_back(k.sharpness);
  for (const auto& h : cage.holes) holes.push_back(h.face);

  Far::TopologyDescriptor desc;
  desc.numVertices = static_cast<int>(cage.points.size());
  desc.numFaces = B.nf;
  desc.numVertsPerFace = cage.face_sizes.data();
  desc.vertIndicesPerFace = cage.face_verts.data();
  using Factory = Far::TopologyRefinerFactory<Far::TopologyDescriptor>;
  const Factory::Options fopt(B.loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, B.so);
  auto rejected = [&](const char* what) {
    std::string e = cage.source + ": OpenSubdiv rejected the cage " + what;
    for (const auto& s : msgs.list) e += "; " + s;
    return e;
  };
  // Tags are added only once they are known to be valid (a bad index would be read out
  // of bounds by the factory), so the topology is built twice when there are tags.
  B.refiner.reset(Factory::Create(desc, fopt));
  if (!B.refiner) return rejected("topology");
  if (std::string e = check_tags(cage, B.refiner->GetLevel(0)); !e.empty()) return e;
  if (!crease_pairs.empty() || !corner_v.empty() || !holes.empty()) {
    desc.numCreases = static_cast<int>(crease_w.size());
    desc.creaseVertexIndexPairs = crease_pairs.data();
    desc.creaseWeights = crease_w.data();
    desc.numCorners = static_cast<int>(corner_v.size());
    desc.cornerVertexIndices = corner_v.data();
    desc.cornerWeights = corner_w.data();
    desc.numHoles = static_cast<int>(holes.size());
    desc.holeIndices = holes.data();
    B.refiner.reset(Factory::Create(desc, fopt));
    if (!B.refiner) return rejected("tags");
  }
  for (const auto& s : msgs.list) B.r.warnings.push_back(cage.source + ": OpenSubdiv: " + s);
  B.lvl = &B.refiner->GetLevel(0);
  return {};
}

// ---- limit surfaces of the base faces
std::string build_base_patches(CageBuild& B) {
  const SubdCage& cage = B.cage;
  SubdModelResult& r = B.r;
  Bfr::RefinerSurfaceFactory<>::Options fo;
  fo.SetApproxLevelSmooth(B.opt.approx_level_smooth);
  fo.SetApproxLevelSharp(B.opt.approx_level_sharp);
  Bfr::RefinerSurfaceFactory<> factory(*B.refiner, fo);
  B.base.assign(B.nf, nullptr);
  for (int f = 0; f < B.nf; ++f) {
    const auto fvs = B.lvl->GetFaceVertices(f);
    std::vector<int> distinct(fvs.begin(), fvs.end());
    std::sort(distinct.begin(), distinct.end());
    if (std::unique(distinct.begin(), distinct.end()) - distinct.begin() < 3) {
      // Fewer than three distinct vertices: OpenSubdiv keeps it in the topology (it
      // sharpens its neighbourhood) but it spans no area.
      r.warnings.push_back(line_ref(cage, cage.face_lines[f]) + "face " + std::to_string(f) +
                           " has fewer than 3 distinct vertices: no patch");
      r.dropped_faces.push_back(f);
      continue;
    }
    if (!factory.FaceHasLimitSurface(f)) {
      r.dropped_faces.push_back(f);
      continue;
    }
    auto b = std::make_shared<BasePatch>();
    if (!factory.InitVertexSurface(f, &b->s) || !b->s.IsValid())
      return line_ref(cage, cage.face_lines[f]) +
             "OpenSubdiv could not build the limit surface of face " + std::to_string(f);
    b->points.resize(static_cast<std::size_t>(b->s.GetNumPatchPoints()) * 3);
    b->s.PreparePatchPoints(&cage.points[0].x, 3, b->points.data(), 3);
    b->triangle = B.loop;
    B.base[f] = std::move(b);
  }
  if (r.dropped_faces.size() == static_cast<std::size_t>(B.nf))
    return cage.source +
           ": no face has a limit surface (all holes, or boundary interpolation 'none' on an "
           "open cage)";
  return {};
}

// Sub-face k of n-gon f on its unit square (OpenSubdiv's quadrangulation).
std::shared_ptr<SubdSurface> subface_surface(const CageBuild& B, int f, int k) {
  const Bfr::Parameterization param = B.base[f]->s.GetParameterization();
  const double z[2] = {0.0, 0.0}, one[2] = {1.0, 1.0};
  double o[2], q[2];
  param.ConvertNormalizedSubFaceToCoord(k, z, o);
  param.ConvertNormalizedSubFaceToCoord(k, one, q);
  return std::make_shared<SubdSurface>(B.base[f], Vec2(o[0], o[1]), q[0] - o[0], true);
}

// ---- Catmull-Clark n-gons as one patch on their flattened polygon (NgonSurface), when
// that polygon splits into convex quads; else (a repeated vertex, a folded face) one
// patch per sub-face.
void flatten_ngons(CageBuild& B) {
  B.poly.assign(B.nf, {});
  B.poly_centre.assign(B.nf, Vec2(0.0));
  B.poly_plane.assign(B.nf, SubdPlane{});
  if (B.loop) return;
  for (int f = 0; f < B.nf; ++f) {
    if (!B.base[f] || B.cage.face_sizes[f] == 4) continue;
    const auto fv = B.lvl->GetFaceVertices(f);
    bool repeats = false;
    for (int i = 0; i < fv.size(); ++i)
      for (int j = 0; j < i; ++j) repeats = repeats || fv[i] == fv[j];
    if (repeats) continue;
    std::vector<Vec3> bnd;
    for (int k = 0; k < fv.size(); ++k) {
      const auto sk = subface_surface(B, f, k);
      bnd.push_back(sk->point(0.0, 0.0));
      bnd.push_back(sk->point(1.0, 0.0));
    }
    if (!flatten_ngon(bnd, subface_surface(B, f, 0)->point(1.0, 1.0), B.poly[f], B.poly_centre[f],
                      B.poly_plane[f]))
      B.poly[f].clear();
  }
}

// ---- which base edges are split at their midpoint (used by a sub-face patch)
void mark_split_edges(CageBuild& B) {
  const int ne = B.lvl->GetNumEdges();
  B.split.assign(ne, 0);
  B.used_e.assign(ne, 0);
  for (int f = 0; f < B.nf; ++f) {
    if (!B.base[f]) continue;
    const auto fe = B.lvl->GetFaceEdges(f);
    for (int i = 0; i < fe.size(); ++i) {
      B.used_e[fe[i]] = 1;
      if (!B.loop && fe.size() != 4) B.split[fe[i]] = 1;
    }
  }
  for (int e = 0; e < ne; ++e)
    if (B.lvl->GetEdgeFaces(e).size() > 2) ++B.r.non_manifold_edges;
}

// ---- model vertices (positions filled from the patches below)
void make_vertices(CageBuild& B) {
  Model& m = B.m;
  const int ne = B.lvl->GetNumEdges();
  B.vtx_of_base.assign(static_cast<std::size_t>(B.lvl->GetNumVertices()), kNone);
  B.vtx_of_mid.assign(ne, kNone);
  B.vtx_of_center.assign(B.nf, kNone);
  auto new_vertex = [&]() {
    m.vertices.push_back({});
    return static_cast<Id>(m.vertices.size() - 1);
  };
  for (int f = 0; f < B.nf; ++f) {
    if (!B.base[f]) continue;
    for (int v : B.lvl->GetFaceVertices(f))
      if (B.vtx_of_base[v] == kNone) B.vtx_of_base[v] = new_vertex();
  }
  for (int e = 0; e < ne; ++e)
    if (B.used_e[e] && B.split[e]) B.vtx_of_mid[e] = new_vertex();
  for (int f = 0; f < B.nf; ++f)
    if (B.base[f] && !B.loop && B.cage.face_sizes[f] != 4 && B.poly[f].empty())
      B.vtx_of_center[f] = new_vertex();
  B.placed.assign(m.vertices.size(), 0);
}

// ---- model edges: pieces of base edges, then spokes (created on first use)
void make_edges(CageBuild& B) {
  Model& m = B.m;
  const int ne = B.lvl->GetNumEdges();
  B.pieces.assign(ne, {});
  B.spoke_base.assign(B.nf, -1);
  int nspokes = 0;
  for (int f = 0; f < B.nf; ++f)
    if (B.vtx_of_center[f] != kNone) B.spoke_base[f] = nspokes, nspokes += B.cage.face_sizes[f];
  B.spoke_edge.assign(nspokes, kNone);
  for (int e = 0; e < ne; ++e) {
    if (!B.used_e[e]) continue;
    const auto ev = B.lvl->GetEdgeVertices(e);
    const Id a = B.vtx_of_base[ev[0]], b = B.vtx_of_base[ev[1]];
    if (B.split[e]) {
      B.pieces[e][0] = {static_cast<Id>(m.edges.size()), 0.0, 0.5};
      m.edges.push_back(Edge{nullptr, {0.0, 0.5}, a, B.vtx_of_mid[e]});
      B.pieces[e][1] = {static_cast<Id>(m.edges.size()), 0.5, 1.0};
      m.edges.push_back(Edge{nullptr, {0.5, 1.0}, B.vtx_of_mid[e], b});
    } else {
      B.pieces[e][0] = {static_cast<Id>(m.edges.size()), 0.0, 1.0};
      m.edges.push_back(Edge{nullptr, {0.0, 1.0}, a, b});
      // An edge from a vertex to itself (a face repeating a vertex, which OpenSubdiv
      // takes as non-manifold and sharp) has a limit curve collapsed to that vertex: a
      // degenerate edge, a pole side of its patches.
      m.edges.back().degenerate = a == b;
    }
  }
  for (int f = 0; f < B.nf; ++f)
    if (B.vtx_of_center[f] != kNone) {
      const auto fe = B.lvl->GetFaceEdges(f);
      for (int i = 0; i < fe.size(); ++i) {
        B.spoke_edge[B.spoke_base[f] + i] = static_cast<Id>(m.edges.size());
        m.edges.push_back(Edge{nullptr, {0.0, 1.0}, B.vtx_of_mid[fe[i]], B.vtx_of_center[f]});
      }
    }
}

// The first use of an edge gives it its 3D curve (the limit curve seen from that
// patch); the first patch at a vertex gives its position.
// On a projected patch `ps` the pcurve is the projection of the straight line in the
// coordinates of s (ProjectedCurve2); the edge's 3D curve always comes from s.
void add_use(CageBuild& B, Loop& loop_, const std::shared_ptr<const Surface>& s, Id edge, bool rev,
             Vec2 a, Vec2 d, const std::shared_ptr<const ProjectedSurface>& ps = nullptr) {
  Edge& ed = B.m.edges[edge];
  EdgeUse u;
  u.edge = edge;
  u.reversed = rev;
  u.range = ed.range;
  const std::shared_ptr<Curve2> line =
      make_line2(a, d, ed.range);  // same t, same point on every side
  u.pcurve = ps ? std::make_shared<ProjectedCurve2>(s, ps->plane(), line) : line;
  if (!ed.curve && !ed.degenerate) ed.curve = std::make_shared<CurveOnPatch>(s, line);
  loop_.uses.push_back(std::move(u));
}

void place(CageBuild& B, Id v, const Surface& s, Vec2 uv) {
  if (v == kNone || B.placed[v]) return;
  B.m.vertices[v].p = s.point(uv.x, uv.y);
  B.placed[v] = 1;
}

// A side of a whole-face patch from corner c0 to c1 along base edge e: its pieces in
// traversal order, each with the pcurve uv(t) of the whole edge.
void add_side(CageBuild& B, Loop& lp, const std::shared_ptr<const Surface>& s, int e, bool forward,
              Vec2 c0, Vec2 c1) {
  // Edge parameter t runs from the edge's first vertex: forward, uv(t) = c0 + t (c1 - c0).
  const Vec2 a = forward ? c0 : c1, d = forward ? c1 - c0 : c0 - c1;
  const int np = B.split[e] ? 2 : 1;
  for (int k = 0; k < np; ++k) {
    const Piece& p = B.pieces[e][forward ? k : np - 1 - k];
    add_use(B, lp, s, p.edge, !forward, a, d);
  }
}

Face patch_face(const std::shared_ptr<SubdSurface>& s) {
  Face fc;
  fc.surface = s;
  fc.kind = SurfaceKind::Other;
  fc.uv_box = s->bounds();
  return fc;
}

// Whether side i of base face f runs along its base edge's direction.
bool side_forward(const CageBuild& B, int f, int i) {
  return B.lvl->GetEdgeVertices(B.lvl->GetFaceEdges(f)[i])[0] == B.lvl->GetFaceVertices(f)[i];
}

// A Catmull-Clark n-gon as one patch on its flattened polygon, projected at a vertex of
// high valence.
void add_ngon_patch(CageBuild& B, int f) {
  const auto fv = B.lvl->GetFaceVertices(f);
  const auto fe = B.lvl->GetFaceEdges(f);
  const int n = fv.size();
  std::vector<std::shared_ptr<const SubdSurface>> sub;
  for (int k = 0; k < n; ++k) sub.push_back(subface_surface(B, f, k));
  bool high_valence = false;
  for (int v : fv)
    high_valence = high_valence || B.lvl->GetVertexEdges(v).size() >= kProjectValence;
  const auto ps = high_valence ? make_projected(sub, B.poly_plane[f]) : nullptr;
  auto s = std::make_shared<NgonSurface>(std::move(sub), B.poly[f], B.poly_centre[f]);
  Face fc;
  fc.surface = ps ? std::static_pointer_cast<const Surface>(ps) : s;
  fc.kind = SurfaceKind::Other;
  fc.uv_box = fc.surface->bounds();
  Loop lp;
  lp.outer = true;
  const std::vector<Vec2>& P = B.poly[f];
  for (int i = 0; i < n; ++i) {
    // Side i bends at its limit middle point P[2i+1] (the model vertex between the
    // edge's two pieces): each piece is a straight pcurve with the edge's parameter.
    const Vec2 a = P[2 * i], mid = P[2 * i + 1], b = P[(2 * i + 2) % (2 * n)];
    const int e = fe[i];
    if (side_forward(B, f, i)) {
      add_use(B, lp, s, B.pieces[e][0].edge, false, a, 2.0 * (mid - a), ps);
      add_use(B, lp, s, B.pieces[e][1].edge, false, 2.0 * mid - b, 2.0 * (b - mid), ps);
    } else {
      add_use(B, lp, s, B.pieces[e][1].edge, true, 2.0 * mid - a, 2.0 * (a - mid), ps);
      add_use(B, lp, s, B.pieces[e][0].edge, true, b, 2.0 * (mid - b), ps);
    }
    place(B, B.vtx_of_base[fv[i]], *s, a);
    place(B, B.vtx_of_mid[e], *s, mid);
  }
  fc.loops.push_back(std::move(lp));
  B.m.faces.push_back(std::move(fc));
  SubdPatch pt{f, -1, n, Vec2(0.0), 1.0, {}, {}, nullptr, {}};
  pt.polygon = B.poly[f];
  pt.centre = B.poly_centre[f];
  if (ps) pt.unprojected = s, pt.plane = ps->plane();
  B.patches.push_back(std::move(pt));
}

// A base face without sub-faces (a quad, a Loop triangle) as one patch on its domain.
void add_whole_patch(CageBuild& B, int f) {
  const auto fv = B.lvl->GetFaceVertices(f);
  const auto fe = B.lvl->GetFaceEdges(f);
  const int n = fv.size();
  const Bfr::Parameterization param = B.base[f]->s.GetParameterization();
  auto s = std::make_shared<SubdSurface>(B.base[f], Vec2(0.0), 1.0);
  Face fc = patch_face(s);
  Loop lp;
  lp.outer = true;
  for (int i = 0; i < n; ++i) {
    double c0[2], c1[2];
    param.GetVertexCoord(i, c0);
    param.GetVertexCoord((i + 1) % n, c1);
    add_side(B, lp, s, fe[i], side_forward(B, f, i), {c0[0], c0[1]}, {c1[0], c1[1]});
    place(B, B.vtx_of_base[fv[i]], *s, {c0[0], c0[1]});
    if (B.split[fe[i]])
      place(B, B.vtx_of_mid[fe[i]], *s, 0.5 * (Vec2(c0[0], c0[1]) + Vec2(c1[0], c1[1])));
  }
  fc.loops.push_back(std::move(lp));
  B.m.faces.push_back(std::move(fc));
  B.patches.push_back({f, -1, n, Vec2(0.0), 1.0, {}, {}, nullptr, {}});
}

// An n-gon as one patch per sub-face: sub-face k has its (0,0) corner at vertex k, (1,0)
// at the midpoint of edge k, (1,1) at the centre and (0,1) at the midpoint of edge k-1
// (OpenSubdiv's quadrangulation, the Ptex convention); CCW like the face.
void add_subface_patches(CageBuild& B, int f) {
  const auto fv = B.lvl->GetFaceVertices(f);
  const auto fe = B.lvl->GetFaceEdges(f);
  const int n = fv.size();
  for (int k = 0; k < n; ++k) {
    auto s = subface_surface(B, f, k);
    Face fc = patch_face(s);
    Loop lp;
    lp.outer = true;
    const int km = (k + n - 1) % n;
    // side 0: vertex k -> midpoint of edge k (half of edge k next to vertex k)
    {
      const int e = fe[k];
      if (side_forward(B, f, k))
        add_use(B, lp, s, B.pieces[e][0].edge, false, {0.0, 0.0}, {2.0, 0.0});
      else
        add_use(B, lp, s, B.pieces[e][1].edge, true, {2.0, 0.0}, {-2.0, 0.0});
    }
    // side 1: midpoint of edge k -> centre (spoke k, t from the midpoint)
    add_use(B, lp, s, B.spoke_edge[B.spoke_base[f] + k], false, {1.0, 0.0}, {0.0, 1.0});
    // side 2: centre -> midpoint of edge k-1 (spoke k-1 backwards)
    add_use(B, lp, s, B.spoke_edge[B.spoke_base[f] + km], true, {0.0, 1.0}, {1.0, 0.0});
    // side 3: midpoint of edge k-1 -> vertex k (half of edge k-1 next to vertex k)
    {
      const int e = fe[km];
      if (side_forward(B, f, km))
        add_use(B, lp, s, B.pieces[e][1].edge, false, {0.0, 2.0}, {0.0, -2.0});
      else
        add_use(B, lp, s, B.pieces[e][0].edge, true, {0.0, 0.0}, {0.0, 2.0});
    }
    place(B, B.vtx_of_base[fv[k]], *s, {0.0, 0.0});
    place(B, B.vtx_of_mid[fe[k]], *s, {1.0, 0.0});
    place(B, B.vtx_of_center[f], *s, {1.0, 1.0});
    fc.loops.push_back(std::move(lp));
    B.m.faces.push_back(std::move(fc));
    B.patches.push_back({f, k, n, s->origin(), s->scale(), {}, {}, nullptr, {}});
  }
}

// ---- the patches of every base face with a limit surface, in base-face order
void make_patches(CageBuild& B) {
  for (int f = 0; f < B.nf; ++f) {
    if (!B.base[f]) continue;
    if (!B.poly[f].empty())
      add_ngon_patch(B, f);
    else if (!B.base[f]->s.GetParameterization().HasSubFaces())
      add_whole_patch(B, f);
    else
      add_subface_patches(B, f);
  }
}

// Patches with a degenerate edge (a pole side) know which of their sides are singular.
void mark_singular_sides(Model& m) {
  for (Face& fc : m.faces)
    for (const EdgeUse& u : fc.loops[0].uses)
      if (m.edges[u.edge].degenerate) {
        auto s = std::const_pointer_cast<Surface>(fc.surface);
        static_cast<SubdSurface&>(*s).set_singular_sides(detect_singular_sides(*s, 1e-9));
        break;
      }
}

// Quads of a patch's domain (its n-gon's sub-faces, else 1) and its point at coordinates
// (s, t) of quad q. Sampled through subd_patch_domain_point: the domain of an n-gon patch
// is its polygon (or that polygon's projection), not the unit square, and outside it sigma
// is only an extension (far out, on a projected patch, a Taylor polynomial).
int domain_quads(const CageBuild& B, Id f) {
  return B.patches[f].polygon.empty() ? 1 : B.patches[f].face_size;
}
Vec3 domain_sample(const CageBuild& B, Id f, int q, double s_, double t_) {
  const Vec2 w = subd_patch_domain_point(B.patches[f], q, {s_, t_});
  return B.m.faces[f].surface->point(w.x, w.y);
}

// ---- bounding box of the limit surface (sampled: the cage's box is larger), tolerances
// and edge lengths
void bound_and_tolerances(CageBuild& B) {
  Model& m = B.m;
  for (Id f = 0; f < static_cast<Id>(m.faces.size()); ++f) {
    constexpr int ns = 8;
    for (int q = 0; q < domain_quads(B, f); ++q)
      for (int i = 0; i <= ns; ++i)
        for (int j = 0; j <= ns - (B.loop ? i : 0); ++j)
          m.bbox.add(domain_sample(B, f, q, double(i) / ns, double(j) / ns));
  }
  for (const Vertex& v : m.vertices) m.bbox.add(v.p);
  const double D = m.bbox.diagonal();
  // Positions are computed, not measured: the tolerances only need to absorb rounding.
  const double tol = 1e-10 * D;
  for (Vertex& v : m.vertices) v.tol = tol;
  for (Edge& e : m.edges) {
    e.tol = tol;
    e.length = e.curve ? arc_length(*e.curve, e.range.lo, e.range.hi) : 0.0;
  }
  for (Face& fc : m.faces) fc.tol = tol;
}

// ---- shells: patches connected through edges; closed when every edge has two uses
void find_shells(Model& m) {
  const auto ef = edge_faces(m);
  std::vector<Id> comp(m.faces.size(), kNone);
  for (Id f0 = 0; f0 < static_cast<Id>(m.faces.size()); ++f0) {
    if (comp[f0] != kNone) continue;
    const Id sh = static_cast<Id>(m.shells.size());
    m.shells.push_back({});
    std::vector<Id> stack{f0};
    comp[f0] = sh;
    bool closed = true;
    while (!stack.empty()) {
      const Id f = stack.back();
      stack.pop_back();
      m.shells[sh].faces.push_back(f);
      for (const Loop& l : m.faces[f].loops)
        for (const EdgeUse& u : l.uses) {
          if (ef[u.edge].size() != 2) closed = false;
          for (Id g : ef[u.edge])
            if (comp[g] == kNone) comp[g] = sh, stack.push_back(g);
        }
    }
    std::sort(m.shells[sh].faces.begin(), m.shells[sh].faces.end());
    m.shells[sh].closed = closed;
  }
  for (Id f = 0; f < static_cast<Id>(m.faces.size()); ++f) m.faces[f].shell = comp[f];
}

// Signed volume of a shell through its limit points (corner fans of sampled patches).
double shell_volume(const CageBuild& B, Id sh) {
  const Model& m = B.m;
  const bool loop = B.loop;
  double vol = 0.0;
  const Vec3 ref = m.bbox.lo;
  for (Id f : m.shells[sh].faces) {
    constexpr int ns = 4;
    for (int q = 0; q < domain_quads(B, f); ++q)
      for (int i = 0; i < ns; ++i)
        for (int j = 0; j < ns; ++j) {
          const double u0 = double(i) / ns, u1 = double(i + 1) / ns, v0 = double(j) / ns,
                       v1 = double(j + 1) / ns;
          if (loop && i + j >= ns) continue;
          const Vec3 a = domain_sample(B, f, q, u0, v0) - ref,
                     b = domain_sample(B, f, q, u1, v0) - ref,
                     c = domain_sample(B, f, q, u0, v1) - ref;
          vol += glm::dot(a, glm::cross(b, c));
          if (!loop || i + j + 1 < ns) {
            const Vec3 d = domain_sample(B, f, q, u1, v1) - ref;
            vol += glm::dot(b, glm::cross(d, c));
          }
        }
  }
  return vol;
}

// ---- closed shells are solids; a negative volume means the cage's faces turn inward,
// then every patch is flagged reversed so the mesh comes out outward.
void make_solids(CageBuild& B) {
  Model& m = B.m;
  for (Id sh = 0; sh < static_cast<Id>(m.shells.size()); ++sh) {
    if (!m.shells[sh].closed) continue;
    if (shell_volume(B, sh) < 0.0)
      for (Id f : m.shells[sh].faces) m.faces[f].reversed = true;
    Solid solid;
    solid.shells.push_back(sh);
    m.solids.push_back(std::move(solid));
  }
}

}  // namespace

bool have_opensubdiv() {
  return true;
}

SubdModelResult model_from_cage(const SubdCage& cage, const SubdOptions& opt) {
  SubdModelResult r;
  r.model.source = cage.source;
  r.model.format = "obj";
  CageBuild B(cage, opt, r);
  if (std::string e = choose_scheme(B); !e.empty()) return r.error = e, r;
  // OpenSubdiv's messages are collected (not printed) for the rest of the build.
  const FarMessages msgs;
  if (std::string e = build_topology(B, msgs); !e.empty()) return r.error = e, r;
  if (std::string e = build_base_patches(B); !e.empty()) return r.error = e, r;
  flatten_ngons(B);
  mark_split_edges(B);
  make_vertices(B);
  make_edges(B);
  make_patches(B);
  mark_singular_sides(r.model);
  r.cage_vertex.assign(cage.points.size(), kNone);
  for (std::size_t v = 0; v < B.vtx_of_base.size() && v < cage.points.size(); ++v)
    r.cage_vertex[v] = B.vtx_of_base[v];
  bound_and_tolerances(B);
  find_shells(r.model);
  make_solids(B);
  r.patches = std::make_shared<const std::vector<SubdPatch>>(std::move(B.patches));
  r.ok = true;
  return r;
}

}  // namespace uvmesh::geom
