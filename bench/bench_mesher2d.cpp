// bench_mesher2d -- uvmesh::m2d::mesh beside reference meshers measured in the same run,
// printed as ONE side-by-side Markdown table (time, rate, quality and memory together).
// Not a test; bench/run.sh configures, builds, runs it and writes bench/results.md.
//
//   bench_mesher2d [--quick] [--reps N] [--only dt|iso|aniso|lfs] [--out FILE] [--work DIR]
//                  [--no-gmsh] [--no-bamg] [--no-cgal] [--keep] [--max-size N]
//                  (--help explains)
//
// What is measured (issue 2, "Benchmark"):
//   dt     Delaunay triangulation of 1e5, 1e6, 4e6 uniform random points in [0,1]^2 (fixed
//          seed): ours (Options::refine = false, no segments: the convex hull) against CGAL
//          Delaunay_triangulation_2<Epick> inserting the range (CGAL sorts spatially).
//   iso    unit square with a circular hole (radius 0.25 at the centre), boundary discretized
//          here to h, meshed to about 1e5 and 1e6 triangles: ours (SizeSpec::uniform(h))
//          against CGAL Delaunay_mesher_2 (Delaunay_mesh_size_criteria_2(0.125, h): the default
//          shape bound B = sqrt 2, i.e. min angle 20.7 deg, and longest edge <= h) and gmsh -2
//          (algorithms 5 Delaunay and 6 Frontal-Delaunay, one thread) on the same boundary
//          points, with h as the gmsh mesh size.
//   aniso  the analytic fields bl and ring (samples/uvmesh2d/fields.h) on the unit square:
//          ours against ffbamg (Debian freefem++) given a background grid carrying the same
//          metric at its vertices (-b grid.mesh -M grid.mtr).
// Ours runs in both field-point modes (Options::field_points, issue 22): saturation (the
// default, the row the ratio column divides) and frontal, side by side in every iso and
// aniso case.
// Quality of every mesh, ours or not, comes from uvmesh::m2d::measure on its vertex and
// triangle arrays with the same SizeSpec (Q_K = alpha h_max / rho_K, alpha = sqrt(3)/6; metric
// Q_K in the mean vertex metric; unit edges: metric length in [1/sqrt2, sqrt2]).
//
// Timing. Every ours / CGAL measurement runs in a fresh child process (this program with
// --child ...) so that heaps do not carry over and the child's peak RSS belongs to that one
// case; the timed region is the library call only (input arrays are built before, quality is
// measured after; our call runs with Options::measure off, so that its own quality
// statistics, which no reference computes, are not timed). Wall time (steady_clock) and
// CPU time (CLOCK_PROCESS_CPUTIME_ID) are both reported: on a loaded shared machine CPU
// time is the steadier of the two. References and
// ours alternate within each repetition (the order flips every repetition); the table keeps
// the best (smallest) wall and the best CPU over the repetitions. gmsh's time is the one it
// logs for "Done meshing 2D (Wall .., CPU ..)" (excludes start-up, .geo parsing, 1D meshing
// and output); bamg logs only CPU ("Cpu time for meshing"), its wall time is that of the
// whole process (includes reading the background grid and writing the mesh).
// Memory: ru_maxrss of the child right after the timed call (input + library structures +
// output arrays, before our quality measure of the reference's mesh); for gmsh and bamg the
// whole external process's ru_maxrss (wait4). Reported per million triangles.
#include <CGAL/Constrained_Delaunay_triangulation_2.h>
#include <CGAL/Delaunay_mesh_face_base_2.h>
#include <CGAL/Delaunay_mesh_size_criteria_2.h>
#include <CGAL/Delaunay_mesher_2.h>
#include <CGAL/Delaunay_triangulation_2.h>
#include <CGAL/Exact_predicates_inexact_constructions_kernel.h>
#include <CGAL/Triangulation_vertex_base_with_info_2.h>
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>
#include <uvmesh/mesher2d/mesher2d.h>
#include <uvmesh2d/fields.h>

#include <algorithm>
#include <array>
#include <charconv>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <functional>
#include <limits>
#include <list>
#include <map>
#include <memory>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "../tests/mesher2d/feature_domains.h"

namespace {

namespace m2d = uvmesh::m2d;
namespace fields = uvmesh::cli2d::fields;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint64_t kSeed = 20240601;  // random points: fixed seed, same set every run

// ------------------------------------------------------------------------------- clocks
double wall_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}
double peak_rss_mb_self() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  return static_cast<double>(ru.ru_maxrss) / 1024.0;  // Linux: kilobytes
}

