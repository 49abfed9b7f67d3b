// bench_subd CAGE.obj... [--hmax-rel R] [--threads N]: for each cage, uvmesh's mesh of
// the limit surface (surface::mesh_model, default sizes with hmax = R * diagonal) and
// OpenSubdiv's uniform tessellation (Bfr::Tessellation, one rate for every face, chosen
// so that its triangle count is the closest to ours), both evaluated through the same
// limit patches and measured by the same code: chordal deviation (centroids and edge
// midpoints projected on the limit surface), shape quality Q, time. One markdown table
// row per cage and method on stdout.
//
// Times are CPU seconds of the process: "model" (OBJ read, OpenSubdiv topology and Bfr
// surfaces) is common to both and reported once; "mesh" is mesh_model for uvmesh,
// tessellation + limit evaluation for OpenSubdiv.
#include <opensubdiv/bfr/parameterization.h>
#include <opensubdiv/bfr/tessellation.h>
#include <time.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "subd_patch.h"  // private to geom: SubdPatch, the patch domains
#include "uvmesh/geom/project.h"
#include "uvmesh/geom/subd.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/surface/check3d.h"
#include "uvmesh/surface/mesher.h"

using namespace uvmesh;
namespace Bfr = OpenSubdiv::Bfr;
namespace Sdc = OpenSubdiv::Sdc;

namespace {

// CPU time of the process (user + system): the machine is shared, so wall clocks measure
// the neighbours; with --threads 1 both sides run on the calling thread.
struct Clock {
  using time_point = double;
  static double now() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
  }
};
double since(Clock::time_point t0) {
  return Clock::now() - t0;
}

Bfr::Parameterization param_of(const geom::SubdModelResult& r, const geom::SubdPatch& p) {
  return Bfr::Parameterization(
      r.scheme == geom::SubdScheme::Loop ? Sdc::SCHEME_LOOP : Sdc::SCHEME_CATMARK, p.face_size);
}

// Base face -> its patches (model faces), in sub-face order.
std::map<geom::Id, std::vector<geom::Id>> patches_by_base(const geom::SubdModelResult& r) {
  std::map<geom::Id, std::vector<geom::Id>> m;
  for (geom::Id f = 0; f < static_cast<geom::Id>(r.patches->size()); ++f)
    m[(*r.patches)[f].base_face].push_back(f);
  return m;
}

std::size_t uniform_count(const geom::SubdModelResult& r,
                          const std::map<geom::Id, std::vector<geom::Id>>& by_base, int rate) {
  std::size_t n = 0;
  for (const auto& [bf, pf] : by_base)
    n += Bfr::Tessellation(param_of(r, (*r.patches)[pf[0]]), rate).GetNumFacets();
  return n;
}

