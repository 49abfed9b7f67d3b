#!/usr/bin/env python3
"""summarize.py -- runs `uvmesh mesh` and the reference tools on CAD models, reads their
JSON reports and writes the verdicts and tables. The engine behind
bench/surface/run.sh (subcommand `bench`) and scripts/corpus.sh (subcommand `corpus`).

  summarize.py bench  [--quick] [--only NAME[,NAME...]] [--out DIR] [--results FILE]
  summarize.py corpus [--jobs N] [--only NAME[,NAME...]] [--out DIR]

Every field name of `uvmesh mesh --report`, `uvmesh info --json`, grade_mesh.py and
gmsh_surface.py is read through the tables REPORT, INFO, GRADE and GMSH below: when a
report changes, adjust them there and nowhere else. Acceptance thresholds are in
THRESHOLDS.

Where things are found (the same order as the CMake tests use):
  shared data  ../shared/data beside the checkout, $UVMESH_SHARED_DATA, /work/shared/data
  tools        <shared data>/../tools (gmsh_surface.py, grade_mesh.py), or $UVMESH_SHARED_TOOLS
  uvmesh       $UVMESH if set (nothing is built), else <build>/samples/uvmesh/uvmesh, built
               first with CMake (Release, Ninja) in $BUILD_DIR (default <repo>/build), $JOBS
               (default 2) jobs; --no-build skips that.
  meshio       the first of python3, /usr/bin/python3 that can import meshio (Debian's
               python3-meshio lives in the system interpreter).
Only the standard library is needed here; no numpy.
"""
import argparse
import concurrent.futures
import datetime
import json
import math
import os
import re
import shutil
import signal
import struct
import subprocess
import sys
import threading
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))

# --------------------------------------------------------------------------------------
# Field names: the one place to adjust when a report changes. Values are dotted paths.
# `uvmesh mesh --report FILE.json` (samples/uvmesh/mesh_cmd.cpp)
REPORT = {
    "points": "counts.points",
    "triangles": "counts.triangles",
    "faces": "counts.faces",
    "faces_failed": "counts.faces_failed",
    "failed_faces": "failed_faces",             # list of {"face": id, "reason": text}
    "seconds_total": "seconds.total",           # read + mesh + write + checks
    "seconds_read": "seconds.read",
    "seconds_curves": "seconds.mesh_curves",
    "seconds_faces": "seconds.mesh_faces",
    "share_Q_lt_1_5": "quality.share_Q_lt_1_5",  # share of triangles with Q_K < 1.5, in [0, 1]
    "Q_max": "quality.Q_max",
    "Q_p95": "quality.Q_p95",
    "bad_away": "quality.bad_away_from_corners",     # Q >= 3, touching no model vertex
    "bad_at_corners": "quality.bad_at_corners",      # Q >= 3, touching a model vertex (exception)
    "bad_narrow_gaps": "quality.bad_in_narrow_gaps",  # Q >= 3 across a face narrower than the
                                                      # proximity floor (no exception any more)
    "bad_acute": "quality.bad_at_acute_corners",     # of bad_at_corners: CAD corner < 20 degrees
                                                      # (the only exception)
    "Q_over_10": "quality.Q_over_10",                # triangles with Q > 10 anywhere
    "simplified": "counts.simplified",               # entities absorbed under the feature size
    "unit_edge_share": "unit_edge_share",        # share of unit edges (metric length in [1/sqrt2, sqrt2])
    "chordal_max": "chordal.max",
    "chordal_tolerance": "chordal.tolerance",    # 0 when no chordal bound was asked for
    "free_edges": "topology.free_edges",
    "non_manifold_edges": "topology.non_manifold_edges",
    "self_intersections": "topology.self_intersections",
    # of those, pairs where the model's own surfaces intersect too (surface::
    # pairs_intersecting_in_model: an input defect the mesh follows; a lower bound)
    "self_intersections_in_model": "topology.self_intersections_in_model",
    # per solid, each solid's triangles on their own: closed, its faces, free and
    # non-manifold edges, self-intersections (both triangles on its faces)
    "solids_topology": "topology.solids",
    # pairs whose two triangles both lie on faces of closed solids; the others involve a
    # sheet or an open shell outside every closed solid
    "self_intersections_in_closed_solids": "topology.self_intersections_in_closed_solids",
    "self_intersections_in_closed_solids_in_model": "topology.self_intersections_in_closed_solids_in_model",
}
# `uvmesh info MODEL --json`
INFO = {
    "diagonal": "bbox.diagonal",                 # in the model's length unit (as `mesh` uses it)
    "units": "units",
    "faces": "counts.faces",
    "solids": "counts.solids",
    "free_edges": "free_edges",
    "non_manifold_edges": "non_manifold_edges",
    "open_shells": "open_shells",
}
# grade_mesh.py (one JSON line); gmsh_surface.py adds its grade to its own record.
GRADE = {
    "triangles": "n_triangles",
    "nodes": "n_nodes",
    "q_min": "q_min",                            # q = 4*sqrt3*A/(a^2+b^2+c^2)
    "q_p01": "q_p01",
    "q_median": "q_median",
    "Q_max": "Q_max",                            # Q_K = alpha*h_max/rho (docs/ARCHITECTURE.md)
    "pct_Q_lt2": "pct_Q_lt2",
    "min_angle": "min_angle_deg",
    "free_edges": "free_edges",
    "non_manifold_edges": "nonmanifold_edges",
    "near_coincident": "near_coincident_vertices",
    "tetgen_ok": "tetgen_ok",
    "tetgen_msg": "tetgen_msg",
}
GMSH = {
    "status": "status",                          # ok / error / fail / timeout
    "wall": "wall_process_s",                    # whole gmsh process: read + 1D + 2D + write
    "cpu": "cpu_process_s",
    "reason": "fail_reason",
}
THRESHOLDS = {
    "unit_edge_share_min": 0.90,
    "share_Q_lt_1_5_min": 0.95,
    # triangle count against gmsh6 with the same options: at most 1.5x where Gmsh's own mesh
    # is decent (its Q max <= 10), 3x where Gmsh buys its count with slivers
    "gmsh_ratio_decent": 1.5,
    "gmsh_ratio_slivers": 3.0,
    "gmsh_decent_Q_max": 10.0,
}
# --------------------------------------------------------------------------------------

CAD_EXTENSIONS = (".step", ".stp", ".igs", ".iges", ".brep")
OUTPUT_FORMATS = ("msh", "mesh", "stl", "obj", "vtk")  # every format `uvmesh mesh -o` writes
GMSH_READS = ("msh", "mesh", "stl", "vtk")  # gmsh 4.8 has no OBJ reader
GMSH_ALGOS = ((6, "Frontal-Delaunay"), (5, "Delaunay"))
# --quick: small, varied, fast (planes; fillets; poles; B-splines; a real part; a helix)
QUICK_MODELS = ("axom_tet.step", "gmsh_cube_fillet.stp", "gmsh_full_sphere.brep", "occt_bottle.brep",
                "nist_ctc_01.stp", "occt_screw.step")
NOT_AVAILABLE = "uvmesh mesh: not available"



