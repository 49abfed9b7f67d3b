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
# robustness tests (bad inputs and options through both CLIs). The 3D surface mesher's
# corpus tests and the determinism test are left to the Release run: under ASan they
# would take most of CI's time. Only these targets are built; ctest runs what was built (catch2's
# discovery registers an unbuilt executable as <name>_NOT_BUILT).
san_targets=(uvmesh uvmesh2d test_mesher2d test_cli2d test_prescan test_io_units
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
# (the CLI tests run uvmesh and uvmesh2d) land in files, checked below. Leaks inside
# third-party libraries (OpenCASCADE's translator tables, nothing of ours) are listed in
# scripts/lsan-suppressions.txt; print_suppressions=0 keeps the list of what matched
# out of the logs.
asan="halt_on_error=1:abort_on_error=1:detect_leaks=1:log_path=$logs/asan"
export ASAN_OPTIONS=$asan
export LSAN_OPTIONS="suppressions=$here/scripts/lsan-suppressions.txt:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:abort_on_error=1:print_stacktrace=1:log_path=$logs/ubsan"
# The hang limit of tests/robustness for instrumented binaries: meshing the corpus'
# repairable files takes up to 80 s of CPU here (20 s with the fast unwinder).
export ROBUST_TIMEOUT=300
# The tests that run `uvmesh` on STEP and IGES files (the only ones here that reach
# OpenCASCADE's readers) record whole allocation stacks (fast_unwind_on_malloc=0), so
# that the suppressions can match: Debian's OpenCASCADE has no frame pointers and the
# fast unwinder stops inside its allocator. Only for them: it makes every allocation
# about 4 times slower. robust_determinism (byte-identical meshes of five models at 1,
# 2 and 8 threads) is left to the Release run: under these options it would take most
# of CI's time, as the surface mesher's corpus tests would.
cad_tests='^robust_(bad_inputs|bad_options)$'
status=0
(cd "$san" && ctest --output-on-failure -j"$jobs" --timeout 1200 -E "_NOT_BUILT|$cad_tests|^robust_determinism$") ||
  status=$?
(cd "$san" && ASAN_OPTIONS="$asan:fast_unwind_on_malloc=0" ctest --output-on-failure -j"$jobs" --timeout 1200 -R "$cad_tests") ||
  status=$?
if [ -n "$(ls -A "$logs")" ]; then
  echo "test.sh: sanitizer reports:" >&2
  for f in "$logs"/*; do
    echo "== $f" >&2
    head -60 "$f" >&2
  done
  status=1
fi
exit "$status"
