"""Convex bodies in 3D: oriented boxes and upright prisms over convex footprints, in one padded layout.

The exact 3D engine (:mod:`..engines.silhouette3d`) works on convex polyhedra: an object's box, and every static
occluder raised to its height as prisms over convex parts of its footprint (a wall line is a prism of zero
thickness; a non-convex footprint, holes included, is cut into triangles merged back into convex parts, so the
parts tile it exactly). A body is its vertices, its edges and its faces; each face is a plane with an outward unit
normal and, where it has an area, its vertices in order.

Faces are padded to the same count per body (a pad is the plane ``0 . x <= 1``, always satisfied) so that ray
entries and containment are vectorised over bodies.

>>> import numpy as np, shapely
>>> wall = prisms_from_footprints([shapely.LineString([(0, 5), (10, 5)])], tops=[2.0], bases=[-1.0])
>>> len(wall), wall.source.tolist(), float(wall.vertices[:, 2].max())
(1, [0], 2.0)
>>> box = bodies_from_boxes(np.array([[10.0, 0, 0.75, 4, 2, 1.5, 0, 0, 0]]))
>>> entries(box.relative_to(np.array([0.0, 0, 1])), np.array([0]), np.array([[1.0, 0, 0]])).tolist()
[8.0]
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import shapely

from .boxes import EDGES, corners, frames

MAX_PART_VERTICES = 8
"""Vertices at most in one convex part of a footprint (triangles are merged up to this)."""

# the six faces of a box as corner numbers (corner k has signs _SIGNS[k] of boxes.py), and the box axis
# (0, 1, 2 for x, y, z) and side (-1, +1) each faces
_BOX_FACES = np.array([[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]])
_BOX_AXIS = np.array([0, 0, 1, 1, 2, 2])
_BOX_SIDE = np.array([-1.0, 1.0, -1.0, 1.0, -1.0, 1.0])


@dataclass(frozen=True, slots=True)
class ConvexBodies:
    """``n`` convex polyhedra.

    Attributes
    ----------
    vertices : ndarray, shape (v, 3)
        Metres.
    vertex_body : ndarray, shape (v,), int64
        The body of each vertex.
    edges : ndarray, shape (e, 2), int64
        Pairs of vertex numbers.
    edge_body : ndarray, shape (e,), int64
    normals : ndarray, shape (n, p, 3)
        Outward unit normals of each body's faces (pads: zero).
    offsets : ndarray, shape (n, p)
        ``c`` of each face's plane ``normal . x <= c`` (pads: 1).
    faces : ndarray, shape (n, p, k), int64
        Each face's vertices in order, -1 after the last (fewer than 3: a face without area, such as the end of
        a wall of zero thickness).
    source : ndarray, shape (n,), int64
        What each body stands for (an object's row, or a static occluder's position in the user's list).
    """

    vertices: np.ndarray
    vertex_body: np.ndarray
    edges: np.ndarray
    edge_body: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    faces: np.ndarray
    source: np.ndarray

    def __len__(self) -> int:
        return len(self.source)

    def relative_to(self, eye: np.ndarray) -> ConvexBodies:
        """The same bodies with the origin moved to ``eye`` (so that map coordinates keep their precision)."""
        eye = np.asarray(eye, dtype=np.float64)
        shift = np.einsum("npj,j->np", self.normals, eye)
        return ConvexBodies(
            self.vertices - eye, self.vertex_body, self.edges, self.edge_body, self.normals,
            self.offsets - shift, self.faces, self.source,
        )  # fmt: skip

    def take(self, keep: np.ndarray) -> ConvexBodies:
        """The bodies ``keep`` (ascending positions), renumbered 0, 1, ..."""
        keep = np.asarray(keep, dtype=np.int64)
        new = np.full(len(self), -1, dtype=np.int64)
        new[keep] = np.arange(len(keep))
        vmask = new[self.vertex_body] >= 0
        vnew = np.cumsum(vmask) - 1
        emask = new[self.edge_body] >= 0
        faces = self.faces[keep]
        faces = np.where(faces >= 0, vnew[np.maximum(faces, 0)], -1)
        return ConvexBodies(
            self.vertices[vmask], new[self.vertex_body[vmask]], vnew[self.edges[emask]], new[self.edge_body[emask]],
            self.normals[keep], self.offsets[keep], faces, self.source[keep],
        )  # fmt: skip

    def bounding_spheres(self) -> tuple[np.ndarray, np.ndarray]:
        """Centre (n, 3) and radius (n,) of a sphere around each body (centred on its mean vertex)."""
        count = np.bincount(self.vertex_body, minlength=len(self)).astype(np.float64)
        centre = np.stack([np.bincount(self.vertex_body, self.vertices[:, k], len(self)) for k in range(3)], 1)
        centre /= np.maximum(count, 1.0)[:, None]
        reach = np.linalg.norm(self.vertices - centre[self.vertex_body], axis=1)
        radius = np.zeros(len(self))
        np.maximum.at(radius, self.vertex_body, reach)
        return centre, radius


def entries(bodies: ConvexBodies, which: np.ndarray, directions: np.ndarray) -> np.ndarray:
    """Distance (in units of each direction's length) at which the ray from the origin along ``directions[i]``
    enters body ``which[i]``; 0 when the origin is inside it, inf when the ray misses it."""
    normals, offsets = bodies.normals[which], bodies.offsets[which]  # (m, p, 3), (m, p)
    nd = np.einsum("mpj,mj->mp", normals, directions)
    with np.errstate(divide="ignore", invalid="ignore"):
        t = offsets / nd
    t0 = np.where(nd < 0, t, 0.0).max(axis=1, initial=0.0)
    t1 = np.where(nd > 0, t, np.inf).min(axis=1, initial=np.inf)
    parallel_out = ((nd == 0) & (offsets < 0)).any(axis=1)
    return np.where((t0 <= t1) & ~parallel_out, t0, np.inf)


def containing_origin(bodies: ConvexBodies, tolerance: float = 1e-9) -> np.ndarray:
    """Which bodies contain or touch the origin (within ``tolerance`` metres), shape (n,) bool."""
    return (bodies.offsets >= -tolerance).all(axis=1)


def bodies_from_boxes(boxes: np.ndarray, source: np.ndarray | None = None) -> ConvexBodies:
    """The oriented boxes (shape (n, 9), :mod:`.boxes`) as convex bodies; ``source`` defaults to 0 .. n-1."""
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 9)
    n = len(boxes)
    frame = frames(boxes)
    centre, rot, half = frame
    vertices = corners(boxes, frame).reshape(-1, 3)
    axis = rot[:, :, _BOX_AXIS].transpose(0, 2, 1)  # (n, 6, 3): the box axis of each face
    normals = axis * _BOX_SIDE[None, :, None]
    offsets = np.einsum("npj,nj->np", normals, centre) + half[:, _BOX_AXIS]
    base = 8 * np.arange(n)
    return ConvexBodies(
        vertices, np.repeat(np.arange(n), 8), (EDGES[None] + base[:, None, None]).reshape(-1, 2),
        np.repeat(np.arange(n), 12), normals, offsets, _BOX_FACES[None] + base[:, None, None],
        np.arange(n, dtype=np.int64) if source is None else np.asarray(source, dtype=np.int64),
    )  # fmt: skip


def convex_parts(polygon: shapely.Polygon) -> list[np.ndarray]:
    """Convex polygons (counter-clockwise vertex arrays, shape (k, 2)) that tile ``polygon`` (holes honoured):
    the polygon itself when convex, else its constrained Delaunay triangles merged greedily along shared edges
    while the union stays convex and has at most :data:`MAX_PART_VERTICES` vertices.

    >>> l_shape = shapely.Polygon([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)])
    >>> parts = convex_parts(l_shape)
    >>> len(parts), sum(shapely.Polygon(p).area for p in parts)
    (2, 3.0)
    """
    polygon = shapely.normalize(shapely.simplify(polygon, 0.0))
    if not polygon.interiors and abs(polygon.convex_hull.area - polygon.area) <= 1e-12 * max(polygon.area, 1.0):
        return _fans(_ccw(polygon)) if polygon.area > 0 else []
    triangles = [t for t in shapely.get_parts(shapely.constrained_delaunay_triangles(polygon)) if t.area > 0]
    pieces: list[shapely.Polygon | None] = list(triangles)
    merged = True
    while merged:
        merged = False
        edge_owner: dict[tuple, int] = {}
        for i, piece in enumerate(pieces):
            if piece is None:
                continue
            ring = np.asarray(piece.exterior.coords)
            for a, b in itertools.pairwise(ring):
                key = tuple(sorted((tuple(a), tuple(b))))
                j = edge_owner.get(key)
                if j is None:
                    edge_owner[key] = i
                    continue
                union = shapely.simplify(pieces[j].union(piece), 0.0)  # type: ignore[union-attr]
                if (
                    isinstance(union, shapely.Polygon)
                    and abs(union.convex_hull.area - union.area) <= 1e-12 * max(union.area, 1.0)
                    and len(union.exterior.coords) - 1 <= MAX_PART_VERTICES
                ):
                    pieces[j], pieces[i] = union, None
                    merged = True
                    break
            if merged:
                break
    return [_ccw(p) for p in pieces if p is not None]


def _fans(ring: np.ndarray) -> list[np.ndarray]:
    """A convex counter-clockwise ring cut into fans from its first vertex of at most :data:`MAX_PART_VERTICES`
    vertices each (a round pole's 64-gon is 11 parts, so every body keeps a small number of faces)."""
    k = len(ring)
    if k <= MAX_PART_VERTICES:
        return [ring]
    step = MAX_PART_VERTICES - 2
    return [np.concatenate([ring[:1], ring[i : min(i + step + 1, k)]]) for i in range(1, k - 1, step)]


def _ccw(polygon: shapely.Polygon) -> np.ndarray:
    ring = np.asarray(shapely.orient_polygons(polygon).exterior.coords)[:-1]
    return ring


def prisms_from_footprints(
    geometries: Sequence[shapely.Geometry], tops: Sequence[float], bases: Sequence[float]
) -> ConvexBodies:
    """Footprints raised from ``bases`` to ``tops`` (z, metres, one per footprint) as convex prisms: polygons cut
    into convex parts (:func:`convex_parts`), each segment of a line a wall of zero thickness. ``source`` of each
    prism is the position of its footprint."""
    footprints: list[np.ndarray] = []
    source: list[int] = []
    for s, geometry in enumerate(geometries):
        for part in shapely.get_parts(geometry):
            if isinstance(part, shapely.Polygon):
                parts = convex_parts(part)
            elif isinstance(part, shapely.LineString | shapely.LinearRing):
                coords = np.asarray(part.coords)
                parts = [coords[i : i + 2] for i in range(len(coords) - 1) if (coords[i] != coords[i + 1]).any()]
            else:
                parts = []
            footprints.extend(parts)
            source.extend([s] * len(parts))
    tops = np.asarray(tops, dtype=np.float64)
    bases = np.asarray(bases, dtype=np.float64)
    return prisms(footprints, tops[source] if source else np.zeros(0), bases[source] if source else np.zeros(0), source)


def prisms(
    footprints: Sequence[np.ndarray], tops: np.ndarray, bases: np.ndarray, source: Sequence[int]
) -> ConvexBodies:
    """Upright prisms over convex counter-clockwise footprints (k >= 3 vertices) or segments (k = 2), from
    ``bases`` to ``tops`` (z, metres)."""
    n = len(footprints)
    sizes = [len(f) for f in footprints]
    p_max = max([k + 2 if k >= 3 else 6 for k in sizes], default=6)
    k_max = max([max(k, 4) for k in sizes], default=4)
    normals = np.zeros((n, p_max, 3))
    offsets = np.ones((n, p_max))
    faces = np.full((n, p_max, k_max), -1, dtype=np.int64)
    vertices, vertex_body, edge_list, edge_body = [], [], [], []
    at = 0
    for b, (xy, top, base) in enumerate(zip(footprints, tops, bases, strict=True)):
        k = len(xy)
        low = np.column_stack([xy, np.full(k, base)])
        high = np.column_stack([xy, np.full(k, top)])
        vertices.extend([low, high])
        vertex_body.append(np.full(2 * k, b))
        if k == 2:
            t = xy[1] - xy[0]
            t = t / np.linalg.norm(t)
            side = np.array([t[1], -t[0], 0.0])
            along = np.array([t[0], t[1], 0.0])
            a3 = low[0]
            plane_normals = [side, -side, -along, along, [0, 0, -1.0], [0, 0, 1.0]]
            plane_points = [a3, a3, a3, low[1], a3, high[0]]
            face_lists = [[0, 1, 3, 2], [0, 2, 3, 1], [0, 2], [1, 3], [0, 1], [2, 3]]
            edges = [[0, 1], [2, 3], [0, 2], [1, 3]]
        else:
            d = np.roll(xy, -1, axis=0) - xy
            length = np.linalg.norm(d, axis=1)
            side = np.column_stack([d[:, 1], -d[:, 0], np.zeros(k)]) / length[:, None]
            plane_normals = [*side, [0, 0, -1.0], [0, 0, 1.0]]
            plane_points = [*low, low[0], high[0]]
            j = np.arange(k)
            face_lists = [[i, (i + 1) % k, k + (i + 1) % k, k + i] for i in j] + [list(j[::-1]), list(k + j)]
            edges = [[i, (i + 1) % k] for i in j] + [[k + i, k + (i + 1) % k] for i in j] + [[i, k + i] for i in j]
        for p, (normal, point, face) in enumerate(zip(plane_normals, plane_points, face_lists, strict=True)):
            normals[b, p] = normal
            offsets[b, p] = float(np.dot(normal, point))
            faces[b, p, : len(face)] = np.asarray(face) + at
        edge_list.append(np.asarray(edges, dtype=np.int64) + at)
        edge_body.append(np.full(len(edges), b))
        at += 2 * k
    return ConvexBodies(
        np.concatenate(vertices) if vertices else np.zeros((0, 3)),
        np.concatenate(vertex_body).astype(np.int64) if vertex_body else np.zeros(0, np.int64),
        np.concatenate(edge_list) if edge_list else np.zeros((0, 2), np.int64),
        np.concatenate(edge_body).astype(np.int64) if edge_body else np.zeros(0, np.int64),
        normals, offsets, faces, np.asarray(source, dtype=np.int64).reshape(-1),
    )  # fmt: skip


def concatenate(first: ConvexBodies, second: ConvexBodies) -> ConvexBodies:
    """``first``'s bodies, then ``second``'s (numbered after them); faces padded to the larger layout."""
    p = max(first.normals.shape[1], second.normals.shape[1])
    k = max(first.faces.shape[2], second.faces.shape[2])

    def pad(b: ConvexBodies, shift: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        n, bp, bk = b.faces.shape
        normals = np.zeros((n, p, 3))
        normals[:, :bp] = b.normals
        offsets = np.ones((n, p))
        offsets[:, :bp] = b.offsets
        faces = np.full((n, p, k), -1, dtype=np.int64)
        faces[:, :bp, :bk] = np.where(b.faces >= 0, b.faces + shift, -1)
        return normals, offsets, faces

    v = len(first.vertices)
    n1, o1, f1 = pad(first, 0)
    n2, o2, f2 = pad(second, v)
    return ConvexBodies(
        np.concatenate([first.vertices, second.vertices]),
        np.concatenate([first.vertex_body, second.vertex_body + len(first)]),
        np.concatenate([first.edges, second.edges + v]),
        np.concatenate([first.edge_body, second.edge_body + len(first)]),
        np.concatenate([n1, n2]), np.concatenate([o1, o2]), np.concatenate([f1, f2]),
        np.concatenate([first.source, second.source]),
    )  # fmt: skip