def triangle_ratio_table(results):
    """Rows of uvmesh triangles / gmsh6 triangles per model, with the bound that applies
    (THRESHOLDS: gmsh's Q max decides between the decent and the sliver bound)."""
    L = ["## Triangle counts against gmsh6", "",
         "Bound: %g x where gmsh6's Q max <= %g, else %g x." % (
             THRESHOLDS["gmsh_ratio_decent"], THRESHOLDS["gmsh_decent_Q_max"], THRESHOLDS["gmsh_ratio_slivers"]), "",
         "| model | uvmesh triangles | uvmesh Q max | gmsh6 triangles | gmsh6 Q max | ratio | bound | within |",
         "|---|---:|---:|---:|---:|---:|---:|---|"]
    over = []
    for r in results:
        u, g = r["tools"]["uvmesh"], r["tools"]["gmsh6"]
        ug, gg = u.get("grade") or {}, g.get("grade") or {}
        nu, ng = ug.get(GRADE["triangles"]), gg.get(GRADE["triangles"])
        if g.get("status") not in ("ok", "error") or not nu or not ng:
            continue
        gq = gg.get(GRADE["Q_max"])
        bound = THRESHOLDS["gmsh_ratio_decent"] if gq is not None and gq <= THRESHOLDS["gmsh_decent_Q_max"] \
            else THRESHOLDS["gmsh_ratio_slivers"]
        ratio = nu / ng
        within = ratio <= bound
        if not within:
            over.append("%s %.2f" % (r["model"], ratio))
        L.append("| %s | %s | %s | %s | %s | %.2f | %g | %s |" % (
            r["model"], fmt(nu), fmt(ug.get(GRADE["Q_max"]), 3), fmt(ng), fmt(gq, 3), ratio, bound,
            "yes" if within else "**no**"))
    L += ["", "Over the bound: %s." % (", ".join(over) or "none"), ""]
    return L

def get(record, key, table):
    """record[table[key]] following the dotted path; None when any part is missing."""
    cur = record
    for part in table[key].split("."):
        if not isinstance(cur, dict) or part not in cur:
            return None
        cur = cur[part]
    return cur


def load_json(path):
    try:
        with open(path) as f:
            return json.load(f)
    except (OSError, ValueError):
        return None


def last_json_line(text):
    for ln in reversed(text.splitlines()):
        ln = ln.strip()
        if ln.startswith("{"):
            try:
                return json.loads(ln)
            except ValueError:
                continue
    return None


def fmt(v, nd=3):
    if v is None:
        return "–"
    if isinstance(v, bool):
        return "yes" if v else "no"
    if isinstance(v, float):
        if math.isinf(v):
            return "inf"
        return ("%." + str(nd) + "g") % v if abs(v) < 1e-3 or abs(v) >= 1e5 else ("%." + str(nd) + "f") % v
    return str(v)


# --------------------------------------------------------------------------- processes
def run(cmd, timeout, out_path=None, err_path=None, cwd=None):
    """Runs cmd in its own process group (the whole group is killed on timeout).
    Returns rc (None on timeout), wall_s, cpu_s (user+sys of the child and its children),
    peak RSS in MB, timed_out, and stdout / stderr (also written to the given files)."""
    t0 = time.perf_counter()
    try:
        p = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, cwd=cwd,
                             start_new_session=True)
    except OSError as e:
        return {"rc": 127, "wall_s": 0.0, "cpu_s": None, "rss_mb": None, "timed_out": False,
                "stdout": "", "stderr": "%s: %s" % (cmd[0], e)}
    killed = []

    def kill():
        killed.append(True)
        try:
            os.killpg(p.pid, signal.SIGKILL)
        except ProcessLookupError:
            pass

    timer = threading.Timer(timeout, kill)
    timer.start()
    # Read both pipes to the end, then reap this very child with wait4 for its rusage.
    chunks = {"out": [], "err": []}

    def pump(stream, key):
        for block in iter(lambda: stream.read(65536), b""):
            chunks[key].append(block)

    readers = [threading.Thread(target=pump, args=(p.stdout, "out")),
               threading.Thread(target=pump, args=(p.stderr, "err"))]
    for t in readers:
        t.start()
    _, status, ru = os.wait4(p.pid, 0)
    wall = time.perf_counter() - t0
    for t in readers:
        t.join()
    timer.cancel()
    p.returncode = os.waitstatus_to_exitcode(status)
    stdout = b"".join(chunks["out"])
    stderr = b"".join(chunks["err"])
    for path, data in ((out_path, stdout), (err_path, stderr)):
        if path:
            with open(path, "wb") as f:
                f.write(data)
    return {"rc": None if killed else p.returncode, "wall_s": round(wall, 4),
            "cpu_s": round(ru.ru_utime + ru.ru_stime, 4), "rss_mb": round(ru.ru_maxrss / 1024.0, 1),
            "timed_out": bool(killed), "stdout": stdout.decode("utf-8", "replace"),
            "stderr": stderr.decode("utf-8", "replace")}


def exit_text(rc):
    """'exit 3', or 'killed by SIGTERM' for a child ended by a signal (rc < 0)."""
    if rc is not None and rc < 0:
        try:
            return "killed by %s" % signal.Signals(-rc).name
        except ValueError:
            return "killed by signal %d" % -rc
    return "exit %s" % rc


def first_error_line(text, limit=200):
    lines = [ln.strip() for ln in text.splitlines() if ln.strip()]
    for ln in lines:
        if "error" in ln.lower():
            return ln[:limit]
    return lines[-1][:limit] if lines else ""


# --------------------------------------------------------------------------- locations
def shared_data():
    cands = [os.path.join(ROOT, "..", "shared", "data"), os.environ.get("UVMESH_SHARED_DATA"), "/work/shared/data"]
    for c in cands:
        if c and os.path.isfile(os.path.join(c, "MANIFEST.tsv")):
            return os.path.abspath(c)
    sys.exit("summarize.py: shared corpus not found (../shared/data beside the checkout, "
             "$UVMESH_SHARED_DATA, /work/shared/data)")


def shared_tools(data):
    t = os.environ.get("UVMESH_SHARED_TOOLS") or os.path.join(os.path.dirname(data), "tools")
    for f in ("gmsh_surface.py", "grade_mesh.py"):
        if not os.path.isfile(os.path.join(t, f)):
            sys.exit("summarize.py: %s not found in %s (set UVMESH_SHARED_TOOLS)" % (f, t))
    return t


def python_with(module):
    for py in ("python3", "/usr/bin/python3", sys.executable):
        exe = shutil.which(py) if not os.path.isabs(py) else py
        if exe and subprocess.run([exe, "-c", "import " + module], stdout=subprocess.DEVNULL,
                                  stderr=subprocess.DEVNULL).returncode == 0:
            return exe
    return None


def uvmesh_exe(no_build):
    exe = os.environ.get("UVMESH")
    if exe:
        if not os.access(exe, os.X_OK):
            sys.exit("summarize.py: $UVMESH=%s is not an executable" % exe)
        return exe
    build = os.environ.get("BUILD_DIR") or os.path.join(ROOT, "build")
    exe = os.path.join(build, "samples", "uvmesh", "uvmesh")
    if not no_build:
        jobs = os.environ.get("JOBS", "2")
        if not os.path.isfile(os.path.join(build, "CMakeCache.txt")):
            subprocess.run(["cmake", "-S", ROOT, "-B", build, "-G", "Ninja", "-DCMAKE_BUILD_TYPE=Release"],
                           check=True, stdout=subprocess.DEVNULL)
        print("building uvmesh in %s ..." % build, file=sys.stderr)
        r = subprocess.run(["cmake", "--build", build, "-j" + jobs, "--target", "uvmesh"],
                           stdout=subprocess.PIPE, stderr=subprocess.STDOUT)
        if r.returncode != 0:
            sys.stderr.write(r.stdout.decode("utf-8", "replace")[-3000:])
            sys.exit("summarize.py: building uvmesh failed")
    if not os.access(exe, os.X_OK):
        sys.exit("summarize.py: uvmesh not found at %s (build it, or set $UVMESH)" % exe)
    return exe


