"""uvmesh's Python API: reading, meshing, arrays, writing, errors, silence."""
import json
import os
import subprocess

import numpy as np
import pytest

from conftest import BRACKET, DATA

UVMESH_EXE = os.environ.get("UVMESH_EXE")


def test_read_counts(uvmesh, bracket):
    # samples/data/bracket.step: one solid, 26 faces (README, tests/samples).
    assert bracket.counts["faces"] == 26
    assert bracket.counts["solids"] == 1
    assert len(bracket.faces) == 26 and len(bracket.edges) == bracket.counts["edges"]
    assert bracket.units == "mm" and bracket.format == "step"
    kinds = {f["kind"] for f in bracket.faces}
    assert "planar" in kinds and "cylinder" in kinds
    assert [f["id"] for f in bracket.faces] == list(range(26))
    assert sorted(bracket.solids[0]["faces"]) == list(range(26))
    assert isinstance(bracket.warnings, list)
    assert {h["name"] for h in bracket.healing} <= {"shapefix", "sewing", "conform"}


def test_read_units(uvmesh):
    m = uvmesh.read(BRACKET, units="m")
    mm = uvmesh.read(BRACKET)
    assert m.units == "m"
    assert m.bbox[1][0] == pytest.approx(mm.bbox[1][0] / 1000)


def test_mesh_arrays(bracket_mesh, bracket):
    m = bracket_mesh
    p, t, f, e, c = m.points, m.triangles, m.face_ids, m.edges, m.edge_curve_ids
    assert p.dtype == np.float64 and p.ndim == 2 and p.shape[1] == 3
    assert t.dtype == np.int32 and t.ndim == 2 and t.shape[1] == 3
    assert f.dtype == np.int32 and f.shape == (t.shape[0],)
    assert e.dtype == np.int32 and e.shape[1] == 2 and c.shape == (e.shape[0],)
    assert len(p) > 100 and len(t) > 100
    # 0-based indices into points, every face meshed, every edge's curve a model edge.
    assert t.min() == 0 and t.max() == len(p) - 1
    assert set(np.unique(f)) == set(range(26))
    assert e.min() >= 0 and e.max() < len(p)
    assert c.min() >= 0 and c.max() < bracket.counts["edges"]
    assert m.failed_faces == []


def test_arrays_without_copies(uvmesh, bracket):
    m = uvmesh.mesh(bracket, threads=1)
    for a in (m.points, m.triangles, m.face_ids, m.edges, m.edge_curve_ids):
        assert a.base is not None and not a.flags.owndata and not a.flags.writeable
    # edges and edge_curve_ids are interleaved views of one vector of segments; the views
    # keep the mesh alive.
    assert np.may_share_memory(m.edges, m.edge_curve_ids)
    assert m.edges.strides == (12, 4) and m.edge_curve_ids.strides == (12,)
    pts = m.points
    expected = pts.copy()
    del m
    assert np.array_equal(pts, expected)


def test_report_is_the_cli_report(uvmesh, bracket_mesh, tmp_path):
    r = bracket_mesh.report
    assert r["counts"]["faces"] == 26 and r["counts"]["faces_failed"] == 0
    assert r["counts"]["triangles"] == len(bracket_mesh.triangles)
    assert r["output"] is None and r["model"] == str(BRACKET)
    # The CLI's --report has the same keys.
    out, rep = tmp_path / "b.msh", tmp_path / "b.json"
    subprocess.run([UVMESH_EXE, "mesh", str(BRACKET), "-o", str(out), "--report", str(rep),
                    "--threads", "2", "-q"], check=True)
    cli = json.loads(rep.read_text())
    assert set(cli) == set(r)
    assert cli["counts"]["triangles"] == r["counts"]["triangles"]
    assert cli["size"] == r["size"]


def test_same_mesh_as_cli(uvmesh, bracket_mesh, tmp_path):
    out = tmp_path / "b.obj"
    subprocess.run([UVMESH_EXE, "mesh", str(BRACKET), "-o", str(out), "-q"], check=True)
    v = [l for l in out.read_text().splitlines() if l.startswith("v ")]
    pts = np.array([[float(x) for x in l.split()[1:4]] for l in v])
    assert np.array_equal(pts, bracket_mesh.points)


