#!/usr/bin/env bash
# First README command: install the dependencies, build (Release), and run the main job
# on a bundled sample. Output goes to out/.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
cd "$here"
./scripts/install-deps.sh
jobs=$(nproc 2>/dev/null || echo 2)
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release
cmake --build build -j"$jobs" --target uvmesh2d
mkdir -p out
# The main job (issue 2): mesh the bundled square-with-a-hole at uniform size, write the
# mesh (Medit and Gmsh) and an SVG picture, print the JSON record.
./build/samples/uvmesh2d/uvmesh2d samples/data/square_hole.poly --size 0.02 \
  -o out/square_hole.mesh -o out/square_hole.msh -o out/square_hole.svg --json
echo "wrote out/square_hole.mesh out/square_hole.msh out/square_hole.svg"
