"""Plane geometry over ragged ring arrays.

All functions here are pure and vectorised over numpy arrays. Conventions used throughout the package:

- lengths in metres, angles in radians, measured counter-clockwise from the +x axis of the recording's frame;
- a set of polygon rings is stored *ragged*: ``coords`` of shape ``(m, 2)`` holds the vertices of all rings one
  after the other (first vertex not repeated at the end) and ``offsets`` of shape ``(n + 1,)`` says that ring ``i``
  is ``coords[offsets[i]:offsets[i + 1]]``;
- rings are oriented so that the material lies on the left of every directed edge (exterior rings
  counter-clockwise, interior rings clockwise).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
import shapely

from .kernels import segment_distance2

TWO_PI = 2.0 * np.pi
TOUCH_TOLERANCE = 1e-9  # metres: a body passing this near a viewpoint touches it (and is transparent to it)


@dataclass(frozen=True, slots=True)
class Rings:
    """Closed polygon rings as ragged arrays.

    Attributes
    ----------
    coords : ndarray, shape (m, 2), float64
        Vertices of all rings, ring after ring, in metres. The first vertex of a ring is not repeated at its end.
    offsets : ndarray, shape (n + 1,), int64
        Ring ``i`` is ``coords[offsets[i]:offsets[i + 1]]``; every ring has at least three vertices.
    """

    coords: np.ndarray
    offsets: np.ndarray

    def __len__(self) -> int:
        return len(self.offsets) - 1

    @property
    def sizes(self) -> np.ndarray:
        """Number of vertices of each ring, shape (n,)."""
        return np.diff(self.offsets)

    def ring(self, i: int) -> np.ndarray:
        """Vertices of ring ``i``, shape (k, 2)."""
        return self.coords[self.offsets[i] : self.offsets[i + 1]]

    def take(self, positions: np.ndarray) -> Rings:
        """The rings at ``positions`` (in that order) as a new ``Rings``."""
        positions = np.asarray(positions, dtype=np.int64)
        sizes = self.sizes[positions]
        offsets = np.zeros(len(positions) + 1, dtype=np.int64)
        np.cumsum(sizes, out=offsets[1:])
        vertex = np.repeat(self.offsets[positions] - offsets[:-1], sizes) + np.arange(offsets[-1])
        return Rings(self.coords[vertex], offsets)

    def slice(self, start: int, stop: int) -> Rings:
        """Rings ``start`` to ``stop - 1`` as a view-backed ``Rings``."""
        offsets = self.offsets[start : stop + 1]
        return Rings(self.coords[offsets[0] : offsets[-1]], offsets - offsets[0])

    @staticmethod
    def empty() -> Rings:
        return Rings(np.zeros((0, 2)), np.zeros(1, dtype=np.int64))


def ring_ids(offsets: np.ndarray) -> np.ndarray:
    """Ring number of every vertex, shape (m,)."""
    return np.repeat(np.arange(len(offsets) - 1), np.diff(offsets))


def next_vertex(offsets: np.ndarray) -> np.ndarray:
    """Index of the following vertex of the same ring (wrapping to the ring's first), shape (m,)."""
    nxt = np.arange(1, offsets[-1] + 1)
    ends = offsets[1:] - 1
    nxt[ends] = offsets[:-1]
    return nxt


def edges(rings: Rings) -> tuple[np.ndarray, np.ndarray]:
    """Start and end points of every edge, each shape (m, 2); edge ``j`` belongs to ring ``ring_ids[j]``."""
    return rings.coords, rings.coords[next_vertex(rings.offsets)]


def signed_area(rings: Rings) -> np.ndarray:
    """Signed area of each ring in square metres (positive when counter-clockwise), shape (n,).

    Taken relative to each ring's first vertex: with map coordinates (UTM: 5e5, 5e6 m) the shoelace terms of
    absolute coordinates are 1e12 m² and would drown the area of a thin ring, and its orientation with it.

    Examples
    --------
    >>> far = Rings(np.array([[5e5, 5.4e6], [5e5 + 2.0, 5.4e6], [5e5 + 1.0, 5.4e6 + 2.0**-20]]), np.array([0, 3]))
    >>> float(signed_area(far)[0]) == 2.0**-20  # a needle 2 m long, 1 µm high
    True
    """
    if len(rings) == 0:
        return np.zeros(0)
    a, b = edges(rings)
    first = np.repeat(rings.coords[rings.offsets[:-1]], rings.sizes, axis=0)
    a, b = a - first, b - first
    cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
    return 0.5 * np.add.reduceat(cross, rings.offsets[:-1]) if len(cross) else np.zeros(len(rings))


def orient(rings: Rings, counter_clockwise: np.ndarray | bool = True) -> Rings:
    """Reverse the rings whose orientation differs from the requested one.

    Parameters
    ----------
    rings : Rings
    counter_clockwise : bool or ndarray of bool, shape (n,)
        Wanted orientation of each ring.
    """
    want = np.broadcast_to(np.asarray(counter_clockwise, dtype=bool), (len(rings),))
    flip = (signed_area(rings) > 0) != want
    if not flip.any():
        return rings
    # vertex j of a flipped ring [s, e) takes vertex s + e - 1 - j; all rings at once
    sizes = rings.sizes
    start = rings.offsets[:-1]
    source = np.arange(rings.offsets[-1])
    vertex_flip = np.repeat(flip, sizes)
    source[vertex_flip] = np.repeat(2 * start + sizes - 1, sizes)[vertex_flip] - source[vertex_flip]
    return Rings(rings.coords[source], rings.offsets)


@numba.njit(cache=True)
def _convex_quadrilaterals(coords, first, min_area):
    n = len(first)
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        s = first[i]
        finite = True
        for k in range(5):
            finite = finite and np.isfinite(coords[s + k, 0]) and np.isfinite(coords[s + k, 1])
        if not finite:
            continue
        positive, negative, sure = 0, 0, True
        for k in range(4):
            ex, ey = coords[s + k + 1, 0] - coords[s + k, 0], coords[s + k + 1, 1] - coords[s + k, 1]
            j = s + (k + 1) % 4
            fx, fy = coords[j + 1, 0] - coords[j, 0], coords[j + 1, 1] - coords[j, 1]
            turn = ex * fy - ey * fx
            sure = sure and abs(turn) > 1e-6 * np.hypot(ex, ey) * np.hypot(fx, fy)
            positive += turn > 0
            negative += turn < 0
        d0x, d0y = coords[s + 2, 0] - coords[s, 0], coords[s + 2, 1] - coords[s, 1]
        d1x, d1y = coords[s + 3, 0] - coords[s + 1, 0], coords[s + 3, 1] - coords[s + 1, 1]
        area = 0.5 * abs(d0x * d1y - d0y * d1x)
        out[i] = sure and (positive == 4 or negative == 4) and area > 10.0 * min_area
    return out


def convex_quadrilaterals(coords: np.ndarray, first: np.ndarray, min_area: float) -> np.ndarray:
    """Which closed 4-vertex rings are, beyond doubt, strictly convex with an area above ``min_area``.

    Such a ring is a valid simple polygon (GEOS ``is_valid`` is True) whose area is not below ``min_area``: all
    four turns have the same sign, and a 4-vertex ring cannot turn twice around. The test is conservative: every
    turn must have a sine above 1e-6 and the area must exceed ``10 * min_area``, far beyond floating-point error
    (the products are taken of edge vectors, not of absolute coordinates); any other ring (also one with a NaN
    or infinite vertex) answers False and is left to the caller to check exactly.

    Parameters
    ----------
    coords : ndarray, shape (m, 2), float64
        Vertices, metres.
    first : ndarray, shape (n,), int64
        Ring ``i`` is the closed ring ``coords[first[i]:first[i] + 5]`` (last vertex repeating the first).
    min_area : float
        Square metres.

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    if len(first) == 0:
        return np.zeros(0, dtype=bool)
    coords = np.ascontiguousarray(coords, dtype=np.float64)
    return _convex_quadrilaterals(coords, np.asarray(first, dtype=np.int64), float(min_area))


def box_rings(x: np.ndarray, y: np.ndarray, length: np.ndarray, width: np.ndarray, yaw: np.ndarray) -> Rings:
    """Counter-clockwise rectangles from centre, size and heading.

    Parameters
    ----------
    x, y : ndarray, shape (n,)
        Centre of each rectangle, metres.
    length, width : ndarray, shape (n,)
        Extent along and across the heading, metres.
    yaw : ndarray, shape (n,)
        Heading, radians counter-clockwise from +x.
    """
    c, s = np.cos(yaw), np.sin(yaw)
    hl, hw = 0.5 * np.asarray(length), 0.5 * np.asarray(width)
    # corners in the body frame, counter-clockwise: rear-right, front-right, front-left, rear-left
    bx = np.stack([-hl, hl, hl, -hl], axis=1)
    by = np.stack([-hw, -hw, hw, hw], axis=1)
    coords = np.empty((len(c), 4, 2))
    coords[..., 0] = np.asarray(x)[:, None] + c[:, None] * bx - s[:, None] * by
    coords[..., 1] = np.asarray(y)[:, None] + s[:, None] * bx + c[:, None] * by
    return Rings(coords.reshape(-1, 2), np.arange(0, 4 * len(c) + 1, 4, dtype=np.int64))


def angular_extent(observer: np.ndarray, rings: Rings) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Directions from an observer that hit each ring's polygon.

    For an observer outside a polygon the directions hitting it form one interval ``[start, start + width]``
    with ``0 < width < 2 pi``; it may straddle the -pi/pi wrap. The interval is found by unwrapping the vertex
    bearings along the ring (robust at the wrap), not by min/max of ``atan2``.

    Parameters
    ----------
    observer : ndarray, shape (2,)
        Observer position, metres.
    rings : Rings
        n polygon rings (any orientation).

    Returns
    -------
    start : ndarray, shape (n,)
        Bearing where the interval starts, radians in [-pi, pi).
    width : ndarray, shape (n,)
        Width of the interval, radians. Meaningless where ``winding`` is not 0.
    winding : ndarray, shape (n,), int64
        Winding number of the ring around the observer: 0 when the observer is outside.

    Examples
    --------
    >>> import numpy as np
    >>> sq = box_rings(np.array([10.0]), np.array([0.0]), np.array([2.0]), np.array([2.0]), np.array([0.0]))
    >>> start, width, winding = angular_extent(np.zeros(2), sq)
    >>> bool(np.isclose(width[0], 2 * np.arctan2(1, 9))), int(winding[0])
    (True, 0)
    """
    n = len(rings)
    if n == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, dtype=np.int64)
    a, b = edges(rings)
    a = a - observer
    b = b - observer
    step = np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1])
    first = rings.offsets[:-1]
    cum = np.cumsum(step)
    base = np.concatenate([[0.0], cum])[first]
    # unwrapped bearing of each vertex's successor, relative to the ring's first vertex
    rel = cum - np.repeat(base, rings.sizes)
    lo = np.minimum(np.minimum.reduceat(rel, first), 0.0)
    hi = np.maximum(np.maximum.reduceat(rel, first), 0.0)
    total = rel[rings.offsets[1:] - 1]
    winding = np.rint(total / TWO_PI).astype(np.int64)
    bearing0 = np.arctan2(a[first, 1], a[first, 0])
    start = np.mod(bearing0 + lo + np.pi, TWO_PI) - np.pi
    return start, hi - lo, winding


