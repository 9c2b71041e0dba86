"""The exact pairwise occlusion test shared by all 2D engines.

A body ``J`` *occludes* a target ``T`` (seen from an observer) when, along at least one direction inside ``T``'s
angular extent, ``J`` is hit strictly before ``T``. Whether that holds depends on the two bodies only, so the
engines find candidate pairs cheaply (spatial index, angular overlap) and call :func:`occludes` to decide.

Exactness: cut ``T``'s extent at the bearings of all vertices of both bodies. Inside one such piece the nearest
edge of each body is a single straight edge, and two straight lines seen along a rotating ray swap order at most
once, so ``J`` is in front somewhere in the piece iff it is in front at one of the piece's two ends (evaluated on
the lines of the edges nearest at the piece's middle). No sampling is involved.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit
from .candidates import MIN_PIECE, candidate_pairs
from .kernels import ray_line_distance, wrap_positive
from .sorting import sorted_values

RELATIVE_TOLERANCE = 1e-9  # J must be nearer by this fraction of T's distance to count as in front
# sine of the angle between two edges' lines under which the relative tolerance lets them tie along the bearings
# where they lie that near; lines meeting at a wider angle (at a corner two bodies share) are ordered exactly
TIE_PARALLEL = 1e-3


@njit(cache=True, inline="always")
def _line_distance(ox, oy, dx, dy, ax, ay, bx, by):
    """Distance along the unit ray (o, d) to the line through a and b (inf when parallel or behind), metres."""
    t = ray_line_distance(dx, dy, ax - ox, ay - oy, bx - ax, by - ay)
    return t if t > 0.0 else np.inf


@njit(cache=True, inline="always")
def _edge_line_distance(ox, oy, dx, dy, seg, j):
    """:func:`_line_distance` to the line of edge ``seg[j]`` (shape (s, 2, 2), metres)."""
    return _line_distance(ox, oy, dx, dy, seg[j, 0, 0], seg[j, 0, 1], seg[j, 1, 0], seg[j, 1, 1])


@njit(cache=True, inline="always")
def _hides(theta, num_e, ex, ey, num_f, fx, fy, keep):
    """Whether, along the bearing ``theta``, line ``f`` is hit before line ``e``, nearer than ``keep`` times the
    latter's distance (lines as in :func:`hidden_span`)."""
    dx, dy = np.cos(theta), np.sin(theta)
    den_e, den_f = dx * ey - dy * ex, dx * fy - dy * fx
    if den_e == 0.0 or den_f == 0.0:  # a line seen edge-on hides nothing and is hidden by nothing
        return False
    return num_f / den_f < (num_e / den_e) * keep


@njit(cache=True)
def hidden_span(base, lo, hi, num_e, ex, ey, num_f, fx, fy):
    """The bearings ``base + [lo, hi]`` (radians, ``0 <= hi - lo < pi``) along which the line ``f`` hides the
    line ``e``: ``f`` is hit nearer than ``(1 - RELATIVE_TOLERANCE)`` times the distance of ``e``, the rule of
    :func:`occludes_one` and of the definition, so that nearly coincident edges tie; lines at an angle whose sine
    exceeds :data:`TIE_PARALLEL` (edges meeting at a corner) tie nowhere but where they meet: ``f`` hides ``e``
    wherever it is nearer.

    A line is given by its direction ``(ex, ey)`` and ``num_e = p x (ex, ey)`` for a point ``p`` on it (relative
    to the observer, metres); its distance along the unit direction ``d`` is ``num_e / (d x e)``. The two
    distances are ratios linear in ``d``, so they swap order at most once within half a turn, along ``w = num_f e
    - k num_e f`` (``k`` the factor above): the bearings hidden are an interval touching ``lo`` or ``hi``, or all
    of them, or none.

    Returns
    -------
    (float, float)
        The hidden bearings relative to ``base``; ``lo >= hi`` when none.

    Examples
    --------
    Seen from the origin between 45° and 90°, the line y = 2 (direction +x: ``num = (0, 2) x (1, 0) = -2``) is
    hidden all along by the line y = 1, and hides none of it:

    >>> import numpy as np
    >>> [float(b) for b in hidden_span(np.pi / 4, 0.0, np.pi / 4, -2.0, 1.0, 0.0, -1.0, 1.0, 0.0)]
    [0.0, 0.7853981633974483]
    >>> lo, hi = hidden_span(np.pi / 4, 0.0, np.pi / 4, -1.0, 1.0, 0.0, -2.0, 1.0, 0.0)
    >>> bool(lo >= hi)
    True

    The line y = 1 against the line through (1, 0) and (0, 2): they cross at (0.5, 1), bearing atan2(1, 0.5);
    before it (from 45°) the slanted line is nearer:

    >>> lo, hi = hidden_span(np.pi / 4, 0.0, np.pi / 4, -1.0, 1.0, 0.0, 2.0, -1.0, 2.0)
    >>> bool(lo == 0.0 and np.isclose(np.pi / 4 + hi, np.arctan2(1.0, 0.5)))
    True
    """
    cross = ex * fy - ey * fx
    nearly_parallel = cross * cross <= TIE_PARALLEL * TIE_PARALLEL * (ex * ex + ey * ey) * (fx * fx + fy * fy)
    keep = 1.0 - RELATIVE_TOLERANCE if nearly_parallel else 1.0
    hides_lo = _hides(base + lo, num_e, ex, ey, num_f, fx, fy, keep)
    hides_hi = _hides(base + hi, num_e, ex, ey, num_f, fx, fy, keep)
    if hides_lo == hides_hi:
        return (lo, hi) if hides_lo else (hi, hi)
    # they swap order along w or -w, which lies within the bearings
    wx = num_f * ex - keep * num_e * fx
    wy = num_f * ey - keep * num_e * fy
    ux, uy = np.cos(base + lo), np.sin(base + lo)
    swap = np.arctan2(ux * wy - uy * wx, ux * wx + uy * wy)
    # w or -w: the one within (or, by rounding, nearest to) the bearings
    other = swap + np.pi if swap < 0.0 else swap - np.pi
    if max(-other, other - (hi - lo)) < max(-swap, swap - (hi - lo)):
        swap = other
    swap = min(max(lo + swap, lo), hi)
    return (lo, swap) if hides_lo else (swap, hi)