def mesh_available(exe):
    """(True, "") when `uvmesh mesh` exists, else (False, why)."""
    r = run([exe, "--help"], 60)
    subs = r["stdout"].split("Subcommands:", 1)
    if r["rc"] == 0 and len(subs) == 2 and re.search(r"^\s+mesh\s", subs[1], re.M):
        return True, ""
    if r["rc"] != 0:
        return False, "%s (`uvmesh --help` failed: %s)" % (NOT_AVAILABLE, first_error_line(r["stderr"]))
    return False, "%s (%s lists no `mesh` subcommand yet)" % (NOT_AVAILABLE, exe)


def models(data, only, quick):
    cad = os.path.join(data, "cad")
    found = sorted(f for f in os.listdir(cad) if f.lower().endswith(CAD_EXTENSIONS))
    if quick:
        found = [f for f in found if f in QUICK_MODELS]
    if only:
        wanted = [w.strip() for w in only.split(",") if w.strip()]
        pick = []
        for w in wanted:
            hits = [f for f in found if f == w or os.path.splitext(f)[0] == w]
            if not hits:
                sys.exit("summarize.py: no model named %s in %s" % (w, cad))
            pick += [h for h in hits if h not in pick]
        found = pick
    return [os.path.join(cad, f) for f in found]


def model_info(exe, model, outdir):
    """`uvmesh info --json --no-check` (the validity check is not needed here), saved as
    OUTDIR/info.json. Returns (info, error)."""
    r = run([exe, "info", "--json", "--no-check", model], 600)
    if r["rc"] != 0:
        return None, "uvmesh info failed (%s): %s" % (
            "timeout" if r["timed_out"] else "exit %s" % r["rc"], first_error_line(r["stderr"]))
    try:
        info = json.loads(r["stdout"])
    except ValueError:
        return None, "uvmesh info printed no JSON"
    with open(os.path.join(outdir, "info.json"), "w") as f:
        json.dump(info, f, indent=1)
    if not get(info, "diagonal", INFO):
        return None, "uvmesh info: no bounding-box diagonal (%s)" % INFO["diagonal"]
    return info, None


def grade(py, tools, mesh, target_h, tetgen=True, timeout=150):
    cmd = [py, os.path.join(tools, "grade_mesh.py"), mesh, "--tetgen-timeout", str(timeout)]
    if target_h:
        cmd += ["--target-h", repr(target_h)]
    if not tetgen:
        cmd.append("--no-tetgen")
    r = run(cmd, timeout + 600)
    g = last_json_line(r["stdout"])
    if g is None:
        return {"grade_error": "grade_mesh.py: %s" % (first_error_line(r["stderr"]) or "no output")}
    return g


# --------------------------------------------------------------------------- bench
def bench_uvmesh(exe, model, outdir, h, threads, timeout, tag, with_report=True):
    out = os.path.join(outdir, tag + ".msh")
    rep = os.path.join(outdir, tag + ".report.json")
    for f in (out, rep):
        if os.path.exists(f):
            os.remove(f)
    cmd = [exe, "mesh", model, "-o", out, "--hmax", repr(h), "--angle", "30", "--threads", str(threads)]
    # The timed run is the user's command, without --report: the report's checks (chordal
    # deviation, self-intersections by BVH, quality histograms) verify the mesh, which Gmsh
    # does not do, and would add 20-50 % to small models. A second, untimed run writes the
    # report the tables read; the mesh is byte-identical (tests/surface_mesh determinism).
    r = run(cmd, timeout, os.path.join(outdir, tag + ".out"), os.path.join(outdir, tag + ".err"))
    rec = {"cmd": " ".join(cmd), "wall_s": r["wall_s"], "cpu_s": r["cpu_s"], "rss_mb": r["rss_mb"],
           "rc": r["rc"], "timed_out": r["timed_out"], "mesh": out}
    if not r["timed_out"] and with_report:
        run(cmd + ["--report", rep], timeout, os.path.join(outdir, tag + ".report.out"),
            os.path.join(outdir, tag + ".report.err"))
    report = load_json(rep)
    rec["report"] = report
    if r["timed_out"]:
        rec["status"], rec["reason"] = "timeout", "exceeded %g s" % timeout
    elif r["rc"] != 0:
        rec["status"] = "fail"
        failed = get(report, "faces_failed", REPORT) if report else None
        rec["reason"] = "%s%s: %s" % (exit_text(r["rc"]), ", %s faces failed" % failed if failed else "",
                                      first_error_line(r["stderr"]) or "no message")
    elif not os.path.isfile(out):
        rec["status"], rec["reason"] = "fail", "exit 0 but no %s" % os.path.basename(out)
    else:
        rec["status"] = "ok"
    return rec


def bench_one(ctx, model):
    name = os.path.basename(model)
    outdir = os.path.join(ctx["out"], name)
    os.makedirs(outdir, exist_ok=True)
    t0 = time.perf_counter()
    res = {"model": name, "tools": {}}
    info, err = model_info(ctx["uvmesh"], model, outdir)
    if info:
        res["diagonal"] = get(info, "diagonal", INFO)
        res["units"] = get(info, "units", INFO)
        res["cad_faces"] = get(info, "faces", INFO)
        h = res["diagonal"] / 40.0
        res["h"] = h
    else:
        res["info_error"] = err
    # (1) uvmesh, one thread, then two threads on the larger models
    if not ctx["mesh_ok"]:
        res["tools"]["uvmesh"] = {"status": "n/a", "reason": ctx["mesh_why"]}
    elif not info:
        res["tools"]["uvmesh"] = {"status": "fail", "reason": err}
    else:
        u = bench_uvmesh(ctx["uvmesh"], model, outdir, h, 1, ctx["uvmesh_timeout"], "uvmesh_t1")
        if u["status"] == "ok":
            u["grade"] = grade(ctx["py"], ctx["tools"], u["mesh"], h, tetgen=True, timeout=ctx["gmsh_timeout"])
            if u["wall_s"] >= ctx["threads_min_s"]:
                u2 = bench_uvmesh(ctx["uvmesh"], model, outdir, h, 2, ctx["uvmesh_timeout"], "uvmesh_t2",
                                  with_report=False)
                u2.pop("report", None)
                u["threads2"] = u2
        res["tools"]["uvmesh"] = u
    # (2) Gmsh references, graded by gmsh_surface.py itself (grade_mesh.py, TetGen included)
    for algo, algo_name in GMSH_ALGOS:
        cmd = [ctx["py"], os.path.join(ctx["tools"], "gmsh_surface.py"), model, outdir, "1.0", str(algo),
               "--curv", "12", "--timeout", str(ctx["gmsh_timeout"])]
        r = run(cmd, 3 * ctx["gmsh_timeout"] + 600)
        g = last_json_line(r["stdout"]) or {}
        rec = {"cmd": " ".join(cmd[1:]), "algo_name": algo_name, "gmsh": g, "grade": g,
               "status": get(g, "status", GMSH) or "fail",
               "wall_s": get(g, "wall", GMSH), "cpu_s": get(g, "cpu", GMSH),
               "reason": get(g, "reason", GMSH) or ("" if g else "gmsh_surface.py: %s" %
                                                     first_error_line(r["stderr"]))}
        if rec["status"] == "timeout":
            rec["wall_s"] = float(ctx["gmsh_timeout"])  # a timeout counts at the timeout time
        res["tools"]["gmsh%d" % algo] = rec
    res["elapsed_s"] = round(time.perf_counter() - t0, 2)
    with open(os.path.join(outdir, "bench.json"), "w") as f:
        json.dump(res, f, indent=1, default=str)
    return res


