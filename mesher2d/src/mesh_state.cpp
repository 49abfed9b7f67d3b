// MeshState's shared services: status, the validated size field, the time limit.
#include "mesh_state.h"

#include <cstdio>

namespace uvmesh::m2d::detail {

std::string fmt_pt(Vec2 p) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "(%.17g, %.17g)", p.x, p.y);
  return buf;
}

bool MeshState::fail(StatusCode c, std::string msg, std::vector<std::int64_t> ent) {
  res.status.code = c;
  res.status.message = std::move(msg);
  res.status.entities = std::move(ent);
  return false;
}

void MeshState::field_fail(std::string msg) {
  if (!field_error) fail(StatusCode::InvalidInput, std::move(msg));
  field_error = true;
}

bool MeshState::over_time(const char* stage) {
  if (!(opt.time_limit > 0) || res.status.code == StatusCode::TimeLimit)
    return res.status.code == StatusCode::TimeLimit;
  const double s = std::chrono::duration<double>(Clock::now() - t_start).count();
  if (s <= opt.time_limit) return false;
  res.status.code = StatusCode::TimeLimit;
  char buf[64];
  std::snprintf(buf, sizeof buf, "%g", opt.time_limit);
  res.status.message = std::string("time limit of ") + buf + " s reached during " + stage;
  return true;
}

Metric2 MeshState::metric(double x, double y) {
  Metric2 m;
  if (size.kind == SizeSpec::Kind::Uniform) return m_uniform;
  if (size.kind == SizeSpec::Kind::Scalar) {
    const double h = size.size(x, y);
    if (!(h > 0) || !std::isfinite(h)) {
      field_fail("the size field returned h = " + std::to_string(h) + " at " + fmt_pt({x, y}));
      return m_uniform;
    }
    return Metric2::iso(h);
  }
  m = size.metric(x, y);
  const double det = m.m11 * m.m22 - m.m12 * m.m12;
  if (!(m.m11 > 0) || !(m.m22 > 0) || !(det > 0) || !std::isfinite(m.m11) ||
      !std::isfinite(m.m12) || !std::isfinite(m.m22)) {
    field_fail("the metric field is not symmetric positive definite at " + fmt_pt({x, y}));
    return m_uniform;
  }
  return cap_anisotropy(m, opt.max_anisotropy);
}

std::string MeshState::seg_name(const SegRec& s) const {
  if (s.input < 0) return "convex hull edge";
  const auto& o = in.segments[s.input];
  return std::to_string(s.input) + " (points " + std::to_string(o.a) + "-" + std::to_string(o.b) +
         ")";
}

}  // namespace uvmesh::m2d::detail
