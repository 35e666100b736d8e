import numpy as np

from qcremesh.geometry.vectors import cross


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
