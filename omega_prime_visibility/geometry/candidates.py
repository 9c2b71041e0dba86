"""Which bodies may hide which targets, from one viewpoint: the (body, target) pairs whose bearings meet and whose
distances allow it (each pair once), with the pairs certain to occlude. The exact decision per pair is
:mod:`.occlusion`'s.

A blocking object is one item, its angular extent (with :data:`CANDIDATE_EPS` to spare); a blocking static body
(a building, a wall: concave, long) is one item per edge. Items are grouped by bearing, so a target meets only the
items of its own bearings. A pair is a candidate when an item overlaps the target's extent and comes nearer than
the target's farthest point: every body with an edge doing so is among them (an object's extent holds all its
edges' bearings, its nearest point is at most any edge's distance), and a pair found only through the object's
whole extent is left to the exact test, which finds no occlusion where no edge is nearer. A static edge must
moreover come nearer than the target's farthest point *within the target's bearings* (:func:`nearest_within`: a
building's side along the street is near the observer, but beside the targets on the street); where that cannot
be told safely (the edge meets the extent in two pieces, or over under :data:`FILTER_MIN_OVERLAP`) the pair stays.

Public, for the engines: :func:`candidate_pairs`, :func:`certainly_occludes`, :func:`bearing_bins`,
:func:`bin_range`.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit
from .kernels import TWO_PI, nearest_offset, prefix_sum, ray_line_distance, reserve, wrap_positive

MIN_PIECE = 1e-12
"""Radians: thinner pieces of a bearing interval are ignored (here and in :mod:`.occlusion`)."""

CANDIDATE_EPS = 1e-9
"""Radians: intervals this close count as overlapping (the exact test decides)."""

STATIC_ACCEPT_ANGLE = 1e-9
"""Radians of overlap a static edge needs with a target's extent to be accepted without the exact test ..."""

STATIC_ACCEPT_RELATIVE = 1e-7
"""... and it must lie nearer than ``1 - STATIC_ACCEPT_RELATIVE`` times the target's nearest distance."""

FILTER_MIN_OVERLAP = 1e-6
"""Radians: a static edge meeting a target's bearings over less (nearly pointing at the observer, where distances
along those bearings are ill-conditioned) is left to the exact test."""

NEARER_MARGIN = 1e-9
"""A static edge coming no nearer than ``1 + NEARER_MARGIN`` times a target's farthest point within its bearings
cannot hide it (the exact test asks for ``1 - 1e-9`` times the target's distance): no candidate pair."""

BEARING_BINS = 256
"""Bins over the full turn that items are grouped into by bearing, so a target meets only the items of its own
bearings (:func:`candidate_pairs`; in town a target's extent holds a few per cent of them)."""


@njit(cache=True, inline="always")
def certainly_occludes(overlap, far, is_object, near_t):
    """Whether a body's bearing interval overlapping a target's extent by ``overlap`` radians, lying within ``far``
    metres of the observer, certainly occludes a target whose nearest point is ``near_t`` metres away: an object
    entirely nearer with more than :data:`MIN_PIECE` of overlap, a static edge nearer by a safety margin
    (:data:`STATIC_ACCEPT_ANGLE`, :data:`STATIC_ACCEPT_RELATIVE`). Shared by the engines' candidate searches.

    Examples
    --------
    >>> bool(certainly_occludes(0.1, 5.0, True, 10.0)), bool(certainly_occludes(0.1, 10.0, True, 10.0))
    (True, False)
    >>> bool(certainly_occludes(1e-10, 5.0, False, 10.0))
    False
    """
    if is_object:
        return overlap > MIN_PIECE and far < near_t
    return overlap > STATIC_ACCEPT_ANGLE and far < near_t * (1.0 - STATIC_ACCEPT_RELATIVE)


