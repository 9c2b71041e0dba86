"""Crediting the edges of a visibility polygon to the objects they lie on."""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import TWO_PI, reserve_rows, wrap_positive
from ...geometry.occlusion import MIN_PIECE, hidden_span
from ...geometry.sorting import argsort_stable
from ...geometry.view import limited_angle
from .polygon_check import on_edge

# radians: two edges of a target meeting at a vertex may share this much of a polygon edge through rounding of
# their bearings; only wider overlaps (both sides of a sliver) are credited once
ROUNDING_OVERLAP = 1e-9
# radians: extents narrower than half a turn by this much skip the polygon edges ending before them
NARROW_MARGIN = 1e-6


@njit(cache=True)
def attribute_visible_angles(
    pts,
    seg,
    seg_offsets,
    targets,
    extent_start,
    extent_width,
    tolerance,
    occ_offsets,
    occ,
    st_offsets,
    st,
    wedge_start=0.0,
    fov=TWO_PI,
    max_range=np.inf,
):
    """Angle of the visibility polygon's boundary lying on each target, radians.

    ``pts`` are the visibility polygon's vertices relative to the observer, counter-clockwise; the polygon is
    star-shaped around the observer, so its edges are ordered by bearing and those inside a target's angular
    extent are found by binary search. A polygon edge may run along several bodies (merging overlapping or
    touching bodies joins their collinear edges into one): each target is credited the bearings over which one
    of its edges lies on the polygon edge (the two lines' points on the ray agree within ``tolerance`` times the
    distance, at least 1 m, at both ends of the bearings credited, measured across the body's edge: see
    :func:`.polygon_check.on_edge`), each bearing once (both sides of a sliver thinner than that lie on the same polygon
    edge). Edges pointing at the observer subtend no angle. Only bearings inside the field of
    view ``[wedge_start, wedge_start + fov]`` along which the edge lies within ``max_range`` metres count (see
    :func:`...view.limited_angle`).

    The polygon only says where *some* body's boundary is seen; which one is decided exactly: a target's edge is
    not credited along bearings where an edge of one of its occluders is hit before it (by the occlusion test's
    :data:`...occlusion.RELATIVE_TOLERANCE`, see :func:`_unhidden`). Bodies lying within the tolerance of each
    other (overlapping cars whose edges are micrometres apart) thus get what the definition gives them, not both
    the polygon edge; pieces thinner than :data:`...occlusion.MIN_PIECE` are not credited.

    ``seg`` holds the edges of all bodies relative to the observer (objects ``0 .. n - 1``, then the static
    sources), ``seg_offsets`` shape (bodies + 1,); the occluders of object ``t`` are the objects
    ``occ[occ_offsets[t]:occ_offsets[t + 1]]`` and the static sources ``st[st_offsets[t]:st_offsets[t + 1]]``.
    """
    limited = fov < TWO_PI or max_range < np.inf
    m = len(pts)
    n_objects = len(occ_offsets) - 1
    visible = np.zeros(n_objects)
    if m < 3:
        return visible
    two_pi = 2.0 * np.pi
    bearing, span, order, sorted_bearing, reach = _edges_by_bearing(pts)
    most_edges = 0
    for t in targets:
        most_edges = max(most_edges, seg_offsets[t + 1] - seg_offsets[t])
    credited_lo = np.empty(most_edges)  # bearings (relative to the polygon edge's start) credited so far
    credited_hi = np.empty(most_edges)
    visited = np.full(m, -1, dtype=np.int64)  # the last target each polygon edge was tried for
    for t in targets:
        s0 = extent_start[t]
        # edges starting within [s0 - pi, s0 + width]: an edge spans < pi, so this holds all that can overlap
        for lo, hi, shift in (
            (s0 - np.pi, s0 + extent_width[t], 0.0),
            (s0 - np.pi - two_pi, s0 + extent_width[t] - two_pi, -two_pi),
            (s0 - np.pi + two_pi, s0 + extent_width[t] + two_pi, two_pi),
        ):
            a, b = _window(sorted_bearing, reach, lo, hi, s0 + shift, extent_width[t])
            for q in range(a, b):
                i = order[q]
                if span[i] <= 0.0 or visited[i] == t:  # (the windows overlap for extents over half a turn)
                    continue
                visited[i] = t
                # the window holds half the polygon: skip at once an edge whose bearings miss the target's extent
                # (it starts neither inside the extent nor before it and reaching into it), 1e-9 rad to spare
                rel0 = wrap_positive(bearing[i] - s0)
                if not (rel0 < extent_width[t] + 1e-9 or rel0 + span[i] > two_pi - 1e-9):
                    continue
                j = (i + 1) % m
                px, py, qx, qy = pts[i, 0], pts[i, 1], pts[j, 0], pts[j, 1]
                n_credited = 0
                for e in range(seg_offsets[t], seg_offsets[t + 1]):
                    ax, ay, bx, by = seg[e, 0, 0], seg[e, 0, 1], seg[e, 1, 0], seg[e, 1, 1]
                    if wedges_apart(px, py, qx, qy, ax, ay, bx, by):
                        continue
                    # the target edge's bearings relative to the polygon edge's start
                    rel_a = np.arctan2(px * ay - py * ax, px * ax + py * ay)
                    rel_b = rel_a + np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
                    shared_lo = max(min(rel_a, rel_b), 0.0)
                    shared_hi = min(max(rel_a, rel_b), span[i])
                    if shared_hi <= shared_lo:
                        continue
                    # the polygon edge runs along this edge at one end of the shared bearings at least (a line
                    # crossing it in between would be nearer than it on one side, and so on the polygon there)
                    on_lo = on_edge(bearing[i] + shared_lo, px, py, qx, qy, ax, ay, bx, by, tolerance)
                    on_hi = on_edge(bearing[i] + shared_hi, px, py, qx, qy, ax, ay, bx, by, tolerance)
                    if not (on_lo or on_hi):
                        continue
                    pieces = _unhidden(
                        px, py, bearing[i], shared_lo, shared_hi, ax, ay, bx, by, seg, seg_offsets,
                        occ[occ_offsets[t] : occ_offsets[t + 1]], n_objects + st[st_offsets[t] : st_offsets[t + 1]],
                    )  # fmt: skip
                    for k in range(len(pieces)):
                        piece_lo, piece_hi = pieces[k, 0], pieces[k, 1]
                        # credited where the polygon runs along the edge at both ends of the unhidden piece
                        if piece_lo != shared_lo or not on_lo:
                            if not on_edge(bearing[i] + piece_lo, px, py, qx, qy, ax, ay, bx, by, tolerance):
                                continue
                        if piece_hi != shared_hi or not on_hi:
                            if not on_edge(bearing[i] + piece_hi, px, py, qx, qy, ax, ay, bx, by, tolerance):
                                continue
                        # bearings another edge of the target was credited on this polygon edge already (both sides
                        # of a sliver thinner than the tolerance) are not credited twice
                        n_credited = _credit(
                            visible, t, piece_lo, piece_hi, credited_lo, credited_hi, n_credited, bearing[i], limited,
                            bx - ax, by - ay, ax * (by - ay) - ay * (bx - ax), wedge_start, fov, max_range,
                        )  # fmt: skip
    return visible


