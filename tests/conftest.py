import importlib.util
from pathlib import Path

import numpy as np
import pytest
from scipy.spatial import Delaunay

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "data"
SHARED = ROOT.parent / "shared" / "data"

# The benchmark's synthetic CAD-like surfaces (open_box, cube, plateau, mesa, box,
# polar_disk), shared with the tests.
_spec = importlib.util.spec_from_file_location("shapes", ROOT / "benchmarks" / "shapes.py")
shapes = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(shapes)

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


def grid_cells(cells):
    """Unit grid cells (k, 2) of integer corners, each split into two counter-clockwise
    triangles along the same diagonal, as a range map is triangulated: (V (n, 3) with
    z = 0, F)."""
    cells = np.asarray(cells)
    corners = np.concatenate([cells, cells + [1, 0], cells + [1, 1], cells + [0, 1]])
    points, index = np.unique(corners, axis=0, return_inverse=True)
    a, b, c, d = index.reshape(4, -1)
    F = np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])
    return np.column_stack([points, np.zeros(len(points))]).astype(np.float64), F


def strip_disk(length, k=10, seed=0):
    """A strip [0, length] x [0, 1] of k x (k length) jittered grid cells, two triangles
    each, bent along its length (z = 0.3 sin x): a disk whose conformal map to the unit
    disk crowds both ends by about exp(-pi length / 2)."""
    n = int(round(k * length))
    x, y = np.meshgrid(np.linspace(0.0, length, n + 1), np.linspace(0.0, 1.0, k + 1))
    P = np.column_stack([x.ravel(), y.ravel()])
    inside = (P > 0).all(1) & (P[:, 0] < length) & (P[:, 1] < 1)
    P[inside] += 0.3 / k * np.random.default_rng(seed).uniform(-1, 1, (inside.sum(), 2))
    i, j = np.meshgrid(np.arange(n), np.arange(k))
    a = (j * (n + 1) + i).ravel()
    F = np.concatenate([np.column_stack([a, a + 1, a + n + 2]), np.column_stack([a, a + n + 2, a + n + 1])])
    return np.column_stack([P, 0.3 * np.sin(P[:, 0])]), F


def flap_disk(width=0.02, length=0.2, step=0.01):
    """The unit square with a flap ``width`` wide and ``length`` long out of the middle of
    its right side (a scan's border with a tongue), meshed on a grid of cells ``step``
    wide, two triangles each, bent (z = 0.2 sin 3x sin 3y): a disk whose conformal map
    crowds the flap's boundary by about exp(-pi length / width) at its tip."""
    x, y = np.arange(0.0, 1 + length + step / 2, step), np.arange(0.0, 1 + step / 2, step)
    P = np.stack(np.meshgrid(x, y), -1).reshape(-1, 2)
    i, j = (g.ravel() for g in np.meshgrid(np.arange(len(x) - 1), np.arange(len(y) - 1)))
    a = j * len(x) + i
    F = np.concatenate([np.column_stack([a, a + 1, a + len(x) + 1]), np.column_stack([a, a + len(x) + 1, a + len(x)])])
    on = (P[:, 0] <= 1 + 1e-9) | (np.abs(P[:, 1] - 0.5) <= width / 2 + 1e-9)
    F = F[on[F].all(1)]
    used, F = np.unique(F, return_inverse=True)
    P = P[used]
    return np.column_stack([P, 0.2 * np.sin(3 * P[:, 0]) * np.sin(3 * P[:, 1])]), F.reshape(-1, 3)


def tube_disk(length, k=16, seed=0):
    """A tube of radius 1 and the given length, open at z = 0 and closed at the other end
    by a hemisphere: rings of k vertices (the tube's rings 2 pi / k apart, each turned by
    half a step, jittered), the cap's rings converging to one pole. A disk whose
    conformal map puts the far end within about exp(-length) of the centre."""
    h = 2 * np.pi / k
    rings = [(z, 1.0) for z in np.linspace(0.0, length, max(int(round(length / h)), 1) + 1)]
    caps = max(int(round(np.pi / 2 / h)), 2)
    rings += [(length + np.sin(a), np.cos(a)) for a in np.pi / 2 * np.arange(1, caps) / caps]
    t = 2 * np.pi * np.arange(k) / k
    turn = t + h / 2 * np.arange(len(rings))[:, None]
    P = np.concatenate(
        [np.column_stack([r * np.cos(s), r * np.sin(s), np.full(k, z)]) for s, (z, r) in zip(turn, rings)]
    )
    P[k:] += 0.05 * h * np.random.default_rng(seed).standard_normal((len(P) - k, 3))
    a = np.arange(k)
    b = (a + 1) % k
    o = k * np.arange(len(rings) - 1)[:, None]  # first vertex of each ring but the last
    F = np.concatenate(
        [
            np.stack([o + a, o + b, o + k + a], -1).reshape(-1, 3),
            np.stack([o + b, o + k + b, o + k + a], -1).reshape(-1, 3),
            np.column_stack([o[-1] + k + a, o[-1] + k + b, np.full(k, len(P))]),
        ]
    )
    return np.concatenate([P, [[0.0, 0.0, length + 1.0]]]), F


