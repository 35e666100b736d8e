"""Checks that a triangle mesh is what an algorithm needs, with one-line errors.

Each kind of defect has its own exception class, all subclasses of :class:`MeshError`
(itself a :class:`ValueError`), and its message names the defect and where it is, e.g.
``"3 boundary loops, a disk has 1"`` or ``"2 non-manifold edges at vertices 4-7, 9-12"``.
"""

from __future__ import annotations

import numpy as np

from . import topology

__all__ = [
    "MeshError",
    "InvalidIndexError",
    "UnreferencedVertexError",
    "DegenerateFaceError",
    "NonManifoldError",
    "OrientationError",
    "TopologyError",
    "as_face_array",
    "as_mesh_arrays",
    "check_triangle_mesh",
    "check_disk",
    "check_not_soup",
    "foldover_edges",
    "in_space",
    "is_triangle_soup",
]


class MeshError(ValueError):
    """The mesh cannot be processed as it is."""


class InvalidIndexError(MeshError):
    """Face or vertex array of the wrong shape or type, indices out of range, coordinates
    that are not finite."""


class UnreferencedVertexError(MeshError):
    """Vertices that no face uses."""


class DegenerateFaceError(MeshError):
    """Faces of zero area or within rounding of it (needles and caps)."""


class NonManifoldError(MeshError):
    """Edges with more than two faces, or vertices whose faces form several fans."""


class OrientationError(MeshError):
    """Neighbouring faces with opposite orientations."""


class TopologyError(MeshError):
    """Wrong number of components or boundary loops, or wrong genus."""


def _some(items, k=5):
    items = list(items)
    head = ", ".join(items[:k])
    return head + (f", ... ({len(items) - k} more)" if len(items) > k else "")


def _plural(n, word):
    return f"{n} {word}" + ("" if n == 1 else "s")


def as_mesh_arrays(V, F):
    """Vertices as float64 and faces as int64 arrays, as the algorithms here take them,
    where the conversion keeps their values and the faces index the vertices: complex
    coordinates (whose imaginary part numpy drops), coordinates that are not finite,
    face indices that are not whole numbers (numpy truncates 2.5 to 2), booleans, faces
    that are not triangles and indices out of range are refused. Floating-point indices
    that are whole numbers (MATLAB's doubles) are taken.

    Parameters
    ----------
    V : (n, d) array_like of real numbers, d 2 or 3
    F : (m, 3) array_like of integers in 0..n-1

    Returns
    -------
    V : (n, d) float64
    F : (m, 3) int64

    Raises
    ------
    InvalidIndexError
    """
    V = np.asarray(V)
    if V.dtype == bool or not np.issubdtype(V.dtype, np.number) or np.iscomplexobj(V):
        raise InvalidIndexError(f"vertex coordinates must be real numbers, got {V.dtype}")
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise InvalidIndexError(f"vertices must be an (n, 2) or (n, 3) array, got shape {V.shape}")
    F = as_face_array(F, len(V))
    _check_finite(V)
    return V.astype(np.float64, copy=False), F


def in_space(V):
    """Vertices (n, 2) or (n, 3) as (n, 3): planar ones in the plane z = 0."""
    V = np.asarray(V)
    return np.column_stack([V, np.zeros(len(V))]) if V.shape[1] == 2 else V


def as_face_array(F, n=None):
    """Face indices as an int64 array, where the conversion keeps their values (see
    :func:`as_mesh_arrays`): a non-empty (m, 3) array of whole numbers in 0..n-1
    (non-negative without ``n``); booleans and non-numbers are refused.

    Parameters
    ----------
    F : (m, 3) array_like of integers
    n : int, optional
        Number of vertices.

    Returns
    -------
    F : (m, 3) int64

    Raises
    ------
    InvalidIndexError
    """
    F = np.asarray(F)
    _check_face_shape(F)
    if F.dtype == bool or not (np.issubdtype(F.dtype, np.integer) or np.issubdtype(F.dtype, np.floating)):
        raise InvalidIndexError(f"face indices must be integers, got {F.dtype}")
    if np.issubdtype(F.dtype, np.floating):
        fractional = F[~(np.isfinite(F) & (F == np.round(F)))]
        if len(fractional):
            raise InvalidIndexError(
                f"face indices must be whole numbers, got {len(fractional)} that are not, e.g. {fractional[0]}"
            )
    F = F.astype(np.int64, copy=False)
    _check_index_range(F, n)
    return F


def _check_face_shape(F):
    if F.ndim != 2 or F.shape[1] != 3 or len(F) == 0:
        raise InvalidIndexError(f"faces must be a non-empty (m, 3) array, got shape {F.shape}")


def _check_index_range(F, n):
    """Indices in 0..n-1 (non-negative where n is None)."""
    low, high = F.min(), F.max()
    if low < 0 or (n is not None and high >= n):
        bound = "0.." if n is None else f"0..{n - 1}"
        raise InvalidIndexError(f"face indices must lie in {bound}, found {low}..{high}")


def _check_finite(V):
    if not np.all(np.isfinite(V)):
        raise InvalidIndexError("vertex coordinates must be finite")


def check_triangle_mesh(V, F):
    """Check a mesh for the defects every algorithm here rejects.

    Indices in range, every vertex used, no degenerate face, edge- and vertex-manifold,
    consistently oriented. Raises the matching :class:`MeshError` subclass on the first
    defect found, in that order.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    """
    _check_triangle_mesh(V, F)


