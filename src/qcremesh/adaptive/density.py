"""Area distortion of a disk parameterization: the density of Algorithm 2."""

from __future__ import annotations

import numpy as np

from ..geometry.operators import doublearea

__all__ = ["area_distortion", "vertex_density"]


def area_distortion(uv, F, V):
    """Per-face ratio of surface area to disk area, (m,).

    Parameters
    ----------
    uv : (n, 2) float
        Disk parameterization.
    F : (m, 3) int
    V : (n, 3) float
        The surface.
    """
    return doublearea(V, F) / doublearea(uv, F)


def vertex_density(uv, F, V):
    """Density of the surface area over the disk at every vertex (Eq. 14):

        rho(v) = sum_{T ∋ v} |T|_surface / sum_{T ∋ v} |T|_disk,

    the area of the surface faces around v over the area of their images in the disk.
    Uniformly spread points on the surface have density proportional to rho in the disk.

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
    V : (n, 3) float

    Returns
    -------
    (n,) float
    """
    F = np.asarray(F)
    n = len(uv)
    surf = np.bincount(F.ravel(), weights=np.repeat(doublearea(V, F), 3), minlength=n)
    disk = np.bincount(F.ravel(), weights=np.repeat(doublearea(uv, F), 3), minlength=n)
    return surf / disk