@njit(cache=True, inline="always")
def bin_range(lo, width, n_bins, spare):
    """The bins (unwrapped, ``first <= last``) covering the bearings ``[lo, lo + width]``, with ``spare`` bins to
    spare on each side; all of them once that makes a full turn. Items are binned with one to spare, so a target
    looking in its own bins (none to spare) meets every item whose bearings meet its own, whatever the rounding.

    Examples
    --------
    >>> bin_range(0.01, 0.02, 256, 0), bin_range(0.01, 0.02, 256, 1), bin_range(-0.01, 0.02, 256, 0)
    ((0, 1), (-1, 2), (255, 256))
    """
    size = TWO_PI / n_bins
    first = int(np.floor(wrap_positive(lo) / size)) - spare
    last = first + 2 * spare + int(np.floor(max(width, 0.0) / size)) + 1
    if last - first + 1 >= n_bins:
        return 0, n_bins - 1
    return first, last


@njit(cache=True)
def bearing_bins(item_lo, item_width):
    """Items grouped by the bins their bearings cover (:func:`bin_range`, one to spare): CSR offsets over
    :data:`BEARING_BINS` bins and the items, ascending within a bin."""
    n_bins = BEARING_BINS
    offsets = np.zeros(n_bins + 1, dtype=np.int64)
    for j in range(len(item_lo)):
        first, last = bin_range(item_lo[j], item_width[j], n_bins, 1)
        for q in range(first, last + 1):
            offsets[q % n_bins + 1] += 1
    prefix_sum(offsets)
    fill = offsets[:-1].copy()
    members = np.empty(offsets[-1], dtype=np.int64)
    for j in range(len(item_lo)):
        first, last = bin_range(item_lo[j], item_width[j], n_bins, 1)
        for q in range(first, last + 1):
            c = q % n_bins
            members[fill[c]] = j
            fill[c] += 1
    return offsets, members


@njit(cache=True)
def nearest_within(ax, ay, bx, by, lo, width):
    """The least distance (metres) from the origin to the segment ``a b`` (metres) along the bearings
    ``[lo, lo + width]`` (radians, within the segment's own): at the foot of the perpendicular to its line where
    that lies within them, else at one of their ends.

    Examples
    --------
    The wall x = 10 from y = -10 to 10, seen between 0 and 45 degrees: nearest straight ahead (10 m); between 30 and
    45 degrees, at 30 degrees (10 / cos 30 = 11.547 m):

    >>> round(nearest_within(10.0, -10.0, 10.0, 10.0, 0.0, np.pi / 4), 3)
    10.0
    >>> round(nearest_within(10.0, -10.0, 10.0, 10.0, np.pi / 6, np.pi / 12), 3)
    11.547
    """
    ex, ey = bx - ax, by - ay
    ee = ex * ex + ey * ey
    if ee == 0.0:
        return np.hypot(ax, ay)
    u = -(ax * ex + ay * ey) / ee
    fx, fy = ax + u * ex, ay + u * ey  # the foot of the perpendicular from the origin to the line
    if wrap_positive(np.arctan2(fy, fx) - lo) <= width:
        return np.hypot(fx, fy)
    return min(
        abs(ray_line_distance(np.cos(lo), np.sin(lo), ax, ay, ex, ey)),
        abs(ray_line_distance(np.cos(lo + width), np.sin(lo + width), ax, ay, ex, ey)),
    )


@njit(cache=True, inline="always")
def _shared(lo, width, start_t, width_t):
    """How the bearings ``[lo, lo + width]`` meet a target's extent ``[start_t, start_t + width_t]`` (radians):
    the piece that starts in the extent, else the one the interval enters it with, as its width (-1 when they do
    not meet) and first bearing; and whether they meet in two pieces (the two widths exceed a full turn: a concave
    target's extent wider than half a turn, an edge reaching round to its other end)."""
    rel = wrap_positive(lo - start_t)
    two = rel < width_t and rel + width > TWO_PI
    if rel < width_t:
        return min(width_t - rel, width), lo, two
    if rel + width > TWO_PI:
        return min(rel + width - TWO_PI, width_t), start_t, two
    return -1.0, start_t, two


