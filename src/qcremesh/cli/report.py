"""Figures for people to look at: the surfaces coloured by triangle quality and distance,
disk meshes coloured by |mu|, and histograms.

matplotlib is an optional dependency (the ``plot`` extra); it is imported only when a
figure is drawn, with the non-interactive Agg backend.
"""

from __future__ import annotations

import html
import json
from pathlib import Path

import numpy as np

from ..mesh.io import atomic_output

__all__ = [
    "check_figure_path",
    "face_distances",
    "plot_disk_levels",
    "plot_disk_map",
    "plot_radius_ratio",
    "plot_surfaces",
    "surface_view",
    "write_remesh_report",
]


def _pyplot():
    try:
        import matplotlib
    except ImportError as exc:
        raise ImportError("plots need matplotlib: pip install 'qcremesh[plot]'") from exc
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def check_figure_path(path):
    """Raise ValueError unless matplotlib can save a figure in the format of ``path``'s
    extension (ImportError without matplotlib), so that a caller can tell before the
    work whose figure it draws."""
    plt = _pyplot()
    fig = plt.figure()
    formats = fig.canvas.get_supported_filetypes()
    plt.close(fig)
    suffix = Path(path).suffix.lower().lstrip(".")
    if suffix not in formats:
        raise ValueError(f"cannot draw .{suffix} figures (png, pdf, svg, jpg, ...)")


def _save(fig, path):
    """Save a figure atomically (no partial file on failure)."""
    with atomic_output(path) as tmp:
        fig.savefig(tmp, dpi=120, metadata={"Software": None} if Path(path).suffix == ".png" else None)


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


def plot_radius_ratio(path, before, after, labels=("input", "remeshed")):
    """Histograms of the radius ratio 2 r_in / R_circ before and after remeshing (as
    Figs. 18-20 of Choi, Gu & Lui).

    Parameters
    ----------
    path : str or os.PathLike
    before, after : (m,) float
        Radius ratio per face.
    """
    plt = _pyplot()
    fig, axes = plt.subplots(1, 2, figsize=(11, 4), sharex=True)
    for ax, q, label, colour in zip(axes, (before, after), labels, ("#a83b3b", "#3b6ea8")):
        ax.hist(q, bins=50, range=(0, 1), color=colour)
        ax.set_title(f"{label}: {len(q)} faces, mean {q.mean():.3f}, min {q.min():.3f}")
        ax.set_xlabel("radius ratio 2 r_in / R_circ")
        ax.set_ylabel("faces")
    fig.tight_layout()
    try:
        _save(fig, path)
    finally:
        plt.close(fig)


def plot_disk_levels(path, meshes, titles):
    """Draw meshes of the disk side by side (the base, subdivided and adaptive meshes of
    Fig. 8).

    Parameters
    ----------
    path : str or os.PathLike
    meshes : list of ((n, 2) float, (m, 3) int)
    titles : list of str
    """
    plt = _pyplot()
    from matplotlib.tri import Triangulation

    fig, axes = plt.subplots(1, len(meshes), figsize=(5 * len(meshes), 5.4), layout="constrained")
    for ax, (uv, F), title in zip(np.atleast_1d(axes), meshes, titles):
        lw = 0.6 if len(F) < 2000 else 0.25 if len(F) < 20000 else 0.1
        ax.triplot(Triangulation(uv[:, 0], uv[:, 1], F), color="k", lw=lw)
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title(f"{title} ({len(F)} faces)")
    try:
        _save(fig, path)
    finally:
        plt.close(fig)


def surface_view(V, F):
    """The rotation that shows a surface from the side most of it faces: (3, 3), its rows
    the screen's x and y axes (the principal axes of the vertices of second and largest
    spread: the longer way up) and the direction towards the viewer (the third principal
    axis, turned to the side of the area-weighted mean normal; a face scan is seen from
    the front)."""
    P = np.asarray(V, dtype=np.float64)
    P = P - P.mean(axis=0)
    R = np.linalg.eigh(P.T @ P)[1][:, [1, 2, 0]].T
    if np.linalg.det(R) < 0:
        R[2] = -R[2]
    if np.cross(V[F[:, 1]] - V[F[:, 0]], V[F[:, 2]] - V[F[:, 0]]).sum(axis=0) @ R[2] < 0:
        R[[0, 2]] = -R[[0, 2]]
    return R


