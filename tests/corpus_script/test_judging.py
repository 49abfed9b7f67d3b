#!/usr/bin/env python3
"""Judging rules of scripts/corpus.sh (bench/surface/summarize.py): which self-intersections
fail a model, the Medit subset a closed solid is handed to TetGen as, and the STL check
behind accepting Gmsh's tolerance weld. Usage: test_judging.py BENCH_SURFACE_DIR"""
import os
import struct
import sys
import tempfile
import unittest

sys.path.insert(0, sys.argv.pop(1) if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "../../bench/surface"))
import summarize as S  # noqa: E402


def report(si, si_model, solids=None, in_solids=None, in_solids_model=None):
    topo = {"self_intersections": si, "self_intersections_in_model": si_model}
    if solids is not None:
        topo["solids"] = solids
    if in_solids is not None:
        topo["self_intersections_in_closed_solids"] = in_solids
        topo["self_intersections_in_closed_solids_in_model"] = in_solids_model
    return {"topology": topo}


class IntersectionRule(unittest.TestCase):
    def test_stray_sheet_beside_a_closed_solid_is_reported_apart(self):
        # nist_ctc_02: one closed solid of 663 faces, a stray face (663) crossing it.
        rep = report(692, 681, [{"solid": 0, "closed": True, "faces": list(range(663))}], 0, 0)
        why, outside = S.intersection_reasons(rep, {"counts": {"faces": 664}}, False)
        self.assertEqual(why, [])
        self.assertEqual(outside, {"pairs": 692, "in_model": 681})

    def test_pairs_on_closed_solids_fail(self):
        # occt_caxif_k1: five solids touching face to face, not made conforming.
        solids = [{"solid": k, "closed": True, "faces": [k]} for k in range(5)]
        rep = report(3651, 3216, solids, 2681, 2278)
        why, outside = S.intersection_reasons(rep, {"counts": {"faces": 94}}, False)
        self.assertEqual(len(why), 1)
        self.assertIn("2681 self-intersections between triangles of closed solids", why[0])
        self.assertIn("2278 where the CAD", why[0])
        self.assertEqual(outside["pairs"], 3651 - 2681)

    def test_every_face_on_a_closed_solid_judges_the_whole_mesh(self):
        solids = [{"solid": 0, "closed": True, "faces": [0, 1, 2, 3]}]
        why, outside = S.intersection_reasons(report(3, 0, solids, 3, 0), {"counts": {"faces": 4}}, True)
        self.assertEqual(why, ["3 self-intersections"])
        self.assertIsNone(outside)
        why, _ = S.intersection_reasons(report(0, 0, solids, 0, 0), {"counts": {"faces": 4}}, True)
        self.assertEqual(why, [])

    def test_no_solid_judges_the_whole_mesh(self):
        # occt_biges: sewn shells, no solid.
        why, outside = S.intersection_reasons(report(1176, 1134), {"counts": {"faces": 15}}, False)
        self.assertEqual(why, ["1176 self-intersections (1134 where the CAD surfaces intersect too)"])
        self.assertIsNone(outside)

    def test_only_open_solids_judge_the_whole_mesh(self):
        solids = [{"solid": 0, "closed": False, "faces": [0, 1]}]
        why, _ = S.intersection_reasons(report(5, 0, solids, 0, 0), {"counts": {"faces": 3}}, False)
        self.assertEqual(why, ["5 self-intersections"])

    def test_missing_count_is_a_reason(self):
        why, _ = S.intersection_reasons({"topology": {}}, {"counts": {"faces": 1}}, True)
        self.assertEqual(len(why), 1)
        self.assertIn("report has no", why[0])


MEDIT = """MeshVersionFormatted 2
Dimension 3

Vertices
5
0 0 0 1
1 0 0 1
0 1 0 1
0 0 1 1
9 9 9 1

Triangles
3
1 2 3 1
1 2 4 2
2 3 4 3

Edges
1
1 2 7

End
"""


class MeditSubset(unittest.TestCase):
    def test_keeps_the_faces_triangles_and_their_vertices(self):
        with tempfile.TemporaryDirectory() as d:
            src, out = os.path.join(d, "m.mesh"), os.path.join(d, "s.mesh")
            with open(src, "w") as f:
                f.write(MEDIT)
            # refs are face id + 1: faces {1, 2} are refs 2 and 3
            self.assertTrue(S.medit_subset(src, {1, 2}, out))
            tok = open(out).read().split()
            v = tok.index("Vertices")
            self.assertEqual(int(tok[v + 1]), 4)  # vertices 1..4 used, vertex 5 never was
            t = tok.index("Triangles")
            self.assertEqual(int(tok[t + 1]), 2)
            tris = [tok[t + 2 + 4 * k: t + 6 + 4 * k] for k in range(2)]
            self.assertEqual(tris, [["1", "2", "4", "2"], ["2", "3", "4", "3"]])
            self.assertFalse(S.medit_subset(src, {7}, out))


def write_stl(path, tris):
    with open(path, "wb") as f:
        f.write(b"test".ljust(80, b" "))
        f.write(struct.pack("<I", len(tris)))
        for t in tris:
            f.write(struct.pack("<12fH", 0, 0, 0, *[c for p in t for c in p], 0))


class StlProper(unittest.TestCase):
    def test_proper_degenerate_and_repeated(self):
        a, b, c, d = (0, 0, 0), (1, 0, 0), (0, 1, 0), (0, 0, 1)
        with tempfile.TemporaryDirectory() as dd:
            p = os.path.join(dd, "x.stl")
            write_stl(p, [(a, b, c), (a, b, d)])
            self.assertTrue(S.stl_proper(p))
            # corners 8 and 8 + 1e-7 are one float32 value (its step at 8 is 9.5e-7)
            write_stl(p, [(a, b, c), ((8, 0, 0), (8 + 1e-7, 0, 0), d)])
            self.assertFalse(S.stl_proper(p))
            write_stl(p, [(a, b, c), (c, a, b)])
            self.assertFalse(S.stl_proper(p))


if __name__ == "__main__":
    unittest.main(verbosity=2)