def tool_row(label, t, last):
    g = t.get("grade") or {}
    ok = t.get("status") in ("ok", "error")  # gmsh "error": mesh written but errors logged
    tri = get(g, "triangles", GRADE) if ok else None
    wall = t.get("wall_s")
    rate = tri / wall if tri and wall else None
    status = t.get("status", "–")
    if t.get("reason") and status != "ok":
        status += ": " + str(t["reason"]).replace("|", "/")[:120]
    tet = get(g, "tetgen_ok", GRADE) if ok else None
    if tet is False and get(g, "tetgen_msg", GRADE):
        tet = "no (%s)" % str(get(g, "tetgen_msg", GRADE)).replace("|", "/")[:80]
    cells = [label, status, fmt(wall), fmt(t.get("cpu_s")), fmt(tri), fmt(rate, 0) if rate else "–",
             fmt(get(g, "q_min", GRADE)) if ok else "–", fmt(get(g, "q_p01", GRADE)) if ok else "–",
             fmt(get(g, "q_median", GRADE)) if ok else "–", fmt(get(g, "Q_max", GRADE)) if ok else "–",
             fmt(get(g, "pct_Q_lt2", GRADE), 1) if ok else "–",
             fmt(get(g, "free_edges", GRADE)) if ok else "–",
             fmt(get(g, "non_manifold_edges", GRADE)) if ok else "–",
             fmt(get(g, "near_coincident", GRADE)) if ok else "–",
             fmt(tet) if ok else "–", last]
    return "| " + " | ".join(cells) + " |"


def geomean(xs):
    xs = [x for x in xs if x and x > 0]
    return math.exp(sum(math.log(x) for x in xs) / len(xs)) if xs else None


def bench_markdown(results, ctx, seconds):
    L = []
    commit = subprocess.run(["git", "-C", ROOT, "rev-parse", "--short", "HEAD"], stdout=subprocess.PIPE,
                            stderr=subprocess.DEVNULL).stdout.decode().strip() or "unknown"
    L.append("<!-- written by bench/surface/run.sh %s on %s, commit %s (working tree may differ) -->" % (
        " ".join(ctx["argv"]) or "(full run)", datetime.datetime.utcnow().strftime("%Y-%m-%dT%H:%MZ"), commit))
    L.append("# Surface meshing: uvmesh vs Gmsh, one thread")
    L.append("")
    L.append("Models: %d from `%s`; whole run %.0f s wall; load average %s at the start, %s at the end. "
             "D = bounding-box diagonal from `uvmesh info --json` (model units)." % (
                 len(results), os.path.join(ctx["data"], "cad"), seconds, ctx["load0"], fmt_load()))
    L.append("")
    L.append("- **uvmesh**: `uvmesh mesh MODEL -o out.msh --hmax D/40 --angle 30 --threads 1`; "
             "wall = whole process (read + curves + faces + write), timed without `--report` (a second, untimed "
             "run with `--report r.json` gives the report columns: its verification, BVH self-intersection "
             "test included, is not meshing work). The 2-thread run (`--threads 2`) is done on "
             "models whose 1-thread wall is at least %g s." % ctx["threads_min_s"])
    L.append("- **gmsh6 / gmsh5**: `gmsh_surface.py MODEL OUTDIR 1.0 {6,5} --curv 12 --timeout %g` "
             "(Frontal-Delaunay / Delaunay, h = D/40, 12 elements per 2π, one thread; wall = whole gmsh "
             "process). A timeout is a failure counted at %g s." % (ctx["gmsh_timeout"], ctx["gmsh_timeout"]))
    L.append("- Every mesh is graded by the same grader, `grade_mesh.py` (q = 4√3·A/Σa², 1 = equilateral; "
             "Q = α·h_max/ρ, Q_K of docs/ARCHITECTURE.md; free / non-manifold edges on the stored indices; near = vertices "
             "closer than 1e-8·D, which TetGen rejects; TetGen = `tetgen -pY` fills the surface).")
    L.append("- gmsh/uvmesh = gmsh wall ÷ uvmesh wall (> 1: uvmesh faster).")
    L.append("")
    # ---- totals
    L.append("## Corpus totals")
    L.append("")
    u_ok = [r for r in results if r["tools"]["uvmesh"].get("status") == "ok"]
    hdr = ["", "uvmesh"] + ["gmsh%d (%s)" % (a, n) for a, n in GMSH_ALGOS]
    L.append("| " + " | ".join(hdr) + " |")
    L.append("|" + "---|" * len(hdr))

    def count(tool, pred):
        return sum(1 for r in results if pred(r["tools"][tool]))

    keys = ["uvmesh"] + ["gmsh%d" % a for a, _ in GMSH_ALGOS]
    row = ["models meshed (status ok)"] + ["%d / %d" % (count(k, lambda t: t.get("status") in ("ok", "error")),
                                                       len(results)) for k in keys]
    L.append("| " + " | ".join(row) + " |")
    row = ["timeouts / failures"] + ["%d / %d" % (count(k, lambda t: t.get("status") == "timeout"),
                                                  count(k, lambda t: t.get("status") not in ("ok", "error")))
                                     for k in keys]
    L.append("| " + " | ".join(row) + " |")
    row = ["TetGen accepts"] + ["%d" % count(k, lambda t: bool((t.get("grade") or {}).get(GRADE["tetgen_ok"])))
                                for k in keys]
    L.append("| " + " | ".join(row) + " |")
    row = ["meshes with free edges"] + [
        "%d" % count(k, lambda t: t.get("status") in ("ok", "error") and
                     ((t.get("grade") or {}).get(GRADE["free_edges"]) or 0) > 0) for k in keys]
    L.append("| " + " | ".join(row) + " |")
    row = ["triangles (sum over meshed models)"] + [
        "%d" % sum((r["tools"][k].get("grade") or {}).get(GRADE["triangles"]) or 0 for r in results
                   if r["tools"][k].get("status") in ("ok", "error")) for k in keys]
    L.append("| " + " | ".join(row) + " |")
    # ratios over the models where uvmesh and gmsh both have a wall time
    sums = ["sum of walls, s (models with a uvmesh wall)"]
    ratio_sum = ["speed ratio gmsh/uvmesh, sum of walls"]
    ratio_geo = ["speed ratio gmsh/uvmesh, geometric mean"]
    faster = ["models where uvmesh is faster (uvmesh ok)"]
    uv_walls = {r["model"]: r["tools"]["uvmesh"].get("wall_s") for r in results}
    both = [r for r in results if uv_walls[r["model"]]]
    sums.append(fmt(sum(uv_walls[r["model"]] for r in both), 4) if both else "–")
    ratio_sum.append("–")
    ratio_geo.append("–")
    faster.append("–")
    for a, _ in GMSH_ALGOS:
        k = "gmsh%d" % a
        pairs = [(r["tools"][k].get("wall_s"), uv_walls[r["model"]]) for r in both if r["tools"][k].get("wall_s")]
        sums.append(fmt(sum(g for g, _ in pairs), 4) if pairs else "–")
        ratio_sum.append(fmt(sum(g for g, _ in pairs) / sum(u for _, u in pairs), 3) if pairs else "–")
        ratio_geo.append(fmt(geomean([g / u for g, u in pairs]), 3) if pairs else "–")
        faster.append("%d of %d" % (sum(1 for r in u_ok if r["tools"][k].get("wall_s") and
                                        r["tools"]["uvmesh"]["wall_s"] < r["tools"][k]["wall_s"]), len(u_ok))
                      if u_ok else "–")
    gm_sum = ["sum of walls, s (all models)", fmt(sum(uv_walls[r["model"]] for r in both), 4) if both else "–"] + [
        fmt(sum(r["tools"]["gmsh%d" % a].get("wall_s") or 0 for r in results), 4) for a, _ in GMSH_ALGOS]
    for row in (gm_sum, sums, ratio_sum, ratio_geo, faster):
        L.append("| " + " | ".join(row) + " |")
    L.append("")
    t2 = [(r["model"], r["tools"]["uvmesh"]["wall_s"], r["tools"]["uvmesh"]["threads2"]) for r in results
          if r["tools"]["uvmesh"].get("threads2")]
    t2ok = [(m, w1, x["wall_s"]) for m, w1, x in t2 if x.get("status") == "ok" and x.get("wall_s")]
    if not ctx["mesh_ok"]:
        L.append("uvmesh: %s — no uvmesh runs, no ratios." % ctx["mesh_why"])
    elif t2ok:
        L.append("2 threads vs 1 (uvmesh, %d models with a 1-thread wall ≥ %g s): sum %.2f s → %.2f s, speedup "
                 "%.2f (sums), %.2f (geometric mean); %s." % (
                     len(t2ok), ctx["threads_min_s"], sum(w for _, w, _ in t2ok), sum(w for _, _, w in t2ok),
                     sum(w for _, w, _ in t2ok) / sum(w for _, _, w in t2ok),
                     geomean([a / b for _, a, b in t2ok]),
                     ", ".join("%s %.2f" % (m, a / b) for m, a, b in t2ok)))
    else:
        L.append("2 threads vs 1: no model took %g s or more with one thread (or the 2-thread runs failed: %s)."
                 % (ctx["threads_min_s"], ", ".join("%s %s" % (m, x.get("status")) for m, _, x in t2) or "none"))
    L.append("")
    # ---- overview
    L.append("## Overview")
    L.append("")
    L.append("| model | CAD faces | D | uvmesh s | gmsh6 s | gmsh5 s | gmsh6/uvmesh | gmsh5/uvmesh | "
             "uvmesh triangles | gmsh6 triangles | uvmesh TetGen | gmsh6 TetGen | gmsh5 TetGen |")
    L.append("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|---|---|")
    for r in results:
        u, g6, g5 = r["tools"]["uvmesh"], r["tools"]["gmsh6"], r["tools"]["gmsh5"]

        def wall(t):
            s = fmt(t.get("wall_s"))
            return s if t.get("status") in ("ok", "error") else "%s (%s)" % (s, t.get("status"))

        def tet(t):
            return fmt((t.get("grade") or {}).get(GRADE["tetgen_ok"])) if t.get("status") in ("ok", "error") else "–"

        def tri(t):
            return fmt((t.get("grade") or {}).get(GRADE["triangles"])) if t.get("status") in ("ok", "error") else "–"
        uw = u.get("wall_s")
        L.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
            r["model"], fmt(r.get("cad_faces")), fmt(r.get("diagonal"), 4), wall(u) if uw else u.get("status"),
            wall(g6), wall(g5), fmt(g6["wall_s"] / uw, 2) if uw and g6.get("wall_s") else "–",
            fmt(g5["wall_s"] / uw, 2) if uw and g5.get("wall_s") else "–", tri(u), tri(g6), tet(u), tet(g6), tet(g5)))
    L.append("")
    L += triangle_ratio_table(results)
    # ---- per model
    L.append("## Per model")
    L.append("")
    cols = ["tool", "status", "wall s", "CPU s", "triangles", "triangles/s", "q min", "q p01", "q median",
            "Q max", "% Q<2", "free edges", "non-manifold", "near", "TetGen", "gmsh/uvmesh"]
    for r in results:
        L.append("### %s" % r["model"])
        L.append("")
        if r.get("info_error"):
            L.append("uvmesh info: %s" % r["info_error"])
        else:
            L.append("%s CAD faces, D = %s %s, h = D/40 = %s." % (fmt(r.get("cad_faces")), fmt(r.get("diagonal"), 5),
                                                                 r.get("units") or "", fmt(r.get("h"), 4)))
        L.append("")
        L.append("| " + " | ".join(cols) + " |")
        L.append("|---|---|" + "---:|" * (len(cols) - 2))
        u = r["tools"]["uvmesh"]
        uw = u.get("wall_s") if u.get("status") in ("ok", "fail", "timeout") else None
        L.append(tool_row("uvmesh", u, "–"))
        if u.get("threads2"):
            t = dict(u["threads2"], grade={})  # same mesh as one thread: not graded again
            L.append(tool_row("uvmesh --threads 2", t, "2-thread speedup %.2f" % (uw / t["wall_s"])
                              if uw and t.get("wall_s") and t.get("status") == "ok" else "–"))
        for a, n in GMSH_ALGOS:
            t = r["tools"]["gmsh%d" % a]
            L.append(tool_row("gmsh%d %s" % (a, n), t, fmt(t["wall_s"] / uw, 2) if uw and t.get("wall_s") else "–"))
        rep = u.get("report")
        if rep:
            L.append("")
            L.append("uvmesh report: %s s total (read %s, curves %s, faces %s); share Q<1.5 %s, Q max %s, "
                     "unit edges %s; chordal max %s (tolerance %s); self-intersections %s." % tuple(
                         fmt(get(rep, k, REPORT)) for k in (
                             "seconds_total", "seconds_read", "seconds_curves", "seconds_faces", "share_Q_lt_1_5",
                             "Q_max", "unit_edge_share", "chordal_max", "chordal_tolerance", "self_intersections")))
        L.append("")
    return "\n".join(L) + "\n"


