#!/usr/bin/env python3
"""Meshes every model of the shared corpus with one uvmesh binary and lists each .msh's
SHA-256, so that two builds can be compared byte for byte (a refactoring must not change
meshes). Both option sets of scripts/corpus.sh: (a) defaults, (b) --hmax D/40 --angle 30;
the subdivision cages at defaults. One thread (output is identical for any count).

    scripts/mesh_identity.py UVMESH OUT.tsv [--jobs N] [--only SUBSTR] [--keep DIR] [--flags "..."]
    scripts/mesh_identity.py --compare A.tsv B.tsv

--flags adds uvmesh mesh flags to every run (--keep-topology: the meshes before feature
sizes). --compare prints the lines that differ and exits 1 when any does.
"""
import argparse
import concurrent.futures as cf
import hashlib
import json
import os
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DATA = os.environ.get("UVMESH_SHARED_DATA", os.path.join(ROOT, "..", "shared", "data"))


def models(only):
    out = []
    for sub, exts in (("cad", (".step", ".stp", ".iges", ".igs", ".brep")), ("subd", (".obj",))):
        d = os.path.join(DATA, sub)
        for nm in sorted(os.listdir(d)):
            if nm.lower().endswith(exts) and (not only or only in nm):
                out.append((sub, os.path.join(d, nm)))
    return out


def run_one(exe, sub, path, keep, flags):
    name = os.path.basename(path)
    variants = [("a", [])]
    if sub == "cad":
        info = subprocess.run([exe, "info", path, "--json"], capture_output=True, text=True)
        try:
            d = json.loads(info.stdout)["bbox"]["diagonal"]
            variants.append(("b", ["--hmax", repr(d / 40.0), "--angle", "30"]))
        except (ValueError, KeyError):
            variants.append(("b", None))
    rows = []
    for tag, extra in variants:
        if extra is None:
            rows.append((name, tag, "info-failed", ""))
            continue
        with tempfile.TemporaryDirectory() as tmp:
            out = os.path.join(keep or tmp, name + "." + tag + ".msh")
            r = subprocess.run([exe, "mesh", path, "-o", out, "--threads", "1"] + extra + flags,
                               capture_output=True, text=True)
            digest = "missing"
            if os.path.exists(out):
                with open(out, "rb") as f:
                    digest = hashlib.sha256(f.read()).hexdigest()
            rows.append((name, tag, digest, "rc=%d" % r.returncode))
    return rows


def compare(a, b):
    def load(p):
        with open(p) as f:
            return {tuple(l.split("\t")[:2]): l.rstrip("\n").split("\t")[2:] for l in f if l.strip()}
    A, B = load(a), load(b)
    diff = [k for k in sorted(set(A) | set(B)) if A.get(k) != B.get(k)]
    for k in diff:
        print("%s %s: %s -> %s" % (k[0], k[1], A.get(k), B.get(k)))
    print("mesh_identity: %d of %d meshes identical" % (len(set(A) | set(B)) - len(diff), len(set(A) | set(B))))
    return 1 if diff else 0


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("exe", nargs="?")
    ap.add_argument("out", nargs="?")
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("--only", default="")
    ap.add_argument("--keep", default="")
    ap.add_argument("--compare", nargs=2)
    ap.add_argument("--flags", default="", help="more uvmesh mesh flags for every run, e.g. --keep-topology")
    args = ap.parse_args()
    if args.compare:
        return compare(*args.compare)
    if args.keep:
        os.makedirs(args.keep, exist_ok=True)
    jobs = models(args.only)
    rows = []
    with cf.ThreadPoolExecutor(args.jobs) as ex:
        for r in ex.map(lambda m: run_one(os.path.abspath(args.exe), m[0], m[1], args.keep, args.flags.split()), jobs):
            rows.extend(r)
    with open(args.out, "w") as f:
        for row in rows:
            f.write("\t".join(row) + "\n")
    print("mesh_identity: %d meshes of %d models -> %s" % (len(rows), len(jobs), args.out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