// OpenSubdiv's uniform tessellation evaluated on our patches: one point set per base
// face (faces are not stitched: chordal deviation and shape do not need it).
surface::SurfaceMesh tessellate(const geom::SubdModelResult& r,
                                const std::map<geom::Id, std::vector<geom::Id>>& by_base,
                                int rate) {
  surface::SurfaceMesh mesh;
  std::vector<double> uv;
  std::vector<int> facets;
  for (const auto& [bf, pf] : by_base) {
    const geom::SubdPatch& p0 = (*r.patches)[pf[0]];
    const Bfr::Parameterization param = param_of(r, p0);
    Bfr::Tessellation tess(param, rate);
    uv.resize(2 * static_cast<std::size_t>(tess.GetNumCoords()));
    tess.GetCoords(uv.data());
    facets.resize(3 * static_cast<std::size_t>(tess.GetNumFacets()));
    tess.GetFacets(facets.data());
    const auto base = static_cast<surface::NodeId>(mesh.points.size());
    // A point's patch: the sub-face holding it (n-gons), else the one patch.
    auto local = [&](int k, geom::Id f) {
      const geom::SubdPatch& p = (*r.patches)[f];
      if (!p.polygon.empty()) {
        // A whole n-gon patch: OpenSubdiv's sub-face coordinates -> its domain (the
        // polygon, or its projection for patches at a high-valence vertex).
        const double c[2] = {uv[2 * k], uv[2 * k + 1]};
        double st[2];
        const int sub = param.ConvertCoordToNormalizedSubFace(c, st);
        return geom::subd_patch_domain_point(p, sub, {st[0], st[1]});
      }
      return (geom::Vec2(uv[2 * k], uv[2 * k + 1]) - p.origin) / p.scale;
    };
    auto patch_of = [&](const geom::Vec2& face_uv) {
      if (!param.HasSubFaces() || pf.size() == 1) return pf[0];
      const double c[2] = {face_uv.x, face_uv.y};
      return pf[static_cast<std::size_t>(param.GetSubFace(c))];
    };
    for (int k = 0; k < tess.GetNumCoords(); ++k) {
      const geom::Id f = patch_of({uv[2 * k], uv[2 * k + 1]});
      const geom::Vec2 l = local(k, f);
      mesh.points.push_back(r.model.faces[f].surface->point(l.x, l.y));
    }
    for (std::size_t t = 0; t + 2 < facets.size(); t += 3) {
      const int a = facets[t], b = facets[t + 1], c = facets[t + 2];
      // The facet's patch: the one most of its corners lie in (a point shared by
      // sub-faces carries the coordinate of one of them only).
      const geom::Id fa = patch_of({uv[2 * a], uv[2 * a + 1]}),
                     fb = patch_of({uv[2 * b], uv[2 * b + 1]}),
                     fc = patch_of({uv[2 * c], uv[2 * c + 1]});
      const geom::Id f = (fb == fc) ? fb : fa;
      mesh.triangles.push_back({base + a, base + b, base + c});
      mesh.triangle_face.push_back(f);
      // Points shared by sub-faces (the centre, spoke points) carry the coordinate of
      // one sub-face only; on another sub-face their local (u,v) is found by projecting
      // the point on that patch (it lies on its boundary).
      std::array<geom::Vec2, 3> l{local(a, f), local(b, f), local(c, f)};
      const int idx[3] = {a, b, c};
      for (int k = 0; k < 3 && (*r.patches)[f].polygon.empty(); ++k)
        if (l[k].x < -1e-9 || l[k].y < -1e-9 || l[k].x > 1 + 1e-9 || l[k].y > 1 + 1e-9)
          l[k] = geom::project_to_surface(*r.model.faces[f].surface, mesh.points[base + idx[k]],
                                          glm::clamp(l[k], geom::Vec2(0.0), geom::Vec2(1.0)),
                                          {{0, 1}, {0, 1}}, r.model.bbox.diagonal())
                     .uv;
      mesh.triangle_uv.push_back(l);
    }
  }
  return mesh;
}

void row(const std::string& cage, const char* method, const surface::SurfaceMesh& m,
         const geom::Model& model, double tol, double secs, double model_secs,
         const std::string& extra) {
  const surface::QualityReport q = surface::measure_quality(m, 1);
  const surface::ChordalReport ch = surface::measure_chordal(m, model, 1);
  const double D = model.bbox.diagonal();
  if (std::getenv("BENCH_SUBD_DEBUG"))
    std::fprintf(stderr, "worst: triangle %d face %d which %d uv (%g %g) dist %g\n",
                 ch.worst.triangle, ch.worst.face, ch.worst.which, ch.worst.uv.x, ch.worst.uv.y,
                 ch.worst.distance),
        std::fprintf(stderr, "  tri face %d uv (%g %g) (%g %g) (%g %g)\n",
                     m.triangle_face[ch.worst.triangle], m.triangle_uv[ch.worst.triangle][0].x,
                     m.triangle_uv[ch.worst.triangle][0].y, m.triangle_uv[ch.worst.triangle][1].x,
                     m.triangle_uv[ch.worst.triangle][1].y, m.triangle_uv[ch.worst.triangle][2].x,
                     m.triangle_uv[ch.worst.triangle][2].y);
  std::printf(
      "| %s | %s | %zu | %.3e | %.3e | %.2f | %.3f | %.3f | %.3f | %.2f | %.3f | %.3f | %s |\n",
      cage.c_str(), method, m.triangles.size(), ch.max / D, ch.mean / D,
      tol > 0 ? ch.max / tol : 0.0, q.share_Q_lt_1_5, q.Q_p50, q.Q_p95, q.Q_max, secs, model_secs,
      extra.c_str());
  std::fflush(stdout);
}

}  // namespace