@numba.njit(cache=True)
def _covers_point(px, py, coords, offsets, tolerance):
    """Whether each ragged ring (``coords`` (m, 2), ``offsets`` (n + 1,), metres) contains the point ``(px, py)``
    (even-odd rule) or passes within ``tolerance`` metres of it; shape (n,) bool."""
    return _covers_in_boxes(px, py, coords, offsets, tolerance, _ring_boxes(coords, offsets))


@numba.njit(cache=True)
def _ring_boxes(coords, offsets):
    """``(x0, y0, x1, y1)`` bounding box of each ragged ring, shape (n, 4)."""
    n = len(offsets) - 1
    boxes = np.empty((n, 4))
    for i in range(n):
        s, e = offsets[i], offsets[i + 1]
        boxes[i, 0], boxes[i, 2] = coords[s:e, 0].min(), coords[s:e, 0].max()
        boxes[i, 1], boxes[i, 3] = coords[s:e, 1].min(), coords[s:e, 1].max()
    return boxes


@numba.njit(cache=True)
def _covers_in_boxes(px, py, coords, offsets, tolerance, boxes):
    n = len(offsets) - 1
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        x0, y0, x1, y1 = boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3]
        if px < x0 - tolerance or px > x1 + tolerance or py < y0 - tolerance or py > y1 + tolerance:
            continue
        s, e = offsets[i], offsets[i + 1]
        inside = False
        best = np.inf
        for j in range(s, e):
            k = j + 1 if j + 1 < e else s
            ax, ay = coords[j, 0] - px, coords[j, 1] - py
            bx, by = coords[k, 0] - px, coords[k, 1] - py
            if (ay > 0) != (by > 0) and ax + (bx - ax) * (0 - ay) / (by - ay) > 0:
                inside = not inside
            best = min(best, segment_distance2(ax, ay, bx, by))
        out[i] = inside or best <= tolerance * tolerance
    return out


