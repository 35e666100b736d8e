"""Remeshing of many files: :func:`remesh_file`, one file read, remeshed, measured and
written, and :func:`remesh_files`, which runs it on several files in parallel processes
(``qcremesh batch``).

:func:`remesh_file` is the unit of work that a process pool or a Dask bag maps over::

    import dask.bag
    jobs = dask.bag.from_sequence([(f, f"out/{Path(f).stem}.ply") for f in files])
    records = jobs.starmap(remesh_file, faces_ratio=0.5).compute(scheduler="processes")
"""

from __future__ import annotations

import multiprocessing
import time
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

from ..adaptive.sizing import check_sizing
from ..geometry.quality import mesh_quality
from ..mesh.io import MeshReadError, read_mesh, write_mesh
from ..mesh.validate import MeshError
from ..remeshing.pipeline import remesh

__all__ = ["remesh_file", "remesh_files", "output_paths", "report_folders"]


def remesh_file(
    input, output, *, faces=None, faces_ratio=None, edge_length=None, sizing=None, report=None, **options
):
    """Read a mesh, remesh it, measure the result against the input and write it
    (atomically: an error leaves no file).

    Parameters
    ----------
    input, output : str or os.PathLike
        The formats follow the extensions (:func:`qcremesh.read_mesh`,
        :func:`qcremesh.write_mesh`).
    faces : int, optional
        Face count wanted (default: the input's).
    faces_ratio : float, optional
        Face count wanted as a fraction of the input's.
    edge_length : float, optional
        Mean output edge length wanted, in the input's units
        (:func:`qcremesh.remesh`'s ``edge_length``); one of ``faces``, ``faces_ratio``
        and this at most.
    sizing : "curvature" or str, optional
        ``"curvature"``, or the name of a per-vertex array of the input holding the
        relative edge lengths wanted.
    report : str or os.PathLike, optional
        A folder (created; its parent must exist) to write the figures and
        ``report.html`` of :func:`qcremesh.cli.report.write_remesh_report` into
        (matplotlib needed).
    **options
        Further keyword arguments of :func:`qcremesh.remesh` (``seed``, ``levels``,
        ``method``, ``relax``, ``creases``, ``cut_crowded``, ``weld_seams``).

    Returns
    -------
    dict
        ``input``, ``output``, ``faces_in``, ``seconds`` (read, remesh, measure and
        write) and the measures of :func:`qcremesh.mesh_quality` with the input as
        reference.

    Raises
    ------
    MeshReadError, MeshError, ValueError
        The input cannot be read or remeshed, or the output written.
    """
    if sum(x is not None for x in (faces, faces_ratio, edge_length)) > 1:
        raise ValueError("give one of faces, faces_ratio and edge_length")
    if faces_ratio is not None and not faces_ratio > 0:
        raise ValueError("faces_ratio must be positive")
    start = time.perf_counter()
    V, F, data = read_mesh(input, return_data=True)
    if faces_ratio is not None:
        faces = max(4, round(faces_ratio * len(F)))
    if sizing is not None and sizing != "curvature":
        if sizing not in data:
            arrays = ", ".join(sorted(data)) or "none"
            raise ValueError(f"no per-vertex array {sizing!r} to take the sizing from (the mesh has: {arrays})")
        sizing = check_sizing(np.asarray(data[sizing], dtype=np.float64).reshape(len(V), -1)[:, 0], len(V))
    result = remesh(V, F, faces, edge_length=edge_length, sizing=sizing, data=data, **options)
    t = time.perf_counter()
    quality = mesh_quality(result.V, result.F, reference=(V, F))
    times = dict(result.times, measure=time.perf_counter() - t)
    out_data = dict(result.data)
    write_mesh(output, result.V, result.F, uv=out_data.pop("uv", None), data=out_data)
    record = {"input": str(input), "output": str(output), "faces_in": len(F)}
    if report is not None:
        from .report import write_remesh_report

        write_remesh_report(report, input, (V, F), result, quality, times)
        record["report"] = str(Path(report) / "report.html")
    return dict(record, seconds=time.perf_counter() - start, **quality)


def _attempt(input, output, options):
    """:func:`remesh_file`, its errors returned as the record's ``error``."""
    try:
        return remesh_file(input, output, **options)
    except (MeshReadError, MeshError, ValueError) as exc:
        return {"input": str(input), "output": None, "error": str(exc)}


def remesh_files(pairs, *, jobs=1, report=None, **options):
    """:func:`remesh_file` of each (input, output) pair, in ``jobs`` processes.

    Parameters
    ----------
    pairs : sequence of (input, output)
    jobs : int
        Processes to run at once; 1 runs the files one after the other in this process.
        Each remesh uses every core for its larger steps, so more processes than cores
        gain nothing; several help where the files are small.
    report : str or os.PathLike, optional
        An existing folder: each file's report goes into a folder in it named after its
        output (:func:`report_folders`).
    **options
        Keyword arguments of :func:`remesh_file`.

    Yields
    ------
    dict
        The record of each file as it is done (:func:`remesh_file`), or, where it failed,
        ``input``, ``output`` None and ``error``, the message; the others go on.
    """
    if jobs < 1:
        raise ValueError("jobs must be at least 1")
    pairs = list(pairs)
    folders = report_folders([output for _, output in pairs], report) if report is not None else [None] * len(pairs)
    tasks = [(input, output, dict(options, report=folder)) for (input, output), folder in zip(pairs, folders)]
    if jobs == 1:
        for task in tasks:
            yield _attempt(*task)
        return
    # spawned, not forked: a fork copies the parent's thread pools in whatever state
    context = multiprocessing.get_context("spawn")
    with ProcessPoolExecutor(max_workers=jobs, mp_context=context) as pool:
        running = [pool.submit(_attempt, *task) for task in tasks]
        try:
            for done in as_completed(running):
                yield done.result()
        finally:
            for future in running:
                future.cancel()


def output_paths(inputs, folder, suffix=None):
    """The output file of each input: ``folder / (stem + suffix)``, the input's suffix
    where ``suffix`` is None.

    Raises
    ------
    ValueError
        Two inputs would be written to the same file.
    """
    folder = Path(folder)
    outputs = [folder / (Path(p).stem + (suffix if suffix is not None else Path(p).suffix)) for p in inputs]
    _check_distinct(inputs, outputs)
    return outputs


def report_folders(outputs, folder):
    """The report folder of each output: ``folder / stem``.

    Raises
    ------
    ValueError
        Two outputs have the same stem (x.ply and x.obj).
    """
    folders = [Path(folder) / Path(output).stem for output in outputs]
    _check_distinct(outputs, folders, "the reports of ")
    return folders


def _check_distinct(sources, targets, label=""):
    """Raise ValueError where two of ``sources`` have the same target."""
    seen = {}
    for source, target in zip(sources, targets):
        if target in seen:
            raise ValueError(f"{label}{seen[target]} and {source} would both be written to {target}")
        seen[target] = source
