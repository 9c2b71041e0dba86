"""A viewpoint's limits: its field of view (a wedge of bearings) and its range (a disk), exactly.

Shared by the 2D engines so that what a sensor can look at means the same everywhere:

- :func:`limited_angle` measures the bearings of an interval that lie inside the wedge and along which a given
  straight edge is hit within range (the engines credit a visible piece of a target with it);
- :func:`view_intervals` gives, per target and ignoring occlusion, the directions of its extent inside the wedge
  along which the target itself is hit within range (its *in-view* directions), as intervals;
- :func:`restrict_observation` keeps of an engine's occluders only those hit before the target along an in-view
  direction (a body beyond range, or outside the field of view, hides nothing the sensor could see).

A direction along which the target is hit within range is one whose ray meets ``target ∩ disk``, so the in-view
directions are the angular extent of that region within the wedge: the bearings of the target's edges clipped to
the disk, and of the arcs of the range circle that run inside the target. No sampling is involved.

Angles are radians counter-clockwise from +x, distances metres, everything relative to the viewpoint.
"""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit
from .kernels import TWO_PI, reserve, segment_distance2, wrap_positive
from .sorting import argsort_stable, sorted_values

SNAP = 1e-12
"""Radians: in-view intervals this close to the ends of a target's extent are taken to reach them."""


@njit(cache=True, inline="always")
def clip_circular(lo, hi, count, c0, cw):
    """Intersect the ``count`` intervals ``lo[:count], hi[:count]`` (relative bearings in [0, 2π]) in place with
    the circular interval ``[c0, c0 + cw]`` (``c0`` relative, any value; ``cw`` < 2π); returns the new count."""
    c = wrap_positive(c0)
    n = count
    k = 0
    out_lo = np.empty(2 * n)
    out_hi = np.empty(2 * n)
    for i in range(n):
        for shift in (c - TWO_PI, c):
            a = max(lo[i], shift)
            b = min(hi[i], shift + cw)
            if b > a:
                out_lo[k] = a
                out_hi[k] = b
                k += 1
    for i in range(k):
        lo[i] = out_lo[i]
        hi[i] = out_hi[i]
    return k


@njit(cache=True)
def limited_angle(t0, t1, ex, ey, num, wedge_start, fov, max_range):
    """Radians of the bearings ``[t0, t1]`` (``t1 - t0 < 2π``) inside the wedge ``[wedge_start, wedge_start + fov]``
    along which the line ``{p : p x e = num}`` (``e = (ex, ey)``; the line's points relative to the viewpoint) is
    hit within ``max_range`` metres.

    The line is hit within range along bearings ``φ ± arccos(d / max_range)``, ``φ`` the bearing of its foot point,
    ``d`` its distance. With ``fov >= 2π`` and an infinite range the result is ``t1 - t0`` exactly.
    """
    length = t1 - t0
    if fov >= TWO_PI and not math.isfinite(max_range):
        return length
    lo = np.empty(4)
    hi = np.empty(4)
    lo[0] = 0.0
    hi[0] = length
    count = 1
    if fov < TWO_PI:
        count = clip_circular(lo, hi, count, wedge_start - t0, fov)
    if count and math.isfinite(max_range):
        e2 = ex * ex + ey * ey
        distance = abs(num) / math.sqrt(e2)
        if distance >= max_range:
            return 0.0
        scale = num / e2
        foot = math.atan2(-scale * ex, scale * ey)
        half = math.acos(distance / max_range)
        count = clip_circular(lo, hi, count, foot - half - t0, 2.0 * half)
    total = 0.0
    for i in range(count):
        total += hi[i] - lo[i]
    return total


@njit(cache=True, inline="always")
def _relative(px, py, start, width):
    """Bearing of ``(px, py)`` relative to ``start``, for a point of a target whose extent is ``[0, width]``."""
    u = wrap_positive(math.atan2(py, px) - start)
    if u > width:  # rounding just outside the extent: take the nearer end
        u = 0.0 if u > 0.5 * (width + TWO_PI) else width
    return u


@njit(cache=True)
def _inside(px, py, coords, first, last):
    """Whether ``(px, py)`` lies inside the ring ``coords[first:last]`` (crossing number; relative coordinates)."""
    inside = False
    j = last - 1
    for i in range(first, last):
        xi, yi = coords[i, 0], coords[i, 1]
        xj, yj = coords[j, 0], coords[j, 1]
        if (yi > py) != (yj > py) and px < (xj - xi) * (py - yi) / (yj - yi) + xi:
            inside = not inside
        j = i
    return inside