// ------------------------------------------------------------------------------- inputs
std::vector<m2d::Vec2> random_points(std::int64_t n) {
  std::mt19937_64 rng(kSeed);
  // 53 random bits -> [0, 1): the same doubles with every standard library.
  auto u = [&rng] { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  std::vector<m2d::Vec2> p(static_cast<std::size_t>(n));
  for (auto& q : p) q = {u(), u()};
  return p;
}

// The isotropic domain: unit square with a hole of radius 0.25 at (0.5, 0.5); the boundary
// is discretized here, with every piece no longer than h, and given to every mesher as is.
struct SquareHole {
  std::vector<m2d::Vec2> outer, inner;  // closed loops (last point connects to the first)
  double area() const { return 1.0 - kPi * 0.25 * 0.25; }
};
SquareHole square_hole(double h) {
  SquareHole d;
  const int ns = static_cast<int>(std::ceil(1.0 / h));
  const m2d::Vec2 corner[4] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  for (int s = 0; s < 4; ++s) {
    const m2d::Vec2 a = corner[s], b = corner[(s + 1) % 4];
    for (int i = 0; i < ns; ++i) {
      const double t = static_cast<double>(i) / ns;
      d.outer.push_back({a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
    }
  }
  const int nc = static_cast<int>(std::ceil(2 * kPi * 0.25 / h));
  for (int i = 0; i < nc; ++i) {
    const double th = 2 * kPi * i / nc;
    d.inner.push_back({0.5 + 0.25 * std::cos(th), 0.5 + 0.25 * std::sin(th)});
  }
  return d;
}
m2d::Pslg to_pslg(const SquareHole& d) {
  m2d::Pslg in;
  auto loop = [&in](const std::vector<m2d::Vec2>& pts, int marker) {
    const auto first = static_cast<m2d::VertId>(in.points.size());
    const auto n = static_cast<m2d::VertId>(pts.size());
    for (const auto& p : pts) in.points.push_back(p);
    for (m2d::VertId i = 0; i < n; ++i)
      in.segments.push_back({first + i, first + (i + 1) % n, marker});
  };
  loop(d.outer, 1);
  loop(d.inner, 2);
  in.holes.push_back({0.5, 0.5});
  return in;
}
m2d::Pslg unit_square() {
  m2d::Pslg in;
  in.points = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
  in.segments = {{0, 1, 1}, {1, 2, 1}, {2, 3, 1}, {3, 0, 1}};
  return in;
}
m2d::SizeSpec aniso_field(const std::string& name, double h0, double hmax) {
  return name == "bl" ? fields::bl(h0, hmax) : fields::ring(h0, hmax);
}

// ------------------------------------------------------------------------------- results
// One measured case: what a child prints on its RESULT line, or what the parent gathers
// from an external tool.
struct Measure {
  bool ok = false;
  std::string error;  // why there is no number
  double tris = 0, verts = 0, wall = kNaN, cpu = kNaN, rss_mb = kNaN;
  std::optional<m2d::Quality> q;
  double median_q = kNaN;  // median_q() of the mesh
  std::string notes;
};

// Median over the triangles of q = 4 sqrt3 area / (sum of the squared edge lengths): 1 for
// the equilateral, 0 for a flat triangle. This is not q_K = 1 / Q_K of eq. 7.6 (which
// m2d::measure reports as Q_M and Q<1.5): it is the normalization the issue states its
// median target in (Gmsh's Frontal-Delaunay reaches 0.99-1.00 in it). Each triangle is
// measured in the mean of its three vertex metrics (identity for a uniform size), as
// m2d::measure's metric quality.
double median_q(const std::vector<m2d::Vec2>& v, const std::vector<std::array<m2d::VertId, 3>>& t,
                const m2d::SizeSpec& size) {
  if (t.empty()) return kNaN;
  std::vector<m2d::Metric2> vm(v.size());
  for (std::size_t i = 0; i < v.size(); ++i)
    vm[i] = size.kind == m2d::SizeSpec::Kind::Metric ? size.metric(v[i].x, v[i].y)
            : size.kind == m2d::SizeSpec::Kind::Scalar
                ? m2d::Metric2::iso(size.size(v[i].x, v[i].y))
                : m2d::Metric2{};
  std::vector<double> q(t.size());
  for (std::size_t k = 0; k < t.size(); ++k) {
    const auto &a = vm[t[k][0]], &b = vm[t[k][1]], &c = vm[t[k][2]];
    const m2d::Metric2 m{(a.m11 + b.m11 + c.m11) / 3, (a.m12 + b.m12 + c.m12) / 3,
                         (a.m22 + b.m22 + c.m22) / 3};
    // Area and squared lengths in the metric: det(M)^(1/2) area, e^T M e.
    auto len2 = [&m](m2d::Vec2 p, m2d::Vec2 r) {
      const double dx = r.x - p.x, dy = r.y - p.y;
      return m.m11 * dx * dx + 2 * m.m12 * dx * dy + m.m22 * dy * dy;
    };
    const m2d::Vec2 p0 = v[t[k][0]], p1 = v[t[k][1]], p2 = v[t[k][2]];
    const double area = 0.5 * ((p1.x - p0.x) * (p2.y - p0.y) - (p1.y - p0.y) * (p2.x - p0.x)) *
                        std::sqrt(m.m11 * m.m22 - m.m12 * m.m12);
    q[k] = 4 * std::sqrt(3.0) * area / (len2(p0, p1) + len2(p1, p2) + len2(p2, p0));
  }
  std::nth_element(q.begin(), q.begin() + static_cast<std::ptrdiff_t>(q.size() / 2), q.end());
  return q[q.size() / 2];
}

// The quality of a mesh, ours or a reference's: m2d::measure and median_q.
void measure_quality(Measure& m, const std::vector<m2d::Vec2>& v,
                     const std::vector<std::array<m2d::VertId, 3>>& t, const m2d::SizeSpec& size) {
  m.q = m2d::measure(v, t, size);
  m.median_q = median_q(v, t, size);
}

void print_result(const Measure& m) {
  std::printf("RESULT tris=%.0f verts=%.0f wall=%.9g cpu=%.9g rss_mb=%.6g", m.tris, m.verts, m.wall,
              m.cpu, m.rss_mb);
  if (m.q) {
    const auto& q = *m.q;
    std::printf(" qmax=%.9g q15=%.9g minang=%.9g mqmax=%.9g mq15=%.9g unit=%.9g medq=%.9g", q.q_max,
                q.share_q_below_1_5, q.min_angle_deg, q.metric_q_max, q.metric_share_q_below_1_5,
                q.unit_edge_share, m.median_q);
  }
  std::printf("\nNOTES %s\n", m.notes.c_str());
  std::fflush(stdout);
}

Measure parse_result(const std::string& out) {
  Measure m;
  std::istringstream in(out);
  std::string line;
  std::map<std::string, double> kv;
  bool seen = false;
  while (std::getline(in, line)) {
    if (line.rfind("RESULT ", 0) == 0) {
      seen = true;
      std::istringstream ls(line.substr(7));
      std::string tok;
      while (ls >> tok) {
        const auto eq = tok.find('=');
        if (eq != std::string::npos)
          kv[tok.substr(0, eq)] = std::strtod(tok.c_str() + eq + 1, nullptr);
      }
    } else if (line.rfind("NOTES ", 0) == 0) {
      m.notes = line.substr(6);
    } else if (line.rfind("ERROR ", 0) == 0) {
      m.error = line.substr(6);
    }
  }
  if (!seen) {
    if (m.error.empty()) m.error = "child printed no result";
    return m;
  }
  m.ok = true;
  m.tris = kv["tris"];
  m.verts = kv["verts"];
  m.wall = kv["wall"];
  m.cpu = kv["cpu"];
  m.rss_mb = kv["rss_mb"];
  if (kv.count("qmax")) {
    m2d::Quality q;
    q.q_max = kv["qmax"];
    q.share_q_below_1_5 = kv["q15"];
    q.min_angle_deg = kv["minang"];
    q.metric_q_max = kv["mqmax"];
    q.metric_share_q_below_1_5 = kv["mq15"];
    q.unit_edge_share = kv["unit"];
    if (kv.count("medq")) m.median_q = kv["medq"];
    m.q = q;
  }
  return m;
}

std::string fmt(const char* f, double v) {
  if (!std::isfinite(v)) return "–";
  char b[64];
  std::snprintf(b, sizeof b, f, v);
  return b;
}

std::string stage_notes(const m2d::Stats& s) {
  std::string o = "stages:";
  for (const auto& st : s.stages) {
    if (st.seconds < 0.0005) continue;
    o += " " + st.name + " " + fmt("%.3g", st.seconds) + "s,";
  }
  if (!o.empty() && o.back() == ',') o.pop_back();
  return o;
}

// Reference meshes may come out clockwise (gmsh, bamg); measure() wants counter-clockwise.
void orient_ccw(const std::vector<m2d::Vec2>& v, std::vector<std::array<m2d::VertId, 3>>& t) {
  for (auto& k : t) {
    const m2d::Vec2 a = v[k[0]], b = v[k[1]], c = v[k[2]];
    if ((b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x) < 0) std::swap(k[1], k[2]);
  }
}

// ------------------------------------------------------------------------------- children
using Epick = CGAL::Exact_predicates_inexact_constructions_kernel;

int child_dt_ours(std::int64_t n) {
  m2d::Pslg in;
  in.points = random_points(n);
  m2d::Options opt;
  opt.refine = false;
  opt.measure = false;  // no quality statistics in the timed call (CGAL computes none)
  const double w0 = wall_now(), c0 = cpu_now();
  m2d::Result r = m2d::mesh(in, m2d::SizeSpec::uniform(0), opt);
  const double w1 = wall_now(), c1 = cpu_now();
  Measure m;
  m.rss_mb = peak_rss_mb_self();
  if (!r.ok()) {
    std::printf("ERROR ours: %s\n", r.status.message.c_str());
    return 1;
  }
  m.wall = w1 - w0;
  m.cpu = c1 - c0;
  m.tris = static_cast<double>(r.mesh.triangles.size());
  m.verts = static_cast<double>(r.mesh.vertices.size());
  // Every stage of the call (wall seconds, Result::stats): where the time goes.
  m.notes = "one thread; whole call timed (Options::measure off); stages (wall s):";
  for (const auto& st : r.stats.stages)
    m.notes += " " + st.name + " " + fmt("%.3g", st.seconds) + ",";
  m.notes.pop_back();
  print_result(m);
  return 0;
}

int child_dt_cgal(std::int64_t n) {
  const auto p = random_points(n);
  std::vector<Epick::Point_2> pts;
  pts.reserve(p.size());
  for (const auto& q : p) pts.emplace_back(q.x, q.y);
  using Dt = CGAL::Delaunay_triangulation_2<Epick>;
  const double w0 = wall_now(), c0 = cpu_now();
  Dt dt;
  dt.insert(pts.begin(), pts.end());  // spatial sort + insertion
  const double w1 = wall_now(), c1 = cpu_now();
  Measure m;
  m.rss_mb = peak_rss_mb_self();
  m.wall = w1 - w0;
  m.cpu = c1 - c0;
  m.tris = static_cast<double>(dt.number_of_faces());
  m.verts = static_cast<double>(dt.number_of_vertices());
  m.notes = "one thread; insert(range): spatial sort + insertion";
  print_result(m);
  return 0;
}

// Options::field_points from its name on the command line ("saturation", "frontal").
m2d::FieldPointMethod method_from(const std::string& name) {
  return name == "frontal" ? m2d::FieldPointMethod::Frontal : m2d::FieldPointMethod::Saturation;
}

// Times one call of our mesher on (in, size) and prints its measures (child process).
int run_ours(const m2d::Pslg& in, const m2d::SizeSpec& size, m2d::FieldPointMethod method,
             bool feature_size = false) {
  // Stats::quality off: the quality of every mesh, ours and the references', is measured
  // below by the same m2d::measure outside the timed region.
  m2d::Options opt;
  opt.measure = false;
  opt.field_points = method;
  opt.feature_size = feature_size;
  const double w0 = wall_now(), c0 = cpu_now();
  m2d::Result r = m2d::mesh(in, size, opt);
  const double w1 = wall_now(), c1 = cpu_now();
  Measure m;
  m.rss_mb = peak_rss_mb_self();
  if (!r.usable()) {
    std::printf("ERROR ours: %s\n", r.status.message.c_str());
    return 1;
  }
  m.wall = w1 - w0;
  m.cpu = c1 - c0;
  m.tris = static_cast<double>(r.mesh.triangles.size());
  m.verts = static_cast<double>(r.mesh.vertices.size());
  measure_quality(m, r.mesh.vertices, r.mesh.triangles, size);
  m.notes = stage_notes(r.stats) + (r.ok() ? "" : "; status: " + r.status.message);
  print_result(m);
  return 0;
}

int child_iso_ours(double h, const std::string& method) {
  return run_ours(to_pslg(square_hole(h)), m2d::SizeSpec::uniform(h), method_from(method));
}

// h: boundary discretization and the size the quality is measured against; s: CGAL's size
// bound (longest edge).
int child_iso_cgal(double h, double s) {
  using Vb = CGAL::Triangulation_vertex_base_with_info_2<std::int32_t, Epick>;
  using Fb = CGAL::Delaunay_mesh_face_base_2<Epick>;
  using Tds = CGAL::Triangulation_data_structure_2<Vb, Fb>;
  using Cdt = CGAL::Constrained_Delaunay_triangulation_2<Epick, Tds>;
  using Criteria = CGAL::Delaunay_mesh_size_criteria_2<Cdt>;
  const SquareHole d = square_hole(h);
  std::vector<std::vector<Epick::Point_2>> loops(2);
  for (const auto& p : d.outer) loops[0].emplace_back(p.x, p.y);
  for (const auto& p : d.inner) loops[1].emplace_back(p.x, p.y);
  std::list<Epick::Point_2> seeds{Epick::Point_2(0.5, 0.5)};

  const double w0 = wall_now(), c0 = cpu_now();
  Cdt cdt;
  for (const auto& loop : loops) {
    std::vector<Cdt::Vertex_handle> vh;
    vh.reserve(loop.size());
    for (const auto& p : loop) vh.push_back(cdt.insert(p));
    for (std::size_t i = 0; i < vh.size(); ++i)
      cdt.insert_constraint(vh[i], vh[(i + 1) % vh.size()]);
  }
  // 0.125 bounds sin^2 of the smallest angle from below (CGAL's default, B = sqrt 2);
  // s bounds the longest edge. The seed marks the hole: its component is not meshed.
  CGAL::refine_Delaunay_mesh_2(cdt, seeds.begin(), seeds.end(), Criteria(0.125, s));
  const double w1 = wall_now(), c1 = cpu_now();
  Measure m;
  m.rss_mb = peak_rss_mb_self();
  m.wall = w1 - w0;
  m.cpu = c1 - c0;

  std::vector<m2d::Vec2> v;
  std::vector<std::array<m2d::VertId, 3>> t;
  for (auto it = cdt.finite_vertices_begin(); it != cdt.finite_vertices_end(); ++it) {
    it->info() = static_cast<std::int32_t>(v.size());
    v.push_back({it->point().x(), it->point().y()});
  }
  for (auto f = cdt.finite_faces_begin(); f != cdt.finite_faces_end(); ++f)
    if (f->is_in_domain())
      t.push_back({f->vertex(0)->info(), f->vertex(1)->info(), f->vertex(2)->info()});
  orient_ccw(v, t);
  m.tris = static_cast<double>(t.size());
  m.verts = static_cast<double>(v.size());
  measure_quality(m, v, t, m2d::SizeSpec::uniform(h));
  m.notes = "CDT insertion + refine_Delaunay_mesh_2, no Lloyd";
  print_result(m);
  return 0;
}

int child_aniso_ours(const std::string& field, double h0, double hmax, const std::string& method) {
  return run_ours(unit_square(), aniso_field(field, h0, hmax), method_from(method));
}

// The domains narrower than their size (tests/mesher2d/feature_domains.h) and the size.
struct LfsDomain {
  const char* name;
  m2d::Pslg in;
  double h;
};
std::vector<LfsDomain> lfs_domains() {
  return {{"thin star (10 spikes 0.19 wide at the base, 14.8° tips)",
           feature_domains::thin_star(10, 1, 0.3), 0.3},
          {"unit square with 3 slots 0.02 wide", feature_domains::slotted_square(0.02), 0.1},
          {"comb of 8 teeth 0.03 wide", feature_domains::comb(8, 0.03), 0.1}};
}

int child_lfs_ours(int domain, const std::string& method, bool on) {
  const auto ds = lfs_domains();
  if (domain < 0 || domain >= static_cast<int>(ds.size())) return 2;
  const LfsDomain& d = ds[static_cast<std::size_t>(domain)];
  return run_ours(d.in, m2d::SizeSpec::uniform(d.h), method_from(method), on);
}

int run_child(int argc, char** argv) {
  // argv: --child KIND ARGS...
  const std::string kind = argc > 2 ? argv[2] : "";
  auto num = [&](int i) { return i < argc ? std::strtod(argv[i], nullptr) : kNaN; };
  if (kind == "dt-ours") return child_dt_ours(static_cast<std::int64_t>(num(3)));
  if (kind == "dt-cgal") return child_dt_cgal(static_cast<std::int64_t>(num(3)));
  const auto arg = [&](int i) { return std::string(i < argc ? argv[i] : ""); };
  if (kind == "iso-ours") return child_iso_ours(num(3), arg(4));
  if (kind == "iso-cgal") return child_iso_cgal(num(3), num(4));
  if (kind == "lfs-ours") return child_lfs_ours(static_cast<int>(num(3)), arg(4), arg(5) == "on");
  if (kind == "aniso-ours" && argc > 5) return child_aniso_ours(argv[3], num(4), num(5), arg(6));
  std::fprintf(stderr, "bench_mesher2d: unknown child '%s'\n", kind.c_str());
  return 2;
}

// ------------------------------------------------------------------------------- processes
struct Proc {
  bool started = false;
  int exit_code = -1;
  std::string out;  // stdout (and stderr when merged)
  double wall = kNaN, cpu = kNaN, rss_mb = kNaN;
};

std::string self_exe() {
  char buf[4096];
  const ssize_t n = readlink("/proc/self/exe", buf, sizeof buf - 1);
  if (n <= 0) return "bench_mesher2d";
  buf[n] = 0;
  return buf;
}

// Runs argv[0] (looked up in PATH) and waits for it; resource usage from wait4 covers that
// process alone (user + system CPU, peak RSS).
Proc run_process(const std::vector<std::string>& args, bool merge_stderr) {
  Proc p;
  int fd[2];
  if (pipe(fd) != 0) return p;
  const double w0 = wall_now();
  const pid_t pid = fork();
  if (pid < 0) {
    close(fd[0]);
    close(fd[1]);
    return p;
  }
  if (pid == 0) {
    dup2(fd[1], STDOUT_FILENO);
    if (merge_stderr) dup2(fd[1], STDERR_FILENO);
    close(fd[0]);
    close(fd[1]);
    std::vector<char*> av;
    for (const auto& a : args) av.push_back(const_cast<char*>(a.c_str()));
    av.push_back(nullptr);
    execvp(av[0], av.data());
    std::fprintf(stderr, "bench_mesher2d: cannot run %s: %s\n", av[0], std::strerror(errno));
    _exit(127);
  }
  close(fd[1]);
  p.started = true;
  char buf[65536];
  for (;;) {
    const ssize_t n = read(fd[0], buf, sizeof buf);
    if (n > 0)
      p.out.append(buf, static_cast<std::size_t>(n));
    else if (n == 0 || errno != EINTR)
      break;
  }
  close(fd[0]);
  int status = 0;
  rusage ru{};
  while (wait4(pid, &status, 0, &ru) < 0 && errno == EINTR) {
  }
  p.wall = wall_now() - w0;
  p.cpu = static_cast<double>(ru.ru_utime.tv_sec + ru.ru_stime.tv_sec) +
          1e-6 * static_cast<double>(ru.ru_utime.tv_usec + ru.ru_stime.tv_usec);
  p.rss_mb = static_cast<double>(ru.ru_maxrss) / 1024.0;
  p.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
  return p;
}

bool in_path(const std::string& prog) {
  const char* path = std::getenv("PATH");
  if (!path) return false;
  std::string_view rest(path);
  while (!rest.empty()) {
    const auto c = rest.find(':');
    const std::string dir(rest.substr(0, c));
    if (access((dir + "/" + prog).c_str(), X_OK) == 0) return true;
    if (c == std::string_view::npos) break;
    rest.remove_prefix(c + 1);
  }
  return false;
}

Measure run_self(const std::vector<std::string>& child_args) {
  std::vector<std::string> a{self_exe(), "--child"};
  a.insert(a.end(), child_args.begin(), child_args.end());
  const Proc p = run_process(a, false);
  Measure m = parse_result(p.out);
  if (p.exit_code != 0 && m.error.empty())
    m.error = "child exited with " + std::to_string(p.exit_code);
  if (!m.error.empty()) m.ok = false;
  return m;
}

std::string num17(double v) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", v);
  return b;
}

// ------------------------------------------------------------------------------- mesh files
// Whitespace tokenizer over a whole file (fast enough for a few million lines).
struct Tokens {
  std::string buf;
  std::size_t pos = 0;
  bool load(const std::string& path) {
    std::ifstream f(path, std::ios::binary);
    if (!f) return false;
    std::ostringstream ss;
    ss << f.rdbuf();
    buf = ss.str();
    return true;
  }
  std::string_view next() {
    while (pos < buf.size() && std::isspace(static_cast<unsigned char>(buf[pos]))) ++pos;
    const std::size_t b = pos;
    while (pos < buf.size() && !std::isspace(static_cast<unsigned char>(buf[pos]))) ++pos;
    return std::string_view(buf).substr(b, pos - b);
  }
  double num() {
    const auto t = next();
    double v = kNaN;
    std::from_chars(t.data(), t.data() + t.size(), v);
    return v;
  }
  long long integer() {
    const auto t = next();
    long long v = -1;
    std::from_chars(t.data(), t.data() + t.size(), v);
    return v;
  }
};

struct PlainMesh {
  std::vector<m2d::Vec2> v;
  std::vector<std::array<m2d::VertId, 3>> t;
  std::string error;
};

// Gmsh MSH 2.2 ASCII: nodes and 3-node triangles (element type 2).
PlainMesh read_msh22(const std::string& path) {
  PlainMesh m;
  Tokens tk;
  if (!tk.load(path)) return m.error = "cannot read " + path, m;
  std::vector<m2d::VertId> id_to_index;
  for (auto w = tk.next(); !w.empty(); w = tk.next()) {
    if (w == "$Nodes") {
      const long long n = tk.integer();
      m.v.reserve(static_cast<std::size_t>(n));
      for (long long i = 0; i < n; ++i) {
        const long long id = tk.integer();
        const double x = tk.num(), y = tk.num();
        tk.num();
        if (id >= static_cast<long long>(id_to_index.size()))
          id_to_index.resize(static_cast<std::size_t>(id) + 1, -1);
        id_to_index[static_cast<std::size_t>(id)] = static_cast<m2d::VertId>(m.v.size());
        m.v.push_back({x, y});
      }
    } else if (w == "$Elements") {
      const long long n = tk.integer();
      for (long long i = 0; i < n; ++i) {
        tk.integer();
        const long long type = tk.integer(), ntags = tk.integer();
        for (long long j = 0; j < ntags; ++j) tk.integer();
        const int nn = type == 2 ? 3 : type == 1 ? 2 : type == 15 ? 1 : type == 3 ? 4 : -1;
        if (nn < 0) return m.error = "unexpected element type " + std::to_string(type), m;
        std::array<long long, 4> nd{};
        for (int j = 0; j < nn; ++j) nd[static_cast<std::size_t>(j)] = tk.integer();
        if (type == 2)
          m.t.push_back({id_to_index[static_cast<std::size_t>(nd[0])],
                         id_to_index[static_cast<std::size_t>(nd[1])],
                         id_to_index[static_cast<std::size_t>(nd[2])]});
      }
    }
  }
  if (m.t.empty()) m.error = "no triangles in " + path;
  return m;
}

// BAMG "DB mesh" (MeshVersionFormatted, Medit-like keywords): Vertices x y ref, Triangles a b c
// ref, 1-based; other sections (Edges, Geometry, SubDomain...) are skipped.
PlainMesh read_bamg_mesh(const std::string& path) {
  PlainMesh m;
  Tokens tk;
  if (!tk.load(path)) return m.error = "cannot read " + path, m;
  for (auto w = tk.next(); !w.empty(); w = tk.next()) {
    if (w == "Vertices") {
      const long long n = tk.integer();
      m.v.resize(static_cast<std::size_t>(n));
      for (auto& p : m.v) {
        p.x = tk.num();
        p.y = tk.num();
        tk.integer();
      }
    } else if (w == "Triangles") {
      const long long n = tk.integer();
      m.t.resize(static_cast<std::size_t>(n));
      for (auto& k : m.t) {
        for (auto& i : k) i = static_cast<m2d::VertId>(tk.integer() - 1);
        tk.integer();
      }
    }
  }
  if (m.t.empty()) m.error = "no triangles in " + path;
  return m;
}

// ------------------------------------------------------------------------------- gmsh
// The same boundary points as ours and CGAL: one straight line per boundary piece, each
// forced to a single element (Transfinite = 2 nodes), mesh size h everywhere.
void write_geo(const std::string& path, const SquareHole& d, double h, int algorithm) {
  std::ofstream f(path);
  f.precision(17);
  f << "// square with a circular hole, boundary discretized by bench_mesher2d, h = " << h << "\n";
  f << "Mesh.Algorithm = " << algorithm << ";\nGeneral.NumThreads = 1;\n";
  f << "Mesh.MeshSizeMin = " << h << ";\nMesh.MeshSizeMax = " << h << ";\n";
  int pid = 0, lid = 0;
  std::vector<int> loop_ids;
  for (const auto* loop : {&d.outer, &d.inner}) {
    const int p0 = pid + 1, l0 = lid + 1;
    for (const auto& p : *loop)
      f << "Point(" << ++pid << ") = {" << p.x << ", " << p.y << ", 0, " << h << "};\n";
    const int n = static_cast<int>(loop->size());
    for (int i = 0; i < n; ++i)
      f << "Line(" << ++lid << ") = {" << p0 + i << ", " << p0 + (i + 1) % n << "};\n";
    f << "Curve Loop(" << loop_ids.size() + 1 << ") = {" << l0 << ":" << lid << "};\n";
    loop_ids.push_back(static_cast<int>(loop_ids.size()) + 1);
  }
  f << "Plane Surface(1) = {1, 2};\n";
  f << "Transfinite Curve{1:" << lid << "} = 2;\n";
}

// "Done meshing 2D (Wall 0.609788s, CPU 0.202141s)"
bool parse_gmsh_2d_time(const std::string& log, double& wall, double& cpu) {
  const auto at = log.find("Done meshing 2D (Wall ");
  if (at == std::string::npos) return false;
  const char* s = log.c_str() + at + std::strlen("Done meshing 2D (Wall ");
  wall = std::strtod(s, nullptr);
  const char* c = std::strstr(s, "CPU ");
  if (!c) return false;
  cpu = std::strtod(c + 4, nullptr);
  return true;
}

Measure run_gmsh(const std::string& work, const SquareHole& d, double h, int algorithm,
                 bool keep_files) {
  Measure m;
  const std::string base = work + "/gmsh_a" + std::to_string(algorithm) + "_h" + fmt("%.6g", h);
  write_geo(base + ".geo", d, h, algorithm);
  const Proc p = run_process(
      {"gmsh", base + ".geo", "-2", "-nt", "1", "-format", "msh22", "-o", base + ".msh"}, true);
  if (p.exit_code != 0) return m.error = "gmsh exited with " + std::to_string(p.exit_code), m;
  double w = kNaN, c = kNaN;
  if (!parse_gmsh_2d_time(p.out, w, c)) return m.error = "no 'Done meshing 2D' in gmsh's log", m;
  PlainMesh pm = read_msh22(base + ".msh");
  if (!keep_files) std::remove((base + ".msh").c_str()), std::remove((base + ".geo").c_str());
  if (!pm.error.empty()) return m.error = pm.error, m;
  orient_ccw(pm.v, pm.t);
  m.ok = true;
  m.wall = w;
  m.cpu = c;
  m.rss_mb = p.rss_mb;
  m.tris = static_cast<double>(pm.t.size());
  m.verts = static_cast<double>(pm.v.size());
  measure_quality(m, pm.v, pm.t, m2d::SizeSpec::uniform(h));
  m.notes = "time from gmsh log 'Done meshing 2D'; whole process " + fmt("%.3g", p.wall) +
            " s wall, " + fmt("%.3g", p.cpu) + " s CPU";
  return m;
}

// ------------------------------------------------------------------------------- bamg
// Background for bamg. bamg adapts to a metric given at the vertices of a background mesh
// (P1 interpolation between them) and lets one background edge be cut into at most 10
// (-maxsubdiv): a uniform grid fine enough for a thin layer everywhere would be huge, and a
// coarse one makes bamg coarsen the layer. So the background is built the way bamg is used in
// an adaptation loop: start from a uniform 100 x 100 grid, run bamg, put the exact analytic
// metric at the vertices of its output, repeat until the vertex count changes by < 3 % (at
// most 8 passes). Only the final pass is timed; its background is bamg's previous output.
void write_metric_file(const std::string& path, const std::vector<m2d::Vec2>& v,
                       const m2d::SizeSpec& size) {
  std::ofstream g(path);
  g.precision(17);
  // "nv 3", then a11 a21 a22 per vertex: the same M as SizeSpec (length^2 = e^T M e).
  g << v.size() << " 3\n";
  for (const auto& p : v) {
    const m2d::Metric2 mm = size.metric(p.x, p.y);
    g << mm.m11 << " " << mm.m12 << " " << mm.m22 << "\n";
  }
}

// A background mesh in bamg's "DB mesh" format, with its boundary edges (edges of one
// triangle) so that bamg builds its geometry from them. (Feeding bamg's own output file back
// as the background, with its Geometry reference, crashes Debian's ffbamg 4.11; a plain file
// written from its vertices and triangles does not.)
void write_bamg_mesh(const std::string& path, const PlainMesh& m) {
  std::ofstream f(path);
  f.precision(17);
  f << "MeshVersionFormatted 0\nDimension 2\nVertices " << m.v.size() << "\n";
  for (const auto& p : m.v) f << p.x << " " << p.y << " 1\n";
  std::vector<std::uint64_t> e;  // directed edges as (a << 32 | b), counter-clockwise triangles
  e.reserve(3 * m.t.size());
  for (const auto& k : m.t)
    for (int i = 0; i < 3; ++i)
      e.push_back(static_cast<std::uint64_t>(k[static_cast<std::size_t>(i)]) << 32 |
                  static_cast<std::uint32_t>(k[static_cast<std::size_t>((i + 1) % 3)]));
  std::vector<std::uint64_t> sorted = e;
  std::sort(sorted.begin(), sorted.end());
  std::vector<std::uint64_t> boundary;
  for (const std::uint64_t d : e) {
    const std::uint64_t rev = (d & 0xFFFFFFFFu) << 32 | d >> 32;
    if (!std::binary_search(sorted.begin(), sorted.end(), rev)) boundary.push_back(d);
  }
  f << "Edges " << boundary.size() << "\n";
  for (const std::uint64_t d : boundary)
    f << (d >> 32) + 1 << " " << (d & 0xFFFFFFFFu) + 1 << " 1\n";
  f << "Triangles " << m.t.size() << "\n";
  for (const auto& k : m.t) f << k[0] + 1 << " " << k[1] + 1 << " " << k[2] + 1 << " 0\n";
  f << "End\n";
}

PlainMesh grid_mesh(int n) {
  PlainMesh m;
  auto id = [n](int i, int j) { return static_cast<m2d::VertId>(j * (n + 1) + i); };
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i)
      m.v.push_back({static_cast<double>(i) / n, static_cast<double>(j) / n});
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      m.t.push_back({id(i, j), id(i + 1, j), id(i + 1, j + 1)});
      m.t.push_back({id(i, j), id(i + 1, j + 1), id(i, j + 1)});
    }
  return m;
}

