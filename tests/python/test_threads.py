"""Two threads meshing two models at once give the arrays of one run after the other."""
import threading

import numpy as np

from conftest import BRACKET, DATA


def _arrays(m):
    return [a.copy() for a in (m.points, m.triangles, m.face_ids, m.edges, m.edge_curve_ids)]


def test_concurrent_equals_sequential(uvmesh):
    jobs = [(BRACKET, dict(hmax=6.0)), (DATA / "subd" / "catmark_cube.obj", dict())]
    sequential = [_arrays(uvmesh.mesh(p, threads=1, **kw)) for p, kw in jobs]
    results, errors = [None, None], []

    def run(i):
        try:
            path, kw = jobs[i]
            results[i] = _arrays(uvmesh.mesh(path, threads=1, **kw))
        except Exception as e:  # pragma: no cover - reported below
            errors.append(e)

    threads = [threading.Thread(target=run, args=(i,)) for i in range(2)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert not errors
    for seq, par in zip(sequential, results):
        for a, b in zip(seq, par):
            assert np.array_equal(a, b)


def test_gil_released(uvmesh):
    # While a thread meshes, another runs Python code: the GIL is not held by meshing.
    model = uvmesh.read(BRACKET)
    ticks = []
    done = threading.Event()

    def tick():
        while not done.is_set():
            ticks.append(1)
            done.wait(0.001)

    t = threading.Thread(target=tick)
    t.start()
    try:
        uvmesh.mesh(model, threads=1, hmax=3.0)
    finally:
        done.set()
        t.join()
    assert len(ticks) > 5
