#!/usr/bin/env bash
# Acceptance of `uvmesh mesh` over the whole shared corpus (every model in
# <shared data>/cad), twice: (a) default options, (b) --hmax D/40 --angle 30 (D = bounding-box
# diagonal from `uvmesh info --json`). A model passes when, in both runs:
#   - uvmesh exits 0 with every face meshed and writes .msh .mesh .stl .obj .vtk and --report
#     (one run a format while `mesh` takes a single -o);
#   - for closed solids: 0 free edges, and 0 non-manifold edges where the CAD model has none
#     (from the report and, on mesh.msh, from grade_mesh.py; for an assembly of two or more
#     solids, made conforming, each solid on its own: the report's topology.solids), and
#     TetGen (-pY) fills it (the whole mesh.msh; each closed solid's own triangles when the
#     file also holds sheets or open shells);
#   - 0 self-intersections: of the whole mesh when every face is on a closed solid or the
#     model has no solid; else of the triangles on closed solids (a stray sheet crossing a
#     solid is the file's, and is reported apart, with how many pairs the CAD shares);
#   - chordal max <= its tolerance (when one is set); unit-edge share >= 0.9;
#     share of triangles with Q < 1.5 >= 0.95; no triangle with Q >= 3 touching no model vertex;
#   - meshio reads every output file, and gmsh every one it has a reader for (not .obj),
#     each with the triangle count its run reported (for .stl: less the triangles Gmsh says
#     its tolerance weld made degenerate, when the file's own triangles are all proper).
# Prints one PASS/FAIL line per model with the reasons, then a summary; exits 1 when a
# model fails, 2 when nothing could be checked (e.g. "uvmesh mesh: not available").
#
#   scripts/corpus.sh [--jobs N] [--only NAME[,NAME...]] [--out DIR] [--timeout S] [--no-build]
#
# Outputs go to out/corpus/<model>/{a,b}/ (git-ignored). Environment as bench/surface/run.sh:
# UVMESH (a binary; nothing built) or BUILD_DIR / JOBS; UVMESH_SHARED_DATA, UVMESH_SHARED_TOOLS.
# Field names of the report and thresholds: bench/surface/summarize.py (tables at the top).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
exec python3 "$root/bench/surface/summarize.py" corpus "$@"