@njit(cache=True)
def _in_range_intervals(coords, first, last, start, width, max_range):
    """Bearings (relative to ``start``) along which the ring ``coords[first:last]`` (relative to the viewpoint,
    which lies outside it) is hit within ``max_range``: sorted, disjoint ``(lo, hi)`` arrays."""
    m = last - first
    lo = np.empty(2 * m + 1)
    hi = np.empty(2 * m + 1)
    crossings = np.empty(2 * m + 2)
    k = 0
    c = 0
    r2 = max_range * max_range
    for i in range(first, last):
        j = i + 1 if i + 1 < last else first
        ax, ay = coords[i, 0], coords[i, 1]
        ex, ey = coords[j, 0] - ax, coords[j, 1] - ay
        e2 = ex * ex + ey * ey
        if e2 == 0.0:
            continue
        ae = ax * ex + ay * ey
        disc = ae * ae - e2 * (ax * ax + ay * ay - r2)
        if disc < 0.0:
            continue
        root = math.sqrt(disc)
        s0 = max((-ae - root) / e2, 0.0)
        s1 = min((-ae + root) / e2, 1.0)
        if s0 > s1:
            continue
        u0 = _relative(ax + s0 * ex, ay + s0 * ey, start, width)
        u1 = _relative(ax + s1 * ex, ay + s1 * ey, start, width)
        lo[k] = min(u0, u1)
        hi[k] = max(u0, u1)
        k += 1
        if s0 > 0.0:
            crossings[c] = u0
            c += 1
        if s1 < 1.0:
            crossings[c] = u1
            c += 1
    # arcs of the range circle inside the target, between consecutive crossings
    crossings = sorted_values(crossings[:c])
    extra_lo = np.empty(c)
    extra_hi = np.empty(c)
    q = 0
    for i in range(c - 1):
        a, b = crossings[i], crossings[i + 1]
        if b - a <= SNAP:
            continue
        mid = start + 0.5 * (a + b)
        if _inside(max_range * math.cos(mid), max_range * math.sin(mid), coords, first, last):
            extra_lo[q] = a
            extra_hi[q] = b
            q += 1
    all_lo = np.concatenate((lo[:k], extra_lo[:q]))
    all_hi = np.concatenate((hi[:k], extra_hi[:q]))
    return _union(all_lo, all_hi, width)


@njit(cache=True)
def _union(lo, hi, width):
    """Sorted union of intervals within ``[0, width]``; ends within :data:`SNAP` of 0 or ``width`` snap to them."""
    order = argsort_stable(lo)
    out_lo = np.empty(len(lo))
    out_hi = np.empty(len(lo))
    k = 0
    for i in order:
        a, b = lo[i], hi[i]
        if a <= SNAP:
            a = 0.0
        if b >= width - SNAP:
            b = width
        if b <= a:
            continue
        if k and a <= out_hi[k - 1]:
            out_hi[k - 1] = max(out_hi[k - 1], b)
        else:
            out_lo[k] = a
            out_hi[k] = b
            k += 1
    return out_lo[:k], out_hi[:k]


