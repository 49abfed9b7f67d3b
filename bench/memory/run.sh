#!/usr/bin/env bash
# Memory benchmark (issue 7): peak resident memory of `uvmesh mesh` per million output
# triangles, measured with /usr/bin/time -v ("Maximum resident set size"), on the largest
# corpus models at default sizes and on one run of about 5 million triangles. Goal: at
# most 300 MB per million triangles. Also reports the peak of `uvmesh info` on the same
# model (reading and healing alone), so that the part that grows with the mesh shows.
# Writes bench/memory/results.md.
#
# Environment: UVMESH (a built uvmesh; default: build it in BUILD_DIR, default
# build-bench-mem), THREADS (default 2), BIG_MODEL and BIG_HMAX_REL (the ~5M-triangle run;
# default nist_ctc_02.stp at 0.0009 of the diagonal).
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/../.." && pwd)
data=${UVMESH_SHARED_DATA:-$root/../shared/data}
[ -f "$data/MANIFEST.tsv" ] || { echo "bench/memory: no corpus at $data (set UVMESH_SHARED_DATA)" >&2; exit 1; }
threads=${THREADS:-2}
uvmesh=${UVMESH:-}
if [ -z "$uvmesh" ]; then
  build=${BUILD_DIR:-$root/build-bench-mem}
  cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$build" -j"$threads" --target uvmesh >/dev/null
  uvmesh=$build/samples/uvmesh/uvmesh
fi
big_model=${BIG_MODEL:-$data/cad/nist_ctc_02.stp}
big_hrel=${BIG_HMAX_REL:-0.0009}

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# peak_kb CMD...: runs CMD under /usr/bin/time -v; prints the peak RSS in kB; the
# command's stderr is kept in $work/err.
peak_kb() {
  /usr/bin/time -v -o "$work/time" "$@" >/dev/null 2>"$work/err" || true
  awk -F: '/Maximum resident set size/ { gsub(/ /, "", $2); print $2 }' "$work/time"
}

rows=()
# measure LABEL MODEL [mesh options]
measure() {
  local label=$1 model=$2
  shift 2
  local info_kb mesh_kb tris wall cpu
  info_kb=$(peak_kb "$uvmesh" info "$model")
  mesh_kb=$(peak_kb "$uvmesh" mesh "$model" -o "$work/out.msh" --binary --threads "$threads" --allow-holes "$@")
  # "uvmesh: FILE: P points, T triangles, F/F faces meshed in S s"
  tris=$(sed -n 's/.* points, \([0-9]*\) triangles,.*/\1/p' "$work/err" | tail -1)
  wall=$(awk -F': ' '/Elapsed \(wall clock\)/ { print $2 }' "$work/time")
  cpu=$(awk -F': ' '/User time|System time/ { s += $2 } END { printf "%.1f", s }' "$work/time")
  if [ -z "$tris" ] || [ "$tris" -eq 0 ]; then
    echo "bench/memory: $label: no triangle count: $(tail -2 "$work/err")" >&2
    return
  fi
  local row
  row=$(awk -v l="$label" -v o="$*" -v t="$tris" -v m="$mesh_kb" -v i="$info_kb" -v w="$wall" -v c="$cpu" 'BEGIN {
    mb = m / 1024; ib = i / 1024; mt = t / 1e6;
    printf "| %s | %s | %.3f | %.0f | %.0f | %.0f | %.0f | %s | %s |", l, (o == "" ? "defaults" : o), mt, mb, ib, mb / mt, (mb - ib) / mt, c, w }')
  echo "$row"
  rows+=("$row")
  rm -f "$work/out.msh"
}

# The corpus models with the most triangles at default sizes (a corpus run at 2234b04:
# 1.80 M, 276 k, 261 k, 246 k, 236 k, 210 k), not the largest files: occt_terrain and
# gmsh_dlr_f6 are large files that give small meshes. MODELS overrides the list.
models=${MODELS:-occt_solidworks_assy.stp nist_ctc_02.stp nist_ftc_10.stp occt_sink.brep occt_motor.brep occt_r0901.stp}
for m in $models; do
  [ -f "$data/cad/$m" ] && measure "$m" "$data/cad/$m"
done
measure "$(basename "$big_model") (~5M)" "$big_model" --hmax-rel "$big_hrel"

{
  echo "# Peak memory per million triangles"
  echo
  echo "Produced by \`bench/memory/run.sh\` on $(date -u +%Y-%m-%d) ($(nproc) cores, shared machine,"
  echo "--threads $threads, output .msh 4.1 binary). Peak RSS from \`/usr/bin/time -v\`; 'info' is the"
  echo "peak of \`uvmesh info\` on the same file (read, heal, check: the part that does not grow"
  echo "with the mesh). Goal (issue 7): at most 300 MB per million triangles."
  echo
  echo "| model | options | M triangles | peak MB | info MB | MB / M tri | (peak - info) MB / M tri | CPU s | wall |"
  echo "|---|---|---:|---:|---:|---:|---:|---:|---:|"
  for r in "${rows[@]}"; do echo "$r"; done
} >"$here/results.md.new"
mv "$here/results.md.new" "$here/results.md"
echo "bench/memory: wrote $here/results.md"