def fmt_load():
    try:
        return " ".join("%.2f" % x for x in os.getloadavg())
    except OSError:
        return "?"


def cmd_bench(a):
    data = shared_data()
    ctx = {"data": data, "tools": shared_tools(data), "py": sys.executable,
           "uvmesh": uvmesh_exe(a.no_build or a.report_only), "out": os.path.abspath(a.out),
           "uvmesh_timeout": a.uvmesh_timeout, "gmsh_timeout": a.gmsh_timeout,
           "threads_min_s": a.threads_min_s, "argv": a.argv, "load0": fmt_load()}
    ctx["mesh_ok"], ctx["mesh_why"] = mesh_available(ctx["uvmesh"])
    if not ctx["mesh_ok"] and not a.report_only:
        print("run.sh: %s -- every uvmesh row is a failure; the Gmsh runs and grading go on" % ctx["mesh_why"],
              file=sys.stderr)
    os.makedirs(ctx["out"], exist_ok=True)
    ms = models(data, a.only, a.quick)
    t0 = time.perf_counter()
    results = []
    if a.report_only:  # the records of an earlier run, as they are
        results = [load_json(os.path.join(ctx["out"], os.path.basename(m), "bench.json")) for m in ms]
        results = [r for r in results if r]
        ms = []
        na = [r["tools"]["uvmesh"] for r in results if r["tools"]["uvmesh"].get("status") == "n/a"]
        ctx["mesh_ok"] = len(na) < len(results)
        ctx["mesh_why"] = na[0].get("reason") if na else ""
        ctx["argv"] = ctx["argv"] + ["(tables rewritten from the records of an earlier run)"]
    for i, m in enumerate(ms, 1):
        r = bench_one(ctx, m)
        results.append(r)
        t = r["tools"]
        print("[%d/%d] %-32s uvmesh %-8s %8s s | gmsh6 %-7s %8s s | gmsh5 %-7s %8s s" % (
            i, len(ms), r["model"], t["uvmesh"].get("status"), fmt(t["uvmesh"].get("wall_s")),
            t["gmsh6"]["status"], fmt(t["gmsh6"].get("wall_s")), t["gmsh5"]["status"],
            fmt(t["gmsh5"].get("wall_s"))), file=sys.stderr, flush=True)
    md = bench_markdown(results, ctx, sum(r.get("elapsed_s") or 0 for r in results) or time.perf_counter() - t0)
    with open(os.path.join(ctx["out"], "results.json"), "w") as f:
        json.dump(results, f, indent=1, default=str)
    tmp = a.results + ".tmp"
    with open(tmp, "w") as f:
        f.write(md)
    os.replace(tmp, a.results)
    print("run.sh: wrote %s (raw records in %s)" % (a.results, ctx["out"]), file=sys.stderr)
    return 0


