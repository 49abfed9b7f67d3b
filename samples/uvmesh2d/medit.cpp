#include "uvmesh2d/medit.h"

#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>

#include "uvmesh2d/text.h"

namespace uvmesh::cli2d {

namespace {

using text::quoted;

constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max() - 1;
constexpr std::int64_t kMaxReserve = 1 << 20;

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

std::string num(double v) {
  std::string s;
  text::append_double(s, v);
  return s;
}

// Token-level reading with messages that name file and line.
class Reader {
 public:
  Reader(std::istream& in, std::string name) : tr_(in), name_(std::move(name)) {}
  std::optional<Diagnostic> error;
  std::string tok;

  bool fail(const std::string& msg) {
    error = Diagnostic{name_, tr_.line(), msg};
    return false;
  }
  bool next(const std::string& what) {
    if (tr_.next(tok)) return true;
    return fail("unexpected end of file: expected " + what);
  }
  bool next_keyword(std::string& kw) {
    if (!tr_.next(tok)) return false;
    kw = tok;
    return true;
  }
  bool integer(const std::string& what, std::int64_t& v) {
    if (!next(what)) return false;
    auto p = text::parse_int(tok);
    if (!p) return fail(what + ": " + quoted(tok) + " is not an integer");
    v = *p;
    return true;
  }
  bool index(const std::string& what, std::int64_t n, std::int32_t& v) {  // 1-based in the file
    std::int64_t i = 0;
    if (!integer(what, i)) return false;
    if (i < 1 || i > n)
      return fail(what + " is " + std::to_string(i) + ", but there are " + std::to_string(n) +
                  " vertices (numbered 1 to " + std::to_string(n) + ")");
    v = static_cast<std::int32_t>(i - 1);
    return true;
  }
  bool ref(const std::string& what, int& v) {
    std::int64_t i = 0;
    if (!integer(what, i)) return false;
    if (i < std::numeric_limits<int>::min() || i > std::numeric_limits<int>::max())
      return fail(what + " is out of range (" + std::to_string(i) + ")");
    v = static_cast<int>(i);
    return true;
  }
  bool count(const std::string& what, std::int64_t& v) {
    if (!integer(what, v)) return false;
    if (v < 0 || v > kMaxCount) return fail(what + " is out of range (" + std::to_string(v) + ")");
    return true;
  }
  bool real(const std::string& what, double& v) {
    if (!next(what)) return false;
    auto p = text::parse_double(tok);
    if (!p) return fail(what + ": " + quoted(tok) + " is not a number");
    if (!std::isfinite(*p)) return fail(what + " is " + quoted(tok) + "; numbers must be finite");
    v = *p;
    return true;
  }
  int line() const { return tr_.line(); }

