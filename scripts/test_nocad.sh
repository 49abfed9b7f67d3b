#!/usr/bin/env bash
# The build without OpenCASCADE (UVMESH_BUILD_CAD=OFF): configures, builds and runs the
# tests that remain (2D mesher, uvmesh2d, size fields, subdivision surfaces, mesh formats),
# in build-nocad/. Run by CI after scripts/test.sh.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build-nocad -G Ninja -DCMAKE_BUILD_TYPE=Release -DUVMESH_BUILD_CAD=OFF
cmake --build build-nocad -j"$jobs"
(cd build-nocad && ctest --output-on-failure -j"$jobs" --timeout 1200 "$@")
