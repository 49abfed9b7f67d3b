// The meshing job shared by `uvmesh mesh` and the Python module (job.h).
#include "uvmesh/io/job.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>

#include "uvmesh/geom/subd.h"
#include "uvmesh/io/report.h"
#include "uvmesh/io/units.h"
#ifdef UVMESH_HAVE_VOLUME
#include "uvmesh/surface/volume.h"
#endif

namespace uvmesh::io {

namespace {

using Clock = std::chrono::steady_clock;
double since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

std::string number(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// The bounds of every numeric option, by flag; the CLI's validators (through
// check_option_value) and check_options both read this table.
struct Bounds {
  const char* flag;
  double lo, hi;
  bool positive;  ///< finite and > lo (= 0); else in [lo, hi]
};
constexpr Bounds kBounds[] = {{"--hmax", 0, HUGE_VAL, true},
                              {"--hmax-rel", 0, HUGE_VAL, true},
                              {"--hmin", 0, HUGE_VAL, true},
                              {"--chordal", 0, HUGE_VAL, true},
                              {"--min-feature", 0, HUGE_VAL, true},
                              {"--sew-tol", 0, HUGE_VAL, true},
                              {"--sew-max-tol", 0, HUGE_VAL, true},
                              {"--angle", 0.1, 180.0, false},
                              {"--feature-angle", 0.0, 180.0, false},
                              {"--grad", 1.0, 100.0, false},
                              {"--aniso", 1.0, 1e4, false},
                              {"--threads", 0, 4096, false},
                              {"--face-time-limit", 0, HUGE_VAL, false}};

// The check of a flag's value; a value of 0 is the default (not checked) when zero_ok.
std::string check_flag(const char* flag, double v, bool zero_ok = true) {
  if (zero_ok && v == 0) return "";
  const std::string e = check_option_value(flag, v);
  return e.empty() ? e : std::string(flag) + ": " + e;
}

std::string check_local_sizes(const MeshJobOptions& o) {
  for (const auto* list : {&o.face_size, &o.edge_size})
    for (const auto& [id, h] : *list)
      if (id < 0 || !(h > 0) || !std::isfinite(h)) {
        std::ostringstream m;  // not string concatenation: GCC 12 warns (-Wrestrict) on it
        m << "'" << id << "=" << h << "': expected ID=SIZE";
        return m.str();
      }
  return "";
}

std::string check_read(const ReadOptions& r) {
  for (std::string e : {check_flag("--sew-tol", r.sew_rel_tol, false),
                        check_flag("--sew-max-tol", r.sew_max_rel_tol, false)})
    if (!e.empty()) return e;
  if (!r.units.empty() && canonical_length_unit(r.units).empty())
    return "--units: unknown length unit '" + r.units + "' (known: " + known_length_units() + ")";
  return "";
}

// Local sizes file: one "face ID H" or "edge ID H" per line; '#' starts a comment.
bool read_size_file(const std::string& path, param::SizeSpec& spec, std::string& err) {
  std::ifstream in(path);
  if (!in) {
    err = path + ": cannot open the sizes file";
    return false;
  }
  std::string line;
  int ln = 0;
  while (std::getline(in, line)) {
    ++ln;
    if (auto c = line.find('#'); c != std::string::npos) line.resize(c);
    std::istringstream ss(line);
    std::string kind;
    if (!(ss >> kind)) continue;
    long id = -1;
    double h = 0;
    std::string extra;
    if (!(ss >> id >> h) || (ss >> extra) || id < 0 || !(h > 0) || !std::isfinite(h) ||
        (kind != "face" && kind != "edge")) {
      err = path + ":" + std::to_string(ln) + ": expected 'face ID SIZE' or 'edge ID SIZE'";
      return false;
    }
    (kind == "face" ? spec.face_size : spec.edge_size)[static_cast<geom::Id>(id)] = h;
  }
  return true;
}

// Local sizes and the ids they name: "" or the error.
std::string local_sizes(const MeshJobOptions& o, const geom::Model& model,
                        surface::MeshOptions& out) {
  for (const auto& [id, h] : o.face_size) out.size.face_size[id] = h;
  for (const auto& [id, h] : o.edge_size) out.size.edge_size[id] = h;
  std::string err;
  if (!o.size_file.empty() && !read_size_file(o.size_file, out.size, err)) return err;
  for (const auto& [id, h] : out.size.face_size)
    if (id >= static_cast<geom::Id>(model.faces.size()))
      return "--face-size names face " + std::to_string(id) + " but the model has " +
             std::to_string(model.faces.size()) + " faces";
  for (const auto& [id, h] : out.size.edge_size)
    if (id >= static_cast<geom::Id>(model.edges.size()))
      return "--edge-size names edge " + std::to_string(id) + " but the model has " +
             std::to_string(model.edges.size()) + " edges";
  return "";
}

template <class T>
nlohmann::json face_list(const std::vector<T>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (const auto& f : v) a.push_back({{"face", f.face}, {"reason", f.reason}});
  return a;
}

// The report's keys that only the mesher knows (simplifications, twins, edge lengths).
void add_mesher_sections(const surface::MeshResult& r, nlohmann::json& j) {
  // Unit edges are measured face by face, in the metric each face was meshed for.
  std::int64_t ne = 0, ns = 0, nl = 0;
  for (const auto& fs : r.faces) ne += fs.edges, ns += fs.short_edges, nl += fs.long_edges;
  j["unit_edge_share"] = r.unit_edge_share();
  j["edge_lengths"] = {{"edges", ne}, {"short", ns}, {"long", nl}};
  j["unit_edge_share_metric"] = surface::kFaceMetricName;
  j["failed_faces"] = face_list(r.failed);
  j["warnings"] = r.warnings;
  nlohmann::json tw = nlohmann::json::array();
  for (const auto& [a, b] : r.twins) tw.push_back({{"face", a}, {"meshed_as", b}});
  j["coincident_faces"] = tw;
  j["degenerate_faces"] = face_list(r.degenerate);
  j["counts"]["faces_degenerate"] = r.degenerate.size();
  j["collapsed_faces"] = face_list(r.collapsed);
  nlohmann::json simp = nlohmann::json::array();
  for (const auto& s : r.simplified)
    simp.push_back({{"what", s.what},
                    {"vertices", s.vertices},
                    {"edges", s.edges},
                    {"faces", s.faces},
                    {"size", s.size},
                    {"why", s.why}});
  j["simplified"] = simp;
  j["counts"]["simplified"] = r.simplified.size();
  j["counts"]["faces_collapsed"] = r.collapsed.size();
}

}  // namespace

std::string check_option_value(std::string_view flag, double v, std::string_view text) {
  const std::string shown = text.empty() ? number(v) : std::string(text);
  for (const Bounds& b : kBounds) {
    if (flag != b.flag) continue;
    if (b.positive)
      return std::isfinite(v) && v > b.lo ? ""
                                          : "expected a finite number > 0, found '" + shown + "'";
    return v >= b.lo && v <= b.hi ? ""
                                  : "value " + shown + " not in range " + number(b.lo) + " to " +
                                        (std::isinf(b.hi) ? std::string("inf") : number(b.hi));
  }
  return "";
}

std::string option_bounds_text(std::string_view flag) {
  for (const Bounds& b : kBounds)
    if (flag == b.flag)
      return b.positive ? "X>0"
                        : "[" + number(b.lo) + " - " +
                              (std::isinf(b.hi) ? std::string("inf") : number(b.hi)) + "]";
  return "";
}

bool parse_id_size(const std::string& s, geom::Id& id, double& h) {
  const auto eq = s.find('=');
  if (eq == std::string::npos) return false;
  try {
    std::size_t k1 = 0, k2 = 0;
    const long v = std::stol(s.substr(0, eq), &k1);
    h = std::stod(s.substr(eq + 1), &k2);
    if (k1 != eq || k2 != s.size() - eq - 1 || v < 0 || !(h > 0) || !std::isfinite(h)) return false;
    id = static_cast<geom::Id>(v);
    return true;
  } catch (...) {
    return false;
  }
}

bool is_cage_path(const std::string& path) {
  std::string ext = std::filesystem::path(path).extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(),
                 [](unsigned char ch) { return std::tolower(ch); });
  return ext == ".obj";
}

std::string check_options(const MeshJobOptions& o) {
  // Explicit hmin against explicit hmax here; against a relative or default hmax once the
  // model is read (mesh_options).
  if (o.hmin > 0 && o.hmax > 0 && o.hmin > o.hmax)
    return "--hmin " + number(o.hmin) + " is larger than hmax " + number(o.hmax);
  const std::pair<const char*, double> values[] = {{"--hmax", o.hmax},
                                                   {"--hmax-rel", o.hmax_rel},
                                                   {"--hmin", o.hmin},
                                                   {"--chordal", o.chordal},
                                                   {"--min-feature", o.min_feature},
                                                   {"--angle", o.angle_deg},
                                                   {"--feature-angle", o.feature_angle_deg},
                                                   {"--grad", o.grad},
                                                   {"--aniso", o.aniso},
                                                   {"--threads", static_cast<double>(o.threads)}};
  for (const auto& [flag, v] : values)
    if (std::string e = check_flag(flag, v); !e.empty()) return e;
  for (std::string e : {check_flag("--face-time-limit", o.face_time_limit, false),
                        check_local_sizes(o), check_read(o.read)})
    if (!e.empty()) return e;
  if (o.volume && !volume_available())
    return "--volume needs Netgen's nglib, and this uvmesh was built without it (install "
           "libnglib-dev and rebuild)";
  geom::SubdScheme scheme;
  geom::SubdBoundary boundary;
  if (!geom::parse_subd_scheme(o.scheme, scheme))
    return "--scheme: " + o.scheme + " not in {auto,catmark,loop}";
  if (!geom::parse_subd_boundary(o.boundary_interp, boundary))
    return "--boundary-interp: " + o.boundary_interp +
           " not in {file,none,edge-only,edge-and-corner}";
  return "";
}

ReadResult read_model(const std::string& path, const MeshJobOptions& o) {
  ReadResult rr;
  if (is_cage_path(path)) {
    geom::SubdOptions so;
    geom::parse_subd_scheme(o.scheme, so.scheme);
    geom::parse_subd_boundary(o.boundary_interp, so.boundary);
    geom::SubdModelResult sr = geom::read_subd(path, so);
    rr.ok = sr.ok;
    rr.error = std::move(sr.error);
    rr.model = std::move(sr.model);
  } else {
    ReadOptions ro = o.read;
    ro.threads = o.threads;  // the assembly's general fuse runs on the same threads as the faces
    rr = read_cad(path, ro);
  }
  return rr;
}

std::string mesh_options(const MeshJobOptions& o, const geom::Model& model,
                         surface::MeshOptions& out) {
  out.size = surface::default_size(model);
  const double D = model.bbox.diagonal();
  if (o.hmax_rel > 0) out.size.hmax = o.hmax_rel * D;
  if (o.hmax > 0) out.size.hmax = o.hmax;
  if (o.hmin > 0) out.size.hmin = o.hmin;
  // Only the default hmin (D/1000) gives way to a small hmax; an explicit one is an error.
  if (o.hmin > 0 && o.hmin > out.size.hmax)
    return "--hmin " + number(o.hmin) + " is larger than hmax " + number(out.size.hmax);
  out.size.hmin = std::min(out.size.hmin, out.size.hmax);
  if (o.chordal > 0 || o.angle_deg > 0) {
    out.size.chordal_tol = o.chordal;
    out.size.angle_tol = o.angle_deg * std::numbers::pi / 180.0;
  }
  if (o.grad > 0) out.size.gradation = o.grad;
  if (o.min_feature > 0) out.min_feature = o.min_feature;
  if (o.feature_angle_deg > 0) out.feature_angle = o.feature_angle_deg * std::numbers::pi / 180.0;
  out.keep_topology = o.keep_topology;
  if (o.aniso > 0) {
    out.size.isotropic = false;
    out.size.max_anisotropy = o.aniso;
  }
  out.threads = o.threads;
  out.face_time_limit = o.face_time_limit;
  out.optimize3d = o.optimize3d;
  out.frontal = o.frontal;
  out.progress = o.progress;
  return local_sizes(o, model, out);
}

bool volume_available() {
#ifdef UVMESH_HAVE_VOLUME
  return true;
#else
  return false;
#endif
}

namespace {

// Tetrahedra in the closed solids of `model` bounded by the surface mesh `r`; the
// surface's largest size bounds the tetrahedra too.
VolumeRun fill_volume(const geom::Model& model, const surface::MeshResult& r) {
  VolumeRun v;
  v.requested = true;
  const auto t0 = Clock::now();
#ifdef UVMESH_HAVE_VOLUME
  surface::VolumeOptions vo;
  vo.hmax = r.size.hmax;
  surface::VolumeResult vr = surface::fill_solids(model, r.mesh, vo);
  v.mesh = std::move(vr.mesh);
  for (const auto& sf : vr.failed) v.failed.push_back(sf.message);
  for (const auto& st : vr.solids)
    v.solids.push_back({{"solid", st.solid},
                        {"triangles", st.triangles},
                        {"tets", st.tets},
                        {"interior_points", st.interior_points},
                        {"seconds", st.seconds}});
#else
  (void)model;
  (void)r;
  v.failed.push_back("this uvmesh was built without Netgen's nglib");
#endif
  v.seconds = since(t0);
  return v;
}

// The report's "volume" section and counts (MeshJobOptions::volume).
void add_volume_section(const VolumeRun& vol, nlohmann::json& j, nlohmann::json& sec) {
  sec["volume"] = vol.seconds;
  nlohmann::json v = tet_report_json(vol.mesh);
  v["mesher"] = "netgen nglib";
  v["filled"] = vol.solids;
  v["failed_solids"] = vol.failed;
  j["volume"] = v;
  j["counts"]["tets"] = vol.mesh.tets.size();
  j["counts"]["solids_filled"] = vol.solids.size();
  j["counts"]["solids_failed"] = vol.failed.size();
}

}  // namespace

MeshRun mesh_job(const geom::Model& model, const MeshJobOptions& o) {
  MeshRun run;
  run.error = mesh_options(o, model, run.asked);
  if (!run.error.empty()) return run;
  const auto t0 = Clock::now();
  run.result = surface::mesh_model(model, run.asked);
  run.seconds = since(t0);
  if (o.volume) run.volume = fill_volume(model, run.result);
  return run;
}

nlohmann::json mesh_report(const MeshJobOptions& opt, const ReadResult& rr, const MeshRun& run,
                           const ReportContext& ctx) {
  const geom::Model& model = rr.model;
  const surface::MeshResult& r = run.result;
  const surface::MeshOptions o = surface::effective_options(model, run.asked);
  const auto t0 = Clock::now();
  CheckOptions co;
  co.threads = opt.threads;
  co.self_intersections = opt.self_intersections;
  co.chordal_tolerance = o.size.chordal_tol;
  co.size = r.size;  // the sizes mesh_model made elements for
  nlohmann::json j = report_json(check_mesh(r.mesh, &model, co));
  j["model"] = ctx.model_path;
  j["output"] = ctx.output.empty() ? nlohmann::json() : nlohmann::json(ctx.output);
  j["units"] = model.units;
  j["bbox_diagonal"] = model.bbox.diagonal();
  j["size"] = {{"hmax", o.size.hmax},
               {"hmin", o.size.hmin},
               {"chordal", o.size.chordal_tol},
               {"angle_deg", o.size.angle_tol * 180.0 / std::numbers::pi},
               {"gradation", o.size.gradation},
               {"isotropic", o.size.isotropic},
               {"min_feature", surface::feature_size(o, model.bbox)},
               {"feature_angle_deg", o.feature_angle * 180.0 / std::numbers::pi},
               {"keep_topology", o.keep_topology},
               {"field_points", o.frontal ? "frontal" : "saturation"}};
  j["counts"]["faces"] = model.faces.size();
  j["counts"]["edges"] = model.edges.size();
  j["counts"]["faces_failed"] = r.failed.size();
  nlohmann::json sec = {
      {"read", ctx.read_seconds}, {"mesh", run.seconds}, {"write", ctx.write_seconds}};
  for (const auto& s : r.stages) sec["mesh_" + s.name] = s.seconds;
  if (run.volume.requested) add_volume_section(run.volume, j, sec);
  add_mesher_sections(r, j);
  // What reading and healing did to the file (uvmesh info shows the same): a refused
  // step (an assembly left non-conforming) changes what the mesh can be.
  nlohmann::json heal = nlohmann::json::array();
  for (const auto& h : rr.report.healing)
    heal.push_back({{"name", h.name}, {"applied", h.applied}, {"detail", h.detail}});
  j["read"] = {{"warnings", rr.report.warnings}, {"healing", heal}};
  sec["checks"] = since(t0);
  sec["total"] = since(ctx.start);
  j["seconds"] = sec;
  return j;
}

}  // namespace uvmesh::io
