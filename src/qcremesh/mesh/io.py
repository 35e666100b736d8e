"""Reading and writing triangle meshes.

OBJ is read and written here: meshio's reader refuses texture coordinates with seams
(``f a/b`` where ``b`` is not ``a``, as every UV-mapped export has) and negative indices,
and written here it carries texture coordinates as ``f a/a b/b c/c`` with bytes that do
not depend on the time of day. OFF is read here too (meshio's reader takes triangles
only, and no COFF nor counts on the header's line). PLY is read and written through
plyfile: meshio's binary reader takes ``uchar`` properties (the usual colours) as signed
bytes (200 read as -56) and refuses ``char``, ``short`` and ``ushort`` ones and elements
other than vertices and faces (a range map's ``camera``), and its writer puts the time of
day in the header. MATLAB ``.mat`` files with variables ``v`` and ``f``
(1-based), as distributed with the public quasi-conformal codes, are read through
:func:`scipy.io.loadmat`. VTK's polygonal data (.vtp, and legacy .vtk files of
POLYDATA, which meshio does not read) goes through pyvista where it is installed. Every
other format goes through meshio (STL, VTK/VTU unstructured grids, ...). Quads are split
along their shorter diagonal, larger convex polygons into fans.
"""

from __future__ import annotations

import importlib.util
import io
import os
import tempfile
import warnings
from contextlib import contextmanager, redirect_stderr, redirect_stdout
from pathlib import Path

import numpy as np

from .polydata import arrays_to_polydata, polydata_to_arrays
from .validate import in_space

__all__ = ["MeshReadError", "read_mesh", "write_mesh", "check_writable", "atomic_output", "meshio_to_arrays"]


class MeshReadError(ValueError):
    """The file cannot be read as a triangle mesh."""


def read_mesh(path, *, return_data=False):
    """Read a triangle mesh; quads are split into two triangles along their shorter
    diagonal, larger convex polygons into the fan from their first corner.

    Parameters
    ----------
    path : str or os.PathLike
        File to read. The format is chosen by the extension.
    return_data : bool, optional
        Also return the per-vertex data stored in the file (colours, scalars,
        texture coordinates) as a dict of arrays with ``n`` rows.

    Returns
    -------
    V : (n, 3) float64
        Vertex positions (a planar mesh gets z = 0).
    F : (m, 3) int64
        Triangles, 0-based indices into ``V``.
    data : dict of str to ndarray
        Only when ``return_data`` is true.

    Raises
    ------
    MeshReadError
        The file is missing, unreadable, or holds no triangles (or holds polygons that
        are not convex, or cells other than polygons).
    """
    path = Path(path)
    if not path.is_file():
        raise MeshReadError(f"{path}: no such file")
    suffix = path.suffix.lower()
    if suffix == ".mat":
        V, F, data = _read_mat(path)
    elif suffix == ".obj":
        V, F, data = _read_obj(path)
    elif suffix == ".off":
        V, F, data = _read_off(path)
    elif suffix == ".ply":
        V, F, data = _read_ply(path)
    elif suffix == ".vtp":
        V, F, data = _read_polydata(path)
    elif suffix == ".vtk":
        V, F, data = _read_vtk(path)
    else:
        V, F, data = _read_meshio(path)
    V = np.ascontiguousarray(V, dtype=np.float64)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise MeshReadError(f"{path}: vertices must have 2 or 3 coordinates")
    V = in_space(V)
    F = np.ascontiguousarray(F, dtype=np.int64)
    if len(F) == 0:
        raise MeshReadError(f"{path}: no triangles in the file")
    if F.min() < 0 or F.max() >= len(V):
        raise MeshReadError(f"{path}: face indices out of range")
    if not np.all(np.isfinite(V)):
        raise MeshReadError(f"{path}: non-finite vertex coordinates")
    return (V, F, data) if return_data else (V, F)


def _read_vtk(path):
    """A legacy VTK file: through meshio (unstructured grids), else through pyvista where
    it is installed (polygonal data, which meshio does not read); meshio's error stands
    where neither reads it."""
    try:
        return _read_meshio(path)
    except MeshReadError as error:
        if importlib.util.find_spec("pyvista") is None:
            raise
        try:
            return _read_polydata(path)
        except MeshReadError:
            raise error


