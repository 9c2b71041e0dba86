"""Convex polygon clipping in compiled loops, for the area measure's common case (every body convex).

A polygon is ``buffer[:count]`` of an array of shape (capacity, 2), counter-clockwise, metres relative to the
viewpoint (the origin). Clipping a convex polygon by a line keeps it convex; subtracting a convex polygon ``S``
from a convex ``P`` leaves the disjoint convex pieces ``P ∩ H_1 ∩ .. ∩ H_{i-1} ∩ ¬H_i`` (``H_i`` the inner side of
``S``'s ``i``-th edge), so "a target minus every shadow" is a list of convex pieces, measured exactly (inside a
range circle by a closed formula per edge).

- :func:`clip_line`: a convex polygon on one side of a line;
- :func:`polygon_area` and :func:`disc_area`: area, and area inside the circle of a radius about the origin;
- :func:`convex_hull`: Andrew's monotone chain, counter-clockwise;
- :func:`subtract`: convex pieces minus one convex polygon;
- :func:`clip_half_plane`, :func:`clip_convex`: a convex polygon on one side of ``m0 + m1 x + m2 y >= 0``, and
  within another convex polygon;
- :func:`drop_repeats`: a ring without the vertices that repeat the one before up to rounding.

Each returns a count, or -1 where a buffer would overflow (the caller then takes the general path).
"""

from __future__ import annotations

import math

from .._compiled.kernel import njit
from .kernels import copy_rows

SHORT_EDGE = 1e-13
"""Length (relative to ``1 +`` the largest coordinate) under which an edge of a subtracted shape has no direction."""


@njit(cache=True)
def clip_line(src, n, ax, ay, bx, by, left, dst):
    """``src[:n]`` (convex) clipped to the left (``left``) or right of the directed line ``a -> b``, into
    ``dst``; the new count (boundary points are kept on both sides)."""
    m = 0
    if n == 0:
        return 0
    ex, ey = bx - ax, by - ay
    px, py = src[n - 1, 0], src[n - 1, 1]
    fp = ex * (py - ay) - ey * (px - ax)
    if not left:
        fp = -fp
    for i in range(n):
        qx, qy = src[i, 0], src[i, 1]
        fq = ex * (qy - ay) - ey * (qx - ax)
        if not left:
            fq = -fq
        if (fp >= 0.0) != (fq >= 0.0):
            if m >= len(dst):
                return -1
            t = fp / (fp - fq)
            dst[m, 0], dst[m, 1] = px + t * (qx - px), py + t * (qy - py)
            m += 1
        if fq >= 0.0:
            if m >= len(dst):
                return -1
            dst[m, 0], dst[m, 1] = qx, qy
            m += 1
        px, py, fp = qx, qy, fq
    return m if m >= 3 else 0


@njit(cache=True)
def polygon_area(poly, n):
    """Area (square metres) of the polygon ``poly[:n]`` (positive when counter-clockwise)."""
    total = 0.0
    for i in range(n):
        j = (i + 1) % n
        total += poly[i, 0] * poly[j, 1] - poly[i, 1] * poly[j, 0]
    return 0.5 * total


@njit(cache=True)
def _segment_disc(ax, ay, bx, by, radius):
    """Signed area of the triangle (origin, a, b) inside the circle of ``radius`` about the origin."""
    dx, dy = bx - ax, by - ay
    qa = dx * dx + dy * dy
    if qa <= 0.0:
        return 0.0
    qb = 2.0 * (ax * dx + ay * dy)
    qc = ax * ax + ay * ay - radius * radius
    root = math.sqrt(max(qb * qb - 4.0 * qa * qc, 0.0))
    t1 = min(max((-qb - root) / (2.0 * qa), 0.0), 1.0)
    t2 = min(max((-qb + root) / (2.0 * qa), 0.0), 1.0)
    p1x, p1y, p2x, p2y = ax + t1 * dx, ay + t1 * dy, ax + t2 * dx, ay + t2 * dy
    r2 = 0.5 * radius * radius
    first = r2 * math.atan2(ax * p1y - ay * p1x, ax * p1x + ay * p1y)
    last = r2 * math.atan2(p2x * by - p2y * bx, p2x * bx + p2y * by)
    return first + 0.5 * (p1x * p2y - p1y * p2x) + last


@njit(cache=True)
def disc_area(poly, n, radius):
    """Area (square metres) of the polygon ``poly[:n]`` inside the circle of ``radius`` metres about the origin
    (all of it for an infinite radius)."""
    if not math.isfinite(radius):
        return abs(polygon_area(poly, n))
    total = 0.0
    for i in range(n):
        j = (i + 1) % n
        total += _segment_disc(poly[i, 0], poly[i, 1], poly[j, 0], poly[j, 1], radius)
    return abs(total)


@njit(cache=True)
def convex_hull(points, k, out):
    """Andrew's monotone chain: the convex hull of ``points[:k]`` counter-clockwise into ``out``; its count."""
    pts = points[:k].copy()
    for i in range(1, k):  # insertion sort by (x, y): a few points
        j = i
        while j > 0 and (pts[j - 1, 0] > pts[j, 0] or (pts[j - 1, 0] == pts[j, 0] and pts[j - 1, 1] > pts[j, 1])):
            tx, ty = pts[j - 1, 0], pts[j - 1, 1]
            pts[j - 1, 0], pts[j - 1, 1] = pts[j, 0], pts[j, 1]
            pts[j, 0], pts[j, 1] = tx, ty
            j -= 1
    if len(out) < 2 * k:
        return -1
    m = 0
    for i in range(k):  # lower hull
        while m >= 2 and _turn(out[m - 2], out[m - 1], pts[i]) <= 0.0:
            m -= 1
        out[m, 0], out[m, 1] = pts[i, 0], pts[i, 1]
        m += 1
    low = m + 1
    for i in range(k - 2, -1, -1):  # upper hull
        while m >= low and _turn(out[m - 2], out[m - 1], pts[i]) <= 0.0:
            m -= 1
        out[m, 0], out[m, 1] = pts[i, 0], pts[i, 1]
        m += 1
    return m - 1 if m > 1 else m


