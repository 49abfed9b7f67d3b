#!/usr/bin/env bash
# Configures, builds and runs the mesher2d comparison benchmark, writes the table to
# bench/results.md and prints it. Not part of the test suite.
#
#   bench/run.sh            full sizes (1e5..4e6 points, 1e5 and 1e6 triangles; about 20-30
#                           minutes on a loaded 2-core machine)
#   bench/run.sh --quick    small sizes only (smoke run, well under a minute)
#   bench/run.sh --only iso --reps 1 ...   any other bench_mesher2d flags pass through
#
# Environment: BUILD_DIR (default <repo>/build-bench), JOBS (default 2),
# RESULTS (default bench/results.md).
# Needs the Debian packages listed in scripts/install-deps.sh (libcgal-dev, gmsh, freefem++).
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/.." && pwd)"
build="${BUILD_DIR:-$root/build-bench}"
jobs="${JOBS:-2}"
results="${RESULTS:-$here/results.md}"

cmake -S "$root" -B "$build" -DCMAKE_BUILD_TYPE=Release -DUVMESH_BUILD_BENCH=ON -DUVMESH_BUILD_CAD=OFF \
  -DUVMESH_BUILD_TESTS=OFF >/dev/null
cmake --build "$build" -j"$jobs" --target bench_mesher2d

tmp="$(mktemp)"
trap 'rm -f "$tmp"' EXIT
# Progress goes to stderr; the table (stdout) is kept.
"$build/bench/bench_mesher2d" --out "$tmp" "$@" >/dev/null
{
  echo "<!-- written by bench/run.sh ${*:-(full run)} on $(date -u +%Y-%m-%dT%H:%MZ), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown) (working tree may differ) -->"
  cat "$tmp"
} >"$results"
cat "$results"
echo
echo "run.sh: table written to $results"