def _read_polydata(path):
    """A VTK file of polygonal data through pyvista; its active texture coordinates as
    data ``uv``."""
    try:
        import pyvista as pv
    except ImportError as exc:
        raise MeshReadError(f"{path}: reading {path.suffix} files needs pyvista: pip install pyvista") from exc
    try:
        mesh = pv.read(path)
    except Exception as exc:  # VTK's readers raise many types
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    if not isinstance(mesh, pv.PolyData):
        raise MeshReadError(f"{path}: not polygonal data (a {type(mesh).__name__})")
    try:
        V, F, data = polydata_to_arrays(mesh, pv)
    except ValueError as exc:
        raise MeshReadError(f"{path}: no triangles in the file") from exc
    uv = mesh.point_data.active_texture_coordinates_name
    if uv in data:
        data["uv"] = data.pop(uv)
    return V, F, data


def _read_meshio(path):
    import meshio

    # meshio prints its parsers' complaints (and numpy overflow warnings on odd STL
    # headers) besides raising: the exception alone reaches the caller.
    said = io.StringIO()
    try:
        with redirect_stdout(said), redirect_stderr(said), np.errstate(all="ignore"):
            m = meshio.read(path)
    except (Exception, SystemExit) as exc:  # meshio raises many types, even SystemExit
        # (a SystemExit carries only a status; what went wrong is what meshio printed)
        printed = [line.strip() for line in said.getvalue().splitlines() if line.strip()]
        detail = printed[0] if isinstance(exc, SystemExit) and printed else exc
        raise MeshReadError(f"{path}: cannot read ({detail})") from exc
    V, F, data = meshio_to_arrays(m, path)
    if "texture_u" in data and "texture_v" in data:
        data["uv"] = np.column_stack([data.pop("texture_u"), data.pop("texture_v")])
    if "obj:vt" in data:
        data["uv"] = np.asarray(data.pop("obj:vt"))[:, :2]
    return V, F, data


def meshio_to_arrays(mesh, name="the mesh"):
    """The surface of a :class:`meshio.Mesh` as arrays: its points, the triangles of its
    triangle, quad and polygon cells (quads split along their shorter diagonal, larger
    convex polygons into the fan from their first corner) and its point data of one row
    per point, by name (as they are: :func:`read_mesh` renames texture coordinates).

    Parameters
    ----------
    mesh : meshio.Mesh
    name : str
        What to call it in errors (the file it was read from).

    Returns
    -------
    V : (n, d) array
        ``mesh.points`` as they are.
    F : (m, 3) int64
    data : dict of str to ndarray

    Raises
    ------
    MeshReadError
        Cells other than triangles, quads, polygons, vertices and lines (a volume
        mesh), none of the first three, polygons that are not convex, indices out of
        range.
    """
    other = {c.type for c in mesh.cells} - {"triangle", "quad", "polygon", "vertex", "line"}
    if other:
        raise MeshReadError(f"{name}: not a triangle mesh (has {', '.join(sorted(other))} cells)")
    blocks = [np.asarray(c.data, dtype=np.int64) for c in mesh.cells if c.type in ("triangle", "quad", "polygon")]
    if not blocks:
        raise MeshReadError(f"{name}: no triangles, quads or polygons")
    tri = [_polygons_to_triangles(name, mesh.points, b.ravel(), np.full(len(b), b.shape[1])) for b in blocks]
    data = {}
    for key, arr in mesh.point_data.items():
        arr = np.asarray(arr)
        if len(arr) == len(mesh.points):
            data[key] = arr
    return mesh.points, np.concatenate(tri), data


