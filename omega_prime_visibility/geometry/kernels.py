"""Small numba building blocks shared by the engines, each written once.

Conventions as in :mod:`.geometry`: lengths in metres, angles in radians counter-clockwise from +x; "index"
arrays are int64. The helpers are plain ``numba.njit`` functions (the tiny ones inlined), callable from any
kernel; each does one thing with the same floating-point operations wherever it is used, so swapping one in for a
hand-written copy changes no result in the last bit.

- copying: :func:`copy_into`, :func:`copy_rows` (numba's slice assignment from an array compiles a formatted
  shape-mismatch message into every kernel that uses it, about 3 s of a first call; the kernels copy with these
  loops instead);
- growable buffers: :func:`reserve`, :func:`push_pair`;
- index building: :func:`prefix_sum`, :func:`group_by_key` (a stable counting sort with its CSR offsets),
  :func:`counting_sort`, :func:`ring_index`, :func:`next_vertex_index` (the sorts: :mod:`.sorting`);
- distances: :func:`nearest_offset` (point to segment), :func:`segment_distance2` (origin to segment),
  :func:`ray_line_distance` (origin along a ray to a line);
- orientation: :func:`orient`, :func:`cross_properly` (two segments);
- angles: :func:`wrap_positive`.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit

TWO_PI = 2.0 * np.pi
MIN_CAPACITY = 16  # smallest capacity a growable buffer is given

# -- copying ---------------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def copy_into(dest, at, source):
    """``dest[at:at + len(source)] = source`` for 1D arrays, as a loop (the caller makes sure it fits).

    Examples
    --------
    >>> dest = np.zeros(5)
    >>> copy_into(dest, 1, np.array([7.0, 8.0]))
    >>> dest.tolist()
    [0.0, 7.0, 8.0, 0.0, 0.0]
    """
    for i in range(len(source)):
        dest[at + i] = source[i]


@njit(cache=True, inline="always")
def copy_rows(dest, at, source):
    """``dest[at:at + len(source)] = source`` for 2D arrays of the same number of columns, as a loop.

    Examples
    --------
    >>> dest = np.zeros((3, 2))
    >>> copy_rows(dest, 1, np.array([[1.0, 2.0]]))
    >>> dest.tolist()
    [[0.0, 0.0], [1.0, 2.0], [0.0, 0.0]]
    """
    for i in range(len(source)):
        for c in range(source.shape[1]):
            dest[at + i, c] = source[i, c]


# -- growable buffers ------------------------------------------------------------------------------------------


@njit(cache=True)
def reserve(buffer, size, needed):
    """``buffer`` if it holds ``needed`` items, else a larger copy of its first ``size`` items.

    Parameters
    ----------
    buffer : ndarray, shape (capacity,)
        Any dtype; items ``[:size]`` are in use.
    size : int
        Items in use.
    needed : int
        Capacity required.

    Returns
    -------
    ndarray, shape (>= needed,)
        The same array, or a new one of ``max(2 * capacity, needed, MIN_CAPACITY)`` items (amortised O(1) appends).
    """
    if needed <= len(buffer):
        return buffer
    grown = np.empty(max(2 * len(buffer), needed, MIN_CAPACITY), dtype=buffer.dtype)
    copy_into(grown, 0, buffer[:size])
    return grown


@njit(cache=True)
def reserve_rows(buffer, size, needed):
    """:func:`reserve` for a 2D buffer of shape (capacity, columns): rows ``[:size]`` are in use."""
    if needed <= len(buffer):
        return buffer
    grown = np.empty((max(2 * len(buffer), needed, MIN_CAPACITY), buffer.shape[1]), dtype=buffer.dtype)
    copy_rows(grown, 0, buffer[:size])
    return grown


@njit(cache=True, inline="always")
def push_pair(first, second, size, i, j):
    """Append the pair ``(i, j)`` at position ``size`` of two growable buffers.

    Returns
    -------
    first, second : ndarray
        The buffers (grown when they were full).
    size : int
        ``size + 1``.
    """
    first = reserve(first, size, size + 1)
    second = reserve(second, size, size + 1)
    first[size] = i
    second[size] = j
    return first, second, size + 1


# -- index building --------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def prefix_sum(counts):
    """Turn ``counts`` (shape (k + 1,), ``counts[i + 1]`` = size of group ``i``, ``counts[0] = 0``) into CSR offsets,
    in place: group ``i`` becomes ``[counts[i], counts[i + 1])``."""
    for i in range(len(counts) - 1):
        counts[i + 1] += counts[i]


@njit(cache=True)
def group_by_key(keys, n_keys, items):
    """``items`` grouped by ``keys[item]`` (a stable counting sort) and the groups' CSR offsets.

    Parameters
    ----------
    keys : ndarray of int, shape (k,)
        A key in ``range(n_keys)`` for every index that ``items`` may hold.
    n_keys : int
    items : ndarray of int64, shape (p,)
        Indices into ``keys``.

    Returns
    -------
    offsets : ndarray of int64, shape (n_keys + 1,)
        Items with key ``c`` are ``grouped[offsets[c]:offsets[c + 1]]``.
    grouped : ndarray of int64, shape (p,)
        ``items`` ordered by key, in their given order within a key.
    """
    offsets = np.zeros(n_keys + 1, dtype=np.int64)
    for r in items:
        offsets[keys[r] + 1] += 1
    prefix_sum(offsets)
    fill = offsets[:-1].copy()
    grouped = np.empty(len(items), dtype=np.int64)
    for r in items:
        grouped[fill[keys[r]]] = r
        fill[keys[r]] += 1
    return offsets, grouped


@njit(cache=True)
def counting_sort(keys, n_keys, items):
    """``items`` (indices into ``keys``) stably reordered by ``keys[item]`` in ``range(n_keys)``, shape (p,)."""
    return group_by_key(keys, n_keys, items)[1]


@njit(cache=True)
def ring_index(offsets):
    """Ring number of every vertex of ragged rings (``offsets`` shape (n + 1,)), shape (m,), int64."""
    ring = np.empty(offsets[-1], dtype=np.int64)
    for i in range(len(offsets) - 1):
        ring[offsets[i] : offsets[i + 1]] = i
    return ring


@njit(cache=True)
def next_vertex_index(offsets):
    """Index of the following vertex of the same ring (wrapping to the ring's first), shape (m,), int64."""
    m = offsets[-1]
    following = np.empty(m, dtype=np.int64)
    for i in range(len(offsets) - 1):
        s, e = offsets[i], offsets[i + 1]
        for j in range(s, e - 1):
            following[j] = j + 1
        if e > s:
            following[e - 1] = s
    return following


# -- distances -------------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def nearest_offset(wx, wy, ex, ey):
    """Offset from a segment's nearest point to a point, metres.

    Parameters
    ----------
    wx, wy : float
        The point minus the segment's start, metres.
    ex, ey : float
        The segment's end minus its start, metres (a zero vector is a point).

    Returns
    -------
    dx, dy : float
        The point minus the segment's point nearest to it; its length is the point–segment distance.
    """
    ee = ex * ex + ey * ey
    u = (wx * ex + wy * ey) / ee if ee > 0.0 else 0.0
    u = min(max(u, 0.0), 1.0)
    return wx - u * ex, wy - u * ey


@njit(cache=True, inline="always")
def segment_distance2(ax, ay, bx, by):
    """Squared distance (square metres) from the origin to the segment from ``(ax, ay)`` to ``(bx, by)``."""
    dx, dy = nearest_offset(-ax, -ay, bx - ax, by - ay)
    return dx * dx + dy * dy


@njit(cache=True, inline="always")
def ray_line_distance(dx, dy, ax, ay, ex, ey):
    """Signed distance from the origin along the unit direction ``(dx, dy)`` to a line, metres.

    The line passes through ``(ax, ay)`` (metres, relative to the ray's origin) with direction ``(ex, ey)``;
    the result is negative when the line is hit behind, ``inf`` when the ray is parallel to it.
    """
    den = dx * ey - dy * ex
    if den == 0.0:
        return np.inf
    return (ax * ey - ay * ex) / den


# -- angles ----------------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def wrap_positive(angle):
    """``angle - 2 pi floor(angle / 2 pi)``: an angle (radians) taken into ``[0, 2 pi]`` (2 pi only by rounding)."""
    return angle - TWO_PI * np.floor(angle / TWO_PI)


# -- orientation -----------------------------------------------------------------------------------------------


@njit(cache=True, inline="always")
def orient(ax, ay, bx, by, cx, cy):
    """Twice the signed area of triangle abc, square metres: positive when c lies left of the line a -> b."""
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@njit(cache=True)
def cross_properly(ax, ay, bx, by, cx, cy, dx, dy):
    """Whether segments ab and cd cross at a single point interior to both.

    Examples
    --------
    The diagonals of a square cross; two segments meeting at an end do not cross properly:

    >>> bool(cross_properly(0.0, 0.0, 2.0, 2.0, 0.0, 2.0, 2.0, 0.0))
    True
    >>> bool(cross_properly(0.0, 0.0, 1.0, 1.0, 1.0, 1.0, 2.0, 0.0))
    False
    """
    d1 = orient(ax, ay, bx, by, cx, cy)
    d2 = orient(ax, ay, bx, by, dx, dy)
    if not ((d1 > 0.0 and d2 < 0.0) or (d1 < 0.0 and d2 > 0.0)):
        return False
    d3 = orient(cx, cy, dx, dy, ax, ay)
    d4 = orient(cx, cy, dx, dy, bx, by)
    return (d3 > 0.0 and d4 < 0.0) or (d3 < 0.0 and d4 > 0.0)