int main(int argc, char** argv) {
  double hmax_rel = 1.0 / 25;
  int threads = 1;
  std::vector<std::string> cages;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--hmax-rel" && i + 1 < argc)
      hmax_rel = std::atof(argv[++i]);
    else if (a == "--threads" && i + 1 < argc)
      threads = std::atoi(argv[++i]);
    else
      cages.push_back(a);
  }
  if (cages.empty()) {
    std::fprintf(stderr, "usage: bench_subd CAGE.obj... [--hmax-rel R] [--threads N]\n");
    return 1;
  }
  std::printf(
      "| cage | method | triangles | chordal max / D | chordal mean / D | max / tol | Q<1.5 | Q "
      "p50 | Q p95 | "
      "Q max | mesh s | model s | note |\n");
  std::printf("|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n");
  double sum_ours = 0, sum_uni = 0, tri_ours = 0, tri_uni = 0;
  for (const std::string& path : cages) {
    const std::string name = path.substr(path.find_last_of('/') + 1);
    auto t0 = Clock::now();
    const geom::SubdModelResult r = geom::read_subd(path, {});
    const double t_model = since(t0);
    if (!r.ok) {
      std::fprintf(stderr, "%s\n", r.error.c_str());
      return 2;
    }
    surface::MeshOptions o;
    o.size = surface::default_size(r.model);
    o.size.hmax = hmax_rel * r.model.bbox.diagonal();
    o.threads = threads;
    t0 = Clock::now();
    const surface::MeshResult ours = surface::mesh_model(r.model, o);
    const double t_ours = since(t0);
    row(name, "uvmesh", ours.mesh, r.model, o.size.chordal_tol, t_ours, t_model,
        ours.failed.empty() ? "" : std::to_string(ours.failed.size()) + " faces failed");

    const auto by_base = patches_by_base(r);
    int best = 1;
    for (int rate = 1; rate <= 128; ++rate) {
      const std::size_t n = uniform_count(r, by_base, rate);
      if (std::llabs(static_cast<long long>(n) -
                     static_cast<long long>(ours.mesh.triangles.size())) <
          std::llabs(static_cast<long long>(uniform_count(r, by_base, best)) -
                     static_cast<long long>(ours.mesh.triangles.size())))
        best = rate;
      if (n > ours.mesh.triangles.size()) break;
    }
    t0 = Clock::now();
    const surface::SurfaceMesh uni = tessellate(r, by_base, best);
    const double t_uni = since(t0);
    row(name, "osd uniform", uni, r.model, o.size.chordal_tol, t_uni, t_model,
        "rate " + std::to_string(best));
    sum_ours += t_ours, sum_uni += t_uni;
    tri_ours += static_cast<double>(ours.mesh.triangles.size()),
        tri_uni += static_cast<double>(uni.triangles.size());
  }
  // The floor under uvmesh's time: mesher2d alone (no surface, no size field) on the unit
  // square, with a uniform size and with a constant metric given as a callback (the path
  // every surface face takes, its field varying), at about the car's triangle count.
  auto m2d_rate = [](bool callback) {
    m2d::Pslg in;
    in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
    const double h = 0.0025;
    const auto t0 = Clock::now();
    const m2d::Result res = callback ? m2d::mesh(in, m2d::SizeSpec::aniso([&](double, double) {
                                                   return m2d::Metric2{1 / (h * h), 0, 1 / (h * h)};
                                                 }),
                                                 {})
                                     : m2d::mesh(in, m2d::SizeSpec::uniform(h), {});
    const double t = since(t0);
    return std::pair{1e6 * t / static_cast<double>(res.mesh.triangles.size()),
                     res.mesh.triangles.size()};
  };
  const auto [us_uniform, n_uniform] = m2d_rate(false);
  const auto [us_callback, n_callback] = m2d_rate(true);
  std::printf(
      "\nCPU microseconds per triangle: uvmesh %.2f (all cages), osd uniform %.3f (tessellation + "
      "limit "
      "evaluation); mesher2d alone on a square: uniform size %.2f (%zu triangles), constant metric "
      "through the "
      "callback %.2f (%zu triangles)\n",
      1e6 * sum_ours / tri_ours, 1e6 * sum_uni / tri_uni, us_uniform, n_uniform, us_callback,
      n_callback);
  return 0;
}
