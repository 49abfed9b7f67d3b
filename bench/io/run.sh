#!/usr/bin/env bash
# Mesh-format benchmark: meshes one corpus model finely with `uvmesh mesh` (a few hundred
# thousand triangles), then bench_io writes it in every format (write time, size) and with
# Draco at 11, 14 and 16 bits (ratio against binary STL and PLY, largest position error).
# Writes bench/io/results.md. Environment: MODEL (default nist_ctc_02.stp from the shared
# corpus), HMAX_REL (default 0.004), BUILD_DIR (default build-bench-io), JOBS (default 2).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=""
for c in "$root/../shared/data" "${UVMESH_SHARED_DATA:-}" /work/shared/data; do
  if [ -n "$c" ] && [ -f "$c/MANIFEST.tsv" ]; then data=$c; break; fi
done
[ -n "$data" ] || { echo "bench/io: the shared corpus is not found" >&2; exit 1; }
model=${MODEL:-$data/cad/nist_ctc_02.stp}
hrel=${HMAX_REL:-0.004}
build=${BUILD_DIR:-$root/build-bench-io}
jobs=${JOBS:-2}

cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DUVMESH_BUILD_BENCH=ON >/dev/null
cmake --build "$build" -j"$jobs" --target uvmesh bench_io >/dev/null

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/samples/uvmesh/uvmesh" mesh "$model" -o "$work/big.msh" --binary --hmax-rel "$hrel" \
  --threads "$jobs" --allow-holes -q
{
  echo "# Mesh formats: write time, size, Draco"
  echo
  echo "Produced by \`bench/io/run.sh\` on $(date -u +%Y-%m-%d) ($(nproc) cores, shared machine):"
  echo "\`uvmesh mesh $(basename "$model") --hmax-rel $hrel\`, written by \`bench_io\` (bench/io/bench_io.cpp) with the model"
  echo "(so .msh carries entities and physical groups, .glb one mesh per solid)."
  echo
  "$build/bench/io/bench_io" "$work/big.msh" --model "$model" --dir "$work/out"
  echo
  echo "Notes: write times are one thread, to a temporary directory (page cache), atomic (temporary"
  echo "file renamed); ASCII numbers are the shortest round-trip form (std::to_chars), so ASCII"
  echo "files keep every bit of the coordinates while binary STL keeps floats only. Draco's time is"
  echo "its encoder (edgebreaker, parallelogram prediction); vertices are split per CAD face (own"
  echo "normals), and quantization is on the largest extent of the mesh (.drc) or of each solid (.glb)."
  echo "Points closer than one quantization step merge when decoded (the columns 'points merged' and"
  echo "'triangles collapsed'): a lossy format for viewing, not for seeding a volume mesher."
} > "$here/results.md.tmp"
mv "$here/results.md.tmp" "$here/results.md"
echo "wrote $here/results.md"
