#!/usr/bin/env python3
"""tet_quality.py MESH.msh -- tetrahedra of a Gmsh 2.2 ASCII file: count, solids (distinct
elementary tags of the tetrahedra), and the two measures of surface/tet_mesh.h (minimum
dihedral angle in degrees, circumradius / shortest edge) as min/p01/median and
max/p99/median (nearest rank). Used by run.sh for gmsh's output, and for uvmesh's to check
that it agrees with uvmesh's own report. Prints one JSON line."""
import json
import math
import sys


def sub(a, b):
    return (a[0] - b[0], a[1] - b[1], a[2] - b[2])


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]


def norm(a):
    return math.sqrt(dot(a, a))


def min_dihedral(p):
    n = []
    for k in range(4):
        u, v, w = p[(k + 1) % 4], p[(k + 2) % 4], p[(k + 3) % 4]
        nk = cross(sub(v, u), sub(w, u))
        if dot(nk, sub(p[k], u)) > 0:
            nk = (-nk[0], -nk[1], -nk[2])
        ln = norm(nk)
        if ln == 0:
            return 0.0
        n.append((nk[0] / ln, nk[1] / ln, nk[2] / ln))
    best = math.pi
    for k in range(4):
        for m in range(k + 1, 4):
            best = min(best, math.pi - math.acos(max(-1.0, min(1.0, dot(n[k], n[m])))))
    return math.degrees(best)


def radius_edge(p):
    a, b, c, d = p
    u, v, w = sub(a, d), sub(b, d), sub(c, d)
    det = dot(u, cross(v, w))
    if det == 0:
        return math.inf
    cvw, cwu, cuv = cross(v, w), cross(w, u), cross(u, v)
    uu, vv, ww = dot(u, u), dot(v, v), dot(w, w)
    num = tuple(uu * cvw[i] + vv * cwu[i] + ww * cuv[i] for i in range(3))
    r = norm(num) / (2 * abs(det))
    e = min(norm(sub(x, y)) for i, x in enumerate(p) for y in p[i + 1:])
    return r / e if e > 0 else math.inf


def rank(s, share):
    k = max(1, min(len(s), math.ceil(share * len(s))))
    return s[k - 1]


def main():
    nodes, tets, solids = {}, [], set()
    with open(sys.argv[1]) as f:
        lines = iter(f)
        for line in lines:
            if line.startswith("$MeshFormat"):
                ver = next(lines).split()[0]
                if not ver.startswith("2"):
                    sys.exit("tet_quality.py reads msh 2.2 only")
            elif line.startswith("$Nodes"):
                for _ in range(int(next(lines))):
                    t = next(lines).split()
                    nodes[int(t[0])] = (float(t[1]), float(t[2]), float(t[3]))
            elif line.startswith("$Elements"):
                for _ in range(int(next(lines))):
                    t = next(lines).split()
                    if t[1] == "4":
                        ntags = int(t[2])
                        solids.add(int(t[4]) if ntags >= 2 else 0)
                        tets.append([int(x) for x in t[3 + ntags:3 + ntags + 4]])
    dih, re_ = [], []
    for t in tets:
        p = [nodes[i] for i in t]
        dih.append(min_dihedral(p))
        re_.append(radius_edge(p))
    dih.sort()
    re_.sort()
    out = {"tets": len(tets), "solids": len(solids)}
    if tets:
        out.update({"dihedral_min": dih[0], "dihedral_p01": rank(dih, 0.01),
                    "dihedral_median": rank(dih, 0.5), "radius_edge_max": re_[-1],
                    "radius_edge_p99": -rank([-x for x in reversed(re_)], 0.01),
                    "radius_edge_median": rank(re_, 0.5)})
    print(json.dumps(out))


main()
