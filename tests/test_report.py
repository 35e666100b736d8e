import numpy as np
import pytest

from conftest import grid_disk
from qcremesh.cli.report import face_distances, plot_surfaces, surface_view


def _sheet():
    """A grid of the rectangle [0, 1] x [0, 3] in the plane z = 0, faces counter-clockwise
    seen from +z."""
    uv, F = grid_disk(9)
    return np.column_stack([uv[:, 0], 3 * uv[:, 1], np.zeros(len(uv))]), F


def test_surface_view_shows_the_side_the_faces_face_the_long_way_up():
    """A rotation (orthonormal rows, determinant 1) whose screen y is the longest axis of
    the vertices and whose third row points to the side the faces face; with the faces
    turned over, to the other side."""
    V, F = _sheet()
    R = surface_view(V, F)
    np.testing.assert_allclose(R @ R.T, np.eye(3), atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0)
    np.testing.assert_allclose(np.abs(R[1]), [0, 1, 0], atol=1e-12)
    np.testing.assert_allclose(R[2], [0, 0, 1], atol=1e-12)
    R = surface_view(V, F[:, ::-1])
    np.testing.assert_allclose(R[2], [0, 0, -1], atol=1e-12)
    assert np.linalg.det(R) == pytest.approx(1.0)


def test_face_distances_are_the_largest_over_centroid_and_edge_midpoints():
    """A copy of the sheet lifted by 0.1 is 0.1 from it on every face; the sheet itself
    0; a face with one corner raised by h is farthest at the midpoints of its two edges
    to that corner, h / 2."""
    V, F = _sheet()
    np.testing.assert_allclose(face_distances(V + [0, 0, 0.1], F, V, F), 0.1, rtol=1e-12)
    np.testing.assert_array_equal(face_distances(V, F, V, F), 0.0)
    T = np.array([[0.2, 0.2, 0.0], [0.6, 0.2, 0.0], [0.2, 0.6, 0.4]])
    assert face_distances(T, np.array([[0, 1, 2]]), V, F)[0] == pytest.approx(0.2)
    # one vertex of the sheet raised by 0.3: its faces 0.15 off (their edges to it), the others 0
    raised = V.copy()
    raised[40, 2] = 0.3
    expected = np.where((F == 40).any(axis=1), 0.15, 0.0)
    np.testing.assert_allclose(face_distances(raised, F, V, F), expected, atol=1e-12)


def test_plot_surfaces_draws_each_panel(tmp_path):
    pytest.importorskip("matplotlib")
    V, F = _sheet()
    q = np.linspace(0, 1, len(F))
    scale = {"vmin": 0.0, "vmax": 1.0, "cmap": "viridis", "label": "q"}
    plot_surfaces(tmp_path / "s.png", [(V, F, q, "a", scale), (V + 1, F, q, "b", scale)], surface_view(V, F))
    assert (tmp_path / "s.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
