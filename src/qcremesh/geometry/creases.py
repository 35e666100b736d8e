"""Sharp edges of a triangle mesh: the creases of CAD tessellations (libigl's ``sharp_edges``)."""

from __future__ import annotations

import numpy as np

from ..mesh.topology import half_edges, twin_half_edges
from .vectors import cross, norm

__all__ = ["check_crease_angle", "dihedral_angles", "sharp_edges"]


def check_crease_angle(angle):
    """Raise ValueError unless 0 < ``angle`` < 180 (degrees)."""
    if not 0.0 < angle < 180.0:
        raise ValueError(f"the crease angle must be between 0 and 180 degrees, not {angle}")


def dihedral_angles(V, F):
    """The angle by which the surface turns across each interior edge: the angle between
    the unit normals n_1, n_2 of its two faces, arccos(n_1 . n_2) in degrees (0 where the
    faces are coplanar, 180 where they fold onto each other; convex and concave alike).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        Consistently oriented.

    Returns
    -------
    E : (k, 2) int64
        The interior edges, as in their first face (:func:`qcremesh.mesh.topology.twin_half_edges`).
    angle : (k,) float
        Degrees, in [0, 180]; NaN where a face has zero area.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    H = half_edges(F)
    i, j = twin_half_edges(F)
    normal = cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    with np.errstate(invalid="ignore", divide="ignore"):
        normal = normal / norm(normal)[:, None]
    m = len(F)
    cosine = np.einsum("ij,ij->i", normal[i % m], normal[j % m])
    return H[i], np.degrees(np.arccos(np.clip(cosine, -1.0, 1.0)))


def sharp_edges(V, F, angle):
    """Interior edges across which the surface turns by more than ``angle`` degrees
    (:func:`dihedral_angles`), (k, 2) int64."""
    check_crease_angle(angle)
    E, turn = dihedral_angles(V, F)
    return E[turn > angle]
