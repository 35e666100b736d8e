"""Machine description, markdown tables and plots of the benchmark results."""

from __future__ import annotations

import os
import platform
import subprocess
import sys
import time
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import numpy as np

from qcremesh.geometry.linsolve import solver_backend
from qcremesh.remeshing.compiled import closest_point_near_kernel

PACKAGES = [
    "qcremesh",
    "numpy",
    "scipy",
    "meshio",
    "pypardiso",
    "numba",
    "libigl",
    "pymeshlab",
    "pyacvd",
    "pyvista",
    "vtk",
    "gpytoolbox",
    "matplotlib",
]
STAGES = ["validate", "tutte", "beltrami", "lbs", "measure"]
TOOL_NAMES = {
    "qcremesh": "qcremesh",
    "tutte": "Tutte (qcremesh)",
    "igl_harmonic": "libigl harmonic",
    "igl_lscm": "libigl LSCM",
    "pymeshlab": "pymeshlab",
    "pyacvd": "pyacvd",
    "botsch": "gpytoolbox remesh_botsch",
}
ROOT = Path(__file__).resolve().parents[1]


# Context ------------------------------------------------------------------------------


def _first_line(path, prefix):
    with open(path) as f:
        return next(
            (line.split(":", 1)[1].strip() for line in f if line.startswith(prefix)), "unknown"
        )


def _git(*args):
    out = subprocess.run(["git", "-C", str(ROOT), *args], capture_output=True, text=True)
    return out.stdout.strip() if out.returncode == 0 else ""


def machine():
    packages = {}
    for name in PACKAGES:
        try:
            packages[name] = version(name)
        except PackageNotFoundError:
            packages[name] = "not installed"
    commit = _git("rev-parse", "--short", "HEAD")
    return {
        "cpu": _first_line("/proc/cpuinfo", "model name"),
        "cores": os.cpu_count(),
        "usable_cores": len(os.sched_getaffinity(0)),
        "ram_gb": round(int(_first_line("/proc/meminfo", "MemTotal").split()[0]) / 2**20, 1),
        "os": platform.platform(),
        "python": platform.python_version(),
        "packages": packages,
        "sparse_solver": solver_backend(),
        "closest_point_search": "compiled (Numba)" if closest_point_near_kernel() else "NumPy",
        # The code measured: the package and the benchmark (the results folder it writes to
        # is left out, as a run over the committed results always finds it changed).
        "git": commit + (" with uncommitted changes" if _git("status", "--porcelain", "--", "src", "benchmarks/*.py") else ""),
        "date": time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime()),
        "load_average_start": os.getloadavg()[0],
    }


def settings(args):
    return {
        "command": " ".join([Path(sys.argv[0]).name, *sys.argv[1:]]),
        "data": str(args.data),
        "quick": args.quick,
        "parts": args.parts,
        "runs": args.runs,
        "budget_s": args.budget,
    }


# Formatting ---------------------------------------------------------------------------


def progress_line(row):
    what = f"{row['kind']:6} {row['tool']:12} {row['name']:18}"
    if "faces" in row:
        what += f" -> {row['faces']:>7}"
    if row.get("subdivide"):
        what += f" (subdivided {row['subdivide']}x)"
    if row.get("variant"):
        what += " ({method}, relax {relax})".format(**row["variant"])
    if row["status"] != "ok":
        return f"{what}  {row['status']}: {row['reason']}"
    return f"{what}  {row['time']['median']:.3f} s  ({row['wall_s']:.1f} s in all)"


def _num(x):
    return f"{x:.3g}"


def _time(t):
    return f"{_num(t['median'])} ({_num(t['min'])}-{_num(t['max'])}, {t['runs']})"


def _pct(x):
    return "n/a" if x is None else f"{100 * x:.2f}"


def _fixed(x, digits):
    return "n/a" if x is None else f"{x:.{digits}f}"


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(str(c) for c in row) + " |" for row in rows]
    return "\n".join(lines) + "\n"


def _not_ok(row, width):
    return [f"{row['status']}: {row['reason']}"] + [""] * (width - 1)


# Parameterization ---------------------------------------------------------------------


