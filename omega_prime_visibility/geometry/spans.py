"""Angular spans: the directions and distances at which a viewpoint can meet a polygon, for deciding cheaply which
bodies cannot be in front of which (numpy, vectorised over (viewpoint, ring) pairs)."""

from __future__ import annotations

import numpy as np

from .rings import Rings

FULL = np.pi
"""Half-width of the span of a ring that surrounds or touches its viewpoint: every direction."""


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
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    ring_of_pair = np.asarray(ring_of_pair, dtype=np.int64)
    p = len(ring_of_pair)
    if p == 0:
        empty = np.zeros(0)
        return empty, empty.copy(), empty.copy(), empty.copy()
    sizes = rings.sizes[ring_of_pair]
    starts = np.zeros(p + 1, dtype=np.int64)
    np.cumsum(sizes, out=starts[1:])
    local = np.arange(starts[-1]) - np.repeat(starts[:-1], sizes)
    pair = np.repeat(np.arange(p), sizes)
    first = rings.offsets[ring_of_pair][pair]
    vertex = rings.coords[first + local] - points[pair]
    following = rings.coords[first + (local + 1) % sizes[pair]] - points[pair]
    angle = np.arctan2(vertex[:, 1], vertex[:, 0])
    step = np.arctan2(following[:, 1], following[:, 0]) - angle
    step = (step + np.pi) % (2 * np.pi) - np.pi  # each edge turns by less than π unless it passes the viewpoint
    # unwrapped angle of each vertex along its ring, from the ring's first vertex
    turned = np.cumsum(step) - step
    turned -= np.repeat(turned[starts[:-1]], sizes)
    unwrapped = np.repeat(angle[starts[:-1]], sizes) + turned
    low = np.minimum.reduceat(unwrapped, starts[:-1])
    high = np.maximum.reduceat(unwrapped, starts[:-1])
    winding = np.add.reduceat(step, starts[:-1])
    # distance to each edge (point to segment), the nearest being the ring's near distance
    edge = following - vertex
    length2 = np.einsum("ij,ij->i", edge, edge)
    t = np.clip(-np.einsum("ij,ij->i", vertex, edge) / np.where(length2 > 0, length2, 1.0), 0.0, 1.0)
    closest = vertex + t[:, None] * edge
    near = np.sqrt(np.minimum.reduceat(np.einsum("ij,ij->i", closest, closest), starts[:-1]))
    far = np.sqrt(np.maximum.reduceat(np.einsum("ij,ij->i", vertex, vertex), starts[:-1]))
    half = 0.5 * (high - low)
    surrounds = (np.abs(winding) > np.pi) | (half >= 0.5 * np.pi * 1.999) | (near <= 0.0)
    half = np.where(surrounds, FULL, half)
    centre = 0.5 * (high + low)
    return centre, half, near, far


def overlapping(centre_a, half_a, centre_b, half_b, slack: float = 1e-9) -> np.ndarray:
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
