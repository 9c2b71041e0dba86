"""The exact occlusion test of :mod:`.occlusion` (``occludes_one``) for many pairs of objects seen from one
observer at once: the same floating-point operations on the same operands, without the work ``occludes_one``
repeats on every call (each vertex's bearing once per observer, a target's cuts once per target, the cuts sorted
by insertion in one work space). Shared by the engines.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit
from .kernels import TWO_PI, segment_distance2, wrap_positive
from .occlusion import MIN_PIECE, RAY_SLACK, RELATIVE_TOLERANCE, _edge_line_distance, _nearest_edge
from .sorting import insertion_sort


@njit(cache=True, inline="always")
def missed_margin(seg, start, stop, ox, oy):
    """Radians beyond its angular extent within which a ray from ``(ox, oy)`` may still hit the body of edges
    ``seg[start:stop]`` (metres) by :func:`.occlusion._nearest_edge`'s slack; ``inf`` when the observer lies too
    near the body for a bound (then no direction is known to miss it).

    A ray counts as hitting an edge of length ``L`` up to ``RAY_SLACK * L`` beyond its ends, at least ``near`` (the
    body's distance) from the observer: at most ``RAY_SLACK * L / (near - RAY_SLACK * L)`` radians from a bearing
    the extent covers. The margin is four times that, plus ``1e-8 / near`` for points rounded by a hundredth of a
    micrometre (the shifts from map coordinates of ten thousand kilometres) and 1e-9 for the rounding of bearings.

    >>> seg = np.array([[[10.0, -1.0], [10.0, 1.0]], [[10.0, 1.0], [12.0, 1.0]]])
    >>> bool(2e-9 < missed_margin(seg, 0, 2, 0.0, 0.0) < 2.1e-9), missed_margin(seg, 0, 2, 10.0, 0.0)
    (True, inf)
    """
    longest2 = 0.0
    near2 = np.inf
    for e in range(start, stop):
        ax, ay = seg[e, 0, 0] - ox, seg[e, 0, 1] - oy
        bx, by = seg[e, 1, 0] - ox, seg[e, 1, 1] - oy
        longest2 = max(longest2, (bx - ax) ** 2 + (by - ay) ** 2)
        near2 = min(near2, segment_distance2(ax, ay, bx, by))
    longest, near = np.sqrt(longest2), np.sqrt(near2)
    if not near > 1e-6 * longest:  # (NaN too)
        return np.inf
    return 1e-9 + (4.0 * RAY_SLACK * longest + 1e-8) / near


@njit(cache=True, inline="always")
def pieces_occlude(
    seg, t_start, t_stop, j_start, j_stop, extent_start, extent_width, cuts, k, ox, oy, body_offset=0.0,
    body_width=TWO_PI, body_margin=np.inf,
):  # fmt: skip
    """The decision of ``occludes_one`` once its cuts are made: whether body ``J`` (``seg[j_start:j_stop]``) is hit
    before target ``T`` (``seg[t_start:t_stop]``) at an end of some piece between the sorted cuts ``cuts[:k]``
    (radians from ``extent_start``), the observer at ``(ox, oy)`` (metres, the frame of ``seg``); the same
    floating-point operations on the same operands as ``occludes_one``, the direction at a cut computed once for
    the two pieces it bounds (inlined: no reference counting in the callers' loops).

    Given ``J``'s angular extent, ``body_width`` radians from ``T``'s extent start minus ``body_offset`` (in
    ``[0, 2 pi]``), and :func:`missed_margin`, a piece whose middle direction lies outside that extent by more than
    the margin is passed over without looking for ``J``'s edges: the ray there misses ``J``, as the search would
    find (about a third of the pieces among crowded, overlapping traffic).
    """
    cached = -1  # the cut whose direction (cached_x, cached_y) was computed last
    cached_x, cached_y = 0.0, 0.0
    for i in range(k - 1):
        u0, u1 = cuts[i], cuts[i + 1]
        if u1 - u0 < MIN_PIECE:
            continue
        if extent_width <= u0:
            break
        if body_width + body_margin < wrap_positive(body_offset + 0.5 * (u0 + u1)) < TWO_PI - body_margin:
            continue  # (the ray misses J)
        mid = extent_start + 0.5 * (u0 + u1)
        dx, dy = np.cos(mid), np.sin(mid)
        body_edge = _nearest_edge(ox, oy, dx, dy, seg, j_start, j_stop)
        if body_edge < 0:  # (J is missed more often than T: T's own edges need not be tried then)
            continue
        target_edge = _nearest_edge(ox, oy, dx, dy, seg, t_start, t_stop)
        if target_edge < 0:
            continue
        for end in range(i, i + 2):
            if end == cached:
                ex, ey = cached_x, cached_y
            else:
                ex, ey = np.cos(extent_start + cuts[end]), np.sin(extent_start + cuts[end])
                cached, cached_x, cached_y = end, ex, ey
            target_distance = _edge_line_distance(ox, oy, ex, ey, seg, target_edge)
            body_distance = _edge_line_distance(ox, oy, ex, ey, seg, body_edge)
            if body_distance < target_distance * (1.0 - RELATIVE_TOLERANCE):
                return True
    return False


@njit(cache=True, inline="always")
def objects_occluded(seg, offsets, start, width, pair_target, pair_body, ox, oy):
    """``occludes_one`` for each pair of objects ``(pair_body[p], pair_target[p])`` (grouped by target), shape (p,)
    bool: the same floating-point operations on the same operands, without the work it repeats on every call.

    Each vertex's bearing (scalar ``np.arctan2``, radians) is computed once per observer and the target's own cuts
    once per target, instead of once per pair; every vertex is cut once instead of once per edge end (equal cuts
    only make empty pieces, which are skipped); the cuts are sorted by insertion (few values, all >= +0.0: the
    order ``np.sort`` gives), and the direction at a cut is computed once for the two pieces it bounds. Everything
    is written out in this one function: a numba function with a loop that takes arrays costs reference counting
    on every call.

    Parameters
    ----------
    seg : ndarray, shape (m, 2, 2)
        The objects' edges (and possibly others after them), metres; object ``i`` owns
        ``seg[offsets[i]:offsets[i + 1]]``.
    start, width : ndarray, shape (n,)
        The objects' angular extents, radians.
    ox, oy : float
        The observer, metres, in the frame of ``seg`` (the sweep shifts everything to put it at the origin).
    """
    n = len(offsets) - 1
    most = 0  # most vertices of a ring
    for i in range(n):
        most = max(most, offsets[i + 1] - offsets[i])
    bearing = np.empty(len(seg))
    margin = np.empty(n)
    have_bearing = np.zeros(n, dtype=np.bool_)
    target_cuts = np.empty(most + 2)
    cuts = np.empty(2 * most + 2)
    hit = np.zeros(len(pair_target), dtype=np.bool_)
    cut_target = -1  # the target whose cuts target_cuts holds
    n_target_cuts = 0
    for p in range(len(pair_target)):
        t, j = pair_target[p], pair_body[p]
        extent_start, extent_width = start[t], width[t]
        for body in (t, j):  # vertex bearings, once per object
            if not have_bearing[body]:
                for v in range(offsets[body], offsets[body + 1]):
                    bearing[v] = np.arctan2(seg[v, 0, 1] - oy, seg[v, 0, 0] - ox)
                margin[body] = missed_margin(seg, offsets[body], offsets[body + 1], ox, oy)
                have_bearing[body] = True
        if t != cut_target:  # the target's cuts: 0, its width and its vertices within it
            target_cuts[0] = 0.0
            target_cuts[1] = extent_width
            n_target_cuts = 2
            for v in range(offsets[t], offsets[t + 1]):
                rel = wrap_positive(bearing[v] - extent_start)
                if rel < extent_width:
                    target_cuts[n_target_cuts] = rel
                    n_target_cuts += 1
            cut_target = t
        for k in range(n_target_cuts):  # (a loop: slices cost reference counting)
            cuts[k] = target_cuts[k]
        k = n_target_cuts
        for v in range(offsets[j], offsets[j + 1]):
            rel = wrap_positive(bearing[v] - extent_start)
            if rel < extent_width:
                cuts[k] = rel
                k += 1
        insertion_sort(cuts, k)
        hit[p] = pieces_occlude(
            seg, offsets[t], offsets[t + 1], offsets[j], offsets[j + 1], extent_start, extent_width, cuts, k, ox, oy,
            wrap_positive(extent_start - start[j]), width[j], margin[j],
        )  # fmt: skip
    return hit