def _param_section(results):
    rows = results["param"]
    out = [
        "## Parameterization of the disk meshes (the analogue of Table 1 of the paper)\n",
        "|mu| of the map disk -> surface (qcremesh.beltrami_coefficient, Eq. 19), unweighted "
        "over the faces. Folded: faces with signed area <= 0, counted against the orientation of "
        "the majority of the faces (a mirrored map is mirrored back first). Disk: boundary on "
        "the unit circle. LSCM has a free boundary and is not a disk map: its distortion is the "
        "floor a disk map can approach.\n",
    ]
    table = []
    for r in rows:
        head = [r["name"], f"{r['faces_in']:,}", TOOL_NAMES[r["tool"]]]
        if r["status"] != "ok":
            table.append(head + _not_ok(r, 7))
            continue
        table.append(
            head
            + [
                f"{r['mu_mean']:.4f}",
                f"{r['mu_median']:.4f}",
                f"{r['mu_max']:.3f}",
                r["folded"],
                "yes" if r["disk"] else "no",
                _time(r["time"]),
                f"{r['peak_rss_mb']:.0f}",
            ]
        )
    out.append(
        _table(
            [
                "mesh",
                "faces",
                "tool",
                "mean abs mu",
                "median abs mu",
                "max abs mu",
                "folded",
                "disk",
                "time s: median (min-max, runs)",
                "peak MB",
            ],
            table,
        )
    )

    ok = {(r["name"], r["tool"]): r for r in rows if r["status"] == "ok"}
    ratios = [
        [
            name,
            _num(q["time"]["median"]),
            _num(h["time"]["median"]),
            f"{q['time']['median'] / h['time']['median']:.1f}",
        ]
        for (name, tool), q in ok.items()
        if tool == "qcremesh" and (h := ok.get((name, "igl_harmonic")))
    ]
    if ratios:
        out.append(
            "\nqcremesh time against igl.harmonic (cotangent weights, arc-length boundary) on "
            "the same mesh:\n"
        )
        out.append(_table(["mesh", "qcremesh s", "igl.harmonic s", "ratio"], ratios))
    stages = [r for r in rows if r["status"] == "ok" and r["tool"] == "qcremesh" and "stages" in r]
    if stages:
        out.append("\nStages of qcremesh.disk_conformal_map (median s per stage):\n")
        out.append(
            _table(
                ["mesh", "faces"] + STAGES,
                [
                    [r["name"], f"{r['faces_in']:,}"] + [f"{r['stages'][s]:.3f}" for s in STAGES]
                    for r in stages
                ],
            )
        )
    return out


# Remeshing ----------------------------------------------------------------------------

REMESH_HEADER = [
    "mesh",
    "tool",
    "faces (vs wanted)",
    "time s: median (min-max, runs)",
    "q mean",
    "q min",
    "q 1%",
    "q>0.9",
    "min angle",
    "valence 6",
    "Hausdorff %",
    "Hausdorff / mean edge",
    "mean dist %",
    "boundary Hausdorff %",
    "manifold",
    "loops",
    "self-intersecting faces (input's)",
    "turned-over faces (input's)",
    "peak MB",
]


def _remesh_cells(r):
    q = r["quality"]
    return [
        f"{q['faces']:,} ({100 * (q['faces'] / r['faces'] - 1):+.1f} %)",
        _time(r["time"]),
        f"{q['q_mean']:.3f}",
        f"{q['q_min']:.3f}",
        f"{q['q_p01']:.3f}",
        f"{q['q_frac_above_0_9']:.3f}",
        f"{q['min_angle_deg']:.1f}",
        _fixed(q["valence6_fraction"], 3),
        _pct(q["hausdorff"]),
        _fixed(q["hausdorff_edges"], 2),
        _pct(q["mean_distance"]),
        _pct(q["boundary_hausdorff"]),
        "yes" if q["manifold"] else "no",
        q["boundary_loops"],
        f"{q['self_intersecting_faces']:,} ({q['reference_self_intersecting_faces']:,})",
        f"{q['turned_over_faces']:,} ({q['reference_turned_over_faces']:,})",
        f"{r['peak_rss_mb']:.0f}",
    ]