def star_disk(tips=5, inner=0.45, k=40, seed=0):
    """A planar star polygon (``tips`` points at radius 1, the notches between them at
    radius ``inner``) meshed irregularly: the Delaunay triangulation of a jittered grid of
    the unit disk (``k`` boundary points per tip) pushed out along each ray onto the
    polygon, so its triangles stretch towards the tips. Vertices (n, 3) at z = 0 and
    counter-clockwise faces; the polygon's corners are vertices."""
    m = 2 * tips
    corners_angle = np.pi * np.arange(m) / tips
    corners = np.where(np.arange(m) % 2 == 0, 1.0, inner)[:, None] * np.column_stack(
        [np.cos(corners_angle), np.sin(corners_angle)]
    )
    b = tips * k
    t = 2 * np.pi * np.arange(b) / b
    uv, _ = grid_disk(int(np.sqrt(b * b / (4 * np.pi))), jitter=0.3, seed=seed)
    uv = 2 * uv - 1
    uv = uv[np.linalg.norm(uv, axis=1) < 1 - 1.0 / np.sqrt(b)]
    uv = np.concatenate([np.column_stack([np.cos(t), np.sin(t)]), uv])
    F = Delaunay(uv).simplices.astype(np.int64)
    a, c = uv[F[:, 1]] - uv[F[:, 0]], uv[F[:, 2]] - uv[F[:, 0]]
    cw = a[:, 0] * c[:, 1] - a[:, 1] * c[:, 0] < 0
    F[cw] = F[cw][:, ::-1]
    # radius of the polygon along each ray: the edge between the corners on either side
    phi = np.mod(np.arctan2(uv[:, 1], uv[:, 0]), 2 * np.pi)
    i = np.minimum((phi / (np.pi / tips)).astype(int), m - 1)
    P, Q = corners[i], corners[(i + 1) % m]
    d = np.column_stack([np.cos(phi), np.sin(phi)])
    edge = Q - P
    radius = (P[:, 0] * edge[:, 1] - P[:, 1] * edge[:, 0]) / (d[:, 0] * edge[:, 1] - d[:, 1] * edge[:, 0])
    return np.column_stack([uv * radius[:, None], np.zeros(len(uv))]), F


def delaunay_excess(uv, F):
    """Largest excess over pi of the two angles opposite an interior edge of a planar
    triangulation (<= 0 where it is Delaunay)."""
    from qcremesh.mesh.topology import half_edges, twin_half_edges

    H = half_edges(F)
    opposite = np.concatenate([F[:, 2], F[:, 0], F[:, 1]])
    i, j = twin_half_edges(F)

    def angle(apex, p, q):
        u, v = uv[p] - uv[apex], uv[q] - uv[apex]
        return np.arctan2(np.abs(u[:, 0] * v[:, 1] - u[:, 1] * v[:, 0]), (u * v).sum(1))

    return (angle(opposite[i], H[i, 0], H[i, 1]) + angle(opposite[j], H[i, 1], H[i, 0]) - np.pi).max()


def split_vertex(V, F, v):
    """Split interior vertex v into two at the same point (the inverse of collapsing an
    edge of zero length): half of its fan goes to the new vertex, and two needles join
    them."""
    faces = np.flatnonzero(np.any(F == v, axis=1))
    nxt = {}
    for f in faces:
        k = int(np.flatnonzero(F[f] == v)[0])
        nxt[F[f, (k + 1) % 3]] = (F[f, (k + 2) % 3], f)
    ring, fans = [next(iter(nxt))], []
    while len(ring) <= len(nxt):
        r, f = nxt[ring[-1]]
        ring.append(r)
        fans.append(f)
    s = len(fans) // 2
    w = len(V)
    F = F.copy()
    for f in fans[s:]:
        F[f][F[f] == v] = w
    needles = [[v, ring[s], w], [w, ring[0], v]]
    return np.concatenate([V, V[v : v + 1]]), np.concatenate([F, needles])


