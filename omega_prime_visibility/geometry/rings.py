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

import numpy as np
import shapely

from .._compiled.kernel import njit
from .kernels import TWO_PI, segment_distance2


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
        return _gathered(self.coords, self.offsets[positions], self.sizes[positions], True, False)

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

    Examples
    --------
    >>> clockwise = Rings(np.array([[0.0, 0.0], [0.0, 1.0], [1.0, 0.0]]), np.array([0, 3]))
    >>> orient(clockwise).coords.tolist()
    [[1.0, 0.0], [0.0, 1.0], [0.0, 0.0]]
    """
    want = np.broadcast_to(np.asarray(counter_clockwise, dtype=bool), (len(rings),))
    return gather_oriented(rings.coords, rings.offsets[:-1], rings.sizes, want)


def gather_oriented(coords: np.ndarray, first: np.ndarray, sizes: np.ndarray, counter_clockwise: Any = True) -> Rings:
    """Rings gathered from ``coords`` (ring ``i`` is ``coords[first[i]:first[i] + sizes[i]]``, metres) and
    reversed where their orientation differs from ``counter_clockwise`` (bool, or one per ring), in one pass.

    The orientation is the sign of :func:`signed_area` (taken relative to each ring's first vertex); a reversed
    ring lists its vertices from last to first.
    """
    return _gathered(coords, first, sizes, counter_clockwise, True)


def _gathered(coords: np.ndarray, first: np.ndarray, sizes: np.ndarray, counter_clockwise: Any, orient: bool) -> Rings:
    sizes = np.asarray(sizes, dtype=np.int64)
    want = np.ascontiguousarray(np.broadcast_to(np.asarray(counter_clockwise, dtype=bool), (len(sizes),)))
    offsets = np.zeros(len(sizes) + 1, dtype=np.int64)
    np.cumsum(sizes, out=offsets[1:])
    coords = np.ascontiguousarray(coords, dtype=np.float64).reshape(-1, 2)
    out = _gather_rings(coords, np.ascontiguousarray(first, dtype=np.int64), offsets, want, orient)
    return Rings(out, offsets)


@njit(cache=True)
def _gather_rings(coords, first, offsets, want, orient):
    """Ring ``i`` of the result is ``coords[first[i]:first[i] + k]`` (``k`` from ``offsets``), reversed where
    ``orient`` and its orientation is not ``want[i]``."""
    out = np.empty((offsets[-1], 2))
    for i in range(len(first)):
        s, k = first[i], offsets[i + 1] - offsets[i]
        keep = True
        if orient:
            x0, y0 = coords[s, 0], coords[s, 1]
            twice_area = 0.0
            for j in range(k):
                jn = j + 1 if j + 1 < k else 0
                ax, ay = coords[s + j, 0] - x0, coords[s + j, 1] - y0
                bx, by = coords[s + jn, 0] - x0, coords[s + jn, 1] - y0
                twice_area += ax * by - ay * bx
            keep = (twice_area > 0) == want[i]
        at = offsets[i]
        for j in range(k):  # element by element: a slice assignment compiles numba's shape-error formatting
            source = s + j if keep else s + k - 1 - j
            out[at + j, 0] = coords[source, 0]
            out[at + j, 1] = coords[source, 1]
    return out


@njit(cache=True)
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


def rings_from(geoms: Sequence[Any]) -> Rings:
    """The rings (LinearRings or LineStrings closed on themselves) of shapely ``geoms`` as ragged arrays."""
    coords, which = shapely.get_coordinates(np.asarray(geoms, dtype=object), return_index=True)
    sizes = np.bincount(which, minlength=len(geoms))
    keep = np.ones(len(coords), dtype=bool)
    keep[np.cumsum(sizes) - 1] = False
    offsets = np.zeros(len(geoms) + 1, dtype=np.int64)
    np.cumsum(sizes - 1, out=offsets[1:])
    return Rings(np.ascontiguousarray(coords[keep]), offsets)


@njit(cache=True)
def ring_covers_point(coords, s, e, px, py, tolerance):
    """Whether the ring ``coords[s:e]`` (metres, closing vertex not repeated) contains the point ``(px, py)``
    (even-odd rule) or passes within ``tolerance`` metres of it.

    Examples
    --------
    >>> square = np.array([[0.0, 0.0], [2.0, 0.0], [2.0, 2.0], [0.0, 2.0]])
    >>> [bool(ring_covers_point(square, 0, 4, x, 1.0, 1e-9)) for x in (1.0, 2.0 + 1e-10, 2.1)]
    [True, True, False]
    """
    inside = False
    best = np.inf
    for j in range(s, e):
        k = j + 1 if j + 1 < e else s
        ax, ay = coords[j, 0] - px, coords[j, 1] - py
        bx, by = coords[k, 0] - px, coords[k, 1] - py
        if (ay > 0) != (by > 0) and ax + (bx - ax) * (0 - ay) / (by - ay) > 0:
            inside = not inside
        best = min(best, segment_distance2(ax, ay, bx, by))
    return inside or best <= tolerance * tolerance
