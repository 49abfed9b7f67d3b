#!/usr/bin/env bash
# Second README command: build everything (Release) and run the whole test suite.
#   scripts/test.sh [--sanitize] [ctest arguments, e.g. -R mesher2d]
# --sanitize (CI): afterwards, build a subset of the suite once more with
# UVMESH_SANITIZE=address,undefined in build-san and run it; any sanitizer report fails.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
sanitize=0
if [ "${1:-}" = --sanitize ]; then
  sanitize=1
  shift
fi
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
(cd build && ctest --output-on-failure -j"$jobs" --timeout 1200 "$@")
[ "$sanitize" -eq 1 ] || exit 0

# The sanitizer subset: the 2D mesher, uvmesh2d and its readers, the mesh readers and
# writers, the OBJ cage reader and OpenSubdiv back end, the size fields, and the
# robustness tests (bad inputs and options through both CLIs, determinism). The 3D
# surface mesher's corpus tests are left to the Release run: under ASan they would take
# most of CI's time. Only these targets are built; ctest runs what was built (catch2's
# discovery registers an unbuilt executable as <name>_NOT_BUILT).
san_targets=(uvmesh uvmesh2d test_mesher2d test_cli2d test_robust_regressions test_prescan test_io_units
             test_mesh_formats test_param)
grep -q "UVMESH_HAVE_OSD:INTERNAL=ON" build/CMakeCache.txt && san_targets+=(test_geom_subd)
san=$here/build-san
cmake -S . -B "$san" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DUVMESH_SANITIZE=address,undefined
cmake --build "$san" -j"$jobs" --target "${san_targets[@]}"
logs=$san/sanitizer-logs
rm -rf "$logs"
mkdir -p "$logs"
# abort_on_error: a report kills the process with SIGABRT, which every test sees as a
# crash, even one that expects a non-zero exit. log_path: the reports of child processes
# (the CLI tests run uvmesh and uvmesh2d) land in files, checked below.
export ASAN_OPTIONS="halt_on_error=1:abort_on_error=1:detect_leaks=1:log_path=$logs/asan"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1:log_path=$logs/ubsan"
export ROBUST_TIMEOUT=60  # the hang limit of tests/robustness, for instrumented binaries
status=0
(cd "$san" && ctest --output-on-failure -j"$jobs" --timeout 1200 -E _NOT_BUILT) || status=$?
if [ -n "$(ls -A "$logs")" ]; then
  echo "test.sh: sanitizer reports:" >&2
  for f in "$logs"/*; do
    echo "== $f" >&2
    head -60 "$f" >&2
  done
  status=1
fi
exit "$status"
