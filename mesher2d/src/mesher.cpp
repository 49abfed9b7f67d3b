// The mesher2d pipeline: classical Delaunay meshing (§7.3.1) governed by a size or metric
// field (§7.5, §7.6.1). Stages and their sections are listed in mesher2d.h; the state they
// share is MeshState (mesh_state.h), each stage's code and scratch is in its own file.
#include <chrono>
#include <string>

#include "mesh_state.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"
#include "uvmesh/mesher2d/predicates.h"

namespace uvmesh::m2d {

namespace {

using detail::MeshState;

// Times the stages into Result::stats: each call closes the stage running since the last.
class StageClock {
 public:
  explicit StageClock(Stats& stats) : stats_(stats) {}
  void operator()(const char* name) {
    const auto t1 = Clock::now();
    stats_.stages.push_back({name, std::chrono::duration<double>(t1 - t0_).count()});
    t0_ = t1;
  }

 private:
  using Clock = std::chrono::steady_clock;
  Stats& stats_;
  Clock::time_point t0_ = Clock::now();
};

// The triangulations own invariants (Options::check): every live triangle counter-
// clockwise, neighbours symmetric, constraints the same on both sides.
bool internal_check(MeshState& ms, const char* when) {
  const TriId nt = ms.tri.num_tris();
  for (TriId t = 0; t < nt; ++t) {
    if (ms.tri.dead(t)) continue;
    const auto& P = ms.tri.points();
    const VertId a = ms.tri.vertex(t, 0), b = ms.tri.vertex(t, 1), c = ms.tri.vertex(t, 2);
    if (pred::orient2d(&P[a].x, &P[b].x, &P[c].x) <= 0)
      return ms.fail(StatusCode::InternalError, std::string("checker ") + when + ": triangle " +
                                                    std::to_string(t) + " is not CCW");
    for (int i = 0; i < 3; ++i) {
      const std::int32_t h = 3 * t + i, g = ms.tri.twin(h);
      if (g == kNone) continue;
      if (ms.tri.twin(g) != h || ms.tri.dead(g / 3) ||
          ms.tri.constraint(g) != ms.tri.constraint(h) ||
          ms.tri.vertex(g / 3, detail::next3(g % 3)) != ms.tri.vertex(t, detail::prev3(i)))
        return ms.fail(StatusCode::InternalError, std::string("checker ") + when +
                                                      ": neighbours of triangle " +
                                                      std::to_string(t) + " are not symmetric");
    }
  }
  return true;
}

// Options::check after a stage: false (status InternalError) when an invariant is broken.
bool checked(MeshState& ms, const char* when) {
  return !ms.opt.check || internal_check(ms, when);
}

// The output checked against the input (Options::check).
void check_output(MeshState& ms, bool delaunay) {
  if (!ms.opt.check) return;
  CheckReport rep = check(ms.res.mesh, ms.in, {.delaunay = delaunay});
  if (!rep.ok()) ms.fail(StatusCode::InternalError, "checker: " + rep.errors.front());
}

// The size the measure conforms to. Without refinement there is none: Euclidean only.
SizeSpec measure_spec(const MeshState& ms) {
  if (!ms.opt.refine || !ms.refine_ok) return SizeSpec::uniform(0);
  if (ms.size.kind == SizeSpec::Kind::Uniform) return SizeSpec::uniform(ms.h_uniform);
  return ms.size;
}

// No segments, holes, regions or refinement: the Delaunay triangulation of the convex
// hull (hull_path.cpp).
void mesh_hull(MeshState& ms, StageClock& stage) {
  stage("input");
  detail::HullDelaunay dh;
  const auto st = dh.build(ms.in.points);
  if (st == detail::HullDelaunay::Status::Collinear) {
    ms.fail(StatusCode::InvalidInput, "all points are collinear: there is no triangle to make");
    return;
  }
  if (st != detail::HullDelaunay::Status::Ok) {
    ms.fail(StatusCode::InternalError,
            "Delaunay triangulation of the convex hull failed (kernel bug guard)");
    return;
  }
  stage("delaunay");
  detail::output_hull(ms, dh);
  stage("output");
  if (ms.opt.measure) {
    ms.res.stats.quality =
        measure(ms.res.mesh.vertices, ms.res.mesh.triangles, SizeSpec::uniform(0));
    stage("measure");
  }
  check_output(ms, /*delaunay=*/true);
}

// Field points, then optimization (Options::refine, Options::optimize).
bool refine_and_optimize(MeshState& ms, StageClock& stage) {
  detail::insert_field_points(ms);
  stage("field points");
  if (!checked(ms, "after field points")) return false;
  if (!ms.opt.optimize || ms.res.status.code == StatusCode::TimeLimit) return true;
  detail::optimize_mesh(ms);
  stage("optimization");
  return checked(ms, "after optimization");
}

void run(MeshState& ms) {
  StageClock stage(ms.res.stats);
  if (!detail::validate_input(ms)) return;
  if (detail::hull_fast_path(ms)) return mesh_hull(ms, stage);
  detail::merge_duplicates(ms);
  detail::build_segments(ms);
  stage("input");
  if (!detail::triangulate_box(ms)) return;
  stage("delaunay");
  if (!detail::enforce_boundary(ms)) return;
  stage("boundary enforcement");
  const bool refine = ms.opt.refine && ms.refine_ok;
  if (refine && ms.opt.feature_size) {
    detail::apply_feature_size(ms);
    stage("feature size");
  }
  if (refine && ms.opt.split_segments) {
    // Curves first: split the enforced segments (input segments already split at the
    // input vertices lying on them, and at crossings) at unit metric length.
    if (!detail::split_boundary(ms)) return;
    stage("boundary discretization");
  }
  if (!detail::color_domain(ms)) return;
  stage("coloring");
  if (!checked(ms, "after coloring")) return;
  if (refine && !refine_and_optimize(ms, stage)) return;
  std::vector<std::uint64_t> edges;  // every output edge once, for the measure
  detail::output_mesh(ms, edges);
  stage("output");
  if (ms.field_error) return;
  if (ms.opt.measure) {
    ms.res.stats.quality = detail::measure_with_edges(ms.res.mesh.vertices, ms.res.mesh.triangles,
                                                      measure_spec(ms), &edges);
    stage("measure");
  }
  check_output(ms, /*delaunay=*/!ms.opt.refine);
}

}  // namespace

Result mesh(const Pslg& in, const SizeSpec& size, const Options& opt) {
  Result res;
  Options o = opt;
#ifndef NDEBUG
  o.check = true;
#endif
  MeshState ms(in, size, o, res);
  run(ms);
  return res;
}

}  // namespace uvmesh::m2d
