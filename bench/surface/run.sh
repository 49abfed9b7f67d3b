#!/usr/bin/env bash
# Surface meshing benchmark: `uvmesh mesh` against Gmsh (Frontal-Delaunay and Delaunay) on
# every CAD model of the shared corpus, single-threaded, all meshes graded by the same
# grader (grade_mesh.py, with its TetGen check). Writes bench/surface/results.md.
# Not part of the test suite; see bench/surface/README.md.
#
#   bench/surface/run.sh                  all ~71 models (Gmsh alone takes an hour or more:
#                                         several models time out at 150 s, twice)
#   bench/surface/run.sh --quick          the 6-model subset
#   bench/surface/run.sh --only axom_tet  one model (file name or stem; comma-separated list)
#   further flags: --gmsh-timeout S (150), --uvmesh-timeout S (600), --threads-min-s S (1.0:
#   models whose 1-thread uvmesh wall reaches this are run with --threads 2 too), --out DIR
#   (work folder, default out/bench-surface), --results FILE, --no-build, --report-only (run
#   nothing: rewrite the results from the records an earlier run left in --out)
#
# Environment: UVMESH (a uvmesh binary: nothing is built), else BUILD_DIR (default
# <repo>/build; `uvmesh` is built there, Release) and JOBS (default 2); UVMESH_SHARED_DATA,
# UVMESH_SHARED_TOOLS to point at the corpus and the reference scripts.
# Needs gmsh and tetgen (scripts/install-deps.sh).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
exec python3 "$here/summarize.py" bench "$@"