RAY_SLACK = 1e-12
"""How far beyond an edge's ends (a fraction of its length) :func:`_nearest_edge` still counts a hit."""


@njit(cache=True)
def _nearest_edge(ox, oy, dx, dy, seg, start, stop):
    """Index of the segment in seg[start:stop] hit first by the ray (o, d), or -1."""
    best = np.inf
    arg = -1
    for j in range(start, stop):
        ax, ay, bx, by = seg[j, 0, 0], seg[j, 0, 1], seg[j, 1, 0], seg[j, 1, 1]
        ex, ey = bx - ax, by - ay
        den = dx * ey - dy * ex
        if den == 0.0:
            continue
        wx, wy = ax - ox, ay - oy
        t = (wx * ey - wy * ex) / den
        u = (wx * dy - wy * dx) / den
        if t > 0.0 and -RAY_SLACK <= u <= 1.0 + RAY_SLACK and t < best:
            best = t
            arg = j
    return arg


@njit(cache=True)
def occludes_one(ox, oy, seg, j_start, j_stop, t_start, t_stop, extent_start, extent_width):
    """Whether body ``J`` is hit strictly before target ``T`` along some direction of ``T``'s extent (exact).

    Parameters
    ----------
    ox, oy : float
        Observer, metres.
    seg : ndarray, shape (s, 2, 2)
        Edges, ``[[x0, y0], [x1, y1]]`` metres; ``J`` owns ``seg[j_start:j_stop]``, ``T`` owns
        ``seg[t_start:t_stop]``.
    extent_start, extent_width : float
        ``T``'s angular extent, radians counter-clockwise from +x (see :func:`geometry.angular_extent`).

    Returns
    -------
    bool
    """
    whole_lo = np.zeros(1)
    whole_hi = np.full(1, extent_width)
    return occludes_within(ox, oy, seg, j_start, j_stop, t_start, t_stop, extent_start, whole_lo, whole_hi)


@njit(cache=True)
def occludes_within(ox, oy, seg, j_start, j_stop, t_start, t_stop, extent_start, allowed_lo, allowed_hi):
    """:func:`occludes_one` along the directions ``extent_start + [allowed_lo[i], allowed_hi[i]]`` only (sorted,
    disjoint intervals of bearings relative to ``T``'s extent start, radians, within its width)."""
    extent_width = allowed_hi[-1]
    n = 2 * (j_stop - j_start + t_stop - t_start) + 2 * len(allowed_lo)
    cuts = np.empty(n)
    k = 0
    for i in range(len(allowed_lo)):
        cuts[k] = allowed_lo[i]
        cuts[k + 1] = allowed_hi[i]
        k += 2
    for lo, hi in ((j_start, j_stop), (t_start, t_stop)):
        for j in range(lo, hi):
            for e in range(2):
                rel = wrap_positive(np.arctan2(seg[j, e, 1] - oy, seg[j, e, 0] - ox) - extent_start)
                if rel < extent_width:
                    cuts[k] = rel
                    k += 1
    cuts = sorted_values(cuts[:k])
    interval = 0
    for i in range(k - 1):
        u0, u1 = cuts[i], cuts[i + 1]
        if u1 - u0 < MIN_PIECE:
            continue
        while interval < len(allowed_hi) and allowed_hi[interval] <= u0:
            interval += 1
        if interval == len(allowed_hi):
            break
        if u0 < allowed_lo[interval]:  # a gap between allowed intervals
            continue
        mid = extent_start + 0.5 * (u0 + u1)
        dx, dy = np.cos(mid), np.sin(mid)
        target_edge = _nearest_edge(ox, oy, dx, dy, seg, t_start, t_stop)
        body_edge = _nearest_edge(ox, oy, dx, dy, seg, j_start, j_stop)
        if target_edge < 0 or body_edge < 0:
            continue
        for u in (u0, u1):
            ex, ey = np.cos(extent_start + u), np.sin(extent_start + u)
            target_distance = _edge_line_distance(ox, oy, ex, ey, seg, target_edge)
            body_distance = _edge_line_distance(ox, oy, ex, ey, seg, body_edge)
            if body_distance < target_distance * (1.0 - RELATIVE_TOLERANCE):
                return True
    return False


