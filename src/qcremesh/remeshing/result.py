"""The result of a remesh, and the wall time of its stages."""

from __future__ import annotations

import time
from dataclasses import dataclass, field

import numpy as np

__all__ = ["RemeshResult", "StageTimes"]


@dataclass
class RemeshResult:
    """Result of :func:`qcremesh.remeshing.pipeline.remesh`.

    Attributes
    ----------
    V : (n, 3) float
        Vertices of the remeshed surface; the vertices of every coarser level come first.
    F : (m, 3) int64
        Its triangles, oriented as the input.
    uv : (n, 2) float
        Disk coordinates of the output vertices (the adaptive disk mesh, whose faces are
        ``disk_levels[-1][1]``: for a closed surface, the vertices of the cut surface's
        remesh, before its two sides were welded).
    levels : list of (V, F)
        The multiresolution hierarchy: level 0 is the base mesh, the last level is
        ``(V, F)``; face f of a level is split into faces 4f..4f+3 of the next.
    data : dict of str to ndarray
        The input's per-vertex attributes carried to the output vertices.
    disk_levels : list of (uv, F)
        The base mesh and its subdivisions in the disk, before the Teichmueller map.
    mu : (m,) complex or None
        Beltrami coefficient of the Teichmueller map, per output face.
    stats : dict
        Numbers of the run: landmarks, CVT uniformity, Teichmueller k and iterations, ...;
        with boundary corners, ``sharpest_corner_degrees`` (the input's angle at the
        sharpest one) and ``corner_quality_bound``, the best smallest radius ratio of a
        fan of triangles filling that angle
        (:func:`~qcremesh.geometry.quality.corner_radius_ratio_bound`), which the output
        follows up to its boundary edges being chords of the input boundary (a ragged
        border cut by a plane through a decimated head: 6.6 degrees, 0.22; min q 0.235).
    times : dict of str to float
        Wall time of each stage, in seconds.
    """

    V: np.ndarray
    F: np.ndarray
    uv: np.ndarray
    levels: list
    data: dict = field(default_factory=dict)
    disk_levels: list = field(default_factory=list)
    mu: np.ndarray | None = None
    stats: dict = field(default_factory=dict)
    times: dict = field(default_factory=dict)


class StageTimes:
    """Wall time of each stage of a remesh, summed over the stage's runs (a stage runs
    once per draw of the landmarks), with ``progress(stage_name)`` called as each starts.

    Attributes
    ----------
    times : dict of str to float
        Seconds per stage.
    """

    def __init__(self, progress=None):
        self.times = {}
        self._progress = progress
        self._started = {}

    def start(self, name):
        """The stage ``name`` starts."""
        if self._progress is not None:
            self._progress(name)
        self._started[name] = time.perf_counter()

    def stop(self, name):
        """The stage ``name`` ends; its time is added."""
        self.times[name] = self.times.get(name, 0.0) + time.perf_counter() - self._started[name]
