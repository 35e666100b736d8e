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

Intrinsic Delaunay triangulation. That Laplacian has negative weights wherever two
angles opposite an edge sum to more than pi, and a triangulation sheared throughout (a
star-shaped domain meshed by pushing a disk mesh out along its rays, mean radius ratio
0.49) gets a map far from conformal: mean |mu| 0.32 on the input's faces, and a remesh
with slivers (smallest radius ratio 0.01 / 0.00 at its face count / half). Where the
map's mean |mu| is above ``INTRINSIC_MU``, steps 1-4 run again on the intrinsic Delaunay
triangulation of the surface (:mod:`qcremesh.geometry.intrinsic`: the same vertices and
the same flat metric on every input triangle, edges flipped until no two opposite angles
sum to more than pi; the metric of step 2 from its edge lengths,
:func:`~qcremesh.beltrami.coefficient.metric_beltrami_coefficient`), whose interior
weights are all non-negative, and the map closer to conformal is kept: the star's has
mean |mu| 0.10, its remesh a smallest radius ratio of 0.63. The scans of
``../shared/data`` have 0.01-0.03 on their own triangulation and are not mapped again
(on the intrinsic one their remeshes came out as good, within the spread over CVT seeds,
at 0.04-0.1 s more).

Free boundary. The boundary correspondence of the Riemann map f: S -> D with f(p) = 0 is
the harmonic measure of the boundary seen from p: the arc of the circle that a piece of
the boundary maps to has length 2 pi omega_p(piece). Discretely, with L the generalized
Laplacian of step 3 and G the Green's function (-L G = delta_p inside, G = 0 on the
boundary), the harmonic measure of the dual boundary cell of a boundary vertex b is the
flux (L G)_b, and these fluxes sum to 1. Each boundary vertex goes to the middle of its
arc, theta_b = 2 pi (sum_{c < b} omega_c + omega_b / 2), and the interior follows from the
LBS with those boundary values. Measured against the alternatives on the meshes of
``../shared/data`` (see docs/disk_map.md): this is the most accurate of the linear
methods tried and needs a single factorization, reused for three solves; its ordering
and symbolic analysis are those of the Tutte embedding's matrix, which has the same
pattern.

Normalization of the Moebius freedom: a vertex p in the middle of the region where the
torsion function (-L u = vertex areas, u = 0 on the boundary) is near its maximum, the
deepest part of the surface, far from every boundary, goes to 0 (see
:func:`_plateau_centre`), and the boundary vertex with the smallest index goes to 1. The
discrete solve puts p within about 1e-4 of 0; a Moebius transformation of the disk
(:func:`mobius_normalize`) makes both exact.

Bijectivity. With non-negative weights and the boundary on a circle, Tutte's and
Floater's theorems make a discrete harmonic map bijective; with the negative weights of
obtuse triangles, or on an intrinsic triangulation whose triangles are not the input's,
a needle of the input can come out folded (camel_b: one face; hand.ply subdivided
twice: three). Folded faces (signed area <= 0) are detected and unfolded by a local
Tutte relaxation around them (:func:`_untangle`); the number of folds found and repaired
is reported.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
from scipy.sparse.csgraph import dijkstra

from ..beltrami.coefficient import beltrami_coefficient, metric_beltrami_coefficient
from ..beltrami.solver import generalized_laplacian
from ..geometry.intrinsic import intrinsic_cotmatrix, intrinsic_delaunay
from ..geometry.linsolve import complement, dirichlet_solve, spd_solver
from ..geometry.operators import signed_doublearea, vertex_areas
from ..mesh.topology import adjacency_matrix, boundary_loop, edges, face_edge_lengths
from ..mesh.validate import TopologyError, as_mesh_arrays, check_disk
from .tutte import tutte_embedding

__all__ = ["DiskMap", "disk_conformal_map", "harmonic_measure", "mobius_normalize"]

# Narrowest arc of the circle a boundary vertex of the disk map gets (radians): Qhull's
# Delaunay triangulation of landmarks on the circle loses points closer than about 1e-7.
MIN_BOUNDARY_ARC = 1e-6

# Rounds of the local Tutte relaxation that unfolds the few faces a harmonic map folds
# (see _untangle).
UNTANGLE_ROUNDS = 200