@njit(cache=True, inline="always")
def wedges_apart(px, py, qx, qy, ax, ay, bx, by):
    """Whether the bearings of the polygon edge ``p q`` (counter-clockwise, under half a turn) and of the edge ``a b``
    (relative to the observer, metres) share none, by the signs of cross products (no arctangent): neither wedge's
    first side lies within the other. Wrong only where they share less than about 1e-15 rad, which credits nothing
    (pieces under :data:`...occlusion.MIN_PIECE` are dropped); an edge pointing through the observer is never called
    apart.

    Examples
    --------
    The polygon edge from (1, 0) to (0, 1) spans 0 to 90 degrees; an edge at 27 to 63 degrees shares them, one at
    225 to 297 degrees does not:

    >>> bool(wedges_apart(1.0, 0.0, 0.0, 1.0, 2.0, 1.0, 1.0, 2.0))
    False
    >>> bool(wedges_apart(1.0, 0.0, 0.0, 1.0, -1.0, -1.0, 1.0, -2.0))
    True
    """
    turn = ax * by - ay * bx
    if turn == 0.0:
        return False
    if turn < 0.0:  # counter-clockwise
        ax, ay, bx, by = bx, by, ax, ay
    a_in = px * ay - py * ax >= 0.0 and ax * qy - ay * qx > 0.0
    p_in = ax * py - ay * px >= 0.0 and px * by - py * bx > 0.0
    return not (a_in or p_in)


