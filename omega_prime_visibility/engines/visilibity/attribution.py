"""Crediting the edges of a visibility polygon to the objects they lie on."""

from __future__ import annotations

import numba
import numpy as np

from ...kernels import TWO_PI, ray_line_distance
from ...view import limited_angle


@numba.njit(cache=True)
def attribute_visible_angles(
    pts, seg, seg_offsets, targets, extent_start, extent_width, tolerance, wedge_start=0.0, fov=TWO_PI, max_range=np.inf
):
    """Angle of the visibility polygon's boundary lying on each target, radians.

    ``pts`` are the visibility polygon's vertices relative to the observer, counter-clockwise; the polygon is
    star-shaped around the observer, so its edges are ordered by bearing and those inside a target's angular
    extent are found by binary search. A polygon edge may run along several bodies (merging overlapping or
    touching bodies joins their collinear edges into one): each target is credited the bearings over which one
    of its edges lies on the polygon edge (the two agree within ``tolerance`` times the distance, at both ends
    of the shared bearings). Edges pointing at the observer subtend no angle. Only bearings inside the field of
    view ``[wedge_start, wedge_start + fov]`` along which the edge lies within ``max_range`` metres count (see
    :func:`...view.limited_angle`).
    """
    limited = fov < TWO_PI or max_range < np.inf
    m = len(pts)
    n_bodies = len(seg_offsets) - 1
    visible = np.zeros(n_bodies)
    if m < 3:
        return visible
    two_pi = 2.0 * np.pi
    bearing = np.empty(m)
    span = np.empty(m)
    for i in range(m):
        ax, ay = pts[i, 0], pts[i, 1]
        bx, by = pts[(i + 1) % m, 0], pts[(i + 1) % m, 1]
        bearing[i] = np.arctan2(ay, ax)
        span[i] = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
    order = np.argsort(bearing)
    sorted_bearing = bearing[order]
    for t in targets:
        s0 = extent_start[t]
        # edges starting within [s0 - pi, s0 + width]: an edge spans < pi, so this holds all that can overlap
        for lo, hi in (
            (s0 - np.pi, s0 + extent_width[t]),
            (s0 - np.pi - two_pi, s0 + extent_width[t] - two_pi),
            (s0 - np.pi + two_pi, s0 + extent_width[t] + two_pi),
        ):
            a = np.searchsorted(sorted_bearing, lo)
            b = np.searchsorted(sorted_bearing, hi, side="right")
            for q in range(a, b):
                i = order[q]
                if span[i] <= 0.0:
                    continue
                j = (i + 1) % m
                px, py, qx, qy = pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1]
                for e in range(seg_offsets[t], seg_offsets[t + 1]):
                    ax, ay, bx, by = seg[e, 0, 0], seg[e, 0, 1], seg[e, 1, 0], seg[e, 1, 1]
                    # the target edge's bearings relative to the polygon edge's start
                    rel_a = np.arctan2(px * ay - py * ax, px * ax + py * ay)
                    rel_b = rel_a + np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
                    shared_lo = max(min(rel_a, rel_b), 0.0)
                    shared_hi = min(max(rel_a, rel_b), span[i])
                    if shared_hi <= shared_lo:
                        continue
                    on_edge = True
                    for rel in (shared_lo, shared_hi):
                        theta = bearing[i] + rel
                        dx, dy = np.cos(theta), np.sin(theta)
                        boundary = ray_line_distance(dx, dy, px, py, qx - px, qy - py)
                        body = ray_line_distance(dx, dy, ax, ay, bx - ax, by - ay)
                        if abs(boundary - body) > tolerance * max(1.0, boundary):
                            on_edge = False
                    if on_edge and limited:
                        ex, ey = bx - ax, by - ay
                        visible[t] += limited_angle(
                            bearing[i] + shared_lo,
                            bearing[i] + shared_hi,
                            ex,
                            ey,
                            ax * ey - ay * ex,
                            wedge_start,
                            fov,
                            max_range,
                        )
                    elif on_edge:
                        visible[t] += shared_hi - shared_lo
    return visible
