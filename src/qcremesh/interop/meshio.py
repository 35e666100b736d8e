"""Remeshing of meshio's meshes.

:func:`remesh_meshio` takes a :class:`meshio.Mesh` and returns one of triangles, with its
point data carried along (interpolated at the new vertices, each array in its type).
"""

from __future__ import annotations

import numpy as np

from ..mesh.io import meshio_to_arrays
from ..remeshing.pipeline import remesh
from . import require

__all__ = ["from_meshio", "to_meshio", "remesh_meshio"]


def from_meshio(mesh):
    """The arrays (V, F (m, 3) int64, data) of a :class:`meshio.Mesh`'s surface: its
    points, its triangles, quads and convex polygons as triangles, and its point data
    by name (:func:`qcremesh.mesh.io.meshio_to_arrays`). Raises TypeError for what is
    not a meshio.Mesh and :class:`qcremesh.mesh.io.MeshReadError` (a ValueError) for a
    mesh of other cells (a volume mesh) or of none of those."""
    if not isinstance(mesh, require("meshio").Mesh):
        raise TypeError(f"expected a meshio.Mesh, got {type(mesh).__name__}")
    return meshio_to_arrays(mesh, "meshio.Mesh")


def to_meshio(V, F, data=None):
    """A :class:`meshio.Mesh` of triangles.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    data : dict of str to (n, ...) array, optional
        Point data, by name.

    Returns
    -------
    meshio.Mesh
    """
    meshio = require("meshio")
    return meshio.Mesh(np.asarray(V), [("triangle", np.asarray(F))], point_data=dict(data or {}))


def remesh_meshio(mesh, faces=None, **options):
    """:func:`qcremesh.remesh` of a :class:`meshio.Mesh`.

    Parameters
    ----------
    mesh : meshio.Mesh
        Triangles, quads or convex polygons (vertex and line cells are left out).
    faces : int, optional
        Face count wanted (default: the input's triangle count, quads counting two).
    **options
        The keyword arguments of :func:`qcremesh.remesh` (``seed``, ``levels``,
        ``edge_length``, ``sizing``, ``creases``, ...), but ``data``: the mesh's own
        point data is carried.

    Returns
    -------
    meshio.Mesh
        The remeshed surface, its point data interpolated at its vertices. Cell data is
        not carried (the faces are new); the run's numbers
        (:attr:`qcremesh.RemeshResult.stats`) are in ``info["qcremesh"]``.
    """
    if "data" in options:
        raise TypeError("remesh_meshio carries the mesh's own point data; data= is not taken")
    V, F, data = from_meshio(mesh)
    result = remesh(V, F, faces, data=data, **options)
    out = to_meshio(result.V, result.F, result.data)
    out.info = {"qcremesh": result.stats}
    return out
