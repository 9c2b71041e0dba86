"""The area and boundary of a union of star-shaped polygons, without building the union (compiled).

Each polygon ``P_j`` is star-shaped around its centre ``c_j`` (a sensor's position) and given counter-clockwise
with its vertices in bearing order around ``c_j`` (what :func:`.engines.sweep.outline.visible_outline` gives; a
field of view narrower than 2π starts with the apex ``c_j`` itself). By Green's theorem the union's area is
``1/2 ∮ x dy - y dx`` along its boundary, and that boundary is made of the pieces of the polygons' edges that no
other polygon covers. So each edge is split where other polygons' edges cross it (or, lying along it, begin and
end), and each piece counts when its midpoint lies outside every other polygon; a piece along another polygon's
edge in the same direction counts for the lower-numbered polygon only, one in the opposite direction (the two
polygons on either side) for neither.

The star shape makes both steps cheap: the edges of ``P_j`` that can meet a segment are those whose bearings from
``c_j`` overlap the segment's, and whether a point lies in ``P_j`` is decided by the one edge at its bearing, both
found by binary search in the vertices' bearings (on the ray of a radial edge, a shadow's side, where that edge
says nothing, by the edges on either side of the ray). Points within :data:`ON_EDGE` (relative to the coordinates'
magnitude) of an edge count as on it: two sensors seeing the same face of a road user give two copies of the face's
line that differ by rounding (1e-13 m), and must be recognised as one boundary.

:func:`union_pieces` also gives the uncovered pieces themselves, the union's boundary, from which
:mod:`.union_rings` builds the union; :func:`star_union_area` is its area alone.
"""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit
from .kernels import TWO_PI

ON_EDGE = 1e-10
"""Distance (relative to ``1 +`` the largest coordinate, metres) within which a point counts as on an edge."""
PARALLEL = 1e-12
"""Sine of the angle below which two edges are taken as parallel (their crossing is not computed)."""
FULL = 4.0
"""A whole turn in the pseudo-bearings of :func:`_angle`."""
BEARING_MARGIN = 1e-9
"""Pseudo-bearing (about radians) by which the window of candidate edges is widened (extras only cost time)."""


@njit(cache=True, inline="always")
def _cross(ax, ay, bx, by):
    return ax * by - ay * bx


@njit(cache=True, inline="always")
def _remainder(angle, period):
    """``angle`` less the nearest multiple of ``period`` (``math.remainder``, which numba lacks)."""
    return angle - period * math.floor(angle / period + 0.5)


@njit(cache=True, inline="always")
def _angle(x, y, center, turn):
    """Pseudo-bearing of (x, y) around ``center``, in ``[0, 4)`` from the bearing whose cosine and sine are
    ``turn``: a monotone function of the bearing (``FULL`` a whole turn, opposite directions 2 apart, slope
    between 1/2 and 1 per radian) that needs no ``atan2``."""
    vx, vy = x - center[0], y - center[1]
    u = vx * turn[0] + vy * turn[1]
    v = vy * turn[0] - vx * turn[1]
    if v >= 0.0:
        if u >= 0.0:
            return v / (u + v) if u + v > 0.0 else 0.0
        return 1.0 - u / (v - u)
    if u < 0.0:
        return 2.0 - v / (-u - v)
    a = 3.0 + u / (u - v)
    return a if a < FULL else 0.0


@njit(cache=True)
def _bearings(points, start, count, center, turn, wedge, end):
    """Pseudo-bearings (see :func:`_angle`; non-decreasing, ``count + 1`` of them: the last closes the ring) of
    one polygon's vertices around its centre; a wedge's apex gets 0 and its closing edge ``end``, the
    pseudo-bearing of the field of view's end."""
    theta = np.empty(count + 1)
    first = 1 if wedge else 0
    if wedge:
        theta[0] = 0.0
    previous = 0.0
    for k in range(first, count):
        b = _angle(points[start + k, 0], points[start + k, 1], center, turn)
        if k == first:  # on the ray at the start (up to rounding): the representative nearest 0
            value = _remainder(b, FULL)
        else:  # consecutive vertices are less than half a turn apart (an edge seen from outside spans less)
            value = previous + _remainder(b - previous, FULL)
        previous = max(previous, value) if k > first else value
        theta[k] = previous
    theta[count] = max(end if wedge else FULL, theta[count - 1])
    return theta


