"""Step 4 of the sweep for one observer: which bodies occlude each target.

A body ``J`` can only occlude target ``T`` when their bearing intervals overlap and ``J`` comes nearer than ``T``'s
farthest point. Candidates are enumerated by sweeping the targets' extents (sorted by start) over the bodies'
intervals (objects: their angular extent; statics: the records of their kept edges), sorted by start, and grouped
by (target, body) with a counting sort. An object lying entirely nearer than ``T``'s nearest point with an extent
overlapping ``T``'s by more than ``MIN_PIECE`` is accepted at once, so is a static edge with a safety margin (the
rule both engines use, :func:`...geometry.candidates.certainly_occludes`); all other candidates are decided
(:mod:`.decide`) by the exact pairwise test of :mod:`...occlusion` (``occludes_one``) on the same shifted segments.
For a static body only its kept edges that meet ``T``'s extent nearer than ``T``'s farthest point are handed to
that test: a ray from outside enters a body through a front-facing edge, so the others cannot decide anything, and
a long guard rail would otherwise cost the test O(pieces x all its edges).

Bodies are numbered objects first (``0..n-1``), then static sources (``n + source``).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.candidates import CANDIDATE_EPS, certainly_occludes
from ...geometry.kernels import TWO_PI, counting_sort, group_by_key, prefix_sum, reserve
from ...geometry.sorting import argsort_floats
from .decide import decided_pairs
from .pieces import R_HI, R_LO

PI = math.pi

#: The objects as one observer sees them: ``seg`` (m, 2, 2) their edges relative to the observer (metres),
#: ``offsets`` (n + 1,) object ``i``'s edges are ``seg[offsets[i]:offsets[i + 1]]``, ``transparent`` (n,) bool,
#: ``passive`` (n,) bool (targets that occlude nothing, see :mod:`.passive`), ``start`` and ``width`` (n,) their
#: angular extents (radians), ``near`` and ``far`` (n,) their nearest and farthest distance (metres).
ObjectsSeen = namedtuple("ObjectsSeen", "seg offsets transparent passive start width near far")


@njit(cache=True)
def _records_by_static_body(record_edge, kept_body, n, n_src):
    """Records of the kept static edges grouped by static source: offsets (n_src + 1,) and record numbers."""
    n_rec = len(record_edge)
    source = np.empty(n_rec, dtype=np.int64)
    static_records = np.empty(n_rec, dtype=np.int64)
    k = 0
    for r in range(n_rec):
        source[r] = kept_body[record_edge[r]] - n
        if source[r] >= 0:
            static_records[k] = r
            k += 1
    return group_by_key(source, n_src, static_records[:k])


@njit(cache=True)
def _candidate_intervals(objects, kept, record_edge, records):
    """The bearing intervals of the bodies and of the targets, for the candidate sweep.

    Returns
    -------
    items : tuple of ndarray, each shape (k,)
        ``(lo, hi, body, near, far)`` sorted by ``lo``: extents of the objects that may occlude (split at the
        -pi/pi direction; not the passive ones) and the records of kept static edges, radians and metres.
    queries : tuple of ndarray, each shape (q,)
        ``(lo, hi, target)`` of the targets' extents (split likewise), in their order of ``lo``.
    """
    n = len(objects.offsets) - 1
    n_rec = len(records)
    n_items = 0
    for i in range(n):
        if not objects.transparent[i] and not objects.passive[i]:
            n_items += 2
    for r in range(n_rec):
        if kept.body[record_edge[r]] >= n:
            n_items += 1
    item_lo = np.empty(n_items)
    item_hi = np.empty(n_items)
    item_body = np.empty(n_items, dtype=np.int64)
    item_near = np.empty(n_items)
    item_far = np.empty(n_items)
    query_lo = np.empty(2 * n)
    query_hi = np.empty(2 * n)
    query_target = np.empty(2 * n, dtype=np.int64)
    k = 0
    n_queries = 0
    for i in range(n):
        if objects.transparent[i]:
            continue
        s = objects.start[i]
        e = s + objects.width[i]
        for part in range(2):
            if part == 0:
                lo, hi = s, min(e, PI)
            else:
                if e <= PI:
                    break
                lo, hi = -PI, e - TWO_PI
            if not objects.passive[i]:
                item_lo[k], item_hi[k], item_body[k] = lo, hi, i
                item_near[k], item_far[k] = objects.near[i], objects.far[i]
                k += 1
            query_lo[n_queries], query_hi[n_queries], query_target[n_queries] = lo, hi, i
            n_queries += 1
    n_object_items = k
    for r in range(n_rec):
        e = record_edge[r]
        if kept.body[e] >= n:
            item_lo[k], item_hi[k], item_body[k] = records[r, R_LO], records[r, R_HI], kept.body[e]
            item_near[k], item_far[k] = kept.distance[e, 0], kept.distance[e, 1]
            k += 1
    order = argsort_floats(item_lo[:k])
    items = (item_lo[order], item_hi[order], item_body[order], item_near[order], item_far[order])
    # without static edges the items are the queries less the passive ones: all of them when as many, in the same
    # order, and one sort serves both
    query_order = order if k == n_queries and k == n_object_items else argsort_floats(query_lo[:n_queries])
    queries = (query_lo[query_order], query_hi[query_order], query_target[query_order])
    return items, queries


@njit(cache=True)
def _candidate_pairs(items, queries, objects):
    """Candidate (target, body) pairs, in bearing order of the targets, and whether each is accepted at once.

    Returns
    -------
    pair_target, pair_body : ndarray, shape (p,), int64
    pair_certain : ndarray of bool, shape (p,)
        Certainly occluding (:func:`...geometry.candidates.certainly_occludes`); the rest go to the exact test.
    """
    n_items = len(items[0])
    capacity = 4 * n_items + 16
    pair_target = np.empty(capacity, dtype=np.int64)
    pair_body = np.empty(capacity, dtype=np.int64)
    pair_certain = np.empty(capacity, dtype=np.bool_)
    active = np.empty(n_items, dtype=np.int64)
    state = np.zeros(4, dtype=np.int64)  # next target, next item, active items, pairs
    # the buffers grow between calls, not inside the loop over targets: an array rebound in a loop costs
    # reference counting on every pass
    while not _pairs_into(items, queries, objects.near, objects.far, len(objects.offsets) - 1, active, state,
                          pair_target, pair_body, pair_certain):  # fmt: skip
        n_pairs = state[3]
        pair_target = reserve(pair_target, n_pairs, n_pairs + n_items)
        pair_body = reserve(pair_body, n_pairs, n_pairs + n_items)
        pair_certain = reserve(pair_certain, n_pairs, n_pairs + n_items)
    n_pairs = state[3]
    return pair_target[:n_pairs], pair_body[:n_pairs], pair_certain[:n_pairs]


@njit(cache=True)
def _pairs_into(items, queries, near, far, n, active, state, pair_target, pair_body, pair_certain):
    """The sweep of :func:`_candidate_pairs` from where ``state`` says, writing pairs to the buffers; stops (and
    returns False, ``state`` updated) before a target whose pairs might not fit, returns True when done.

    ``active`` holds the items that started before the current target (the first ``state[2]``), ``near, far``
    (n,) the objects' distances (metres).
    """
    item_lo, item_hi, item_body, item_near, item_far = items
    query_lo, query_hi, query_target = queries
    n_items = len(item_lo)
    q, p, n_active, n_pairs = state[0], state[1], state[2], state[3]
    while q < len(query_lo):
        if n_pairs + n_items > len(pair_target):
            state[0], state[1], state[2], state[3] = q, p, n_active, n_pairs
            return False
        t = query_target[q]
        lo, hi = query_lo[q], query_hi[q]
        while p < n_items and item_lo[p] < lo:
            active[n_active] = p
            n_active += 1
            p += 1
        far_t = far[t]
        near_t = near[t]
        keep = 0
        for a in range(n_active):
            it = active[a]
            if item_hi[it] <= lo - CANDIDATE_EPS:
                continue  # ended before this target (and before all later ones)
            active[keep] = it
            keep += 1
            j = item_body[it]
            if j != t and item_near[it] < far_t:
                pair_target[n_pairs] = t
                pair_body[n_pairs] = j
                overlap = min(hi, item_hi[it]) - lo
                pair_certain[n_pairs] = certainly_occludes(overlap, item_far[it], j < n, near_t)
                n_pairs += 1
        n_active = keep
        it = p
        while it < n_items and item_lo[it] < hi + CANDIDATE_EPS:
            j = item_body[it]
            if j != t and item_near[it] < far_t:
                pair_target[n_pairs] = t
                pair_body[n_pairs] = j
                overlap = min(hi, item_hi[it]) - item_lo[it]
                pair_certain[n_pairs] = certainly_occludes(overlap, item_far[it], j < n, near_t)
                n_pairs += 1
            it += 1
        q += 1
    state[0], state[1], state[2], state[3] = q, p, n_active, n_pairs
    return True


@njit(cache=True)
def occluders(objects, n_src, kept, record_edge, records, statics, ox, oy):
    """Occluders of every object seen from ``(ox, oy)`` (metres), grouped by target.

    Parameters
    ----------
    objects : ObjectsSeen
    n_src : int
        Number of static sources.
    kept, record_edge, records
        The kept edges and their records (:func:`.pieces.front_facing_edges`).
    statics : StaticEdges

    Returns
    -------
    occ_offsets : ndarray, shape (n + 1,), int64
    occ : ndarray, shape (k,), int64
        Object ``t``'s occluding objects are ``occ[occ_offsets[t]:occ_offsets[t + 1]]``, ascending.
    st_offsets, st : ndarray
        Likewise for the occluding static sources.
    """
    n = len(objects.offsets) - 1
    items, queries = _candidate_intervals(objects, kept, record_edge, records)
    pair_target, pair_body, pair_certain = _candidate_pairs(items, queries, objects)
    n_pairs = len(pair_target)

    # sort the pairs by (target, body): counting sort by body, then (stably) by target
    by_body = counting_sort(pair_body, n + n_src, np.arange(n_pairs))
    order = counting_sort(pair_target, n, by_body)

    # unique pairs, decided; the static bodies' records only when some static pair needs the exact test
    needs_static = False
    for p in range(n_pairs):
        needs_static |= pair_body[p] >= n and not pair_certain[p]
    if needs_static:
        static_offsets, static_records = _records_by_static_body(record_edge, kept.body, n, n_src)
    else:
        static_offsets, static_records = np.zeros(n_src + 1, dtype=np.int64), np.zeros(0, dtype=np.int64)
    found_body, occ_offsets, st_offsets = decided_pairs(
        objects, kept, record_edge, records, statics, ox, oy, pair_target, pair_body, pair_certain, order,
        static_offsets, static_records,
    )  # fmt: skip
    n_found = len(found_body)
    prefix_sum(occ_offsets)
    prefix_sum(st_offsets)
    occ = np.empty(occ_offsets[n], dtype=np.int64)
    st = np.empty(st_offsets[n], dtype=np.int64)
    n_occ = 0
    n_st = 0
    for r in range(n_found):  # sorted by target, then body: objects before statics
        if found_body[r] < n:
            occ[n_occ] = found_body[r]
            n_occ += 1
        else:
            st[n_st] = found_body[r] - n
            n_st += 1
    return occ_offsets, occ, st_offsets, st
