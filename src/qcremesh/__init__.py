"""qcremesh: surface remeshing by quasi-conformal parameterization.

Following "Quasi-conformal Surface Remeshing" (Choi, Gu, Lui). The public API works on
plain numpy arrays: ``V`` (n, 3) float64 vertices and ``F`` (m, 3) int64 triangles.
"""

__version__ = "0.1.0"

from .adaptive.sizing import curvature_sizing
from .beltrami.coefficient import beltrami_coefficient, compose_beltrami, mu_chop
from .beltrami.solver import generalized_laplacian, linear_beltrami_solver
from .beltrami.teichmuller import teichmuller_map
from .geometry.quality import mesh_quality
from .mesh.io import read_mesh, write_mesh
from .mesh.validate import MeshError, check_disk
from .param.disk import DiskMap, disk_conformal_map
from .param.tutte import tutte_embedding
from .remeshing.pipeline import RemeshResult, remesh

__all__ = [
    "read_mesh",
    "write_mesh",
    "check_disk",
    "MeshError",
    "tutte_embedding",
    "beltrami_coefficient",
    "compose_beltrami",
    "mu_chop",
    "generalized_laplacian",
    "linear_beltrami_solver",
    "disk_conformal_map",
    "DiskMap",
    "teichmuller_map",
    "remesh",
    "RemeshResult",
    "curvature_sizing",
    "mesh_quality",
]