# Where a face of the Tutte embedding has |mu| within this of 1 (a dilatation above 1e6),
# the generalized Laplacian is built from the surface's side lengths instead.
MU_PRECISION = 1e-6
# Above this mean |mu| the map is computed again on the intrinsic Delaunay triangulation
# of the surface, and the closer to conformal of the two kept (the scans of
# ../shared/data: 0.02-0.03 on their own triangulation).
INTRINSIC_MU = 0.05

# The centre of the map is the middle of the region where the torsion function is within
# this fraction of its maximum (see _plateau_centre).
PLATEAU = 0.1


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
    intrinsic_flips : int
        Edge flips from the input's triangulation to its intrinsic Delaunay
        triangulation, where the map was computed on it (0 otherwise).
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
    intrinsic_flips: int = 0
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
    V, F = as_mesh_arrays(V, F)
    bnd = check_disk(V, F) if check else boundary_loop(F)
    if len(bnd) == len(V):
        raise TopologyError(
            "every vertex is on the boundary; the disk map needs an interior vertex (split the faces 1-to-4 first)"
        )
    times["validate"] = time.perf_counter() - t0

    result = _map_on(V, F, bnd, F, None, times)
    if result.mean_abs_mu > INTRINSIC_MU:
        # The input's triangulation may be what spoils the map: the same surface on its
        # intrinsic Delaunay triangulation, kept where the map comes out closer to
        # conformal.
        t = time.perf_counter()
        F_int, lengths, _, flips = intrinsic_delaunay(V, F)
        times["intrinsic"] = time.perf_counter() - t
        if flips:
            other = _map_on(V, F, bnd, F_int, lengths, times)
            if other.mean_abs_mu < result.mean_abs_mu:
                result = other
                result.intrinsic_flips = flips
    result.times = times
    return result


def _map_on(V, F, bnd, T, lengths, times):
    """Steps 1-4 on the triangulation ``T`` of the surface: the input's ``F`` (``lengths``
    None: the metric of the embedding), or its intrinsic Delaunay triangulation with side
    lengths ``lengths``; the map of the input's vertices, measured on its faces ``F``."""
    n = len(V)
    t1 = time.perf_counter()
    tutte, solver = tutte_embedding(T, bnd, n, return_solver=True)
    t2 = time.perf_counter()
    times["tutte"] = times.get("tutte", 0.0) + t2 - t1

    mu = None
    if np.all(signed_doublearea(tutte, T) > 0):
        mu = beltrami_coefficient(tutte, T, V) if lengths is None else metric_beltrami_coefficient(tutte, T, lengths)
    if mu is not None and np.all(np.abs(mu) < 1 - MU_PRECISION):
        L = generalized_laplacian(tutte, T, mu)
    else:
        # A Tutte embedding can flatten faces (of an intrinsic triangulation whose edges
        # run twice between two vertices), or squeeze them so that |mu| rounds to 1 (a CAD
        # cylinder cut open: its caps' fans along the cut); the operator is the same
        # without it.
        L = intrinsic_cotmatrix(T, face_edge_lengths(V, T) if lengths is None else lengths, n)
    t3 = time.perf_counter()
    times["beltrami"] = times.get("beltrami", 0.0) + t3 - t2

    interior = complement(bnd, n)
    solve_interior = solver.refactorize(-L[interior][:, interior])
    area = vertex_areas(V, F, n)
    torsion = np.zeros(n)
    torsion[interior] = solve_interior(area[interior])
    center = _plateau_centre(V, F, torsion)
    omega, _ = harmonic_measure(L, bnd, center, solve_interior)
    z = mobius_normalize(_free_boundary_map(L, bnd, omega, solve_interior), center, bnd[0])
    # Faces of the input that the map folds (needles, or faces across the obtuse angles
    # whose cotangent weights are negative) are unfolded after the normalization, which
    # could turn a face left nearly flat over.
    z, repaired, folded = _untangle(z, F, bnd)
    uv = np.column_stack([z.real, z.imag])
    t4 = time.perf_counter()
    times["lbs"] = times.get("lbs", 0.0) + t4 - t3

    # Faces the map squeezes to zero area (below double precision, counted as folded)
    # have no finite mu.
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = beltrami_coefficient(uv, F, V)
    times["measure"] = times.get("measure", 0.0) + time.perf_counter() - t4
    narrowest = int(np.count_nonzero((omega > 0) & (omega < MIN_BOUNDARY_ARC / (2 * np.pi))))
    return DiskMap(uv, mu, tutte, bnd, center, folded, repaired, narrowest)


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


