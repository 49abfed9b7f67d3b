"""Shared fixtures of the Python module's tests: the bundled bracket, read once."""
import os
import pathlib

import pytest

SOURCE = pathlib.Path(os.environ.get("UVMESH_SOURCE_DIR",
                                     pathlib.Path(__file__).resolve().parents[2]))
DATA = pathlib.Path(os.environ.get("UVMESH_SHARED_DATA", SOURCE.parent / "shared" / "data"))
BRACKET = SOURCE / "samples" / "data" / "bracket.step"


@pytest.fixture(scope="session")
def uvmesh():
    import uvmesh as module
    return module


@pytest.fixture(scope="session")
def bracket(uvmesh):
    return uvmesh.read(BRACKET)


@pytest.fixture(scope="session")
def bracket_mesh(uvmesh, bracket):
    return uvmesh.mesh(bracket, threads=2)
