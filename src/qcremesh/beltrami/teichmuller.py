"""Landmark-matching Teichmueller maps by the quasi-conformal (QC) iteration.

Among the quasi-conformal maps of a planar domain that send given landmark vertices to
given targets, the Teichmueller map (T-map) has the smallest maximal distortion
||mu||_inf. Its Beltrami coefficient has constant modulus, mu = k conj(phi) / |phi| with
phi a holomorphic quadratic differential (Lui, Lam, Yau & Gu, "Teichmueller mapping
(T-map) and its applications to landmark matching registration", SIAM J. Imaging Sci.
7(1), 2014). Their QC iteration alternates the linear Beltrami solver (Eq. 16) with a
projection of the map's coefficient onto constant modulus, starting from mu = 0:

    f_n = LBS(mu_n)                       landmarks (and boundary) prescribed
    nu = C(mu(f_n))                       mu(f) = f_zbar / f_z per face, chopped
    mu_{n+1} = k nu / |nu|,  k = <|nu|>   <.>: area-weighted mean over the source faces

The Laplacian smoothing of nu that the paper puts before the projection is available
(``smooth``) but off by default: it averages the argument of nu over neighbouring faces,
and around the landmarks, where the argument of a T-map's coefficient turns quickly (phi
has poles there), that moves the fixed point away from a Teichmueller map. Measured on
Delaunay disks with 24 boundary and 60 interior landmarks: without smoothing the
standard deviation of |mu(f)| is about 5 % of k at convergence and no face folds; with
the averaging of the smoothing alone it is about 30 % and faces next to landmarks fold.

Boundary. With the boundary loop given, the whole boundary goes to the unit circle: the
boundary landmarks at their targets, the other boundary vertices at fixed places on the
arcs between them (:func:`circle_boundary_positions`), so the Dirichlet data of every
solve is the same.

Folds. The harmonic map of the first solve folds faces next to landmarks that are far
from where their neighbours put them. A folded face (|nu| > 1) keeps the chopped
coefficient ``chop`` nu / |nu| instead of being projected to modulus k (in our tests,
faces projected to k right after folding next to a landmark stayed folded). The
iteration stops only without folds. Where the targets ask for far more local distortion
than k can give at the resolution of the mesh (landmarks much closer to each other than
to their other neighbours, needle-shaped triangles between landmarks), faces next to
landmarks can stay folded; the result is then the iterate with the fewest folded faces,
and reports how many.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..geometry.linsolve import dirichlet_solve, spd_solver
from ..geometry.operators import doublearea, signed_doublearea, uniform_laplacian
from .coefficient import beltrami_coefficient, face_to_vertex, mu_chop, vertex_to_face
from .solver import generalized_laplacian

__all__ = ["TeichmullerResult", "teichmuller_map", "circle_boundary_positions"]


@dataclass
class TeichmullerResult:
    """Result of :func:`teichmuller_map`.

    Attributes
    ----------
    uv : (n, 2) float
        Image of every vertex.
    mu : (m,) complex
        Beltrami coefficient f_zbar / f_z of the returned map, per face.
    k : float
        Area-weighted mean of |mu| over the source faces (the constant modulus of a
        Teichmueller map).
    iterations : int
        Number of QC iterations run.
    converged : bool
        Whether the stopping rule was met.
    landmark_error : float
        Largest distance of a landmark to its target.
    folded_faces : int
        Faces whose image has signed area of opposite sign to the source face, or zero.
    history : list of float
        max |mu_{n+1} - mu_n| of every iteration.
    """

    uv: np.ndarray
    mu: np.ndarray
    k: float
    iterations: int
    converged: bool
    landmark_error: float
    folded_faces: int
    history: list = field(default_factory=list)


def teichmuller_map(
    uv,
    F,
    landmarks,
    targets,
    *,
    boundary=None,
    max_iter=300,
    tol=1e-2,
    smooth=0.0,
    chop=0.95,
):
    """Landmark-matching Teichmueller map of a planar mesh by the QC iteration.

    Starting from mu_0 = 0 (a harmonic map), every iteration

    1. solves f_n = LBS(mu_n): the generalized Laplace equation (Eq. 16) with the
       landmarks at their targets, and, with ``boundary``, the other boundary vertices at
       their places on the unit circle (:func:`circle_boundary_positions`);
    2. takes nu = mu(f_n) = f_zbar / f_z per face and chops it: where |nu| >= 1 (a
       folded face), nu := ``chop`` nu / |nu|;
    3. if ``smooth`` = s > 0, smooths nu: averaged to the vertices over their incident
       faces, one implicit diffusion step (D - s L) nu' = D nu with L the uniform graph
       Laplacian of the source mesh and D its degree matrix (factorized once), and back
       to the faces as the mean of their three vertices;
    4. projects onto constant modulus: mu_{n+1} = k nu / |nu|, with k the area-weighted
       mean of |nu|, except on the faces f_n folds, which keep the chopped nu;

    and stops when max |mu_{n+1} - mu_n| < ``tol`` and f_{n+1} folds no face, or after
    ``max_iter`` iterations.

    Parameters
    ----------
    uv : (n, 2) float
        Source planar mesh, without degenerate faces.
    F : (m, 3) int
        Consistently oriented faces.
    landmarks : (k,) int
        Distinct vertices with prescribed images, k >= 1.
    targets : (k, 2) float or (k,) complex
        Their images; matched exactly.
    boundary : (b,) int, optional
        The ordered boundary loop. When given, the whole boundary goes to the unit
        circle: the boundary landmarks (at least one) must have their targets on it, and
        every other boundary vertex is placed on the arc between the landmarks before and
        after it along the loop, in proportion to the source arc length. By default the
        boundary vertices that are not landmarks are free (the natural boundary condition
        of Eq. 16).
    max_iter : int
        Largest number of QC iterations.
    tol : float
        Tolerance on max |mu_{n+1} - mu_n| over the faces.
    smooth : float
        Diffusion time s of the smoothing of step 3, in graph steps (about sqrt(s)
        rings); 0 (the default) skips the step (module documentation).
    chop : float
        Modulus, < 1, given to the coefficient of folded faces.

    Returns
    -------
    TeichmullerResult
        The last of the iterates that fold the fewest faces: the last iterate when it
        folds none.

    Examples
    --------
    Landmarks on a grid moved by the affine map z + 0.2 conj(z), with the whole boundary
    fixed by it, give that map back, with |mu| = 0.2:

    >>> import numpy as np
    >>> from scipy.spatial import Delaunay
    >>> g = np.linspace(0, 1, 7)
    >>> uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    >>> F = Delaunay(uv).simplices
    >>> z = uv[:, 0] + 1j * uv[:, 1]
    >>> land = np.flatnonzero((uv % 1 == 0).any(1) | (np.abs(z - 0.5 - 0.5j) < 1e-9))
    >>> res = teichmuller_map(uv, F, land, (z + 0.2 * np.conj(z))[land])
    >>> res.converged, round(res.k, 8), res.folded_faces
    (True, 0.2, 0)
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    n = len(uv)
    landmarks = np.asarray(landmarks, dtype=np.int64).ravel()
    t = _as_complex(targets)
    if len(landmarks) == 0 or len(t) != len(landmarks):
        raise ValueError("need at least one landmark and one target per landmark")
    if len(np.unique(landmarks)) != len(landmarks):
        raise ValueError("landmarks must be distinct")
    orient = np.sign(signed_doublearea(uv, F))
    if np.any(orient == 0):
        raise ValueError("the source mesh has degenerate faces")

    known, values = landmarks, t
    if boundary is not None:
        moving, positions = circle_boundary_positions(uv, boundary, landmarks, t)
        known, values = np.concatenate([landmarks, moving]), np.concatenate([t, positions])
    area = doublearea(uv, F)
    area = area / area.sum()
    smoother = _smoother(F, n, smooth)

    def lbs(mu):
        z, _ = dirichlet_solve(generalized_laplacian(uv, F, mu), known, values)
        return z, orient * signed_doublearea(_pairs(z), F) <= 0

    mu = np.zeros(len(F), dtype=np.complex128)
    z, folded = lbs(mu)
    best = z, folded
    history = []
    converged = False
    while len(history) < max_iter and not converged:
        chopped = mu_chop(beltrami_coefficient(uv, F, z), 1.0, chop)
        nu = smoother(chopped)
        modulus = np.abs(nu)
        k = area @ modulus
        unit = np.divide(nu, modulus, out=np.zeros_like(nu), where=modulus > 0)
        new = np.where(folded, chopped, k * unit)
        history.append(float(np.max(np.abs(new - mu))))
        mu = new
        z, folded = lbs(mu)
        if np.count_nonzero(folded) <= np.count_nonzero(best[1]):
            best = z, folded
        converged = history[-1] < tol and not folded.any()
    z, folded = best
    mu_z = beltrami_coefficient(uv, F, z)
    return TeichmullerResult(
        uv=_pairs(z),
        mu=mu_z,
        k=float(area @ np.abs(mu_z)),
        iterations=len(history),
        converged=converged,
        landmark_error=float(np.max(np.abs(z[landmarks] - t))),
        folded_faces=int(np.count_nonzero(folded)),
        history=history,
    )