@njit(cache=True)
def _view_intervals(coords, offsets, targets, start, width, wedge_start, fov, max_range):
    n = len(offsets) - 1
    off = np.zeros(n + 1, dtype=np.int64)
    out_lo = np.empty(2 * n + 2)
    out_hi = np.empty(2 * n + 2)
    in_fov = np.zeros(n)
    in_view = np.zeros(n)
    fov_lo = np.empty(2)
    fov_hi = np.empty(2)
    limited_range = math.isfinite(max_range)
    r2 = max_range * max_range
    k = 0
    for t in range(n):
        off[t] = k
        if not targets[t]:
            continue
        w = width[t]
        fov_lo[0] = 0.0
        fov_hi[0] = w
        fov_count = 1
        if fov < TWO_PI:
            fov_count = clip_circular(fov_lo, fov_hi, 1, wedge_start - start[t], fov)
        for i in range(fov_count):
            in_fov[t] += fov_hi[i] - fov_lo[i]
        if fov_count == 0:
            continue
        whole = True  # the whole extent within range
        if limited_range:
            near2 = np.inf
            far2 = 0.0
            first, last = offsets[t], offsets[t + 1]
            for i in range(first, last):
                j = i + 1 if i + 1 < last else first
                near2 = min(near2, segment_distance2(coords[i, 0], coords[i, 1], coords[j, 0], coords[j, 1]))
                far2 = max(far2, coords[i, 0] * coords[i, 0] + coords[i, 1] * coords[i, 1])
            if near2 > r2:
                continue
            whole = far2 <= r2
        if whole:
            out_lo = reserve(out_lo, k, k + fov_count)
            out_hi = reserve(out_hi, k, k + fov_count)
            for i in range(fov_count):
                out_lo[k] = fov_lo[i]
                out_hi[k] = fov_hi[i]
                in_view[t] += fov_hi[i] - fov_lo[i]
                k += 1
            continue
        lo, hi = _in_range_intervals(coords, offsets[t], offsets[t + 1], start[t], w, max_range)
        out_lo = reserve(out_lo, k, k + 2 * len(lo))
        out_hi = reserve(out_hi, k, k + 2 * len(lo))
        for f in range(fov_count):  # both lists are sorted and disjoint; the fov's intervals are apart
            for i in range(len(lo)):
                a = max(lo[i], fov_lo[f])
                b = min(hi[i], fov_hi[f])
                if b > a:
                    out_lo[k] = a
                    out_hi[k] = b
                    in_view[t] += b - a
                    k += 1
    off[n] = k
    return off, out_lo[:k], out_hi[:k], in_fov, in_view


def view_intervals(
    coords: np.ndarray,
    offsets: np.ndarray,
    targets: np.ndarray,
    start: np.ndarray,
    width: np.ndarray,
    wedge_start: float,
    fov: float,
    max_range: float,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """The in-view directions of each target, ignoring occlusion.

    Parameters
    ----------
    coords, offsets : ndarray
        The objects' rings relative to the viewpoint (metres), ragged (``offsets`` shape (n + 1,)).
    targets : ndarray of bool, shape (n,)
        Objects to compute (the viewpoint outside each); others get no interval.
    start, width : ndarray, shape (n,)
        Angular extents (:func:`..geometry.angular_extent`), radians.
    wedge_start, fov : float
        The field of view ``[wedge_start, wedge_start + fov]``, radians (``fov >= 2π``: all around).
    max_range : float
        Metres (``inf``: no limit).

    Returns
    -------
    offsets : ndarray, shape (n + 1,), int64
        Target ``t``'s intervals are ``lo[offsets[t]:offsets[t + 1]]``, ``hi[...]``.
    lo, hi : ndarray
        Bearings relative to the target's ``start``, sorted and disjoint, within ``[0, width]``.
    in_fov : ndarray, shape (n,)
        Radians of the extent inside the wedge (range ignored).
    in_view : ndarray, shape (n,)
        Radians of in-view directions (the intervals' total).

    Examples
    --------
    A 2 m square 10 m ahead seen through a wedge that covers its left half, then with a range of 9.05 m (its
    near side, 9 m away, is within range for ``|y| <= sqrt(9.05² - 9²)``):

    >>> from .rings import box_rings, angular_extent
    >>> sq = box_rings(np.array([10.0]), np.array([0.0]), np.array([2.0]), np.array([2.0]), np.array([0.0]))
    >>> start, width, _ = angular_extent(np.zeros(2), sq)
    >>> off, lo, hi, in_fov, in_view = view_intervals(sq.coords, sq.offsets, np.array([True]), start, width,
    ...     0.0, 1.0, np.inf)
    >>> bool(np.isclose(in_view[0], width[0] / 2)), bool(np.isclose(in_fov[0], in_view[0]))
    (True, True)
    >>> in_view = view_intervals(sq.coords, sq.offsets, np.array([True]), start, width, 0.0, 2 * np.pi, 9.05)[4]
    >>> bool(np.isclose(in_view[0], 2 * np.arctan(np.sqrt(9.05**2 - 81) / 9)))
    True
    """
    return _view_intervals(
        np.ascontiguousarray(coords, dtype=np.float64),
        np.asarray(offsets, dtype=np.int64),
        np.asarray(targets, dtype=np.bool_),
        np.asarray(start, dtype=np.float64),
        np.asarray(width, dtype=np.float64),
        float(wedge_start),
        float(fov),
        float(max_range),
    )