def _check_triangle_mesh(V, F):
    """The checks of :func:`check_triangle_mesh`; the pairs of twin half-edges
    (:func:`qcremesh.mesh.topology.twin_half_edges`) that the last ones share."""
    V = np.asarray(V)
    F = np.asarray(F)
    _check_face_shape(F)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise InvalidIndexError(f"vertices must be an (n, 3) array, got shape {V.shape}")
    if not np.issubdtype(F.dtype, np.integer):
        raise InvalidIndexError(f"face indices must be integers, got {F.dtype}")
    _check_index_range(F, len(V))
    _check_finite(V)
    unref = topology.unreferenced_vertices(F, len(V))
    if len(unref):
        raise UnreferencedVertexError(
            f"{_plural(len(unref), 'unreferenced vertex')}: {_some(map(str, unref))}".replace(
                "vertexs", "vertices"
            )
        )
    degen = topology.degenerate_faces(V, F)
    if len(degen):
        raise DegenerateFaceError(
            f"{_plural(len(degen), 'degenerate face')} (zero area or within rounding of it): "
            f"{_some(map(str, degen))}"
        )
    # one sort of the edges for the three checks on them
    twins = topology.twin_half_edges(F)
    bad_edges = topology.nonmanifold_edges(F, twins)
    if len(bad_edges):
        where = _some(f"{a}-{b}" for a, b in bad_edges)
        raise NonManifoldError(f"{_plural(len(bad_edges), 'non-manifold edge')} at vertices {where}")
    pinched = topology.nonmanifold_vertices(F, twins)
    if len(pinched):
        raise NonManifoldError(
            f"{_plural(len(pinched), 'non-manifold vertex')} (faces in several fans): "
            f"{_some(map(str, pinched))}".replace("vertexs", "vertices")
        )
    flipped = topology.inconsistent_edges(F, twins)
    if len(flipped):
        where = _some(f"{a}-{b}" for a, b in flipped)
        raise OrientationError(
            f"faces are not consistently oriented: {_plural(len(flipped), 'edge')} "
            f"traversed twice in the same direction, at vertices {where}"
        )
    return twins


def check_disk(V, F):
    """Check that a mesh is a topological disk, as a disk parameterization needs.

    A disk is one manifold, consistently oriented component with exactly one boundary
    loop and Euler characteristic 1 (genus 0). The checks of
    :func:`check_triangle_mesh` come first.

    Returns
    -------
    (b,) int64
        The boundary loop (see :func:`qcremesh.mesh.topology.boundary_loops`).

    Raises
    ------
    MeshError
        A subclass naming the first defect, e.g. ``TopologyError("3 boundary loops, a
        disk has 1")`` or ``TopologyError("genus 1 (Euler characteristic -1), a disk has
        genus 0")``.
    """
    twins = _check_triangle_mesh(V, F)
    ncomp, _ = topology.connected_components(F, len(V))
    if ncomp != 1:
        check_not_soup(F)
        raise TopologyError(f"{ncomp} connected components, a disk has 1")
    loops = topology.boundary_loops(F, twins)
    if len(loops) == 0:
        raise TopologyError("closed surface (no boundary), a disk has 1 boundary loop")
    if len(loops) != 1:
        raise TopologyError(f"{len(loops)} boundary loops, a disk has 1")
    # Every edge is manifold here: 3 m = 2 E_interior + E_boundary.
    m = len(F)
    chi = len(V) - (3 * m + len(loops[0])) // 2 + m
    if chi != 1:
        genus = (2 - chi - len(loops)) // 2
        raise TopologyError(f"genus {genus} (Euler characteristic {chi}), a disk has genus 0")
    return loops[0]


def is_triangle_soup(F):
    """Whether the faces F (m, 3) are a triangle soup: more than one face, and no two
    sharing a vertex (an export that gave every face its own corners)."""
    F = np.asarray(F)
    return len(F) > 1 and np.bincount(F.ravel()).max() == 1


def check_not_soup(F):
    """Raise TopologyError for a triangle soup (:func:`is_triangle_soup`), which the
    remesh would take for as many pieces as it has faces."""
    if is_triangle_soup(F):
        raise TopologyError(
            f"{len(F)} connected components, a disk has 1 (no two faces share a vertex: weld the coincident "
            "vertices first)"
        )


def foldover_edges(V, F, angle=170.0):
    """Interior edges where the surface folds back onto itself: the normals of their two
    faces differ by more than ``angle`` degrees.

    No check above finds a surface that overlaps itself (a flat disk whose triangles were
    pushed across each other), as its connectivity is sound; its folds are such edges. A
    real surface has few: human_face.obj 2 of its 51k interior edges (the walls of its
    narrowest slits), decimated-max.obj 16 of 15.8k, the other disk meshes of
    ../shared/data none.

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
        Consistently oriented faces.
    angle : float
        In degrees.

    Returns
    -------
    (k, 2) int64
        The edges, as vertex pairs.
    """
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    normal = np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]])
    normal /= np.maximum(np.linalg.norm(normal, axis=1, keepdims=True), 1e-300)
    i, j = topology.twin_half_edges(F)
    m = len(F)
    turned = (normal[i % m] * normal[j % m]).sum(1) < np.cos(np.radians(angle))
    return topology.half_edges(F)[i[turned]]
