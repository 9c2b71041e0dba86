"""An exact check that a visibility polygon's boundary really is the first thing hit in every direction.

VisiLibity1's radial sweep keeps the edges crossing the current ray in a ``std::priority_queue`` whose order is
evaluated at the bearing where each comparison happened; edges whose end the sweep has passed stay in the queue
until they surface (and two such edges compare as "greater" than each other). Once that order goes stale the
queue's top need not be the nearest edge, and the sweep continues along a farther body: a nearer body (or a
sliver of it) is missing from the polygon. Long edges, which stay queued over a wide bearing range among many
shorter ones, make this likely (a long thin wall among scattered cars does; in town, a pedestrian between parked
cars in front of a building, about one frame in five). The copy compiled with the package is patched
(``native/visilibity.cpp``, ``Edge_Queue``: the queue is reordered, passed edges dropped, at each such event); the
check stays, and a polygon that fails it is computed again from halves of the holes.

Such a polygon is detectable: the boundary of a correct visibility polygon lies, in every direction, on the
nearest body, so no blocking edge may come nearer than the boundary along any ray. Within the bearing interval
shared by one polygon edge and one body edge both are straight lines, whose depth order along a rotating ray changes
at most once, so comparing the two at the interval's ends decides it (as in :mod:`..occlusion`).

The converse happens too: where bodies' edges meet at a kink of a few nanometres (merged overlapping cars whose
edges are a nanoradian apart), VisiLibity's polygon can cut from one vertex straight to another, nearer than the
bodies. Its edges must therefore each run along some body edge (or the box around everything) over all their
bearings. :func:`polygon_fails` checks both.
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import TWO_PI, ray_line_distance, reserve_rows
from ...geometry.sorting import argsort_stable

MIN_SPAN = 1e-12  # radians; edges subtending less point at the observer and bound nothing
# radians; narrower shared intervals are not compared: where a body's silhouette ends, the polygon's radial edge
# starts at the same bearing up to rounding, and a sliver this thin changes a visible angle by nothing that counts
MIN_SHARED = 1e-9
CHECK_ABSOLUTE = 1e-7  # metres: a body must come this much nearer than the polygon's boundary to count as missed
CHECK_RELATIVE = 1e-9  # ... plus this fraction of the boundary's distance
BOX_SIDE = 1e-12  # relative to the polygon's size: its points on the box around everything lie this near its sides
# metres: a polygon edge may run along no body over this length (the flat end of a wall thickened to 2e-8 m, a
# 0.1 µm join between touching bodies)
UNCOVERED = 1e-6
ON_EDGE = 1e-6  # a polygon edge runs along a body edge within this fraction of the distance (at least 1 m)


@njit(cache=True)
def on_edge(theta, px, py, qx, qy, ax, ay, bx, by, tolerance):
    """Whether, along the bearing ``theta``, the polygon edge ``p q`` runs along the body edge ``a b`` (relative
    to the observer, metres): the points of the two lines on the ray lie within ``tolerance`` times the distance
    (at least 1 m) of each other, measured across the body's edge (along a grazing ray a tiny offset between the
    lines, such as VisiLibity's joining gap, would otherwise look long)."""
    ex, ey = bx - ax, by - ay
    dx, dy = np.cos(theta), np.sin(theta)
    boundary = ray_line_distance(dx, dy, px, py, qx - px, qy - py)
    body = ray_line_distance(dx, dy, ax, ay, ex, ey)
    return lines_meet(dx, dy, boundary, body, ex, ey, tolerance)


@njit(cache=True, inline="always")
def lines_meet(dx, dy, boundary, body, ex, ey, tolerance):
    """:func:`on_edge` once the distances along the unit direction ``(dx, dy)`` to the polygon edge's line
    (``boundary``) and to the body edge's (``body``, direction ``(ex, ey)``) are known, metres."""
    gap = abs(boundary - body)
    allowed = tolerance * max(1.0, boundary)
    return gap <= allowed or gap * (abs(dx * ey - dy * ex) / np.hypot(ex, ey)) <= allowed


