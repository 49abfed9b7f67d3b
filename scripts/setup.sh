#!/usr/bin/env bash
# First README command: install the dependencies, build (Release), and run the main job
# on a bundled sample. Output goes to out/.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
./scripts/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
targets=(uvmesh2d uvmesh)
# The Python module (samples/python), when its CMake found pybind11 and OpenCASCADE.
grep -q '^build uvmesh_python:' build/build.ninja && targets+=(uvmesh_python)
cmake --build build -j"$jobs" --target "${targets[@]}"
mkdir -p out
# The main job: mesh the bundled L-bracket (STEP AP214, mm; made by samples/make_bracket)
# with the default sizes, write the mesh (Gmsh 4.1) and its JSON report.
./build/samples/uvmesh/uvmesh mesh samples/data/bracket.step -o out/bracket.msh --report out/bracket.json
echo "wrote out/bracket.msh out/bracket.json"
