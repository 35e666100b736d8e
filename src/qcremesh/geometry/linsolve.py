"""Sparse symmetric positive definite solves, factorized once and reused.

The factorization is PARDISO (through the optional ``pypardiso`` package, Intel MKL) when
it is installed, and SuperLU from scipy otherwise. SuperLU is run in symmetric mode with
a minimum-degree ordering of A + A^T and no pivoting, which is what an SPD matrix allows
and several times faster than its default.
"""

from __future__ import annotations

import os

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["spd_solver", "solver_backend", "dirichlet_solve"]

try:
    import pypardiso as _pypardiso
except ImportError:  # the optional "fast" extra
    _pypardiso = None


class _PardisoFactor:
    """PARDISO Cholesky factor of an SPD matrix; releases MKL's memory when collected
    (pypardiso itself keeps it until told).

    pypardiso searches the file system for MKL each time a solver is made (about 0.2 s);
    the path found the first time is handed to the next ones.
    """

    mkl_path = None

    def __init__(self, A):
        self.upper = sp.triu(A, format="csr")
        self.upper.sort_indices()
        self.solver = self._new_solver()
        self.solver.factorize(self.upper)

    @classmethod
    def _new_solver(cls):
        if cls.mkl_path is None or "PYPARDISO_MKL_RT" in os.environ:
            solver = _pypardiso.PyPardisoSolver(mtype=2)
            cls.mkl_path = solver.libmkl._name
            return solver
        os.environ["PYPARDISO_MKL_RT"] = cls.mkl_path
        try:
            return _pypardiso.PyPardisoSolver(mtype=2)
        finally:
            del os.environ["PYPARDISO_MKL_RT"]

    def __call__(self, B):
        return self.solver.solve(self.upper, np.ascontiguousarray(B))

    def __del__(self):
        self.solver.free_memory(everything=True)


def solver_backend():
    """Name of the sparse direct solver in use: ``"pardiso"`` or ``"superlu"``."""
    return "pardiso" if _pypardiso is not None else "superlu"


def spd_solver(A, backend=None):
    """Factorize a sparse symmetric positive definite matrix once.

    Parameters
    ----------
    A : (k, k) sparse matrix
        Symmetric positive definite.
    backend : {"pardiso", "superlu"}, optional
        Defaults to :func:`solver_backend`.

    Returns
    -------
    solve : callable
        ``solve(b)`` for ``b`` of shape (k,) or (k, r), real or complex, returns
        ``A^{-1} b`` with the shape and kind of ``b``.
    """
    backend = backend or solver_backend()
    A = sp.csr_matrix(A, dtype=np.float64)
    if A.shape[0] == 0:
        return lambda b: np.zeros_like(np.asarray(b, dtype=np.result_type(b, np.float64)))
    if backend == "pardiso":
        if _pypardiso is None:
            raise ImportError("the pardiso backend needs the pypardiso package")
        real_solve = _PardisoFactor(A)

    elif backend == "superlu":
        lu = spla.splu(
            A.tocsc(),
            permc_spec="COLAMD",
            diag_pivot_thresh=0.0,
            options={"SymmetricMode": True},
        )
        real_solve = lu.solve
    else:
        raise ValueError(f"unknown solver backend {backend!r}")

    def solve(b):
        b = np.asarray(b)
        vector = b.ndim == 1
        B = b.reshape(len(b), -1)
        if np.iscomplexobj(B):
            r = B.shape[1]
            X = real_solve(np.hstack([B.real, B.imag]).astype(np.float64))
            X = X.reshape(len(b), -1)
            X = X[:, :r] + 1j * X[:, r:]
        else:
            X = np.asarray(real_solve(B.astype(np.float64))).reshape(len(b), -1)
        return X[:, 0] if vector else X

    return solve


def dirichlet_solve(L, known, values, solve_free=None):
    """Solve L x = 0 at the free vertices with x prescribed at ``known``.

    Symmetric elimination: with I the free and K the known vertices,
    -L_II x_I = L_IK x_K, and -L_II is symmetric positive definite when every component of
    the mesh has a known vertex.

    Parameters
    ----------
    L : (n, n) sparse, symmetric, negative semi-definite
    known : (k,) int
    values : (k,) or (k, r) float or complex
    solve_free : callable, optional
        A factorized ``(-L_II)^{-1}`` to reuse (as returned by ``spd_solver``).

    Returns
    -------
    x : (n,) or (n, r)
    solve_free : callable
        The factorization of -L_II, for further solves with the same matrix.
    """
    L = sp.csr_matrix(L)
    n = L.shape[0]
    known = np.asarray(known)
    free = np.ones(n, dtype=bool)
    free[known] = False
    free = np.flatnonzero(free)
    values = np.asarray(values)
    rows = L[free]
    if solve_free is None:
        solve_free = spd_solver(-rows[:, free])
    rhs = rows[:, known] @ values
    x = np.zeros((n,) + values.shape[1:], dtype=np.result_type(values, np.float64))
    x[known] = values
    x[free] = solve_free(rhs)
    return x, solve_free
