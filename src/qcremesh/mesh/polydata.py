"""VTK polygonal data (pyvista's :class:`pyvista.PolyData`, the .vtp files and the legacy
.vtk files of POLYDATA) as the arrays of a triangle mesh, and back. pyvista is an optional
dependency: the callers pass its module."""

from __future__ import annotations

import numpy as np

__all__ = ["polydata_to_arrays", "arrays_to_polydata"]


def polydata_to_arrays(mesh, pv):
    """The arrays of a :class:`pyvista.PolyData`'s faces; polygons of more than three
    corners and triangle strips are triangulated first
    (:meth:`pyvista.PolyData.triangulate`), lines and vertex cells left out.

    Parameters
    ----------
    mesh : pyvista.PolyData
    pv : module
        pyvista.

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
    if not isinstance(mesh, pv.PolyData):
        hint = ": mesh.extract_surface() gives its surface" if isinstance(mesh, pv.DataSet) else ""
        raise TypeError(f"expected a pyvista.PolyData, got {type(mesh).__name__}{hint}")
    if mesh.faces.size == 0 and mesh.n_strips == 0:
        raise ValueError("the PolyData has no faces (polygons or triangle strips)")
    if not mesh.is_all_triangles or mesh.n_strips:
        mesh = mesh.triangulate()  # (the faces below are its polygons: lines and vertices left out)
    V = np.array(mesh.points, dtype=np.float64)
    F = np.asarray(mesh.faces, dtype=np.int64).reshape(-1, 4)[:, 1:].copy()
    data = {}
    for name in mesh.point_data.keys():
        values = np.asarray(mesh.point_data[name])
        if values.dtype.kind in "biuf" and len(values) == mesh.n_points:
            data[name] = values
    return V, F, data


def arrays_to_polydata(V, F, data, pv):
    """A :class:`pyvista.PolyData` of triangles.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    data : dict of str to (n, ...) array or None
        Point data, by name.
    pv : module
        pyvista.

    Returns
    -------
    pyvista.PolyData
    """
    F = np.asarray(F, dtype=np.int64)
    cells = np.column_stack([np.full(len(F), 3, dtype=np.int64), F]).ravel()
    out = pv.PolyData(np.asarray(V, dtype=np.float64), faces=cells)
    for name, values in (data or {}).items():
        out.point_data[name] = values
    return out
