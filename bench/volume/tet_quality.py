#!/usr/bin/env python3
"""tet_quality.py MESH.msh -- the tetrahedra of a Gmsh 2.2 ASCII file, measured by
uvmesh.tet_quality() (the report's definitions, surface/tet_mesh.h: minimum dihedral
angle in degrees, circumradius / shortest edge; nearest-rank percentiles), so that
gmsh's mesh and uvmesh's are measured by the same code. Needs the Python module
(PYTHONPATH=<build>/python, /usr/bin/python3; run.sh sets both). Prints one JSON line:
tets, solids (distinct elementary tags of the tetrahedra), dihedral min/p01/median,
radius-edge max/p99/median."""
import json
import sys

import uvmesh


def read_msh22(path):
    """Points (1-based tags mapped to rows), tetrahedra as rows, and their elementary tags."""
    rows, points, tets, tags = {}, [], [], []
    with open(path) as f:
        lines = iter(f)
        for line in lines:
            if line.startswith("$MeshFormat"):
                if not next(lines).split()[0].startswith("2"):
                    sys.exit("tet_quality.py reads msh 2.2 only")
            elif line.startswith("$Nodes"):
                for _ in range(int(next(lines))):
                    t = next(lines).split()
                    rows[int(t[0])] = len(points)
                    points.append([float(t[1]), float(t[2]), float(t[3])])
            elif line.startswith("$Elements"):
                for _ in range(int(next(lines))):
                    t = next(lines).split()
                    if t[1] == "4":
                        ntags = int(t[2])
                        tags.append(int(t[4]) if ntags >= 2 else 0)
                        tets.append([rows[int(x)] for x in t[3 + ntags:3 + ntags + 4]])
    return points, tets, tags


def main():
    points, tets, tags = read_msh22(sys.argv[1])
    out = {"tets": len(tets), "solids": len(set(tags))}
    if tets:
        q = uvmesh.tet_quality(points, tets, tags)
        d, r = q["min_dihedral_deg"], q["radius_edge"]
        out.update({"dihedral_min": d["min"], "dihedral_p01": d["p01"],
                    "dihedral_median": d["median"], "radius_edge_max": r["max"],
                    "radius_edge_p99": r["p99"], "radius_edge_median": r["median"],
                    "inverted": q["inverted"]})
    print(json.dumps(out))


main()
