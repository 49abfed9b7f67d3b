// bench_cad -- import time of the three largest corpus models (pre-scan alone, import
// as read, import with healing) and the cost of one metric evaluation (surface
// derivatives, curvature, 3D metric, induced (u,v) metric, background-grid metric) on an
// analytic torus and on OCC faces, printed beside a quality figure measured in the same
// run (relative error of the induced metric against true 3D lengths).
//
//   bench_cad [DATA_DIR] [--repeat N]
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include "uvmesh/geom/analytic.h"
#include "uvmesh/io/cad_reader.h"
#include "uvmesh/io/prescan.h"
#include "uvmesh/param/size_field.h"

using namespace uvmesh;
using Clock = std::chrono::steady_clock;

namespace {

double secs(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

struct MetricCost {
  double eval_ns, curvature_ns, metric3_ns, induced_ns, field_ns, induced_err;
};

// Mean cost per call over `n` random points of the face's box, and the worst relative
// error |l_Muv(d) - l_M3(sigma(uv + d) - sigma(uv))| / l for steps of 1e-6 of the box.
MetricCost metric_cost(const geom::Surface& s, const geom::Box2& box, const param::SizeSpec& spec,
                       int n) {
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> U(0.05, 0.95);
  std::vector<geom::Vec2> uv(static_cast<std::size_t>(n));
  for (auto& p : uv) p = {box.u.at(U(rng)), box.v.at(U(rng))};
  MetricCost c{};
  volatile double sink = 0.0;
  auto t0 = Clock::now();
  for (const auto& p : uv) sink = sink + s.eval(p.x, p.y).p.x;
  c.eval_ns = secs(t0) * 1e9 / n;
  t0 = Clock::now();
  for (const auto& p : uv) sink = sink + param::principal_curvatures(s.eval(p.x, p.y)).k1;
  c.curvature_ns = secs(t0) * 1e9 / n;
  t0 = Clock::now();
  for (const auto& p : uv) sink = sink + param::surface_metric(s, p.x, p.y, spec)(0, 0);
  c.metric3_ns = secs(t0) * 1e9 / n;
  t0 = Clock::now();
  for (const auto& p : uv) {
    const param::Metric3 m3 = param::surface_metric(s, p.x, p.y, spec);
    sink = sink + param::induced_metric(m3, s.eval(p.x, p.y), spec)(0, 0);
  }
  c.induced_ns = secs(t0) * 1e9 / n;
  param::FaceSizeField field(s, box, spec);
  t0 = Clock::now();
  for (const auto& p : uv) sink = sink + field.metric_uv(p.x, p.y)(0, 0);
  c.field_ns = secs(t0) * 1e9 / n;
  for (int i = 0; i < std::min(n, 200); ++i) {
    const auto& p = uv[static_cast<std::size_t>(i)];
    const param::Metric3 m3 = param::surface_metric(s, p.x, p.y, spec);
    const param::Metric2 muv = param::induced_metric(m3, s.eval(p.x, p.y), spec);
    const geom::Vec2 d(1e-6 * box.u.length(), 0.7e-6 * box.v.length());
    const double l3 = m3.length(s.point(p.x + d.x, p.y + d.y) - s.point(p.x, p.y));
    if (l3 > 0) c.induced_err = std::max(c.induced_err, std::abs(muv.length(d) - l3) / l3);
  }
  return c;
}

void print_cost(const char* what, const MetricCost& c) {
  std::printf("  %-28s %9.0f %9.0f %9.0f %9.0f %9.0f   %.1e\n", what, c.eval_ns, c.curvature_ns,
              c.metric3_ns, c.induced_ns, c.field_ns, c.induced_err);
}

}  // namespace

int main(int argc, char** argv) {
  std::string data = UVMESH_SHARED_DATA;
  int repeat = 1;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--repeat") && i + 1 < argc)
      repeat = std::max(1, std::atoi(argv[++i]));
    else
      data = argv[i];
  }
  // The three largest CAD models of the corpus, by file size.
  std::vector<std::pair<std::uintmax_t, std::string>> files;
  for (const auto& e : std::filesystem::directory_iterator(data + "/cad"))
    files.emplace_back(e.file_size(), e.path().string());
  std::sort(files.rbegin(), files.rend());
  files.resize(std::min<std::size_t>(3, files.size()));

