// Invariant tests of uvmesh::m2d::mesh over thousands of seeded random PSLGs, grouped by
// input property (pslg_gen.h): random, integer-grid (collinear and cocircular),
// duplicate, star-shaped with holes, comb with holes, nested regions, small angles and
// grid-snapped segments. Every case is checked by check() plus the properties each
// family promises. Failures are collected per test and reported with the family and
// seed, which reproduce the input: e.g. gen::star_with_holes(17).
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <exception>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "field_point_methods.h"
#include "pslg_gen.h"
#include "uvmesh/mesher2d/check.h"
#include "uvmesh/mesher2d/mesher2d.h"

using namespace uvmesh::m2d;

namespace {

// Collects failures of many cases; one CHECK at the end lists the first few.
struct Failures {
  std::vector<std::string> list;
  std::int64_t cases = 0;
  void add(const gen::Case& c, const std::string& what) { list.push_back(c.name + ": " + what); }
  void report() const {
    std::string s = std::to_string(list.size()) + " failing of " + std::to_string(cases) + " cases";
    for (std::size_t i = 0; i < list.size() && i < 25; ++i) s += "\n  " + list[i];
    INFO(s);
    CHECK(list.empty());
  }
};

std::string first_errors(const CheckReport& r) {
  std::string s;
  for (std::size_t i = 0; i < r.errors.size() && i < 3; ++i) s += (i ? " | " : "") + r.errors[i];
  return s;
}

const char* code_name(StatusCode c) {
  switch (c) {
    case StatusCode::Ok:
      return "Ok";
    case StatusCode::InvalidInput:
      return "InvalidInput";
    case StatusCode::CrossingSegments:
      return "CrossingSegments";
    case StatusCode::OpenBoundary:
      return "OpenBoundary";
    case StatusCode::Incomplete:
      return "Incomplete";
    case StatusCode::InternalError:
      return "InternalError";
    case StatusCode::TimeLimit:
      return "TimeLimit";
  }
  return "?";
}

std::string status_str(const Status& s) {
  return std::string(code_name(s.code)) + " \"" + s.message + "\"";
}

// Runs the mesher, turning an exception into a failure.
bool run(const gen::Case& c, const SizeSpec& size, const Options& opt, Result& r, Failures& f) {
  try {
    r = mesh(c.pslg, size, opt);
    return true;
  } catch (const std::exception& e) {
    f.add(c, std::string("exception: ") + e.what());
  } catch (...) {
    f.add(c, "unknown exception");
  }
  return false;
}

Options cdt_options() {
  Options o;
  o.refine = false;
  o.split_segments = false;
  o.optimize = false;
  return o;
}

Vec2 centroid(const Mesh& m, std::size_t t) {
  const auto& v = m.triangles[t];
  return {(m.vertices[v[0]].x + m.vertices[v[1]].x + m.vertices[v[2]].x) / 3,
          (m.vertices[v[0]].y + m.vertices[v[1]].y + m.vertices[v[2]].y) / 3};
}

// Seeds per family; the whole file runs in about a minute in Release on 2 cores.
constexpr std::uint64_t kCdtSeeds = 1200;    // x 9 families = 10800 CDTs (~7 s)
constexpr std::uint64_t kRefineSeeds = 180;  // x 9 families = 1620 refined meshes (~20 s)

}  // namespace

