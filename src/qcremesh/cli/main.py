"""The ``qcremesh`` command line.

``qcremesh param INPUT -o OUTPUT.obj [--plot FILE.png]``
    Conformal disk parameterization (Algorithm 1). The OBJ holds the input vertices as
    ``v``, their disk coordinates as ``vt`` with the same index, and the input faces as
    ``f a/a b/b c/c``.

Errors (unreadable file, a mesh that is not a disk, ...) are printed as one line on
stderr, the exit status is 1, and no output file is written.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

from .. import __version__
from ..mesh.io import MeshReadError, read_mesh, write_mesh
from ..mesh.validate import MeshError
from ..param.disk import disk_conformal_map

__all__ = ["main"]


class CommandError(Exception):
    """An error to report on one line."""


def _parser():
    p = argparse.ArgumentParser(
        prog="qcremesh",
        description="Surface remeshing by quasi-conformal parameterization.",
    )
    p.add_argument("--version", action="version", version=f"qcremesh {__version__}")
    sub = p.add_subparsers(dest="command", required=True)
    q = sub.add_parser(
        "param",
        help="conformal parameterization of a disk-topology mesh onto the unit disk",
        description="Free-boundary conformal map onto the unit disk (Algorithm 1).",
    )
    q.add_argument("input", help="triangle mesh (OBJ, PLY, OFF, STL, VTK, .mat, ...)")
    q.add_argument("-o", "--output", required=True, help="output OBJ with disk coordinates as vt")
    q.add_argument("--plot", metavar="FILE.png", help="draw the disk coloured by |mu| and its histogram")
    return p


def _param(args, out):
    if Path(args.output).suffix.lower() != ".obj":
        raise CommandError(f"{args.output}: the parameterization is written as OBJ (use .obj)")
    for target in filter(None, [args.output, args.plot]):
        if not Path(target).parent.is_dir() and str(Path(target).parent) != "":
            raise CommandError(f"{target}: folder {Path(target).parent} does not exist")
    t0 = time.perf_counter()
    V, F = read_mesh(args.input)
    t_read = time.perf_counter() - t0
    try:
        result = disk_conformal_map(V, F)
    except MeshError as exc:
        raise CommandError(f"{args.input}: {exc}") from exc
    t1 = time.perf_counter()
    write_mesh(args.output, V, F, uv=result.uv)
    t_write = time.perf_counter() - t1
    print(f"{args.input}: {len(V)} vertices, {len(F)} faces", file=out)
    print(
        f"|mu| of the map disk -> surface: mean {result.mean_abs_mu:.5f}, "
        f"max {result.max_abs_mu:.4f}",
        file=out,
    )
    print(
        f"folded faces: {result.folded_faces}"
        + (f" ({result.repaired_faces} folded by the first solve, repaired)" if result.repaired_faces else ""),
        file=out,
    )
    print(f"boundary on the unit circle to {result.boundary_radius_error:.1e}", file=out)
    stages = {"read": t_read, **result.times, "write": t_write}
    if args.plot:
        t2 = time.perf_counter()
        from .report import plot_disk_map

        plot_disk_map(args.plot, result.uv, F, result.mu, title=Path(args.input).name)
        stages["plot"] = time.perf_counter() - t2
    print("time (s): " + ", ".join(f"{k} {v:.3f}" for k, v in stages.items()), file=out)
    print(f"wrote {args.output}" + (f" and {args.plot}" if args.plot else ""), file=out)


def main(argv=None):
    """Entry point of the ``qcremesh`` console script; returns the exit status."""
    args = _parser().parse_args(argv)
    try:
        if args.command == "param":
            _param(args, sys.stdout)
    except (CommandError, MeshReadError, ImportError) as exc:
        print(f"qcremesh: error: {exc}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