# --------------------------------------------------------------------------- corpus
def reader_checks(meshio_py, path, expected_tris, timeout):
    """[] when meshio and (for the formats it reads) gmsh read `path` with the expected
    number of triangles, else the reasons."""
    ext = path.rsplit(".", 1)[-1]
    why = []
    if meshio_py is None:
        why.append("meshio not installed (python3-meshio)")
    else:
        code = ("import json, sys, meshio\nm = meshio.read(sys.argv[1])\n"
                "print(json.dumps({'triangles': sum(len(c.data) for c in m.cells if c.type == 'triangle'),"
                " 'points': len(m.points)}))")
        r = run([meshio_py, "-c", code, path], timeout)
        j = last_json_line(r["stdout"])
        if r["rc"] != 0 or j is None:
            why.append("meshio cannot read .%s: %s" % (ext, first_error_line(r["stderr"]) or "timeout"))
        elif expected_tris is not None and j["triangles"] != expected_tris:
            why.append("meshio reads %d triangles from .%s, report says %d" % (j["triangles"], ext, expected_tris))
    if ext in GMSH_READS:
        back = path + ".gmsh_reread.msh"
        r = run(["gmsh", "-nopopup", "-v", "2", path, "-0", "-o", back, "-format", "msh22"], timeout)
        tris = None
        if r["rc"] == 0 and os.path.isfile(back):
            tris = count_msh22_triangles(back)
            os.remove(back)
        if tris is None:
            why.append("gmsh cannot read .%s: %s" % (ext, first_error_line(r["stderr"] + r["stdout"]) or "timeout"))
        elif expected_tris is not None and tris != expected_tris:
            # STL has no shared vertices: Gmsh welds them within its Geometry.Tolerance
            # (relative to the bounding box) and drops a triangle whose corners weld together,
            # saying how many ("N duplicate/M degenerate triangles in STL file"). A CAD edge
            # kept exactly (gmsh_t20_part's 8.8e-7, 1.3e-8 D, one float32 step) can be that
            # short. That loss is Gmsh's tolerance, not the file's: accepted when the file's
            # own float32 triangles are all proper and distinct, and Gmsh's dropped count
            # accounts for every missing triangle.
            m = re.search(r"(\d+) duplicate/(\d+) degenerate triangles in STL file", r["stderr"] + r["stdout"])
            dropped = int(m.group(1)) + int(m.group(2)) if m else 0
            if not (ext == "stl" and m and tris + dropped == expected_tris and stl_proper(path)):
                why.append("gmsh reads %d triangles from .%s, report says %d" % (tris, ext, expected_tris))
    return why


def stl_proper(path):
    """A binary STL whose every triangle has three distinct float32 corners and no
    triangle repeats another (as a set of corners). False for an ASCII or short file."""
    with open(path, "rb") as f:
        data = f.read()
    if len(data) < 84:
        return False
    n = struct.unpack_from("<I", data, 80)[0]
    if len(data) != 84 + 50 * n:
        return False
    seen = set()
    for t in range(n):
        v = struct.unpack_from("<9f", data, 84 + 50 * t + 12)
        c = (v[0:3], v[3:6], v[6:9])
        if c[0] == c[1] or c[1] == c[2] or c[0] == c[2]:
            return False
        key = tuple(sorted(c))
        if key in seen:
            return False
        seen.add(key)
    return True


def count_msh22_triangles(path):
    with open(path, errors="replace") as f:
        for ln in f:
            if ln.strip() == "$Elements":
                n = int(next(f))
                return sum(1 for _ in range(n) if next(f).split()[1] == "2")
    return None


def mesh_variant(ctx, model, vdir, extra):
    """Runs `uvmesh mesh` for one variant, writing every output format. Returns the run
    record, its command, the report, and {output file: triangles its run reported}."""
    os.makedirs(vdir, exist_ok=True)
    outs = [os.path.join(vdir, "mesh." + e) for e in OUTPUT_FORMATS]
    rep = os.path.join(vdir, "report.json")
    base = [ctx["uvmesh"], "mesh", model] + extra + ["--report", rep]
    for f in outs + [rep]:
        if os.path.exists(f):
            os.remove(f)
    if not ctx.get("one_output_per_run"):
        cmd = base[:3] + sum((["-o", o] for o in outs), []) + base[3:]
        r = run(cmd, ctx["timeout"], os.path.join(vdir, "run.out"), os.path.join(vdir, "run.err"))
        # A `mesh` that takes a single -o either refuses the command line before meshing
        # (CLI11: "-o: At Most 1 required but received 5") or writes only one of the files:
        # then mesh once per format, and keep doing so for the rest of the run.
        refused = r["rc"] not in (0, None) and not os.path.exists(rep) and re.search(
            r"(^|\W)(-o|--output)\b", r["stderr"])
        partial = r["rc"] == 0 and 0 < sum(os.path.isfile(o) for o in outs) < len(outs)
        if not (refused or partial):
            report = load_json(rep)
            return r, cmd, report, {o: get(report, "triangles", REPORT) if report else None for o in outs}
        ctx["one_output_per_run"] = True
    # One run a format, each with a report of its own (a multi-threaded mesh need not be
    # the same twice): the first run (.msh) is the one judged, the others give files.
    first = None
    expected = {}
    for i, o in enumerate(outs):
        ri_rep = rep if i == 0 else os.path.join(vdir, "report.%s.json" % o.rsplit(".", 1)[-1])
        c = base[:3] + ["-o", o] + extra + ["--report", ri_rep]
        ri = run(c, ctx["timeout"], os.path.join(vdir, "run%d.out" % i), os.path.join(vdir, "run%d.err" % i))
        ri_report = load_json(ri_rep)
        expected[o] = get(ri_report, "triangles", REPORT) if ri_report else None
        if first is None:
            first = (ri, c)
        if ri["timed_out"]:
            first = (ri, c)  # report the timeout; the remaining formats would time out too
            break
    return first[0], first[1], load_json(rep), expected


def closed_solid(info):
    """A solid bounded by closed shells: free edges and open shells are errors in its mesh."""
    return (get(info, "solids", INFO) or 0) > 0 and get(info, "free_edges", INFO) == 0 and \
        not get(info, "open_shells", INFO)


