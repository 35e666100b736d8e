from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import Delaunay

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
SHARED = ROOT.parent / "shared" / "data"

# Disk-topology meshes of ../shared/data (see its README).
SHARED_DISKS = [
    "venus.off",
    "camel_b.obj",
    "fran_cut.ply",
    "foot.off",
    "human_face.obj",
    "head_neck_cut.obj",
    "human_brain.ply",
    "hand.ply",
]


def shared(name):
    """Path of a mesh in ../shared/data; skips the test when it is not there."""
    path = SHARED / name
    if not path.is_file():
        pytest.skip(f"{path} not available")
    return path


def grid_disk(k=8, jitter=0.0, seed=0):
    """Delaunay triangulation of a k x k grid on [0, 1]^2, counter-clockwise faces."""
    g = np.linspace(0.0, 1.0, k)
    uv = np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    if jitter:
        rng = np.random.default_rng(seed)
        inside = ((uv > 0) & (uv < 1)).all(1)
        uv[inside] += rng.uniform(-jitter, jitter, (inside.sum(), 2)) / k
    F = Delaunay(uv).simplices.astype(np.int64)
    a = uv[F[:, 1]] - uv[F[:, 0]]
    b = uv[F[:, 2]] - uv[F[:, 0]]
    cw = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    F[cw] = F[cw][:, ::-1]
    return uv, F
