#!/usr/bin/env bash
# Volume meshing benchmark (issue 24): `uvmesh mesh --volume` (Netgen's nglib filling our
# surface mesh) against `gmsh -3` from the same CAD file with the same largest size, on
# closed solids of the shared corpus. Writes bench/volume/results.md. Not a test.
#
#   bench/volume/run.sh                 the default models below
#   bench/volume/run.sh a.step b.brep   these corpus files (names under $DATA/cad)
#
# Size: hmax = D/20 (D = bounding-box diagonal, as uvmesh computes it; --hmax-rel 0.05);
# gmsh gets the same absolute value (read from uvmesh's report) as -clmax, and 20 elements
# per 2 pi of curvature (uvmesh's default --angle 18); gmsh reads STEP/IGES in mm, so the
# value is converted from the file's unit (uvmesh's report) for those. Both single-threaded (gmsh -nt 1,
# uvmesh --threads 1). Times are wall-clock of the whole process (read + surface + volume +
# write). Quality of both meshes is measured by tet_quality.py (the definitions of
# surface/tet_mesh.h) from .msh 2.2 files; the uvmesh column's figures also appear in its
# own report. Environment: UVMESH (binary, default <repo>/build/samples/uvmesh/uvmesh),
# DATA (default /work/shared/data), TIMEOUT (seconds per run, default 600).
set -uo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)"
root="$(cd "$here/../.." && pwd)"
uvmesh="${UVMESH:-$root/build/samples/uvmesh/uvmesh}"
data="${DATA:-/work/shared/data}"
timeout="${TIMEOUT:-600}"
models=("$@")
[ ${#models[@]} -eq 0 ] && models=(axom_tet.step dagmc_two_cubes.stp occt_bottle.brep
  gmsh_cube_fillet.stp nist_ctc_01.stp caxif_io1_cm.stp gmsh_mambo.step occt_crankarm.brep)
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT

now() { date +%s.%N; }
rows=()
for m in "${models[@]}"; do
  f="$data/cad/$m"
  [ -f "$f" ] || { echo "missing $f" >&2; continue; }
  echo "== $m" >&2
  t0=$(now)
  timeout "$timeout" "$uvmesh" mesh "$f" -o "$work/u.msh" --format msh22 --volume --hmax-rel 0.05 \
    --threads 1 --no-selfint -q --report "$work/u.json" 2>"$work/u.err"
  urc=$?
  t1=$(now)
  ut=$(echo "$t1 - $t0" | bc)
  nsolids=$(python3 -c "import json;j=json.load(open('$work/u.json'));print(len(j['topology'].get('solids',[])))" 2>/dev/null || echo "?")
  h=$(python3 -c "import json;print(json.load(open('$work/u.json'))['size']['hmax'])" 2>/dev/null || echo "")
  # gmsh's OCC reader converts STEP and IGES lengths to mm; uvmesh keeps the file's unit.
  hg="$h"
  case "$m" in
    *.brep) ;;
    *) hg=$(python3 -c "import json;u=json.load(open('$work/u.json')).get('units','');print($h*{'mm':1,'cm':10,'m':1000,'in':25.4,'inch':25.4,'ft':304.8,'um':1e-3}.get(u,1))" 2>/dev/null || echo "$h") ;;
  esac
  uq=$( [ -f "$work/u.msh" ] && python3 "$here/tet_quality.py" "$work/u.msh" || echo '{}')
  rm -f "$work/g.msh"
  t0=$(now)
  timeout "$timeout" gmsh "$f" -3 -nt 1 -clmax "$hg" -setnumber Mesh.MeshSizeFromCurvature 20 \
    -format msh22 -o "$work/g.msh" >"$work/g.log" 2>&1
  grc=$?
  t1=$(now)
  gt=$(echo "$t1 - $t0" | bc)
  gq=$( [ -f "$work/g.msh" ] && [ $grc -eq 0 ] && python3 "$here/tet_quality.py" "$work/g.msh" || echo '{}')
  rows+=("$(python3 - "$m" "$nsolids" "$h" "$urc" "$ut" "$uq" "$grc" "$gt" "$gq" <<'PY'
import json, sys
m, ns, h, urc, ut, uq, grc, gt, gq = sys.argv[1:]
uq, gq = json.loads(uq), json.loads(gq)
def cell(q, rc, t):
    if not q.get("tets"):
        return ["failed (exit %s)" % rc, "%.1f" % float(t), "-", "-", "-"]
    return ["%d/%s%s" % (q["solids"], ns, "" if rc == "0" else " (exit %s)" % rc), "%.1f" % float(t),
            str(q["tets"]), "%.1f / %.1f" % (q["dihedral_min"], q["dihedral_p01"]),
            "%.2f / %.2f" % (q["radius_edge_max"], q["radius_edge_p99"])]
hh = "%.3g" % float(h) if h else "?"
print("| " + " | ".join([m, hh] + cell(uq, urc, ut) + cell(gq, grc, gt)) + " |")
PY
)")
done

{
  echo "<!-- written by bench/volume/run.sh on $(date -u +%Y-%m-%dT%H:%MZ), commit $(git -C "$root" rev-parse --short HEAD 2>/dev/null || echo unknown) -->"
  echo "# Volume meshing: uvmesh --volume (Netgen nglib) vs gmsh -3"
  echo
  echo "hmax = D/20 for both (gmsh: -clmax, 20 elements per 2 pi of curvature), single thread, wall time of the whole process."
  echo "Solids: regions with tetrahedra / solids in the model. Dihedral: minimum dihedral angle in degrees, min / p01."
  echo "Radius-edge: circumradius / shortest edge, max / p99 (0.61 for the regular tetrahedron)."
  echo
  echo "| model | hmax | uvmesh solids | uvmesh s | uvmesh tets | uvmesh dihedral | uvmesh radius-edge | gmsh solids | gmsh s | gmsh tets | gmsh dihedral | gmsh radius-edge |"
  echo "|---|---|---|---|---|---|---|---|---|---|---|---|"
  printf '%s\n' "${rows[@]}"
} > "$here/results.md"
cat "$here/results.md"
