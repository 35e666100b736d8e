import numpy as np
import pytest

from conftest import grid_disk
from qcremesh.geometry.threads import MIN_CHUNK_ROWS, map_row_chunks, query_workers
from qcremesh.mesh.topology import vertex_face_incidence
from qcremesh.remeshing.onsurface import closest_point_near


def test_chunks_give_the_serial_result():
    rows = np.random.default_rng(0).standard_normal((5 * MIN_CHUNK_ROWS + 7, 3))

    def norms_and_signs(x, scale):
        return scale * np.linalg.norm(x, axis=1), np.sign(x)

    serial = norms_and_signs(rows, 2.0)
    for workers in (1, 2, 3, -1):
        chunked = map_row_chunks(norms_and_signs, [rows], [2.0], workers=workers)
        assert len(chunked) == 2
        assert all(np.array_equal(a, b) for a, b in zip(serial, chunked))


def test_few_rows_run_in_one_call():
    calls = []

    def record(x):
        calls.append(len(x))
        return (x,)

    map_row_chunks(record, [np.zeros(MIN_CHUNK_ROWS + 1)], workers=2)
    assert calls == [MIN_CHUNK_ROWS + 1]


@pytest.mark.parametrize("workers", [2, -1])
def test_closest_point_search_is_the_same_on_threads(workers):
    """Points scattered over a wavy surface: the same faces, points and coordinates to the
    last bit with one thread and with several."""
    uv, F = grid_disk(120)
    V = np.column_stack([uv, 0.05 * np.sin(9 * uv[:, 0]) * np.cos(7 * uv[:, 1])])
    rng = np.random.default_rng(1)
    start = rng.integers(0, len(F), 4 * MIN_CHUNK_ROWS)
    P = V[F[start]].mean(1) + 0.02 * rng.standard_normal((len(start), 3))
    vf = vertex_face_incidence(F, len(V))
    one = closest_point_near(P, start, V, F, vf, workers=1)
    many = closest_point_near(P, start, V, F, vf, workers=workers)
    assert all(np.array_equal(a, b) for a, b in zip(one, many))


def test_small_queries_start_no_threads():
    assert query_workers(0) == query_workers(MIN_CHUNK_ROWS - 1) == 1
    assert query_workers(MIN_CHUNK_ROWS) == query_workers(10**6) == -1