def plot_surfaces(path, panels, view):
    """Draw surfaces side by side, each face coloured by a value and shaded by how much
    it faces the viewer, in the orthographic ``view`` of :func:`surface_view` (the faces
    painted from the farthest to the nearest).

    Parameters
    ----------
    path : str or os.PathLike
    panels : list of ((n, 3) float, (m, 3) int, (m,) float, str, dict)
        Vertices, faces, the value of each face, a title, and the colour scale as keyword
        arguments of :class:`matplotlib.colors.Normalize` with ``cmap`` and ``label``.
    view : (3, 3) float
    """
    plt = _pyplot()
    from matplotlib.collections import PolyCollection
    from matplotlib.colors import Normalize

    fig, axes = plt.subplots(1, len(panels), figsize=(5.5 * len(panels), 6), layout="constrained")
    for ax, (V, F, values, title, scale) in zip(np.atleast_1d(axes), panels):
        X = np.asarray(V, dtype=np.float64) @ view.T
        N = np.cross(X[F[:, 1]] - X[F[:, 0]], X[F[:, 2]] - X[F[:, 0]])
        facing = np.abs(N[:, 2]) / np.maximum(np.linalg.norm(N, axis=1), 1e-300)
        order = np.argsort(X[F].mean(axis=1)[:, 2], kind="stable")
        scale = dict(scale)
        cmap, label = plt.get_cmap(scale.pop("cmap")), scale.pop("label")
        norm = Normalize(**scale)
        colours = cmap(norm(np.asarray(values)[order]))
        colours[:, :3] *= (0.35 + 0.65 * facing[order])[:, None]
        lw = 0.15 if len(F) <= 30000 else 0.0
        ax.add_collection(
            PolyCollection(X[F[order], :2], facecolors=colours, edgecolors=(0, 0, 0, 0.35), linewidths=lw)
        )
        ax.set_xlim(X[:, 0].min(), X[:, 0].max())
        ax.set_ylim(X[:, 1].min(), X[:, 1].max())
        ax.set_aspect("equal")
        ax.set_axis_off()
        ax.set_title(f"{title} ({len(F):,} faces)")
        fig.colorbar(plt.cm.ScalarMappable(norm=norm, cmap=cmap), ax=ax, shrink=0.6, label=label)
    try:
        _save(fig, path)
    finally:
        plt.close(fig)


def face_distances(V, F, V0, F0):
    """Distance from each face of (V, F) to the surface (V0, F0): the largest over its
    centroid and the midpoints of its edges, (m,)."""
    from ..geometry.distance import point_mesh_distance
    from ..mesh.topology import edges

    E = edges(F)
    points = np.concatenate([V[F].mean(axis=1), (V[E[:, 0]] + V[E[:, 1]]) / 2])
    d = point_mesh_distance(points, V0, F0)[0]
    # each face's three edges, by their rows in E
    key = np.sort(np.stack([F, np.roll(F, -1, axis=1)], axis=2), axis=2)
    row = np.searchsorted(E[:, 0] * len(V) + E[:, 1], key[..., 0] * len(V) + key[..., 1])
    return np.maximum(d[: len(F)], d[len(F) + row].max(axis=1))


def _write_text(path, text):
    with atomic_output(path) as tmp:
        Path(tmp).write_text(text)