def judge_variant(ctx, model, info, vname, extra):
    vdir = os.path.join(ctx["out"], os.path.basename(model), vname)
    r, cmd, rep, expected = mesh_variant(ctx, model, vdir, extra)
    rec = {"variant": vname, "cmd": " ".join(cmd), "wall_s": r["wall_s"], "rc": r["rc"], "reasons": []}
    why = rec["reasons"]
    if r["timed_out"]:
        why.append("timeout after %g s" % ctx["timeout"])
        return rec
    if r["rc"] != 0:
        why.append("%s: %s" % (exit_text(r["rc"]), first_error_line(r["stderr"]) or "no message"))
    if rep is None:
        why.append("no report (--report)")
        return rec
    rec["triangles"] = tris = get(rep, "triangles", REPORT)
    # The acceptance's reported exceptions: Q >= 3 at a model vertex, or across a gap of
    # the face narrower than the mesher's proximity floor.
    rec["exceptions"] = {k: get(rep, k, REPORT) for k in ("bad_at_corners", "bad_narrow_gaps")}
    failed = get(rep, "faces_failed", REPORT)
    if failed:
        ff = get(rep, "failed_faces", REPORT) or []
        why.append("%s faces failed%s" % (failed, (": " + json.dumps(ff[:3])[:160]) if ff else ""))
    if not tris:
        why.append("no triangles")
    closed = closed_solid(info)
    manifold = get(info, "non_manifold_edges", INFO) == 0

    def need(key, ok, text):
        v = get(rep, key, REPORT)
        if v is None:
            why.append("report has no %s" % REPORT[key])
        elif not ok(v):
            why.append(text % v)

    # An assembly of touching solids is made conforming (uvmesh mesh --conform, the
    # default): each interface is meshed once and shared by two solids, so the whole mesh
    # has non-manifold edges where an interface meets the outside, by construction. The
    # acceptance asks it of every closed solid: each solid's triangles on their own must
    # have no free and no non-manifold edge (the report's topology.solids).
    per_solid = get(rep, "solids_topology", REPORT) or []
    assembly = len(per_solid) >= 2
    if closed:
        need("free_edges", lambda v: v == 0, "%s free edges")
        if manifold and not assembly:
            need("non_manifold_edges", lambda v: v == 0, "%s non-manifold edges")
    # Every closed solid, also one beside sheets or open shells of the file.
    for so in per_solid:
        if not so.get("closed"):
            continue
        if so.get("free_edges") or so.get("non_manifold_edges"):
            why.append("solid %s: %s free / %s non-manifold edges" % (
                so.get("solid"), so.get("free_edges"), so.get("non_manifold_edges")))
    reasons, outside = intersection_reasons(rep, info, closed)
    why += reasons
    if outside is not None:
        rec["intersections_outside_solids"] = outside
    tol = get(rep, "chordal_tolerance", REPORT)
    if tol is None:
        why.append("report has no %s" % REPORT["chordal_tolerance"])
    elif tol > 0:  # 0: no chordal bound in force (e.g. --angle alone), nothing to hold to
        need("chordal_max", lambda v: v <= tol, "chordal max %%.4g > tolerance %.4g" % tol)
    need("unit_edge_share", lambda v: v >= THRESHOLDS["unit_edge_share_min"],
         "unit edge share %%.3f < %g" % THRESHOLDS["unit_edge_share_min"])
    need("share_Q_lt_1_5", lambda v: v >= THRESHOLDS["share_Q_lt_1_5_min"],
         "share Q<1.5 %%.3f < %g" % THRESHOLDS["share_Q_lt_1_5_min"])
    need("bad_away", lambda v: v == 0, "%s triangles with Q >= 3 touching no model vertex")
    need("Q_over_10", lambda v: v == 0, "%s triangles with Q > 10")
    corners, acute, gaps = (get(rep, k, REPORT) for k in ("bad_at_corners", "bad_acute", "bad_narrow_gaps"))
    if None not in (corners, acute) and corners - acute > 0:
        why.append("%d triangles with Q >= 3 at CAD corners of 20 degrees or more" % (corners - acute))
    if gaps:
        why.append("%d triangles with Q >= 3 across narrow gaps" % gaps)
    # Every output file: present, read by meshio and gmsh with the report's triangle count.
    for o, n in expected.items():
        if not os.path.isfile(o):
            why.append("no %s" % os.path.basename(o))
        else:
            why += reader_checks(ctx["meshio_py"], o, n, ctx["timeout"])
    # The .msh as a volume mesher sees it: topology on the stored indices, TetGen.
    msh = os.path.join(vdir, "mesh.msh")
    if os.path.isfile(msh):
        g = grade(ctx["py"], ctx["tools"], msh, None, tetgen=closed, timeout=ctx["timeout"])
        rec["grade"] = {k: get(g, k, GRADE) for k in GRADE}
        if g.get("grade_error"):
            why.append(g["grade_error"])
        else:
            if closed and get(g, "free_edges", GRADE):
                why.append("mesh.msh has %s free edges (grade_mesh.py)" % get(g, "free_edges", GRADE))
            if closed and manifold and not assembly and get(g, "non_manifold_edges", GRADE):
                why.append("mesh.msh has %s non-manifold edges (grade_mesh.py)" % get(g, "non_manifold_edges", GRADE))
            if closed and not get(g, "tetgen_ok", GRADE):
                why.append("tetgen -pY rejects the surface: %s" % get(g, "tetgen_msg", GRADE))
    # A model with closed solids beside sheets or open shells is not closed as a whole:
    # each closed solid's own triangles go to grade_mesh.py and TetGen then.
    med = os.path.join(vdir, "mesh.mesh")
    if not closed and os.path.isfile(med):
        for so in per_solid:
            if not so.get("closed") or not so.get("faces"):
                continue
            sub = os.path.join(vdir, "solid%s.mesh" % so.get("solid"))
            if not medit_subset(med, set(so["faces"]), sub):
                why.append("solid %s: no triangles in mesh.mesh" % so.get("solid"))
                continue
            g = grade(ctx["py"], ctx["tools"], sub, None, tetgen=True, timeout=ctx["timeout"])
            rec.setdefault("solid_grades", []).append(
                {"solid": so.get("solid"), **{k: get(g, k, GRADE) for k in GRADE}})
            if g.get("grade_error"):
                why.append("solid %s: %s" % (so.get("solid"), g["grade_error"]))
                continue
            for k, text in (("free_edges", "free"), ("non_manifold_edges", "non-manifold")):
                if get(g, k, GRADE):
                    why.append("solid %s: %s %s edges (grade_mesh.py)" % (so.get("solid"), get(g, k, GRADE), text))
            if not get(g, "tetgen_ok", GRADE):
                why.append("solid %s: tetgen -pY rejects its surface: %s" % (so.get("solid"), get(g, "tetgen_msg", GRADE)))
            os.remove(sub)
    return rec


def intersection_reasons(rep, info, closed):
    """The acceptance's self-intersection test of one run: (reasons, pairs outside the
    closed solids or None).

    No two triangles of the closed solids may intersect: each solid's surface is what a
    volume mesher fills, and two solids of an assembly must not overlap. A model whose
    every face is on a closed solid, or that has no solid, is judged on the whole mesh. A
    sheet or open shell beside closed solids (nist_ctc_02's stray face) is meshed as the
    file has it: pairs involving it are returned apart, with how many are where the CAD
    surfaces cross too, and fail nothing."""
    why = []
    per_solid = get(rep, "solids_topology", REPORT) or []
    si = get(rep, "self_intersections", REPORT)
    si_model = get(rep, "self_intersections_in_model", REPORT)
    in_solids = get(rep, "self_intersections_in_closed_solids", REPORT)
    in_solids_model = get(rep, "self_intersections_in_closed_solids_in_model", REPORT)
    on_closed = sum(len(so.get("faces", [])) for so in per_solid if so.get("closed"))
    every_face_closed = closed and on_closed >= (get(info, "faces", INFO) or 0)
    if si is None:
        return ["report has no %s" % REPORT["self_intersections"]], None
    if every_face_closed or in_solids is None or not on_closed:
        if si:
            why.append("%d self-intersections%s" % (
                si, " (%d where the CAD surfaces intersect too)" % si_model if si_model else ""))
        return why, None
    if in_solids:
        why.append("%d self-intersections between triangles of closed solids%s" % (
            in_solids, " (%d where the CAD surfaces intersect too)" % in_solids_model if in_solids_model else ""))
    return why, {"pairs": si - in_solids, "in_model": (si_model or 0) - (in_solids_model or 0)}