@njit(cache=True)
def _items(ox, oy, seg, seg_body, blocking, start, width, n_objects):
    """The bodies' nearest and farthest distances from ``(ox, oy)`` (metres, shape (n_bodies,): chosen by squared
    norms, measured once by hypot; a hypot per edge end cost a third of the search), and the items of the search
    (see the module docstring): ``(lo, width, near, far, body, edge)``, static edges first (``edge`` their edge), then
    the blocking objects (``edge`` -1)."""
    n_bodies = len(blocking)
    m = len(seg)
    n_items = 0
    for b in range(n_objects):
        n_items += blocking[b]
    for j in range(m):
        n_items += seg_body[j] >= n_objects and blocking[seg_body[j]]
    item_lo = np.empty(n_items)
    item_width = np.empty(n_items)
    item_near = np.empty(n_items)
    item_far = np.empty(n_items)
    item_body = np.empty(n_items, dtype=np.int64)
    item_edge = np.full(n_items, -1, dtype=np.int64)
    nearest = np.zeros((n_bodies, 3))  # squared norm, x, y
    farthest = np.zeros((n_bodies, 3))
    nearest[:, 0] = np.inf
    farthest[:, 0] = -1.0
    k = 0
    for j in range(m):
        ax, ay = seg[j, 0, 0] - ox, seg[j, 0, 1] - oy
        bx, by = seg[j, 1, 0] - ox, seg[j, 1, 1] - oy
        dx, dy = nearest_offset(-ax, -ay, bx - ax, by - ay)
        fx, fy = (ax, ay) if ax * ax + ay * ay >= bx * bx + by * by else (bx, by)
        b = seg_body[j]
        if dx * dx + dy * dy < nearest[b, 0]:
            nearest[b, 0], nearest[b, 1], nearest[b, 2] = dx * dx + dy * dy, dx, dy
        if fx * fx + fy * fy > farthest[b, 0]:
            farthest[b, 0], farthest[b, 1], farthest[b, 2] = fx * fx + fy * fy, fx, fy
        if b >= n_objects and blocking[b]:
            span = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
            ta = np.arctan2(ay, ax)
            item_lo[k] = ta if span >= 0 else ta + span
            item_width[k] = abs(span)
            item_near[k], item_far[k] = np.hypot(dx, dy), np.hypot(fx, fy)
            item_body[k], item_edge[k] = b, j
            k += 1
    near = np.full(n_bodies, np.inf)
    far = np.zeros(n_bodies)
    for b in range(n_bodies):
        if np.isfinite(nearest[b, 0]):
            near[b], far[b] = np.hypot(nearest[b, 1], nearest[b, 2]), np.hypot(farthest[b, 1], farthest[b, 2])
    for b in range(n_objects):
        if blocking[b]:
            item_lo[k], item_width[k] = start[b] - CANDIDATE_EPS, width[b] + 2.0 * CANDIDATE_EPS
            item_near[k], item_far[k], item_body[k] = near[b], far[b], b
            k += 1
    return near, far, (item_lo, item_width, item_near, item_far, item_body, item_edge)


