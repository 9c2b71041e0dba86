"""Step 4b of the sweep for one observer: the candidate (target, body) pairs of :mod:`.occluders` decided.

Pairs not accepted at once go to the exact pairwise test of :mod:`...occlusion` (``occludes_one``). For two objects
it is evaluated here with the same floating-point operations on the same operands, but without the work that
``occludes_one`` repeats on every call: the vertex bearings are computed once per observer, the target's own cuts
once per target, the directions at the cuts once for the two pieces they bound, and nothing is allocated. A static
body is tested on those of its kept edges that can matter (:func:`_occludes_static`).

Bodies are numbered objects first (``0..n-1``), then static sources (``n + source``).
"""

from __future__ import annotations

import math

import numba
import numpy as np

from ...kernels import wrap_positive
from ...occlusion import MIN_PIECE, RELATIVE_TOLERANCE, _edge_line_distance, _nearest_edge, occludes_one
from .pieces import R_HI, R_LO

TWO_PI = 2.0 * math.pi
CANDIDATE_EPS = 1e-9  # radians; intervals this close count as overlapping (the exact test decides)


@numba.njit(cache=True)
def _occludes_static(
    objects, target, kept, record_edge, records, static_records, first, stop, statics, ox, oy, scratch
):
    """The exact occlusion test of a static body against a target, on the body's edges that can matter.

    A ray from outside enters a body through a front-facing edge, so only the body's kept edges whose bearing
    interval meets the target's extent and that come nearer than the target's farthest point can be hit before
    it; the others are left out (long guard rails would otherwise cost the exact test O(pieces * all edges)).

    Parameters
    ----------
    objects : ObjectsSeen
    target : int
        Object number.
    kept, record_edge, records
        The kept edges and their records (:func:`.pieces.front_facing_edges`).
    static_records : ndarray, int64
        Records grouped by static body (:func:`_records_by_static_body`); the body's are ``first:stop``, ascending.
    statics : StaticEdges
        Unshifted; the observer is at ``(ox, oy)``, metres.
    scratch : ndarray, shape (>= m_target + k, 2, 2)
        Work space for the segments handed to ``occludes_one``.
    """
    t_start, t_width, t_far = objects.start[target], objects.width[target], objects.far[target]
    m = len(objects.seg)
    k = 0
    for e in range(objects.offsets[target], objects.offsets[target + 1]):
        scratch[k] = objects.seg[e]
        k += 1
    target_edges = k
    previous = -1
    for r in static_records[first:stop]:
        e = record_edge[r]
        if e == previous or kept.distance[e, 0] >= t_far:
            continue
        x = (records[r, R_LO] - t_start) % TWO_PI
        if not (x <= t_width + CANDIDATE_EPS or x + (records[r, R_HI] - records[r, R_LO]) >= TWO_PI - CANDIDATE_EPS):
            continue
        previous = e
        s = kept.edge[e] - m
        scratch[k, 0, 0] = statics.start[s, 0] - ox
        scratch[k, 0, 1] = statics.start[s, 1] - oy
        scratch[k, 1, 0] = statics.end[s, 0] - ox
        scratch[k, 1, 1] = statics.end[s, 1] - oy
        k += 1
    if k == target_edges:
        return False
    return occludes_one(0.0, 0.0, scratch, target_edges, k, 0, target_edges, t_start, t_width)


@numba.njit(cache=True, inline="always")
def _vertex_bearings(seg, offsets, i, bearing, have_bearing):
    """Fill ``bearing`` (radians, scalar ``np.arctan2`` as ``occludes_one`` takes it) for object ``i``'s vertices,
    once per observer: vertex ``v`` is the start of edge ``v`` (and the end of the edge before it)."""
    if have_bearing[i]:
        return
    for v in range(offsets[i], offsets[i + 1]):
        bearing[v] = np.arctan2(seg[v, 0, 1], seg[v, 0, 0])
    have_bearing[i] = True


@numba.njit(cache=True, inline="always")
def _target_cuts(offsets, bearing, t, extent_start, extent_width, cuts):
    """The cuts that ``occludes_one`` makes in target ``t``'s extent for ``t`` itself: 0, the width and its vertices'
    bearings relative to the extent start (radians, those below the width); written to ``cuts``, count returned."""
    cuts[0] = 0.0
    cuts[1] = extent_width
    k = 2
    for v in range(offsets[t], offsets[t + 1]):
        rel = wrap_positive(bearing[v] - extent_start)
        if rel < extent_width:
            cuts[k] = rel
            k += 1
    return k


