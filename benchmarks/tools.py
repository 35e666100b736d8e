"""The tools being compared, each called the way a user would call it.

A parameterization is a function ``(V, F) -> (uv, stage_times)``. A remesher is a
:class:`Remesher`: a function ``run(V, F, param) -> (V, F, stage_times)`` and the first
value of the parameter that sets its face count. Tools that take an edge length instead
of a face count are calibrated by worker.py. Nothing here times or measures anything:
worker.py does that the same way for every tool. Each tool imports its package when it
is called, so a missing package skips that tool only.
"""

from __future__ import annotations

import importlib
from dataclasses import dataclass
from typing import Callable

import numpy as np

import qcremesh
from qcremesh.geometry.operators import doublearea
from qcremesh.remeshing.relax import SNAP_REACH


class Unavailable(Exception):
    """The tool cannot run here (package not installed, function not written yet)."""


def _require(module):
    try:
        return importlib.import_module(module)
    except ImportError as error:
        raise Unavailable(f"{module} is not installed ({error})") from error


# Parameterizations --------------------------------------------------------------------


def qcremesh_disk(V, F):
    result = qcremesh.disk_conformal_map(V, F)
    return result.uv, result.times


def tutte(V, F):
    return qcremesh.tutte_embedding(F), {}


def igl_harmonic(V, F):
    """Harmonic map with cotangent weights, boundary on the circle by arc length."""
    igl = _require("igl")
    bnd = igl.boundary_loop(F)
    bnd_uv = igl.map_vertices_to_circle(np.asfortranarray(V), bnd.astype(np.int32))
    return igl.harmonic(V, F, bnd, bnd_uv, 1), {}


def igl_lscm(V, F):
    """Least-squares conformal map, free boundary, two opposite boundary vertices pinned."""
    igl = _require("igl")
    bnd = igl.boundary_loop(F)
    pinned = bnd[[0, len(bnd) // 2]]
    uv, _ = igl.lscm(V, F, pinned, np.array([[0.0, 0.0], [1.0, 0.0]]))
    return uv, {}


PARAMETERIZATIONS = {
    "qcremesh": qcremesh_disk,
    "tutte": tutte,
    "igl_harmonic": igl_harmonic,
    "igl_lscm": igl_lscm,
}


# Remeshers ----------------------------------------------------------------------------


def edge_length_for(V, F, faces):
    """Edge length of the equilateral triangles that tile the surface with ``faces`` faces
    (area of one: sqrt(3) / 4 l^2)."""
    area = doublearea(V, F).sum() / 2
    return float(np.sqrt(4 * area / (np.sqrt(3) * faces)))


@dataclass(frozen=True)
class Remesher:
    """``run(V, F, param) -> (V, F, stage_times)``; ``initial(V, F, faces)`` is the first
    parameter; ``by_length`` tools take a target edge length, which the worker corrects
    by sqrt(faces achieved / faces wanted) until the count is close enough."""

    run: Callable
    initial: Callable
    by_length: bool
    setting: str


def _qcremesh_remesh(V, F, faces):
    remesh = getattr(qcremesh, "remesh", None)
    if remesh is None:
        raise Unavailable("not available: qcremesh.remesh is not in this version of qcremesh")
    result = remesh(V, F, faces=faces, seed=0)
    return result.V, result.F, dict(getattr(result, "times", {}))


def qcremesh_variant(method, relax, seed=0, sizing=None, creases=None, snap=SNAP_REACH):
    """qcremesh.remesh with one of the paper's ablations (``method``), ``relax``
    relaxation sweeps (0: the paper's pipeline alone), the CVT ``seed``, a ``sizing``
    (None: uniform), ``creases`` (an angle in degrees, or None) and the snapping's reach
    ``snap``."""

    def run(V, F, faces):
        result = qcremesh.remesh(
            V, F, faces=faces, seed=seed, method=method, relax=relax, sizing=sizing, creases=creases, snap=snap
        )
        return result.V, result.F, dict(result.times, draws=result.stats.get("draws", 1))

    return Remesher(
        run,
        lambda V, F, faces: faces,
        False,
        f"remesh(V, F, faces=N, method={method!r}, relax={relax}, seed={seed}, sizing={sizing!r}, "
        f"creases={creases!r}, snap={snap})",
    )


def _pymeshlab(V, F, length):
    pymeshlab = _require("pymeshlab")
    ms = pymeshlab.MeshSet()
    ms.add_mesh(pymeshlab.Mesh(vertex_matrix=V, face_matrix=F))
    ms.meshing_isotropic_explicit_remeshing(targetlen=pymeshlab.PureValue(length))
    mesh = ms.current_mesh()
    return mesh.vertex_matrix(), mesh.face_matrix(), {}


ACVD_SUBDIVISIONS = 2


def _pyacvd(V, F, clusters):
    pyacvd = _require("pyacvd")
    pyvista = _require("pyvista")
    clustering = pyacvd.Clustering(pyvista.make_tri_mesh(V, F))
    clustering.subdivide(ACVD_SUBDIVISIONS)
    clustering.cluster(clusters)
    mesh = clustering.create_mesh()
    return np.asarray(mesh.points, dtype=np.float64), mesh.faces.reshape(-1, 4)[:, 1:], {}


def _botsch(V, F, length):
    gpytoolbox = _require("gpytoolbox")
    U, G = gpytoolbox.remesh_botsch(V, F, 10, length)
    return U, G, {}


REMESHERS = {
    "qcremesh": Remesher(
        _qcremesh_remesh,
        lambda V, F, faces: faces,
        False,
        "remesh(V, F, faces=N, seed=0)",
    ),
    "pymeshlab": Remesher(
        _pymeshlab,
        edge_length_for,
        True,
        "meshing_isotropic_explicit_remeshing, 10 iterations, targetlen calibrated; "
        "boundary vertices stay on the input boundary (no freeze option)",
    ),
    "pyacvd": Remesher(
        _pyacvd,
        lambda V, F, faces: faces // 2,
        False,
        f"Clustering on the input subdivided {ACVD_SUBDIVISIONS} times, N/2 clusters",
    ),
    "botsch": Remesher(
        _botsch,
        edge_length_for,
        True,
        "gpytoolbox remesh_botsch, 10 iterations, h calibrated; boundary vertices frozen",
    ),
}