@numba.njit(cache=True)
def _covers_points(points, coords, offsets, tolerance):
    """:func:`_covers_point` for each of ``points`` (shape (k, 2)), shape (k, n) bool."""
    out = np.empty((len(points), len(offsets) - 1), dtype=np.bool_)
    boxes = _ring_boxes(coords, offsets)
    for p in range(len(points)):
        out[p] = _covers_in_boxes(points[p, 0], points[p, 1], coords, offsets, tolerance, boxes)
    return out


@numba.njit(cache=True)
def _covers_points_by_frame(points, point_starts, coords, offsets, frame_starts, tolerance):
    counts = np.zeros(len(points) + 1, dtype=np.int64)
    for f in range(len(frame_starts) - 1):
        for p in range(point_starts[f], point_starts[f + 1]):
            counts[p + 1] = counts[p] + frame_starts[f + 1] - frame_starts[f]
    out = np.empty(counts[-1], dtype=np.bool_)
    for f in range(len(frame_starts) - 1):
        p0, p1 = point_starts[f], point_starts[f + 1]
        if p1 > p0:
            s, e = frame_starts[f], frame_starts[f + 1]
            inside = _covers_points(points[p0:p1], coords, offsets[s : e + 1], tolerance)
            out[counts[p0] : counts[p1]] = inside.ravel()
    return out, counts


