#!/usr/bin/env python3
"""Open 2D meshes with the reference readers and print what they see, as JSON.

    mesh_counts.py FILE...     (.mesh and .msh)

For every file: meshio's point count, triangle and line counts and the sums of the cell
references (medit:ref / gmsh:physical), and gmsh's (python API) node, triangle and line
counts. Used by tests/cli2d/test_crosscheck.cpp to compare with what uvmesh2d wrote.
"""
import json
import sys

import gmsh
import meshio


def meshio_counts(path):
    m = meshio.read(path)
    r = {"points": int(len(m.points)), "triangle": 0, "line": 0, "triangle_ref_sum": 0, "line_ref_sum": 0}
    key = "medit:ref" if path.endswith(".mesh") else "gmsh:physical"
    refs = m.cell_data.get(key)
    for i, block in enumerate(m.cells):
        if block.type in ("triangle", "line"):
            r[block.type] += int(len(block.data))
            if refs is not None:
                r[block.type + "_ref_sum"] += int(sum(int(v) for v in refs[i]))
    return r


def gmsh_counts(path):
    gmsh.open(path)
    tags, _, _ = gmsh.model.mesh.getNodes()
    r = {"nodes": int(len(tags)), "triangle": 0, "line": 0}
    types, etags, _ = gmsh.model.mesh.getElements()
    for t, e in zip(types, etags):
        if t == 2:
            r["triangle"] += int(len(e))
        elif t == 1:
            r["line"] += int(len(e))
    gmsh.clear()
    return r


def main():
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    out = {}
    for path in sys.argv[1:]:
        out[path] = {"meshio": meshio_counts(path), "gmsh": gmsh_counts(path)}
    gmsh.finalize()
    print(json.dumps(out))


if __name__ == "__main__":
    main()