@numba.njit(cache=True)
def _occludes_object(seg, offsets, bearing, j, t, extent_start, extent_width, target_cuts, n_target_cuts, cuts):
    """``occludes_one(0.0, 0.0, seg, offsets[j], offsets[j + 1], offsets[t], offsets[t + 1], extent_start,
    extent_width)``, the same floating-point operations on the same operands, without its per-call work.

    The vertex ``bearing`` (radians, :func:`_vertex_bearings`) and the target's own cuts (:func:`_target_cuts`)
    are computed once per observer and target instead of once per pair; every vertex is cut at once instead of
    once per edge end (equal cuts only make empty pieces, which are skipped); the directions at the cuts are
    computed once for the two pieces they bound; ``cuts`` is work space (shape >= ``n_target_cuts`` + J's
    vertices) sorted by insertion (few values, all >= +0.0: the same order as ``np.sort``).
    """
    for k in range(n_target_cuts):  # (a loop: slices would cost reference counting on every call)
        cuts[k] = target_cuts[k]
    k = n_target_cuts
    for v in range(offsets[j], offsets[j + 1]):
        rel = wrap_positive(bearing[v] - extent_start)
        if rel < extent_width:
            cuts[k] = rel
            k += 1
    for a in range(1, k):
        value = cuts[a]
        b = a - 1
        while b >= 0 and cuts[b] > value:
            cuts[b + 1] = cuts[b]
            b -= 1
        cuts[b + 1] = value
    t_start, t_stop, j_start, j_stop = offsets[t], offsets[t + 1], offsets[j], offsets[j + 1]
    cached = -1  # the cut whose direction (cached_x, cached_y) was computed last
    cached_x, cached_y = 0.0, 0.0
    for i in range(k - 1):
        u0, u1 = cuts[i], cuts[i + 1]
        if u1 - u0 < MIN_PIECE:
            continue
        if extent_width <= u0:
            break
        mid = extent_start + 0.5 * (u0 + u1)
        dx, dy = np.cos(mid), np.sin(mid)
        target_edge = _nearest_edge(0.0, 0.0, dx, dy, seg, t_start, t_stop)
        body_edge = _nearest_edge(0.0, 0.0, dx, dy, seg, j_start, j_stop)
        if target_edge < 0 or body_edge < 0:
            continue
        for end in range(i, i + 2):
            if end == cached:
                ex, ey = cached_x, cached_y
            else:
                ex, ey = np.cos(extent_start + cuts[end]), np.sin(extent_start + cuts[end])
                cached, cached_x, cached_y = end, ex, ey
            target_distance = _edge_line_distance(0.0, 0.0, ex, ey, seg, target_edge)
            body_distance = _edge_line_distance(0.0, 0.0, ex, ey, seg, body_edge)
            if body_distance < target_distance * (1.0 - RELATIVE_TOLERANCE):
                return True
    return False


@numba.njit(cache=True)
def decided_pairs(
    objects, kept, record_edge, records, statics, ox, oy, pair_target, pair_body, pair_certain, order,
    static_offsets, static_records,
):  # fmt: skip
    """The unique candidate pairs, in ``order`` (by target, then body), that occlude: accepted at once or by the
    exact test.

    Every array the loop reads is bound once before it (a named tuple's field or a conditionally rebuilt array
    read inside the loop costs reference counting on every pass).

    Returns
    -------
    found_body : ndarray, shape (f,), int64
        The occluding body of each occluding pair, by target, then body.
    occ_offsets, st_offsets : ndarray, shape (n + 1,), int64
        ``occ_offsets[t + 1]`` and ``st_offsets[t + 1]``: how many objects and static bodies occlude ``t``.
    """
    seg, offsets, start, width = objects.seg, objects.offsets, objects.start, objects.width
    n = len(offsets) - 1
    n_pairs = len(order)
    bearing = np.empty(len(seg))  # vertex bearings, filled per object when first needed
    have_bearing = np.zeros(n, dtype=np.bool_)
    most = 0  # most vertices of a ring
    for i in range(n):
        most = max(most, offsets[i + 1] - offsets[i])
    target_cuts = np.empty(most + 2)
    n_target_cuts = -1
    cut_target = -1  # the target whose cuts target_cuts holds
    cuts = np.empty(2 * most + 2)
    scratch = np.empty((len(seg) + len(records) if len(static_records) else 0, 2, 2))
    occ_offsets = np.zeros(n + 1, dtype=np.int64)
    st_offsets = np.zeros(n + 1, dtype=np.int64)
    found_body = np.empty(n_pairs, dtype=np.int64)
    n_found = 0
    u = 0
    while u < n_pairs:
        t = pair_target[order[u]]
        j = pair_body[order[u]]
        certain = False
        while u < n_pairs and pair_target[order[u]] == t and pair_body[order[u]] == j:
            certain |= pair_certain[order[u]]
            u += 1
        if not certain:
            if j < n:
                if cut_target != t:
                    _vertex_bearings(seg, offsets, t, bearing, have_bearing)
                    n_target_cuts = _target_cuts(offsets, bearing, t, start[t], width[t], target_cuts)
                    cut_target = t
                _vertex_bearings(seg, offsets, j, bearing, have_bearing)
                hit = _occludes_object(
                    seg, offsets, bearing, j, t, start[t], width[t], target_cuts, n_target_cuts, cuts
                )
            else:
                hit = _occludes_static(
                    objects, t, kept, record_edge, records, static_records, static_offsets[j - n],
                    static_offsets[j - n + 1], statics, ox, oy, scratch,
                )  # fmt: skip
            if not hit:
                continue
        found_body[n_found] = j
        n_found += 1
        if j < n:
            occ_offsets[t + 1] += 1
        else:
            st_offsets[t + 1] += 1
    return found_body[:n_found], occ_offsets, st_offsets
