"""Figures for people to look at: disk meshes coloured by |mu| and histograms.

matplotlib is an optional dependency (the ``plot`` extra); it is imported only when a
figure is drawn, with the non-interactive Agg backend.
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path

import numpy as np

__all__ = ["plot_disk_map"]


def _pyplot():
    try:
        import matplotlib
    except ImportError as exc:
        raise ImportError("plots need matplotlib: pip install 'qcremesh[plot]'") from exc
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def _save(fig, path):
    """Save a figure atomically (no partial file on failure)."""
    path = Path(path)
    fd, tmp = tempfile.mkstemp(suffix=path.suffix, prefix=".tmp-", dir=path.parent)
    os.close(fd)
    try:
        fig.savefig(tmp, dpi=120, metadata={"Software": None} if path.suffix == ".png" else None)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def plot_disk_map(path, uv, F, mu, title=None):
    """Draw a disk parameterization coloured by |mu| beside the histogram of |mu|
    (as Figs. 4-6 of Choi, Gu & Lui).

    Parameters
    ----------
    path : str or os.PathLike
        Output image (PNG, PDF, SVG: by extension).
    uv : (n, 2) float
    F : (m, 3) int
    mu : (m,) complex
        Beltrami coefficient per face.
    title : str, optional
    """
    plt = _pyplot()
    from matplotlib.tri import Triangulation

    a = np.abs(mu)
    fig, (ax0, ax1) = plt.subplots(1, 2, figsize=(11, 5), gridspec_kw={"width_ratios": [1.1, 1]})
    tri = Triangulation(uv[:, 0], uv[:, 1], F)
    vmax = max(float(np.quantile(a, 0.99)), 1e-6)
    pc = ax0.tripcolor(tri, facecolors=a, cmap="viridis", vmin=0, vmax=vmax, shading="flat")
    if len(F) <= 20000:
        ax0.triplot(tri, color="k", lw=0.1, alpha=0.4)
    ax0.set_aspect("equal")
    ax0.set_axis_off()
    fig.colorbar(pc, ax=ax0, fraction=0.046, pad=0.02, label="|mu| (clipped at 99th percentile)")
    ax0.set_title("disk parameterization coloured by |mu|")
    ax1.hist(a, bins=60, range=(0, max(float(a.max()), 1e-6)), color="#3b6ea8")
    ax1.set_xlabel("|mu|")
    ax1.set_ylabel("faces")
    ax1.set_title(f"mean |mu| = {a.mean():.4f}, median = {np.median(a):.4f}, max = {a.max():.3f}")
    if title:
        fig.suptitle(title)
    fig.tight_layout()
    try:
        _save(fig, path)
    finally:
        plt.close(fig)
