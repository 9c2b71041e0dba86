"""The region a viewpoint sees, as a polygon, from the sweep's nearest pieces (step 3's intervals).

Within each interval of the sweep the boundary of the seen region runs along the nearest piece's edge, or, where
that edge lies beyond range (or nothing is hit), along the range circle; inside a field of view narrower than
2π the region is a wedge with its apex at the viewpoint. The region is star-shaped around the viewpoint, so its
vertices in bearing order give a simple polygon. Edges are exact; arcs of the range circle are drawn as chords
every ``arc_step`` radians.
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import reserve_rows, wrap_positive
from ...geometry.sorting import argsort_stable
from ...geometry.view import clip_circular
from .heap_sweep import nearest_intervals
from .pieces import EX, EY, NUM, PI, TWO_PI

SAME_POINT = 1e-9  # relative distance under which two consecutive outline points are one


@njit(cache=True)
def _arc(out, k, radius, a, b, arc_step):
    """Append the points of the arc of ``radius`` from bearing ``a`` to ``b`` (chords of at most ``arc_step``)."""
    steps = max(1, math.ceil((b - a) / arc_step))
    out = reserve_rows(out, k, k + steps + 1)
    for i in range(steps + 1):
        t = a + (b - a) * i / steps
        out[k, 0] = radius * math.cos(t)
        out[k, 1] = radius * math.sin(t)
        k += 1
    return out, k


@njit(cache=True)
def _line_point(out, k, ex, ey, num, t):
    out = reserve_rows(out, k, k + 1)
    c, s = math.cos(t), math.sin(t)
    r = num / (c * ey - s * ex)
    out[k, 0] = r * c
    out[k, 1] = r * s
    return out, k + 1


@njit(cache=True)
def visible_outline(pieces, wedge_start, fov, radius, arc_step):
    """Vertices (metres, relative to the viewpoint, counter-clockwise) of the region seen.

    Parameters
    ----------
    pieces : ndarray, shape (k, 9)
        The piece table of :mod:`.pieces` (nothing farther than ``radius`` needs to be in it).
    wedge_start, fov : float
        The field of view ``[wedge_start, wedge_start + fov]``, radians (``fov >= 2π``: all around).
    radius : float
        The range, metres (finite: callers bound an unlimited range).
    arc_step : float
        Radians between the points drawn on arcs of the range circle.
    """
    lo, hi, top, _, _ = nearest_intervals(pieces)
    # the whole circle, bearing order: the sweep's intervals and the gaps between them (top -1)
    q = len(lo)
    all_lo = np.empty(2 * q + 1)
    all_hi = np.empty(2 * q + 1)
    all_top = np.empty(2 * q + 1, dtype=np.int64)
    n = 0
    current = -PI
    for i in range(q):
        if lo[i] > current:
            all_lo[n], all_hi[n], all_top[n] = current, lo[i], -1
            n += 1
        all_lo[n], all_hi[n], all_top[n] = lo[i], hi[i], top[i]
        n += 1
        current = hi[i]
    if current < PI:
        all_lo[n], all_hi[n], all_top[n] = current, PI, -1
        n += 1
    # clipped to the wedge, in bearing order from its start
    base = wedge_start if fov < TWO_PI else -PI
    sub_lo = np.empty(2 * n)
    sub_hi = np.empty(2 * n)
    sub_top = np.empty(2 * n, dtype=np.int64)
    sub_key = np.empty(2 * n)
    m = 0
    for i in range(n):
        a, b = all_lo[i], all_hi[i]
        if b <= a:
            continue
        part_lo = np.zeros(2)
        part_hi = np.full(2, b - a)
        count = 1
        if fov < TWO_PI:
            count = clip_circular(part_lo, part_hi, count, wedge_start - a, fov)
        for p in range(count):
            sub_lo[m] = a + part_lo[p]
            sub_hi[m] = a + part_hi[p]
            sub_top[m] = all_top[i]
            middle = 0.5 * (sub_lo[m] + sub_hi[m])  # the start may round to just before the wedge's start
            sub_key[m] = wrap_positive(middle - base) if fov < TWO_PI else middle - base
            m += 1
    order = argsort_stable(sub_key[:m])
    out = np.empty((4 * m + 8, 2))
    k = 0
    if fov < TWO_PI:
        out[0, 0] = 0.0
        out[0, 1] = 0.0
        k = 1
    for o in order:
        a, b, t = sub_lo[o], sub_hi[o], sub_top[o]
        if t < 0:
            out, k = _arc(out, k, radius, a, b, arc_step)
            continue
        ex, ey, num = pieces[t, EX], pieces[t, EY], pieces[t, NUM]
        e2 = ex * ex + ey * ey
        distance = abs(num) / math.sqrt(e2)
        if distance >= radius:
            out, k = _arc(out, k, radius, a, b, arc_step)
            continue
        scale = num / e2
        foot = math.atan2(-scale * ex, scale * ey)
        foot += TWO_PI * math.floor((0.5 * (a + b) - foot) / TWO_PI + 0.5)  # the representative nearest the interval
        half = math.acos(distance / radius)
        near_lo = max(a, foot - half)
        near_hi = min(b, foot + half)
        if near_hi <= near_lo:
            out, k = _arc(out, k, radius, a, b, arc_step)
            continue
        if near_lo > a:
            out, k = _arc(out, k, radius, a, near_lo, arc_step)
        out, k = _line_point(out, k, ex, ey, num, near_lo)
        out, k = _line_point(out, k, ex, ey, num, near_hi)
        if near_hi < b:
            out, k = _arc(out, k, radius, near_hi, b, arc_step)
    return _without_repeats(out[:k])


@njit(cache=True)
def _without_repeats(points):
    """``points`` without those within ``SAME_POINT`` (relative to their distance) of the previous one kept: two
    edges meeting at a corner give it twice, and the rounded copies could otherwise turn back by 1e-15 m."""
    keep = np.ones(len(points), dtype=np.bool_)
    last = 0
    for i in range(1, len(points)):
        dx, dy = points[i, 0] - points[last, 0], points[i, 1] - points[last, 1]
        scale = 1.0 + abs(points[i, 0]) + abs(points[i, 1])
        if dx * dx + dy * dy <= (SAME_POINT * scale) ** 2:
            keep[i] = False
        else:
            last = i
    return points[keep]