struct BamgRun {
  Proc proc;
  std::string error;
};
BamgRun bamg_pass(const std::string& bg, const std::string& mtr, const std::string& out,
                  long long& nbv) {
  BamgRun r;
  for (int attempt = 0; attempt < 2; ++attempt) {
    r.proc = run_process(
        {"ffbamg", "-b", bg, "-M", mtr, "-o", out, "-nbv", std::to_string(nbv), "-v", "2"}, true);
    if (r.proc.exit_code == 0) return r;
    nbv *= 4;  // the usual failure is running out of the preallocated vertices
  }
  std::string tail =
      r.proc.out.size() > 160 ? r.proc.out.substr(r.proc.out.size() - 160) : r.proc.out;
  std::replace(tail.begin(), tail.end(), '\n', ' ');
  r.error = "ffbamg exited with " + std::to_string(r.proc.exit_code) + ": " + tail;
  return r;
}

struct BamgCase {
  std::string bg, mtr;          // final background mesh and its metric file
  int passes = 0, bg_pass = 0;  // bamg passes run; the pass whose output is the background
  long long nbv = 0, bg_tris = 0;
  std::string error;
};

BamgCase prepare_bamg(const std::string& work, const std::string& field, double h0, double hmax,
                      double expect_verts) {
  BamgCase c;
  const m2d::SizeSpec size = aniso_field(field, h0, hmax);
  const std::string base =
      work + "/bamg_" + field + "_" + fmt("%.6g", h0) + "_" + fmt("%.6g", hmax);
  // -nbv is bamg's preallocated vertex capacity (every array is sized from it): twice what
  // ours produced leaves room without inflating the process's memory much.
  c.nbv = std::max<long long>(50000, static_cast<long long>(2 * expect_verts));
  std::string bg = base + "_p0.mesh", mtr = base + "_p0.mtr";
  const PlainMesh grid = grid_mesh(100);
  write_bamg_mesh(bg, grid);
  write_metric_file(mtr, grid.v, size);
  c.bg_tris = static_cast<long long>(grid.t.size());
  double last = 0;
  for (int k = 1; k <= 8; ++k) {
    const std::string out = base + "_p" + std::to_string(k) + ".mesh";
    const BamgRun r = bamg_pass(bg, mtr, out, c.nbv);
    if (!r.error.empty()) return c.error = r.error, c;
    PlainMesh pm = read_bamg_mesh(out);
    if (!pm.error.empty()) return c.error = pm.error, c;
    orient_ccw(pm.v, pm.t);
    c.passes = k;
    const double nv = static_cast<double>(pm.v.size());
    if (k >= 2 && std::fabs(nv - last) < 0.03 * nv) break;  // bg (and mtr) are the final input
    last = nv;
    bg = base + "_p" + std::to_string(k) + "_bg.mesh";
    write_bamg_mesh(bg, pm);
    c.bg_pass = k;
    mtr = base + "_p" + std::to_string(k) + ".mtr";
    write_metric_file(mtr, pm.v, size);
    c.bg_tris = static_cast<long long>(pm.t.size());
  }
  c.bg = bg;
  c.mtr = mtr;
  return c;
}

