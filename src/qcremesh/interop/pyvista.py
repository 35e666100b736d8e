"""Remeshing of pyvista's surfaces.

:func:`remesh_pyvista` takes a :class:`pyvista.PolyData` and returns one, with its point
data (scalars, vectors, texture coordinates, normals) carried along.
"""

from __future__ import annotations

import numpy as np

from ..remeshing.pipeline import remesh
from . import require

__all__ = ["from_pyvista", "to_pyvista", "remesh_pyvista"]



def from_pyvista(mesh):
    """The arrays of a :class:`pyvista.PolyData`'s faces; polygons of more than three
    corners are triangulated first (:meth:`pyvista.PolyData.triangulate`), lines and
    vertex cells left out.

    Parameters
    ----------
    mesh : pyvista.PolyData

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64
    data : dict of str to (n, ...) array
        The numeric point data arrays, by name.

    Raises
    ------
    TypeError
        ``mesh`` is not a PolyData (``mesh.extract_surface()`` gives the surface of
        another dataset).
    ValueError
        It has no faces.
    """
    pv = require("pyvista")
    if not isinstance(mesh, pv.PolyData):
        hint = ": mesh.extract_surface() gives its surface" if isinstance(mesh, pv.DataSet) else ""
        raise TypeError(f"expected a pyvista.PolyData, got {type(mesh).__name__}{hint}")
    if mesh.faces.size == 0 and mesh.n_strips == 0:
        raise ValueError("the PolyData has no faces (polygons or triangle strips)")
    if not mesh.is_all_triangles or mesh.n_strips:
        mesh = mesh.triangulate()  # (the faces below are its polygons: lines and vertices left out)
    V = np.array(mesh.points, dtype=np.float64)
    F = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 4)[:, 1:].copy()
    return V, F, _point_arrays(mesh)


def _point_arrays(mesh):
    """Numeric point data of ``mesh``, by name."""
    out = {}
    for name in mesh.point_data.keys():
        values = np.asarray(mesh.point_data[name])
        if values.dtype.kind in "biuf" and len(values) == mesh.n_points:
            out[name] = values
    return out


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
    pv = require("pyvista")
    F = np.asarray(F, dtype=np.int64)
    cells = np.column_stack([np.full(len(F), 3, dtype=np.int64), F]).ravel()
    out = pv.PolyData(np.asarray(V, dtype=np.float64), faces=cells)
    for name, values in (data or {}).items():
        out.point_data[name] = values
    return out


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
