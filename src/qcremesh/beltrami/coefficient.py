"""Beltrami coefficients of piecewise-linear maps, their composition and chopping.

A map f = u + i v is quasi-conformal with Beltrami coefficient mu when
f_zbar = mu f_z (Eq. 1 of Choi, Gu & Lui), with f_z = (f_x - i f_y) / 2 and
f_zbar = (f_x + i f_y) / 2. For a piecewise-linear map these derivatives are constant on
each face, so mu is one complex number per face.
"""

from __future__ import annotations

import numpy as np

from ..geometry.operators import face_gradients
from ..mesh.topology import adjacency_matrix, vertex_face_incidence
from ..mesh.validate import as_mesh_arrays

__all__ = [
    "complex_derivatives",
    "beltrami_coefficient",
    "metric_beltrami_coefficient",
    "compose_beltrami",
    "mu_chop",
    "face_to_vertex",
    "vertex_to_face",
    "coherent_mu",
]


def _as_complex(target):
    target = np.asarray(target)
    if np.iscomplexobj(target):
        return target.ravel()
    if target.ndim == 2 and target.shape[1] == 2:
        return target[:, 0] + 1j * target[:, 1]
    raise ValueError("a planar target must be (n, 2) real or (n,) complex")


def complex_derivatives(uv, F, target):
    """Wirtinger derivatives f_z and f_zbar of a piecewise-linear planar map, per face.

    Parameters
    ----------
    uv : (n, 2) float
        Source planar mesh.
    F : (m, 3) int
    target : (n, 2) float or (n,) complex
        Image of every vertex.

    Returns
    -------
    fz, fzbar : (m,) complex
    """
    Dx, Dy = face_gradients(uv, F)
    f = _as_complex(target)[np.asarray(F)]
    fx = (Dx * f).sum(1)
    fy = (Dy * f).sum(1)
    return (fx - 1j * fy) / 2, (fx + 1j * fy) / 2


def beltrami_coefficient(uv, F, target):
    """Beltrami coefficient of the piecewise-linear map from a planar mesh, per face.

    * Planar target, (n, 2) or complex (n,): mu = f_zbar / f_z. Orientation-preserving
      faces have |mu| < 1; a face the map folds over has |mu| > 1, a face it flattens
      |mu| = 1 (or inf where f_z = 0).
    * Surface target, (n, 3): with the tangent vectors f_x, f_y of the face and the
      first fundamental form E = |f_x|^2, G = |f_y|^2, F = f_x . f_y,

          mu = (E - G + 2 i F) / (E + G + 2 sqrt(E G - F^2))        (Eq. 19)

      which is the coefficient of the map onto the surface with its induced metric
      (|mu| < 1 on every non-degenerate face). For a planar target (z = 0) both formulas
      agree on orientation-preserving faces.

    Parameters
    ----------
    uv : (n, 2) float
        Source planar mesh (need not be counter-clockwise; the signed area is used).
    F : (m, 3) int
    target : (n, 2) float, (n,) complex or (n, 3) float

    Returns
    -------
    mu : (m,) complex

    Examples
    --------
    The affine map f(z) = z + 0.3 conj(z) has mu = 0.3 on every face:

    >>> import numpy as np
    >>> uv = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]])
    >>> z = uv[:, 0] + 1j * uv[:, 1]
    >>> beltrami_coefficient(uv, np.array([[0, 1, 2]]), z + 0.3 * np.conj(z)).round(12)
    array([0.3+0.j])
    """
    uv, F = as_mesh_arrays(uv, F)
    target = np.asarray(target)
    if target.ndim == 2 and target.shape[1] == 3:
        Dx, Dy = face_gradients(uv, F)
        P = target[np.asarray(F)]  # (m, 3 corners, 3 coords)
        fx = np.einsum("mk,mkd->md", Dx, P)
        fy = np.einsum("mk,mkd->md", Dy, P)
        E = (fx * fx).sum(1)
        G = (fy * fy).sum(1)
        Fm = (fx * fy).sum(1)
        root = np.sqrt(np.maximum(E * G - Fm * Fm, 0.0))
        return (E - G + 2j * Fm) / (E + G + 2 * root)
    fz, fzbar = complex_derivatives(uv, F, target)
    with np.errstate(divide="ignore", invalid="ignore"):
        return fzbar / fz