def _triangles_read_back(path):
    """The triangle count of a written file, read back by `uvmesh check` or meshio."""
    ext = path.suffix
    if ext in (".msh", ".mesh", ".meshb", ".stl", ".obj", ".ply", ".drc"):
        out = subprocess.run([UVMESH_EXE, "check", str(path), "--json", "--no-selfint"],
                             check=True, capture_output=True, text=True).stdout
        return json.loads(out)["counts"]["triangles"]
    if ext in (".vtk", ".vtu"):
        meshio = pytest.importorskip("meshio")
        return len(meshio.read(path).get_cells_type("triangle"))
    if ext in (".poly", ".smesh"):
        lines = [l for l in path.read_text().splitlines() if l.strip() and l[0] != "#"]
        npts = int(lines[0].split()[0])
        return int(lines[1 + npts].split()[0])  # one facet per triangle
    assert ext == ".glb"
    assert path.read_bytes()[:4] == b"glTF"
    return None


FORMATS = [".msh", ".mesh", ".meshb", ".stl", ".obj", ".ply", ".vtk", ".vtu", ".poly",
           ".smesh", ".drc", ".glb"]


@pytest.mark.parametrize("ext", FORMATS)
def test_write_every_format(bracket_mesh, tmp_path, ext):
    path = tmp_path / ("bracket" + ext)
    bracket_mesh.write(path)
    n = _triangles_read_back(path)
    if n is not None:
        assert n == len(bracket_mesh.triangles)


def test_write_options(uvmesh, bracket_mesh, tmp_path):
    bracket_mesh.write(tmp_path / "a.msh", format="msh22")
    assert (tmp_path / "a.msh").read_text().startswith("$MeshFormat\n2.2")
    bracket_mesh.write(tmp_path / "a.stl", ascii=True)
    assert (tmp_path / "a.stl").read_text().startswith("solid")
    with pytest.raises(ValueError, match="unknown mesh extension"):
        bracket_mesh.write(tmp_path / "a.xyz")
    with pytest.raises(ValueError, match="unknown format 'nope'"):
        bracket_mesh.write(tmp_path / "a.msh", format="nope")
    with pytest.raises(OSError):
        bracket_mesh.write(tmp_path / "missing-dir" / "a.msh")
    bracket_mesh.write(tmp_path / "r.msh")
    assert bracket_mesh.report["output"] == str(tmp_path / "r.msh")


def test_to_meshio(bracket_mesh):
    pytest.importorskip("meshio")
    mm = bracket_mesh.to_meshio()
    assert np.array_equal(mm.points, bracket_mesh.points)
    assert np.array_equal(mm.get_cells_type("triangle"), bracket_mesh.triangles)
    assert np.array_equal(mm.cell_data["face_id"][0], bracket_mesh.face_ids)


BAD = sorted(p for p in (DATA / "bad").iterdir()
             if p.name not in ("occt_bad_header.igs", "occt_bearing_axis.brep",
                               "occt_corrupted.stp")) if (DATA / "bad").is_dir() else []


@pytest.mark.parametrize("path", BAD, ids=[p.name for p in BAD])
def test_cad_read_error(uvmesh, path):
    # The corpus' rejected files (tests/robustness/bad_inputs.sh); the three it expects
    # to load are left out.
    with pytest.raises(uvmesh.CadReadError) as e:
        uvmesh.read(path)
    assert path.name in str(e.value) and e.value.path == str(path)
    with pytest.raises(uvmesh.CadReadError):
        uvmesh.mesh(path)


def test_bad_corpus_present():
    assert len(BAD) >= 8, "the shared corpus' bad/ folder is missing: %s" % DATA


def test_cad_read_error_line(uvmesh, tmp_path):
    cage = tmp_path / "cage.obj"
    cage.write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 9\n")
    with pytest.raises(uvmesh.CadReadError) as e:
        uvmesh.read(cage)
    assert e.value.line == 4, str(e.value)
    with pytest.raises(uvmesh.CadReadError, match="nothing.step"):
        uvmesh.read(tmp_path / "nothing.step")


@pytest.mark.parametrize("kw, message", [
    (dict(hmin=5, hmax=1), "--hmin 5 is larger than hmax 1"),
    (dict(hmax=-1), "--hmax: expected a finite number > 0"),
    (dict(hmin=float("nan")), "--hmin: expected a finite number > 0"),
    (dict(grad=0.5), "--grad"),
    (dict(angle=500), "--angle"),
    (dict(face_sizes={3: -1.0}), "expected ID=SIZE"),
    (dict(face_sizes={100000: 1.0}), "--face-size names face 100000"),
    (dict(hmin=1e6), "is larger than hmax"),
    (dict(scheme="bogus"), "--scheme"),
    (dict(units="furlong"), "unknown length unit 'furlong'"),
])
def test_value_errors(uvmesh, kw, message):
    with pytest.raises(ValueError) as e:
        uvmesh.mesh(BRACKET, **kw)
    assert message in str(e.value)


