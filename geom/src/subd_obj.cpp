// OBJ control cages (OpenSubdiv's dialect with `t` tag lines) and the option names of
// the subdivision back end. Needs nothing but the standard library, so a build without
// OpenSubdiv still reads cages and reports that it cannot evaluate them.
#include <array>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <fstream>
#include <sstream>
#include <string_view>

#include "subd_patch.h"
#include "uvmesh/geom/subd.h"

namespace uvmesh::geom {
namespace {

// Whitespace-separated tokens of one line.
std::vector<std::string_view> split(std::string_view s) {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < s.size()) {
    while (i < s.size() && (s[i] == ' ' || s[i] == '\t' || s[i] == '\r')) ++i;
    const std::size_t b = i;
    while (i < s.size() && s[i] != ' ' && s[i] != '\t' && s[i] != '\r') ++i;
    if (i > b) out.push_back(s.substr(b, i - b));
  }
  return out;
}

template <class T>
bool to_number(std::string_view s, T& out) {
  const char* e = s.data() + s.size();
  auto [p, ec] = std::from_chars(s.data(), e, out);
  return ec == std::errc() && p == e;
}

// Same bound as the CAD readers (io::ReadOptions::max_abs_coordinate): beyond it double
// spacing exceeds 1e-4 and the metric of the limit surface overflows, so such a vertex is
// a corrupt file, not a model.
constexpr double kMaxAbsCoordinate = 1e12;

// Thrown inside the parser, caught once at its end: one message naming the line.
struct ParseError {
  int line;
  std::string what;
};

}  // namespace

bool parse_subd_scheme(const std::string& s, SubdScheme& out) {
  if (s == "auto")
    out = SubdScheme::Auto;
  else if (s == "catmark" || s == "catmull-clark")
    out = SubdScheme::CatmullClark;
  else if (s == "loop")
    out = SubdScheme::Loop;
  else
    return false;
  return true;
}

bool parse_subd_boundary(const std::string& s, SubdBoundary& out) {
  if (s == "file")
    out = SubdBoundary::FromFile;
  else if (s == "none")
    out = SubdBoundary::None;
  else if (s == "edge-only")
    out = SubdBoundary::EdgeOnly;
  else if (s == "edge-and-corner")
    out = SubdBoundary::EdgeAndCorner;
  else
    return false;
  return true;
}

std::string_view to_string(SubdScheme s) {
  switch (s) {
    case SubdScheme::Auto:
      return "auto";
    case SubdScheme::CatmullClark:
      return "catmark";
    case SubdScheme::Loop:
      return "loop";
  }
  return "auto";
}

std::string_view to_string(SubdBoundary b) {
  switch (b) {
    case SubdBoundary::FromFile:
      return "file";
    case SubdBoundary::None:
      return "none";
    case SubdBoundary::EdgeOnly:
      return "edge-only";
    case SubdBoundary::EdgeAndCorner:
      return "edge-and-corner";
  }
  return "file";
}

