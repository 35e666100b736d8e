"""Row-wise vectorized functions run on chunks of rows in a thread pool.

NumPy releases the GIL inside its array loops, so a function whose output rows depend
only on the matching input rows (a closest-point search, say) runs on two halves of its
rows in two threads nearly twice as fast, with the same result to the last bit.
"""

from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

__all__ = ["available_cores", "map_row_chunks", "query_workers"]

# Fewest rows per chunk: below this the threads' overhead outweighs the gain.
MIN_CHUNK_ROWS = 4096

_pool = None


def available_cores():
    """Number of cores this process may run on."""
    if hasattr(os, "sched_getaffinity"):
        return len(os.sched_getaffinity(0))
    return os.cpu_count() or 1


def query_workers(count):
    """The ``workers`` argument of scipy's ``cKDTree.query`` for ``count`` query points:
    -1 (every core) from MIN_CHUNK_ROWS up, else 1. scipy starts a thread per core on
    every call with -1, which costs more than a small query (the CVT of a few hundred
    landmarks queries a few thousand samples, about a hundred times: 0.5 s of the 1.3 s
    of remeshing an open box of 2,250 faces along its creases went to starting threads)."""
    return -1 if count >= MIN_CHUNK_ROWS else 1


def _executor():
    global _pool
    if _pool is None:
        _pool = ThreadPoolExecutor(max_workers=available_cores(), thread_name_prefix="qcremesh")
    return _pool


def map_row_chunks(func, rows, shared=(), workers=-1):
    """``func(*rows, *shared)`` computed on chunks of the rows, in parallel, and
    concatenated.

    Parameters
    ----------
    func : callable
        Returns a tuple of arrays whose row i depends only on row i of each of ``rows``.
    rows : sequence of (k, ...) arrays
        Arguments split along their first axis.
    shared : sequence
        Arguments passed whole to every chunk.
    workers : int
        Number of threads; -1 for every available core. Fewer are used where a chunk
        would get under 4096 rows.

    Returns
    -------
    tuple of arrays
        The same as ``func(*rows, *shared)``.

    Examples
    --------
    >>> a = np.arange(20000.0)
    >>> map_row_chunks(lambda x, c: (x * c, x + c), [a], [2.0])[0][-1]
    np.float64(39998.0)
    """
    k = len(rows[0])
    workers = available_cores() if workers == -1 else max(int(workers), 1)
    chunks = min(workers, k // MIN_CHUNK_ROWS)
    if chunks <= 1:
        return func(*rows, *shared)
    bounds = np.linspace(0, k, chunks + 1).astype(int)
    pool = _executor()
    futures = [
        pool.submit(func, *(r[lo:hi] for r in rows), *shared) for lo, hi in zip(bounds[1:-1], bounds[2:])
    ]
    first = func(*(r[bounds[0] : bounds[1]] for r in rows), *shared)
    parts = [first] + [f.result() for f in futures]
    return tuple(np.concatenate(p) for p in zip(*parts))