@njit(cache=True)
def candidate_pairs(ox, oy, seg, seg_body, blocking, targets, start, width, n_objects):
    """Pairs (body, target) where a blocking body's item (see the module docstring) overlaps the target's extent
    and comes nearer than the target's farthest point, each pair once, grouped by target in the order of
    ``targets``; whether the pair certainly occludes (:func:`certainly_occludes`); and the targets found hidden
    behind a single object (wholly inside the extent of an object entirely nearer).

    Parameters
    ----------
    ox, oy : float
        The viewpoint, metres.
    seg : ndarray, shape (s, 2, 2)
        Edges of all bodies (objects ``0 .. n_objects - 1``, then static sources), metres; ``seg_body`` (s,) their
        body numbers, ascending.
    blocking : ndarray of bool, shape (n_bodies,)
    targets : ndarray, shape (t,), int64
        Objects with the viewpoint outside.
    start, width : ndarray, shape (n_objects,)
        The objects' angular extents, radians.

    Returns
    -------
    body, target : ndarray, shape (p,), int64
    certain : ndarray of bool, shape (p,)
    hidden : ndarray of bool, shape (n_bodies,)
    """
    n_bodies = len(blocking)
    near, far, items = _items(ox, oy, seg, seg_body, blocking, start, width, n_objects)
    item_lo, item_width, item_near, item_far, item_body, item_edge = items
    n_items = len(item_lo)
    cap = 8 * len(targets) + 16
    out_body = np.empty(cap, dtype=np.int64)
    out_target = np.empty(cap, dtype=np.int64)
    out_certain = np.empty(cap, dtype=np.bool_)
    hidden = np.zeros(n_bodies, dtype=np.bool_)
    k = 0
    seen = np.full(n_bodies, -1, dtype=np.int64)  # the last target each body was paired with ...
    pair_of = np.empty(n_bodies, dtype=np.int64)  # ... and that pair's number
    bin_offsets, bin_items = bearing_bins(item_lo, item_width)
    n_bins = len(bin_offsets) - 1
    stamp = np.full(n_items, -1, dtype=np.int64)
    for r in range(len(targets)):
        t = targets[r]
        # room for a pair with every body (grown per target: an array rebound per pair costs reference counting)
        if k + n_bodies > len(out_body):
            out_body = reserve(out_body, k, k + n_bodies)
            out_target = reserve(out_target, k, k + n_bodies)
            out_certain = reserve(out_certain, k, k + n_bodies)
        first, last = bin_range(start[t], width[t], n_bins, 0)
        for q in range(first, last + 1):
            c = q % n_bins
            for i in range(bin_offsets[c], bin_offsets[c + 1]):
                it = bin_items[i]
                if stamp[it] == r:
                    continue
                stamp[it] = r
                b = item_body[it]
                if b == t or item_near[it] >= far[t]:
                    continue
                is_object = b < n_objects
                overlap, lo, two = _shared(item_lo[it], item_width[it], start[t], width[t])
                if overlap < 0.0:
                    continue
                if is_object:  # the rule as for the whole extent, unwidened
                    rel = wrap_positive(start[b] - start[t])
                    inside = rel < width[t] - MIN_PIECE or rel + width[b] > TWO_PI + MIN_PIECE
                    certain = item_far[it] < near[t] and inside
                else:
                    certain = certainly_occludes(overlap, item_far[it], False, near[t])
                if seen[b] == t:  # a static body met through another edge
                    out_certain[pair_of[b]] |= certain
                    continue
                if not is_object and not certain and overlap >= FILTER_MIN_OVERLAP:
                    # a wall beside the target (a building's side along the street) is nearer somewhere, but not
                    # within the target's bearings: no pair unless it comes nearer than the target there
                    j = item_edge[it]
                    ax, ay = seg[j, 0, 0] - ox, seg[j, 0, 1] - oy
                    bx, by = seg[j, 1, 0] - ox, seg[j, 1, 1] - oy
                    if not two and nearest_within(ax, ay, bx, by, lo, overlap) >= far[t] * (1.0 + NEARER_MARGIN):
                        continue
                seen[b], pair_of[b] = t, k
                out_body[k], out_target[k], out_certain[k] = b, t, certain
                if is_object and item_far[it] < near[t] and wrap_positive(start[t] - start[b]) + width[t] <= width[b]:
                    hidden[t] = True  # the target's whole extent inside that of an object entirely nearer
                k += 1
    return out_body[:k], out_target[:k], out_certain[:k], hidden