def circle_boundary_positions(uv, boundary, landmarks, targets):
    """Places on the unit circle for the boundary vertices that are not landmarks.

    The boundary landmarks cut the loop into arcs. A vertex of the arc from landmark a to
    the next landmark b (along the loop) at source arc length s from a, on an arc of
    source length l, goes to

        t_a exp(i (s / l) delta),

    with delta in (0, 2 pi] the angle from t_a to t_b turning the way the loop turns in
    the source (counter-clockwise if the loop encloses positive area); a single boundary
    landmark makes one arc of angle 2 pi.

    Parameters
    ----------
    uv : (n, 2) float
        Source mesh.
    boundary : (b,) int
        The boundary loop, in order.
    landmarks : (k,) int
    targets : (k, 2) float or (k,) complex
        The targets of the landmarks on the boundary must lie on the unit circle.

    Returns
    -------
    vertices : (b',) int
        The boundary vertices that are not landmarks, in loop order.
    positions : (b',) complex
        Their images.
    """
    uv = np.asarray(uv, dtype=np.float64)
    bnd = np.asarray(boundary, dtype=np.int64).ravel()
    t = _as_complex(targets)
    slot = np.full(len(uv), -1)
    slot[np.asarray(landmarks, dtype=np.int64)] = np.arange(len(t))
    is_land = slot[bnd] >= 0
    if not is_land.any():
        raise ValueError("the boundary needs at least one landmark")
    # Start the loop at a landmark, so that every arc is a contiguous run.
    start = int(np.argmax(is_land))
    bnd, is_land = np.roll(bnd, -start), np.roll(is_land, -start)
    ends = t[slot[bnd[is_land]]]
    if np.max(np.abs(np.abs(ends) - 1.0)) > 1e-9:
        raise ValueError("the targets of boundary landmarks must lie on the unit circle")
    P = uv[bnd]
    ccw = np.sum(P[:, 0] * np.roll(P[:, 1], -1) - np.roll(P[:, 0], -1) * P[:, 1]) > 0
    if len(ends) == 1:
        turn = np.array([2 * np.pi])
    else:
        turn = np.angle(np.roll(ends, -1) / ends)
        turn = np.mod(turn if ccw else -turn, 2 * np.pi)
    delta = turn if ccw else -turn
    edge = np.linalg.norm(np.roll(P, -1, axis=0) - P, axis=1)
    s = np.concatenate([[0.0], np.cumsum(edge)])  # arc length at each vertex, and the end
    arc = np.cumsum(is_land) - 1
    first = s[:-1][is_land]
    length = np.append(first[1:], s[-1]) - first
    inner = ~is_land
    a = arc[inner]
    frac = (s[:-1][inner] - first[a]) / length[a]
    return bnd[inner], ends[a] * np.exp(1j * frac * delta[a])


def _as_complex(points):
    """(k, 2) real or (k,) complex or real points as (k,) complex."""
    points = np.asarray(points)
    if points.ndim == 2 and points.shape[1] == 2 and not np.iscomplexobj(points):
        return points[:, 0] + 1j * points[:, 1]
    if points.ndim == 1:
        return points.astype(np.complex128)
    raise ValueError("points must be (k, 2) real or (k,) complex")


def _pairs(z):
    return np.column_stack([z.real, z.imag])


def _smoother(F, n, s):
    """The smoothing of step 3 as a function of per-face values, (m,) -> (m,)."""
    if s <= 0:
        return lambda nu: nu
    L = uniform_laplacian(F, n)
    D = sp.diags(-L.diagonal())
    solve = spd_solver(D - s * L)
    return lambda nu: vertex_to_face(F, solve(D @ face_to_vertex(F, nu, n)))
