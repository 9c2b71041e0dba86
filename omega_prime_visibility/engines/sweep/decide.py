"""Step 4b of the sweep for one observer: the candidate (target, body) pairs of :mod:`.occluders` decided.

Pairs not accepted at once go to the exact pairwise test of :mod:`...occlusion` (``occludes_one``). For two objects
it is evaluated for all pairs at once (:func:`...object_pairs.objects_occluded`) with the same floating-point
operations on the same operands, but without the work that ``occludes_one`` repeats on every call. A static body is
tested on those of its kept edges that can matter (:func:`_occludes_static`).

Bodies are numbered objects first (``0..n-1``), then static sources (``n + source``).
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.candidates import CANDIDATE_EPS
from ...geometry.kernels import TWO_PI, copy_rows, wrap_positive
from ...geometry.object_pairs import objects_occluded, pieces_occlude
from ...geometry.sorting import insertion_sort
from .pieces import R_HI, R_LO


@njit(cache=True)
def _occludes_static(
    objects, target, kept, record_edge, records, static_records, first, stop, statics, ox, oy, scratch, cuts
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
        Work space for the segments handed to the exact test.
    cuts : ndarray, shape (>= 2 * (m_target + k) + 2,)
        Work space for its cuts (:func:`_scratch_occluded`).
    """
    t_start, t_width, t_far = objects.start[target], objects.width[target], objects.far[target]
    m = len(objects.seg)
    k = 0
    for e in range(objects.offsets[target], objects.offsets[target + 1]):
        copy_rows(scratch[k], 0, objects.seg[e])
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
    return _scratch_occluded(scratch, target_edges, k, t_start, t_width, cuts)


@njit(cache=True)
def _scratch_occluded(seg, target_edges, stop, extent_start, extent_width, cuts):
    """``occludes_one(0.0, 0.0, seg, target_edges, stop, 0, target_edges, extent_start, extent_width)``: the body's
    edges ``seg[target_edges:stop]`` against the target's ``seg[:target_edges]``, observer at the origin, with the
    same floating-point operations on the same operands, in the work space ``cuts`` (shape >= 2 * stop + 2)
    instead of new arrays, the cuts sorted by insertion (the order ``np.sort`` gives: all are >= +0.0 or equal
    to it)."""
    cuts[0] = 0.0
    cuts[1] = extent_width
    k = 2
    for lo, hi in ((target_edges, stop), (0, target_edges)):
        for j in range(lo, hi):
            for e in range(2):
                rel = wrap_positive(np.arctan2(seg[j, e, 1] - 0.0, seg[j, e, 0] - 0.0) - extent_start)
                if rel < extent_width:
                    cuts[k] = rel
                    k += 1
    insertion_sort(cuts, k)
    return pieces_occlude(seg, 0, target_edges, target_edges, stop, extent_start, extent_width, cuts, k, 0.0, 0.0)


@njit(cache=True)
def decided_pairs(
    objects, kept, record_edge, records, statics, ox, oy, pair_target, pair_body, pair_certain, order,
    static_offsets, static_records,
):  # fmt: skip
    """The unique candidate pairs, in ``order`` (by target, then body), that occlude: accepted at once or by the
    exact test.

    Parameters
    ----------
    objects : .occluders.ObjectsSeen
    kept, record_edge, records
        The kept edges and their records (:func:`.pieces.front_facing_edges`).
    statics : .pieces.StaticEdges
        Unshifted; the observer is at ``(ox, oy)``, metres.
    pair_target, pair_body : ndarray, shape (p,), int64
    pair_certain : ndarray of bool, shape (p,)
        The candidate pairs and whether each is accepted at once (:func:`.occluders._candidate_pairs`).
    order : ndarray, shape (p,), int64
        The pairs sorted by target, then body.
    static_offsets, static_records : ndarray, int64
        The records of each static body (:func:`.occluders._records_by_static_body`); read only when a static pair
        needs the exact test.

    Returns
    -------
    found_body : ndarray, shape (f,), int64
        The occluding body of each occluding pair, by target, then body.
    occ_offsets, st_offsets : ndarray, shape (n + 1,), int64
        ``occ_offsets[t + 1]`` and ``st_offsets[t + 1]``: how many objects and static bodies occlude ``t``.
    """
    n = len(objects.offsets) - 1
    n_pairs = len(order)
    # the unique pairs; those not accepted at once are marked -1 (object pairs) or -2 (static) for the exact test
    unique_target = np.empty(n_pairs, dtype=np.int64)
    unique_body = np.empty(n_pairs, dtype=np.int64)
    state = np.empty(n_pairs, dtype=np.int8)  # 1: occludes, 0: does not, -1 / -2: to be tested
    n_unique = 0
    n_object_tests = 0
    u = 0
    while u < n_pairs:
        t = pair_target[order[u]]
        j = pair_body[order[u]]
        certain = False
        while u < n_pairs and pair_target[order[u]] == t and pair_body[order[u]] == j:
            certain |= pair_certain[order[u]]
            u += 1
        unique_target[n_unique], unique_body[n_unique] = t, j
        state[n_unique] = 1 if certain else (-1 if j < n else -2)
        n_object_tests += state[n_unique] == -1
        n_unique += 1
    tested = np.empty(n_object_tests, dtype=np.int64)
    k = 0
    for r in range(n_unique):
        if state[r] == -1:
            tested[k] = r
            k += 1
    hit = objects_occluded(
        objects.seg, objects.offsets, objects.start, objects.width, unique_target[tested], unique_body[tested], 0.0, 0.0
    )
    for k in range(n_object_tests):
        state[tested[k]] = hit[k]
    scratch = np.empty((len(objects.seg) + len(records) if len(static_records) else 0, 2, 2))
    cuts = np.empty(2 * len(scratch) + 2)
    for r in range(n_unique):
        if state[r] == -2:
            j = unique_body[r]
            state[r] = _occludes_static(
                objects, unique_target[r], kept, record_edge, records, static_records, static_offsets[j - n],
                static_offsets[j - n + 1], statics, ox, oy, scratch, cuts,
            )  # fmt: skip
    occ_offsets = np.zeros(n + 1, dtype=np.int64)
    st_offsets = np.zeros(n + 1, dtype=np.int64)
    found_body = np.empty(n_unique, dtype=np.int64)
    n_found = 0
    for r in range(n_unique):
        if state[r] == 1:
            j = unique_body[r]
            found_body[n_found] = j
            n_found += 1
            if j < n:
                occ_offsets[unique_target[r] + 1] += 1
            else:
                st_offsets[unique_target[r] + 1] += 1
    return found_body[:n_found], occ_offsets, st_offsets
