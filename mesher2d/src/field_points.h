// Stage 6 of mesher2d, field points (internal): the waves' shared state. Saturation waves
// (field_points.cpp, §7.3.5, §7.5.2) and front waves (frontal.cpp, §7.4.3) both produce
// candidates and insert them through the same filter and kernel.
#pragma once

#include <cstdint>
#include <vector>

#include "edge_sampling.h"
#include "key_set.h"
#include "mesh_state.h"

namespace uvmesh::m2d::detail {

// The waves (saturation and fronts) and their scratch.
//
// Saturation: after the first wave only the triangles around the vertices the last wave inserted,
// and their neighbours, are scanned, in triangle order as the full scan goes. Every
// triangle made since the last scan has such a vertex; an edge older than that had
// its points tried and rejected, and they stay rejected (vertices are only added: the
// nearest vertex of a point, a cavity vertex, only comes closer; constrained edges
// stay). Its candidates would be the same again: they depend on its ends (fixed, with
// their metrics and boundary ratios), the field, and the two vertices opposite it
// (the bound in edge_candidates), unchanged while its two triangles are. So the points
// inserted are the same, in the same order, as with the full scan, but for a candidate
// that an anisotropic cavity refused (not star-shaped: not monotone, a later wave could
// take it) and the walk's random tie-breaks, which see fewer candidates; on surface
// faces this gave the same counts and measures, with a few coordinates differing in
// their last bits. With a uniform field the full scan took a third of the field-point
// time after the lattice (three passes over a million triangles to insert a few thousand
// points). With a varying field under a boundary gradation (every surface face), where
// the analysed-edge set does not apply, the later waves would sample every edge again,
// tens of times the first wave's samplings for a few thousand insertions.
// Fronts use the same scan set, in insertion order (front_candidates says why a triangle
// outside it needs no new look).
struct FieldPoints {
  struct Cand {
    Vec2 p;
    VertId hint;   // the edge's first vertex
    bool chained;  // follows the previous candidate on the same edge
    double r = 1;  // boundary size ratio (Options::boundary_gradation)
    // The domain component the point must fall in (a front point is computed from one
    // triangle and may land beyond a constraint or outside the domain); kNone: no check.
    std::int32_t region = kNone;
  };
  enum class Next { Wave, Done, Stop };  // after a wave: another, finished, or stopped

  explicit FieldPoints(MeshState& ms_) : ms(ms_), es(ms_) {}
  void run();
  void init_vertex_metrics();
  bool waves(void (FieldPoints::*candidates)(bool), int max_waves, int& count);
  bool saturation_waves();
  // frontal.cpp: the front waves (Options::field_points == Frontal).
  bool front_waves();
  void front_candidates(bool subset);
  bool accepted(TriId t) const;
  bool front_edge(TriId t, int i) const;
  void front_point(TriId t, int i);
  double front_ratio(VertId c, Vec2 p) const;
  void scan_set();
  void wave_candidates(bool subset);
  void edge_candidates(TriId t, int i);
  Next insert_candidates();

  MeshState& ms;
  bool from_boundary = false;  // Options::boundary_gradation applies
  bool aniso = false;          // the anisotropic cavity criterion
  bool use_analysed = false;   // edges are analysed once (analysed)
  std::vector<Cand> cands;
  EdgeSampler es;
  std::vector<VertId> born;          // the vertices the last wave inserted
  std::vector<TriId> scan;           // the triangles the next wave scans (subset)
  KeySet64 analysed;                 // edges (a << 32 | b) already analysed
  std::vector<std::uint32_t> tmark;  // scan_set: triangle marks
  std::uint32_t tepoch = 0;
  // front_candidates: triangle acceptance, computed once per wave (acc_mark == acc_epoch).
  mutable std::vector<std::uint32_t> acc_mark;
  mutable std::vector<char> acc_value;
  std::uint32_t acc_epoch = 0;
};

}  // namespace uvmesh::m2d::detail