namespace {

// `v x y z [w]`
void parse_vertex(const std::vector<std::string_view>& tok, int ln, SubdCage& c) {
  if (tok.size() < 4 || tok.size() > 5) throw ParseError{ln, "expected 'v x y z'"};
  Vec3 p;
  for (int k = 0; k < 3; ++k) {
    if (!to_number(tok[1 + k], p[k]))
      throw ParseError{ln, "malformed vertex coordinate '" + std::string(tok[1 + k]) + "'"};
    if (!std::isfinite(p[k]))
      throw ParseError{ln, "vertex coordinate is not finite (" + std::string(tok[1 + k]) + ")"};
    if (std::abs(p[k]) > kMaxAbsCoordinate)
      throw ParseError{ln, "vertex coordinate " + std::string(tok[1 + k]) +
                               " is beyond the accepted magnitude 1e12 (corrupted coordinate?)"};
  }
  c.points.push_back(p);
}

// `f v1 v2 v3 ...`; positive indices beyond the vertices so far go to forward_refs.
void parse_face(const std::vector<std::string_view>& tok, int ln, SubdCage& c,
                std::vector<std::pair<int, int>>& forward_refs) {
  if (tok.size() < 4) throw ParseError{ln, "a face needs at least 3 vertices"};
  const std::size_t first = c.face_verts.size();
  for (std::size_t k = 1; k < tok.size(); ++k) {
    // "v", "v/vt", "v//vn", "v/vt/vn": only the vertex index matters.
    const std::string_view vs = tok[k].substr(0, tok[k].find('/'));
    long idx = 0;
    if (!to_number(vs, idx))
      throw ParseError{ln, "malformed face index '" + std::string(tok[k]) + "'"};
    if (idx == 0) throw ParseError{ln, "face index 0 (OBJ indices start at 1)"};
    long v0 = 0;
    if (idx < 0) {
      v0 = static_cast<long>(c.points.size()) + idx;  // relative to the vertices so far
      if (v0 < 0)
        throw ParseError{ln, "face index " + std::to_string(idx) +
                                 " refers before the first vertex (" +
                                 std::to_string(c.points.size()) + " defined so far)"};
    } else {
      v0 = idx - 1;
      if (v0 > 0x7fffffffL - 1)
        throw ParseError{ln, "face index " + std::to_string(idx) + " is too large"};
      if (v0 >= static_cast<long>(c.points.size()))
        forward_refs.push_back({static_cast<int>(v0), ln});
    }
    c.face_verts.push_back(static_cast<int>(v0));
  }
  // A vertex repeated in a face is left to OpenSubdiv, which takes such faces as
  // non-manifold (the corpus has such cages, on purpose).
  c.face_sizes.push_back(static_cast<int>(c.face_verts.size() - first));
  c.face_lines.push_back(ln);
}

// The arguments of one `t` line.
struct TagArgs {
  std::string name;
  std::array<int, 3> n{};  // nint, nfloat, nstring
  std::vector<int> ia;
  std::vector<float> fa;
  std::vector<std::string> sa;
};

// t NAME nints/nfloats/nstrings ints... floats... strings...
TagArgs parse_tag_args(const std::vector<std::string_view>& tok, int ln) {
  if (tok.size() < 3) throw ParseError{ln, "expected 't NAME nint/nfloat/nstring ...'"};
  TagArgs t;
  t.name = std::string(tok[1]);
  const std::string& tname = t.name;
  std::array<int, 3>& n = t.n;
  {
    const std::string_view cs = tok[2];
    const auto s1 = cs.find('/'), s2 = s1 == std::string_view::npos ? s1 : cs.find('/', s1 + 1);
    if (s2 == std::string_view::npos || !to_number(cs.substr(0, s1), n[0]) ||
        !to_number(cs.substr(s1 + 1, s2 - s1 - 1), n[1]) || !to_number(cs.substr(s2 + 1), n[2]) ||
        n[0] < 0 || n[1] < 0 || n[2] < 0)
      throw ParseError{
          ln, "malformed tag counts '" + std::string(cs) + "' (expected nint/nfloat/nstring)"};
  }
  // Summed in 64 bits: three counts near INT_MAX overflow int.
  const std::int64_t nargs = std::int64_t{n[0]} + n[1] + n[2];
  if (static_cast<std::int64_t>(tok.size()) != 3 + nargs)
    throw ParseError{ln, "tag '" + tname + "' announces " + std::to_string(nargs) +
                             " arguments but has " + std::to_string(tok.size() - 3)};
  t.ia.resize(n[0]);
  t.fa.resize(n[1]);
  for (int k = 0; k < n[0]; ++k)
    if (!to_number(tok[3 + k], t.ia[k]))
      throw ParseError{
          ln, "malformed integer '" + std::string(tok[3 + k]) + "' in tag '" + tname + "'"};
  for (int k = 0; k < n[1]; ++k) {
    const auto& s = tok[3 + n[0] + k];
    if (!to_number(s, t.fa[k]) || !std::isfinite(t.fa[k]))
      throw ParseError{ln, "malformed number '" + std::string(s) + "' in tag '" + tname + "'"};
  }
  for (int k = 0; k < n[2]; ++k) t.sa.emplace_back(tok[3 + n[0] + n[1] + k]);
  for (int i : t.ia)
    if (i < 0)
      throw ParseError{ln, "negative index " + std::to_string(i) + " in tag '" + tname +
                               "' (tag indices are 0-based)"};
  return t;
}

// A `t` line: creases, corners, holes, interpolateboundary, creasemethod; other tags are
// ignored with a warning.
void parse_tag(const std::vector<std::string_view>& tok, int ln, const std::string& name,
               SubdCage& c) {
  const TagArgs t = parse_tag_args(tok, ln);
  const std::string& tname = t.name;
  const std::array<int, 3>& n = t.n;
  const std::vector<int>& ia = t.ia;
  const std::vector<float>& fa = t.fa;
  const std::vector<std::string>& sa = t.sa;
  if (tname == "crease") {
    // A chain of vertices; one sharpness for all its edges or one per edge.
    if (n[0] < 2 || (n[1] != 1 && n[1] != n[0] - 1))
      throw ParseError{ln, "crease: expected 2 or more vertices and 1 sharpness (or one per edge)"};
    for (int k = 0; k + 1 < n[0]; ++k)
      c.creases.push_back({ia[k], ia[k + 1], fa[n[1] == 1 ? 0 : k], ln});
  } else if (tname == "corner") {
    if (n[0] < 1 || (n[1] != 1 && n[1] != n[0]))
      throw ParseError{ln, "corner: expected vertices and 1 sharpness (or one per vertex)"};
    for (int k = 0; k < n[0]; ++k) c.corners.push_back({ia[k], fa[n[1] == 1 ? 0 : k], ln});
  } else if (tname == "hole") {
    for (int k = 0; k < n[0]; ++k) c.holes.push_back({ia[k], ln});
  } else if (tname == "interpolateboundary") {
    if (n[0] != 1 || ia[0] > 2)
      throw ParseError{ln, "interpolateboundary: expected one integer 0, 1 or 2"};
    c.interpolate_boundary = ia[0];
  } else if (tname == "creasemethod") {
    if (n[2] != 1 || (sa[0] != "normal" && sa[0] != "chaikin"))
      throw ParseError{ln, "creasemethod: expected 'normal' or 'chaikin'"};
    c.chaikin = sa[0] == "chaikin";
  } else {
    c.warnings.push_back(name + ":" + std::to_string(ln) + ": tag '" + tname + "' ignored");
  }
}

// One OBJ statement (the line without its comment).
void parse_statement(const std::vector<std::string_view>& tok, int ln, const std::string& name,
                     SubdCage& c, std::vector<std::pair<int, int>>& forward_refs) {
  const std::string_view kw = tok[0];
  if (kw == "v") {
    parse_vertex(tok, ln, c);
  } else if (kw == "f") {
    parse_face(tok, ln, c, forward_refs);
  } else if (kw == "t") {
    parse_tag(tok, ln, name, c);
  } else if (kw == "vt" || kw == "vn" || kw == "vp" || kw == "g" || kw == "o" || kw == "s" ||
             kw == "usemtl" || kw == "mtllib" || kw == "l") {
    // texture, normals, grouping and materials do not change the limit surface
  } else {
    c.warnings.push_back(name + ":" + std::to_string(ln) + ": statement '" + std::string(kw) +
                         "' ignored");
  }
}

}  // namespace

