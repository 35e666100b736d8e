import re

import numpy as np
import pytest

from conftest import DATA, grid_disk, shared
from qcremesh import curvature_sizing, linear_beltrami_solver, mesh_quality, teichmuller_map
from qcremesh.mesh import validate as v
from qcremesh.mesh.io import read_mesh


def lift(uv):
    return np.column_stack([uv, np.zeros(len(uv))])


def test_disk_passes():
    uv, F = grid_disk(6)
    v.check_disk(lift(uv), F)


@pytest.mark.parametrize(
    "mesh, error, message",
    [
        ("alex_3.ply", v.TopologyError, "4 boundary loops, a disk has 1"),
        ("featuretype.STL", v.TopologyError, "16 boundary loops, a disk has 1"),
    ],
)
def test_bundled_hard_cases(mesh, error, message):
    V, F = read_mesh(DATA / mesh)
    with pytest.raises(error) as exc:
        v.check_disk(V, F)
    assert str(exc.value) == message


@pytest.mark.parametrize(
    "mesh, error, message",
    [
        ("decimated-max.obj", v.TopologyError, "closed surface (no boundary), a disk has 1 boundary loop"),
        ("Hand1.off", v.TopologyError, "genus 1 (Euler characteristic -1), a disk has genus 0"),
        (
            "face-YH.off",
            v.NonManifoldError,
            "3 non-manifold edges at vertices 44042-44089, 44042-54138, 44089-54138",
        ),
    ],
)
def test_shared_hard_cases(mesh, error, message):
    V, F = read_mesh(shared(mesh))
    with pytest.raises(error) as exc:
        v.check_disk(V, F)
    assert str(exc.value) == message


def test_as_mesh_arrays_keeps_the_values_or_refuses():
    """Whole-number float indices (MATLAB's doubles) and integer coordinates are taken;
    conversions that would change values are refused: fractional indices (truncated),
    booleans, complex coordinates (their imaginary part dropped)."""
    uv, F = grid_disk(4)
    V, G = v.as_mesh_arrays((10 * uv).astype(np.int32), F.astype(np.float64))
    assert V.dtype == np.float64 and G.dtype == np.int64
    np.testing.assert_array_equal(G, F)
    np.testing.assert_array_equal(V, (10 * uv).astype(np.int32))
    half = F.astype(np.float64)
    half[3, 1] += 0.5
    with pytest.raises(v.InvalidIndexError) as e:
        v.as_mesh_arrays(uv, half)
    assert str(e.value) == f"face indices must be whole numbers, got 1 that are not, e.g. {F[3, 1] + 0.5}"
    with pytest.raises(v.InvalidIndexError, match="^face indices must be integers, got bool$"):
        v.as_mesh_arrays(uv, F > 3)
    with pytest.raises(v.InvalidIndexError, match="^vertex coordinates must be real numbers, got complex128$"):
        v.as_mesh_arrays(uv + 1j, F)
    for bad in (uv.ravel(), np.zeros((len(uv), 4))):
        message = rf"^vertices must be an \(n, 2\) or \(n, 3\) array, got shape {re.escape(str(bad.shape))}$"
        with pytest.raises(v.InvalidIndexError, match=message):
            v.as_mesh_arrays(bad, F)


@pytest.mark.parametrize(
    "defect, message",
    [
        ("out of range", r"^face indices must lie in 0\.\.15, found 0\.\.17$"),
        ("negative", r"^face indices must lie in 0\.\.15, found -1\.\.15$"),
        ("quads", r"^faces must be a non-empty \(m, 3\) array, got shape \(18, 4\)$"),
        ("empty", r"^faces must be a non-empty \(m, 3\) array, got shape \(0, 3\)$"),
        ("flat", r"^faces must be a non-empty \(m, 3\) array, got shape \(54,\)$"),
        ("not finite", r"^vertex coordinates must be finite$"),
    ],
)
def test_entry_points_refuse_faces_that_do_not_index_the_vertices(defect, message):
    """What as_mesh_arrays refuses, every entry point that takes it refuses with the same
    words (numpy's IndexError, a failed factorization or a quality of NaN before)."""
    uv, F = grid_disk(4)
    V = lift(uv)
    G = {
        "out of range": np.where(F == 5, 17, F),
        "negative": np.where(F == 5, -1, F),
        "quads": np.column_stack([F, F[:, :1]]),
        "empty": F[:0],
        "flat": F.ravel(),
    }.get(defect, F)
    if defect == "not finite":
        V = np.where(np.arange(len(V))[:, None] == 3, np.nan, V)
    calls = [
        lambda: v.as_mesh_arrays(V, G),
        lambda: mesh_quality(V, G),
        lambda: curvature_sizing(V, G, 0.2),
        lambda: linear_beltrami_solver(V[:, :2], G, np.zeros(len(F)), np.array([0, 1]), V[[0, 1], :2]),
        lambda: teichmuller_map(V[:, :2], G, np.array([0]), V[[0], :2]),
    ]
    for call in calls:
        with pytest.raises(v.InvalidIndexError, match=message):
            call()