def metric_beltrami_coefficient(uv, F, lengths):
    """Beltrami coefficient of a planar mesh onto a metric given by edge lengths, per face.

    Eq. 19 with the first fundamental form of the face solved from its side lengths: the
    metric g = [[E, F], [F, G]] on the planar face for which each side e_k (from corner k
    to corner k + 1) has length l_k, e_k^T g e_k = l_k^2 (three equations, three
    unknowns), then

        mu = (E - G + 2 i F) / (E + G + 2 sqrt(E G - F^2)).

    With ``lengths`` the side lengths of a mesh in space this is
    :func:`beltrami_coefficient` with the surface as target; the lengths may also be
    those of an intrinsic triangulation, which has no embedding.

    Parameters
    ----------
    uv : (n, 2) float
        Source planar mesh, counter-clockwise.
    F : (m, 3) int
    lengths : (m, 3) float
        ``lengths[f, k]``: length of the side from ``F[f, k]`` to ``F[f, (k + 1) % 3]``.

    Returns
    -------
    mu : (m,) complex
    """
    P = np.asarray(uv, dtype=np.float64)[np.asarray(F)]
    e = np.roll(P, -1, axis=1) - P  # (m, 3 sides, 2)
    A = np.stack([e[..., 0] ** 2, 2 * e[..., 0] * e[..., 1], e[..., 1] ** 2], axis=-1)
    E, Fm, G = np.linalg.solve(A, np.asarray(lengths, dtype=np.float64)[..., None] ** 2)[..., 0].T
    root = np.sqrt(np.maximum(E * G - Fm * Fm, 0.0))
    return (E - G + 2j * Fm) / (E + G + 2 * root)


def compose_beltrami(mu_f, fz, mu_g_at_f):
    """Beltrami coefficient of a composition g o f (Eq. 7).

        mu_{g o f} = (mu_f + r mu_g(f)) / (1 + conj(mu_f) r mu_g(f)),   r = conj(f_z) / f_z

    Parameters
    ----------
    mu_f : (m,) complex
        Coefficient of f per face.
    fz : (m,) complex
        f_z per face (see :func:`complex_derivatives`).
    mu_g_at_f : (m,) complex
        Coefficient of g on the image of each face.

    Returns
    -------
    (m,) complex
    """
    r = np.conj(fz) / fz
    t = r * mu_g_at_f
    return (mu_f + t) / (1 + np.conj(mu_f) * t)


def mu_chop(mu, bound=1.0, value=0.95):
    """Bring |mu| below 1 where it is not: where |mu| >= ``bound`` set mu to
    ``value * mu / |mu|``, keeping its argument (non-finite values become ``value``).

    Parameters
    ----------
    mu : (m,) complex
    bound : float
        Threshold on |mu|.
    value : float
        Modulus given to the chopped entries, < 1.

    Returns
    -------
    (m,) complex
        A copy of ``mu``.
    """
    mu = np.array(mu, dtype=np.complex128)
    with np.errstate(invalid="ignore"):
        mod = np.abs(mu)
        bad = ~(mod < bound)
        keep_arg = bad & np.isfinite(mu) & (mod > 0)
        mu[keep_arg] = value * mu[keep_arg] / mod[keep_arg]
    mu[bad & ~keep_arg] = value
    return mu


def face_to_vertex(F, values, n=None):
    """Average per-face values onto the vertices, uniformly over the incident faces.

    Parameters
    ----------
    F : (m, 3) int
    values : (m,) or (m, k)
    n : int, optional
        Number of vertices.

    Returns
    -------
    (n,) or (n, k)
    """
    F = np.asarray(F)
    n = int(F.max()) + 1 if n is None else n
    values = np.asarray(values)
    m = len(F)
    incidence = vertex_face_incidence(F, n)
    count = np.maximum(np.diff(incidence.indptr), 1)
    out = incidence @ values.reshape(m, -1) / count[:, None]
    return out.reshape((n,) + values.shape[1:])


def vertex_to_face(F, values):
    """Mean of the three vertex values of every face, (m,) or (m, k)."""
    return np.asarray(values)[np.asarray(F)].mean(axis=1)


def coherent_mu(F, mu, n, rings):
    """Modulus of a per-face Beltrami coefficient averaged around each vertex: as a complex
    number over the vertex's faces (:func:`face_to_vertex`), then ``rings`` times with its
    neighbours (the mean of the vertex's value and theirs). Coefficients of random
    argument (a conformal map on skinny triangles) cancel; a stretch in one direction (a
    map that is not conformal) stays.

    Parameters
    ----------
    F : (m, 3) int
    mu : (m,) complex
    n : int
        Number of vertices.
    rings : int

    Returns
    -------
    (n,) float
    """
    m = face_to_vertex(F, mu, n)
    A = adjacency_matrix(F, n)
    degree = np.asarray(A.sum(axis=1)).ravel()
    for _ in range(rings):
        m = (A @ m + m) / (degree + 1)
    return np.abs(m)
