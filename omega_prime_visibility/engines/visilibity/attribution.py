"""Crediting the edges of a visibility polygon to the objects they lie on."""

from __future__ import annotations

import numba
import numpy as np

from ...kernels import TWO_PI, ray_line_distance
from ...view import limited_angle

# radians: two edges of a target meeting at a vertex may share this much of a polygon edge through rounding of
# their bearings; only wider overlaps (both sides of a sliver) are credited once
ROUNDING_OVERLAP = 1e-9


@numba.njit(cache=True)
def attribute_visible_angles(
    pts, seg, seg_offsets, targets, extent_start, extent_width, tolerance, wedge_start=0.0, fov=TWO_PI, max_range=np.inf
):
    """Angle of the visibility polygon's boundary lying on each target, radians.

    ``pts`` are the visibility polygon's vertices relative to the observer, counter-clockwise; the polygon is
    star-shaped around the observer, so its edges are ordered by bearing and those inside a target's angular
    extent are found by binary search. A polygon edge may run along several bodies (merging overlapping or
    touching bodies joins their collinear edges into one): each target is credited the bearings over which one
    of its edges lies on the polygon edge (the two lines' points on the ray agree within ``tolerance`` times the
    distance, at least 1 m, at both ends of the shared bearings, measured across the body's edge: see
    :func:`_on_edge`), each bearing once (both sides of a sliver thinner than that lie on the same polygon
    edge). Edges pointing at the observer subtend no angle. Only bearings inside the field of
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
    most_edges = 0
    for t in targets:
        most_edges = max(most_edges, seg_offsets[t + 1] - seg_offsets[t])
    credited_lo = np.empty(most_edges)  # bearings (relative to the polygon edge's start) credited so far
    credited_hi = np.empty(most_edges)
    visited = np.full(m, -1, dtype=np.int64)  # the last target each polygon edge was tried for
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
                if span[i] <= 0.0 or visited[i] == t:  # (the windows overlap for extents over half a turn)
                    continue
                visited[i] = t
                j = (i + 1) % m
                px, py, qx, qy = pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1]
                n_credited = 0
                for e in range(seg_offsets[t], seg_offsets[t + 1]):
                    ax, ay, bx, by = seg[e, 0, 0], seg[e, 0, 1], seg[e, 1, 0], seg[e, 1, 1]
                    # the target edge's bearings relative to the polygon edge's start
                    rel_a = np.arctan2(px * ay - py * ax, px * ax + py * ay)
                    rel_b = rel_a + np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
                    shared_lo = max(min(rel_a, rel_b), 0.0)
                    shared_hi = min(max(rel_a, rel_b), span[i])
                    if shared_hi <= shared_lo:
                        continue
                    if not _on_edge(bearing[i], shared_lo, shared_hi, px, py, qx, qy, ax, ay, bx, by, tolerance):
                        continue
                    # bearings another edge of the target was credited on this polygon edge already (both sides of
                    # a sliver thinner than the tolerance) are not credited twice
                    n_credited = _credit(
                        visible, t, shared_lo, shared_hi, credited_lo, credited_hi, n_credited, bearing[i],
                        limited, bx - ax, by - ay, ax * (by - ay) - ay * (bx - ax), wedge_start, fov, max_range,
                    )  # fmt: skip
    return visible


@numba.njit(cache=True)
def _on_edge(start, shared_lo, shared_hi, px, py, qx, qy, ax, ay, bx, by, tolerance):
    """Whether the polygon edge ``p q`` runs along the body edge ``a b`` over the bearings ``start + [shared_lo,
    shared_hi]``: at both ends the points of the two lines on the ray lie within ``tolerance`` times the distance
    (at least 1 m) of each other, measured across the body's edge (along a grazing ray a tiny offset between
    the lines, such as VisiLibity's joining gap, would otherwise look long)."""
    ex, ey = bx - ax, by - ay
    length = np.hypot(ex, ey)
    for rel in (shared_lo, shared_hi):
        theta = start + rel
        dx, dy = np.cos(theta), np.sin(theta)
        boundary = ray_line_distance(dx, dy, px, py, qx - px, qy - py)
        body = ray_line_distance(dx, dy, ax, ay, ex, ey)
        gap = abs(boundary - body)
        allowed = tolerance * max(1.0, boundary)
        if gap > allowed and gap * (abs(dx * ey - dy * ex) / length) > allowed:
            return False
    return True


@numba.njit(cache=True)
def _credit(
    visible, t, lo, hi, credited_lo, credited_hi, n_credited, start, limited, ex, ey, num, wedge_start, fov, max_range
):
    """Credit target ``t`` the bearings ``start + [lo, hi]`` not credited yet on this polygon edge (``credited_lo,
    credited_hi[:n_credited]``), record them, and return the new count."""
    pieces_lo = np.empty(n_credited + 1)
    pieces_hi = np.empty(n_credited + 1)
    pieces_lo[0], pieces_hi[0] = lo, hi
    n_pieces = 1
    for c in range(n_credited):  # cut [lo, hi] by every interval credited before
        k = 0
        while k < n_pieces:
            a, b = pieces_lo[k], pieces_hi[k]
            c_lo, c_hi = credited_lo[c], credited_hi[c]
            if min(b, c_hi) - max(a, c_lo) <= ROUNDING_OVERLAP:
                k += 1
                continue
            if a < c_lo and c_hi < b:  # split in two
                pieces_hi[k] = c_lo
                pieces_lo[n_pieces], pieces_hi[n_pieces] = c_hi, b
                n_pieces += 1
                k += 1
            elif a < c_lo:
                pieces_hi[k] = c_lo
                k += 1
            elif c_hi < b:
                pieces_lo[k] = c_hi
                k += 1
            else:  # wholly covered: drop it
                n_pieces -= 1
                pieces_lo[k], pieces_hi[k] = pieces_lo[n_pieces], pieces_hi[n_pieces]
    for k in range(n_pieces):
        if limited:
            visible[t] += limited_angle(
                start + pieces_lo[k], start + pieces_hi[k], ex, ey, num, wedge_start, fov, max_range
            )
        else:
            visible[t] += pieces_hi[k] - pieces_lo[k]
    if n_credited < len(credited_lo):
        credited_lo[n_credited], credited_hi[n_credited] = lo, hi
        n_credited += 1
    return n_credited