def _remesh_section(results):
    rows = results["remesh"]
    out = [
        "## Remeshing\n",
        "Every output measured by `qcremesh.geometry.quality.mesh_quality`: radius ratio q = 2 "
        "r_in / R_circ per face, the smallest angle (degrees), the fraction of interior vertices "
        "of valence 6, Hausdorff and mean distance to the input in % of its bounding-box "
        "diagonal (and the Hausdorff distance in mean edge lengths of the output, which depends "
        "less on the face count), the Hausdorff distance between the boundaries (n/a when only one of the two "
        "meshes has a boundary), manifoldness and boundary loops of the output, and its faces that "
        "meet another where the connectivity does not join them (self-intersections, those of the "
        "input beside them: a remesh that follows a surface through itself does too), and its faces "
        "turned over against the input (their normals more than 90 degrees from those of the input faces "
        "nearest their corners; the input's against itself beside them, which counts where it passes "
        "through itself). Tools that take "
        "an edge length are calibrated to the face count, starting from the length of the "
        "previous run where there is one (the run with the final length is the first timed "
        "run).\n",
    ]
    for label, half in (
        ("at the input's face count", False),
        ("at half the input's face count", True),
    ):
        table = []
        for r in rows:
            if r["half"] != half:
                continue
            head = [r["name"], TOOL_NAMES[r["tool"]]]
            table.append(
                head
                + (_remesh_cells(r) if r["status"] == "ok" else _not_ok(r, len(REMESH_HEADER) - 2))
            )
        out.append(f"\n### {label.capitalize()}\n")
        out.append(_table(REMESH_HEADER, table))
    used = {r["tool"]: r["setting"] for r in rows if r["status"] == "ok"}
    out.append("\nSettings: " + "; ".join(f"{TOOL_NAMES[t]}: {s}" for t, s in used.items()) + ".\n")
    return out


# Ablations ----------------------------------------------------------------------------


def _variant_table(rows, header, head, cells):
    """Markdown table of qcremesh variant runs: the cells ``head(r)`` then ``cells(r,
    quality)`` per row, or the reason the run failed."""
    table = []
    for r in rows:
        first = head(r)
        rest = cells(r, r["quality"]) if r["status"] == "ok" else _not_ok(r, len(header) - len(first))
        table.append(first + rest)
    return _table(header, table)


def _ablation_section(results):
    rows = results["ablation"]
    out = [
        "## Ablations\n",
        "qcremesh's methods at the input's face count (one run each): `uniform` (a regular mesh "
        "of the disk projected as is, the paper's Fig. 7), `base` (the CVT base mesh at full "
        "resolution), `subdivided` (base mesh and subdivision, Figs. 18-20 (c)), `teichmuller` "
        "(and the Teichmueller map, Figs. 18-20 (d)); relax 0 is the paper's pipeline alone, "
        "relax 40 adds the relaxation (the default).\n",
    ]
    header = ["mesh", "method", "relax", "faces", "time s", "q mean", "q min", "q 1%", "q>0.9",
              "Hausdorff %", "mean dist %"]
    out.append(
        _variant_table(
            rows,
            header,
            lambda r: [r["name"], r["variant"]["method"], r["variant"]["relax"]],
            lambda r, q: [
                f"{q['faces']:,}",
                _num(r["time"]["median"]),
                f"{q['q_mean']:.3f}",
                f"{q['q_min']:.3f}",
                f"{q['q_p01']:.3f}",
                f"{q['q_frac_above_0_9']:.3f}",
                _pct(q["hausdorff"]),
                _pct(q["mean_distance"]),
            ],
        )
    )
    out += _ablation_ordering(rows)
    return out


def _ablation_ordering(rows):
    """The paper's claims per mesh, at relax 0: of the adaptive meshes (base, subdivided,
    teichmuller) the Teichmueller map's has the best mean quality (Figs. 18-20), and the
    uniform mesh of the disk, whose triangles are conformal images of equilateral ones,
    loses the geometry: the largest Hausdorff distance (Fig. 7)."""
    lines = ["\nThe paper's ordering, at relax 0 (the pipeline alone):\n"]
    for name in dict.fromkeys(r["name"] for r in rows):
        got = {
            r["variant"]["method"]: r["quality"]
            for r in rows
            if r["name"] == name and r["variant"]["relax"] == 0 and r["status"] == "ok"
        }
        if len(got) < 4:
            continue
        best = max(("base", "subdivided", "teichmuller"), key=lambda k: got[k]["q_mean"])
        worst = max(got, key=lambda k: got[k]["hausdorff"])
        lines.append(
            f"- {name}: best mean q of the adaptive meshes: {best} "
            f"({_verdict(best == 'teichmuller')}); largest Hausdorff distance: {worst} "
            f"({_verdict(worst == 'uniform')})"
        )
    return lines + [""]


