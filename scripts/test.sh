#!/usr/bin/env bash
# Second README command: build everything (Release) and run the whole test suite.
# Extra arguments go to ctest (e.g. -R mesher2d).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs"
cd build
ctest --output-on-failure -j"$jobs" --timeout 1200 "$@"