@njit(cache=True)
def polygon_fails(pts, seg, check, absolute_tolerance, relative_tolerance, on_tolerance):
    """Whether a visibility polygon's boundary is not the first thing hit along some ray: a checked body edge
    comes nearer than it, or it runs along no body (nor the box around everything) over some bearings.

    Parameters
    ----------
    pts : ndarray, shape (m, 2)
        Vertices of the visibility polygon relative to the observer (metres), counter-clockwise; the polygon is
        star-shaped around the observer (the origin), so its vertices go round once in bearing.
    seg : ndarray, shape (s, 2, 2)
        Edges of the bodies, relative to the observer, ``seg[j] = [[x0, y0], [x1, y1]]``.
    check : ndarray of bool, shape (s,)
        Edges of bodies that block the view (the others are ignored).
    absolute_tolerance, relative_tolerance : float
        An edge must be nearer than the boundary by more than ``absolute + relative * distance`` metres.
    on_tolerance : float
        A polygon edge runs along a body edge where they lie within this fraction of the distance (see
        :func:`on_edge`); edges on the sides of the polygon's bounding box (the environment's outer box) need not.

    Returns
    -------
    bool

    Examples
    --------
    A square room seen from its centre, with a wall 5 m ahead: the wall comes nearer than the boundary.

    >>> import numpy as np
    >>> square = np.array([[10.0, -10.0], [10.0, 10.0], [-10.0, 10.0], [-10.0, -10.0]])
    >>> wall = np.array([[[5.0, -1.0], [5.0, 1.0]]])
    >>> bool(polygon_fails(square, wall, np.array([True]), 1e-9, 1e-9, 1e-6))
    True
    >>> bool(polygon_fails(square, wall + 10.0, np.array([True]), 1e-9, 1e-9, 1e-6))
    False

    A polygon that cuts a corner of the room runs along nothing there:

    >>> cut = np.array([[10.0, -10.0], [10.0, 5.0], [5.0, 10.0], [-10.0, 10.0], [-10.0, -10.0]])
    >>> bool(polygon_fails(cut, wall + 10.0, np.array([True]), 1e-9, 1e-9, 1e-6))
    True
    """
    m = len(pts)
    if m < 3:
        return False
    # unwrapped bearing of every polygon vertex, starting at vertex 0's bearing
    start = np.empty(m + 1)
    start[0] = np.arctan2(pts[0, 1], pts[0, 0])
    for i in range(m):
        ax, ay = pts[i, 0], pts[i, 1]
        bx, by = pts[(i + 1) % m, 0], pts[(i + 1) % m, 1]
        start[i + 1] = start[i] + np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
    covered = np.empty((8, 3))  # (polygon edge, lo, hi): bearings along which it runs along a body edge
    n_covered = 0
    for j in range(len(seg)):
        if not check[j]:
            continue
        ax, ay, bx, by = seg[j, 0, 0], seg[j, 0, 1], seg[j, 1, 0], seg[j, 1, 1]
        span = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
        if abs(span) < MIN_SPAN:
            continue
        lo = np.arctan2(ay, ax) if span > 0 else np.arctan2(by, bx)
        lo = start[0] + (lo - start[0]) - TWO_PI * np.floor((lo - start[0]) / TWO_PI)
        hi = lo + abs(span)
        # the polygon edges overlapping [lo, hi], going round once more where the interval wraps past the start
        for turn in range(2):
            shift = turn * TWO_PI
            if hi - shift <= start[0]:
                break
            k = max(np.searchsorted(start, lo - shift, side="right") - 1, 0)
            while k < m and start[k] < hi - shift:
                shared_lo, shared_hi = max(lo - shift, start[k]), min(hi - shift, start[k + 1])
                if start[k + 1] - start[k] >= MIN_SPAN and shared_hi - shared_lo >= MIN_SHARED:
                    px, py = pts[k, 0], pts[k, 1]
                    qx, qy = pts[(k + 1) % m, 0], pts[(k + 1) % m, 1]
                    along = True
                    for theta in (shared_lo, shared_hi):
                        dx, dy = np.cos(theta), np.sin(theta)
                        boundary = ray_line_distance(dx, dy, px, py, qx - px, qy - py)
                        body = ray_line_distance(dx, dy, ax, ay, bx - ax, by - ay)
                        if body < boundary - absolute_tolerance - relative_tolerance * boundary:
                            return True
                        along = along and lines_meet(dx, dy, boundary, body, bx - ax, by - ay, on_tolerance)
                    if along:
                        if n_covered == len(covered):  # (rebinding on every pass costs reference counting)
                            covered = reserve_rows(covered, n_covered, n_covered + 1)
                        covered[n_covered, 0], covered[n_covered, 1], covered[n_covered, 2] = k, shared_lo, shared_hi
                        n_covered += 1
                k += 1
    return _uncovered(pts, start, covered[:n_covered])


@njit(cache=True)
def _uncovered(pts, start, covered):
    """Whether some polygon edge runs along no body edge (``covered``: rows ``(edge, lo, hi)`` of bearings where
    it does) over a stretch longer than :data:`UNCOVERED` (and wider than :data:`MIN_SHARED`), and not along a
    side of the polygon's bounding box (the environment's outer box)."""
    m = len(pts)
    x0, y0 = pts[:, 0].min(), pts[:, 1].min()
    x1, y1 = pts[:, 0].max(), pts[:, 1].max()
    scale = max(1.0, abs(x0), abs(y0), abs(x1), abs(y1))
    order = argsort_stable(covered[:, 1].copy())
    order = order[argsort_stable(covered[order, 0])]  # by edge, then by bearing
    q = 0
    for k in range(m):
        reached = start[k]
        longest = 0.0  # metres: the longest stretch along which edge k runs along no body edge
        while q < len(order) and covered[order[q], 0] == k:
            r = order[q]
            longest = max(longest, _stretch(pts, k, reached, covered[r, 1]))
            reached = max(reached, covered[r, 2])
            q += 1
        longest = max(longest, _stretch(pts, k, reached, start[k + 1]))
        if start[k + 1] - start[k] < MIN_SPAN or longest <= UNCOVERED:
            continue
        px, py = pts[k, 0], pts[k, 1]
        qx, qy = pts[(k + 1) % m, 0], pts[(k + 1) % m, 1]
        near = BOX_SIDE * scale  # on a side of the environment's outer box (VisiLibity rounds its points there)
        on_x = max(abs(px - x0), abs(qx - x0)) <= near or max(abs(px - x1), abs(qx - x1)) <= near
        on_y = max(abs(py - y0), abs(qy - y0)) <= near or max(abs(py - y1), abs(qy - y1)) <= near
        if not (on_x or on_y):
            return True
    return False


@njit(cache=True)
def _stretch(pts, k, lo, hi):
    """Length (metres) of polygon edge ``k`` between the bearings ``lo`` and ``hi``; 0 when narrower than
    :data:`MIN_SHARED`."""
    if hi - lo < MIN_SHARED:
        return 0.0
    px, py = pts[k, 0], pts[k, 1]
    ex, ey = pts[(k + 1) % len(pts), 0] - px, pts[(k + 1) % len(pts), 1] - py
    a = ray_line_distance(np.cos(lo), np.sin(lo), px, py, ex, ey)
    b = ray_line_distance(np.cos(hi), np.sin(hi), px, py, ex, ey)
    return np.hypot(b * np.cos(hi) - a * np.cos(lo), b * np.sin(hi) - a * np.sin(lo))