@njit(cache=True)
def _segment_distance(px, py, ax, ay, bx, by):
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 == 0.0 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2))
    ex, ey = ax + t * dx - px, ay + t * dy - py
    return math.sqrt(ex * ex + ey * ey)


@njit(cache=True)
def _covered(mx, my, dx, dy, i, j, points, start, count, center, turn, wedge, theta, o, tol):
    """Whether polygon ``j`` covers the point (mx, my) of an edge of polygon ``i`` running along (dx, dy): inside
    it, or on one of its edges in the opposite direction, or in the same direction when ``j < i``."""
    a = _angle(mx, my, center, turn)
    k = min(max(_search(theta, o, count, a, True) - 1, 0), count - 1)
    outside = wedge and a > theta[o + count]
    main = k - 1 if theta[o + k + 1] <= theta[o + k] and k > 0 else k  # past the last vertex: not the radial edge
    ax, ay = points[start + main, 0], points[start + main, 1]
    f = start + (main + 1) % count
    ex, ey = points[f, 0] - ax, points[f, 1] - ay
    side = _cross(ex, ey, mx - ax, my - ay)
    # near the edge's line, or near a bearing where radial edges meet it: which edge is it on, if any
    r = math.sqrt((mx - center[0]) ** 2 + (my - center[1]) ** 2)
    near = outside or side * side <= tol * tol * (ex * ex + ey * ey)
    # pseudo-bearing gaps are at most the angles' gaps: this finds all points within 2 tol of a vertex's ray
    near = near or (a - theta[o + k]) * r <= 2.0 * tol or (theta[o + k + 1] - a) * r <= 2.0 * tol
    if near:
        for step in range(-1, 2):  # the edge at the bearing and its neighbours (radial edges at the same bearing)
            e = (k + step) % count
            px, py = points[start + e, 0], points[start + e, 1]
            g = start + (e + 1) % count
            qx, qy = points[g, 0], points[g, 1]
            if (px != qx or py != qy) and _segment_distance(mx, my, px, py, qx, qy) <= tol:
                return (qx - px) * dx + (qy - py) * dy < 0.0 or j < i
        if _radial(points, start, count, main, center, tol):
            # on the ray of a radial edge but off it, where ``side`` is rounding: inside where inside the edges
            # on both sides of the ray (the wedge's apex edges, radial too, say nothing)
            inside, seen = True, False
            for e in ((main + count - 1) % count, (main + 1) % count):
                if not _radial(points, start, count, e, center, tol):
                    px, py = points[start + e, 0], points[start + e, 1]
                    g = start + (e + 1) % count
                    seen = True
                    inside = inside and _cross(points[g, 0] - px, points[g, 1] - py, mx - px, my - py) > 0.0
            return not outside and seen and inside
    return not outside and side > 0.0


@njit(cache=True)
def _radial(points, start, count, e, center, tol):
    """Whether edge ``e`` of a polygon lies along a ray from its centre (its line within ``tol`` of it)."""
    px, py = points[start + e, 0], points[start + e, 1]
    g = start + (e + 1) % count
    ex, ey = points[g, 0] - px, points[g, 1] - py
    off = _cross(ex, ey, center[0] - px, center[1] - py)
    return off * off <= tol * tol * (ex * ex + ey * ey)