@njit(cache=True)
def _occludes_pairs(ox, oy, seg, seg_offsets, occluder, target, extent_start, extent_width):
    """:func:`occludes_one` for each pair ``(occluder[p], target[p])`` of body numbers, shape (p,) bool."""
    out = np.zeros(len(occluder), dtype=np.bool_)
    for p in range(len(occluder)):
        j, t = occluder[p], target[p]
        out[p] = occludes_one(
            ox,
            oy,
            seg,
            seg_offsets[j],
            seg_offsets[j + 1],
            seg_offsets[t],
            seg_offsets[t + 1],
            extent_start[t],
            extent_width[t],
        )
    return out


def occludes(
    observer: np.ndarray,
    segments: np.ndarray,
    segment_offsets: np.ndarray,
    occluder: np.ndarray,
    target: np.ndarray,
    extent_start: np.ndarray,
    extent_width: np.ndarray,
) -> np.ndarray:
    """Decide, for candidate pairs, whether ``occluder`` is hit before ``target`` in some direction.

    Parameters
    ----------
    observer : ndarray, shape (2,)
        Observer position, metres.
    segments : ndarray, shape (s, 2, 2)
        Edges of all bodies, body after body; body ``b`` owns ``segments[segment_offsets[b]:segment_offsets[b+1]]``.
    segment_offsets : ndarray, shape (n_bodies + 1,), int64
    occluder, target : ndarray, shape (p,), int64
        Body numbers of each candidate pair. Targets must have the observer outside them.
    extent_start, extent_width : ndarray, shape (n_bodies,)
        Angular extent of each body (radians, see :func:`geometry.angular_extent`); read for targets only.

    Returns
    -------
    ndarray of bool, shape (p,)
    """
    if len(occluder) == 0:
        return np.zeros(0, dtype=bool)
    return _occludes_pairs(
        float(observer[0]),
        float(observer[1]),
        np.ascontiguousarray(segments, dtype=np.float64),
        np.asarray(segment_offsets, dtype=np.int64),
        np.asarray(occluder, dtype=np.int64),
        np.asarray(target, dtype=np.int64),
        np.asarray(extent_start, dtype=np.float64),
        np.asarray(extent_width, dtype=np.float64),
    )


def occluding_pairs(
    observer: np.ndarray,
    segments: np.ndarray,
    segment_offsets: np.ndarray,
    blocking: np.ndarray,
    targets: np.ndarray,
    extent_start: np.ndarray,
    extent_width: np.ndarray,
    n_objects: int,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """All pairs ``(occluder, target)`` of body numbers where the occluder is hit before the target somewhere.

    Candidates are blocking objects whose extent meets the target's and static bodies with an edge doing so, nearer
    than the target's farthest point (:func:`.candidates.candidate_pairs`); those certain to occlude (an object
    entirely nearer, a static edge nearer by a margin) are accepted at once, the rest are decided by
    :func:`occludes`.

    Parameters
    ----------
    observer : ndarray, shape (2,)
    segments, segment_offsets
        Edges of all bodies grouped by body, as for :func:`occludes`; bodies ``0 .. n_objects - 1`` are objects.
    blocking : ndarray of bool, shape (n_bodies,)
        Bodies that can occlude.
    targets : ndarray, shape (t,), int64
        Target body numbers (objects with the observer outside).
    extent_start, extent_width : ndarray, shape (n_objects,)
        Angular extents of the objects, radians.

    Returns
    -------
    occluder, target : ndarray, shape (p,), int64
    hidden : ndarray of bool, shape (n_bodies,)
        Targets found entirely hidden behind a single object (a cheap sufficient test, not all hidden ones).
    """
    empty = np.zeros(0, dtype=np.int64)
    n_bodies = len(segment_offsets) - 1
    if len(targets) == 0 or len(segments) == 0:
        return empty, empty, np.zeros(n_bodies, dtype=bool)
    seg_body = np.repeat(np.arange(n_bodies), np.diff(segment_offsets))
    body, target, certain, hidden = candidate_pairs(
        float(observer[0]),
        float(observer[1]),
        np.ascontiguousarray(segments, dtype=np.float64),
        seg_body,
        np.asarray(blocking, dtype=np.bool_),
        np.asarray(targets, dtype=np.int64),
        np.asarray(extent_start, dtype=np.float64),
        np.asarray(extent_width, dtype=np.float64),
        int(n_objects),
    )
    check = ~certain
    certain[check] = occludes(
        observer, segments, segment_offsets, body[check], target[check], extent_start, extent_width
    )
    return body[certain], target[certain], hidden
