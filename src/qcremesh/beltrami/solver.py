"""The linear Beltrami solver (LBS): the quasi-conformal map of a planar mesh with a
prescribed Beltrami coefficient and prescribed positions of some vertices.

For f = u + i v with f_zbar = mu f_z and mu = rho + i tau, both u and v solve

    div(A grad u) = 0,   A = [[a1, a2], [a2, a3]],                               (Eq. 16)
    a1 = ((rho - 1)^2 + tau^2) / (1 - |mu|^2),  a2 = -2 tau / (1 - |mu|^2),
    a3 = ((1 + rho)^2 + tau^2) / (1 - |mu|^2),

with det A = 1. It is discretized by piecewise-linear finite elements on the source mesh
with mu constant per face, which gives a symmetric matrix, the generalized Laplacian;
for mu = 0 it is the cotangent Laplacian.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from ..geometry.linsolve import dirichlet_solve
from ..geometry.operators import doublearea
from ..mesh.validate import as_mesh_arrays
from .coefficient import mu_chop

__all__ = ["beltrami_tensor", "generalized_laplacian", "generalized_laplacian_weights", "linear_beltrami_solver"]


def beltrami_tensor(mu):
    """Coefficients (a1, a2, a3) of the symmetric matrix A of Eq. 16, per face.

    Parameters
    ----------
    mu : (m,) complex, |mu| < 1

    Returns
    -------
    a1, a2, a3 : (m,) float
    """
    mu = np.asarray(mu, dtype=np.complex128)
    rho, tau = mu.real, mu.imag
    den = 1.0 - rho * rho - tau * tau
    if np.any(den <= 0):
        raise ValueError("the Beltrami coefficient must satisfy |mu| < 1 (use mu_chop)")
    return ((rho - 1) ** 2 + tau**2) / den, -2 * tau / den, ((1 + rho) ** 2 + tau**2) / den


def generalized_laplacian(uv, F, mu):
    """Generalized Laplacian of the Beltrami equation on a planar mesh (Eq. 16).

    For face T with corners i and rotated opposite edges w_i = (y_j - y_k, x_k - x_j),
    (i, j, k) cyclic, the element entries are

        L_ij = -w_i^T A_T w_j / (4 |T|),

    summed over the faces: the negated finite-element stiffness matrix of
    div(A grad .), symmetric with a negative diagonal and zero row sums. With mu = 0 it
    equals :func:`qcremesh.geometry.operators.cotmatrix`. When mu is the coefficient
    (Eq. 19) of a map from ``uv`` onto a surface, it equals the cotangent Laplacian of
    the surface itself, since A = sqrt(EG - F^2) g^{-1} is then the conformal class of the
    surface metric g.

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
    mu : (m,) complex, |mu| < 1

    Returns
    -------
    (n, n) CSR float
    """
    uv, F = as_mesh_arrays(uv, F)
    n = len(uv)
    off = generalized_laplacian_weights(uv, F, mu)
    i, j = np.array([0, 1, 2]), np.array([1, 2, 0])
    rows, cols = F[:, i].ravel(), F[:, j].ravel()
    off = off.ravel()
    # the diagonal follows from the zero row sums (the w_i of a face sum to zero)
    diag = -np.bincount(np.r_[rows, cols], weights=np.r_[off, off], minlength=n)
    return sp.csr_matrix(
        (np.r_[off, off, diag], (np.r_[rows, cols, np.arange(n)], np.r_[cols, rows, np.arange(n)])),
        shape=(n, n),
    )


def generalized_laplacian_weights(uv, F, mu):
    """Off-diagonal element entries of the generalized Laplacian (Eq. 16), per face.

    L_ij = -w_i^T A_T w_j / (4 |T|) for the corner pairs (i, j) = (0, 1), (1, 2), (2, 0)
    of every face (see :func:`generalized_laplacian`, which sums them over the faces).

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int
    mu : (m,) complex, |mu| < 1

    Returns
    -------
    (m, 3) float
        Column k is the entry of the pair (k, k + 1 mod 3).
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F)
    a1, a2, a3 = beltrami_tensor(mu)
    P = uv[F]
    # w[:, k] = (y_{k+1} - y_{k+2}, x_{k+2} - x_{k+1})
    d = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)  # P[k+2] - P[k+1]
    wx, wy = -d[:, :, 1], d[:, :, 0]
    area4 = 2.0 * doublearea(uv, F)
    i, j = np.array([0, 1, 2]), np.array([1, 2, 0])
    return -(
        a1[:, None] * wx[:, i] * wx[:, j]
        + a2[:, None] * (wx[:, i] * wy[:, j] + wx[:, j] * wy[:, i])
        + a3[:, None] * wy[:, i] * wy[:, j]
    ) / area4[:, None]


def linear_beltrami_solver(uv, F, mu, landmarks, targets, *, bound=1.0, chop=0.95):
    """Quasi-conformal map of a planar mesh with Beltrami coefficient mu (LBS, Eq. 16).

    Solves the generalized Laplace equation for x and y together (one factorization, a
    complex right-hand side) with the positions of ``landmarks`` prescribed. Faces with
    |mu| >= ``bound`` are first chopped to modulus ``chop`` (see :func:`mu_chop`).

    Parameters
    ----------
    uv : (n, 2) float
        Source planar mesh.
    F : (m, 3) int
    mu : (m,) complex
    landmarks : (k,) int
        Vertices with prescribed positions (at least one per connected component; for a
        disk, typically the boundary plus interior landmarks).
    targets : (k, 2) float or (k,) complex
        Their positions.

    Returns
    -------
    (n, 2) float
        The image of every vertex.

    Examples
    --------
    An affine map is reproduced from its boundary values:

    >>> import numpy as np
    >>> from scipy.spatial import Delaunay
    >>> g = np.linspace(0, 1, 6)
    >>> uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    >>> F = Delaunay(uv).simplices
    >>> z = uv[:, 0] + 1j * uv[:, 1]
    >>> f = 2 * z + 0.5j * np.conj(z)
    >>> b = np.flatnonzero((uv == 0).any(1) | (uv == 1).any(1))
    >>> mu = np.full(len(F), 0.25j)
    >>> out = linear_beltrami_solver(uv, F, mu, b, f[b])
    >>> bool(np.allclose(out[:, 0] + 1j * out[:, 1], f))
    True
    """
    mu = mu_chop(mu, bound, chop)
    targets = np.asarray(targets)
    if np.iscomplexobj(targets):
        t = targets.ravel()
    else:
        t = targets[:, 0] + 1j * targets[:, 1]
    L = generalized_laplacian(uv, F, mu)
    z, _ = dirichlet_solve(L, landmarks, t)
    return np.column_stack([z.real, z.imag])