def write_remesh_report(folder, name, original, result, quality, times):
    """Write the figures of a remeshing run and a ``report.html`` that shows them with
    the numbers.

    Files: ``surfaces.png`` (the input and the output coloured by radius ratio and the
    output by its distance to the input, :func:`plot_surfaces`), ``radius_ratio.png``
    (histograms before and after), ``disk_meshes.png`` (base,
    subdivided and adaptive disk meshes), ``teichmuller_mu.png`` (|mu| of the
    Teichmueller map, when there is one), ``summary.json`` and ``report.html``.

    Parameters
    ----------
    folder : str or os.PathLike
        Created if missing (its parent must exist).
    name : str
        Name of the input, for the titles.
    original : ((n, 3) float, (m, 3) int)
        The input mesh.
    result : qcremesh.remeshing.pipeline.RemeshResult
    quality : dict
        :func:`qcremesh.geometry.quality.mesh_quality` of the output.
    times : dict of str to float
    """
    from ..geometry.quality import radius_ratio

    folder = Path(folder)
    folder.mkdir(exist_ok=True)
    V0, F0 = original
    q0, q = radius_ratio(V0, F0), radius_ratio(result.V, result.F)
    diagonal = float(np.linalg.norm(V0.max(axis=0) - V0.min(axis=0)))
    distance = 100 * face_distances(result.V, result.F, V0, F0) / diagonal
    ratio = {"vmin": 0.0, "vmax": 1.0, "cmap": "viridis", "label": "radius ratio 2 r_in / R_circ"}
    plot_surfaces(
        folder / "surfaces.png",
        [
            (V0, F0, q0, "input", ratio),
            (result.V, result.F, q, "remeshed", ratio),
            (result.V, result.F, distance, "remeshed: distance to the input",
             {"vmin": 0.0, "vmax": max(float(distance.max()), 1e-12), "cmap": "magma",
              "label": "% of the bounding-box diagonal"}),
        ],
        surface_view(V0, F0),
    )
    plot_radius_ratio(folder / "radius_ratio.png", q0, q)
    base_uv, base_F = result.disk_levels[0]
    sub_uv, sub_F = result.disk_levels[-1]
    plot_disk_levels(
        folder / "disk_meshes.png",
        [(base_uv, base_F), (sub_uv, sub_F), (result.uv, sub_F)],
        ["base mesh", "subdivided", "adaptive (final)"],
    )
    figures = [
        ("surfaces.png", "The surfaces: radius ratio before and after, and how far the output lies from the input"),
        ("radius_ratio.png", "Radius ratio before and after"),
        ("disk_meshes.png", "Meshes of the disk"),
    ]
    if result.mu is not None:
        plot_disk_map(folder / "teichmuller_mu.png", result.uv, sub_F, result.mu, title="Teichmueller map")
        figures.append(("teichmuller_mu.png", "|mu| of the Teichmueller map"))
    summary = {"input": str(name), "quality": quality, "stats": result.stats, "times": times}
    _write_text(folder / "summary.json", json.dumps(summary, indent=2, default=float))
    rows = "".join(
        f"<tr><td>{html.escape(str(k))}</td><td>{v:.6g}</td></tr>" if isinstance(v, float)
        else f"<tr><td>{html.escape(str(k))}</td><td>{html.escape(str(v))}</td></tr>"
        for section in (quality, result.stats)
        for k, v in section.items()
    )
    time_rows = "".join(f"<tr><td>{html.escape(k)}</td><td>{v:.3f} s</td></tr>" for k, v in times.items())
    imgs = "".join(f'<h2>{html.escape(t)}</h2><img src="{f}" alt="{html.escape(t)}">' for f, t in figures)
    page = f"""<!DOCTYPE html>
<html lang="en"><head><meta charset="utf-8"><title>qcremesh report: {html.escape(str(name))}</title>
<style>body{{font-family:sans-serif;max-width:1200px;margin:2em auto}}img{{max-width:100%}}
table{{border-collapse:collapse}}td{{border:1px solid #ccc;padding:2px 8px}}</style></head>
<body><h1>qcremesh report: {html.escape(str(name))}</h1>
<h2>Numbers</h2><table>{rows}</table><h2>Time per stage</h2><table>{time_rows}</table>
{imgs}</body></html>
"""
    _write_text(folder / "report.html", page)