@njit(cache=True)
def _add_splits(splits, n, ax, ay, bx, by, cx, cy, ex, ey, tol, canonical):
    """Append to ``splits`` (rows: parameter along a-b, x, y) the points where c-e crosses a-b or, lying along it,
    begins or ends. A crossing's point is computed along the ``canonical`` edge of the two (a-b if True), the
    same way from either edge's side, so the pieces the two edges end and start there meet exactly."""
    if max(cx, ex) < min(ax, bx) - tol or min(cx, ex) > max(ax, bx) + tol:
        return n
    if max(cy, ey) < min(ay, by) - tol or min(cy, ey) > max(ay, by) + tol:
        return n
    rx, ry = bx - ax, by - ay
    sx, sy = ex - cx, ey - cy
    d = _cross(rx, ry, sx, sy)
    len_r = math.sqrt(rx * rx + ry * ry)
    len_s = math.sqrt(sx * sx + sy * sy)
    if abs(d) > PARALLEL * len_r * len_s:
        # seen from c-e, d changes sign and both cross products too: t and u are the same to the bit
        t = _cross(cx - ax, cy - ay, sx, sy) / d
        u = _cross(cx - ax, cy - ay, rx, ry) / d
        slack = tol / len_s
        if 0.0 < t < 1.0 and -slack <= u <= 1.0 + slack:
            splits[n, 0] = t
            splits[n, 1], splits[n, 2] = (ax + t * rx, ay + t * ry) if canonical else (cx + u * sx, cy + u * sy)
            n += 1
    if abs(_cross(rx, ry, cx - ax, cy - ay)) <= tol * len_r or abs(_cross(rx, ry, ex - ax, ey - ay)) <= tol * len_r:
        for px, py in ((cx, cy), (ex, ey)):  # along a-b: its ends split a-b (extra splits are harmless)
            t = ((px - ax) * rx + (py - ay) * ry) / (len_r * len_r)
            if 0.0 < t < 1.0:
                splits[n, 0], splits[n, 1], splits[n, 2] = t, px, py  # the vertex itself: other pieces end there
                if abs(_cross(rx, ry, px - ax, py - ay)) > tol * len_r:  # off a-b: its projection
                    splits[n, 1], splits[n, 2] = ax + t * rx, ay + t * ry
                n += 1
    return n


@njit(cache=True)
def star_union_area(points, starts, centers, bases, fovs):
    """Area (square metres) of the union of star-shaped polygons.

    Parameters
    ----------
    points : ndarray, shape (n, 2)
        The polygons' vertices, one after the other, each counter-clockwise in bearing order around its centre
        (metres; best near the origin, e.g. relative to the observer, for rounding); a polygon with a field of
        view narrower than 2π starts with its apex, its centre.
    starts : ndarray, shape (p + 1,), int64
        Polygon ``j`` is ``points[starts[j]:starts[j + 1]]``.
    centers : ndarray, shape (p, 2)
        The centres the polygons are star-shaped around, same frame as ``points``.
    bases, fovs : ndarray, shape (p,)
        Bearing (radians) where each polygon's vertices start, and its angular extent (radians, ``>= 2π``: all
        around, then ``bases`` is the bearing of its first vertex).
    """
    return union_pieces(points, starts, centers, bases, fovs, False)[0]


