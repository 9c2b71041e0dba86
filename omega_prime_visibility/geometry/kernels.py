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
  :func:`counting_sort`, :func:`ring_index`, :func:`next_vertex_index`, :func:`insertion_sort` (a few values in
  place);
- sorting: :func:`argsort_stable`, :func:`sorted_values`, :func:`unique_values` (written once here instead of
  numba's ``np.argsort``/``np.sort``/``np.unique``, whose quicksort and mergesort are compiled anew for every
  kind, dtype and layout: several seconds of a first call);
- distances: :func:`nearest_offset` (point to segment), :func:`segment_distance2` (origin to segment),
  :func:`ray_line_distance` (origin along a ray to a line);
- orientation: :func:`orient`, :func:`cross_properly` (two segments);
- angles: :func:`wrap_positive`.
"""

from __future__ import annotations

import numba
import numpy as np

TWO_PI = 2.0 * np.pi
MIN_CAPACITY = 16  # smallest capacity a growable buffer is given

# -- copying ---------------------------------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def reserve_rows(buffer, size, needed):
    """:func:`reserve` for a 2D buffer of shape (capacity, columns): rows ``[:size]`` are in use."""
    if needed <= len(buffer):
        return buffer
    grown = np.empty((max(2 * len(buffer), needed, MIN_CAPACITY), buffer.shape[1]), dtype=buffer.dtype)
    copy_rows(grown, 0, buffer[:size])
    return grown


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
def prefix_sum(counts):
    """Turn ``counts`` (shape (k + 1,), ``counts[i + 1]`` = size of group ``i``, ``counts[0] = 0``) into CSR offsets,
    in place: group ``i`` becomes ``[counts[i], counts[i + 1])``."""
    for i in range(len(counts) - 1):
        counts[i + 1] += counts[i]


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def counting_sort(keys, n_keys, items):
    """``items`` (indices into ``keys``) stably reordered by ``keys[item]`` in ``range(n_keys)``, shape (p,)."""
    return group_by_key(keys, n_keys, items)[1]


@numba.njit(cache=True)
def ring_index(offsets):
    """Ring number of every vertex of ragged rings (``offsets`` shape (n + 1,)), shape (m,), int64."""
    ring = np.empty(offsets[-1], dtype=np.int64)
    for i in range(len(offsets) - 1):
        ring[offsets[i] : offsets[i + 1]] = i
    return ring


@numba.njit(cache=True)
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


@numba.njit(cache=True, inline="always")
def insertion_sort(values, n):
    """Sort ``values[:n]`` ascending in place, by insertion (fast for the few values of a pair test; inlined, so a
    loop calling it pays no reference counting). Equal values keep their order; without NaN the result is the
    order ``np.sort`` gives, but for ``-0.0`` and ``+0.0``, which it may order either way.

    >>> values = np.array([3.0, 1.0, 2.0, 9.0])
    >>> insertion_sort(values, 3); values.tolist()
    [1.0, 2.0, 3.0, 9.0]
    """
    for a in range(1, n):
        value = values[a]
        b = a - 1
        while b >= 0 and values[b] > value:
            values[b + 1] = values[b]
            b -= 1
        values[b + 1] = value


# -- distances -------------------------------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
def segment_distance2(ax, ay, bx, by):
    """Squared distance (square metres) from the origin to the segment from ``(ax, ay)`` to ``(bx, by)``."""
    dx, dy = nearest_offset(-ax, -ay, bx - ax, by - ay)
    return dx * dx + dy * dy


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
def wrap_positive(angle):
    """``angle - 2 pi floor(angle / 2 pi)``: an angle (radians) taken into ``[0, 2 pi]`` (2 pi only by rounding)."""
    return angle - TWO_PI * np.floor(angle / TWO_PI)


# -- orientation -----------------------------------------------------------------------------------------------


@numba.njit(cache=True, inline="always")
def orient(ax, ay, bx, by, cx, cy):
    """Twice the signed area of triangle abc, square metres: positive when c lies left of the line a -> b."""
    return (bx - ax) * (cy - ay) - (by - ay) * (cx - ax)


@numba.njit(cache=True)
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


# -- sorting ---------------------------------------------------------------------------------------------------

INSERTION_RUN = 16  # runs of this many items are sorted by insertion before merging


@numba.njit(cache=True, inline="always")
def _after(a, b):
    """Whether key ``a`` sorts after key ``b`` (NaN after every number, as numpy sorts)."""
    return a > b or (a != a and b == b)


@numba.njit(cache=True)
def argsort_stable(keys):
    """Positions that sort ``keys`` ascending, equal keys in their order: ``np.argsort(keys, kind="stable")``.

    Parameters
    ----------
    keys : ndarray, shape (n,)
        Numbers (float64 or int64, C-contiguous: pass ``column.copy()`` for a column of a table); NaN sorts last.

    Returns
    -------
    ndarray, shape (n,), int64

    Examples
    --------
    >>> import numpy as np
    >>> argsort_stable(np.array([2.0, np.nan, 1.0, 2.0, -0.5])).tolist()
    [4, 2, 0, 3, 1]
    """
    n = len(keys)
    order = np.arange(n)
    for lo in range(0, n, INSERTION_RUN):  # runs sorted by insertion ...
        for a in range(lo + 1, min(lo + INSERTION_RUN, n)):
            x = order[a]
            b = a - 1
            while b >= lo and _after(keys[order[b]], keys[x]):
                order[b + 1] = order[b]
                b -= 1
            order[b + 1] = x
    if n <= INSERTION_RUN:
        return order
    other = np.empty(n, dtype=np.int64)
    width = INSERTION_RUN
    while width < n:  # ... then merged bottom-up, between two buffers
        for lo in range(0, n, 2 * width):
            mid, hi = min(lo + width, n), min(lo + 2 * width, n)
            i, j = lo, mid
            for out in range(lo, hi):
                if j >= hi or (i < mid and not _after(keys[order[i]], keys[order[j]])):
                    other[out] = order[i]
                    i += 1
                else:
                    other[out] = order[j]
                    j += 1
        order, other = other, order
        width *= 2
    return order


@numba.njit(cache=True)
def sorted_values(values):
    """A sorted copy of ``values`` (as :func:`argsort_stable` takes them): ``np.sort(values)``.

    Examples
    --------
    >>> import numpy as np
    >>> sorted_values(np.array([3.0, -1.0, 2.0])).tolist()
    [-1.0, 2.0, 3.0]
    """
    return values[argsort_stable(values)]


@numba.njit(cache=True)
def unique_values(values):
    """The distinct ``values``, ascending: ``np.unique(values)``.

    Examples
    --------
    >>> import numpy as np
    >>> unique_values(np.array([5, 1, 5, 3, 1])).tolist()
    [1, 3, 5]
    """
    ordered = sorted_values(values)
    keep = np.ones(len(ordered), dtype=np.bool_)
    for i in range(1, len(ordered)):
        keep[i] = ordered[i] != ordered[i - 1]
    return ordered[keep]
