"""Tutte embedding of a disk-topology mesh onto the unit disk."""

from __future__ import annotations

import numpy as np

from ..geometry.linsolve import dirichlet_solve
from ..geometry.operators import uniform_laplacian
from ..mesh.topology import boundary_loop
from ..mesh.validate import as_face_array

__all__ = ["map_vertices_to_circle", "tutte_embedding"]


def map_vertices_to_circle(V, bnd):
    """Place a boundary loop on the unit circle, spaced by the lengths of its edges.

    Parameters
    ----------
    V : (n, d) float
        Vertex positions; ``None`` for the fake metric (every edge of length 1, so
        equal angles).
    bnd : (b,) int
        Boundary loop, in order.

    Returns
    -------
    (b, 2) float
        Counter-clockwise positions, the first vertex at (1, 0).
    """
    bnd = np.asarray(bnd)
    if V is None:
        length = np.ones(len(bnd))
    else:
        V = np.asarray(V, dtype=np.float64)
        length = np.linalg.norm(V[np.roll(bnd, -1)] - V[bnd], axis=1)
    theta = 2 * np.pi * np.concatenate([[0.0], np.cumsum(length)[:-1]]) / length.sum()
    return np.column_stack([np.cos(theta), np.sin(theta)])


def tutte_embedding(F, bnd=None, n=None, *, return_solver=False):
    """Tutte embedding onto the unit disk with the fake metric (every edge length 1).

    The boundary loop goes to the unit circle at equal angles, and every interior vertex
    to the average of its neighbours: L x = 0 inside with L the uniform graph
    Laplacian. By Tutte's theorem the result is a bijective piecewise-linear map onto a
    convex polygon inscribed in the circle (no folded face).

    Parameters
    ----------
    F : (m, 3) int
        A disk-topology mesh (whole-number floats are taken; indices that are not, or
        out of range, refused: :func:`qcremesh.mesh.validate.as_face_array`).
    bnd : (b,) int, optional
        Its boundary loop; :func:`qcremesh.mesh.topology.boundary_loop` by default.
        Counter-clockwise when the loop keeps the interior on its left, which is the
        orientation :func:`boundary_loop` returns, so faces keep their orientation.
    n : int, optional
        Number of vertices.
    return_solver : bool
        Also return the factorization of the interior block of the Laplacian, whose
        ordering and symbolic analysis serve any other Laplacian of the mesh (see
        :meth:`qcremesh.geometry.linsolve.SPDSolver.refactorize`).

    Returns
    -------
    uv : (n, 2) float
    solver : SPDSolver
        Only with ``return_solver``.
    """
    F = as_face_array(F, n)
    n = int(F.max()) + 1 if n is None else n
    bnd = boundary_loop(F) if bnd is None else np.asarray(bnd)
    uv, solver = dirichlet_solve(uniform_laplacian(F, n), bnd, map_vertices_to_circle(None, bnd))
    return (uv, solver) if return_solver else uv