def _seeds_section(results):
    rows = results["seeds"]
    out = [
        "## Seeds\n",
        "qcremesh (default settings) with the CVT seeds 0-3, one run each: the landmarks are "
        "drawn from the seed, and the smallest radius ratio and the distance to the surface "
        "depend on that draw (draws: how many landmark draws the run needed to bring every "
        "face to 0.3 or more, at most 3).\n",
    ]
    header = ["mesh", "faces wanted", "seed", "draws", "time s", "q mean", "q min", "q 1%", "Hausdorff %"]
    table = _variant_table(
        rows,
        header,
        lambda r: [r["name"], f"{r['faces']:,}", r["variant"]["seed"]],
        lambda r, q: [
            f"{r['stages']['draws']:.0f}",
            _num(r["time"]["median"]),
            f"{q['q_mean']:.3f}",
            f"{q['q_min']:.3f}",
            f"{q['q_p01']:.3f}",
            _pct(q["hausdorff"]),
        ],
    )
    return out + [table, ""]


def _beside_default(rows, results, title, text):
    """A section of qcremesh variant runs, each beside qcremesh's default run of the
    remesh part (same mesh, face count and seed) after a slash, where there is one."""
    default = {
        (r["name"], r["half"]): r["quality"]
        for r in results.get("remesh", [])
        if r["tool"] == "qcremesh" and r["status"] == "ok"
    }

    def beside(r, key, fmt):
        q, d = r["quality"], default.get((r["name"], r["half"]))
        return fmt(q[key]) + (f" / {fmt(d[key])}" if d is not None else "")

    def three(x):
        return f"{x:.3f}"

    header = ["mesh", "faces wanted", "time s", "q mean", "q min", "q>0.9", "Hausdorff %"]
    table = _variant_table(
        rows,
        header,
        lambda r: [r["name"], f"{r['faces']:,}"],
        lambda r, q: [
            _num(r["time"]["median"]),
            beside(r, "q_mean", three),
            beside(r, "q_min", three),
            beside(r, "q_frac_above_0_9", three),
            beside(r, "hausdorff", _pct),
        ],
    )
    return [title, text, table, ""]


def _sizing_section(results):
    """The curvature sizing beside qcremesh's default runs."""
    return _beside_default(
        results["sizing"],
        results,
        "## Sizing\n",
        "qcremesh with `sizing=\"curvature\"` (edges from 0.4 to 2 times the planned length, "
        "scaled to even out how far the surface leaves its tangent plane at half an edge, and "
        "along the border no longer than the same rule gives for the border's bend), one "
        "run each, seed 0; after the slash, the default (uniform) run of the remesh part.\n",
    )


def _snap_section(results):
    """qcremesh without the snapping beside its default runs."""
    return _beside_default(
        results["snap"],
        results,
        "## Snapping\n",
        "qcremesh with `snap=0`: the input vertices that the relaxation leaves far from the "
        "output (pocket bottoms, tips) are not pulled onto (default: those farther than half "
        "an edge), one run each, seed 0; after the slash, the default run of the remesh part.\n",
    )


