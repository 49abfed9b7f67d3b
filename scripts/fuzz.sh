#!/usr/bin/env bash
# Runs one libFuzzer target (tests/fuzz) for a given time:
#   scripts/fuzz.sh TARGET SECONDS [extra libFuzzer flags]
#   scripts/fuzz.sh list
# TARGET: poly_mesh2d, obj_cage, mesh_msh, mesh_medit, mesh_meshb, mesh_stl, mesh_obj,
# mesh_ply, mesh_drc (with or without the fuzz_ prefix).
# Builds with Debian's clang++ (-fsanitize=fuzzer,address,undefined) in build-fuzz/
# (UVMESH_FUZZ_BUILD overrides), one job (the machines have 2 cores). Starts from the
# committed seeds in tests/fuzz/corpus/TARGET and keeps what it learns in
# $FUZZ_CORPUS/TARGET (default build-fuzz/corpus; point it outside the worktree, e.g.
# /work/fuzz-corpus, so that a corpus and its fuzzing time survive a fresh build dir); a crash, leak, timeout (10 s per input, of wall time:
# FUZZ_TIMEOUT=SECONDS raises it when the fuzzer runs at low priority on a busy machine,
# where a starved process would report false timeouts) or out-of-memory (2 GB) leaves its
# input in build-fuzz/artifacts/TARGET/ and exits non-zero.
# FUZZ_NICE=N runs the fuzzer under `nice -n N` (shared machines).
# The last line printed is the run's CPU time (user+sys of the fuzzer process), the
# measure of how long a target really ran on a loaded machine.
# A finding becomes a named "robust: ..." test beside the component it hit (tests/<area>).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=${UVMESH_FUZZ_BUILD:-$here/build-fuzz}
targets="poly_mesh2d obj_cage mesh_msh mesh_medit mesh_meshb mesh_stl mesh_obj mesh_ply mesh_drc"
if [ "${1:-}" = list ]; then
  echo "$targets"
  exit 0
fi
if [ $# -lt 2 ]; then
  echo "usage: scripts/fuzz.sh TARGET SECONDS [libFuzzer flags] (targets: $targets)" >&2
  exit 1
fi
t=${1#fuzz_}
secs=$2
shift 2
if [[ " $targets " != *" $t "* ]]; then
  echo "fuzz.sh: unknown target '$t' (targets: $targets)" >&2
  exit 1
fi
cxx=$(command -v clang++ || command -v clang++-14 || true)
if [ -z "$cxx" ]; then
  echo "fuzz.sh: clang++ not found (scripts/install-deps.sh installs clang and libclang-rt-14-dev)" >&2
  exit 1
fi
cmake -S "$here/tests/fuzz" -B "$build" -G Ninja -DCMAKE_CXX_COMPILER="$cxx" >/dev/null
cmake --build "$build" -j1 --target "fuzz_$t"
seeds=$here/tests/fuzz/corpus/$t
work=${FUZZ_CORPUS:-$build/corpus}/$t
art=$build/artifacts/$t
mkdir -p "$work" "$art"
export ASAN_OPTIONS=${ASAN_OPTIONS:-halt_on_error=1:detect_leaks=1}
export UBSAN_OPTIONS=${UBSAN_OPTIONS:-halt_on_error=1:print_stacktrace=1}
echo "fuzz.sh: fuzz_$t for $secs s (seeds $seeds, corpus $work, artifacts $art)"
status=0
TIMEFORMAT="fuzz.sh: fuzz_$t wall %R s, CPU %U s user + %S s sys"
time nice -n "${FUZZ_NICE:-0}" "$build/fuzz_$t" "$work" "$seeds" -max_total_time="$secs" \
  -timeout="${FUZZ_TIMEOUT:-10}" -rss_limit_mb=2048 -max_len=65536 -artifact_prefix="$art/" \
  -print_final_stats=1 "$@" || status=$?
exit "$status"
