"""Landmark-matching Teichmueller maps by the quasi-conformal (QC) iteration.

Among the quasi-conformal maps of a planar domain that send given landmark vertices to
given targets, the Teichmueller map (T-map) has the smallest maximal distortion
||mu||_inf. Its Beltrami coefficient has constant modulus, mu = k conj(phi) / |phi| with
phi a holomorphic quadratic differential (Lui, Lam, Yau & Gu, "Teichmueller mapping
(T-map) and its applications to landmark matching registration", SIAM J. Imaging Sci.
7(1), 2014). Their QC iteration alternates the linear Beltrami solver (LBS, Eq. 16) with
the projection of the map's coefficient onto constant modulus:

    f_n = LBS(mu_n)                       landmarks (and boundary) prescribed
    nu = S(C(mu(f_n)))                    C: chopping of folded faces, S: smoothing
    mu_{n+1} = k nu / |nu|,  k = <|nu|>   <.>: area-weighted mean over the source faces

Source conformal structure. By default the source is the planar mesh itself. With
``reference="equilateral"`` every face is instead given the shape of an equilateral
triangle: the source is the equilateral complex of the mesh (a flat surface with cone
points at vertices of valence other than 6), whose conformal structure is the one a
semi-regular mesh is meant to have. The coefficient that is projected is then that of
T = f o R^{-1}, with R the affine map of each face onto an equilateral triangle; in the
frame of the face in which R_z > 0 (Eq. 7 with the coefficient -mu_R of R^{-1}),

    mu_T = (mu_f - mu_R) / (1 - conj(mu_R) mu_f),
    mu_f = (mu_T + mu_R) / (1 + conj(mu_R) mu_T),

a Moebius transformation of the unit disk, so |mu_T| < 1 exactly where f does not fold.
The LBS still runs on the planar source with mu_f: the generalized Laplacian of
f o R^{-1} on the equilateral faces with mu_T equals that of f on the planar faces with
mu_f. The frames are consistent across a subdivided face (its four children have the same
R up to a half turn, which leaves mu unchanged), so the coefficient can be smoothed.
|mu_T| measures how far the image triangle is from equilateral: the radius ratio of the
image is a decreasing function of |mu_T| (for a given direction of the stretch), and the
face weights of k are equal, so the mean of k over the faces is the mean distortion of the
output triangles. This is why the remeshing pipeline uses it: the Tutte embedding of the
subdivided mesh, as a source, adds its own distortion (around every base vertex of
valence other than 6 and along the boundary) to what the map is measured by, whereas the
equilateral reference measures the triangles of the output directly.

Warm start and guard. Given an ``initial`` map that matches the landmarks and folds no
face (for the pipeline, the linear subdivision of the base mesh), the iteration starts
from its coefficient instead of from the harmonic map, which folds faces next to
landmarks that are far from where their neighbours put them. Where the landmarks ask for
more local distortion than the mesh resolution can spread (needle-shaped base triangles),
a face of an iterate can fold or reach a modulus |mu_T| above both ``guard`` and its
modulus in the initial map; such faces and the faces sharing a vertex with them keep the
initial map's coefficient from then on (the LBS reproduces a map from its own
coefficient, so the initial map, which is valid, is kept locally). Without an initial
map, a folded face keeps the chopped coefficient ``chop`` nu / |nu| instead of being
projected to modulus k.

Smoothing. The Laplacian smoothing of nu averages it to the vertices over their incident
faces and back to the faces as the mean of their three vertices (``smooth`` passes). It
also averages the argument of nu, which turns quickly around landmarks (phi has poles
there), so the fixed point is only approximately a Teichmueller map; measured on the
remeshing meshes it lowers the mean of |mu_T| from about 0.2 to 0.15 (the piecewise
constant coefficient of the subdivision is averaged out) and converges in fewer
iterations.

Boundary. With the boundary loop given, the whole boundary goes to the unit circle: the
boundary landmarks at their targets, the other boundary vertices at fixed places on the
arcs between them (:func:`circle_boundary_positions`); from an initial map, they stay
where it puts them. The Dirichlet data of every solve is the same, so the matrices of all
the solves have the same sparsity pattern, and each is factorized with the ordering and
symbolic analysis of the first.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..geometry.linsolve import complement, spd_solver
from ..geometry.operators import doublearea, signed_doublearea
from ..mesh.validate import as_mesh_arrays
from .coefficient import face_to_vertex, mu_chop, vertex_to_face
from .solver import generalized_laplacian_weights

__all__ = ["TeichmullerResult", "teichmuller_map", "circle_boundary_positions", "equilateral_coefficient"]


@dataclass
class TeichmullerResult:
    """Result of :func:`teichmuller_map`.

    Attributes
    ----------
    uv : (n, 2) float
        Image of every vertex.
    mu : (m,) complex
        Beltrami coefficient of the returned map, per face: f_zbar / f_z on the planar
        source, or mu_T of the map from the equilateral faces with
        ``reference="equilateral"`` (module documentation).
    k : float
        Area-weighted mean of |mu| over the source (or reference) faces: the constant
        modulus of a Teichmueller map.
    iterations : int
        Number of QC iterations run.
    converged : bool
        Whether the stopping rule was met.
    landmark_error : float
        Largest distance of a landmark to its target.
    folded_faces : int
        Faces whose image has signed area of opposite sign to the source face, or zero.
    guarded_faces : int
        Faces that kept the coefficient of the initial map (module documentation).
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
    guarded_faces: int = 0
    history: list = field(default_factory=list)


