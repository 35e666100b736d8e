"""Remeshing of pyvista's surfaces.

:func:`remesh_pyvista` takes a :class:`pyvista.PolyData` and returns one, with its point
data (scalars, vectors, texture coordinates, normals) carried along.
"""

from __future__ import annotations

import numpy as np

from ..mesh.polydata import arrays_to_polydata, polydata_to_arrays
from ..remeshing.pipeline import remesh
from . import require

__all__ = ["from_pyvista", "to_pyvista", "remesh_pyvista"]


def from_pyvista(mesh):
    """The arrays (V (n, 3), F (m, 3), data) of a :class:`pyvista.PolyData`'s faces, its
    numeric point data by name: :func:`qcremesh.mesh.polydata.polydata_to_arrays`, which
    triangulates polygons of more than three corners, leaves out lines and vertex cells,
    and raises TypeError for a dataset that is not a PolyData and ValueError for one
    without faces.
    """
    return polydata_to_arrays(mesh, require("pyvista"))


def to_pyvista(V, F, data=None):
    """A :class:`pyvista.PolyData` of triangles.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    data : dict of str to (n, ...) array, optional
        Point data, by name.

    Returns
    -------
    pyvista.PolyData
    """
    return arrays_to_polydata(V, F, data, require("pyvista"))


def remesh_pyvista(mesh, faces=None, **options):
    """:func:`qcremesh.remesh` of a :class:`pyvista.PolyData`.

    Parameters
    ----------
    mesh : pyvista.PolyData
    faces : int, optional
        Face count wanted (default: the input's triangle count).
    **options
        The keyword arguments of :func:`qcremesh.remesh` (``seed``, ``levels``,
        ``sizing``, ``creases``, ...), but ``data``: the mesh's own point data is
        carried.

    Returns
    -------
    pyvista.PolyData
        The remeshed surface with the input's point data interpolated at its vertices
        (in their types: colours as bytes stay bytes), the active scalars, vectors and
        texture coordinates as in the input, and the active normals made unit vectors
        again. Cell data is not carried (the faces are new).
    """
    if "data" in options:
        raise TypeError("remesh_pyvista carries the mesh's own point data; data= is not taken")
    V, F, data = from_pyvista(mesh)
    result = remesh(V, F, faces, data=data, **options)
    point_data = dict(result.data)
    normals = mesh.point_data.active_normals_name
    if normals in point_data:
        n = point_data[normals]
        length = np.linalg.norm(n, axis=1, keepdims=True)
        point_data[normals] = np.where(length > 0, n / np.where(length > 0, length, 1), n).astype(n.dtype)
    out = to_pyvista(result.V, result.F, point_data)
    for kind in ("scalars", "vectors", "normals", "texture_coordinates"):
        name = getattr(mesh.point_data, f"active_{kind}_name")
        if name in point_data:
            setattr(out.point_data, f"active_{kind}_name", name)
    return out
