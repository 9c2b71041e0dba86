"""Angular spans: the directions and distances at which a viewpoint can meet a polygon, for deciding cheaply which
bodies cannot be in front of which (one compiled loop over (viewpoint, ring) pairs)."""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit
from .kernels import segment_distance2
from .rings import Rings

FULL = np.pi
"""Half-width of the span of a ring that surrounds or touches its viewpoint: every direction."""
SLACK = 1e-9
"""Radians by which spans are widened before deciding that they share no direction."""


def angular_spans(
    points: np.ndarray, rings: Rings, ring_of_pair: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """For each pair ``k``, the directions from ``points[k]`` that meet ring ``ring_of_pair[k]``, and the nearest
    and farthest distance of the ring.

    Parameters
    ----------
    points : ndarray, shape (p, 2)
        Viewpoints, metres.
    rings : Rings
        Polygon rings, metres.
    ring_of_pair : ndarray of int, shape (p,)
        The ring of each pair.

    Returns
    -------
    centre : ndarray, shape (p,)
        Middle direction of the span, radians counter-clockwise from +x.
    half : ndarray, shape (p,)
        Half the span's width, radians; :data:`FULL` (π) when the ring surrounds or touches the viewpoint.
    near, far : ndarray, shape (p,)
        Smallest distance from the viewpoint to the ring's outline and largest to its vertices, metres.

    Two rings whose spans (closed arcs) do not overlap cannot hide each other; a ring whose ``near`` exceeds
    another's ``far`` cannot be in front of it.

    Examples
    --------
    >>> square = Rings(np.array([[1.0, -1], [3, -1], [3, 1], [1, 1]]), np.array([0, 4]))
    >>> centre, half, near, far = angular_spans(np.zeros((1, 2)), square, np.array([0]))
    >>> float(centre[0]), round(float(half[0]), 6), float(near[0]), round(float(far[0]) ** 2, 9)
    (0.0, 0.785398, 1.0, 10.0)
    """
    points = np.ascontiguousarray(points, dtype=np.float64).reshape(-1, 2)
    ring_of_pair = np.ascontiguousarray(ring_of_pair, dtype=np.int64)
    coords = np.ascontiguousarray(rings.coords, dtype=np.float64)
    offsets = np.ascontiguousarray(rings.offsets, dtype=np.int64)
    return _spans(points, coords, offsets, ring_of_pair)


@njit(cache=True)
def _spans(points, coords, offsets, ring_of_pair):
    """:func:`angular_spans` in one loop: per pair, the vertices' bearings unwrapped along the ring (each edge
    turns by less than π unless it passes the viewpoint), the ring's winding, and its near and far distances."""
    p = len(ring_of_pair)
    centre, half, near, far = np.empty(p), np.empty(p), np.empty(p), np.empty(p)
    for k in range(p):
        r = ring_of_pair[k]
        start, n = offsets[r], offsets[r + 1] - offsets[r]
        px, py = points[k, 0], points[k, 1]
        ax, ay = coords[start, 0] - px, coords[start, 1] - py
        angle = math.atan2(ay, ax)
        unwrapped, low, high, winding = angle, angle, angle, 0.0
        near2, far2 = np.inf, 0.0
        for i in range(n):
            j = start + (i + 1) % n
            bx, by = coords[j, 0] - px, coords[j, 1] - py
            following = math.atan2(by, bx)
            step = following - angle
            step = (step + np.pi) % (2 * np.pi) - np.pi
            if i > 0:
                low, high = min(low, unwrapped), max(high, unwrapped)
            unwrapped += step
            winding += step
            near2 = min(near2, segment_distance2(ax, ay, bx, by))
            far2 = max(far2, ax * ax + ay * ay)
            ax, ay, angle = bx, by, following
        near[k], far[k] = math.sqrt(near2), math.sqrt(far2)
        h = 0.5 * (high - low)
        if abs(winding) > np.pi or h >= 0.5 * np.pi * 1.999 or near[k] <= 0.0:
            h = FULL
        half[k], centre[k] = h, 0.5 * (high + low)
    return centre, half, near, far


@njit(cache=True, inline="always")
def spans_share(centre_a, half_a, centre_b, half_b):
    """Whether two spans share a direction (:func:`overlapping` for two scalars, widened by :data:`SLACK`)."""
    gap = abs((centre_a - centre_b + np.pi) % (2 * np.pi) - np.pi)
    return gap <= half_a + half_b + SLACK


@njit(cache=True, inline="always")
def may_be_in_front(centre_b, half_b, near_b, centre_t, half_t, far_t):
    """Whether body ``b`` may hide part of target ``t`` (spans and distances from :func:`angular_spans`): they
    share a direction and ``b`` begins no farther than ``t`` ends (up to a relative 1e-9)."""
    return near_b <= far_t * (1 + 1e-9) + 1e-9 and spans_share(centre_b, half_b, centre_t, half_t)


def overlapping(centre_a, half_a, centre_b, half_b, slack: float = SLACK) -> np.ndarray:
    """Whether spans ``a`` and ``b`` (broadcast) share a direction, as closed arcs widened by ``slack`` radians.

    Examples
    --------
    >>> overlapping(np.array([0.0, 0.0]), np.array([0.1, 0.1]), np.array([0.25, 3.1]), np.array([0.1, 0.1]))
    array([False, False])
    >>> bool(overlapping(0.0, 0.1, 0.2, 0.1)), bool(overlapping(3.1, 0.1, -3.1, 0.1))
    (True, True)
    """
    gap = np.abs((np.asarray(centre_a) - np.asarray(centre_b) + np.pi) % (2 * np.pi) - np.pi)
    return gap <= np.asarray(half_a) + np.asarray(half_b) + slack