// (a) + (b): before refinement the result is the constrained Delaunay triangulation of the
// input: valid, Delaunay across every non-constrained edge, every input point a vertex.
// Without segments it is the Delaunay triangulation of the convex hull: 2n - 2 - h
// triangles (n distinct points, h of them on the hull boundary), the hull edges are the
// only constrained edges.
TEST_CASE("CDT of random PSLGs of every family is valid and Delaunay", "[invariants][cdt]") {
  for (const auto& fam : gen::families()) {
    Failures f;
    for (std::uint64_t seed = 1; seed <= kCdtSeeds; ++seed) {
      const gen::Case c = fam.make(seed);
      ++f.cases;
      Result r;
      if (!run(c, SizeSpec::uniform(0), cdt_options(), r, f)) continue;
      if (!r.ok()) {
        f.add(c, "status " + status_str(r.status));
        continue;
      }
      const CheckReport rep = check(r.mesh, c.pslg, {.delaunay = true});
      if (!rep.ok()) {
        f.add(c, "check: " + first_errors(rep));
        continue;
      }
      if (c.all_points_in_domain) {
        if (r.mesh.input_vertex.size() != c.pslg.points.size()) {
          f.add(c, "input_vertex has " + std::to_string(r.mesh.input_vertex.size()) + " entries");
          continue;
        }
        for (std::size_t i = 0; i < c.pslg.points.size(); ++i)
          if (r.mesh.input_vertex[i] == kNone) {
            f.add(c, "input point " + std::to_string(i) + " is missing from the mesh");
            break;
          }
      }
      if (fam.points_only) {
        const std::int64_t n = gen::distinct_count(c.pslg.points);
        const std::int64_t h = gen::hull_vertex_count(c.pslg.points);
        if (h == 0) continue;  // all collinear: no 2D hull (the generators avoid it)
        const auto nt = static_cast<std::int64_t>(r.mesh.triangles.size());
        if (nt != 2 * n - 2 - h)
          f.add(c, std::to_string(nt) +
                       " triangles, expected 2n-2-h = " + std::to_string(2 * n - 2 - h) +
                       " (n=" + std::to_string(n) + ", h=" + std::to_string(h) + ")");
        else if (static_cast<std::int64_t>(r.mesh.vertices.size()) != n)
          f.add(c, std::to_string(r.mesh.vertices.size()) + " vertices for " + std::to_string(n) +
                       " distinct points");
        else if (static_cast<std::int64_t>(r.mesh.boundary_edges.size()) != h)
          f.add(c, std::to_string(r.mesh.boundary_edges.size()) +
                       " constrained edges, expected the " + std::to_string(h) + " hull edges");
      }
    }
    INFO("family " << fam.name);
    f.report();
  }
}

// (c): refinement with a uniform size keeps the mesh valid, keeps the regions' attributes
// (nested squares: the attribute of the innermost square containing the triangle), and
// leaves nothing inside holes.
TEST_CASE("refined meshes of random PSLGs are valid, with regions and holes respected",
          "[invariants][refine]") {
  const FieldPointMethod method = FIELD_POINT_METHOD;
  for (const auto& fam : gen::families()) {
    Failures f;
    for (std::uint64_t seed = 1; seed <= kRefineSeeds; ++seed) {
      const gen::Case c = fam.make(seed);
      ++f.cases;
      Result r;
      Options o = method_options(method);
      o.max_vertices = 2'000'000;
      if (!run(c, SizeSpec::uniform(c.h), o, r, f)) continue;
      if (!r.ok()) {
        f.add(c, "status " + status_str(r.status) + " (h=" + std::to_string(c.h) + ")");
        continue;
      }
      const CheckReport rep = check(r.mesh, c.pslg, {.delaunay = false});
      if (!rep.ok()) {
        f.add(c, "check: " + first_errors(rep));
        continue;
      }
      if (r.mesh.triangles.empty()) {
        f.add(c, "no triangles");
        continue;
      }
      if (c.all_points_in_domain)
        for (std::size_t i = 0; i < c.pslg.points.size(); ++i)
          if (r.mesh.input_vertex[i] == kNone) {
            f.add(c, "input point " + std::to_string(i) + " is missing from the mesh");
            break;
          }
      for (std::size_t t = 0; t < r.mesh.triangles.size(); ++t) {
        const Vec2 g = centroid(r.mesh, t);
        if (c.in_hole(g)) {
          f.add(c, "triangle " + std::to_string(t) + " lies inside a hole");
          break;
        }
        double want = c.attribute_at(g);
        if (std::isnan(want)) want = 0;  // no region seed: attribute 0
        if (r.mesh.triangle_attribute.size() != r.mesh.triangles.size() ||
            r.mesh.triangle_attribute[t] != want) {
          f.add(c, "triangle " + std::to_string(t) + " has attribute " +
                       (r.mesh.triangle_attribute.size() > t
                            ? std::to_string(r.mesh.triangle_attribute[t])
                            : "none") +
                       ", expected " + std::to_string(want));
          break;
        }
      }
    }
    INFO("family " << fam.name << ", " << method_name(method));
    f.report();
  }
}