void remove_bamg_files(const std::string& work, const std::string& field, double h0, double hmax) {
  const std::string base =
      work + "/bamg_" + field + "_" + fmt("%.6g", h0) + "_" + fmt("%.6g", hmax);
  for (int k = 0; k <= 9; ++k)
    for (const char* ext : {".mesh", ".mtr", ".mesh.gmsh", "_bg.mesh"})
      std::remove((base + "_p" + std::to_string(k) + ext).c_str());
  std::remove((base + "_final.mesh").c_str());
  std::remove((base + "_final.mesh.gmsh").c_str());
}

Measure run_bamg(const std::string& work, BamgCase& c, const std::string& field, double h0,
                 double hmax) {
  Measure m;
  if (!c.error.empty()) return m.error = c.error, m;
  const std::string out =
      work + "/bamg_" + field + "_" + fmt("%.6g", h0) + "_" + fmt("%.6g", hmax) + "_final.mesh";
  const BamgRun r = bamg_pass(c.bg, c.mtr, out, c.nbv);
  if (!r.error.empty()) return m.error = r.error, m;
  // " Cpu time for meshing          : 0.77s  Nb Vertices/s = 2029.87"
  double cpu = kNaN;
  if (const auto at = r.proc.out.find("Cpu time for meshing "); at != std::string::npos) {
    const auto colon = r.proc.out.find(':', at);
    if (colon != std::string::npos) cpu = std::strtod(r.proc.out.c_str() + colon + 1, nullptr);
  }
  PlainMesh pm = read_bamg_mesh(out);
  if (!pm.error.empty()) return m.error = pm.error, m;
  orient_ccw(pm.v, pm.t);
  m.ok = true;
  m.wall = r.proc.wall;
  m.cpu = cpu;
  m.rss_mb = r.proc.rss_mb;
  m.tris = static_cast<double>(pm.t.size());
  m.verts = static_cast<double>(pm.v.size());
  measure_quality(m, pm.v, pm.t, aniso_field(field, h0, hmax));
  m.notes =
      "CPU from bamg's log 'Cpu time for meshing'; wall = whole process incl. I/O (process CPU " +
      fmt("%.3g", r.proc.cpu) + " s); background: bamg's own pass-" + std::to_string(c.bg_pass) +
      " output (" + std::to_string(c.bg_tris) + " tri) + exact metric at its vertices; -nbv " +
      std::to_string(c.nbv);
  return m;
}

