"""uvmesh.mesh(..., volume=True): tetrahedra filling the closed solids, bounded by the
surface mesh unchanged (the volume stage of io/job.h, as `uvmesh mesh --volume`)."""
import numpy as np
import pytest

from conftest import DATA


def boundary_faces(tets):
    """The faces used by exactly one tetrahedron, each as a sorted triple."""
    faces = np.sort(np.concatenate([tets[:, [1, 2, 3]], tets[:, [0, 3, 2]],
                                    tets[:, [0, 1, 3]], tets[:, [0, 2, 1]]]), axis=1)
    uniq, count = np.unique(faces, axis=0, return_counts=True)
    return uniq[count == 1]


def test_volume_bounded_by_the_surface(uvmesh, bracket):
    m = uvmesh.mesh(bracket, volume=True, threads=2)
    assert m.tets.dtype == np.int32 and m.tets.shape[1] == 4 and len(m.tets) > 0
    assert m.tet_solids.shape == (len(m.tets),) and set(m.tet_solids.tolist()) == {0}
    assert m.failed_solids == []
    # The surface's points come first, unchanged; the boundary is exactly its triangles.
    n = len(m.points)
    assert len(m.volume_points) > n
    assert np.array_equal(m.volume_points[:n], m.points)
    tri = np.unique(np.sort(m.triangles, axis=1), axis=0)
    assert np.array_equal(boundary_faces(m.tets), tri)
    # Positive volumes, and the same counts as the report's volume section.
    p = m.volume_points[m.tets]
    vol = np.einsum("ij,ij->i", np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), p[:, 3] - p[:, 0])
    assert (vol > 0).all()
    r = m.report
    assert r["counts"]["tets"] == len(m.tets) and r["counts"]["solids_filled"] == 1
    assert r["volume"]["tets"] == len(m.tets)
    # Without volume=, no tetrahedra and no volume section.
    plain = uvmesh.mesh(bracket, threads=2)
    assert len(plain.tets) == 0 and "volume" not in plain.report


def test_volume_written_and_read_by_meshio(uvmesh, bracket, tmp_path):
    meshio = pytest.importorskip("meshio")
    m = uvmesh.mesh(bracket, volume=True, threads=2)
    for ext in ("msh", "vtu", "mesh"):
        out = tmp_path / ("bracket." + ext)
        m.write(out)
        back = meshio.read(str(out))
        tets = sum(len(c.data) for c in back.cells if c.type == "tetra")
        assert tets == len(m.tets), ext
    mm = m.to_meshio()
    assert sum(len(c.data) for c in mm.cells if c.type == "tetra") == len(m.tets)
    with pytest.raises(ValueError):
        m.write(tmp_path / "bracket.stl")  # tetrahedra go to .msh, .mesh, .vtu only


def test_volume_assembly_two_regions(uvmesh):
    # Two cubes sharing a face (read conforming): one region per solid, the interface
    # triangles shared by a tetrahedron of each.
    m = uvmesh.mesh(DATA / "cad" / "dagmc_two_cubes.stp", volume=True, threads=2)
    assert sorted(set(m.tet_solids.tolist())) == [0, 1]
    assert m.report["counts"]["solids_filled"] == 2


def test_tet_quality_of_any_tetrahedra(uvmesh, bracket):
    # The regular tetrahedron: dihedral acos(1/3) = 70.53 degrees, radius-edge sqrt(6)/4.
    s = 1 / np.sqrt(2)
    regular = [[1, 0, -s], [-1, 0, -s], [0, 1, s], [0, -1, s]]
    q = uvmesh.tet_quality(regular, [[1, 0, 2, 3]])
    assert q["tets"] == 1 and q["inverted"] == 0
    assert q["min_dihedral_deg"]["min"] == pytest.approx(np.degrees(np.arccos(1 / 3)), abs=1e-9)
    assert q["radius_edge"]["max"] == pytest.approx(np.sqrt(6) / 4, abs=1e-12)
    # Listed in the other order it is inverted; its shape measures do not change.
    flipped = uvmesh.tet_quality(regular, [[0, 1, 2, 3]])
    assert flipped["inverted"] == 1
    assert flipped["radius_edge"]["max"] == pytest.approx(np.sqrt(6) / 4, abs=1e-12)
    # On a mesh of ours it gives what the report's volume section gives.
    m = uvmesh.mesh(bracket, volume=True, threads=2)
    ours = uvmesh.tet_quality(m.volume_points, m.tets, m.tet_solids)
    v = m.report["volume"]
    for key in ("tets", "inverted", "min_dihedral_deg", "radius_edge"):
        assert ours[key] == v[key]
    with pytest.raises(ValueError):
        uvmesh.tet_quality(regular, [[0, 1, 2, 4]])
    with pytest.raises(ValueError):
        uvmesh.tet_quality(regular, [[0, 1, 2, 3]], tet_solids=[0, 0])
