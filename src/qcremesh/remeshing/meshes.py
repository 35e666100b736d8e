"""The two meshes the relaxation works with: the input surface, on which the output
vertices move, with its disk map; and the output's connectivity, which stays while they
move. Each is built once per relaxation and handed as one to the smoothing, the snapping
and the two pattern searches.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from scipy import sparse

from ..geometry.operators import face_normals
from ..mesh.topology import adjacency_matrix, boundary_loop, edges, vertex_face_incidence

__all__ = ["InputSurface", "OutputMesh", "input_surface", "output_mesh"]


class InputSurface(NamedTuple):
    """The input surface and its disk parameterization (:func:`input_surface`).

    Attributes
    ----------
    V : (n, 3) float
    F : (m, 3) int
    disk_uv : (n, 2) float
        The disk position of each vertex.
    vertex_faces : (n, m) CSR
        Vertex-face incidence of ``F``.
    normals : (m, 3) float
        Unit face normals.
    """

    V: np.ndarray
    F: np.ndarray
    disk_uv: np.ndarray
    vertex_faces: sparse.csr_matrix
    normals: np.ndarray


def input_surface(V, F, disk_uv):
    """The :class:`InputSurface` of the mesh (V (n, 3), F (m, 3)) with disk positions
    ``disk_uv`` (n, 2)."""
    return InputSurface(V, F, disk_uv, vertex_face_incidence(F, len(V)), face_normals(V, F))


class OutputMesh(NamedTuple):
    """The connectivity of an output mesh of k vertices (:func:`output_mesh`).

    Attributes
    ----------
    F : (l, 3) int
        Faces.
    A : (k, k) CSR
        Vertex adjacency.
    VF : (k, l) CSR
        Vertex-face incidence.
    E : (e, 2) int
        Edges (:func:`qcremesh.mesh.topology.edges`).
    loop : (b,) int
        Boundary loop.
    """

    F: np.ndarray
    A: sparse.csr_matrix
    VF: sparse.csr_matrix
    E: np.ndarray
    loop: np.ndarray


def output_mesh(F, k):
    """The :class:`OutputMesh` of the disk-topology faces ``F`` (l, 3) over ``k`` vertices."""
    return OutputMesh(F, adjacency_matrix(F, k), vertex_face_incidence(F, k), edges(F), boundary_loop(F))
