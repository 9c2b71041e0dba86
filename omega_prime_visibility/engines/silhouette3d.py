"""The exact 3D reference for box scenes: silhouettes in a central projection, measured as solid angle.

Two disjoint convex bodies are met in the same order along every direction from an eye point that sees both (a
plane separates them), so the directions along which a box target is the first thing hit are its silhouette
minus the silhouettes of the boxes in front of it. Directions over the full sphere are split into the six faces
of a cube around the eye; on each face a box's directions form a convex polygon (the central projection of the
box clipped to the face's pyramid, whose vertices are the box's corners inside the pyramid, the crossings of its
edges with the pyramid's four planes, and the pyramid's edges where they pierce the box). Polygons are
subtracted with shapely and measured exactly (each planar triangle from the face's centre is a spherical
triangle, Van Oosterom and Strackee's formula).

What is exact and what is not:

- box silhouettes, their order and the horizontal field of view (half-planes on each face) are exact to
  floating point;
- the vertical field of view bounds directions by elevation, whose limits are cones: they are drawn as polygons
  of :data:`CURVE_POINTS` vertices per face (error below 1e-6 of a face's solid angle);
- the range is exact where every box lies wholly within it (no effect) or wholly beyond it (not visible); a
  viewpoint whose range cuts a box is computed by the default ray engine instead (``raycast3d``, within its
  documented sampling error), so a frame is never refused (:func:`box_visibility` itself raises
  :class:`RangeCutsBox` there);
- overlapping boxes are ordered by one direction of their common silhouette (exact only for disjoint boxes).

Static occluders are not boxes: this engine refuses them (the ray engine handles them).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import shapely

from ..inputs.objects import FrameObjects
from ..inputs.statics import StaticOccluders
from ..threed.boxes import EDGES, contains, corners, farthest_distance, frames, nearest_distance, ray_entries
from . import Observation, Viewpoint, get_engine, group_pairs
from .observe3d import eye_and_view, observation, own_body

CURVE_POINTS = 2048
"""Vertices of the polygon standing for an elevation limit on one cube face."""
MIN_SOLID_ANGLE = 1e-13
"""Steradians; smaller pieces of a silhouette count as empty."""

_UP = np.array([0.0, 0.0, 1.0])
# (forward, u, v) of the six cube faces; the side faces have v = up so elevation limits are curves v = f(u)
FACES = np.array(
    [
        [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
        [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
        [[0, 0, -1], [1, 0, 0], [0, 1, 0]],
    ],
    dtype=np.float64,
)
_SQUARE = shapely.box(-1.0, -1.0, 1.0, 1.0)
_CORNERS_UV = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]], dtype=np.float64)


def ring_solid_angle(uv: np.ndarray) -> float:
    """Signed solid angle (steradians) of the closed ring ``uv`` (shape (k, 2), on a face at distance 1).

    >>> round(ring_solid_angle(np.array([[-1.0, -1.0], [1, -1], [1, 1], [-1, 1]])) / (4 * math.pi / 6), 12)
    1.0
    """
    u0, v0 = uv[:, 0], uv[:, 1]
    u1, v1 = np.roll(u0, -1), np.roll(v0, -1)
    triple = u0 * v1 - v0 * u1
    nb, nc = np.sqrt(u0 * u0 + v0 * v0 + 1), np.sqrt(u1 * u1 + v1 * v1 + 1)
    return float(2 * np.arctan2(triple, nb * nc + nb + nc + u0 * u1 + v0 * v1 + 1).sum())


def solid_angle(geometry: shapely.Geometry | None) -> float:
    """Solid angle (steradians) of a polygonal shapely geometry drawn on a cube face (holes subtracted)."""
    if geometry is None or geometry.is_empty:
        return 0.0
    total = 0.0
    for part in shapely.get_parts(geometry):
        if isinstance(part, shapely.Polygon):
            total += abs(ring_solid_angle(np.asarray(part.exterior.coords)[:-1]))
            total -= sum(abs(ring_solid_angle(np.asarray(r.coords)[:-1])) for r in part.interiors)
        elif isinstance(part, shapely.GeometryCollection):
            total += solid_angle(part)
    return total


def silhouettes(box_corners: np.ndarray, boxes: np.ndarray, eye: np.ndarray) -> list[list[shapely.Polygon | None]]:
    """``out[f][i]``: the directions of box ``i`` on cube face ``f`` as a convex polygon in face coordinates
    (None where the box is not seen through that face). ``box_corners`` is :func:`~..boxes3d.corners` of
    ``boxes``; the eye must lie outside every box given."""
    rel = box_corners - eye  # (n, 8, 3)
    centre, rot, half = frames(boxes)
    n = len(boxes)
    out: list[list[shapely.Polygon | None]] = []
    for forward, eu, ev in FACES:
        d, u, v = rel @ forward, rel @ eu, rel @ ev  # (n, 8)
        tol = 1e-12 * np.maximum(np.abs(d), 1.0)
        inside = (d > 0) & (np.abs(u) <= d + tol) & (np.abs(v) <= d + tol)
        points: list[list[np.ndarray]] = [[np.stack([u[i, inside[i]], v[i, inside[i]]], 1) / d[i, inside[i], None]]
                                          for i in range(n)]  # fmt: skip
        a, b = EDGES[:, 0], EDGES[:, 1]
        for g in (d - u, d + u, d - v, d + v):
            ga, gb = g[:, a], g[:, b]
            cross = ga * gb < 0
            t = np.where(cross, ga / np.where(cross, ga - gb, 1.0), 0.0)
            dd = d[:, a] + t * (d[:, b] - d[:, a])
            uu = u[:, a] + t * (u[:, b] - u[:, a])
            vv = v[:, a] + t * (v[:, b] - v[:, a])
            ok = cross & (dd > 0) & (np.abs(uu) <= dd * (1 + 1e-9)) & (np.abs(vv) <= dd * (1 + 1e-9))
            for i in np.flatnonzero(ok.any(axis=1)):
                k = ok[i]
                points[i].append(np.clip(np.stack([uu[i, k], vv[i, k]], 1) / dd[i, k, None], -1.0, 1.0))
        directions = forward + _CORNERS_UV[:, :1] * eu + _CORNERS_UV[:, 1:] * ev
        for c in range(4):
            hit = ray_entries(eye, np.repeat(directions[c : c + 1], n, 0), centre, rot, half, np.arange(n))
            for i in np.flatnonzero(np.isfinite(hit)):
                points[i].append(_CORNERS_UV[c : c + 1])
        face = []
        for i in range(n):
            pts = np.concatenate(points[i])
            hull = shapely.MultiPoint(pts).convex_hull if len(pts) >= 3 else None
            face.append(hull if isinstance(hull, shapely.Polygon) and solid_angle(hull) > MIN_SOLID_ANGLE else None)
        out.append(face)
    return out


def _clip(polygon: np.ndarray, c: np.ndarray) -> np.ndarray:
    """Convex ``polygon`` (k, 2) clipped to ``c[0] + c[1] u + c[2] v >= 0``."""
    out = []
    k = len(polygon)
    for i in range(k):
        p, q = polygon[i], polygon[(i + 1) % k]
        fp, fq = c[0] + c[1] * p[0] + c[2] * p[1], c[0] + c[1] * q[0] + c[2] * q[1]
        if fp >= 0:
            out.append(p)
        if (fp >= 0) != (fq >= 0):
            out.append(p + (q - p) * (fp / (fp - fq)))
    return np.array(out).reshape(-1, 2)


def _half_space(normal: np.ndarray, face: np.ndarray) -> shapely.Geometry:
    """Directions ``p`` with ``normal . p >= 0`` on a cube face."""
    square = np.array([[-1.0, -1.0], [1, -1], [1, 1], [-1, 1]])
    clipped = _clip(square, np.array([normal @ face[0], normal @ face[1], normal @ face[2]]))
    return shapely.Polygon(clipped) if len(clipped) >= 3 else shapely.Polygon()


def _elevation_above(limit: float, f: int) -> shapely.Geometry:
    """Directions of elevation >= ``limit`` (radians) on cube face ``f``, the curved limit as a polygon."""
    if limit <= -math.pi / 2:
        return _SQUARE
    if f < 4:  # side face: elevation = atan(v / sqrt(1 + u^2))
        u = np.linspace(-1.0, 1.0, CURVE_POINTS)
        v = np.clip(math.tan(limit) * np.sqrt(1 + u * u), -2.0, 2.0)
        return shapely.Polygon(np.column_stack([np.r_[u, 1, -1], np.r_[v, 3, 3]])).intersection(_SQUARE)
    up = f == 4  # top face: elevation = ±atan(1 / r), r = |(u, v)|
    if (up and limit <= 0) or (not up and limit <= -math.pi / 2):
        return _SQUARE
    if not up and limit >= 0:
        return shapely.Polygon()
    angle = np.linspace(0, 2 * math.pi, 4 * CURVE_POINTS, endpoint=False)
    disk = shapely.Polygon(np.column_stack([np.cos(angle), np.sin(angle)]) / abs(math.tan(limit)))
    return _SQUARE.intersection(disk) if up else _SQUARE.difference(disk)


def view_regions(heading: float, half_fov: float, low: float, high: float) -> list[shapely.Geometry | None]:
    """Per cube face, the directions in view as a polygon in face coordinates (None: the whole face)."""
    out: list[shapely.Geometry | None] = []
    left = np.array([math.cos(heading + half_fov), math.sin(heading + half_fov), 0.0])
    right = np.array([math.cos(heading - half_fov), math.sin(heading - half_fov), 0.0])
    n_left, n_right = np.cross(left, _UP), np.cross(_UP, right)  # p . n >= 0 on the inner side of each limit
    for f, face in enumerate(FACES):
        region = None
        if half_fov < math.pi:
            a, b = _half_space(n_left, face), _half_space(n_right, face)
            region = a.intersection(b) if half_fov <= math.pi / 2 else a.union(b)
        if low > -math.pi / 2:
            above = _elevation_above(low, f)
            region = above if region is None else region.intersection(above)
        if high < math.pi / 2:
            below = _SQUARE.difference(_elevation_above(high, f))
            region = below if region is None else region.intersection(below)
        out.append(region)
    return out


def box_visibility(
    boxes: np.ndarray,
    eye: np.ndarray,
    *,
    transparent: np.ndarray | None = None,
    view: tuple[float, float, float, float] = (0.0, math.pi, -math.pi / 2, math.pi / 2),
    max_range: float = math.inf,
) -> tuple[np.ndarray, np.ndarray, list[list[int]], np.ndarray, np.ndarray]:
    """Exact visible and total solid angle of every box seen from ``eye``.

    Parameters
    ----------
    boxes : ndarray, shape (n, 9)
        Oriented boxes (:mod:`..threed.boxes`), metres and radians.
    eye : ndarray, shape (3,)
        The eye point, metres.
    transparent : ndarray of bool, shape (n,), optional
        Boxes that neither block nor are measured (the observer's own body); boxes containing the eye are added.
    view : (heading, half horizontal fov, lowest elevation, highest elevation)
        Radians, as :func:`..threed.boxes.view_limits` returns.
    max_range : float
        Metres; see the module docstring.

    Returns
    -------
    visible : ndarray, shape (n,)
        Steradians of directions along which the box is the first thing hit, within the view.
    extent : ndarray, shape (n,)
        Steradians of directions that hit the box at all.
    occluders : list of lists of int
        Per box, the boxes in front of it along some direction of its silhouette, ascending.
    transparent : ndarray of bool, shape (n,)
        The transparent boxes (given, or containing the eye).
    in_fov : ndarray, shape (n,)
        Steradians of the box's directions inside the view, occlusion ignored.

    Examples
    --------
    >>> car = [10.0, 0, 0.75, 4, 2, 1.5, 0, 0, 0]
    >>> truck = [20.0, 0, 2.0, 8, 2.5, 4.0, 0, 0, 0]  # 4 m high behind a 1.5 m car
    >>> visible, extent, occ, _, _ = box_visibility(np.array([car, truck]), np.array([0.0, 0, 1.25]))
    >>> round(float(visible[1] / extent[1]), 3), occ
    (0.559, [[], [0]])
    """
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 9)
    eye = np.asarray(eye, dtype=np.float64)
    n = len(boxes)
    skip = contains(boxes, eye) if transparent is None else np.asarray(transparent, bool) | contains(boxes, eye)
    solid = np.flatnonzero(~skip)
    visible, extent, in_fov = np.zeros(n), np.zeros(n), np.zeros(n)
    occluders: list[list[int]] = [[] for _ in range(n)]
    if len(solid) == 0:
        return visible, extent, occluders, skip, in_fov
    sub = boxes[solid]
    near, far = nearest_distance(sub, eye), farthest_distance(sub, eye)
    cut = (near <= max_range) & (far > max_range)
    if cut.any():
        raise RangeCutsBox(
            f"the range of {max_range} m cuts box(es) {solid[cut].tolist()}: the silhouette engine measures only "
            "boxes wholly within or wholly beyond the range; use the ray engine"
        )
    sil = silhouettes(corners(sub), sub, eye)
    regions = view_regions(*view)
    centre, rot, half = frames(sub)
    front: dict[tuple[int, int], bool] = {}  # (i, j): box j is in front of box i where both are seen

    def in_front(i: int, j: int, overlap: shapely.Geometry, face: np.ndarray) -> bool:
        if (i, j) not in front:
            p = overlap.representative_point()
            direction = face[0] + p.x * face[1] + p.y * face[2]
            t = ray_entries(eye, np.stack([direction, direction]), centre, rot, half, np.array([i, j]))
            if not np.isfinite(t).all():  # a sliver of an overlap: fall back on the nearest points
                t = np.array([near[i], near[j]])
            front[(i, j)], front[(j, i)] = bool(t[1] < t[0]), bool(t[0] < t[1])
        return front[(i, j)]

    for f, face in enumerate(FACES):
        polys = sil[f]
        seen = [i for i in range(len(solid)) if polys[i] is not None]
        for i in seen:
            extent[solid[i]] += solid_angle(polys[i])
            seen_part = polys[i] if regions[f] is None else polys[i].intersection(regions[f])
            in_fov[solid[i]] += solid_angle(seen_part)
            if near[i] > max_range or seen_part.is_empty:
                continue
            part = polys[i]
            blockers = []
            for j in seen:
                if j == i or not polys[i].intersects(polys[j]):
                    continue
                overlap = polys[i].intersection(polys[j])
                if solid_angle(overlap) > MIN_SOLID_ANGLE and in_front(i, j, overlap, face):
                    blockers.append(polys[j])
                    occluders[solid[i]].append(int(solid[j]))
            if blockers:
                part = part.difference(shapely.union_all(blockers))
            if regions[f] is not None:
                part = part.intersection(regions[f])
            visible[solid[i]] += solid_angle(part)
    return visible, extent, [sorted(set(o)) for o in occluders], skip, in_fov


class RangeCutsBox(ValueError):
    """A sensor's range cuts a box: part of it lies within range, part beyond, and its visible part is no longer
    bounded by planes, so :func:`box_visibility` cannot measure it exactly."""


class SilhouetteEngine:
    """The exact box engine (see the module docstring); ``measure = "steradians"``."""

    name: ClassVar[str] = "silhouette3d"
    measure: ClassVar[str] = "steradians"

    def __init__(self, statics: StaticOccluders) -> None:
        solids = getattr(statics, "solids", None)
        if statics.n_sources or (solids is not None and solids.n_sources):
            raise ValueError("the silhouette3d engine handles box scenes only; use raycast3d with static occluders")
        self.statics = statics
        self._rays = None  # the ray engine, for viewpoints whose range cuts a box (built when first needed)

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; needs the frame's 3D boxes (``objects.boxes3d``)."""
        boxes = getattr(objects, "boxes3d", None)
        if boxes is None:
            raise ValueError("3D engines need the 3D boxes of the objects: load them with three_d=True (mode='3d')")
        out = []
        n = len(objects)
        for view in viewpoints:
            eye, limits = eye_and_view(view, boxes)
            try:
                visible, extent, occ, skip, in_fov = box_visibility(
                    boxes, eye, transparent=own_body(view, n), view=limits, max_range=view.range
                )
            except RangeCutsBox:  # never refuse the frame: this viewpoint is ray-cast (the default setting)
                out.append(self._ray_engine().observe(objects, [view])[0])
                continue
            key = np.repeat(np.arange(n), [len(o) for o in occ])
            value = np.array([j for o in occ for j in o], dtype=np.int64)
            offsets, occluders = group_pairs(key, value, n)
            empty = np.zeros(n + 1, dtype=np.int64)
            in_view = np.where(nearest_distance(boxes, eye) <= view.range, in_fov, 0.0)
            none = np.zeros(0, np.int64)
            out.append(observation(view, visible, extent, offsets, occluders, empty, none, skip, in_view, in_fov))
        return out

    def _ray_engine(self):
        """The default ray engine for these (empty) statics, built once."""
        if self._rays is None:
            self._rays = get_engine("raycast3d")(self.statics)
        return self._rays