@njit(cache=True)
def _edges_by_bearing(pts):
    """The polygon's edges (from vertex ``i`` to ``i + 1``, relative to the observer) by bearing: each edge's
    ``bearing`` and ``span`` (radians), their ``order`` by bearing and the bearings in that order, and ``reach``:
    the farthest bearing reached by the edges up to each one in that order (a window of edges need start no
    earlier than the first edge reaching the target's extent)."""
    m = len(pts)
    bearing = np.empty(m)
    span = np.empty(m)
    for i in range(m):
        ax, ay = pts[i, 0], pts[i, 1]
        bx, by = pts[(i + 1) % m, 0], pts[(i + 1) % m, 1]
        bearing[i] = np.arctan2(ay, ax)
        span[i] = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
    order = argsort_stable(bearing)
    sorted_bearing = bearing[order]
    reach = np.empty(m)
    farthest = -np.inf
    for q in range(m):
        farthest = max(farthest, sorted_bearing[q] + max(span[order[q]], 0.0))
        reach[q] = farthest
    return bearing, span, order, sorted_bearing, reach


@njit(cache=True, inline="always")
def _window(sorted_bearing, reach, lo, hi, first, width):
    """The positions ``a .. b - 1`` (in bearing order) of the edges starting within ``[lo, hi]`` (radians) that can
    meet an extent starting at ``first`` (shifted as the window is) of ``width``: for extents under half a turn,
    edges ending before it (by 1e-8 rad) start before it by over half a turn less its width, and the caller's test
    would skip them all, so the window skips them too (the same edges, in the same order)."""
    a = np.searchsorted(sorted_bearing, lo)
    if width < np.pi - NARROW_MARGIN:
        a = max(a, np.searchsorted(reach, first - 1e-8))
    return a, np.searchsorted(sorted_bearing, hi, side="right")


@njit(cache=True)
def _unhidden(px, py, start, lo, hi, ax, ay, bx, by, seg, seg_offsets, occluders, static_occluders):
    """The pieces of the bearings ``start + [lo, hi]`` (radians, relative to the direction ``p`` of bearing
    ``start``) along which no edge of the given bodies hides the edge ``a b`` (:func:`...occlusion.hidden_span`),
    shape (k, 2), ascending, relative to ``start``; pieces thinner than :data:`...occlusion.MIN_PIECE` are
    dropped."""
    ex, ey = bx - ax, by - ay
    num_e = ax * ey - ay * ex
    hidden = np.empty((8, 2))
    n_hidden = 0
    for group in (occluders, static_occluders):
        for body in group:
            for f in range(seg_offsets[body], seg_offsets[body + 1]):
                cx, cy, dx, dy = seg[f, 0, 0], seg[f, 0, 1], seg[f, 1, 0], seg[f, 1, 1]
                rel_c = np.arctan2(px * cy - py * cx, px * cx + py * cy)
                rel_d = rel_c + np.arctan2(cx * dy - cy * dx, cx * dx + cy * dy)
                shared_lo, shared_hi = max(min(rel_c, rel_d), lo), min(max(rel_c, rel_d), hi)
                if shared_hi <= shared_lo:
                    continue
                fx, fy = dx - cx, dy - cy
                h_lo, h_hi = hidden_span(start, shared_lo, shared_hi, num_e, ex, ey, cx * fy - cy * fx, fx, fy)
                if h_hi > h_lo:
                    if n_hidden == len(hidden):  # (rebinding the array on every pass costs reference counting)
                        hidden = reserve_rows(hidden, n_hidden, n_hidden + 1)
                    hidden[n_hidden, 0], hidden[n_hidden, 1] = h_lo, h_hi
                    n_hidden += 1
    pieces = np.empty((n_hidden + 1, 2))
    n_pieces = 0
    reached = lo
    for q in argsort_stable(hidden[:n_hidden, 0].copy()):
        if hidden[q, 0] - reached >= MIN_PIECE:
            pieces[n_pieces, 0], pieces[n_pieces, 1] = reached, hidden[q, 0]
            n_pieces += 1
        reached = max(reached, hidden[q, 1])
    if hi - reached >= MIN_PIECE:
        pieces[n_pieces, 0], pieces[n_pieces, 1] = reached, hi
        n_pieces += 1
    return pieces[:n_pieces]


@njit(cache=True)
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
