"""Conformal parameterization of a disk-topology mesh onto the unit disk, with a free
boundary (Algorithm 1 of Choi, Gu & Lui).

1. Tutte embedding T: S -> D with the fake metric (every edge of length 1).
2. Beltrami coefficient mu of T^{-1}: D -> S, per face of the Tutte mesh (Eq. 19).
3. Quasi-conformal map g: D -> D with Beltrami coefficient mu, by the linear Beltrami
   solver on the Tutte mesh (Eq. 16), with the boundary free on the unit circle (Eq. 11).
4. g o T: S -> D is conformal: by the composition rule (Eq. 7) the Beltrami
   coefficient of T^{-1} o g^{-1} vanishes when mu_g = mu_{T^{-1}}. On the vertices
   g o T is simply the value of g at the Tutte vertex.

With mu of T^{-1} from Eq. 19, the matrix A of Eq. 16 on each face is sqrt(det g) g^{-1}
for the surface metric g pulled back to the Tutte face, so the generalized Laplacian of
step 3 is exactly the cotangent Laplacian of the surface (checked by a test). The Tutte
mesh is the domain on which it is assembled; its regularity is what the paper's fake
metric buys.

Free boundary. The boundary correspondence of the Riemann map f: S -> D with f(p) = 0 is
the harmonic measure of the boundary seen from p: the arc of the circle that a piece of
the boundary maps to has length 2 pi omega_p(piece). Discretely, with L the generalized
Laplacian of step 3 and G the Green's function (-L G = delta_p inside, G = 0 on the
boundary), the harmonic measure of the dual boundary cell of a boundary vertex b is the
flux (L G)_b, and these fluxes sum to 1. Each boundary vertex goes to the middle of its
arc, theta_b = 2 pi (sum_{c < b} omega_c + omega_b / 2), and the interior follows from the
LBS with those boundary values. Measured against the alternatives on the meshes of
``../shared/data`` (see README): this is the most accurate of the linear methods tried
and needs a single factorization, reused for three solves; its ordering and symbolic
analysis are those of the Tutte embedding's matrix, which has the same pattern.

Normalization of the Moebius freedom: the vertex p that maximizes the torsion function
(-L u = vertex areas, u = 0 on the boundary; its maximum is the deepest point of the
surface, far from every boundary) goes to 0, and the boundary vertex with the smallest
index goes to 1. The discrete solve puts p within about 1e-4 of 0; a Moebius
transformation of the disk (:func:`mobius_normalize`) makes both exact.

Bijectivity. The generalized Laplacian of a surface with obtuse triangles has negative
edge weights, and then the discrete harmonic map can fold faces. Folded faces (signed
area <= 0) are detected, and the map is solved again with the negative weights raised
to a small positive floor: with positive weights and the boundary on a circle, Tutte's
and Floater's theorems make the map bijective. The number of folds found and repaired
is reported. The repair's matrix has the same pattern too, so it costs one numerical
factorization.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp

from ..beltrami.coefficient import beltrami_coefficient
from ..beltrami.solver import generalized_laplacian
from ..geometry.linsolve import complement, dirichlet_solve, spd_solver
from ..geometry.operators import doublearea, signed_doublearea
from ..mesh.topology import boundary_loop
from ..mesh.validate import check_disk
from .tutte import tutte_embedding

__all__ = ["DiskMap", "disk_conformal_map", "harmonic_measure", "mobius_normalize"]

# Narrowest arc of the circle a boundary vertex of the disk map gets (radians): Qhull's
# Delaunay triangulation of landmarks on the circle loses points closer than about 1e-7.
MIN_BOUNDARY_ARC = 1e-6


@dataclass
class DiskMap:
    """Result of :func:`disk_conformal_map`.

    Attributes
    ----------
    uv : (n, 2) float
        Disk coordinates of every vertex, in input order.
    mu : (m,) complex
        Beltrami coefficient of the map from the disk to the surface, per face (0 for a
        conformal map).
    tutte : (n, 2) float
        The Tutte embedding of step 1.
    boundary : (b,) int
        The boundary loop, counter-clockwise on the circle.
    center : int
        The vertex mapped to 0.
    folded_faces : int
        Faces with non-positive signed area in the final map (0 unless the repair failed).
    repaired_faces : int
        Faces folded by the first solve and unfolded by the repair.
    narrowest_arcs : int
        Boundary vertices whose harmonic measure was below MIN_BOUNDARY_ARC and got that
        arc instead: where the map crowds the boundary beyond what the remeshing
        resolves, and is not conformal (the ends of a long strip, the legs of a surface
        cut along slits).
    times : dict of str to float
        Wall time of each stage, in seconds.
    """

    uv: np.ndarray
    mu: np.ndarray
    tutte: np.ndarray
    boundary: np.ndarray
    center: int
    folded_faces: int
    repaired_faces: int
    narrowest_arcs: int = 0
    times: dict = field(default_factory=dict)

    @property
    def mean_abs_mu(self):
        """Unweighted mean of |mu| over the faces."""
        return float(np.mean(np.abs(self.mu)))

    @property
    def max_abs_mu(self):
        """Largest |mu| over the faces."""
        return float(np.max(np.abs(self.mu)))

    @property
    def boundary_radius_error(self):
        """Largest | |z| - 1 | over the boundary vertices."""
        z = self.uv[self.boundary]
        return float(np.max(np.abs(np.hypot(z[:, 0], z[:, 1]) - 1.0)))


def harmonic_measure(L, bnd, p, solve_interior=None):
    """Discrete harmonic measure of the boundary seen from an interior vertex.

    With G the Green's function at p (-L G = e_p at the interior vertices, G = 0 on the
    boundary), the measure of boundary vertex b is the flux (L G)_b; the fluxes sum to 1.

    Parameters
    ----------
    L : (n, n) sparse
        Symmetric Laplacian with a negative diagonal (cotangent or generalized).
    bnd : (b,) int
        Boundary vertices.
    p : int
        Interior vertex.
    solve_interior : callable, optional
        Factorization of -L restricted to the interior vertices (in increasing order).

    Returns
    -------
    omega : (b,) float
    solve_interior : callable
    """
    n = L.shape[0]
    interior = complement(bnd, n)
    if solve_interior is None:
        solve_interior = spd_solver(-L[interior][:, interior])
    e = np.zeros(len(interior))
    e[np.searchsorted(interior, p)] = 1.0
    G = np.zeros(n)
    G[interior] = solve_interior(e)
    return (L[bnd] @ G), solve_interior


def _clamped(L, floor):
    """Copy of L with every off-diagonal weight raised to at least ``floor``."""
    C = sp.coo_matrix(L)
    off = C.row != C.col
    w = np.where(off, np.maximum(C.data, floor), 0.0)
    W = sp.csr_matrix((w, (C.row, C.col)), shape=L.shape)
    return (W - sp.diags(np.asarray(W.sum(axis=1)).ravel())).tocsr()


def disk_conformal_map(V, F, *, check=True):
    """Free-boundary conformal map of a disk-topology mesh onto the unit disk.

    Algorithm 1 of Choi, Gu & Lui (see the module documentation for the method, the
    free boundary, the normalization and the fold repair).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        A disk: one manifold, consistently oriented component with one boundary loop and
        Euler characteristic 1.
    check : bool
        Validate the mesh first (raises :class:`qcremesh.mesh.validate.MeshError`).

    Returns
    -------
    DiskMap
    """
    times = {}
    t0 = time.perf_counter()
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    bnd = check_disk(V, F) if check else boundary_loop(F)
    n = len(V)
    t1 = time.perf_counter()
    times["validate"] = t1 - t0

    tutte, solver = tutte_embedding(F, bnd, n, return_solver=True)
    t2 = time.perf_counter()
    times["tutte"] = t2 - t1

    mu_tutte = beltrami_coefficient(tutte, F, V)
    L = generalized_laplacian(tutte, F, mu_tutte)
    t3 = time.perf_counter()
    times["beltrami"] = t3 - t2

    interior = complement(bnd, n)
    solve_interior = solver.refactorize(-L[interior][:, interior])
    # Torsion function: its maximum is the deepest point, mapped to 0.
    area = np.bincount(F.ravel(), weights=np.repeat(doublearea(V, F) / 6, 3), minlength=n)
    torsion = solve_interior(area[interior])
    center = int(interior[np.argmax(torsion)])
    omega, _ = harmonic_measure(L, bnd, center, solve_interior)
    z, repaired = _free_boundary_map(L, F, bnd, omega, solve_interior)
    z = mobius_normalize(z, center, bnd[0])
    uv = np.column_stack([z.real, z.imag])
    t4 = time.perf_counter()
    times["lbs"] = t4 - t3

    # Faces the map squeezes to zero area (below double precision, counted as folded)
    # have no finite mu.
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = beltrami_coefficient(uv, F, V)
    folded = int(np.count_nonzero(signed_doublearea(uv, F) <= 0))
    times["measure"] = time.perf_counter() - t4
    narrowest = int(np.count_nonzero((omega > 0) & (omega < MIN_BOUNDARY_ARC / (2 * np.pi))))
    return DiskMap(uv, mu, tutte, bnd, center, folded, repaired, narrowest, times)


def mobius_normalize(z, center, anchor):
    """Compose a disk map with the Moebius transformation of the disk that sends vertex
    ``center`` to 0 and vertex ``anchor`` (on the boundary) to 1:

        w = e^{i phi} (z - a) / (1 - conj(a) z),   a = z[center].

    The transformation is a conformal automorphism of the unit disk, so the boundary
    stays on the circle and the map stays conformal.

    Parameters
    ----------
    z : (n,) complex
    center, anchor : int

    Returns
    -------
    (n,) complex
    """
    a = z[center]
    w = (z - a) / (1 - np.conj(a) * z)
    w[center] = 0.0
    return w * (np.abs(w[anchor]) / w[anchor])


def _boundary_angles(omega):
    """Angles of the boundary vertices from their harmonic measures: the middle of each
    vertex's arc, the first vertex at 0.

    Non-positive measures (possible next to obtuse triangles) are raised to 1e-3 of the
    mean so the angles strictly increase. Positive measures are kept down to an arc of
    MIN_BOUNDARY_ARC: the harmonic measure decays exponentially along a protrusion (about
    exp(-pi L / w) at the end of a strip L long and w wide), and an arc below that is
    narrower than the triangulation of the landmarks resolves. Raised to 1e-3 of the
    mean instead, they leave the map far from conformal along the protrusion: on a strip
    8 times as long as wide, mean |mu| 0.31 instead of 0.17, and the remesh 12 % / 10 %
    short of its face count with mean radius ratio 0.95 / 0.89 at its count / half,
    instead of 2 % short and 0.96 / 0.95."""
    floor = np.where(omega > 0, MIN_BOUNDARY_ARC / (2 * np.pi), 1e-3 * omega.mean())
    omega = np.maximum(omega, floor)
    omega = omega / omega.sum()
    theta = 2 * np.pi * (np.cumsum(omega) - omega / 2)
    return theta - theta[0]


def _free_boundary_map(L, F, bnd, omega, solve_interior):
    theta = _boundary_angles(omega)
    zb = np.exp(1j * theta)
    z, _ = dirichlet_solve(L, bnd, zb, solve_interior)
    folded = int(np.count_nonzero(signed_doublearea(np.column_stack([z.real, z.imag]), F) <= 0))
    if folded == 0:
        return z, 0
    weights = L.data[L.indices != np.repeat(np.arange(L.shape[0]), np.diff(L.indptr))]
    floor = 1e-2 * np.median(weights[weights > 0])
    C = _clamped(L, floor)
    interior = complement(bnd, L.shape[0])
    z, _ = dirichlet_solve(C, bnd, zb, solve_interior.refactorize(-C[interior][:, interior]))
    return z, folded