def teichmuller_map(
    uv,
    F,
    landmarks,
    targets,
    *,
    boundary=None,
    initial=None,
    reference=None,
    max_iter=300,
    tol=1e-2,
    smooth=0,
    chop=0.95,
    guard=0.45,
):
    """Landmark-matching Teichmueller map of a planar mesh by the QC iteration.

    Starting from the ``initial`` map, or else from the harmonic map f_0 = LBS(mu_0) with
    mu_0 = 0 on the source (mu_T = 0 with the equilateral reference), every iteration

    1. takes nu = mu(f_n) per face (mu_T with ``reference``, module documentation) and
       chops it: where |nu| >= 1 (a folded face), nu := ``chop`` nu / |nu|;
    2. smooths nu ``smooth`` times: nu := V2F(F2V(nu)), with F2V the mean over the faces
       incident to a vertex and V2F the mean over the three vertices of a face;
    3. projects onto constant modulus: mu_{n+1} = k nu / |nu|, with k the area-weighted
       mean of |nu|; faces f_n folds keep the chopped coefficient, or, from an initial
       map, the guarded faces keep its coefficient (module documentation);
    4. solves f_{n+1} = LBS(mu_{n+1}): the generalized Laplace equation (Eq. 16) with the
       landmarks at their targets, and, with ``boundary``, the other boundary vertices at
       their places on the unit circle (:func:`circle_boundary_positions`);

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
        of Eq. 16). With ``initial``, they stay where it puts them instead.
    initial : (n, 2) float, optional
        A map to start from, with the landmarks on their targets and no folded face.
    reference : {None, "equilateral"}
        Conformal structure of the source: the planar faces, or equilateral faces.
    max_iter : int
        Largest number of QC iterations.
    tol : float
        Tolerance on max |mu_{n+1} - mu_n| over the faces.
    smooth : int
        Number of smoothing passes of step 2.
    chop : float
        Modulus, < 1, given to the coefficient of folded faces.
    guard : float
        Modulus above which a face of an iterate that is more distorted than in the
        initial map is guarded (only with ``initial``).

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
    uv, F = as_mesh_arrays(uv, F)
    n = len(uv)
    landmarks = np.asarray(landmarks, dtype=np.int64).ravel()
    t = _as_complex(targets)
    if len(landmarks) == 0 or len(t) != len(landmarks):
        raise ValueError("need at least one landmark and one target per landmark")
    if len(np.unique(landmarks)) != len(landmarks):
        raise ValueError("landmarks must be distinct")
    if reference not in (None, "equilateral"):
        raise ValueError(f"unknown reference {reference!r}")
    if np.any(signed_doublearea(uv, F) == 0):
        raise ValueError("the source mesh has degenerate faces")

    known, values = landmarks, t
    if boundary is not None and initial is not None:
        moving = np.setdiff1d(np.asarray(boundary, dtype=np.int64), landmarks)
        known, values = np.concatenate([landmarks, moving]), np.concatenate([t, _as_complex(initial)[moving]])
    elif boundary is not None:
        moving, positions = circle_boundary_positions(uv, boundary, landmarks, t)
        known, values = np.concatenate([landmarks, moving]), np.concatenate([t, positions])
    if reference is None:
        mu_r = np.zeros(len(F), dtype=np.complex128)
        area = doublearea(uv, F)
    else:
        mu_r = equilateral_coefficient(uv, F)
        area = np.ones(len(F))
    area = area / area.sum()
    lbs = _LBS(uv, F, known, values)

    P = uv[F, 0] + 1j * uv[F, 1]
    edge = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)

    def coefficient(z):
        """mu_T of the map z per face (see :func:`equilateral_coefficient` for mu_f), and
        its folded faces: those with |mu_f| >= 1."""
        Z = z[F]
        with np.errstate(invalid="ignore", divide="ignore"):
            mu_f = -(Z * edge).sum(1) / (Z * np.conj(edge)).sum(1)
            mu_t = (mu_f - mu_r) / (1 - np.conj(mu_r) * mu_f)
        return mu_t, ~(np.abs(mu_f) < 1)

    if initial is None:
        z = lbs(mu_r)
        mu = np.zeros(len(F), dtype=np.complex128)
        guarded = None
    else:
        z = _as_complex(initial)
        mu = mu_chop(coefficient(z)[0], 1.0, chop)
        guarded = np.zeros(len(F), dtype=bool)
        start, start_modulus = mu, np.abs(mu)
    mu_z, folded = coefficient(z)
    best = z, folded
    history = []
    converged = False
    while len(history) < max_iter and not converged:
        chopped = mu_chop(mu_z, 1.0, chop)
        nu = chopped
        for _ in range(smooth):
            nu = vertex_to_face(F, face_to_vertex(F, nu, n))
        modulus = np.abs(nu)
        k = area @ modulus
        unit = np.divide(nu, modulus, out=np.zeros_like(nu), where=modulus > 0)
        if guarded is None:
            new = np.where(folded, chopped, k * unit)
        else:
            bad = folded | (np.abs(mu_z) > np.maximum(guard, start_modulus))
            touched = np.zeros(n, dtype=bool)
            touched[F[bad]] = True
            guarded |= touched[F].any(axis=1)
            new = np.where(guarded, start, k * unit)
        history.append(float(np.max(np.abs(new - mu))))
        mu = new
        z = lbs((mu + mu_r) / (1 + np.conj(mu_r) * mu))
        mu_z, folded = coefficient(z)
        if np.count_nonzero(folded) <= np.count_nonzero(best[1]):
            best = z, folded
        converged = history[-1] < tol and not folded.any()
    z, folded = best
    mu_z = coefficient(z)[0]
    return TeichmullerResult(
        uv=_pairs(z),
        mu=mu_z,
        k=float(area @ np.abs(mu_z)),
        iterations=len(history),
        converged=converged,
        landmark_error=float(np.max(np.abs(z[landmarks] - t))),
        folded_faces=int(np.count_nonzero(folded)),
        guarded_faces=0 if guarded is None else int(np.count_nonzero(guarded)),
        history=history,
    )


def equilateral_coefficient(uv, F):
    """Beltrami coefficient mu_R of the affine map R of every face onto an equilateral
    triangle of the same orientation, in the frame of the source face.

    With p_0, p_1, p_2 the corners of a face (complex), d_j = p_{j+2} - p_{j+1} the edge
    opposite corner j and q_j = omega^j (omega = exp(2 pi i / 3), conjugated for a
    clockwise face) the corners of the equilateral triangle, the gradient of the hat
    function of corner j is i d_j / (2 A) as a complex number (A the signed area), so

        R_z = -i sum_j q_j conj(d_j) / (4 A),   R_zbar = i sum_j q_j d_j / (4 A),
        mu_R = -sum_j q_j d_j / sum_j q_j conj(d_j).

    It does not depend on the rotation of the equilateral triangle, and is 0 exactly on
    equilateral faces.

    Parameters
    ----------
    uv : (n, 2) float
    F : (m, 3) int

    Returns
    -------
    (m,) complex
    """
    uv = np.asarray(uv, dtype=np.float64)
    F = np.asarray(F)
    P = uv[F, 0] + 1j * uv[F, 1]
    d = np.roll(P, -2, axis=1) - np.roll(P, -1, axis=1)
    q = np.exp(2j * np.pi / 3 * np.arange(3))
    q = np.where(signed_doublearea(uv, F)[:, None] >= 0, q, np.conj(q))
    return -(q * d).sum(1) / (q * np.conj(d)).sum(1)


class _LBS:
    """The linear Beltrami solver of a fixed mesh and fixed Dirichlet data, mu -> z.

    Eliminating the known vertices K from the generalized Laplacian L(mu) (Eq. 16) leaves
    A z_I = B z_K with A = -L_II and B = L_IK. Both are assembled from the three
    off-diagonal entries of every face (L_ij = -w_i^T A_T w_j / (4 |T|), the diagonal from
    the zero row sums) into sparsity patterns computed once, and A is refactorized with
    the ordering and symbolic analysis of the first solve.
    """

    def __init__(self, uv, F, known, values):
        n = len(uv)
        self.n = n
        self.values = values
        self.uv, self.F = uv, F
        self.known = np.asarray(known)
        slot = np.full(n, -1)
        self.free = complement(self.known, n)
        slot[self.free] = np.arange(len(self.free))
        slot_k = np.full(n, -1)
        slot_k[self.known] = np.arange(len(self.known))
        i, j = F[:, [0, 1, 2]].ravel(), F[:, [1, 2, 0]].ravel()
        si, sj, ki, kj = slot[i], slot[j], slot_k[i], slot_k[j]
        # Entries of A: -off at (i, j) and (j, i), +off at (i, i) and (j, j), free rows and
        # columns only; entries of B: +off at (i, j) for i free, j known, and symmetric.
        e = np.arange(len(i))
        both = (si >= 0) & (sj >= 0)
        a_rows = np.concatenate([si[both], sj[both], si[si >= 0], sj[sj >= 0]])
        a_cols = np.concatenate([sj[both], si[both], si[si >= 0], sj[sj >= 0]])
        self.a_edge = np.concatenate([e[both], e[both], e[si >= 0], e[sj >= 0]])
        self.a_sign = np.concatenate([-np.ones(2 * both.sum()), np.ones((si >= 0).sum() + (sj >= 0).sum())])
        ij, ji = (si >= 0) & (kj >= 0), (sj >= 0) & (ki >= 0)
        b_rows = np.concatenate([si[ij], sj[ji]])
        b_cols = np.concatenate([kj[ij], ki[ji]])
        self.b_edge = np.concatenate([e[ij], e[ji]])
        nf, nk = len(self.free), len(self.known)
        self.a_pattern = _pattern(a_rows, a_cols, (nf, nf))
        self.b_pattern = _pattern(b_rows, b_cols, (nf, nk))
        self.solver = None

    def __call__(self, mu):
        off = generalized_laplacian_weights(self.uv, self.F, mu).ravel()
        A = _assemble(self.a_pattern, self.a_sign * off[self.a_edge])
        B = _assemble(self.b_pattern, off[self.b_edge])
        self.solver = spd_solver(A) if self.solver is None else self.solver.refactorize(A)
        z = np.zeros(self.n, dtype=np.complex128)
        z[self.known] = self.values
        z[self.free] = self.solver(B @ self.values)
        return z


def _pattern(rows, cols, shape):
    """CSR pattern (indptr, indices, shape) of the entries (rows, cols), and the slot of
    every entry in its data array (duplicates share a slot)."""
    key = rows.astype(np.int64) * shape[1] + cols
    unique, slot = np.unique(key, return_inverse=True)
    indptr = np.searchsorted(unique // shape[1], np.arange(shape[0] + 1))
    return indptr, unique % shape[1], shape, slot, len(unique)


def _assemble(pattern, values):
    indptr, indices, shape, slot, nnz = pattern
    return sp.csr_matrix((np.bincount(slot, weights=values, minlength=nnz), indices, indptr), shape=shape)


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