 private:
  text::TokenReader tr_;
  std::string name_;
};

// Keywords we accept and skip: integers per entry after the count.
int skipped_width(const std::string& kw) {
  if (kw == "corners" || kw == "requiredvertices" || kw == "ridges" || kw == "requirededges" ||
      kw == "requiredtriangles")
    return 1;
  if (kw == "quadrilaterals") return 5;
  return 0;
}

}  // namespace

MeditRead parse_medit_mesh(std::istream& in, const std::string& name) {
  MeditRead r;
  MeditMesh2& m = r.mesh;
  Reader rd(in, name);
  auto failed = [&]() -> MeditRead& {
    r.error = rd.error;
    return r;
  };
  auto fail = [&](const std::string& msg) -> MeditRead& {
    rd.fail(msg);
    return failed();
  };
  bool have_version = false, have_dim = false, have_vertices = false;
  std::string kw_raw;
  while (rd.next_keyword(kw_raw)) {
    const std::string kw = lower(kw_raw);
    if (kw == "meshversionformatted") {
      std::int64_t v = 0;
      if (!rd.integer("MeshVersionFormatted", v)) return failed();
      if (v < 1 || v > 4)
        return fail("MeshVersionFormatted must be 1 to 4, found " + std::to_string(v));
      m.version = static_cast<int>(v);
      have_version = true;
    } else if (kw == "dimension") {
      std::int64_t d = 0;
      if (!rd.integer("Dimension", d)) return failed();
      if (d != 2 && d != 3)
        return fail("Dimension must be 2 (or 3 with z ignored), found " + std::to_string(d));
      m.dimension = static_cast<int>(d);
      have_dim = true;
    } else if (kw == "vertices") {
      if (!have_dim) return fail("Vertices before Dimension");
      std::int64_t n = 0;
      if (!rd.count("number of vertices", n)) return failed();
      m.vertices.reserve(static_cast<std::size_t>(std::min(n, kMaxReserve)));
      m.vertex_refs.reserve(static_cast<std::size_t>(std::min(n, kMaxReserve)));
      for (std::int64_t i = 0; i < n; ++i) {
        std::string what = "vertex " + std::to_string(i + 1);
        m2d::Vec2 v;
        double z = 0;
        int ref = 0;
        if (!rd.real(what + " x", v.x) || !rd.real(what + " y", v.y)) return failed();
        if (m.dimension == 3 && !rd.real(what + " z", z)) return failed();
        if (!rd.ref(what + " reference", ref)) return failed();
        m.vertices.push_back(v);
        m.vertex_refs.push_back(ref);
      }
      have_vertices = true;
    } else if (kw == "triangles" || kw == "edges") {
      const bool tri = kw == "triangles";
      if (!have_vertices) return fail(kw_raw + " before Vertices");
      const auto nv = static_cast<std::int64_t>(m.vertices.size());
      std::int64_t n = 0;
      if (!rd.count(tri ? "number of triangles" : "number of edges", n)) return failed();
      for (std::int64_t i = 0; i < n; ++i) {
        std::string what = (tri ? "triangle " : "edge ") + std::to_string(i + 1);
        std::array<std::int32_t, 3> t{};
        int ref = 0;
        for (int k = 0; k < (tri ? 3 : 2); ++k)
          if (!rd.index(what + " vertex " + std::to_string(k + 1), nv,
                        t[static_cast<std::size_t>(k)]))
            return failed();
        if (!rd.ref(what + " reference", ref)) return failed();
        if (tri) {
          m.triangles.push_back({t[0], t[1], t[2]});
          m.triangle_refs.push_back(ref);
          m.triangle_lines.push_back(rd.line());
        } else {
          m.edges.push_back({t[0], t[1]});
          m.edge_refs.push_back(ref);
        }
      }
    } else if (int w = skipped_width(kw); w > 0) {
      std::int64_t n = 0, dummy = 0;
      if (!rd.count("number of " + kw_raw, n)) return failed();
      for (std::int64_t i = 0; i < n * w; ++i)
        if (!rd.integer(kw_raw + " entry", dummy)) return failed();
    } else if (kw == "end") {
      break;
    } else {
      return fail("unsupported keyword " + quoted(kw_raw) +
                  " (read: MeshVersionFormatted, Dimension, Vertices, Triangles, Edges, End)");
    }
  }
  if (!have_version) return fail("not a Medit mesh: MeshVersionFormatted is missing");
  return r;
}

MeditRead read_medit_mesh(const std::string& path) {
  std::string ext = text::extension(path);
  if (ext == ".meshb") {
    MeditRead r;
    r.error = Diagnostic{path, 0,
                         "binary Medit files (.meshb) are not supported; use the ASCII .mesh form"};
    return r;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    MeditRead r;
    r.error = Diagnostic{path, 0, "cannot open the file for reading"};
    return r;
  }
  return parse_medit_mesh(in, path);
}

SolRead parse_medit_sol(std::istream& in, const std::string& name, std::int64_t expected_vertices) {
  SolRead r;
  MeditSol& s = r.sol;
  Reader rd(in, name);
  auto failed = [&]() -> SolRead& {
    r.error = rd.error;
    return r;
  };
  auto fail = [&](const std::string& msg) -> SolRead& {
    rd.fail(msg);
    return failed();
  };
  bool have_version = false, have_dim = false, have_field = false;
  std::string kw_raw;
  while (rd.next_keyword(kw_raw)) {
    const std::string kw = lower(kw_raw);
    if (kw == "meshversionformatted") {
      std::int64_t v = 0;
      if (!rd.integer("MeshVersionFormatted", v)) return failed();
      if (v < 1 || v > 4)
        return fail("MeshVersionFormatted must be 1 to 4, found " + std::to_string(v));
      have_version = true;
    } else if (kw == "dimension") {
      std::int64_t d = 0;
      if (!rd.integer("Dimension", d)) return failed();
      if (d != 2)
        return fail("Dimension must be 2 for a 2D size field, found " + std::to_string(d));
      s.dimension = 2;
      have_dim = true;
    } else if (kw == "solatvertices") {
      if (!have_dim) return fail("SolAtVertices before Dimension");
      if (have_field) return fail("a second SolAtVertices section");
      std::int64_t n = 0, nfields = 0;
      if (!rd.count("number of vertices", n)) return failed();
      const int count_line = rd.line();
      if (expected_vertices >= 0 && n != expected_vertices) {
        r.error = Diagnostic{name, count_line,
                             "the solution has values at " + std::to_string(n) +
                                 " vertices, but the background mesh has " +
                                 std::to_string(expected_vertices)};
        return r;
      }
      if (!rd.count("number of fields", nfields)) return failed();
      if (nfields < 1 || nfields > 64)
        return fail("number of fields must be 1 to 64, found " + std::to_string(nfields));
      std::vector<int> widths;
      int keep = -1, stride = 0, offset = 0;
      for (std::int64_t f = 0; f < nfields; ++f) {
        std::int64_t t = 0;
        if (!rd.integer("field type", t)) return failed();
        int w = t == 1 ? 1 : t == 2 ? 2 : t == 3 ? 3 : 0;
        if (w == 0)
          return fail("field type must be 1 (scalar), 2 (vector) or 3 (symmetric tensor), found " +
                      std::to_string(t));
        if (keep < 0 && t != 2) {
          keep = static_cast<int>(f);
          offset = stride;
          s.type = t == 1 ? MeditSol::Type::Scalar : MeditSol::Type::Tensor;
        }
        widths.push_back(w);
        stride += w;
      }
      if (keep < 0) return fail("no size (type 1) or metric (type 3) field: only vectors");
      const int width = widths[static_cast<std::size_t>(keep)];
      s.values.reserve(static_cast<std::size_t>(std::min(n * width, kMaxReserve)));
      std::vector<double> row(static_cast<std::size_t>(stride));
      for (std::int64_t i = 0; i < n; ++i) {
        std::string what = "vertex " + std::to_string(i + 1);
        for (int k = 0; k < stride; ++k)
          if (!rd.real(what + " value " + std::to_string(k + 1), row[static_cast<std::size_t>(k)]))
            return failed();
        const double* v = row.data() + offset;
        if (s.type == MeditSol::Type::Scalar) {
          if (!(v[0] > 0)) return fail(what + ": the size must be > 0, found " + num(v[0]));
        } else {
          const double det = v[0] * v[2] - v[1] * v[1];
          if (!(v[0] > 0) || !(v[2] > 0) || !(det > 0))
            return fail(what + ": the metric (m11 m12 m22) = (" + num(v[0]) + " " + num(v[1]) +
                        " " + num(v[2]) + ") is not positive definite");
        }
        s.values.insert(s.values.end(), v, v + width);
        s.lines.push_back(rd.line());
      }
      have_field = true;
    } else if (kw.rfind("solat", 0) == 0) {
      return fail("unsupported keyword " + quoted(kw_raw) + ": only SolAtVertices is supported");
    } else if (kw == "end") {
      break;
    } else {
      return fail("unsupported keyword " + quoted(kw_raw) +
                  " (read: MeshVersionFormatted, Dimension, SolAtVertices, End)");
    }
  }
  if (!have_version) return fail("not a Medit solution: MeshVersionFormatted is missing");
  if (!have_field) return fail("no SolAtVertices section");
  return r;
}

SolRead read_medit_sol(const std::string& path, std::int64_t expected_vertices) {
  if (text::extension(path) == ".solb") {
    SolRead r;
    r.error = Diagnostic{path, 0,
                         "binary Medit files (.solb) are not supported; use the ASCII .sol form"};
    return r;
  }
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    SolRead r;
    r.error = Diagnostic{path, 0, "cannot open the file for reading"};
    return r;
  }
  return parse_medit_sol(in, path, expected_vertices);
}

