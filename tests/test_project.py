import numpy as np

from conftest import DATA
from qcremesh.mesh.io import read_mesh
from qcremesh.mesh.topology import boundary_loop
from qcremesh.param.disk import disk_conformal_map
from qcremesh.remeshing.project import in_type, project_to_surface


def test_affine_fields_are_interpolated_exactly_inside_and_along_the_boundary():
    """Barycentric interpolation, and linear interpolation along the boundary polyline,
    reproduce an affine function of the positions: the lifted points lie on the surface
    (the fran_cut scan, through its disk map) and an affine field of its vertices is that
    function of the lifted points, to rounding."""
    V, F = read_mesh(DATA / "fran_cut.ply")
    dm = disk_conformal_map(V, F)
    rng = np.random.default_rng(0)
    r = np.sqrt(rng.uniform(0, 0.95**2, 300))
    t = rng.uniform(0, 2 * np.pi, 300)
    edge = rng.uniform(0, 2 * np.pi, 40)
    query = np.r_[np.column_stack([r * np.cos(t), r * np.sin(t)]), np.column_stack([np.cos(edge), np.sin(edge)])]
    on_circle = np.r_[np.zeros(300, dtype=bool), np.ones(40, dtype=bool)]
    M, c = np.array([[1.0, 2.0], [-0.5, 0.3], [0.7, -1.1]]), np.array([0.2, -0.4])
    X, field = project_to_surface(dm.uv, F, dm.boundary, query, on_circle, [V, V @ M + c])
    assert X.shape == (340, 3) and field.shape == (340, 2)
    np.testing.assert_allclose(field, X @ M + c, atol=1e-12)
    # the boundary points on the boundary polyline: each on a segment between consecutive
    # boundary vertices
    b = boundary_loop(F)
    A, B = V[b], V[np.roll(b, -1)]
    diag = np.linalg.norm(np.ptp(V, axis=0))
    for p in X[on_circle]:
        s = np.clip(((p - A) * (B - A)).sum(1) / ((B - A) ** 2).sum(1), 0, 1)
        assert np.linalg.norm(A + s[:, None] * (B - A) - p, axis=1).min() < 1e-12 * diag
    # at the angles of the boundary vertices' own images, the boundary vertices themselves
    at = np.angle(dm.uv[b, 0] + 1j * dm.uv[b, 1])
    circle = np.column_stack([np.cos(at), np.sin(at)])
    (Xb,) = project_to_surface(dm.uv, F, dm.boundary, circle, np.ones(len(b), dtype=bool), [V])
    np.testing.assert_allclose(Xb, V[b], atol=1e-9 * diag)


def test_fields_come_back_in_their_type():
    """Colours of 0-255 as bytes are rounded and clipped to what a byte holds, labels of
    a signed type rounded, flags true where the interpolated value is at least 1/2,
    float32 stays float32."""
    values = np.array([-3.2, 0.4, 0.6, 254.6, 300.0])
    np.testing.assert_array_equal(in_type(values, np.dtype(np.uint8)), [0, 0, 1, 255, 255])
    assert in_type(values, np.dtype(np.uint8)).dtype == np.uint8
    np.testing.assert_array_equal(in_type(values, np.dtype(np.int16)), [-3, 0, 1, 255, 300])
    np.testing.assert_array_equal(in_type(np.array([0.2, 0.5, 0.9]), np.dtype(bool)), [False, True, True])
    assert in_type(values, np.dtype(np.float32)).dtype == np.float32