def _read_obj(path):
    """Positions, faces and per-vertex data of a Wavefront OBJ file.

    Face corners ``a``, ``a/t``, ``a/t/n`` or ``a//n`` name a position, a texture
    coordinate and a normal; negative indices count back from the last one read. Texture
    coordinates (data ``uv``) and normals (``normals``) are kept where every corner of a
    vertex names the same value; a vertex with several (a seam of the texture) keeps the
    positions and faces but not that data.
    """
    try:
        lines = path.read_text(errors="replace").splitlines()
    except OSError as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    head = np.array([line.split(maxsplit=1)[0] if line.strip() else "" for line in lines])
    rows = {tag: [lines[i].split() for i in np.flatnonzero(head == tag)] for tag in ("v", "vt", "vn", "f")}
    if not rows["f"]:
        raise MeshReadError(f"{path}: no triangles in the file")
    try:
        V = np.array([r[1:4] for r in rows["v"]], dtype=np.float64)
        vt = np.array([r[1:3] for r in rows["vt"]], dtype=np.float64)
        vn = np.array([r[1:4] for r in rows["vn"]], dtype=np.float64)
        sizes = np.fromiter(map(len, rows["f"]), dtype=np.int64, count=len(rows["f"])) - 1
        corner = np.array([c for r in rows["f"] for c in r[1:]])
        position, _, rest = np.char.partition(corner, "/").T
        texture, _, normal = np.char.partition(rest, "/").T
        refs = [np.where(part == "", "0", part).astype(np.int64) for part in (position, texture, normal)]
    except ValueError as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    if V.ndim != 2 or V.shape[1] != 3:
        raise MeshReadError(f"{path}: cannot read (vertices need 3 coordinates)")
    # 1-based, or negative from the last one read before the face's line
    is_face = head == "f"
    for k, tag in enumerate(("v", "vt", "vn")):
        read_before = np.repeat(np.cumsum(head == tag)[is_face], sizes)
        refs[k] = np.where(refs[k] < 0, read_before + refs[k], refs[k] - 1)
    F = _polygons_to_triangles(path, V, refs[0], sizes)
    data = {}
    for name, ref, values in (("uv", refs[1], vt), ("normals", refs[2], vn)):
        per_vertex = _per_vertex(refs[0], ref, values, len(V))
        if per_vertex is not None:
            data[name] = per_vertex
    return V, F, data


def _polygons_to_triangles(path, V, corners, sizes):
    """Triangles of polygons given by their corners in a row and their sizes, in order:
    triangles as they are, quads split along their shorter diagonal, larger convex
    polygons into the fan from their first corner (:func:`_fans`)."""
    if np.any(sizes < 3):
        raise MeshReadError(f"{path}: cannot read (a face with fewer than 3 corners)")
    if len(corners) and (corners.min() < 0 or corners.max() >= len(V)):
        raise MeshReadError(f"{path}: face indices out of range")
    start = np.cumsum(sizes) - sizes
    at = np.cumsum(sizes - 2) - (sizes - 2)
    F = np.empty((int(np.sum(sizes - 2)), 3), dtype=np.int64)
    for n in np.unique(sizes):
        these = sizes == n
        P = corners[start[these, None] + np.arange(n)]
        T = P if n == 3 else _split_quads(V, P) if n == 4 else _fans(path, V, P)
        F[(at[these, None] + np.arange(n - 2)).ravel()] = T
    return F


def _fans(path, V, P):
    """The fans of polygons (k, n) from their first corners, (k (n - 2), 3), polygon by
    polygon; refused unless every polygon is convex (each fan triangle turns as the
    polygon does, about its Newell normal)."""
    X = np.asarray(V, dtype=np.float64)[P]
    normal = np.cross(X, np.roll(X, -1, axis=1)).sum(1)
    a, b, c = X[:, :1], X[:, 1:-1], X[:, 2:]
    turn = np.einsum("kjd,kd->kj", np.cross(b - a, c - a), normal)
    if np.any(turn <= 0):
        raise MeshReadError(
            f"{path}: a face of {P.shape[1]} corners is not convex (or not flat): triangulate the mesh first"
        )
    n = P.shape[1]
    fan = np.stack([np.broadcast_to(P[:, :1], (len(P), n - 2)), P[:, 1:-1], P[:, 2:]], axis=2)
    return fan.reshape(-1, 3)


def _read_off(path):
    """Positions and faces of an OFF file (also COFF, NOFF, ...: the numbers after a
    vertex's first three, and after a face's corners, are left out; comments after #)."""
    try:
        rows = [line.split("#", 1)[0].split() for line in path.read_text(errors="replace").splitlines()]
    except OSError as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    rows = [r for r in rows if r]
    if not rows or not rows[0][0].endswith("OFF"):
        raise MeshReadError(f"{path}: cannot read (no OFF header)")
    counts, at = (rows[0][1:], 1) if len(rows[0]) > 1 else (rows[1] if len(rows) > 1 else [], 2)
    try:
        nv, nf = int(counts[0]), int(counts[1])
        V = np.array([r[:3] for r in rows[at : at + nv]], dtype=np.float64)
        faces = rows[at + nv : at + nv + nf]
        sizes = np.array([int(r[0]) for r in faces], dtype=np.int64)
        corners = np.array([c for r, k in zip(faces, sizes) for c in r[1 : 1 + k]], dtype=np.int64)
    except (ValueError, IndexError) as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    if V.shape != (nv, 3) or len(sizes) != nf or len(corners) != sizes.sum():
        raise MeshReadError(f"{path}: cannot read (fewer vertices or faces than its header says)")
    if not nf:
        raise MeshReadError(f"{path}: no triangles in the file")
    return V, _polygons_to_triangles(path, V, corners, sizes), {}