def _crease_section(results):
    """Every remesher and qcremesh keeping the creases, on the synthetic CAD-like shapes."""
    out = [
        "## Creases\n",
        "Synthetic CAD-like surfaces with creases (benchmarks/shapes.py: `open_box`, a box open "
        "at the top whose grid lines crowd towards its edges; `cube`, closed, 8 x 8 squares a "
        "side; `plateau`, a disk raised inside a ring 0.1 wide, a crease at each side of the "
        "ring; `mesa`, a flat top on a cone, one closed crease), at their face count and at "
        "half of it: every remesher with its default settings (pymeshlab keeps the edges "
        "turning by more than 30 degrees by default), and qcremesh with `creases=60`.\n",
    ]
    header = ["shape", "faces wanted", "tool", "faces", "time s", "q mean", "q min", "q>0.9",
              "Hausdorff %"]
    table = _variant_table(
        results["creases"],
        header,
        lambda r: [r["name"], f"{r['faces']:,}", TOOL_NAMES[r["tool"]] + (
            f" creases={r['variant']['creases']:g}" if "variant" in r else "")],
        lambda r, q: [
            f"{q['faces']:,}",
            _num(r["time"]["median"]),
            f"{q['q_mean']:.3f}",
            f"{q['q_min']:.3f}",
            f"{q['q_frac_above_0_9']:.3f}",
            _pct(q["hausdorff"]),
        ],
    )
    return out + [table, ""]


# Scaling ------------------------------------------------------------------------------


def fit_exponents(rows):
    """Least-squares slope of log(time) against log(faces), per kind, over the levels that ran."""
    fits = {}
    for kind in ("param", "remesh"):
        ok = [r for r in rows if r["kind"] == kind and r["status"] == "ok"]
        if len(ok) >= 2:
            x = np.log([r["faces_in"] for r in ok])
            y = np.log([r["time"]["median"] for r in ok])
            fits[kind] = float(np.polyfit(x, y, 1)[0])
    return fits


def _scaling_section(results):
    rows = results["scaling"]
    out = [
        f"## Scaling: qcremesh on {rows[0]['name']} subdivided 0, 1 and 2 times\n",
        "Peak memory is that of the whole worker process (Python, the libraries and the loaded "
        "mesh included); the resident size after loading is given beside it.\n",
    ]
    table = []
    for r in rows:
        head = [
            "disk_conformal_map" if r["kind"] == "param" else "remesh",
            r.get("subdivide", 0),
            f"{r.get('faces_in', 0):,}",
        ]
        if r["status"] != "ok":
            table.append(head + _not_ok(r, 4))
            continue
        stages = ", ".join(f"{k} {v:.2f}" for k, v in r.get("stages", {}).items())
        table.append(
            head + [_time(r["time"]), f"{r['peak_rss_mb']:.0f}", f"{r['load_rss_mb']:.0f}", stages]
        )
    out.append(
        _table(
            [
                "job",
                "subdivisions",
                "faces",
                "time s: median (min-max, runs)",
                "peak MB",
                "MB after load",
                "stages (median s)",
            ],
            table,
        )
    )
    fits = results.get("scaling_fit", {})
    if fits:
        out.append(
            "\nFitted exponent b of time ~ faces^b: "
            + ", ".join(
                f"{'disk_conformal_map' if k == 'param' else 'remesh'} {b:.2f}"
                for k, b in fits.items()
            )
            + ".\n"
        )
    return out


# Targets ------------------------------------------------------------------------------

MU_TARGETS = {"human_face.obj": 0.022, "hand.ply": 0.020, "human_brain.ply": 0.026}


def _verdict(ok):
    return "met" if ok else "**not met**"


def _param_targets(results):
    lines = []
    qc = {
        r["name"]: r
        for r in results.get("param", [])
        if r["tool"] == "qcremesh" and r["status"] == "ok"
    }
    for name, bound in MU_TARGETS.items():
        if name in qc:
            mu = qc[name]["mu_mean"]
            lines.append(f"- mean abs mu on {name} <= {bound}: {mu:.4f}, {_verdict(mu <= bound)}")
    if qc:
        folded = {n: r["folded"] for n, r in qc.items() if r["folded"]}
        lines.append(
            f"- no folded faces on {len(qc)} disk meshes: {_verdict(not folded)}"
            + (f" ({folded})" if folded else "")
        )
    if "hand.ply" in qc:
        t = qc["hand.ply"]["time"]["median"]
        lines.append(f"- disk_conformal_map of hand.ply <= 1 s: {t:.2f} s, {_verdict(t <= 1.0)}")
    big = [
        r
        for r in results.get("scaling", [])
        if r["kind"] == "param"
        and r["status"] == "ok"
        and r["name"] == "hand.ply"
        and r.get("subdivide") == 2
    ]
    for r in big:
        t, peak = r["time"]["median"], r["peak_rss_mb"]
        lines.append(
            f"- hand.ply subdivided twice ({r['faces_in']:,} faces) <= 15 s: {t:.2f} s, "
            f"{_verdict(t <= 15)}; "
            f"peak <= 3 GB: {peak / 1024:.2f} GB, {_verdict(peak <= 3072)}"
        )
    return lines


