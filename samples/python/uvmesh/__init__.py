"""uvmesh: mesh CAD models (STEP, IGES, BREP) and subdivision cages (OBJ) into triangle
surface meshes.

    import uvmesh
    model = uvmesh.read("part.step")          # CadReadError if it cannot be read
    m = uvmesh.mesh(model, hmax=2.5)          # MeshingError if a face cannot be meshed
    m.points, m.triangles, m.face_ids         # numpy views (float64 N x 3, int32 M x 3, M)
    m.write("part.msh")                       # any format `uvmesh mesh -o` writes

The options, their defaults and their checks are those of `uvmesh mesh` (one definition,
in the C++ library: io/job.h); a keyword left at None keeps the command line's default,
and a bad value raises ValueError with the command line's message. Nothing is global:
no session, no signal handlers, nothing printed; reading, meshing and writing release the
GIL, so threads may mesh different models at once.
"""

import json as _json
import re as _re

from ._uvmesh import Mesh, Model
from . import _uvmesh

__all__ = ["read", "mesh", "tet_quality", "Model", "Mesh", "UvmeshError", "CadReadError", "MeshingError"]

_READ_KEYWORDS = frozenset(_uvmesh._read_keywords())


class UvmeshError(Exception):
    """Base class of uvmesh's errors."""


class CadReadError(UvmeshError):
    """The model could not be read. ``path`` is the file; ``line`` the line the message
    names (a cage's ``file:LINE:``), else None; ``entity`` a STEP entity (``#123``) the
    message names, else None. ``str(err)`` is the message ``uvmesh mesh`` prints."""

    def __init__(self, message, path):
        super().__init__(message)
        self.path = path
        m = _re.match(r".*?:(\d+):", message)
        self.line = int(m.group(1)) if m else None
        m = _re.search(r"#(\d+)", message)
        self.entity = "#" + m.group(1) if m else None


class MeshingError(UvmeshError):
    """Some faces could not be meshed, or with volume=True some solids not filled.
    ``failed_faces`` lists (face id, reason); ``mesh`` is the partial Mesh, every other
    face meshed and solid filled (``mesh.failed_solids`` names those that are not;
    ``allow_holes=True`` returns it instead of raising)."""

    def __init__(self, message, failed_faces, mesh):
        super().__init__(message)
        self.failed_faces = failed_faces
        self.mesh = mesh


def read(path, *, heal=None, units=None, conform=None, any_extension=None, partial=None,
         check=None, sew_tol=None, sew_max_tol=None, scheme=None, boundary_interp=None,
         threads=None):
    """Reads a STEP, IGES or BREP file, or an OBJ subdivision cage, into a Model.

    heal (default True): ShapeFix and sewing. units: convert to this length unit ("mm",
    "inch", ...; default: the file's). conform (default True): imprint touching solids.
    scheme ("auto", "catmark", "loop") and boundary_interp: for .obj cages. Others as the
    command line's --any-extension, --partial, --no-check (check=False), --sew-tol,
    --sew-max-tol. Raises CadReadError, or ValueError for a bad option.
    """
    options = dict(heal=heal, units=units, conform=conform, any_extension=any_extension,
                   partial=partial, check=check, sew_tol=sew_tol, sew_max_tol=sew_max_tol,
                   scheme=scheme, boundary_interp=boundary_interp, threads=threads)
    path = str(path)
    model, error = _uvmesh._read(path, options)
    if error is not None:
        raise CadReadError(error, path)
    return model


