"""Which rings contain or touch points: the transparency of bodies to a viewpoint (over ragged rings, see
:mod:`.geometry`, in compiled loops).

A body *touches* a point when its boundary passes within :data:`TOUCH_TOLERANCE` of it; containing or touching a
viewpoint makes a body transparent to it.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit
from ..geometry.kernels import copy_into
from ..geometry.rings import Rings, ring_covers_point

TOUCH_TOLERANCE = 1e-9  # metres: a body passing this near a viewpoint touches it (and is transparent to it)


@njit(cache=True)
def _covers_point(px, py, coords, offsets, tolerance):
    """Whether each ragged ring (``coords`` (m, 2), ``offsets`` (n + 1,), metres) contains the point ``(px, py)``
    (even-odd rule) or passes within ``tolerance`` metres of it; shape (n,) bool."""
    return _covers_in_boxes(px, py, coords, offsets, tolerance, _ring_boxes(coords, offsets))


@njit(cache=True)
def _ring_boxes(coords, offsets):
    """``(x0, y0, x1, y1)`` bounding box of each ragged ring, shape (n, 4)."""
    n = len(offsets) - 1
    boxes = np.empty((n, 4))
    for i in range(n):
        s, e = offsets[i], offsets[i + 1]
        boxes[i, 0], boxes[i, 2] = coords[s:e, 0].min(), coords[s:e, 0].max()
        boxes[i, 1], boxes[i, 3] = coords[s:e, 1].min(), coords[s:e, 1].max()
    return boxes


@njit(cache=True)
def _covers_in_boxes(px, py, coords, offsets, tolerance, boxes):
    n = len(offsets) - 1
    out = np.zeros(n, dtype=np.bool_)
    for i in range(n):
        x0, y0, x1, y1 = boxes[i, 0], boxes[i, 1], boxes[i, 2], boxes[i, 3]
        if px < x0 - tolerance or px > x1 + tolerance or py < y0 - tolerance or py > y1 + tolerance:
            continue
        out[i] = ring_covers_point(coords, offsets[i], offsets[i + 1], px, py, tolerance)
    return out


@njit(cache=True)
def _covers_points(points, coords, offsets, tolerance):
    """:func:`_covers_point` for each of ``points`` (shape (k, 2)), shape (k, n) bool."""
    out = np.empty((len(points), len(offsets) - 1), dtype=np.bool_)
    boxes = _ring_boxes(coords, offsets)
    for p in range(len(points)):
        copy_into(out[p], 0, _covers_in_boxes(points[p, 0], points[p, 1], coords, offsets, tolerance, boxes))
    return out


@njit(cache=True)
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
            copy_into(out, counts[p0], inside.ravel())
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


@njit(cache=True)
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
