"""Projection of points of the disk onto the surface (step 3 of the paper's Algorithm 2):
barycentric interpolation in the disk parameterization, by angle along the boundary."""

from __future__ import annotations

import numpy as np

from ..adaptive.landmarks import boundary_angles, interpolate_on_boundary
from ..geometry.locate import interpolate_barycentric, locate_points

__all__ = ["check_data", "in_type", "project_to_surface"]


def project_to_surface(disk_uv, F, bnd, query_uv, on_circle, fields):
    """Lift points of the disk onto the surface through a disk parameterization.

    Interior points are located in the parameterization's triangles and interpolated
    barycentrically; points flagged ``on_circle`` are interpolated by angle along the
    boundary loop, so they land on the boundary polyline of the surface.

    Parameters
    ----------
    disk_uv : (n, 2) float
        Parameterization of the surface.
    F : (m, 3) int
    bnd : (b,) int
        Boundary loop of the surface.
    query_uv : (k, 2) float
    on_circle : (k,) bool
    fields : sequence of (n,) or (n, d) arrays
        Per-vertex data of the surface to interpolate: its positions (n, 3), attributes.

    Returns
    -------
    list of arrays
        Each of ``fields`` at the query points, in its type: integer fields (colours of
        0-255 as bytes, labels) rounded to the nearest value the type holds, boolean ones
        true where the interpolated value is at least 1/2.
    """
    types = [np.asarray(f).dtype for f in fields]
    fields = [np.asarray(f, dtype=np.float64) for f in fields]
    out = [np.zeros((len(query_uv),) + f.shape[1:]) for f in fields]
    inner = ~on_circle
    if inner.any():
        face, bary = locate_points(disk_uv, F, query_uv[inner])[:2]
        for o, f in zip(out, fields):
            o[inner] = interpolate_barycentric(F, face, bary, f)
    if on_circle.any():
        theta_b = boundary_angles(disk_uv, bnd)
        theta = np.arctan2(query_uv[on_circle, 1], query_uv[on_circle, 0])
        for o, f in zip(out, fields):
            o[on_circle] = interpolate_on_boundary(theta_b, f[bnd], theta)
    return [in_type(o, t) for o, t in zip(out, types)]


def check_data(data, n):
    """Per-vertex data of a mesh with ``n`` vertices (a dict of str to arrays, or None) as
    a dict of arrays, each (n,) or (n, ...) of booleans, integers or floats.

    Raises
    ------
    ValueError
        Where an array has not one row per vertex, or holds values that interpolation
        cannot take (strings, objects, complex numbers).
    """
    checked = {}
    for key, values in (data or {}).items():
        a = np.asarray(values)
        if a.ndim == 0 or a.shape[0] != n:
            raise ValueError(f"data[{key!r}] must have one row per input vertex ({n}); got shape {a.shape}")
        if not (a.dtype == np.bool_ or np.issubdtype(a.dtype, np.integer) or np.issubdtype(a.dtype, np.floating)):
            raise ValueError(f"data[{key!r}] must hold booleans, integers or floats to interpolate; got {a.dtype}")
        checked[key] = a
    return checked


def in_type(values, dtype):
    """Interpolated float64 ``values`` of a field of type ``dtype`` back in that type."""
    if dtype == np.bool_:
        return values >= 0.5
    if np.issubdtype(dtype, np.integer):
        info = np.iinfo(dtype)
        return np.clip(np.rint(values), info.min, info.max).astype(dtype)
    return values.astype(dtype, copy=False)