def test_each_defect_message():
    uv, F = grid_disk(4)
    V = lift(uv)
    with pytest.raises(v.InvalidIndexError, match=r"face indices must lie in 0\.\.15, found 0\.\.16"):
        v.check_disk(V, np.r_[F, [[0, 1, 16]]])
    with pytest.raises(v.UnreferencedVertexError) as e:
        v.check_disk(np.r_[V, [[5, 5, 5], [6, 6, 6]]], F)
    assert str(e.value) == "2 unreferenced vertices: 16, 17"
    Vd = V.copy()
    Vd[5] = (Vd[4] + Vd[6]) / 2  # collinear with its neighbours in a row
    Fd = np.r_[F, [[4, 5, 6]]]
    with pytest.raises(v.MeshError):
        v.check_disk(Vd, Fd)
    with pytest.raises(v.DegenerateFaceError) as e:
        v.check_triangle_mesh(V, np.r_[F, [[0, 0, 1]]])
    assert str(e.value) == f"1 degenerate face (zero area or within rounding of it): {len(F)}"
    middle = np.argmin(np.linalg.norm(uv[F].mean(1) - 0.5, axis=1))
    a, b = sorted(F[middle, :2])
    with pytest.raises(v.NonManifoldError) as e:
        v.check_triangle_mesh(np.r_[V, [[0.1, 0.1, 1.0]]], np.r_[F, [[a, b, 16]]])
    assert str(e.value) == f"1 non-manifold edge at vertices {a}-{b}"
    flipped = F.copy()
    flipped[middle] = flipped[middle, ::-1]
    with pytest.raises(v.OrientationError, match="faces are not consistently oriented: 3 edges"):
        v.check_triangle_mesh(V, flipped)
    two = np.r_[F, F + 16]
    with pytest.raises(v.TopologyError) as e:
        v.check_disk(np.r_[V, V + 2], two)
    assert str(e.value) == "2 connected components, a disk has 1"


def test_bowtie_message():
    V = np.array([[0, 0, 0], [1, 0, 0], [0, 1, 0], [-1, 0, 0], [0, -1, 0]], float)
    F = np.array([[0, 1, 2], [0, 3, 4]])
    with pytest.raises(v.NonManifoldError) as e:
        v.check_disk(V, F)
    assert str(e.value) == "1 non-manifold vertex (faces in several fans): 0"


def test_foldover_edges_find_where_the_surface_overlaps_itself():
    """A flat grid has no fold, nor does it bent by 90 degrees along a line; pushing one
    interior vertex across its neighbours turns some of its faces over, and the edges
    between those and the faces beside them (normals 180 degrees apart) are the folds."""
    uv, F = grid_disk(8)
    X = lift(uv)
    assert len(v.foldover_edges(X, F)) == 0
    bent = X.copy()
    bent[:, 2] = np.maximum(uv[:, 0] - 0.5, 0)
    bent[:, 0] = np.minimum(uv[:, 0], 0.5)
    assert len(v.foldover_edges(bent, F)) == 0
    centre = np.argmin(np.hypot(*(uv - 0.5).T))
    ring = np.unique(F[np.any(F == centre, axis=1)])
    X[centre, :2] += [0.3, 0.25]  # two grid steps across its neighbours
    folds = v.foldover_edges(X, F)
    assert len(folds) > 0
    assert np.all(np.isin(folds, ring))


def test_triangle_soup_is_told_to_be_welded():
    """A mesh whose faces share no vertex (each with corners of its own, as some writers
    export) gets the hint to weld them."""
    uv, F = grid_disk(4)
    V = lift(uv)[F].reshape(-1, 3)
    with pytest.raises(v.TopologyError) as e:
        v.check_disk(V, np.arange(len(V)).reshape(-1, 3))
    assert str(e.value) == (
        f"{len(F)} connected components, a disk has 1 (no two faces share a vertex: weld the coincident vertices first)"
    )



def test_check_not_soup():
    v.check_not_soup(np.array([[0, 1, 2]]))
    v.check_not_soup(np.array([[0, 1, 2], [2, 3, 4]]))
    with pytest.raises(v.TopologyError, match=r"^2 connected components, a disk has 1 \(no two faces share a "
                       r"vertex: weld the coincident vertices first\)$"):
        v.check_not_soup(np.array([[0, 1, 2], [3, 4, 5]]))


def test_in_space_puts_planar_vertices_in_the_plane_z_0():
    uv = np.array([[0.5, 1.0], [2.0, -1.0]])
    np.testing.assert_array_equal(v.in_space(uv), [[0.5, 1.0, 0.0], [2.0, -1.0, 0.0]])
    X = np.arange(6.0).reshape(2, 3)
    assert v.in_space(X) is X