def medit_subset(path, faces, out):
    """Writes the triangles of mesh.mesh (Medit ASCII, ref = face id + 1) on the given
    model faces, with only the vertices they use, to `out`. False when there are none."""
    with open(path) as f:
        tok = f.read().split()
    pts, tris, i = [], [], 0
    while i < len(tok):
        w = tok[i]
        if w == "Vertices":
            n = int(tok[i + 1])
            pts = [tok[i + 2 + 4 * k: i + 5 + 4 * k] for k in range(n)]
            i += 2 + 4 * n
        elif w == "Triangles":
            n = int(tok[i + 1])
            for k in range(n):
                a, b, c, ref = tok[i + 2 + 4 * k: i + 6 + 4 * k]
                if int(ref) - 1 in faces:
                    tris.append((int(a), int(b), int(c), ref))
            i += 2 + 4 * n
        elif w == "Edges":
            i += 2 + 3 * int(tok[i + 1])
        elif w == "Corners":
            i += 2 + int(tok[i + 1])
        else:
            i += 1
    if not tris:
        return False
    used = sorted({v for t in tris for v in t[:3]})
    new = {v: k + 1 for k, v in enumerate(used)}
    with open(out, "w") as f:
        f.write("MeshVersionFormatted 2\nDimension 3\n\nVertices\n%d\n" % len(used))
        for v in used:
            f.write(" ".join(pts[v - 1][:3]) + " 0\n")
        f.write("\nTriangles\n%d\n" % len(tris))
        for a, b, c, ref in tris:
            f.write("%d %d %d %s\n" % (new[a], new[b], new[c], ref))
        f.write("\nEnd\n")
    return True


def corpus_one(ctx, model):
    name = os.path.basename(model)
    mdir = os.path.join(ctx["out"], name)
    shutil.rmtree(mdir, ignore_errors=True)
    os.makedirs(mdir)
    res = {"model": name, "variants": []}
    info, err = model_info(ctx["uvmesh"], model, mdir)
    if not info:
        res["variants"].append({"variant": "info", "reasons": [err]})
    else:
        d = get(info, "diagonal", INFO)
        res["closed"] = closed_solid(info)
        for vname, extra in (("a", []), ("b", ["--hmax", repr(d / 40.0), "--angle", "30"])):
            res["variants"].append(judge_variant(ctx, model, info, vname, extra))
    res["pass"] = all(not v["reasons"] for v in res["variants"])
    with open(os.path.join(mdir, "verdict.json"), "w") as f:
        json.dump(res, f, indent=1)
    return res


def corpus_line(res):
    parts = []
    for v in res["variants"]:
        if v["reasons"]:
            # one line a model: the tools' own multi-line messages are folded with " / "
            parts.append("%s: %s" % (v["variant"], "; ".join(re.sub(r"\s*\|\s*", " / ", w) for w in v["reasons"])))
        else:
            ex = v.get("exceptions") or {}
            parts.append("%s: ok %s s, %s triangles, Q>=3 exceptions: %s at model vertices, %s in narrow gaps" % (
                v["variant"], fmt(v.get("wall_s")), fmt(v.get("triangles")), fmt(ex.get("bad_at_corners")),
                fmt(ex.get("bad_narrow_gaps"))))
    return "%s %-32s %s" % ("PASS" if res["pass"] else "FAIL", res["model"], " | ".join(parts))


def cmd_corpus(a):
    data = shared_data()
    ctx = {"data": data, "tools": shared_tools(data), "py": sys.executable, "meshio_py": python_with("meshio"),
           "uvmesh": uvmesh_exe(a.no_build), "out": os.path.abspath(a.out), "timeout": a.timeout}
    ok, why = mesh_available(ctx["uvmesh"])
    if not ok:
        print("corpus.sh: %s -- nothing to check; exit 2" % why, file=sys.stderr)
        return 2
    if shutil.which("gmsh") is None or shutil.which("tetgen") is None:
        print("corpus.sh: gmsh and tetgen are needed (scripts/install-deps.sh)", file=sys.stderr)
        return 2
    os.makedirs(ctx["out"], exist_ok=True)
    ms = models(data, a.only, False)
    t0 = time.perf_counter()
    results = []
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, a.jobs)) as ex:
        futs = {ex.submit(corpus_one, ctx, m): m for m in ms}
        for fut in concurrent.futures.as_completed(futs):
            try:
                res = fut.result()
            except Exception as e:  # noqa: BLE001 -- a crash of the checker is a failure too
                res = {"model": os.path.basename(futs[fut]), "pass": False,
                       "variants": [{"variant": "checker", "reasons": ["internal error: %r" % (e,)]}]}
            results.append(res)
            print(corpus_line(res), flush=True)
    results.sort(key=lambda r: r["model"])
    with open(os.path.join(ctx["out"], "summary.json"), "w") as f:
        json.dump(results, f, indent=1)
    passed = [r for r in results if r["pass"]]
    failed = [r for r in results if not r["pass"]]
    reasons = {}
    for r in failed:
        for v in r["variants"]:
            for w in v["reasons"]:
                key = re.sub(r"(?<![<>\w.])[-+]?\d[\d.e+-]*", "N", w.split(":")[0])  # "Q<1.5" stays
                reasons.setdefault(key, set()).add(r["model"])
    print("")
    print("corpus: %d models, %.0f s; outputs in %s" % (len(results), time.perf_counter() - t0, ctx["out"]))
    for key, ms_ in sorted(reasons.items(), key=lambda kv: -len(kv[1])):
        print("  %3d  %s  (%s)" % (len(ms_), key, ", ".join(sorted(ms_)[:6]) + (", ..." if len(ms_) > 6 else "")))
    print("corpus: %d passed, %d failed" % (len(passed), len(failed)))
    return 0 if not failed else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = ap.add_subparsers(dest="cmd", required=True)
    b = sub.add_parser("bench", help="uvmesh vs gmsh on the corpus -> results.md")
    b.add_argument("--quick", action="store_true", help="the 6-model subset %s" % ", ".join(QUICK_MODELS))
    b.add_argument("--only", help="model file names or stems, comma-separated")
    b.add_argument("--out", default=os.path.join(ROOT, "out", "bench-surface"), help="work folder")
    b.add_argument("--results", default=os.path.join(HERE, "results.md"))
    b.add_argument("--uvmesh-timeout", type=float, default=600.0)
    b.add_argument("--gmsh-timeout", type=float, default=150.0)
    b.add_argument("--threads-min-s", type=float, default=1.0,
                   help="run --threads 2 on models whose 1-thread wall is at least this (s)")
    b.add_argument("--no-build", action="store_true")
    b.add_argument("--report-only", action="store_true",
                   help="run nothing: rewrite the results from the records an earlier run left in --out")
    c = sub.add_parser("corpus", help="acceptance of `uvmesh mesh` over the corpus")
    c.add_argument("--jobs", type=int, default=1)
    c.add_argument("--only", help="model file names or stems, comma-separated")
    c.add_argument("--out", default=os.path.join(ROOT, "out", "corpus"), help="work folder")
    c.add_argument("--timeout", type=float, default=600.0, help="per uvmesh / reader / TetGen run (s)")
    c.add_argument("--no-build", action="store_true")
    a, rest = ap.parse_known_args()
    if rest:
        ap.error("unknown arguments: %s" % " ".join(rest))
    a.argv = sys.argv[2:]
    return cmd_bench(a) if a.cmd == "bench" else cmd_corpus(a)


if __name__ == "__main__":
    sys.exit(main())
