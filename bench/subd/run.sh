#!/usr/bin/env bash
# Builds bench_subd and runs it on every cage of ../shared/data/subd (one thread), writing
# the markdown table to BUILD_DIR/bench_subd_results.table (bench/subd/results.md quotes it).
# Usage: bench/subd/run.sh [BUILD_DIR] [--hmax-rel R]
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=${1:-$here/build-bench}
shift || true
data=${UVMESH_SHARED_DATA:-$here/../shared/data}
[ -d "$data/subd" ] || data=/work/shared/data
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DUVMESH_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j2 --target bench_subd
"$build/bench/subd/bench_subd" "$data"/subd/*.obj --threads 1 "$@" | tee "$build/bench_subd_results.table"
