import numpy as np

from qcremesh.geometry.vectors import cross, norm


def test_cross_of_the_basis_is_right_handed():
    e = np.eye(3)
    np.testing.assert_array_equal(cross(e, np.roll(e, -1, axis=0)), np.roll(e, -2, axis=0))
    np.testing.assert_array_equal(cross(e[0], e[0]), np.zeros(3))


def test_cross_is_numpy_cross_to_the_last_bit():
    rng = np.random.default_rng(7)
    a, b = rng.normal(size=(2, 500, 4, 3)) * 10.0 ** rng.integers(-8, 8, size=(2, 500, 1, 1))
    assert np.array_equal(cross(a, b), np.cross(a, b))
    # broadcast as numpy.cross: one vector against many
    assert np.array_equal(cross(a[:, 0], b[0, 0]), np.cross(a[:, 0], b[0, 0]))


def test_norm_is_numpy_norm_to_the_last_bit():
    """Lengths of 2- and 3-vectors over many scales, on contiguous arrays and on views
    whose last axis is strided (the corners of faces, a transposed array)."""
    rng = np.random.default_rng(8)
    for d in (2, 3):
        a = rng.normal(size=(500, 4, d)) * 10.0 ** rng.integers(-150, 150, size=(500, 4, d))
        assert np.array_equal(norm(a), np.linalg.norm(a, axis=-1))
        view = np.ascontiguousarray(a.transpose(2, 0, 1)).transpose(1, 2, 0)
        assert np.array_equal(norm(view), np.linalg.norm(view, axis=-1))
    np.testing.assert_array_equal(norm([[3.0, 4.0, 12.0], [np.inf, 0.0, 1.0]]), [13.0, np.inf])


def test_aligned():
    from qcremesh.geometry.vectors import aligned

    a = np.array([[0.0, 0.0, 1.0]] * 4)
    b = np.array([[0.0, 1e-7, 3.0], [0.0, 1e-5, 1.0], [0.0, 0.0, -1.0], [0.0, 0.0, 0.0]])
    assert aligned(a, b, 1e-6).tolist() == [True, False, False, False]  # a zero vector points nowhere