// (d): exact duplicates are merged, counted and reported; points one ulp apart are
// distinct and all kept.
TEST_CASE("duplicate points are merged and reported, 1-ulp neighbours kept",
          "[invariants][duplicates]") {
  Failures f;
  for (std::uint64_t seed = 1; seed <= 1000; ++seed) {
    const gen::Case c = gen::duplicate_points(seed);
    ++f.cases;
    Result r;
    if (!run(c, SizeSpec::uniform(0), cdt_options(), r, f)) continue;
    if (!r.ok()) {
      f.add(c, "status " + status_str(r.status));
      continue;
    }
    if (r.stats.duplicates_merged != c.exact_duplicates)
      f.add(c, "duplicates_merged " + std::to_string(r.stats.duplicates_merged) + ", expected " +
                   std::to_string(c.exact_duplicates));
    if (c.exact_duplicates > 0 && r.status.warnings.empty())
      f.add(c, "duplicates merged without a warning");
    const CheckReport rep = check(r.mesh, c.pslg, {.delaunay = true});
    if (!rep.ok()) f.add(c, "check: " + first_errors(rep));
    if (r.mesh.input_vertex.size() != c.pslg.points.size()) {
      f.add(c, "input_vertex size");
      continue;
    }
    // Equal points <-> equal vertices.
    std::map<std::pair<double, double>, VertId> seen;
    std::set<VertId> used;
    for (std::size_t i = 0; i < c.pslg.points.size(); ++i) {
      const VertId v = r.mesh.input_vertex[i];
      const auto key = std::make_pair(c.pslg.points[i].x, c.pslg.points[i].y);
      auto it = seen.find(key);
      if (it == seen.end()) {
        if (!used.insert(v).second) {
          f.add(c, "distinct input point " + std::to_string(i) + " shares vertex " +
                       std::to_string(v));
          break;
        }
        seen.emplace(key, v);
      } else if (it->second != v) {
        f.add(c, "duplicate input point " + std::to_string(i) + " maps to vertex " +
                     std::to_string(v) + ", its twin to " + std::to_string(it->second));
        break;
      }
    }
  }
  f.report();
}

TEST_CASE("duplicated polygon vertices referenced by segments are merged",
          "[invariants][duplicates]") {
  // A star polygon with holes where some vertices are repeated and segments use either
  // copy: after merging, the same domain as without the copies.
  Failures f;
  for (std::uint64_t seed = 1; seed <= 100; ++seed) {
    gen::Case c = gen::star_with_holes(seed);
    c.name += " with duplicated vertices (Rng(seed * 7919), chance 0.3 per segment end b)";
    gen::Rng rng(seed * 7919);
    int copies = 0;
    for (auto& s : c.pslg.segments)
      if (rng.chance(0.3)) {
        c.pslg.points.push_back(c.pslg.points[s.b]);
        s.b = static_cast<VertId>(c.pslg.points.size() - 1);
        ++copies;
      }
    ++f.cases;
    Result r;
    Options o;
    if (!run(c, SizeSpec::uniform(c.h), o, r, f)) continue;
    if (!r.ok()) {
      f.add(c, "status " + status_str(r.status));
      continue;
    }
    if (r.stats.duplicates_merged != copies)
      f.add(c, "duplicates_merged " + std::to_string(r.stats.duplicates_merged) + ", expected " +
                   std::to_string(copies));
    if (copies > 0 && r.status.warnings.empty()) f.add(c, "duplicates merged without a warning");
    const CheckReport rep = check(r.mesh, c.pslg);
    if (!rep.ok()) f.add(c, "check: " + first_errors(rep));
  }
  f.report();
}

