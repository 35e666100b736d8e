"""Remeshing of trimesh's meshes.

:func:`remesh_trimesh` takes a :class:`trimesh.Trimesh` and returns one, with what its
vertices carry carried along: ``vertex_attributes``, texture coordinates (with the
material) and vertex colours. trimesh splits the vertices along a texture's seams; they
are merged first, and the texture coordinates, which differ across the seams, left out
(``weld=False`` keeps both).
"""

from __future__ import annotations

import warnings

import numpy as np

from ..remeshing.pipeline import remesh
from . import require

__all__ = ["from_trimesh", "to_trimesh", "weld_seams", "remesh_trimesh"]

# names of the texture coordinates and vertex colours among the per-vertex data
UV = "uv"
COLORS = "vertex_colors"



def from_trimesh(mesh):
    """The arrays of a :class:`trimesh.Trimesh`.

    Parameters
    ----------
    mesh : trimesh.Trimesh

    Returns
    -------
    V : (n, 3) float64
    F : (m, 3) int64
    data : dict of str to (n, ...) array
        ``mesh.vertex_attributes`` with one row per vertex, ``"uv"`` the texture
        coordinates of a textured mesh, ``"vertex_colors"`` the (n, 4) uint8 RGBA colours of
        a mesh coloured per vertex.

    Raises
    ------
    TypeError
        ``mesh`` is not a Trimesh (a Scene: ``scene.to_mesh()`` joins its geometry).
    """
    trimesh = require("trimesh")
    if not isinstance(mesh, trimesh.Trimesh):
        hint = ": scene.to_mesh() joins its geometry into one" if isinstance(mesh, trimesh.Scene) else ""
        raise TypeError(f"expected a trimesh.Trimesh, got {type(mesh).__name__}{hint}")
    V = np.array(mesh.vertices, dtype=np.float64)
    F = np.array(mesh.faces, dtype=np.int64)
    data = {k: np.asarray(v) for k, v in mesh.vertex_attributes.items() if len(v) == len(V)}
    uv = getattr(mesh.visual, "uv", None)
    if mesh.visual.kind == "texture" and uv is not None and len(uv) == len(V):
        data[UV] = np.asarray(uv, dtype=np.float64)
    elif mesh.visual.kind == "vertex":
        data[COLORS] = np.asarray(mesh.visual.vertex_colors)
    return V, F, data


def to_trimesh(V, F, data=None, *, material=None):
    """A :class:`trimesh.Trimesh` of arrays, as they are (trimesh's processing, which merges
    vertices, is left to the caller).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    data : dict of str to (n, ...) array, optional
        Per-vertex data: ``"uv"`` becomes the texture coordinates (with ``material``),
        ``"vertex_colors"`` the vertex colours, the rest ``vertex_attributes``.
    material : trimesh.visual.material.Material, optional
        The texture of the texture coordinates.

    Returns
    -------
    trimesh.Trimesh
    """
    trimesh = require("trimesh")
    data = dict(data or {})
    uv, colors = data.pop(UV, None), data.pop(COLORS, None)
    if uv is not None:
        visual = trimesh.visual.TextureVisuals(uv=uv, material=material)
    elif colors is not None:
        visual = trimesh.visual.ColorVisuals(vertex_colors=colors)
    else:
        visual = None
    return trimesh.Trimesh(V, F, visual=visual, vertex_attributes=data, process=False)


def weld_seams(V, F, data):
    """Vertices at the same position merged into one, as trimesh splits them along the
    seams of a texture (a textured OBJ of a closed bunny loaded by trimesh has 179
    boundary loops, 5 read by qcremesh).

    Parameters
    ----------
    V : (n, 3) float
    F : (m, 3) int
    data : dict of str to (n, ...) array

    Returns
    -------
    V : (k, 3) float
    F : (m, 3) int64
    data : dict
        The arrays whose copies of each merged vertex agree (the texture coordinates along
        the seams do not).
    dropped : list of str
        The names of the others.
    """
    unique, first, inverse = np.unique(V, axis=0, return_index=True, return_inverse=True)
    inverse = inverse.reshape(-1)
    if len(unique) == len(V):
        return V, np.asarray(F, dtype=np.int64), data, []
    kept, dropped = {}, []
    for name, values in data.items():
        values = np.asarray(values)
        if np.array_equal(values, values[first][inverse]):
            kept[name] = values[first]
        else:
            dropped.append(name)
    return V[first], inverse[np.asarray(F)], kept, dropped


def remesh_trimesh(mesh, faces=None, *, weld=True, **options):
    """:func:`qcremesh.remesh` of a :class:`trimesh.Trimesh`.

    Parameters
    ----------
    mesh : trimesh.Trimesh
    faces : int, optional
        Face count wanted (default: the input's).
    weld : bool
        Merge the vertices at the same position first (:func:`weld_seams`): trimesh
        splits them along a texture's seams, which would stay boundaries of the remesh.
        The per-vertex data that differ across a seam (the texture coordinates) are then
        left out, with a warning; ``weld=False`` keeps the seams and the texture.
    **options
        The keyword arguments of :func:`qcremesh.remesh` (``seed``, ``levels``,
        ``sizing``, ``creases``, ...), but ``data``: the mesh's own is carried.

    Returns
    -------
    trimesh.Trimesh
        The remeshed surface, with the input's vertex attributes, texture coordinates
        (and material) and vertex colours interpolated at its vertices; the numbers of the
        run (:attr:`qcremesh.RemeshResult.stats`) in ``metadata["qcremesh"]``.
    """
    if "data" in options:
        raise TypeError("remesh_trimesh carries the mesh's own per-vertex data; data= is not taken")
    V, F, data = from_trimesh(mesh)
    if weld:
        V, F, data, dropped = weld_seams(V, F, data)
        if dropped:
            names = ", ".join(dropped)
            warnings.warn(
                f"remesh_trimesh merged the vertices at the same position (a texture's seams); {names} differ "
                f"across them and are left out (weld=False keeps the seams, as boundaries, and {names})",
                stacklevel=2,
            )
    result = remesh(V, F, faces, data=data, **({} if weld else {"weld_seams": False}) | options)
    material = getattr(mesh.visual, "material", None) if UV in data else None
    out = to_trimesh(result.V, result.F, result.data, material=material)
    out.metadata["qcremesh"] = dict(result.stats)
    return out