  std::printf("Import (seconds, best of %d)\n", repeat);
  std::printf("  %-28s %8s %6s %6s %6s %8s %8s %8s %8s %8s\n", "model", "MB", "faces", "edges",
              "solids", "prescan", "read", "build", "as-read", "healed");
  std::vector<io::ReadResult> keep;
  for (const auto& [bytes, path] : files) {
    double pre = 1e30, rd = 1e30, bld = 1e30, plain = 1e30, healed = 1e30;
    io::ReadResult r;
    for (int k = 0; k < repeat; ++k) {
      auto t0 = Clock::now();
      (void)io::prescan_file(path, {});
      pre = std::min(pre, secs(t0));
      io::ReadOptions o;
      o.heal = false;
      t0 = Clock::now();
      r = io::read_cad(path, o);
      plain = std::min(plain, secs(t0));
      rd = std::min(rd, r.report.read_seconds);
      bld = std::min(bld, r.report.build_seconds);
      t0 = Clock::now();
      (void)io::read_cad(path, io::ReadOptions{});
      healed = std::min(healed, secs(t0));
    }
    if (!r.ok) {
      std::printf("  %s: %s\n", path.c_str(), r.error.c_str());
      continue;
    }
    std::printf("  %-28s %8.2f %6zu %6zu %6zu %8.3f %8.3f %8.3f %8.3f %8.3f\n",
                std::filesystem::path(path).filename().c_str(), bytes / 1e6, r.model.faces.size(),
                r.model.edges.size(), r.model.solids.size(), pre, rd, bld, plain, healed);
    keep.push_back(std::move(r));
  }
  std::printf(
      "  (read = OCC parse + transfer incl. prescan; build = geom::Model incl. BRepCheck per "
      "face;\n"
      "   as-read = whole read_cad --no-heal; healed = read_cad with ShapeFix + sewing)\n\n");

  std::printf(
      "Metric evaluation (ns per call; error = worst relative error of the induced metric)\n");
  std::printf("  %-28s %9s %9s %9s %9s %9s   %s\n", "surface", "sigma+D2", "curvat.", "M3",
              "M3+Muv", "grid Muv", "error");
  const int n = 20000;
  param::SizeSpec spec;
  spec.hmax = 1.0;
  spec.hmin = 1e-3;
  spec.chordal_tol = 1e-3;
  auto torus = geom::make_torus(geom::Frame{}, 4.0, 1.0);
  print_cost("analytic torus", metric_cost(*torus, torus->bounds(), spec, n));
  for (const io::ReadResult& r : keep) {
    // The first B-spline face and the first elementary face of each model.
    for (bool bspline : {true, false}) {
      for (std::size_t f = 0; f < r.model.faces.size(); ++f) {
        const geom::Face& face = r.model.faces[f];
        if (!face.surface || (face.kind == geom::SurfaceKind::BSpline) != bspline) continue;
        param::SizeSpec s2 = spec;
        const double d = r.model.bbox.diagonal();
        s2.hmax = d / 20;
        s2.hmin = d / 2e4;
        s2.chordal_tol = d * 1e-4;
        const std::string label =
            std::filesystem::path(r.model.source).stem().string().substr(0, 14) + " f" +
            std::to_string(f) + " " + std::string(to_string(face.kind));
        print_cost(label.c_str(), metric_cost(*face.surface, face.uv_box, s2, n / 4));
        break;
      }
    }
  }
  return 0;
}