def _remesh_targets(results):
    rows = [r for r in results.get("remesh", []) if r["status"] == "ok"]
    disks = {m["mesh"] for m in results["meshes"] if m["not_disk"] is None}
    qc = {
        (r["name"], r["faces"]): r for r in rows if r["tool"] == "qcremesh" and r["name"] in disks
    }
    if not qc:
        reasons = {
            r["reason"]
            for r in results.get("remesh", [])
            if r["tool"] == "qcremesh" and r["status"] != "ok" and r["name"] in disks
        }
        return [
            "- qcremesh against the other remeshers: no qcremesh remesh results ("
            + "; ".join(sorted(reasons))
            + ")"
        ]
    turned = {
        f"{name} at {faces:,} faces": r["quality"]["turned_over_faces"]
        for (name, faces), r in qc.items()
        if r["quality"]["turned_over_faces"] > r["quality"]["reference_turned_over_faces"]
    }
    lines = [
        f"- normals consistent with the input's (no face turned over against it beyond the input's own) on "
        f"the {len(qc)} remeshes of disk meshes: {_verdict(not turned)}" + (f" ({turned})" if turned else "")
    ]
    table = []
    for (name, faces), r in qc.items():
        others = [
            o for o in rows if o["tool"] != "qcremesh" and o["name"] == name and o["faces"] == faces
        ]
        if not others:
            continue
        q = r["quality"]
        best = {
            key: max(o["quality"][key] for o in others)
            for key in ("q_min", "q_frac_above_0_9", "q_mean")
        }
        best["hausdorff"] = min(o["quality"]["hausdorff"] for o in others)
        fastest = min(o["time"]["median"] for o in others)
        table.append(
            [
                name,
                f"{faces:,}",
                f"{q['q_min']:.3f} / {best['q_min']:.3f} {_verdict(q['q_min'] > best['q_min'])}",
                f"{q['q_frac_above_0_9']:.3f} / {best['q_frac_above_0_9']:.3f} "
                f"{_verdict(q['q_frac_above_0_9'] > best['q_frac_above_0_9'])}",
                f"{q['q_mean']:.3f} / {best['q_mean']:.3f} "
                f"{_verdict(q['q_mean'] >= best['q_mean'])}",
                f"{_pct(q['hausdorff'])} / {_pct(best['hausdorff'])} "
                f"{_verdict(q['hausdorff'] <= best['hausdorff'])}",
                f"{_num(r['time']['median'])} / {_num(fastest)}",
            ]
        )
    return lines + [
        "\nqcremesh against the best of the other remeshers on each disk mesh (qcremesh / best "
        "other):\n",
        _table(
            [
                "mesh",
                "faces",
                "q min (ahead)",
                "q>0.9 (ahead)",
                "q mean (no worse)",
                "Hausdorff % (no worse)",
                "time s (qcremesh / fastest)",
            ],
            table,
        ),
    ]


# Whole report -------------------------------------------------------------------------


