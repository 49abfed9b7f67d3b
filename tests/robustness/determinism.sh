#!/usr/bin/env bash
# Determinism of `uvmesh mesh`: the same input and options give a byte-identical output
# file across runs and for 1, 2 and 8 threads. Models with seams and poles (torus,
# sphere), many faces (bottle, nist_ctc_01), an assembly made conforming by OCC's general
# fuse, which runs in OCC's parallel mode from 2 threads (caxif_dm1_id, 7 solids), and a
# subdivision cage. The format is .msh 4.1
# ASCII with 17 significant digits, so a difference in the last bit of a coordinate shows.
# On a difference it prints the first differing line of the .msh with its section, so the
# stage (nodes: placement; elements: connectivity) is visible in the log.
#
# usage: determinism.sh UVMESH SHARED_DATA
set -uo pipefail
uvmesh=$1 data=$2
tmp=$(mktemp -d "${TMPDIR:-/tmp}/uvmesh_det.XXXXXX")
trap 'rm -rf "$tmp"' EXIT
failures=0

models=(
  cad/gmsh_torus1.brep
  cad/gmsh_full_sphere.brep
  cad/occt_bottle.brep
  cad/nist_ctc_01.stp
  cad/caxif_dm1_id.stp
  subd/catmark_torus.obj
)

# first_difference A B: "line N in section $X: <a> | <b>"
first_difference() {
  awk 'NR == FNR { a[FNR] = $0; next }
       /^\$/ { sec = $0 }
       a[FNR] != $0 { printf "line %d in %s: %.100s | %.100s\n", FNR, sec, a[FNR], $0; found = 1; exit }
       END { if (!found) print "(one file is a prefix of the other)" }' "$1" "$2"
}

for m in "${models[@]}"; do
  f=$data/$m
  if [ ! -f "$f" ]; then
    echo "FAIL: $f missing"
    failures=$((failures + 1))
    continue
  fi
  name=$(basename "$m")
  ref=""
  before=$failures
  for run in 1:a 1:b 2:a 8:a 8:b; do
    t=${run%%:*}
    out=$tmp/$name.t$t.${run##*:}.msh
    if ! "$uvmesh" mesh "$f" -o "$out" -q --threads "$t" --allow-holes 2>"$tmp/err"; then
      echo "FAIL: $name --threads $t: exit $?: $(head -3 "$tmp/err")"
      failures=$((failures + 1))
      continue
    fi
    if [ -z "$ref" ]; then
      ref=$out
    elif ! cmp -s "$ref" "$out"; then
      echo "FAIL: $name: $(basename "$out") differs from $(basename "$ref"): $(first_difference "$ref" "$out")"
      failures=$((failures + 1))
    fi
  done
  if [ -n "$ref" ] && [ "$failures" -eq "$before" ]; then
    echo "$name: $(wc -l <"$ref") lines, identical across runs and 1/2/8 threads"
  fi
done

echo "determinism: ${#models[@]} models, $failures failure(s)"
[ "$failures" -eq 0 ]