def covers_points_by_frame(
    points: np.ndarray,
    point_starts: np.ndarray,
    rings: Rings,
    frame_starts: np.ndarray,
    tolerance: float = TOUCH_TOLERANCE,
) -> tuple[np.ndarray, np.ndarray]:
    """:func:`covers_points` for the points of many frames in one compiled call: the points
    ``point_starts[f]:point_starts[f + 1]`` against the rings ``frame_starts[f]:frame_starts[f + 1]``.

    Returns the flat answers (bool) and their offsets (shape (k + 1,)): point ``p``'s answers for the rings of
    its frame, in order, are ``covered[offsets[p]:offsets[p + 1]]``.

    Examples
    --------
    >>> squares = Rings(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]] * 2), np.array([0, 4, 8]))
    >>> covered, offsets = covers_points_by_frame(
    ...     np.array([[1.0, 1.0], [3.0, 1.0]]), np.array([0, 1, 2]), squares, np.array([0, 1, 2]))
    >>> covered.tolist(), offsets.tolist()
    ([True, False], [0, 1, 2])
    """
    covered, offsets = _covers_points_by_frame(
        np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2),
        np.asarray(point_starts, dtype=np.int64),
        np.ascontiguousarray(rings.coords, dtype=np.float64),
        np.asarray(rings.offsets, dtype=np.int64),
        np.asarray(frame_starts, dtype=np.int64),
        float(tolerance),
    )
    return covered, offsets