SubdCageResult parse_obj_cage(std::istream& in, const std::string& name) {
  SubdCageResult r;
  SubdCage& c = r.cage;
  c.source = name;
  // Positive face indices may refer to vertices defined further down (some exporters
  // write them so); they are checked at the end against the final vertex count.
  std::vector<std::pair<int, int>> forward_refs;  // (index, line)
  std::string line;
  int ln = 0;
  try {
    while (std::getline(in, line)) {
      ++ln;
      if (auto h = line.find('#'); h != std::string::npos) line.resize(h);
      const auto tok = split(line);
      if (!tok.empty()) parse_statement(tok, ln, name, c, forward_refs);
    }
    for (const auto& [idx, fl] : forward_refs)
      if (idx >= static_cast<int>(c.points.size()))
        throw ParseError{fl, "face references vertex " + std::to_string(idx + 1) +
                                 " but the file has only " + std::to_string(c.points.size()) +
                                 " vertices"};
    if (ln == 0) throw ParseError{0, "the file is empty"};
    if (c.face_sizes.empty()) throw ParseError{ln, "no faces"};
  } catch (const ParseError& e) {
    // Line 0: the whole file, not one of its lines.
    r.error = name + (e.line > 0 ? ":" + std::to_string(e.line) : std::string()) + ": " + e.what;
    return r;
  }
  r.ok = true;
  return r;
}

