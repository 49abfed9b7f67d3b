#!/usr/bin/env bash
# Volume meshing benchmark (issue 24): `uvmesh mesh --volume` (Netgen's nglib filling our
# surface mesh) against `gmsh -3` from the same CAD file with the same largest size, on
# the closed solids of the shared corpus. Writes bench/volume/results.md. Not a test.
#
#   bench/volume/run.sh                 every corpus model with a solid (MANIFEST.tsv)
#   bench/volume/run.sh a.step b.brep   these corpus files (names under $DATA/cad)
#
# Size: hmax = D/20 (D = bounding-box diagonal, as uvmesh computes it; --hmax-rel 0.05);
# gmsh gets the same absolute value (read from uvmesh's report) as -clmax, and 20 elements
# per 2 pi of curvature (uvmesh's default --angle 18); gmsh reads STEP/IGES in mm, so the
# value is converted from the file's unit (uvmesh's report) for those. Both single-threaded
# (gmsh -nt 1, uvmesh --threads 1). Times are wall-clock of the whole process (read +
# surface + volume + write); a model's two runs follow each other, JOBS models run at once
# (default 1; with 2 on 2 cores each process still has a core, but memory bandwidth is
# shared: compare the two tools within a row). Quality of both meshes is measured by
# tet_quality.py through uvmesh.tet_quality() (the report's definitions) from .msh 2.2
# files. Environment: UVMESH (binary, default <repo>/build/samples/uvmesh/uvmesh), PYMOD
# (the Python module's folder, default <repo>/build/python), DATA (default
# /work/shared/data), TIMEOUT (seconds per run, default 600), JOBS.
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
uvmesh="${UVMESH:-$root/build/samples/uvmesh/uvmesh}"
export PYTHONPATH="${PYMOD:-$root/build/python}"
py=/usr/bin/python3
data="${DATA:-/work/shared/data}"
timeout="${TIMEOUT:-600}"
jobs="${JOBS:-1}"
models=("$@")
if [ ${#models[@]} -eq 0 ]; then
  mapfile -t models < <(awk -F'\t' 'NR > 1 && $1 ~ /^cad\// && $9 > 0 { sub(/^cad\//, "", $1); print $1 }' \
    "$data/MANIFEST.tsv")
fi
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

now() { date +%s.%N; }
one_model() {
  local m=$1 w=$work/$2 f t0 t1 urc ut nsolids h hg uq grc gt gq
  mkdir -p "$w"
  local f="$data/cad/$m"
  [ -f "$f" ] || { echo "missing $f" >&2; return; }
  echo "== $m" >&2
  t0=$(now)
  timeout "$timeout" "$uvmesh" mesh "$f" -o "$w/u.msh" --format msh22 --volume --hmax-rel 0.05 \
    --threads 1 --no-selfint -q --report "$w/u.json" 2>"$w/u.err"
  urc=$?
  t1=$(now)
  ut=$(echo "$t1 - $t0" | bc)
  nsolids=$($py -c "import json;j=json.load(open('$w/u.json'));print(len(j['topology'].get('solids',[])))" 2>/dev/null || echo "?")
  h=$($py -c "import json;print(json.load(open('$w/u.json'))['size']['hmax'])" 2>/dev/null || echo "")
  # gmsh's OCC reader converts STEP and IGES lengths to mm; uvmesh keeps the file's unit.
  hg="$h"
  case "$m" in
    *.brep) ;;
    *) hg=$($py -c "import json;u=json.load(open('$w/u.json')).get('units','');print($h*{'mm':1,'cm':10,'m':1000,'in':25.4,'inch':25.4,'ft':304.8,'um':1e-3}.get(u,1))" 2>/dev/null || echo "$h") ;;
  esac
  uq=$( [ -f "$w/u.msh" ] && $py "$here/tet_quality.py" "$w/u.msh" || echo '{}')
  rm -f "$w/g.msh"
  t0=$(now)
  timeout "$timeout" gmsh "$f" -3 -nt 1 -clmax "$hg" -setnumber Mesh.MeshSizeFromCurvature 20 \
    -format msh22 -o "$w/g.msh" >"$w/g.log" 2>&1
  grc=$?
  t1=$(now)
  gt=$(echo "$t1 - $t0" | bc)
  gq=$( [ -f "$w/g.msh" ] && [ $grc -eq 0 ] && $py "$here/tet_quality.py" "$w/g.msh" || echo '{}')
  # One JSON line per model: the table and the summary are made from these at the end.
  $py -c 'import json,sys; m,ns,h,urc,ut,uq,grc,gt,gq=sys.argv[1:]; print(json.dumps(dict(
      model=m, solids=ns, hmax=h, u_rc=int(urc), u_s=float(ut), u=json.loads(uq), g_rc=int(grc),
      g_s=float(gt), g=json.loads(gq))))' "$m" "$nsolids" "$h" "$urc" "$ut" "$uq" "$grc" "$gt" "$gq" >"$w/row.json"
}

# JOBS models at once, each as a numbered job; rows are gathered in the models' order.
i=0
for m in "${models[@]}"; do
  while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  one_model "$m" "$i" &
  i=$((i + 1))
done
wait
for ((k = 0; k < i; k++)); do cat "$work/$k/row.json" 2>/dev/null; done >"$work/rows.jsonl"

{
  echo "<!-- written by bench/volume/run.sh on $(date -u +%Y-%m-%dT%H:%MZ), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown), JOBS=$jobs, TIMEOUT=$timeout -->"
  "$py" "$here/table.py" "$work/rows.jsonl"
} >"$here/results.md"
cat "$here/results.md"
