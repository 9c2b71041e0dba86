"""Step 3 for targets that may not block (``occluders=``): each measured against the blocking bodies only.

A *passive* target is a target that neither blocks the view nor occludes anything (a pedestrian when only vehicles
block). Its visible angle is that of a scene holding the blocking bodies and itself alone, which needs no sweep of
its own: the blocking bodies' sweep (:func:`.heap_sweep.nearest_intervals`) gives the nearest blocking piece over
each bearing interval, and the target's own nearest pieces are compared with it interval by interval. All pieces
are cut at every crossing of two bodies' edges (:mod:`.pieces`), so over the bearings two pieces share their depth
order does not change and one comparison (:func:`.heap_sweep.nearer`, along the bisector of the shared bearings)
decides it; where the blocking piece is nearer, the target is still seen where it lies within the occlusion test's
tolerance of it (:func:`.heap_sweep.unhidden_by_top`), as in the sweep itself.
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import group_by_key
from ...geometry.occlusion import MIN_PIECE
from ...geometry.sorting import argsort_stable
from ...geometry.view import limited_angle
from .heap_sweep import credited_angles, nearer, nearest_intervals, unhidden_by_top
from .pieces import EX, EY, HI, LO, NUM, TWO_PI


@njit(cache=True)
def passive_angles(pieces, body, passive, n_bodies, wedge_start, fov, max_range):
    """Radians along which each body is the first thing hit, the passive ones (``passive[body]``, objects only)
    among the blocking bodies alone, inside the field of view ``[wedge_start, wedge_start + fov]`` and within
    ``max_range`` metres; what :func:`.heap_sweep.visible_angles` gives for the others.

    Parameters
    ----------
    pieces : ndarray, shape (k, 9)
        The piece table of :mod:`.pieces`, every piece cut where it crosses an edge of another body.
    body : ndarray, shape (k,), int64
        The body of each piece: objects ``0..n-1`` (``passive`` has their flags), then static sources.
    passive : ndarray of bool, shape (n,)
    n_bodies : int
    wedge_start, fov, max_range : float
        Radians, radians (``>= 2π``: all around), metres (``inf``: no limit).

    Returns
    -------
    ndarray, shape (n_bodies,)

    Examples
    --------
    Seen from the origin, a wall of pieces at x = 1 hides an object at x = 2 unless that object is passive; a
    passive object at x = 1/2 in front of the wall hides nothing:

    >>> import numpy as np
    >>> def piece(x, lo, hi):  # the edge x = const, from bearing lo to hi (radians)
    ...     p, q = np.array([x, x * np.tan(lo)]), np.array([x, x * np.tan(hi)])
    ...     e = q - p
    ...     return [lo, hi, np.cos(lo), np.sin(lo), np.cos(hi), np.sin(hi), e[0], e[1], p[0] * e[1] - p[1] * e[0]]
    >>> pieces = np.array([piece(1.0, -0.5, 0.5), piece(2.0, -0.2, 0.7), piece(0.5, -0.1, 0.1)])
    >>> body = np.array([0, 1, 2])
    >>> passive_angles(pieces, body, np.array([False, False, True]), 3, 0.0, 2 * np.pi, np.inf).round(6)
    array([1. , 0.2, 0.2])
    >>> passive_angles(pieces, body, np.array([False, True, True]), 3, 0.0, 2 * np.pi, np.inf).round(6)
    array([1. , 0.2, 0.2])
    """
    limited = fov < TWO_PI or max_range < np.inf
    n = len(passive)
    blocking = np.empty(len(pieces), dtype=np.int64)
    mine_all = np.empty(len(pieces), dtype=np.int64)  # the passive bodies' pieces
    n_blocking = 0
    n_mine = 0
    for p in range(len(pieces)):
        if body[p] >= n or not passive[body[p]]:
            blocking[n_blocking] = p
            n_blocking += 1
        else:
            mine_all[n_mine] = p
            n_mine += 1
    blocking = blocking[:n_blocking]
    own_offsets, own = group_by_key(body, n, mine_all[:n_mine])  # each passive body's own pieces
    blocking_pieces = pieces[blocking]
    env_lo, env_hi, env_top, tie_offsets, ties = nearest_intervals(blocking_pieces, True)
    visible = credited_angles(
        blocking_pieces, body[blocking], n_bodies, wedge_start, fov, max_range, env_lo, env_hi, env_top,
        tie_offsets, ties,
    )  # fmt: skip
    n_env = len(env_lo)
    for i in range(n):
        if own_offsets[i + 1] == own_offsets[i]:
            continue
        mine = own[own_offsets[i] : own_offsets[i + 1]]
        lo, hi, top = _own_nearest(pieces, mine)
        total = 0.0
        q = 0  # the first blocking interval that ends after the current bearing
        for r in range(len(lo)):
            g = mine[top[r]]
            cursor, end = lo[r], hi[r]
            while q < n_env and env_hi[q] <= cursor:
                q += 1
            while cursor < end:  # between consecutive events of the blocking sweep and of the body's own
                t = -1
                if q >= n_env or env_lo[q] >= end:
                    stop = end
                elif env_lo[q] > cursor:
                    stop = env_lo[q]
                else:
                    stop = min(end, env_hi[q])
                    t = blocking[env_top[q]]
                if stop - cursor >= MIN_PIECE:  # (rounding between events at one bearing, as in the sweep)
                    a, b = cursor, stop
                    if t >= 0 and not nearer(pieces, g, t):
                        a, b = unhidden_by_top(pieces, t, g, cursor, stop)
                        if b - a < MIN_PIECE:
                            a = b
                    if b > a:
                        if limited:
                            total += limited_angle(
                                a, b, pieces[g, EX], pieces[g, EY], pieces[g, NUM], wedge_start, fov, max_range
                            )
                        else:
                            total += b - a
                if t >= 0 and env_hi[q] <= end:
                    q += 1
                cursor = stop
        visible[i] = total
    return visible


@njit(cache=True)
def _own_nearest(pieces, mine):
    """A body's own nearest piece, bearing by bearing: intervals ``lo, hi`` (radians, ascending) and the position
    in ``mine`` (its piece numbers) of the piece nearest over each; pieces that share no bearing (those of a
    convex body) are their own intervals."""
    k = len(mine)
    starts = np.empty(k)
    for a in range(k):
        starts[a] = pieces[mine[a], LO]
    order = argsort_stable(starts)  # by bearing
    for a in range(1, k):
        if pieces[mine[order[a]], LO] < pieces[mine[order[a - 1]], HI]:  # overlapping pieces: the sweep decides
            lo, hi, top, _, _ = nearest_intervals(pieces[mine], True)  # (ties unused: one compiled signature)
            return lo, hi, top
    lo = np.empty(k)
    hi = np.empty(k)
    for a in range(k):
        lo[a] = pieces[mine[order[a]], LO]
        hi[a] = pieces[mine[order[a]], HI]
    return lo, hi, order