SubdCageResult read_obj_cage(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    SubdCageResult r;
    r.error = path + ": cannot open";
    return r;
  }
  return parse_obj_cage(in, path);
}

SubdModelResult read_subd(const std::string& path, const SubdOptions& opt) {
  SubdCageResult c = read_obj_cage(path);
  if (!c.ok) {
    SubdModelResult r;
    r.error = std::move(c.error);
    return r;
  }
  SubdModelResult r = model_from_cage(c.cage, opt);
  r.model.source = path;
  r.warnings.insert(r.warnings.begin(), c.cage.warnings.begin(), c.cage.warnings.end());
  return r;
}

// Quad k of an n-gon domain: corner k, side point k, centre, side point k-1 (CCW).
static void ngon_quad(const std::vector<Vec2>& poly, int k, Vec2& p00, Vec2& p10, Vec2& p01) {
  const int m = static_cast<int>(poly.size());
  p00 = poly[2 * k];
  p10 = poly[2 * k + 1];
  p01 = poly[(2 * k + m - 1) % m];
}

Vec2 ngon_domain_point(const std::vector<Vec2>& poly, Vec2 c, int k, Vec2 st) {
  Vec2 p00, p10, p01;
  ngon_quad(poly, k, p00, p10, p01);
  return (1 - st.x) * (1 - st.y) * p00 + st.x * (1 - st.y) * p10 + st.x * st.y * c +
         (1 - st.x) * st.y * p01;
}

Vec2 subd_patch_domain_point(const SubdPatch& P, int q, Vec2 st) {
  const Vec2 x = P.polygon.empty() ? st : ngon_domain_point(P.polygon, P.centre, q, st);
  if (!P.unprojected) return x;
  return P.plane.map(P.unprojected->point(x.x, x.y));
}

Vec2 ngon_subface_coords(const std::vector<Vec2>& poly, Vec2 c, int k, Vec2 x) {
  Vec2 p00, p10, p01;
  ngon_quad(poly, k, p00, p10, p01);
  const Vec2 e = p10 - p00, f = p01 - p00, g = c - p10 - p01 + p00;
  // Newton on P(s,t) = p00 + s e + t f + s t g = x; the quads are convex (model_from_cage
  // checks), so P is one-to-one on the unit square and Newton converges quadratically,
  // also a little outside it.
  Vec2 st{0.0};
  for (int it = 0; it < 30; ++it) {
    const Vec2 Ps = e + st.y * g, Pt = f + st.x * g;
    const Vec2 r = p00 + st.x * e + st.y * f + st.x * st.y * g - x;
    const double det = Ps.x * Pt.y - Ps.y * Pt.x;
    if (!(std::abs(det) > 0)) break;
    const Vec2 d{(Pt.y * r.x - Pt.x * r.y) / det, (-Ps.y * r.x + Ps.x * r.y) / det};
    st -= d;
    if (std::abs(d.x) + std::abs(d.y) <= 1e-15 * (1 + std::abs(st.x) + std::abs(st.y))) break;
  }
  return st;
}

#ifndef UVMESH_HAVE_OSD
bool have_opensubdiv() {
  return false;
}
SubdModelResult model_from_cage(const SubdCage& cage, const SubdOptions&) {
  SubdModelResult r;
  r.error = cage.source +
            ": this uvmesh was built without OpenSubdiv (libosd-dev): cannot evaluate subdivision "
            "surfaces";
  return r;
}
#endif

}  // namespace uvmesh::geom