// ------------------------------------------------------------------------------- table
struct Row {
  std::string bench, tool;
  Measure best;  // best wall and best CPU over the repetitions
  bool is_ours = false;
  int group = 0;    // rows of one case share a group; ratios are taken within it
  bool dt = false;  // Delaunay rows: rate in points/s, no shape quality
  bool metric = false;
  double items = 0;  // points (dt) or triangles
  int reps = 1;
};

void merge_best(Measure& best, const Measure& m) {
  if (!m.ok) {
    if (!best.ok && best.error.empty()) best.error = m.error;
    return;
  }
  if (!best.ok) {
    best = m;
    return;
  }
  best.wall = std::min(best.wall, m.wall);
  if (std::isfinite(m.cpu)) best.cpu = std::isfinite(best.cpu) ? std::min(best.cpu, m.cpu) : m.cpu;
  best.rss_mb = std::max(best.rss_mb, m.rss_mb);
}

std::string table(const std::vector<Row>& rows, const std::string& header) {
  std::ostringstream o;
  o << header;
  o << "| benchmark | tool | triangles | wall s | CPU s | M/s CPU | M/s wall | ours ÷ this (CPU, "
       "wall) | median q | Q_M | Q<1.5 "
       "| min angle | metric Q_M | metric Q<1.5 | unit edges | peak RSS MB | MB / M tri | notes "
       "|\n";
  o << "|---|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n";
  for (const auto& r : rows) {
    const Measure& m = r.best;
    o << "| " << r.bench << " | " << r.tool << " | ";
    if (!m.ok) {
      const bool blocked = m.error.rfind("BLOCKED", 0) == 0;
      o << "– | – | – | – | – | – | – | – | – | – | – | – | – | – | – | "
        << (blocked ? "" : "FAILED: ") << m.error << " |\n";
      continue;
    }
    const double items = r.dt ? r.items : m.tris;
    const double rc = items / m.cpu * 1e-6, rw = items / m.wall * 1e-6;
    std::string ratio = "–";
    if (!r.is_ours) {
      for (const auto& s : rows)
        if (s.group == r.group && s.is_ours && s.best.ok) {
          const double sitems = s.dt ? s.items : s.best.tris;
          const double oc = sitems / s.best.cpu * 1e-6, ow = sitems / s.best.wall * 1e-6;
          ratio = fmt("%.2f", oc / rc) + ", " + fmt("%.2f", ow / rw);
        }
    }
    o << fmt("%.0f", m.tris) << " | " << fmt("%.3f", m.wall) << " | " << fmt("%.3f", m.cpu) << " | "
      << fmt("%.3f", rc) << " | " << fmt("%.3f", rw) << " | " << ratio << " | ";
    if (r.dt || !m.q) {
      o << "– | – | – | – | – | – | – | ";
    } else {
      // Euclidean shape for the isotropic rows, shape in the metric for the anisotropic ones
      // (an anisotropic mesh is meant to be flat in the Euclidean sense).
      const auto& q = *m.q;
      o << fmt("%.4f", m.median_q) << " | ";
      if (r.metric)
        o << "– | – | – | " << fmt("%.3f", q.metric_q_max) << " | "
          << fmt("%.1f%%", 100 * q.metric_share_q_below_1_5) << " | ";
      else
        o << fmt("%.3f", q.q_max) << " | " << fmt("%.1f%%", 100 * q.share_q_below_1_5) << " | "
          << fmt("%.1f°", q.min_angle_deg) << " | – | – | ";
      o << fmt("%.1f%%", 100 * q.unit_edge_share) << " | ";
    }
    o << fmt("%.0f", m.rss_mb) << " | " << fmt("%.0f", m.rss_mb / (m.tris * 1e-6)) << " | best of "
      << r.reps << "; " << m.notes << " |\n";
  }
  return o.str();
}