// (e): crossing segments are an error naming both, or are split at their intersection.
TEST_CASE("crossing segments are reported or split", "[invariants][crossing]") {
  Failures f;
  for (std::uint64_t seed = 1; seed <= 300; ++seed) {
    Vec2 x;
    const gen::Case c = gen::crossing_pair(seed, &x);
    ++f.cases;
    Result r;
    Options o = cdt_options();
    o.split_crossing_segments = false;
    if (!run(c, SizeSpec::uniform(0), o, r, f)) continue;
    if (r.status.code != StatusCode::CrossingSegments) {
      f.add(c, "split=false: status " + status_str(r.status) + ", expected CrossingSegments");
    } else {
      const auto& e = r.status.entities;
      const bool names = std::find(e.begin(), e.end(), 4) != e.end() &&
                         std::find(e.begin(), e.end(), 5) != e.end();
      if (!names || r.status.message.find("segment 4") == std::string::npos ||
          r.status.message.find("segment 5") == std::string::npos)
        f.add(c, "split=false: status does not name segments 4 and 5: " + status_str(r.status));
    }
    for (const bool refine : {false, true}) {
      Options os = refine ? Options{} : cdt_options();
      os.split_crossing_segments = true;
      const std::string tag = refine ? "split=true refine=true: " : "split=true refine=false: ";
      if (!run(c, SizeSpec::uniform(c.h), os, r, f)) continue;
      if (!r.ok()) {
        f.add(c, tag + "status " + status_str(r.status));
        continue;
      }
      const CheckReport rep = check(r.mesh, c.pslg, {.delaunay = !refine});
      if (!rep.ok()) f.add(c, tag + "check: " + first_errors(rep));
      if (r.stats.crossings_split < 1) f.add(c, tag + "stats.crossings_split = 0");
      double best = 1e300;
      for (auto& v : r.mesh.vertices) best = std::min(best, std::hypot(v.x - x.x, v.y - x.y));
      if (!(best <= 1e-9))
        f.add(c, tag + "no vertex at the crossing point (nearest " + std::to_string(best) + ")");
    }
  }
  f.report();
}

TEST_CASE("a segment through input vertices is split there", "[invariants][crossing]") {
  Failures f;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    int on = 0;
    const gen::Case c = gen::segment_through_vertex(seed, &on);
    ++f.cases;
    for (const bool refine : {false, true}) {
      Result r;
      const std::string tag = refine ? "refine=true: " : "refine=false: ";
      if (!run(c, SizeSpec::uniform(c.h), refine ? Options{} : cdt_options(), r, f)) continue;
      if (!r.ok()) {
        f.add(c, tag + "status " + status_str(r.status));
        continue;
      }
      if (r.stats.segments_split_at_vertices < 1)
        f.add(c, tag + "stats.segments_split_at_vertices = 0");
      const CheckReport rep = check(r.mesh, c.pslg, {.delaunay = !refine});
      if (!rep.ok()) f.add(c, tag + "check: " + first_errors(rep));
      // Every point on the segment is a vertex with constrained edges on both sides.
      for (std::size_t i = 6; i < c.pslg.points.size(); ++i) {
        const VertId v = r.mesh.input_vertex.size() > i ? r.mesh.input_vertex[i] : kNone;
        int deg = 0;
        for (auto& e : r.mesh.boundary_edges) deg += (e.a == v) + (e.b == v);
        if (v == kNone || deg != 2)
          f.add(c, tag + "input point " + std::to_string(i) + " on segment 4 has " +
                       std::to_string(deg) + " constrained edges, expected 2");
      }
    }
  }
  f.report();
}

// (f): a hole seed inside a polygon with a gap empties the domain: OpenBoundary, no crash.
TEST_CASE("a hole leaking through a gap in the boundary gives OpenBoundary", "[invariants][open]") {
  Failures f;
  for (std::uint64_t seed = 1; seed <= 200; ++seed) {
    const gen::Case c = gen::open_boundary(seed);
    ++f.cases;
    for (const bool refine : {false, true}) {
      Result r;
      if (!run(c, SizeSpec::uniform(c.h), refine ? Options{} : cdt_options(), r, f)) continue;
      if (r.status.code != StatusCode::OpenBoundary)
        f.add(c, std::string(refine ? "refine=true" : "refine=false") + ": status " +
                     status_str(r.status) + ", expected OpenBoundary");
    }
  }
  f.report();
}