def mesh(model, *, hmax=None, hmin=None, chordal=None, angle=None, grad=None,
         face_sizes=None, edge_sizes=None, threads=None, progress=None, hmax_rel=None,
         aniso=None, min_feature=None, feature_angle=None, keep_topology=None,
         size_file=None, face_time_limit=None, optimize3d=None, self_intersections=None,
         volume=None, frontal=None, allow_holes=False, **read_options):
    """Meshes a Model, or the file at a path (read with ``read_options``, the keywords of
    read(), e.g. ``scheme="loop"`` for an OBJ cage), into a Mesh.

    Sizes in model units, None: the command line's default (D = bounding-box diagonal:
    hmax D/20, hmin D/1000, chordal D/1000, angle 18 degrees, grad 1.3). face_sizes /
    edge_sizes: {id: size}. threads: 0 = all cores. progress(done, total): called as faces
    are meshed (with the GIL; an exception it raises is raised by mesh() when meshing is
    over). face_time_limit: seconds per face (120; 0 = none). frontal=True: frontal point
    placement (--frontal). self_intersections: the
    report's search. volume=True also fills every closed solid with tetrahedra (Netgen)
    bounded by the surface mesh unchanged: Mesh.tets (K x 4, indices into
    Mesh.volume_points, whose first rows are Mesh.points) and Mesh.tet_solids. Raises
    MeshingError when faces fail or solids are not filled (unless allow_holes), ValueError
    for a bad option.
    """
    unknown = set(read_options) - _READ_KEYWORDS
    if unknown:
        raise TypeError("mesh() got an unexpected keyword argument '%s'" % sorted(unknown)[0])
    if not isinstance(model, Model):
        model = read(model, threads=threads, **read_options)
    elif any(v is not None for v in read_options.values()):
        key = next(k for k, v in read_options.items() if v is not None)
        raise ValueError("%s= applies when reading a file: pass a path, or give it to "
                         "uvmesh.read()" % key)
    # The keywords are MeshJobOptions' fields (io/job.h) by name, each with a setter in
    # module.cpp: a new option of the job is one field, one setter and one keyword here.
    options = dict(hmax=hmax, hmin=hmin, chordal=chordal, angle=angle, grad=grad,
                   face_sizes=face_sizes, edge_sizes=edge_sizes, threads=threads,
                   hmax_rel=hmax_rel, aniso=aniso, min_feature=min_feature,
                   feature_angle=feature_angle, keep_topology=keep_topology,
                   size_file=size_file, face_time_limit=face_time_limit,
                   optimize3d=optimize3d, self_intersections=self_intersections,
                   volume=volume, frontal=frontal)
    result = _uvmesh._mesh(model, options, progress)
    failed = result.failed_faces
    if failed and not allow_holes:
        raise MeshingError("%d face(s) could not be meshed (%s)" % (
            len(failed), "; ".join("face %d: %s" % f for f in failed[:5])), failed, result)
    if result.failed_solids and not allow_holes:
        raise MeshingError("%d solid(s) could not be filled (%s)" % (
            len(result.failed_solids), "; ".join(result.failed_solids[:5])), [], result)
    return result


def tet_quality(points, tets, tet_solids=None):
    """The quality of any tetrahedral mesh (another mesher's too), as the report's
    ``volume`` section gives it for ``volume=True``: ``tets``, ``inverted`` (volume <= 0),
    ``volume``, ``min_dihedral_deg`` {min, p01, median} and ``radius_edge`` {max, p99,
    median} (circumradius / shortest edge), whole and per solid. ``points``: N x 3;
    ``tets``: M x 4 0-based indices; ``tet_solids``: M solid ids (default all 0)."""
    import numpy
    tets = numpy.asarray(tets).reshape(-1, 4)
    if tet_solids is None:
        tet_solids = numpy.zeros(len(tets), dtype=numpy.int64)
    return _json.loads(_uvmesh._tet_quality(numpy.asarray(points, dtype=numpy.float64).reshape(-1, 3),
                                            tets, numpy.asarray(tet_solids).reshape(-1)))


def _report(self):
    """The JSON report of ``uvmesh mesh --report`` as a dict (made on first use: it runs
    the quality, topology, chordal and self-intersection checks)."""
    return _json.loads(self._report_json)


def _to_meshio(self):
    """A meshio.Mesh (triangles, cell data "face_id"; with volume=True also the
    tetrahedra, cell data "solid_id", -1 on triangles and "face_id" -1 on tetrahedra);
    needs meshio."""
    import meshio
    import numpy
    if len(self.tets) == 0:
        return meshio.Mesh(self.points, [("triangle", self.triangles)],
                           cell_data={"face_id": [self.face_ids]})
    none_t = numpy.full(len(self.triangles), -1, dtype=numpy.int32)
    none_k = numpy.full(len(self.tets), -1, dtype=numpy.int32)
    return meshio.Mesh(self.volume_points,
                       [("triangle", self.triangles), ("tetra", self.tets)],
                       cell_data={"face_id": [self.face_ids, none_k],
                                  "solid_id": [none_t, self.tet_solids]})


Mesh.report = property(_report)
Mesh.to_meshio = _to_meshio