def _per_vertex(vertex, ref, values, n):
    """``values[ref]`` per vertex where every corner of a vertex names the same value, else
    None (also where a corner names none or a value out of range)."""
    if values.ndim != 2 or ref.min() < 0 or ref.max() >= len(values):
        return None
    out = np.full((n, values.shape[1]), np.nan)
    out[vertex] = values[ref]
    if not np.array_equal(out[vertex], values[ref]):
        return None
    return np.nan_to_num(out)


def _read_ply(path):
    """Positions, faces and per-vertex scalars (in the file's types) of a PLY file through
    plyfile; read first as triangles, which plyfile then reads as one array (hand.ply:
    0.35 s as lists of any length, 0.002 s so), and where a face is not, again."""
    from plyfile import PlyData, PlyElementParseError

    triangles = {"face": {"vertex_indices": 3, "vertex_index": 3}}
    try:
        with warnings.catch_warnings():  # numpy's, on an empty list in an ASCII file
            warnings.simplefilter("ignore")
            try:
                ply = PlyData.read(path, known_list_len=triangles)
            except PlyElementParseError:
                ply = PlyData.read(path)
        vertex = ply["vertex"].data
        V = np.column_stack([vertex[c] for c in "xyz"]).astype(np.float64)
        face = ply["face"].data
    except Exception as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    lists = [n for n in face.dtype.names if n in ("vertex_indices", "vertex_index")]
    if not lists:
        raise MeshReadError(f"{path}: cannot read (faces without vertex_indices)")
    polys = face[lists[0]]
    if polys.dtype != object:  # read as triangles
        sizes, corners = np.full(len(polys), 3), polys.astype(np.int64).ravel()
    else:
        sizes = np.fromiter(map(len, polys), dtype=np.int64, count=len(polys))
        corners = np.concatenate(polys).astype(np.int64) if len(polys) else np.zeros(0, dtype=np.int64)
    F = _polygons_to_triangles(path, V, corners, sizes)
    # the vertices' numbers (lists, as some scanners write, are left out)
    data = {
        n: np.array(vertex[n], dtype=vertex.dtype[n].newbyteorder("="))  # a copy, not a view of the file
        for n in vertex.dtype.names
        if n not in ("x", "y", "z") and vertex.dtype[n] != object
    }
    if "texture_u" in data and "texture_v" in data:
        data["uv"] = np.column_stack([data.pop("texture_u"), data.pop("texture_v")])
    return V, F, data


def _split_quads(P, Q):
    """Two triangles per quad (a, b, c, d), split along its shorter diagonal, (2 q, 3)."""
    P = np.asarray(P, dtype=np.float64)
    a, b, c, d = np.asarray(Q, dtype=np.int64).T
    ac = np.linalg.norm(P[c] - P[a], axis=1) <= np.linalg.norm(P[d] - P[b], axis=1)
    first = np.where(ac[:, None], np.column_stack([a, b, c]), np.column_stack([a, b, d]))
    second = np.where(ac[:, None], np.column_stack([a, c, d]), np.column_stack([b, c, d]))
    return np.stack([first, second], axis=1).reshape(-1, 3)


def _read_mat(path):
    from scipy.io import loadmat

    try:
        d = loadmat(path)
    except Exception as exc:
        raise MeshReadError(f"{path}: cannot read ({exc})") from exc
    if "v" not in d or "f" not in d:
        raise MeshReadError(f"{path}: a .mat mesh needs variables 'v' and 'f'")
    V = np.asarray(d["v"], dtype=np.float64)
    F = np.asarray(d["f"], dtype=np.int64) - 1
    if F.ndim != 2 or F.shape[1] != 3:
        raise MeshReadError(f"{path}: 'f' must be an (m, 3) array")
    data = {
        k: np.asarray(val).ravel()
        for k, val in d.items()
        if not k.startswith("__") and k not in ("v", "f") and np.size(val) == len(V)
    }
    return V, F, data