std::vector<int> triangle_refs(const m2d::Mesh& m, bool has_regions, std::string* warning) {
  const std::size_t n = m.triangles.size();
  std::vector<int> refs(n, 1);
  bool use_attr = has_regions && m.triangle_attribute.size() == n;
  if (use_attr) {
    for (double a : m.triangle_attribute) {
      if (!(std::nearbyint(a) == a) || std::fabs(a) > std::numeric_limits<int>::max()) {
        use_attr = false;
        if (warning)
          *warning =
              "regional attributes are not all integers; triangle references are component numbers "
              "instead";
        break;
      }
    }
  }
  for (std::size_t i = 0; i < n; ++i) {
    if (use_attr)
      refs[i] = static_cast<int>(m.triangle_attribute[i]);
    else if (i < m.triangle_region.size())
      refs[i] = m.triangle_region[i] + 1;
  }
  return refs;
}

void write_medit(std::ostream& out, const m2d::Mesh& m, const std::vector<int>& tri_refs) {
  std::string b;
  b.reserve(1 << 20);
  auto flush = [&](bool force) { text::flush_buffer(out, b, force); };
  b += "MeshVersionFormatted 2\nDimension 2\n\nVertices\n";
  text::append_int(b, static_cast<std::int64_t>(m.vertices.size()));
  b += '\n';
  for (std::size_t i = 0; i < m.vertices.size(); ++i) {
    text::append_double(b, m.vertices[i].x);
    b += ' ';
    text::append_double(b, m.vertices[i].y);
    b += ' ';
    text::append_int(b, i < m.vertex_markers.size() ? m.vertex_markers[i] : 0);
    b += '\n';
    flush(false);
  }
  b += "\nTriangles\n";
  text::append_int(b, static_cast<std::int64_t>(m.triangles.size()));
  b += '\n';
  for (std::size_t i = 0; i < m.triangles.size(); ++i) {
    for (m2d::VertId v : m.triangles[i]) {
      text::append_int(b, v + 1);
      b += ' ';
    }
    text::append_int(b, i < tri_refs.size() ? tri_refs[i] : 0);
    b += '\n';
    flush(false);
  }
  b += "\nEdges\n";
  text::append_int(b, static_cast<std::int64_t>(m.boundary_edges.size()));
  b += '\n';
  for (const m2d::BoundaryEdge& e : m.boundary_edges) {
    text::append_int(b, e.a + 1);
    b += ' ';
    text::append_int(b, e.b + 1);
    b += ' ';
    text::append_int(b, e.marker);
    b += '\n';
    flush(false);
  }
  b += "\nEnd\n";
  flush(true);
}

}  // namespace uvmesh::cli2d
