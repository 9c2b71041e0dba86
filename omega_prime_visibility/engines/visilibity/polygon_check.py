"""An exact check that a visibility polygon's boundary really is the first thing hit in every direction.

VisiLibity1's radial sweep keeps the edges crossing the current ray in a ``std::priority_queue`` whose order is
evaluated at the bearing where each comparison happened; edges whose end the sweep has passed stay in the queue
until they surface (and two such edges compare as "greater" than each other). Once that order goes stale the
queue's top need not be the nearest edge, and the sweep continues along a farther body: a nearer body (or a
sliver of it) is missing from the polygon. Long edges, which stay queued over a wide bearing range among many
shorter ones, make this likely (a long thin wall among scattered cars does).

Such a polygon is detectable: the boundary of a correct visibility polygon lies, in every direction, on the
nearest body, so no blocking edge may come nearer than the boundary along any ray. :func:`nearer_edge_exists`
checks exactly that. Within the bearing interval shared by one polygon edge and one body edge both are straight
lines, whose depth order along a rotating ray changes at most once, so comparing the two at the interval's ends
decides it (as in :mod:`..occlusion`).
"""

from __future__ import annotations

import numba
import numpy as np

from ...kernels import ray_line_distance

TWO_PI = 2.0 * np.pi
MIN_SPAN = 1e-12  # radians; edges subtending less point at the observer and bound nothing
# radians; narrower shared intervals are not compared: where a body's silhouette ends, the polygon's radial edge
# starts at the same bearing up to rounding, and a sliver this thin changes a visible angle by nothing that counts
MIN_SHARED = 1e-9
CHECK_ABSOLUTE = 1e-7  # metres: a body must come this much nearer than the polygon's boundary to count as missed
CHECK_RELATIVE = 1e-9  # ... plus this fraction of the boundary's distance


@numba.njit(cache=True)
def nearer_edge_exists(pts, seg, check, absolute_tolerance, relative_tolerance):
    """Whether some checked edge comes nearer than the boundary of a visibility polygon along some ray.

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

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> square = np.array([[10.0, -10.0], [10.0, 10.0], [-10.0, 10.0], [-10.0, -10.0]])
    >>> wall = np.array([[[5.0, -1.0], [5.0, 1.0]]])
    >>> bool(nearer_edge_exists(square, wall, np.array([True]), 1e-9, 1e-9))
    True
    >>> bool(nearer_edge_exists(square, wall + 10.0, np.array([True]), 1e-9, 1e-9))
    False
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
                    p0, p1 = pts[k], pts[(k + 1) % m]
                    for theta in (shared_lo, shared_hi):
                        dx, dy = np.cos(theta), np.sin(theta)
                        boundary = ray_line_distance(dx, dy, p0[0], p0[1], p1[0] - p0[0], p1[1] - p0[1])
                        body = ray_line_distance(dx, dy, ax, ay, bx - ax, by - ay)
                        if body < boundary - absolute_tolerance - relative_tolerance * boundary:
                            return True
                k += 1
    return False