@njit(cache=True)
def union_pieces(points, starts, centers, bases, fovs, collect):
    """The union's area and, when ``collect``, its boundary: the uncovered pieces of the polygons' edges.

    Parameters as for :func:`star_union_area`. Returns the area (square metres), the pieces (rows ``x0, y0, x1,
    y1``, metres, each directed as its polygon's edge, so the union lies to their left; none unless ``collect``;
    pieces at most twice the tolerance long are left out) and the tolerance (metres) within which points count as
    one.
    """
    p = len(starts) - 1
    tol = ON_EDGE * (1.0 + np.abs(points).max()) if len(points) else 0.0
    wedges = fovs < TWO_PI
    turns = np.empty((p, 2))
    turns[:, 0], turns[:, 1] = np.cos(bases), np.sin(bases)
    thetas = np.zeros(len(points) + p)  # polygon j's bearings at starts[j] + j
    boxes = np.empty((p, 4))
    for j in range(p):
        s, c = starts[j], starts[j + 1] - starts[j]
        if c >= 3:
            end = _angle(math.cos(bases[j] + fovs[j]), math.sin(bases[j] + fovs[j]), np.zeros(2), turns[j])
            thetas[s + j : s + j + c + 1] = _bearings(points, s, c, centers[j], turns[j], wedges[j], end)
            boxes[j, 0], boxes[j, 1] = points[s : s + c, 0].min() - tol, points[s : s + c, 1].min() - tol
            boxes[j, 2], boxes[j, 3] = points[s : s + c, 0].max() + tol, points[s : s + c, 1].max() + tol
    angles = np.full((len(points), p), np.nan)  # bearing of vertex v around centre j, computed when first needed
    splits = np.empty((64, 3))  # where other polygons' edges split the current edge: parameter along it, x, y
    spans = np.empty((64, 6))  # the pieces of the current edge covered so far: parameters along it, ends' x, y
    pieces = np.empty((len(points) + 16 if collect else 0, 4))
    count = 0
    order = np.arange(p)
    twice = 0.0
    for i in range(p):
        si, ci = starts[i], starts[i + 1] - starts[i]
        if ci < 3:
            continue
        for k in range(ci):
            va, vb = si + k, si + (k + 1) % ci
            ax, ay, bx, by = points[va, 0], points[va, 1], points[vb, 0], points[vb, 1]
            if ax == bx and ay == by:
                continue
            lo_x, hi_x, lo_y, hi_y = min(ax, bx), max(ax, bx), min(ay, by), max(ay, by)
            dx, dy = bx - ax, by - ay
            m = 0
            whole = False
            for jj in range(p):
                j = order[jj]  # the polygon that covered the last edge first: it likely covers this one too
                sj, cj = starts[j], starts[j + 1] - starts[j]
                if j == i or cj < 3:
                    continue
                if hi_x < boxes[j, 0] or lo_x > boxes[j, 2] or hi_y < boxes[j, 1] or lo_y > boxes[j, 3]:
                    continue
                o = sj + j  # polygon j's bearings: thetas[o : o + cj + 1]
                off = _cross(dx, dy, centers[j, 0] - ax, centers[j, 1] - ay)
                through = off * off <= (1e3 * tol) ** 2 * (dx * dx + dy * dy)
                if through and _segment_distance(centers[j, 0], centers[j, 1], ax, ay, bx, by) <= 1e3 * tol:
                    first, last = 0, cj  # through the centre: bearings say nothing
                else:
                    if math.isnan(angles[va, j]):
                        angles[va, j] = _angle(ax, ay, centers[j], turns[j])
                    if math.isnan(angles[vb, j]):
                        angles[vb, j] = _angle(bx, by, centers[j], turns[j])
                    first, last = _candidates(angles[va, j], angles[vb, j], thetas, o, cj)
                if splits.shape[0] < 3 * (last - first + 4):
                    splits = np.empty((6 * (last - first + 4), 3))
                splits[0, 0], splits[0, 1], splits[0, 2] = 0.0, ax, ay
                splits[1, 0], splits[1, 1], splits[1, 2] = 1.0, bx, by
                n = 2
                for q in range(first, last):
                    e = q % cj
                    f = (e + 1) % cj
                    n = _add_splits(
                        splits, n, ax, ay, bx, by, points[sj + e, 0], points[sj + e, 1], points[sj + f, 0],
                        points[sj + f, 1], tol, i < j,
                    )  # fmt: skip
                if wedges[j]:  # the two edges through the apex, whatever the bearings
                    for e in (0, cj - 1):
                        f = (e + 1) % cj
                        n = _add_splits(
                            splits, n, ax, ay, bx, by, points[sj + e, 0], points[sj + e, 1], points[sj + f, 0],
                            points[sj + f, 1], tol, i < j,
                        )  # fmt: skip
                _sort_rows(splits, n)
                if spans.shape[0] < m + n:
                    grown = np.empty((2 * (m + n), 6))
                    grown[:m] = spans[:m]
                    spans = grown
                for q in range(n - 1):
                    t0, t1 = splits[q, 0], splits[q + 1, 0]
                    if t1 <= t0:
                        continue
                    tm = 0.5 * (t0 + t1)
                    mx, my = ax + tm * dx, ay + tm * dy
                    if mx < boxes[j, 0] or mx > boxes[j, 2] or my < boxes[j, 1] or my > boxes[j, 3]:
                        continue
                    if _covered(mx, my, dx, dy, i, j, points, sj, cj, centers[j], turns[j], wedges[j], thetas, o, tol):
                        spans[m, 0], spans[m, 1] = t0, t1
                        spans[m, 2], spans[m, 3] = splits[q, 1], splits[q, 2]
                        spans[m, 4], spans[m, 5] = splits[q + 1, 1], splits[q + 1, 2]
                        m += 1
                if m == 1 and spans[0, 0] == 0.0 and spans[0, 1] == 1.0:
                    whole = True
                    order[jj], order[0] = order[0], order[jj]
                    break
            if not whole:
                _sort_rows(spans, m)
                twice += (1.0 - _covered_length(spans, m)) * _cross(ax, ay, bx, by)
                if collect:
                    pieces, count = _gaps(spans, m, ax, ay, bx, by, pieces, count, tol)
    return 0.5 * twice, pieces[:count], tol


