#!/usr/bin/env python3
"""table.py ROWS.jsonl -- the Markdown table and summary of bench/volume/run.sh from its
one-JSON-line-per-model rows (model, solids, hmax, u_rc/u_s/u and g_rc/g_s/g: exit code,
wall seconds and tet_quality.py's measures of uvmesh's and gmsh's mesh)."""
import json
import statistics
import sys

rows = [json.loads(line) for line in open(sys.argv[1]) if line.strip()]


def filled(q):
    return bool(q.get("tets"))


def cell(q, rc, t, ns):
    if not filled(q):
        why = "timeout" if rc == 124 else "exit %d" % rc
        return ["failed (%s)" % why, "%.1f" % t, "-", "-", "-"]
    return ["%d/%s%s" % (q["solids"], ns, "" if rc == 0 else " (exit %d)" % rc), "%.1f" % t,
            str(q["tets"]), "%.1f / %.1f" % (q["dihedral_min"], q["dihedral_p01"]),
            "%.2f / %.2f" % (q["radius_edge_max"], q["radius_edge_p99"])]


print("# Volume meshing: uvmesh --volume (Netgen nglib) vs gmsh -3")
print()
print("hmax = D/20 for both (gmsh: -clmax, 20 elements per 2 pi of curvature), single thread, "
      "wall time of the whole process.")
print("Solids: regions with tetrahedra / solids in the model. Dihedral: minimum dihedral angle "
      "in degrees, min / p01.")
print("Radius-edge: circumradius / shortest edge, max / p99 (0.61 for the regular tetrahedron).")
print()
print("| model | hmax | uvmesh solids | uvmesh s | uvmesh tets | uvmesh dihedral | uvmesh radius-edge "
      "| gmsh solids | gmsh s | gmsh tets | gmsh dihedral | gmsh radius-edge |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|")
for r in rows:
    h = "%.3g" % float(r["hmax"]) if r["hmax"] else "?"
    print("| " + " | ".join([r["model"], h] + cell(r["u"], r["u_rc"], r["u_s"], r["solids"]) +
                            cell(r["g"], r["g_rc"], r["g_s"], r["solids"])) + " |")

both = [r for r in rows if filled(r["u"]) and filled(r["g"])]
print()
print("Summary over %d models with a solid:" % len(rows))
print()
print("| | uvmesh | gmsh |")
print("|---|---|---|")
for label, key in (("models with every solid filled", "all"), ("models with no tetrahedra", "none")):
    def count(side):
        if key == "none":
            return sum(1 for r in rows if not filled(r[side]))
        return sum(1 for r in rows if filled(r[side]) and str(r[side]["solids"]) == str(r["solids"])
                   and r[side[0] + "_rc"] == 0)
    print("| %s | %d | %d |" % (label, count("u"), count("g")))
if both:
    def med(side, key):
        return statistics.median(r[side][key] for r in both)
    print("| median of the minimum dihedral (models both filled, %d) | %.1f | %.1f |" % (
        len(both), med("u", "dihedral_min"), med("g", "dihedral_min")))
    print("| median of the dihedral p01 | %.1f | %.1f |" % (med("u", "dihedral_p01"),
                                                          med("g", "dihedral_p01")))
    print("| median of the radius-edge max | %.2f | %.2f |" % (med("u", "radius_edge_max"),
                                                             med("g", "radius_edge_max")))
    ratios = sorted(r["u_s"] / r["g_s"] for r in both if r["g_s"] > 0)
    print("| time ratio uvmesh / gmsh, median [min, max] | %.2f [%.2f, %.2f] | 1 |" % (
        statistics.median(ratios), ratios[0], ratios[-1]))
    tr = sorted(r["u"]["tets"] / r["g"]["tets"] for r in both)
    print("| tetrahedra ratio uvmesh / gmsh, median [min, max] | %.2f [%.2f, %.2f] | 1 |" % (
        statistics.median(tr), tr[0], tr[-1]))
