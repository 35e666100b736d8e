"""Sparse symmetric positive definite solves, factorized once and reused.

The factorization is PARDISO (through the optional ``pypardiso`` package, Intel MKL) when
it is installed, and SuperLU from scipy otherwise. SuperLU is run in symmetric mode with
a minimum-degree ordering of A + A^T and no pivoting, which is what an SPD matrix allows
and several times faster than its default (on the cotangent Laplacian of hand.ply, 53k
vertices: 0.23 s and 4.2M factor entries, against 0.32 s and 6.7M with COLAMD).

A factorization can be redone for another matrix with the same sparsity pattern
(:meth:`SPDSolver.refactorize`): the fill-reducing ordering and the symbolic analysis,
which cost more than the numerical factorization on meshes, are kept. The Tutte
embedding and the linear Beltrami solver of the same mesh share them this way.
"""

from __future__ import annotations

import os
import weakref

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

__all__ = ["SPDSolver", "spd_solver", "solver_backend", "dirichlet_solve", "complement"]

try:
    import pypardiso as _pypardiso
except ImportError:  # the optional "fast" extra
    _pypardiso = None

# PARDISO settings (0-based iparm indices of the MKL documentation): parallel nested
# dissection ordering, pivot perturbation 1e-8 as for SPD matrices, two-level parallel
# factorization. Measured on the Tutte matrix of a 850k-vertex mesh, 2 cores: analysis
# 2.2 -> 1.8 s, factorization 1.3 -> 0.7 s, solve 0.67 -> 0.09 s against MKL's defaults.
_PARDISO_IPARM = {0: 1, 1: 3, 9: 8, 23: 1}


class _Pardiso:
    """A PARDISO Cholesky factorization (matrix type 2, real SPD) of the upper triangle of
    a matrix; numerical refactorization (phase 22) reuses the analysis (phase 11).

    pypardiso searches the file system for MKL each time a solver is made (about 0.2 s);
    the path found the first time is handed to the next ones. MKL's memory is released
    when the object is collected or at exit (pypardiso itself keeps it until told).
    """

    mkl_path = None

    def __init__(self, upper):
        self.solver = self._new_solver()
        for i, value in _PARDISO_IPARM.items():
            self.solver.set_iparm(i + 1, value)
        self.upper = upper
        weakref.finalize(self, self.solver.free_memory, True)
        self._run(12, np.zeros((upper.shape[0], 1)))

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

    def _run(self, phase, B):
        self.solver.set_phase(phase)
        return self.solver._call_pardiso(self.upper, np.asfortranarray(B, dtype=np.float64))

    def refactorize(self, upper):
        self.upper = upper
        self._run(22, np.zeros((upper.shape[0], 1)))

    def solve(self, B):
        return self._run(33, B)


class _SuperLU:
    """SuperLU in symmetric mode with a minimum-degree ordering of A + A^T;
    refactorization reuses that ordering (the matrix is permuted by it and factorized in
    its natural order)."""

    def __init__(self, A):
        self.lu = self._factor(A, "MMD_AT_PLUS_A")
        self.perm = np.argsort(self.lu.perm_c)  # A[perm][:, perm] needs no reordering
        self.permuted = False

    @staticmethod
    def _factor(A, ordering):
        return spla.splu(
            sp.csc_matrix(A), permc_spec=ordering, diag_pivot_thresh=0.0, options={"SymmetricMode": True}
        )

    def refactorize(self, A):
        self.lu = self._factor(A[self.perm][:, self.perm], "NATURAL")
        self.permuted = True

    def solve(self, B):
        if not self.permuted:
            return self.lu.solve(B)
        X = np.empty_like(B)
        X[self.perm] = self.lu.solve(B[self.perm])
        return X


class SPDSolver:
    """``solve(b)`` returns ``A^{-1} b`` for a factorized sparse SPD matrix A.

    ``b`` is (k,) or (k, r), real or complex; the result has its shape and kind. Made by
    :func:`spd_solver`.
    """

    def __init__(self, A, backend):
        self.shape = A.shape
        self.pattern = (A.indptr, A.indices)
        self.backend = backend
        if A.shape[0] == 0:
            self._factor = None
        elif backend == "pardiso":
            self._factor = _Pardiso(self._upper(A))
        else:
            self._factor = _SuperLU(A)

    @staticmethod
    def _upper(A):
        upper = sp.triu(A, format="csr")
        upper.sort_indices()
        return upper

    def refactorize(self, A):
        """Factorize another matrix with the same sparsity pattern, in place.

        The ordering and the symbolic analysis of the first factorization are reused;
        afterwards this solver solves with ``A``. A matrix with another pattern is
        factorized from scratch.

        Parameters
        ----------
        A : (k, k) sparse matrix
            Symmetric positive definite, of the shape of the first one.

        Returns
        -------
        SPDSolver
            ``self``.
        """
        A = _csr(A)
        if A.shape != self.shape:
            raise ValueError(f"refactorize needs a {self.shape} matrix, got {A.shape}")
        same = all(np.array_equal(a, b) for a, b in zip(self.pattern, (A.indptr, A.indices)))
        if self._factor is None:
            return self
        if not same:
            self.__init__(A, self.backend)
        elif self.backend == "pardiso":
            self._factor.refactorize(self._upper(A))
        else:
            self._factor.refactorize(A)
        return self

    def __call__(self, b):
        b = np.asarray(b)
        if self._factor is None:
            return np.zeros_like(b, dtype=np.result_type(b, np.float64))
        vector = b.ndim == 1
        B = b.reshape(len(b), -1)
        if np.iscomplexobj(B):
            r = B.shape[1]
            X = self._factor.solve(np.hstack([B.real, B.imag]).astype(np.float64)).reshape(len(b), -1)
            X = X[:, :r] + 1j * X[:, r:]
        else:
            X = np.asarray(self._factor.solve(B.astype(np.float64))).reshape(len(b), -1)
        return X[:, 0] if vector else X


def _csr(A):
    A = sp.csr_matrix(A, dtype=np.float64)
    A.sort_indices()
    return A


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
    SPDSolver
        ``solve(b)`` for ``b`` of shape (k,) or (k, r), real or complex, returns
        ``A^{-1} b`` with the shape and kind of ``b``; ``solve.refactorize(A2)`` redoes
        the numerical factorization for a matrix of the same pattern.
    """
    backend = backend or solver_backend()
    if backend not in ("pardiso", "superlu"):
        raise ValueError(f"unknown solver backend {backend!r}")
    if backend == "pardiso" and _pypardiso is None:
        raise ImportError("the pardiso backend needs the pypardiso package")
    return SPDSolver(_csr(A), backend)


def complement(indices, n):
    """The indices 0..n-1 not in ``indices``, increasing, (n - k,) int64."""
    keep = np.ones(n, dtype=bool)
    keep[indices] = False
    return np.flatnonzero(keep)


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
    solve_free : SPDSolver, optional
        A factorization of -L_II to reuse (as returned by ``spd_solver``).

    Returns
    -------
    x : (n,) or (n, r)
    solve_free : SPDSolver
        The factorization of -L_II, for further solves with the same matrix.
    """
    L = sp.csr_matrix(L)
    n = L.shape[0]
    known = np.asarray(known)
    free = complement(known, n)
    values = np.asarray(values)
    rows = L[free]
    if solve_free is None:
        solve_free = spd_solver(-rows[:, free])
    rhs = rows[:, known] @ values
    x = np.zeros((n,) + values.shape[1:], dtype=np.result_type(values, np.float64))
    x[known] = values
    x[free] = solve_free(rhs)
    return x, solve_free