@njit(cache=True)
def _sort_rows(rows, n):
    """Sort ``rows[:n]`` in place by their first column (a few rows, mostly in order: no allocation)."""
    for a in range(1, n):
        b = a - 1
        while b >= 0 and rows[b, 0] > rows[b + 1, 0]:
            for c in range(rows.shape[1]):
                rows[b, c], rows[b + 1, c] = rows[b + 1, c], rows[b, c]
            b -= 1


@njit(cache=True)
def _covered_length(spans, m):
    """Total length of the union of the intervals ``spans[:m, :2]`` (sorted by start)."""
    if m == 0:
        return 0.0
    total = 0.0
    lo, hi = spans[0, 0], spans[0, 1]
    for q in range(1, m):
        if spans[q, 0] > hi:
            total += hi - lo
            lo, hi = spans[q, 0], spans[q, 1]
        else:
            hi = max(hi, spans[q, 1])
    return total + hi - lo


@njit(cache=True)
def _gaps(spans, m, ax, ay, bx, by, pieces, count, tol):
    """Append to ``pieces`` (rows ``x0, y0, x1, y1``) the parts of the edge a-b outside the covered ``spans[:m]``
    (sorted by start; columns: parameters, then the ends' x, y) that are longer than ``2 tol``."""
    x, y, reach = ax, ay, 0.0  # the end of the covered part so far
    for q in range(m + 1):
        if q < m and spans[q, 0] <= reach:
            if spans[q, 1] > reach:
                x, y, reach = spans[q, 4], spans[q, 5], spans[q, 1]
            continue
        ex, ey = (spans[q, 2], spans[q, 3]) if q < m else (bx, by)
        if q == m and reach >= 1.0:
            break
        if (ex - x) ** 2 + (ey - y) ** 2 > 4.0 * tol * tol:
            if count == len(pieces):
                grown = np.empty((2 * count + 16, 4))
                grown[:count] = pieces[:count]
                pieces = grown
            pieces[count, 0], pieces[count, 1], pieces[count, 2], pieces[count, 3] = x, y, ex, ey
            count += 1
        if q < m:
            x, y, reach = spans[q, 4], spans[q, 5], spans[q, 1]
    return pieces, count


@njit(cache=True, inline="always")
def _search(theta, o, count, value, right):
    """``np.searchsorted(theta[o : o + count + 1], value, side)`` without the slice."""
    lo, hi = 0, count + 1
    while lo < hi:
        mid = (lo + hi) >> 1
        if theta[o + mid] < value or (right and theta[o + mid] == value):
            lo = mid + 1
        else:
            hi = mid
    return lo


@njit(cache=True)
def _candidates(a, b, theta, o, count):
    """Range ``[first, last)`` of edge numbers (modulo ``count``) of a star polygon (bearings
    ``theta[o : o + count + 1]``) whose bearings overlap those of a segment with ends at bearings ``a``, ``b``."""
    span = _remainder(b - a, FULL)
    lo = (a if span >= 0.0 else b) - BEARING_MARGIN
    hi = lo + abs(span) + 2.0 * BEARING_MARGIN
    if lo < 0.0:  # the window wraps past the start: two ranges, given as one through the end
        lo += FULL
        hi += FULL
    first = max(_search(theta, o, count, lo, False) - 1, 0)
    if hi <= FULL:
        last = min(_search(theta, o, count, hi, True), count)
        return first, max(last, first)
    last = min(_search(theta, o, count, hi - FULL, True), count)
    return first, count + last