def markdown(results):
    m = results["machine"]
    s = results["settings"]
    out = [
        "# qcremesh benchmarks\n",
        f"`{s['command']}` on {m['date']}, data from "
        f"`{s['data']}`{' (quick mode)' if s['quick'] else ''}; "
        f"{results['total_s']:.0f} s in all.\n",
        "## Machine\n",
        f"- CPU: {m['cpu']}, {m['cores']} cores ({m['usable_cores']} usable), {m['ram_gb']} GB RAM",
        f"- {m['os']}, Python {m['python']}, sparse solver of qcremesh: {m['sparse_solver']}, "
        f"closest-point search of qcremesh: {m['closest_point_search']}",
        f"- qcremesh at git {m['git'] or 'unknown'}",
        f"- load average (1 min) {m['load_average_start']:.1f} at the start, "
        f"{m['load_average_end']:.1f} at the end "
        "(the benchmark itself accounts for about 1; more means other processes shared the "
        f"{m['usable_cores']} cores "
        "and the times are noisier)",
        "- " + ", ".join(f"{k} {v}" for k, v in m["packages"].items()) + "\n",
        "Each tool runs in a process of its own, kept for all its jobs (the jobs one at a time, "
        "interleaved across tools; the scaling runs each in a new process). Times are wall times of the tool's "
        "call alone (loading the mesh excluded, conversion to and from the tool's own mesh type "
        "included), after one untimed run on a small mesh (so that importing the tool and "
        "loading compiled code is in no timed run): the median of "
        f"up to {s['runs']} runs, fewer once the runs add up to {s['budget_s']:.0f} s, with "
        "min and max. Peak MB "
        "is the peak resident memory of that process during the job (its mark reset at the "
        "job's start, so memory an earlier job of the process left allocated counts too).\n",
    ]
    if results.get("param"):
        out += _param_section(results)
    if results.get("remesh"):
        out += _remesh_section(results)
    if results.get("ablation"):
        out += _ablation_section(results)
    if results.get("seeds"):
        out += _seeds_section(results)
    if results.get("sizing"):
        out += _sizing_section(results)
    if results.get("snap"):
        out += _snap_section(results)
    if results.get("creases"):
        out += _crease_section(results)
    if results.get("scaling"):
        out += _scaling_section(results)
    targets = _param_targets(results) + (_remesh_targets(results) if results.get("remesh") else [])
    if targets:
        out += ["## Targets (issues 2 and 3)\n"] + targets
    if results["skipped_meshes"]:
        out += ["\n## Files not benchmarked\n"] + [
            f"- {r['mesh']}: {r['reason']}" for r in results["skipped_meshes"]
        ]
    return "\n".join(out) + "\n"


# Plots --------------------------------------------------------------------------------


def plots(results, folder):
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.ticker import NullFormatter

    param = [r for r in results.get("param", []) if r["status"] == "ok"]
    remesh = [r for r in results.get("remesh", []) if r["status"] == "ok"]
    scaling = [r for r in results.get("scaling", []) if r["status"] == "ok"]

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    panels = (
        (axes[0], param, "param", "parameterization time", "input faces"),
        (axes[1], remesh, "remesh", "remeshing time (input count and half)", "output faces"),
    )
    for ax, rows, kind, title, xlabel in panels:
        for tool in dict.fromkeys(r["tool"] for r in rows):
            mine = [r for r in rows if r["tool"] == tool]
            faces = [r["quality"]["faces"] if kind == "remesh" else r["faces_in"] for r in mine]
            ax.plot(faces, [r["time"]["median"] for r in mine], "o", label=TOOL_NAMES[tool])
        big = [r for r in scaling if r["kind"] == kind]
        if big:
            faces = [r["faces_in"] for r in big]
            ax.plot(
                faces,
                [r["time"]["median"] for r in big],
                "k^--",
                label=f"qcremesh, {big[0]['name']} subdivided",
            )
        ax.set(xscale="log", yscale="log", xlabel=xlabel, ylabel="wall time (s)", title=title)
        ax.xaxis.set_minor_formatter(NullFormatter())
        if ax.has_data():
            ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / "time_vs_faces.png", dpi=120)
    plt.close(fig)

    if not remesh:
        return
    disks = {m["mesh"] for m in results["meshes"] if m["not_disk"] is None}
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5))
    for ax, key, label in (
        (axes[0], "q_mean", "mean radius ratio"),
        (axes[1], "q_min", "min radius ratio"),
    ):
        for tool in dict.fromkeys(r["tool"] for r in remesh):
            mine = [r for r in remesh if r["tool"] == tool and r["name"] in disks]
            ax.scatter(
                [r["time"]["median"] for r in mine],
                [r["quality"][key] for r in mine],
                label=TOOL_NAMES[tool],
            )
        ax.set(
            xscale="log",
            xlabel="wall time (s)",
            ylabel=label,
            title=f"{label} against time, disk meshes, both counts",
        )
        ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(folder / "quality_vs_time.png", dpi=120)
    plt.close(fig)