def test_bad_keywords(uvmesh, bracket):
    with pytest.raises(TypeError):
        uvmesh.mesh(bracket, hmaxx=1)
    with pytest.raises(TypeError):
        uvmesh.mesh(bracket, hmax="big")
    with pytest.raises(ValueError, match="heal= applies when reading"):
        uvmesh.mesh(bracket, heal=False)


def test_cli_gives_the_same_messages(bracket, tmp_path):
    r = subprocess.run([UVMESH_EXE, "mesh", str(BRACKET), "-o", str(tmp_path / "x.msh"),
                        "--face-size", "100000=1"], capture_output=True, text=True)
    assert r.returncode == 1
    assert "--face-size names face 100000 but the model has 26 faces" in r.stderr


def test_meshing_error(uvmesh, bracket):
    # A face time limit no face can meet: every face fails.
    with pytest.raises(uvmesh.MeshingError) as e:
        uvmesh.mesh(bracket, face_time_limit=1e-9, threads=1)
    err = e.value
    assert err.failed_faces and all(isinstance(f, int) and r for f, r in err.failed_faces)
    assert isinstance(err.mesh, uvmesh.Mesh)
    assert err.mesh.failed_faces == err.failed_faces
    assert not set(f for f, _ in err.failed_faces) & set(np.unique(err.mesh.face_ids))
    m = uvmesh.mesh(bracket, face_time_limit=1e-9, threads=1, allow_holes=True)
    assert m.failed_faces == err.failed_faces


def test_nothing_printed(uvmesh, capfd, tmp_path):
    model = uvmesh.read(BRACKET)
    m = uvmesh.mesh(model, threads=2)
    m.write(tmp_path / "q.msh")
    _ = m.report
    with pytest.raises(uvmesh.CadReadError):
        uvmesh.read(DATA / "bad" / "synth_truncated.stp")
    with pytest.raises(uvmesh.MeshingError):
        uvmesh.mesh(model, face_time_limit=1e-9)
    out, err = capfd.readouterr()
    assert out == "" and err == ""


def test_no_signal_handlers(uvmesh):
    import signal
    before = {s: signal.getsignal(s) for s in (signal.SIGSEGV, signal.SIGFPE, signal.SIGINT)}
    uvmesh.mesh(uvmesh.read(BRACKET), threads=1)
    assert before == {s: signal.getsignal(s) for s in before}


def test_progress(uvmesh, bracket):
    calls = []
    uvmesh.mesh(bracket, threads=2, progress=lambda done, total: calls.append((done, total)))
    assert calls and calls[-1][1] == 26 and max(d for d, _ in calls) == 26

    def boom(done, total):
        raise KeyError("stop")

    with pytest.raises(KeyError):
        uvmesh.mesh(bracket, threads=2, progress=boom)
    with pytest.raises(TypeError):
        uvmesh.mesh(bracket, progress=3)


def test_obj_cage(uvmesh):
    cage = DATA / "subd" / "catmark_cube.obj"
    m = uvmesh.mesh(cage, scheme="catmark", threads=2)
    assert len(m.triangles) > 0 and m.failed_faces == []
    assert m.model.format != "step"
    loop = uvmesh.mesh(DATA / "subd" / "loop_icosahedron.obj", scheme="loop", hmax=0.3)
    assert len(loop.triangles) > 0
    with pytest.raises(ValueError, match="--scheme"):
        uvmesh.mesh(cage, scheme="butterfly")


def test_mesh_a_path_with_read_options(uvmesh):
    m = uvmesh.mesh(BRACKET, heal=False, units="cm", hmax=0.8, self_intersections=False,
                    threads=2)
    assert m.model.units == "cm" and m.failed_faces == []
    r = m.report
    assert r["size"]["hmax"] == 0.8 and r["units"] == "cm"
    assert all(not h["applied"] for h in r["read"]["healing"])


def test_cli_and_python_accept_the_same_values(uvmesh, tmp_path):
    # The bounds are one table (io/job.h check_option_value): the CLI's message for a bad
    # value is the one ValueError carries.
    for flag, kw, value in [("--grad", "grad", "0.5"), ("--hmax", "hmax", "-2"),
                            ("--angle", "angle", "200")]:
        r = subprocess.run([UVMESH_EXE, "mesh", str(BRACKET), "-o", str(tmp_path / "x.msh"),
                            flag, value], capture_output=True, text=True)
        assert r.returncode == 1
        with pytest.raises(ValueError) as e:
            uvmesh.mesh(BRACKET, **{kw: float(value)})
        detail = str(e.value).split(": ", 1)[1]
        assert detail in r.stderr, (r.stderr, str(e.value))