def _plateau_centre(V, F, torsion):
    """The middle of the longest shortest path (along the edges) across the region, around
    the maximum of the torsion function, where it is within ``PLATEAU`` of the maximum.

    Along a long part of a surface of constant width (a strip, a finger) the torsion
    function is flat to within rounding, and its maximum falls anywhere along it: at 5.2
    of a strip 8 long (jittered grid), whose far end the map then crowds by exp(-pi 5.2)
    instead of exp(-pi 4) (mean |mu| 0.23 against 0.13 from the middle). The region is
    then a band along the part, and the middle of its longest path the middle of the
    part; elsewhere the region is a small patch around the maximum. The path's ends are
    found by two sweeps of Dijkstra's algorithm (from the maximum to the farthest vertex,
    and from there to the farthest again)."""
    plateau = torsion >= (1 - PLATEAU) * torsion.max()
    # (the edges of the faces with two corners or more on the plateau: no sort of them all)
    near = F[plateau[F].sum(1) >= 2]
    E = edges(near) if len(near) else np.zeros((0, 2), dtype=np.int64)
    E = E[plateau[E[:, 0]] & plateau[E[:, 1]]]
    length = np.linalg.norm(V[E[:, 0]] - V[E[:, 1]], axis=1)
    graph = sp.csr_matrix((length, (E[:, 0], E[:, 1])), shape=(len(V), len(V)))
    start = int(np.argmax(torsion))
    reach = dijkstra(graph, directed=False, indices=start)
    end = int(np.argmax(np.where(np.isfinite(reach), reach, -1.0)))
    reach, previous = dijkstra(graph, directed=False, indices=end, return_predecessors=True)
    far = int(np.argmax(np.where(np.isfinite(reach), reach, -1.0)))
    path = [far]
    while path[-1] != end:
        path.append(int(previous[path[-1]]))
    path = np.array(path)
    return int(path[np.argmin(np.abs(reach[path] - reach[far] / 2))])


def _free_boundary_map(L, bnd, omega, solve_interior):
    theta = _boundary_angles(omega)
    return dirichlet_solve(L, bnd, np.exp(1j * theta), solve_interior)[0]


def _untangle(z, F, bnd):
    """Unfold the faces of a disk map by local Tutte relaxation: in each round, the
    interior vertices of the folded faces and of the faces around them go to the mean of
    their neighbours (one Jacobi sweep of the uniform Laplacian there, the rest staying),
    until no face is folded or after ``UNTANGLE_ROUNDS`` rounds. A Tutte embedding folds
    no face, and the few faces a harmonic map folds are needles whose neighbourhood it
    maps well, so this ends within a few rounds and moves few vertices.

    Returns the map, the number of faces folded (signed area <= 0) before and after."""
    folded = signed_doublearea(np.column_stack([z.real, z.imag]), F) <= 0
    before = int(np.count_nonzero(folded))
    if before == 0:
        return z, 0, 0
    n = len(z)
    interior = np.ones(n, dtype=bool)
    interior[bnd] = False
    z = z.copy()
    for _ in range(UNTANGLE_ROUNDS):
        region = np.zeros(n, dtype=bool)
        region[F[folded].ravel()] = True
        # The corners of the faces at the region are the region and its neighbours; the
        # faces at those hold all their edges, so the adjacency of those faces alone has
        # their whole rows (not the whole mesh's: 1.4 s at 1.7M faces for a few folds).
        near = np.zeros(n, dtype=bool)
        near[F[region[F].any(axis=1)].ravel()] = True
        A = adjacency_matrix(F[near[F].any(axis=1)], n)
        v = np.flatnonzero(near & interior)
        z[v] = (A[v] @ z) / np.diff(A.indptr)[v]
        folded = signed_doublearea(np.column_stack([z.real, z.imag]), F) <= 0
        if not folded.any():
            break
    return z, before, int(np.count_nonzero(folded))