@njit(cache=True, inline="always")
def _turn(o, a, b):
    return (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])


@njit(cache=True)
def subtract(pieces, counts, n_pieces, shape, k, out, out_counts, scratch):
    """The convex ``pieces[:n_pieces]`` (each ``pieces[p, :counts[p]]``) minus the convex ``shape[:k]``, as
    disjoint convex pieces into ``out``/``out_counts``; their number, or -1 on overflow. Pieces whose bounding
    boxes miss the shape's are passed on whole; edges of the shape shorter than :data:`SHORT_EDGE` (relative to
    its coordinates) are passed over (a repeated vertex)."""
    if k < 3:
        for p in range(n_pieces):
            copy_rows(out[p], 0, pieces[p, : counts[p]])
            out_counts[p] = counts[p]
        return n_pieces
    sx0, sy0 = shape[:k, 0].min(), shape[:k, 1].min()
    sx1, sy1 = shape[:k, 0].max(), shape[:k, 1].max()
    scale = 1.0 + max(abs(sx0), abs(sy0), abs(sx1), abs(sy1))
    rest, other = scratch[0], scratch[1]
    made = 0
    for p in range(n_pieces):
        c = counts[p]
        poly = pieces[p]
        if (poly[:c, 0].max() <= sx0 or poly[:c, 0].min() >= sx1 or poly[:c, 1].max() <= sy0
                or poly[:c, 1].min() >= sy1):  # fmt: skip
            if made >= len(out):
                return -1
            copy_rows(out[made], 0, poly[:c])
            out_counts[made] = c
            made += 1
            continue
        copy_rows(rest, 0, poly[:c])
        n_rest = c
        for i in range(k):
            j = (i + 1) % k
            if abs(shape[j, 0] - shape[i, 0]) + abs(shape[j, 1] - shape[i, 1]) <= SHORT_EDGE * scale:
                continue  # no direction to cut along: its two sides would both keep the whole piece
            if made >= len(out):
                return -1
            m = clip_line(rest, n_rest, shape[i, 0], shape[i, 1], shape[j, 0], shape[j, 1], False, out[made])
            if m < 0:
                return -1
            if m >= 3 and abs(polygon_area(out[made], m)) > 0.0:
                out_counts[made] = m
                made += 1
            n_rest = clip_line(rest, n_rest, shape[i, 0], shape[i, 1], shape[j, 0], shape[j, 1], True, other)
            if n_rest < 0:
                return -1
            rest, other = other, rest
            if n_rest < 3:
                break
        rest, other = scratch[0], scratch[1]
    return made


@njit(cache=True)
def clip_half_plane(src, n, m0, m1, m2, dst):
    """``src[:n]`` (convex) clipped to ``m0 + m1 u + m2 v >= 0`` into ``dst``; the new count (0 when fewer than
    3 vertices are left), -1 when ``dst`` is too small."""
    if n == 0:
        return 0
    k = 0
    pg = m0 + m1 * src[n - 1, 0] + m2 * src[n - 1, 1]
    px, py = src[n - 1, 0], src[n - 1, 1]
    for i in range(n):
        qx, qy = src[i, 0], src[i, 1]
        qg = m0 + m1 * qx + m2 * qy
        if (pg >= 0.0) != (qg >= 0.0):
            if k >= len(dst):
                return -1
            t = pg / (pg - qg)
            dst[k, 0], dst[k, 1] = px + (qx - px) * t, py + (qy - py) * t
            k += 1
        if qg >= 0.0:
            if k >= len(dst):
                return -1
            dst[k, 0], dst[k, 1] = qx, qy
            k += 1
        px, py, pg = qx, qy, qg
    return k if k >= 3 else 0


@njit(cache=True)
def clip_convex(src, n, shape, k, dst, scratch):
    """``src[:n] ∩ shape[:k]`` (both convex, ``shape`` counter-clockwise) into ``dst``; its count, -1 on overflow."""
    copy_rows(dst, 0, src[:n])
    m = n
    for i in range(k):
        j = (i + 1) % k
        m = clip_line(dst, m, shape[i, 0], shape[i, 1], shape[j, 0], shape[j, 1], True, scratch)
        if m <= 0:
            return m
        copy_rows(dst, 0, scratch[:m])
    return m


@njit(cache=True)
def drop_repeats(poly, n, repeat=1e-12):
    """Remove, in place, the vertices of ``poly[:n]`` within ``repeat`` of the one before (clipping leaves them;
    an edge that short has no direction to cut along); the new count (0 below 3).

    >>> import numpy as np
    >>> ring = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1e-15], [0.0, 1.0], [0.0, 0.0]])
    >>> drop_repeats(ring, 5)
    3
    """
    k = 0
    for i in range(n):
        if k and abs(poly[i, 0] - poly[k - 1, 0]) + abs(poly[i, 1] - poly[k - 1, 1]) <= repeat:
            continue
        poly[k, 0], poly[k, 1] = poly[i, 0], poly[i, 1]
        k += 1
    while k > 1 and abs(poly[k - 1, 0] - poly[0, 0]) + abs(poly[k - 1, 1] - poly[0, 1]) <= repeat:
        k -= 1
    return k if k >= 3 else 0