def sphere_mesh(n=1500, seed=0):
    """The convex hull of n random points of the unit sphere: a closed surface of genus
    0 with irregular triangles, faces turned outwards."""
    from scipy.spatial import ConvexHull

    P = np.random.default_rng(seed).standard_normal((n, 3))
    P /= np.linalg.norm(P, axis=1)[:, None]
    F = ConvexHull(P).simplices.astype(np.int64)
    outward = (np.cross(P[F[:, 1]] - P[F[:, 0]], P[F[:, 2]] - P[F[:, 0]]) * P[F].mean(1)).sum(1) > 0
    F[~outward] = F[~outward][:, ::-1]
    return P, F


def torus_mesh(k=24, seed=0, seam=False):
    """A torus (radii 2 and 0.7) of k x k/2 grid cells, two triangles each: closed, genus 1.
    With ``seam``, the ring of vertices at angle 0 around the axis is written twice, once
    for the cells on each side of it (as a file split along its texture seam): a tube
    whose two rims lie at the same points."""
    rings = k + 1 if seam else k
    a, b = np.meshgrid(2 * np.pi * np.arange(rings) / k, 2 * np.pi * np.arange(k // 2) / (k // 2), indexing="ij")
    a, b = a.ravel(), b.ravel()
    V = np.column_stack([(2 + 0.7 * np.cos(b)) * np.cos(a), (2 + 0.7 * np.cos(b)) * np.sin(a), 0.7 * np.sin(b)])
    i, j = np.meshgrid(np.arange(k), np.arange(k // 2), indexing="ij")
    idx = lambda i, j: (i % rings) * (k // 2) + j % (k // 2)  # noqa: E731
    q = [idx(i, j), idx(i + 1, j), idx(i + 1, j + 1), idx(i, j + 1)]
    F = np.concatenate([np.column_stack([q[0].ravel(), q[1].ravel(), q[2].ravel()]),
                        np.column_stack([q[0].ravel(), q[2].ravel(), q[3].ravel()])])
    return V, F


def uv_sphere(nu=24, nv=12):
    """A unit sphere as a (nu + 1) x (nv + 1) grid of vertices in longitude and
    latitude, two triangles per cell, every seam written twice (as a textured mesh is):
    the meridian at longitude 0 once per side, and each pole once per face there (whose
    fans are faces of zero area). A disk, on which the seams are boundary."""
    u, v = np.meshgrid(np.linspace(0, 2 * np.pi, nu + 1), np.linspace(0, np.pi, nv + 1), indexing="ij")
    u, v = u.ravel(), v.ravel()
    V = np.column_stack([np.sin(v) * np.cos(u), np.sin(v) * np.sin(u), np.cos(v)])
    idx = np.arange(len(V)).reshape(nu + 1, nv + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    return V, np.concatenate([np.column_stack([a, b, c]), np.column_stack([a, c, d])])


def cad_cylinder(sections=64, height=2.0, lid=True):
    """A closed cylinder of radius 1 tessellated as CAD exports do (and numbered as
    trimesh.creation.cylinder numbers it): each facet of its side two triangles as long
    as the cylinder, each cap a fan from its centre; faces turned outwards. Without its
    top cap (``lid``), a cup: a disk."""
    t = 2 * np.pi * np.arange(sections) / sections
    bottom = np.column_stack([np.cos(t), np.sin(t), np.full(sections, -height / 2)])
    top = bottom + [0, 0, height]
    # the bottom centre, the first facet's edge, the top centre, then each facet's edge
    ring = np.r_[1, 4 + 2 * np.arange(sections - 1)]
    V = np.zeros((2 * sections + 2, 3))
    V[[0, 3]] = [[0, 0, -height / 2], [0, 0, height / 2]]
    V[ring], V[ring + 1] = bottom, top
    b, c = ring, np.roll(ring, -1)
    F = np.concatenate(
        [
            np.column_stack([b, np.zeros(sections, dtype=np.int64), c]),
            np.column_stack([b, c, b + 1]),
            np.column_stack([b + 1, c, c + 1]),
            np.column_stack([b + 1, c + 1, np.full(sections, 3)]),
        ][: 4 if lid else 3]
    )
    used, F = np.unique(F, return_inverse=True)
    return V[used], F.reshape(-1, 3)


def uv_capsule(height=3.0, radius=0.3, sections=64, rings=32):
    """A closed capsule along z (a cylinder of ``height`` between two hemispheres of
    ``radius``) tessellated as revolved shapes are (as trimesh.creation.capsule): each
    hemisphere ``rings`` rings of ``sections`` vertices and a fan at its pole, the cylinder
    between them one band of 2 * ``sections`` triangles as long as it; faces turned
    outwards."""
    t = 2 * np.pi * np.arange(sections) / sections

    def ring(polar, z):
        r = radius * np.sin(polar)
        return np.column_stack([r * np.cos(t), r * np.sin(t), np.full(sections, z + radius * np.cos(polar))])

    polar = np.pi / 2 * np.arange(1, rings + 1) / rings  # from a pole to the equator
    top = [ring(a, height / 2) for a in polar]
    bottom = [ring(np.pi - a, -height / 2) for a in polar[::-1]]
    V = np.concatenate([[[0, 0, height / 2 + radius]]] + top + bottom + [[[0, 0, -height / 2 - radius]]])
    k = 2 * rings  # rings from top to bottom, ring i from vertex 1 + i * sections
    j = np.arange(sections)
    a = (1 + np.arange(k - 1)[:, None] * sections + j).ravel()
    b = (1 + np.arange(k - 1)[:, None] * sections + (j + 1) % sections).ravel()
    last = 1 + (k - 1) * sections
    F = np.concatenate(
        [
            np.column_stack([np.zeros(sections, dtype=np.int64), 1 + j, 1 + (j + 1) % sections]),
            np.column_stack([a, a + sections, b + sections]),
            np.column_stack([a, b + sections, b]),
            np.column_stack([np.full(sections, len(V) - 1), last + (j + 1) % sections, last + j]),
        ]
    )
    return V, F


def cad_trough(facets=40, length=5.0):
    """A quarter cylinder of radius 1 tessellated as CAD exports do: each facet two
    triangles as long as the cylinder."""
    u = np.linspace(0, np.pi / 2, facets)
    arc = np.column_stack([np.cos(u), np.sin(u), np.zeros(facets)])
    V = np.concatenate([arc, arc + [0, 0, length]])
    i = np.arange(facets - 1)
    F = np.concatenate([np.column_stack([i, i + 1, i + facets + 1]), np.column_stack([i, i + facets + 1, i + facets])])
    return V, F


def holed_disk(k=30, holes=((0.3, 0.3, 0.12), (0.7, 0.6, 0.15)), seed=0):
    """A jittered k x k grid of the unit square bent into a bump, with round holes (x, y,
    radius) cut out, their borders sampled on their circles at the grid's spacing: a
    surface of genus 0 with 1 + len(holes) boundary loops, counter-clockwise faces."""
    uv = grid_disk(k, jitter=0.3, seed=seed)[0]
    keep = np.ones(len(uv), dtype=bool)
    rims = []
    for x, y, r in holes:
        keep &= np.hypot(uv[:, 0] - x, uv[:, 1] - y) > r + 0.5 / k
        t = 2 * np.pi * np.arange(int(np.ceil(2 * np.pi * r * k))) / np.ceil(2 * np.pi * r * k)
        rims.append(np.column_stack([x + r * np.cos(t), y + r * np.sin(t)]))
    uv = np.concatenate([uv[keep]] + rims)
    F = Delaunay(uv).simplices.astype(np.int64)
    centre = uv[F].mean(1)
    inside = np.zeros(len(F), dtype=bool)
    for x, y, r in holes:
        inside |= np.hypot(centre[:, 0] - x, centre[:, 1] - y) < r
    F = F[~inside]
    a, b = uv[F[:, 1]] - uv[F[:, 0]], uv[F[:, 2]] - uv[F[:, 0]]
    cw = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0] < 0
    F[cw] = F[cw][:, ::-1]
    V = np.column_stack([uv, 0.3 * np.sin(np.pi * uv[:, 0]) * np.sin(np.pi * uv[:, 1])])
    return V, F


def holed_plate(k=30, holes=((0.25, 0.3, 0.12), (0.7, 0.3, 0.12), (0.5, 0.72, 0.14)), thickness=0.1):
    """A flat plate ``thickness`` thick with round holes through it (x, y, radius in the
    unit square, as :func:`holed_disk`): the planar triangulation of the square with
    the holes cut out on both faces, joined along every border by a wall of rows of
    quads about as high as the grid's spacing. Closed, of genus ``len(holes)``, faces
    turned outwards."""
    from qcremesh.mesh.topology import boundary_edges

    V, F = holed_disk(k, holes)
    n = len(V)
    rows = max(int(round(thickness * k)), 1)
    layers = [np.column_stack([V[:, :2], np.full(n, thickness * (0.5 - r / rows))]) for r in range(rows + 1)]
    a, b = boundary_edges(F).T
    walls = [
        np.concatenate([np.column_stack([b, a, a + n]), np.column_stack([b, a + n, b + n])]) + r * n
        for r in range(rows)
    ]
    bottom = F[:, ::-1] + rows * n
    used, F = np.unique(np.concatenate([F, bottom] + walls), return_inverse=True)
    return np.concatenate(layers)[used], F.reshape(-1, 3)
