"""Step 3 of the sweep for one observer: the angular sweep over the pieces, with an indexed binary heap.

Start and end events are sorted by bearing; the active pieces live in an indexed binary heap (``heap`` holds
piece numbers, ``position[piece]`` where each sits, so a piece is deleted where it is, not when it surfaces) and
only pieces active together are ever compared. Two pieces are compared along the bisector of the directions they
share, where neither touches the other, which makes the comparison independent of the sweep position. Between two
consecutive event bearings the heap's top is the nearest piece; the interval's angle is credited to its body, and
to the bodies of pieces that it does not hide by the occlusion test's relative tolerance (coincident or nearly
coincident edges of overlapping or duplicated objects: along those directions no body is hit before the other, so
each is the first thing hit, as :mod:`...occlusion` and the definition decide).
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import reserve
from ...geometry.occlusion import MIN_PIECE, hidden_span
from ...geometry.sorting import argsort_floats
from ...geometry.view import limited_angle
from .pieces import EX, EY, HI, LO, NUM, TWO_PI, UHX, UHY, ULX, ULY


# numpy's error model: a piece whose line passes through the viewpoint, shared over half a turn, has a zero
# bisector and 0 / 0 as its distance (NaN: no order, the tie rule decides) instead of raising ZeroDivisionError
@njit(cache=True, error_model="numpy")
def nearer(pieces, a, b):
    """Whether piece ``a`` is nearer than piece ``b`` along the bisector of the directions both cover.

    ``pieces`` is the (k, 9) piece table of :mod:`.pieces`; the distance of a piece along a direction ``d`` is
    ``NUM / (d x (q - p))``, here with ``d`` the (unnormalised) sum of the unit directions at the shared
    interval's ends. Ties (and distances that are not numbers) go to the lower piece number.
    """
    if pieces[a, LO] >= pieces[b, LO]:
        x1, y1 = pieces[a, ULX], pieces[a, ULY]
    else:
        x1, y1 = pieces[b, ULX], pieces[b, ULY]
    if pieces[a, HI] <= pieces[b, HI]:
        x2, y2 = pieces[a, UHX], pieces[a, UHY]
    else:
        x2, y2 = pieces[b, UHX], pieces[b, UHY]
    dx, dy = x1 + x2, y1 + y2
    distance_a = pieces[a, NUM] / (dx * pieces[a, EY] - dy * pieces[a, EX])
    distance_b = pieces[b, NUM] / (dx * pieces[b, EY] - dy * pieces[b, EX])
    if distance_a < distance_b:
        return True
    if distance_a > distance_b:
        return False
    return a < b


@njit(cache=True)
def unhidden_by_top(pieces, top, other, lo, hi):
    """The bearings of ``[lo, hi]`` (radians, an interval between events) along which the nearest piece ``top``
    does not hide piece ``other`` (:func:`...occlusion.hidden_span`: ``other`` lies within the occlusion test's
    relative tolerance of it, as coincident edges of overlapping or duplicated objects do), ``(a, b)``; empty
    (``a >= b``) when it hides all of them."""
    h_lo, h_hi = hidden_span(
        lo, 0.0, hi - lo, pieces[other, NUM], pieces[other, EX], pieces[other, EY],
        pieces[top, NUM], pieces[top, EX], pieces[top, EY],
    )  # fmt: skip
    if h_hi <= h_lo:
        return lo, hi
    if h_lo > 0.0:
        return lo, lo + h_lo
    return lo + h_hi, hi


CLEARLY_NEARER = 1.0 - 1e-6
"""A piece whose farthest point is nearer than this times another's nearest point lies wholly nearer than it by far
more than the occlusion test's relative tolerance (1e-9) and rounding: it hides all of the other, which ties with it
nowhere."""


@njit(cache=True, error_model="numpy")
def piece_reach(pieces):
    """Per piece, the distance (metres) of its farthest point and of its nearest point from the observer.

    A piece is a segment between the points its edge's line meets at the bearings ``LO`` and ``HI``: it is
    farthest at an end (inf where an end is not a number or lies behind the observer) and nearest at the foot of the
    perpendicular from the observer where that falls between the ends, else at an end; never nearer than its line.

    >>> import math, numpy as np
    >>> def piece(p, q):  # the piece table's row of the whole edge p -> q (columns of .pieces)
    ...     (px, py), (qx, qy) = p, q
    ...     lo, hi = math.atan2(py, px), math.atan2(qy, qx)
    ...     return [lo, hi, math.cos(lo), math.sin(lo), math.cos(hi), math.sin(hi), qx - px, qy - py,
    ...             px * (qy - py) - py * (qx - px)]
    >>> farthest, nearest = piece_reach(np.array([piece((3, -4), (3, 4)), piece((10, 1), (10, 2))]))
    >>> farthest.round(9).tolist(), nearest.round(9).tolist()  # (the second's line passes 10 m away)
    ([5.0, 10.198039027], [3.0, 10.049875621])
    """
    k = len(pieces)
    farthest = np.empty(k)
    nearest = np.empty(k)
    for p in range(k):
        ex, ey, num = pieces[p, EX], pieces[p, EY], pieces[p, NUM]
        at_lo = num / (pieces[p, ULX] * ey - pieces[p, ULY] * ex)
        at_hi = num / (pieces[p, UHX] * ey - pieces[p, UHY] * ex)
        far = max(at_lo, at_hi)
        line = abs(num) / np.sqrt(ex * ex + ey * ey)
        if far >= 0.0 and at_lo >= 0.0 and at_hi >= 0.0 and far < np.inf:  # (NaN compares False)
            farthest[p] = far
            # the segment from the end at LO (x0, y0) to the end at HI: where along it the foot falls, clamped
            x0, y0 = at_lo * pieces[p, ULX], at_lo * pieces[p, ULY]
            dx, dy = at_hi * pieces[p, UHX] - x0, at_hi * pieces[p, UHY] - y0
            length2 = dx * dx + dy * dy
            t = min(max(-(x0 * dx + y0 * dy) / length2, 0.0), 1.0) if length2 > 0.0 else 0.0
            nearest[p] = max(line, np.sqrt((x0 + t * dx) ** 2 + (y0 + t * dy) ** 2))
        else:
            farthest[p] = np.inf
            nearest[p] = line
    return farthest, nearest


@njit(cache=True, inline="always")
def _ends_first(pieces, a, b):
    """Whether piece ``a`` ends before piece ``b``: at a smaller ``HI``, or at the same with a lower number."""
    return pieces[a, HI] < pieces[b, HI] or (pieces[a, HI] == pieces[b, HI] and a < b)


@njit(cache=True)
def nearest_intervals(pieces, with_ties=False):
    """The sweep: consecutive bearing intervals between events and the nearest piece over each.

    Parameters
    ----------
    pieces : ndarray, shape (k, 9)
        The piece table of :mod:`.pieces`.
    with_ties : bool
        Also list, per interval, the other pieces that the nearest piece does not hide along some of it (they
        tie with it there: see :func:`unhidden_by_top`).

    Returns
    -------
    lo, hi : ndarray, shape (q,)
        Bearings (radians), ``hi[i] == lo[i + 1]`` where pieces are active on both sides; together they cover
        the bearings where some piece is active, in ascending order.
    top : ndarray, shape (q,), int64
        The nearest piece over ``[lo[i], hi[i]]``.
    tie_offsets : ndarray, shape (q + 1,), int64
    ties : ndarray, int64
        With ``with_ties``, the pieces tying with ``top[i]`` are ``ties[tie_offsets[i]:tie_offsets[i + 1]]`` (they
        sit in the heap right below its top: every piece between them and the top ties with it too, being
        nearer than they are); else empty.
    """
    k = len(pieces)
    out_lo = np.empty(2 * k)
    out_hi = np.empty(2 * k)
    out_top = np.empty(2 * k, dtype=np.int64)
    tie_offsets = np.zeros(2 * k + 1 if with_ties else 1, dtype=np.int64)
    ties = np.empty(0, dtype=np.int64)
    n_ties = 0
    q = 0
    if k == 0:
        return out_lo, out_hi, out_top, tie_offsets, ties
    by_lo = argsort_floats(pieces[:, LO].copy())
    heap = np.empty(k, dtype=np.int64)
    position = np.full(k, -1, dtype=np.int64)
    # the active pieces again, as a binary min-heap by (HI, piece number): the ends come out in the order that a
    # stable sort of all ends by HI gives, without sorting the pieces that are not active
    ends = np.empty(k, dtype=np.int64)
    stack = np.empty(k if with_ties else 0, dtype=np.int64)
    farthest, nearest = piece_reach(pieces) if with_ties else (pieces[:0, 0], pieces[:0, 0])
    size = 0  # active pieces, in both heaps
    i = 0  # next start event, in by_lo
    while i < k or size > 0:
        if size > 0 and not (i < k and pieces[by_lo[i], LO] < pieces[ends[0], HI]):
            theta = pieces[ends[0], HI]
        else:
            theta = pieces[by_lo[i], LO]
        if theta != theta:  # (no event would ever match it: the sweep would not end)
            raise ValueError("a piece's bearing is not a number")
        # the events at theta, ends first, one at a time: a piece ending at slot h is replaced by the heap's last,
        # a starting piece is appended; then the piece at slot h moves up while nearer than its parent, else down
        # while a child is nearer; likewise in the ends' heap. (Written out here, once, rather than as sift functions:
        # a numba function with a loop that takes arrays costs reference counting on every call, inlined or not.)
        while (size > 0 and pieces[ends[0], HI] == theta) or (i < k and pieces[by_lo[i], LO] == theta):
            if size > 0 and pieces[ends[0], HI] == theta:
                ending = ends[0]
                size -= 1
                x = ends[size]  # out of the ends' heap: its last moves down from the root while a child ends sooner
                e = 0
                while True:
                    child = 2 * e + 1
                    if child >= size:
                        break
                    if child + 1 < size and _ends_first(pieces, ends[child + 1], ends[child]):
                        child += 1
                    if not _ends_first(pieces, ends[child], x):
                        break
                    ends[e] = ends[child]
                    e = child
                ends[e] = x
                h = position[ending]
                position[ending] = -1
                if h == size:  # it was the last slot: nothing moves
                    continue
                heap[h] = heap[size]
            else:
                x = by_lo[i]
                i += 1
                e = size  # into the ends' heap: up from the last slot while it ends sooner than its parent
                while e > 0:
                    parent = (e - 1) >> 1
                    if not _ends_first(pieces, x, ends[parent]):
                        break
                    ends[e] = ends[parent]
                    e = parent
                ends[e] = x
                h = size
                heap[h] = x
                size += 1
            x = heap[h]
            if h > 0 and nearer(pieces, x, heap[(h - 1) >> 1]):
                while h > 0:
                    parent = (h - 1) >> 1
                    y = heap[parent]
                    if not nearer(pieces, x, y):
                        break
                    heap[h] = y
                    position[y] = h
                    h = parent
            else:
                while True:
                    child = 2 * h + 1
                    if child >= size:
                        break
                    if child + 1 < size and nearer(pieces, heap[child + 1], heap[child]):
                        child += 1
                    if not nearer(pieces, heap[child], x):
                        break
                    heap[h] = heap[child]
                    position[heap[h]] = h
                    h = child
            heap[h] = x
            position[x] = h
        if size > 0:
            following = pieces[ends[0], HI]
            if i < k and pieces[by_lo[i], LO] < following:
                following = pieces[by_lo[i], LO]
            out_lo[q] = theta
            out_hi[q] = following
            out_top[q] = heap[0]
            if with_ties and size > 1:  # the heap's slots below the top that tie with it, depth first
                if n_ties + size > len(ties):  # (grown rarely: a call that returns an array costs reference counting)
                    ties = reserve(ties, n_ties, n_ties + size)
                stack[0] = 0
                n_stack = 1
                while n_stack > 0:
                    n_stack -= 1
                    slot = stack[n_stack]
                    for child in (2 * slot + 1, 2 * slot + 2):
                        if child >= size or farthest[heap[0]] < nearest[heap[child]] * CLEARLY_NEARER:
                            continue  # (the top lies wholly nearer: it hides all of the child, which ties nowhere)
                        a, b = unhidden_by_top(pieces, heap[0], heap[child], theta, following)
                        if b - a >= MIN_PIECE:
                            ties[n_ties] = heap[child]
                            n_ties += 1
                            stack[n_stack] = child
                            n_stack += 1
            if with_ties:
                tie_offsets[q + 1] = n_ties
            q += 1
    return out_lo[:q], out_hi[:q], out_top[:q], tie_offsets[: q + 1 if with_ties else 1], ties[:n_ties]


@njit(cache=True)
def visible_angles(pieces, body, n_bodies, wedge_start, fov, max_range):
    """Angle (radians) along which each body's pieces are the nearest thing hit, inside the field of view
    ``[wedge_start, wedge_start + fov]`` and within ``max_range`` metres (see :func:`...view.limited_angle`),
    shape (n_bodies,); intervals thinner than :data:`...occlusion.MIN_PIECE` count for nothing.

    Parameters
    ----------
    pieces : ndarray, shape (k, 9)
        The piece table of :mod:`.pieces`.
    body : ndarray, shape (>= k,), int64
        The body of each piece, in ``range(n_bodies)``.
    wedge_start, fov, max_range : float
        Radians, radians (``>= 2π``: all around), metres (``inf``: no limit).
    """
    lo, hi, top, tie_offsets, ties = nearest_intervals(pieces, True)
    return credited_angles(pieces, body, n_bodies, wedge_start, fov, max_range, lo, hi, top, tie_offsets, ties)


@njit(cache=True)
def credited_angles(pieces, body, n_bodies, wedge_start, fov, max_range, lo, hi, top, tie_offsets, ties):
    """:func:`visible_angles` from the sweep's intervals (what :func:`nearest_intervals` gives with ties)."""
    limited = fov < TWO_PI or max_range < np.inf
    visible = np.zeros(n_bodies)
    credited = np.full(n_bodies, -1, dtype=np.int64)  # the last interval each body was credited
    for q in range(len(lo)):
        if hi[q] - lo[q] < MIN_PIECE:  # (rounding between events at one bearing, such as collinear corners)
            continue
        t = top[q]
        credited[body[t]] = q
        for r in range(tie_offsets[q] - 1, tie_offsets[q + 1]):  # the top, then the pieces tying with it
            a, b = lo[q], hi[q]
            if r >= tie_offsets[q]:
                t = ties[r]
                if credited[body[t]] == q:  # (another of this body's pieces)
                    continue
                credited[body[t]] = q
                a, b = unhidden_by_top(pieces, top[q], t, a, b)
            if limited:
                visible[body[t]] += limited_angle(
                    a, b, pieces[t, EX], pieces[t, EY], pieces[t, NUM], wedge_start, fov, max_range
                )
            else:
                visible[body[t]] += b - a
    return visible
