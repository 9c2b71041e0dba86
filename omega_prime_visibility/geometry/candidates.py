"""Which bodies may hide which targets, from one viewpoint: the edges of the blocking bodies grouped by bearing,
and the (body, target) pairs whose bearings meet and whose distances allow it (each pair once), with the pairs
certain to occlude. The exact decision per pair is :mod:`.occlusion`'s.

Public, for the engines: :func:`candidate_pairs`, :func:`bearing_bins`, :func:`bin_range`.
"""

from __future__ import annotations

import numba
import numpy as np

from .kernels import TWO_PI, argsort_stable, nearest_offset, prefix_sum, reserve, wrap_positive

MIN_PIECE = 1e-12
"""Radians: thinner pieces of a bearing interval are ignored (here and in :mod:`.occlusion`)."""

BEARING_BINS = 256
"""Bins over the full turn that edges are grouped into by bearing, so a target meets only the edges of its own
bearings (:func:`candidate_pairs`; in town a target's extent holds a few per cent of the edges)."""


@numba.njit(cache=True, inline="always")
def bin_range(lo, width, n_bins):
    """The bins (unwrapped, ``first <= last``) covering the bearings ``[lo, lo + width]`` with one bin to spare on
    each side; all of them once the interval is within two bins of a full turn."""
    size = TWO_PI / n_bins
    first = int(np.floor(wrap_positive(lo) / size)) - 1
    last = first + 2 + int(np.floor(max(width, 0.0) / size)) + 1
    if last - first + 1 >= n_bins:
        return 0, n_bins - 1
    return first, last


@numba.njit(cache=True)
def bearing_bins(e_start, e_width, seg_body, blocking):
    """The edges of blocking bodies grouped by the bins their bearings cover (:func:`_bin_range`): CSR offsets
    over :data:`BEARING_BINS` bins and the edges, ascending within a bin."""
    n_bins = BEARING_BINS
    offsets = np.zeros(n_bins + 1, dtype=np.int64)
    for j in range(len(e_start)):
        if blocking[seg_body[j]]:
            first, last = bin_range(e_start[j], e_width[j], n_bins)
            for q in range(first, last + 1):
                offsets[q % n_bins + 1] += 1
    prefix_sum(offsets)
    fill = offsets[:-1].copy()
    members = np.empty(offsets[-1], dtype=np.int64)
    for j in range(len(e_start)):
        if blocking[seg_body[j]]:
            first, last = bin_range(e_start[j], e_width[j], n_bins)
            for q in range(first, last + 1):
                c = q % n_bins
                members[fill[c]] = j
                fill[c] += 1
    return offsets, members


@numba.njit(cache=True)
def candidate_pairs(ox, oy, seg, seg_body, blocking, targets, start, width, n_objects):
    """Pairs (body, target) where some edge of a blocking body overlaps the target's extent and comes nearer
    than the target's farthest point, each pair once; and whether the pair is certainly occluding (an object
    entirely nearer than the target's nearest point, with overlapping extents)."""
    n_bodies = len(blocking)
    m = len(seg)
    e_start = np.empty(m)
    e_width = np.empty(m)
    e_near = np.empty(m)
    near = np.full(n_bodies, np.inf)
    far = np.zeros(n_bodies)
    for j in range(m):
        ax, ay = seg[j, 0, 0] - ox, seg[j, 0, 1] - oy
        bx, by = seg[j, 1, 0] - ox, seg[j, 1, 1] - oy
        span = np.arctan2(ax * by - ay * bx, ax * bx + ay * by)
        ta = np.arctan2(ay, ax)
        e_start[j] = ta if span >= 0 else ta + span
        e_width[j] = abs(span)
        dx, dy = nearest_offset(-ax, -ay, bx - ax, by - ay)
        e_near[j] = np.hypot(dx, dy)
        b = seg_body[j]
        near[b] = min(near[b], e_near[j])
        far[b] = max(far[b], np.hypot(ax, ay), np.hypot(bx, by))
    cap = 8 * len(targets) + 16
    out_body = np.empty(cap, dtype=np.int64)
    out_target = np.empty(cap, dtype=np.int64)
    out_certain = np.empty(cap, dtype=np.bool_)
    hidden = np.zeros(n_bodies, dtype=np.bool_)
    k = 0
    seen = np.full(n_bodies, -1, dtype=np.int64)
    bin_offsets, bin_segments = bearing_bins(e_start, e_width, seg_body, blocking)
    n_bins = len(bin_offsets) - 1
    stamp = np.full(m, -1, dtype=np.int64)
    gathered = np.empty(m, dtype=np.int64)
    for r in range(len(targets)):
        t = targets[r]
        # the blocking edges whose bearings may meet the target's extent (its bins, one to spare on each side), in
        # ascending order: the pairs come out exactly as from a loop over every edge
        first, last = bin_range(start[t], width[t], n_bins)
        n = 0
        for q in range(first, last + 1):
            c = q % n_bins
            for i in range(bin_offsets[c], bin_offsets[c + 1]):
                j = bin_segments[i]
                if stamp[j] != r:
                    stamp[j] = r
                    gathered[n] = j
                    n += 1
        candidates = gathered[:n][argsort_stable(gathered[:n])]
        for j in candidates:
            b = seg_body[j]
            if b == t or not blocking[b] or seen[b] == t or e_near[j] >= far[t]:
                continue
            rel = wrap_positive(e_start[j] - start[t])
            if rel < width[t] or rel + e_width[j] > TWO_PI:
                seen[b] = t
                out_body = reserve(out_body, k, k + 1)
                out_target = reserve(out_target, k, k + 1)
                out_certain = reserve(out_certain, k, k + 1)
                out_body[k] = b
                out_target[k] = t
                certain = False
                if b < n_objects and far[b] < near[t]:
                    # the body's whole extent is nearer; it occludes iff the two extents overlap
                    rel2 = wrap_positive(start[b] - start[t])
                    certain = rel2 < width[t] - MIN_PIECE or rel2 + width[b] > TWO_PI + MIN_PIECE
                    # the target's whole extent inside the body's: the target is hidden behind it
                    rel3 = wrap_positive(start[t] - start[b])
                    if rel3 + width[t] <= width[b]:
                        hidden[t] = True
                out_certain[k] = certain
                k += 1
    return out_body[:k], out_target[:k], out_certain[:k], hidden