def write_mesh(path, V, F, *, uv=None, data=None):
    """Write a triangle mesh, atomically.

    The file appears only once it is complete: it is written to a temporary file in the
    same folder and renamed, so a failure never leaves a partial output.

    Parameters
    ----------
    path : str or os.PathLike
        Output file; the format is chosen by the extension (``.obj`` is written here,
        ``.ply`` through plyfile, ``.vtp`` through pyvista, anything else through meshio).
    V : (n, 3) or (n, 2) array_like
        Vertex positions.
    F : (m, 3) array_like of int
        Triangles, 0-based.
    uv : (n, 2) array_like, optional
        Texture coordinates, one per vertex. In OBJ they become ``vt`` lines with the
        vertex's index and faces ``f a/a b/b c/c``; in VTP the active texture
        coordinates; in other formats point data ``texture_u`` and ``texture_v``.
    data : dict of str to (n,) or (n, k) array_like, optional
        Further per-vertex data (ignored by OBJ).
    """
    path = Path(path)
    check_writable(path)
    V = np.asarray(V, dtype=np.float64)
    F = np.asarray(F, dtype=np.int64)
    if V.ndim != 2 or V.shape[1] not in (2, 3):
        raise ValueError(f"V must be (n, 3), got shape {V.shape}")
    if F.ndim != 2 or F.shape[1] != 3:
        raise ValueError(f"F must be (m, 3), got shape {F.shape}")
    if uv is not None:
        uv = np.asarray(uv, dtype=np.float64)
        if uv.shape != (len(V), 2):
            raise ValueError(f"uv must be ({len(V)}, 2), got shape {uv.shape}")
    point_data = {k: np.asarray(v) for k, v in (data or {}).items()}
    if uv is not None:
        point_data.update(texture_u=uv[:, 0], texture_v=uv[:, 1])
    with atomic_output(path) as tmp:
        if path.suffix.lower() == ".obj":
            _write_obj(tmp, V, F, uv)
        elif path.suffix.lower() == ".ply":
            _write_ply(tmp, V, F, point_data)
        elif path.suffix.lower() == ".vtp":
            _write_polydata(tmp, V, F, data, uv)
        else:
            _write_meshio(tmp, V, F, point_data)


def check_writable(path):
    """Raise ValueError unless :func:`write_mesh` can write the format of ``path`` by its
    extension (OBJ, PLY, VTP where pyvista is installed, or one of meshio's, whose writer
    is tried on one triangle: some need a module not installed, as XDMF h5py), so that a
    caller can tell before the work whose result it writes."""
    import meshio

    name = Path(path).name.lower()
    if name.endswith(".vtp"):
        if importlib.util.find_spec("pyvista") is None:
            raise ValueError("cannot write .vtp files without pyvista: pip install pyvista")
        return
    known = [ext for ext in (".obj", *meshio.extension_to_filetypes) if name.endswith(ext)]
    if not known:
        what = f"{Path(path).suffix} files" if Path(path).suffix else "a file without an extension"
        raise ValueError(
            f"cannot write {what} (the extension names the format: .obj, .ply, .off, .stl, .vtk, .vtu, ...)"
        )
    ext = max(known, key=len)
    if ext not in (".obj", ".ply"):
        with tempfile.TemporaryDirectory() as folder:
            _write_meshio(Path(folder) / f"probe{ext}", np.eye(3), np.array([[0, 1, 2]]), {})


@contextmanager
def atomic_output(path):
    """Context for writing a file that appears only once complete.

    Yields the path of a temporary file in the same folder (with the same extension, so
    writers that choose the format by extension still work); on success it is renamed to
    ``path``, with the permissions of the file it replaces or, for a new file, those the
    process's umask gives (the temporary file is private); on any error it is removed and
    ``path`` is left untouched.
    """
    path = Path(path)
    fd, tmp = tempfile.mkstemp(suffix=path.suffix.lower(), prefix=".tmp-", dir=path.parent)
    os.close(fd)
    try:
        yield tmp
        if path.exists():
            mode = path.stat().st_mode & 0o7777
        else:
            umask = os.umask(0)
            os.umask(umask)
            mode = 0o666 & ~umask
        os.chmod(tmp, mode)
        os.replace(tmp, path)
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise


def _write_obj(path, V, F, uv):
    parts = [_format_rows("v", in_space(V))]
    if uv is None:
        parts.append(_format_rows("f", F + 1, integer=True))
    else:
        parts.append(_format_rows("vt", uv))
        idx = np.repeat(F + 1, 2, axis=1)
        parts.append(_format_rows("f", idx, integer=True, pairs=True))
    with open(path, "w") as fh:
        fh.write("".join(parts))


def _format_rows(tag, A, integer=False, pairs=False):
    if len(A) == 0:
        return ""
    if integer:
        cols = A.shape[1] // 2 if pairs else A.shape[1]
        cell = "{}/{}" if pairs else "{}"
        fmt = tag + (" " + cell) * cols + "\n"
    else:
        fmt = tag + " {!r}" * A.shape[1] + "\n"
    return (fmt * len(A)).format(*A.ravel().tolist())


def _write_meshio(path, V, F, point_data):
    import meshio

    # 32-bit indices where they fit: smaller files, and the type most readers expect
    cells = F.astype(np.int32) if len(V) < 2**31 else F
    mesh = meshio.Mesh(V, [("triangle", cells)], point_data=point_data)
    try:
        with redirect_stdout(io.StringIO()), redirect_stderr(io.StringIO()):
            meshio.write(path, mesh)
    except Exception as exc:
        raise ValueError(f"cannot write {Path(path).suffix} files ({exc})") from exc


def _write_polydata(path, V, F, data, uv):
    """VTK XML polygonal data through pyvista, ``uv`` as its active texture coordinates."""
    import pyvista as pv

    mesh = arrays_to_polydata(in_space(V), F, data, pv)
    if uv is not None:
        mesh.active_texture_coordinates = uv
    mesh.save(path)


def _write_ply(path, V, F, point_data):
    """Binary PLY through plyfile: coordinates as doubles, the per-vertex data in their
    types where PLY has them (booleans as bytes, 64-bit integers as 32-bit ones where
    their values fit, doubles otherwise), faces as lists of 32-bit indices."""
    from plyfile import PlyData, PlyElement

    if len(V) >= 2**31:
        raise ValueError("cannot write .ply files of 2**31 vertices or more (32-bit indices)")
    columns = {"x": V[:, 0], "y": V[:, 1]}
    if V.shape[1] == 3:
        columns["z"] = V[:, 2]
    for name, values in _ply_columns(point_data).items():
        if name in columns:
            raise ValueError(f"cannot write per-vertex data named {name!r} to .ply (a coordinate's name)")
        columns[name] = _ply_typed(values)
    vertex = np.empty(len(V), dtype=[(name, values.dtype) for name, values in columns.items()])
    for name, values in columns.items():
        vertex[name] = values
    face = np.empty(len(F), dtype=[("vertex_indices", np.int32, (3,))])
    face["vertex_indices"] = F
    elements = [PlyElement.describe(vertex, "vertex"), PlyElement.describe(face, "face", len_types={"vertex_indices": "u1"})]
    PlyData(elements, byte_order="<").write(str(path))


def _ply_typed(values):
    """``values`` in a type that PLY holds (8 to 32-bit integers, floats, doubles)."""
    if values.dtype == np.bool_:
        return values.astype(np.uint8)
    if values.dtype.kind in "iu" and values.dtype.itemsize == 8:
        big = len(values) and (values.min() < np.iinfo(np.int32).min or values.max() > np.iinfo(np.int32).max)
        return values.astype(np.float64 if big else np.int32)
    if values.dtype.kind == "f" and values.dtype.itemsize < 4:
        return values.astype(np.float32)
    if values.dtype.kind not in "iuf":
        raise ValueError(f"cannot write per-vertex data of type {values.dtype} to .ply")
    return values.astype(values.dtype.newbyteorder("<"))


def _ply_columns(point_data):
    """Per-vertex arrays of several columns split into one property each, as PLY holds
    them: ``normals`` into ``nx``, ``ny``, ``nz``, any other ``name`` into ``name_0``,
    ``name_1``, ..."""
    out = {}
    for name, arr in point_data.items():
        if arr.ndim == 1 or (arr.ndim == 2 and arr.shape[1] == 1):
            out[name] = arr.reshape(len(arr))
            continue
        flat = arr.reshape(len(arr), -1)
        names = ("nx", "ny", "nz") if name == "normals" and flat.shape[1] == 3 else [f"{name}_{j}" for j in range(flat.shape[1])]
        out.update(zip(names, flat.T))
    return out