def covers_points(points: np.ndarray, rings: Rings, tolerance: float = TOUCH_TOLERANCE) -> np.ndarray:
    """:func:`covers_point` for several points at once (one compiled call), shape (k, n) bool.

    Examples
    --------
    >>> square = Rings(np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]]), np.array([0, 4]))
    >>> covers_points(np.array([[1.0, 1.0], [3.0, 1.0], [2.0, 1.0]]), square).ravel().tolist()
    [True, False, True]
    """
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    coords = np.ascontiguousarray(rings.coords, dtype=np.float64)
    offsets = np.asarray(rings.offsets, dtype=np.int64)
    return _covers_points(points, coords, offsets, float(tolerance))


@numba.njit(cache=True)
def _points_in_boxes(points, boxes):
    out = np.empty((len(points), len(boxes)), dtype=np.bool_)
    for p in range(len(points)):
        x, y = points[p, 0], points[p, 1]
        for b in range(len(boxes)):
            out[p, b] = boxes[b, 0] <= x <= boxes[b, 2] and boxes[b, 1] <= y <= boxes[b, 3]
    return out


def points_in_boxes(points: np.ndarray, boxes: np.ndarray) -> np.ndarray:
    """Whether each point (shape (k, 2), metres) lies in each closed box ``(x0, y0, x1, y1)`` (shape (s, 4), as
    ``shapely.bounds`` gives; NaN boxes hold nothing), shape (k, s) bool.

    Examples
    --------
    >>> points_in_boxes(np.array([[1.0, 1.0], [2.0, 0.0]]), np.array([[0.0, 0.0, 2.0, 2.0], [5, 5, 6, 6]]))
    array([[ True, False],
           [ True, False]])
    """
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    return _points_in_boxes(points, np.ascontiguousarray(boxes, dtype=np.float64).reshape(-1, 4))


def covers_point(point: np.ndarray, rings: Rings, tolerance: float = TOUCH_TOLERANCE) -> np.ndarray:
    """Whether each ring's polygon contains ``point`` or has it within ``tolerance`` metres of its boundary.

    Returns
    -------
    ndarray of bool, shape (n,)
    """
    if len(rings) == 0:
        return np.zeros(0, dtype=bool)
    coords = np.ascontiguousarray(rings.coords, dtype=np.float64)
    offsets = np.asarray(rings.offsets, dtype=np.int64)
    return _covers_point(float(point[0]), float(point[1]), coords, offsets, float(tolerance))


def rings_from(geoms: Sequence[Any]) -> Rings:
    """The rings (LinearRings or LineStrings closed on themselves) of shapely ``geoms`` as ragged arrays."""
    coords, which = shapely.get_coordinates(np.asarray(geoms, dtype=object), return_index=True)
    sizes = np.bincount(which, minlength=len(geoms))
    keep = np.ones(len(coords), dtype=bool)
    keep[np.cumsum(sizes) - 1] = False
    offsets = np.zeros(len(geoms) + 1, dtype=np.int64)
    np.cumsum(sizes - 1, out=offsets[1:])
    return Rings(np.ascontiguousarray(coords[keep]), offsets)