std::string load_line() {
  double load[3] = {kNaN, kNaN, kNaN};
  getloadavg(load, 3);
  return "load average " + fmt("%.2f", load[0]) + " " + fmt("%.2f", load[1]) + " " +
         fmt("%.2f", load[2]);
}

std::string machine_line() {
  std::string cpu = "unknown CPU";
  std::ifstream f("/proc/cpuinfo");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  return cpu + ", " + std::to_string(sysconf(_SC_NPROCESSORS_ONLN)) + " cores";
}

int usage(int code) {
  std::fprintf(
      code ? stderr : stdout,
      "usage: bench_mesher2d [--quick] [--reps N] [--only dt|iso|aniso|lfs] [--out FILE]\n"
      "                      [--work DIR]\n"
      "                      [--no-gmsh] [--no-bamg] [--no-cgal] [--keep] [--max-size N]\n"
      "  --quick   small sizes only (smoke run); default: the full sizes of issue 2\n"
      "  --reps N  repetitions per case, ours and references alternating (default 2, quick 1)\n"
      "  --out F   also write the Markdown table to F\n"
      "  --work D  scratch directory for .geo/.msh/bamg files (default /tmp/uvmesh-bench-PID)\n"
      "  --keep    keep the scratch files (inputs and outputs of gmsh and bamg)\n"
      "  --max-size N  skip cases of more than N points / triangles\n");
  return code;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc > 1 && std::string(argv[1]) == "--child") return run_child(argc, argv);
  bool quick = false, use_gmsh = true, use_bamg = true, use_cgal = true, keep = false;
  int reps = -1;
  double max_size = std::numeric_limits<double>::infinity();
  std::string only, out_path, work;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    auto value = [&]() -> std::string {
      if (i + 1 >= argc) std::exit(usage(2));
      return argv[++i];
    };
    if (a == "--quick")
      quick = true;
    else if (a == "--reps")
      reps = std::atoi(value().c_str());
    else if (a == "--only")
      only = value();
    else if (a == "--out")
      out_path = value();
    else if (a == "--work")
      work = value();
    else if (a == "--no-gmsh")
      use_gmsh = false;
    else if (a == "--no-bamg")
      use_bamg = false;
    else if (a == "--no-cgal")
      use_cgal = false;
    else if (a == "--keep")
      keep = true;
    else if (a == "--max-size")
      max_size = std::strtod(value().c_str(), nullptr);
    else if (a == "--help" || a == "-h")
      return usage(0);
    else
      return usage(2);
  }
  if (work.empty()) work = "/tmp/uvmesh-bench-" + std::to_string(getpid());
  mkdir(work.c_str(), 0755);
  const bool have_gmsh = use_gmsh && in_path("gmsh");
  const bool have_bamg = use_bamg && in_path("ffbamg");
  const std::string load_at_start = load_line();
  const double run_start = wall_now();
  // Repetitions: best of 3 for cases below a million points / triangles, 1 above (a full
  // run stays around a quarter of an hour on a loaded 2-core machine); --reps overrides.
  auto reps_for = [&](double items) { return reps > 0 ? reps : quick ? 1 : items < 9e5 ? 3 : 1; };

  // Sizes. Delaunay: numbers of points. Isotropic: h from the equilateral estimate
  // N = 4 A / (sqrt3 h^2), A = 1 - pi/16 (ours lands within a few % of it); the same h for
  // every tool. Anisotropic: (h0, hmax) with N = (4/sqrt3) * integral of sqrt(det M), for bl
  // ln(hmax/h0) / (hmax (hmax - h0)); ring computed numerically.
  const std::vector<std::int64_t> dt_sizes =
      quick ? std::vector<std::int64_t>{100000}
            : std::vector<std::int64_t>{100000, 1000000, 4000000};
  struct Iso {
    const char* label;
    double h, n;
  };
  const std::vector<Iso> iso_sizes =
      quick ? std::vector<Iso>{{"~2e4", 0.0095, 2e4}}
            : std::vector<Iso>{{"~1e5", 0.0043, 1e5}, {"~1e6", 0.00136, 1e6}};
  struct Aniso {
    const char* field;
    double h0, hmax, n;
  };
  const std::vector<Aniso> aniso_sizes =
      quick ? std::vector<Aniso>{{"bl", 0.0005, 0.02, 2.2e4}, {"ring", 0.0005, 0.02, 1.8e4}}
            : std::vector<Aniso>{{"bl", 0.002, 0.1, 900},  // steep: tangent size 0.1
                                 {"ring", 0.002, 0.1, 800},      {"bl", 0.0001, 0.01, 1.07e5},
                                 {"ring", 0.0001, 0.01, 0.9e5},  {"bl", 0.00003, 0.003, 1.19e6},
                                 {"ring", 0.00003, 0.003, 1.0e6}};

  std::vector<Row> rows;
  int group = 0;
  auto progress = [](const std::string& s) {
    std::fprintf(stderr, "bench_mesher2d: %s\n", s.c_str());
  };
  // Runs the measurements of one case, ours and references alternating, the order flipped
  // every repetition.
  auto run_case = [&](std::vector<Row> rs, const std::vector<std::function<Measure()>>& fns,
                      double items) {
    const int n = reps_for(items);
    for (int k = 0; k < n; ++k) {
      std::vector<std::size_t> order(rs.size());
      for (std::size_t i = 0; i < order.size(); ++i) order[i] = i;
      if (k % 2 == 1) std::reverse(order.begin(), order.end());
      for (const std::size_t i : order) {
        progress(rs[i].bench + " / " + rs[i].tool + " (rep " + std::to_string(k + 1) + " of " +
                 std::to_string(n) + ")");
        merge_best(rs[i].best, fns[i]());
      }
    }
    for (auto& r : rs) r.reps = n;
    rows.insert(rows.end(), rs.begin(), rs.end());
  };
  auto blocked = [](std::string why) {
    return [why] {
      Measure m;
      m.error = why;
      return m;
    };
  };

  if (only.empty() || only == "dt") {
    for (const std::int64_t n : dt_sizes) {
      if (static_cast<double>(n) > max_size) continue;
      ++group;
      const std::string b = "Delaunay, " + fmt("%.0e", static_cast<double>(n)) + " random points";
      std::vector<Row> rs(2);
      rs[0] = {b, "**ours** (refine=false)", {}, true, group, true, false, static_cast<double>(n)};
      rs[1] = {b,     "CGAL Delaunay_triangulation_2 (Epick)",
               {},    false,
               group, true,
               false, static_cast<double>(n)};
      run_case(rs,
               {[n] {
                  return run_self({"dt-ours", std::to_string(n)});
                },
                [n] {
                  return run_self({"dt-cgal", std::to_string(n)});
                }},
               static_cast<double>(n));
    }
  }
  if (only.empty() || only == "iso") {
    for (const Iso& s : iso_sizes) {
      if (s.n > max_size) continue;
      ++group;
      const std::string b =
          std::string("square with hole, ") + s.label + " tri, h=" + fmt("%.4g", s.h);
      const SquareHole d = square_hole(s.h);
      std::vector<Row> rs;
      std::vector<std::function<Measure()>> fns;
      const double h = s.h;
      rs.push_back({b, "**ours** (uniform h, saturation)", {}, true, group, false, false, 0});
      fns.push_back([h] { return run_self({"iso-ours", num17(h), "saturation"}); });
      rs.push_back({b, "**ours** (uniform h, frontal)", {}, false, group, false, false, 0});
      fns.push_back([h] { return run_self({"iso-ours", num17(h), "frontal"}); });
      // CGAL's size bound caps the longest edge, so with S = h its edges are mostly shorter
      // than h and it makes about twice the triangles; S = sqrt2 h (the upper end of the
      // unit-edge range) gives a mesh of about the same count as the others.
      rs.push_back({b, "CGAL Delaunay_mesher_2 (B=√2, S=h)", {}, false, group, false, false, 0});
      rs.push_back({b, "CGAL Delaunay_mesher_2 (B=√2, S=√2·h)", {}, false, group, false, false, 0});
      if (use_cgal) {
        fns.push_back([h] { return run_self({"iso-cgal", num17(h), num17(h)}); });
        fns.push_back([h] { return run_self({"iso-cgal", num17(h), num17(std::sqrt(2.0) * h)}); });
      } else {
        fns.push_back(blocked("BLOCKED: --no-cgal"));
        fns.push_back(blocked("BLOCKED: --no-cgal"));
      }
      for (const int algo : {5, 6}) {
        rs.push_back({b,
                      std::string("gmsh -2, algo ") +
                          (algo == 5 ? "5 Delaunay" : "6 Frontal-Delaunay") + ", -nt 1",
                      {},
                      false,
                      group,
                      false,
                      false,
                      0});
        if (have_gmsh)
          fns.push_back([&work, d, h, algo, keep] { return run_gmsh(work, d, h, algo, keep); });
        else
          fns.push_back(blocked("BLOCKED: gmsh not found in PATH (or --no-gmsh)"));
      }
      run_case(rs, fns, s.n);
    }
  }
  if (only.empty() || only == "aniso") {
    for (const Aniso& s : aniso_sizes) {
      if (s.n > max_size) continue;
      ++group;
      const std::string f = s.field;
      const std::string b =
          f + ":" + fmt("%g", s.h0) + "," + fmt("%g", s.hmax) + " on the unit square";
      const double h0 = s.h0, hmax = s.hmax, n = s.n;
      auto verts = std::make_shared<double>(0.0);  // ours' vertex count sizes bamg's -nbv
      auto bamg = std::make_shared<std::optional<BamgCase>>();  // background, built once
      std::vector<Row> rs;
      std::vector<std::function<Measure()>> fns;
      rs.push_back({b, "**ours** (anisotropic, saturation)", {}, true, group, false, true, 0});
      fns.push_back([f, h0, hmax, verts] {
        Measure m = run_self({"aniso-ours", f, num17(h0), num17(hmax), "saturation"});
        if (m.ok) *verts = m.verts;
        return m;
      });
      rs.push_back({b, "**ours** (anisotropic, frontal)", {}, false, group, false, true, 0});
      fns.push_back([f, h0, hmax] {
        return run_self({"aniso-ours", f, num17(h0), num17(hmax), "frontal"});
      });
      rs.push_back({b,
                    "ffbamg (Debian freefem++), -b background -M metric",
                    {},
                    false,
                    group,
                    false,
                    true,
                    0});
      if (have_bamg)
        fns.push_back([&work, f, h0, hmax, n, verts, bamg, progress] {
          if (!bamg->has_value()) {
            progress("  building bamg's background (adaptation passes, not timed)");
            *bamg = prepare_bamg(work, f, h0, hmax, *verts > 0 ? *verts : 0.6 * n);
          }
          return run_bamg(work, **bamg, f, h0, hmax);
        });
      else
        fns.push_back(blocked("BLOCKED: ffbamg not found in PATH (or --no-bamg)"));
      run_case(rs, fns, n);
      if (!keep) remove_bamg_files(work, f, h0, hmax);
    }
  }

  if (only.empty() || only == "lfs") {
    // Options::feature_size off and on, in both field-point modes (uvmesh2d's default is on).
    const auto ds = lfs_domains();
    for (std::size_t k = 0; k < ds.size(); ++k) {
      ++group;
      const std::string b = std::string(ds[k].name) + ", uniform h=" + fmt("%g", ds[k].h);
      std::vector<Row> rs;
      std::vector<std::function<Measure()>> fns;
      for (const char* method : {"saturation", "frontal"})
        for (const char* on : {"off", "on"}) {
          rs.push_back({b,
                        std::string("**ours** (") + method + ", feature size " + on + ")",
                        {},
                        rs.empty(),
                        group,
                        false,
                        false,
                        0});
          const std::string dom = std::to_string(k), m = method, o = on;
          fns.push_back([dom, m, o] { return run_self({"lfs-ours", dom, m, o}); });
        }
      run_case(rs, fns, 1e3);
    }
  }

  std::ostringstream head;
  head << "## bench_mesher2d " << (quick ? "(--quick)" : "(full)") << "\n\n";
  head << "Machine: " << machine_line() << "; " << load_at_start << " at the start, " << load_line()
       << " at the end; whole run " << fmt("%.0f", wall_now() - run_start) << " s wall. "
       << "Each case: ours and the references alternate, order flipped every repetition; best "
          "(smallest) "
          "wall and CPU kept separately over the repetitions (count in the notes). The machine is "
          "shared: wall times are noisy, "
          "CPU times are the steadier figure. Rates: M points/s for Delaunay rows, M triangles/s "
          "otherwise. "
          "'ours ÷ this' = our rate (saturation, the default) divided by this row's rate (> 1: "
          "ours faster). Median q = 4√3·area / Σ edge² (median_q), in the metric for the "
          "anisotropic rows. Quality by "
          "uvmesh::m2d::measure for every mesh (Q_K = (√3/6)·h_max/ρ_K; unit edges: metric length "
          "in "
          "[1/√2, √2], for the isotropic rows relative to h). Peak RSS: the child process right "
          "after the "
          "timed call (ours, CGAL) or the whole external process (gmsh, bamg).\n\n";
  const std::string t = table(rows, head.str());
  std::fputs(t.c_str(), stdout);
  if (!out_path.empty()) {
    std::ofstream f(out_path);
    f << t;
  }
  if (!keep) rmdir(work.c_str());
  return 0;
}
