"""An exact angular-sweep engine in numba: visible angles in O(N log N) per observer, no polygon clipping.

Per frame (shared by all observers of the frame), on the unshifted coordinates:

- the pairs of edges of *different* bodies that cross properly (objects against objects by sort-and-sweep of
  their bounding boxes along the axis of larger spread, objects against static edges through a uniform grid
  built once per recording; static against static crossings are found once, in the constructor).

Per observer, with everything shifted so that the observer sits at the origin:

1. *Front-facing edges*: an edge of a ring (material on its left) is kept when the observer lies strictly on
   its right; a two-sided wall segment is kept in the orientation that faces the observer. Edges collinear
   with the observer subtend no angle and are dropped, so are the edges of transparent bodies and static edges
   farther away than the farthest target (they cannot be in front of anything that is reported). A kept edge
   runs counter-clockwise from ``p`` to ``q`` and subtends less than pi.
2. *Pieces*: each kept edge's bearing interval is cut at the -pi/pi direction (an edge straddling it becomes
   two records) and at the bearings where it crosses an edge of another body. Within a piece no other piece
   starts crossing it, so any two pieces that share directions keep their depth order over all of them.
3. *Sweep*: start and end events sorted by bearing; the active pieces live in an indexed binary heap (true
   deletion, so only pieces active together are ever compared). Two pieces are compared along the bisector
   of the directions they share, where neither touches the other, which makes the comparison independent of
   the sweep position. Between two consecutive event bearings the heap's top is the nearest piece; the
   interval's angle is credited to its body.
4. *Occluders*: a body ``J`` can only occlude target ``T`` when their bearing intervals overlap and ``J``
   comes nearer than ``T``'s farthest point. Candidates are enumerated by sweeping the targets' extents (sorted
   by start) over the bodies' intervals (objects: their angular extent; statics: their kept edges), sorted by
   start, and grouped by (target, body) with a counting sort. An object lying entirely nearer than ``T``'s
   nearest point with an extent overlapping ``T``'s by more than ``MIN_PIECE`` is accepted at once (the rule of
   the VisiLibity engine), so is a static edge with a safety margin; all other candidates are decided by the
   exact pairwise test of :mod:`..occlusion` (``occludes_one``) on the same shifted segments. For a static body
   only its kept edges that meet ``T``'s extent nearer than ``T``'s farthest point are handed to that test: a
   ray from outside enters a body through a front-facing edge, so the others cannot decide anything, and a long
   guard rail would otherwise cost the test O(pieces x all its edges).

Angular extents are computed exactly as :func:`..geometry.angular_extent` does (same operations; the arctangents
go through numpy, whose SIMD ``arctan2`` differs from libm's in the last bit).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numba
import numpy as np

from ..geometry import edges, ring_ids
from ..occlusion import MIN_PIECE, occludes_one
from ..scene import FrameObjects, StaticOccluders
from . import Observation, Viewpoint
from .crossings import build_static_grid, prepare_frame, segment_distance2, static_crossings

PI = math.pi
TWO_PI = 2.0 * math.pi
STATIC_ACCEPT_ANGLE = 1e-9  # radians of overlap needed to accept a static edge without the exact test
STATIC_ACCEPT_RELATIVE = 1e-7  # ... and it must lie nearer than (1 - this) times the target's nearest distance
CANDIDATE_EPS = 1e-9  # radians; intervals this close count as overlapping (the exact test decides)


# columns of the piece table
_LO, _HI, _ULX, _ULY, _UHX, _UHY, _EX, _EY, _NUM = range(9)


@numba.njit(cache=True)
def _less(P, a, b):
    """Whether piece a is nearer than piece b along the bisector of the directions both cover."""
    if P[a, _LO] >= P[b, _LO]:
        x1, y1 = P[a, _ULX], P[a, _ULY]
    else:
        x1, y1 = P[b, _ULX], P[b, _ULY]
    if P[a, _HI] <= P[b, _HI]:
        x2, y2 = P[a, _UHX], P[a, _UHY]
    else:
        x2, y2 = P[b, _UHX], P[b, _UHY]
    dx, dy = x1 + x2, y1 + y2
    ta = P[a, _NUM] / (dx * P[a, _EY] - dy * P[a, _EX])
    tb = P[b, _NUM] / (dx * P[b, _EY] - dy * P[b, _EX])
    if ta < tb:
        return True
    if ta > tb:
        return False
    return a < b


@numba.njit(cache=True)
def _sift_up(P, heap, pos, i):
    x = heap[i]
    while i > 0:
        parent = (i - 1) >> 1
        y = heap[parent]
        if not _less(P, x, y):
            break
        heap[i] = y
        pos[y] = i
        i = parent
    heap[i] = x
    pos[x] = i


@numba.njit(cache=True)
def _sift_down(P, heap, pos, i, size):
    x = heap[i]
    while True:
        c = 2 * i + 1
        if c >= size:
            break
        if c + 1 < size and _less(P, heap[c + 1], heap[c]):
            c += 1
        if not _less(P, heap[c], x):
            break
        heap[i] = heap[c]
        pos[heap[i]] = i
        i = c
    heap[i] = x
    pos[x] = i


@numba.njit(cache=True)
def _sweep(P, body, n_bodies):
    """Angle (radians) along which each body's pieces are the nearest thing hit."""
    k = len(P)
    visible = np.zeros(n_bodies)
    if k == 0:
        return visible
    by_lo = np.argsort(P[:, _LO].copy())
    by_hi = np.argsort(P[:, _HI].copy())
    heap = np.empty(k, dtype=np.int64)
    pos = np.full(k, -1, dtype=np.int64)
    size = 0
    i = 0
    j = 0
    while j < k:
        theta = P[by_hi[j], _HI]
        if i < k and P[by_lo[i], _LO] < theta:
            theta = P[by_lo[i], _LO]
        while j < k and P[by_hi[j], _HI] == theta:
            r = by_hi[j]
            h = pos[r]
            size -= 1
            if h < size:
                last = heap[size]
                heap[h] = last
                pos[last] = h
                if h > 0 and _less(P, last, heap[(h - 1) >> 1]):
                    _sift_up(P, heap, pos, h)
                else:
                    _sift_down(P, heap, pos, h, size)
            pos[r] = -1
            j += 1
        while i < k and P[by_lo[i], _LO] == theta:
            r = by_lo[i]
            heap[size] = r
            size += 1
            _sift_up(P, heap, pos, size - 1)
            i += 1
        if size > 0:
            nxt = P[by_hi[j], _HI]  # j < k: active pieces still have to end
            if i < k and P[by_lo[i], _LO] < nxt:
                nxt = P[by_lo[i], _LO]
            visible[body[heap[0]]] += nxt - theta
    return visible


# -- one observer ------------------------------------------------------------------------------------------


@numba.njit(cache=True)
def _extents(seg, offsets, ang, m):
    """``geometry.angular_extent`` of the shifted object rings, with the same floating-point operations."""
    n = len(offsets) - 1
    start = np.empty(n)
    width = np.empty(n)
    winding = np.empty(n, dtype=np.int64)
    cum = 0.0
    for i in range(n):
        s, e = offsets[i], offsets[i + 1]
        base = cum
        lo = np.inf
        hi = -np.inf
        rel = 0.0
        for j in range(s, e):
            cum += ang[j]
            rel = cum - base
            lo = min(lo, rel)
            hi = max(hi, rel)
        lo = min(lo, 0.0)
        hi = max(hi, 0.0)
        winding[i] = np.int64(np.rint(rel / TWO_PI))
        start[i] = (ang[m + s] + lo + PI) % TWO_PI - PI
        width[i] = hi - lo
    return start, width, winding


@numba.njit(cache=True)
def _observe_one(ox, oy, coords, offsets, nxt, ang, obj_tr, st_a, st_b, st_src, st_two, st_tr, ci, cj):
    n = len(offsets) - 1
    m = len(coords)
    n_st = len(st_a)
    n_src = len(st_tr)
    nb = n + n_src

    # shifted object edges
    seg = np.empty((m, 2, 2))
    for j in range(m):
        seg[j, 0, 0] = coords[j, 0] - ox
        seg[j, 0, 1] = coords[j, 1] - oy
        seg[j, 1, 0] = coords[nxt[j], 0] - ox
        seg[j, 1, 1] = coords[nxt[j], 1] - oy
    start, width, _ = _extents(seg, offsets, ang, m)

    dmin = np.empty(n)
    dmax = np.empty(n)
    reach2 = 0.0  # squared distance of the farthest target point
    for i in range(n):
        lo2 = np.inf
        hi2 = 0.0
        for j in range(offsets[i], offsets[i + 1]):
            ax, ay = seg[j, 0, 0], seg[j, 0, 1]
            lo2 = min(lo2, segment_distance2(ax, ay, seg[j, 1, 0], seg[j, 1, 1]))
            hi2 = max(hi2, ax * ax + ay * ay)
        dmin[i] = math.sqrt(lo2)
        dmax[i] = math.sqrt(hi2)
        if not obj_tr[i]:
            reach2 = max(reach2, hi2)
    reach2 *= 1.0 + 1e-9

    # 1. front-facing edges, oriented counter-clockwise (p -> q), with their bearing records
    g_total = m + n_st
    kid = np.full(g_total, -1, dtype=np.int64)
    kp = np.empty((g_total, 2))
    kq = np.empty((g_total, 2))
    kbody = np.empty(g_total, dtype=np.int64)
    kg = np.empty(g_total, dtype=np.int64)  # the kept edge's number among all edges
    kd = np.empty((g_total, 2))  # nearest and farthest distance of the edge
    rec_edge = np.empty(2 * g_total, dtype=np.int64)
    rec = np.empty((2 * g_total, 6))  # lo, hi, ulx, uly, uhx, uhy
    n_kept = 0
    n_rec = 0
    ring_of = np.empty(m, dtype=np.int64)
    for i in range(n):
        ring_of[offsets[i] : offsets[i + 1]] = i
    for g in range(g_total):
        if g < m:
            bdy = ring_of[g]
            if obj_tr[bdy]:
                continue
            ax, ay, bx, by = seg[g, 0, 0], seg[g, 0, 1], seg[g, 1, 0], seg[g, 1, 1]
            two = False
        else:
            s = g - m
            src = st_src[s]
            if st_tr[src]:
                continue
            ax, ay = st_a[s, 0] - ox, st_a[s, 1] - oy
            bx, by = st_b[s, 0] - ox, st_b[s, 1] - oy
            if segment_distance2(ax, ay, bx, by) > reach2:
                continue
            two = st_two[s]
            bdy = n + src
        c = ax * by - ay * bx
        if c < 0.0:
            px, py, qx, qy = bx, by, ax, ay
            flipped = True
        elif c > 0.0 and two:
            px, py, qx, qy = ax, ay, bx, by
            flipped = False
        else:
            continue
        if g < m:  # vertex bearings from numpy's arctan2 (the same values as the extents use)
            lo = ang[m + nxt[g]] if flipped else ang[m + g]
            hi = ang[m + g] if flipped else ang[m + nxt[g]]
        else:
            lo = math.atan2(py, px)
            hi = math.atan2(qy, qx)
        if py == 0.0 and px < 0.0:
            lo = -PI
        if qy == 0.0 and qx < 0.0:
            hi = PI
        kid[g] = n_kept
        kg[n_kept] = g
        kp[n_kept, 0], kp[n_kept, 1] = px, py
        kq[n_kept, 0], kq[n_kept, 1] = qx, qy
        kbody[n_kept] = bdy
        kd[n_kept, 0] = math.sqrt(segment_distance2(ax, ay, bx, by))
        kd[n_kept, 1] = math.sqrt(max(ax * ax + ay * ay, bx * bx + by * by))
        rp = math.sqrt(px * px + py * py)
        rq = math.sqrt(qx * qx + qy * qy)
        if py > 0.0 and qy < 0.0:  # straddles the -pi/pi direction
            rec_edge[n_rec] = n_kept
            rec[n_rec, 0], rec[n_rec, 1] = lo, PI
            rec[n_rec, 2], rec[n_rec, 3], rec[n_rec, 4], rec[n_rec, 5] = px / rp, py / rp, -1.0, 0.0
            n_rec += 1
            rec_edge[n_rec] = n_kept
            rec[n_rec, 0], rec[n_rec, 1] = -PI, hi
            rec[n_rec, 2], rec[n_rec, 3], rec[n_rec, 4], rec[n_rec, 5] = -1.0, 0.0, qx / rq, qy / rq
            n_rec += 1
        elif lo < hi:
            rec_edge[n_rec] = n_kept
            rec[n_rec, 0], rec[n_rec, 1] = lo, hi
            rec[n_rec, 2], rec[n_rec, 3], rec[n_rec, 4], rec[n_rec, 5] = px / rp, py / rp, qx / rq, qy / rq
            n_rec += 1
        n_kept += 1

    first_rec = np.full(n_kept + 1, 0, dtype=np.int64)
    for r in range(n_rec):
        first_rec[rec_edge[r] + 1] += 1
    for e in range(n_kept):
        first_rec[e + 1] += first_rec[e]

    # 2. cut records where edges of different bodies cross
    split_rec = np.empty(2 * len(ci), dtype=np.int64)
    split = np.empty((2 * len(ci), 3))  # bearing, ux, uy
    n_split = 0
    for c in range(len(ci)):
        e1 = kid[ci[c]]
        e2 = kid[cj[c]]
        if e1 < 0 or e2 < 0:
            continue
        p1x, p1y = kp[e1, 0], kp[e1, 1]
        d1x, d1y = kq[e1, 0] - p1x, kq[e1, 1] - p1y
        p2x, p2y = kp[e2, 0], kp[e2, 1]
        d2x, d2y = kq[e2, 0] - p2x, kq[e2, 1] - p2y
        den = d1x * d2y - d1y * d2x
        if den == 0.0:
            continue
        t = ((p2x - p1x) * d2y - (p2y - p1y) * d2x) / den
        xx, yy = p1x + t * d1x, p1y + t * d1y
        rr = math.sqrt(xx * xx + yy * yy)
        if rr == 0.0:
            continue
        phi = math.atan2(yy, xx)
        for e in (e1, e2):
            for r in range(first_rec[e], first_rec[e + 1]):
                if rec[r, 0] < phi < rec[r, 1]:
                    split_rec[n_split] = r
                    split[n_split, 0], split[n_split, 1], split[n_split, 2] = phi, xx / rr, yy / rr
                    n_split += 1
                    break
    split_off = np.zeros(n_rec + 1, dtype=np.int64)
    for s in range(n_split):
        split_off[split_rec[s] + 1] += 1
    for r in range(n_rec):
        split_off[r + 1] += split_off[r]
    fill = split_off[:-1].copy()
    split_sorted = np.empty((n_split, 3))
    for s in range(n_split):
        r = split_rec[s]
        split_sorted[fill[r]] = split[s]
        fill[r] += 1

    # pieces
    P = np.empty((n_rec + n_split, 9))
    body = np.empty(n_rec + n_split, dtype=np.int64)
    n_piece = 0
    for r in range(n_rec):
        e = rec_edge[r]
        s0, s1 = split_off[r], split_off[r + 1]
        # insertion sort of this record's cuts by bearing
        for a in range(s0 + 1, s1):
            row0, row1, row2 = split_sorted[a, 0], split_sorted[a, 1], split_sorted[a, 2]
            b = a - 1
            while b >= s0 and split_sorted[b, 0] > row0:
                split_sorted[b + 1] = split_sorted[b]
                b -= 1
            split_sorted[b + 1, 0], split_sorted[b + 1, 1], split_sorted[b + 1, 2] = row0, row1, row2
        px, py = kp[e, 0], kp[e, 1]
        ex, ey = kq[e, 0] - px, kq[e, 1] - py
        num = px * ey - py * ex
        lo, ulx, uly = rec[r, 0], rec[r, 2], rec[r, 3]
        for s in range(s0, s1 + 1):
            if s < s1:
                hi, uhx, uhy = split_sorted[s, 0], split_sorted[s, 1], split_sorted[s, 2]
            else:
                hi, uhx, uhy = rec[r, 1], rec[r, 4], rec[r, 5]
            if hi > lo:
                P[n_piece, _LO], P[n_piece, _HI] = lo, hi
                P[n_piece, _ULX], P[n_piece, _ULY], P[n_piece, _UHX], P[n_piece, _UHY] = ulx, uly, uhx, uhy
                P[n_piece, _EX], P[n_piece, _EY], P[n_piece, _NUM] = ex, ey, num
                body[n_piece] = kbody[e]
                n_piece += 1
                lo, ulx, uly = hi, uhx, uhy

    # 3. the sweep
    visible = _sweep(P[:n_piece], body, nb)[:n].copy()

    # 4. occluders
    occ_offsets, occ, st_offsets, st = _occluders(
        n, n_src, offsets, obj_tr, start, width, dmin, dmax, rec[:n_rec], rec_edge[:n_rec], kbody, kd, kg, seg, st_a,
        st_b, ox, oy,
    )  # fmt: skip
    return visible, width, occ_offsets, occ, st_offsets, st


@numba.njit(cache=True)
def _records_by_static_body(rec_edge, kbody, n, n_src):
    """Records of the kept static edges grouped by static source: offsets (n_src + 1,) and record numbers."""
    first = np.zeros(n_src + 1, dtype=np.int64)
    for r in range(len(rec_edge)):
        b = kbody[rec_edge[r]]
        if b >= n:
            first[b - n + 1] += 1
    for k in range(n_src):
        first[k + 1] += first[k]
    fill = first[:-1].copy()
    recs = np.empty(first[n_src], dtype=np.int64)
    for r in range(len(rec_edge)):
        b = kbody[rec_edge[r]]
        if b >= n:
            recs[fill[b - n]] = r
            fill[b - n] += 1
    return first, recs


@numba.njit(cache=True)
def _occludes_static(seg, t0, t1, t_start, t_width, t_far, rec, rec_edge, kd, kg, recs, st_a, st_b, ox, oy, m, sub):
    """The exact occlusion test of a static body against a target, on the body's edges that can matter.

    A ray from outside enters a body through a front-facing edge, so only the body's kept edges whose bearing
    interval meets the target's extent and that come nearer than the target's farthest point can be hit before
    it; the others are left out (long guard rails would otherwise cost the exact test O(pieces * all edges)).
    """
    k = 0
    for e in range(t0, t1):
        sub[k] = seg[e]
        k += 1
    mt = k
    previous = -1
    for r in recs:
        e = rec_edge[r]
        if e == previous or kd[e, 0] >= t_far:
            continue
        x = (rec[r, 0] - t_start) % TWO_PI
        if not (x <= t_width + CANDIDATE_EPS or x + (rec[r, 1] - rec[r, 0]) >= TWO_PI - CANDIDATE_EPS):
            continue
        previous = e
        s = kg[e] - m
        sub[k, 0, 0] = st_a[s, 0] - ox
        sub[k, 0, 1] = st_a[s, 1] - oy
        sub[k, 1, 0] = st_b[s, 0] - ox
        sub[k, 1, 1] = st_b[s, 1] - oy
        k += 1
    if k == mt:
        return False
    return occludes_one(0.0, 0.0, sub, mt, k, 0, mt, t_start, t_width)


@numba.njit(cache=True)
def _accept(overlap, far, is_object, near_t, static_near_t):
    """Whether an interval of a body, overlapping a target's extent by ``overlap`` radians and lying within
    ``far`` of the observer, certainly occludes the target (the rule the VisiLibity engine uses for objects)."""
    if is_object:
        return overlap > MIN_PIECE and far < near_t
    return overlap > STATIC_ACCEPT_ANGLE and far < static_near_t


@numba.njit(cache=True)
def _counting_sort(keys, n_keys, items):
    """``items`` (indices into ``keys``) stably reordered by ``keys[item]`` in ``range(n_keys)``."""
    count = np.zeros(n_keys + 1, dtype=np.int64)
    for r in items:
        count[keys[r] + 1] += 1
    for j in range(n_keys):
        count[j + 1] += count[j]
    out = np.empty(len(items), dtype=np.int64)
    for r in items:
        out[count[keys[r]]] = r
        count[keys[r]] += 1
    return out


@numba.njit(cache=True)
def _occluders(
    n, n_src, offsets, obj_tr, start, width, dmin, dmax, rec, rec_edge, kbody, kd, kg, seg, st_a, st_b, ox, oy,
):  # fmt: skip
    nb = n + n_src
    n_rec = len(rec)
    # items: objects' extents (split at the -pi/pi direction), static kept edges' records
    n_items = 0
    for i in range(n):
        if not obj_tr[i]:
            n_items += 2
    for r in range(n_rec):
        if kbody[rec_edge[r]] >= n:
            n_items += 1
    it_lo = np.empty(n_items)
    it_hi = np.empty(n_items)
    it_body = np.empty(n_items, dtype=np.int64)
    it_near = np.empty(n_items)
    it_far = np.empty(n_items)
    q_lo = np.empty(2 * n)
    q_hi = np.empty(2 * n)
    q_t = np.empty(2 * n, dtype=np.int64)
    k = 0
    nq = 0
    for i in range(n):
        if obj_tr[i]:
            continue
        s = start[i]
        e = s + width[i]
        for part in range(2):
            if part == 0:
                lo, hi = s, min(e, PI)
            else:
                if e <= PI:
                    break
                lo, hi = -PI, e - TWO_PI
            it_lo[k], it_hi[k], it_body[k], it_near[k], it_far[k] = lo, hi, i, dmin[i], dmax[i]
            k += 1
            q_lo[nq], q_hi[nq], q_t[nq] = lo, hi, i
            nq += 1
    for r in range(n_rec):
        e = rec_edge[r]
        if kbody[e] >= n:
            it_lo[k], it_hi[k], it_body[k] = rec[r, 0], rec[r, 1], kbody[e]
            it_near[k], it_far[k] = kd[e, 0], kd[e, 1]
            k += 1
    n_items = k
    order = np.argsort(it_lo[:n_items])
    s_lo, s_hi, s_body = it_lo[order], it_hi[order], it_body[order]
    s_near, s_far = it_near[order], it_far[order]
    q_order = np.argsort(q_lo[:nq])

    # candidate pairs (target, body, accepted), in bearing order of the targets
    cap = 4 * n_items + 16
    pt = np.empty(cap, dtype=np.int64)
    pb = np.empty(cap, dtype=np.int64)
    pf = np.empty(cap, dtype=np.bool_)
    n_pairs = 0
    active = np.empty(n_items, dtype=np.int64)  # items that started before the current target
    n_active = 0
    p = 0
    for qq in range(nq):
        q = q_order[qq]
        t = q_t[q]
        lo, hi = q_lo[q], q_hi[q]
        while p < n_items and s_lo[p] < lo:
            active[n_active] = p
            n_active += 1
            p += 1
        if n_pairs + n_items > cap:
            cap = max(2 * cap, n_pairs + n_items)
            pt2 = np.empty(cap, dtype=np.int64)
            pb2 = np.empty(cap, dtype=np.int64)
            pf2 = np.empty(cap, dtype=np.bool_)
            pt2[:n_pairs] = pt[:n_pairs]
            pb2[:n_pairs] = pb[:n_pairs]
            pf2[:n_pairs] = pf[:n_pairs]
            pt, pb, pf = pt2, pb2, pf2
        far_t = dmax[t]
        near_t = dmin[t]
        static_near_t = near_t * (1.0 - STATIC_ACCEPT_RELATIVE)
        keep = 0
        for a in range(n_active):
            it = active[a]
            if s_hi[it] <= lo - CANDIDATE_EPS:
                continue  # ended before this target (and before all later ones)
            active[keep] = it
            keep += 1
            j = s_body[it]
            if j != t and s_near[it] < far_t:
                pt[n_pairs] = t
                pb[n_pairs] = j
                pf[n_pairs] = _accept(min(hi, s_hi[it]) - lo, s_far[it], j < n, near_t, static_near_t)
                n_pairs += 1
        n_active = keep
        it = p
        while it < n_items and s_lo[it] < hi + CANDIDATE_EPS:
            j = s_body[it]
            if j != t and s_near[it] < far_t:
                pt[n_pairs] = t
                pb[n_pairs] = j
                pf[n_pairs] = _accept(min(hi, s_hi[it]) - s_lo[it], s_far[it], j < n, near_t, static_near_t)
                n_pairs += 1
            it += 1

    # sort the pairs by (target, body): counting sort by body, then (stably) by target
    by_body = _counting_sort(pb[:n_pairs], nb, np.arange(n_pairs))
    order = _counting_sort(pt[:n_pairs], n, by_body)

    # unique pairs, decided
    m = len(seg)
    static_first = np.zeros(0, dtype=np.int64)  # records of each static body, built when first needed
    static_recs = np.zeros(0, dtype=np.int64)
    sub = np.empty((0, 2, 2))
    occ_count = np.zeros(n + 1, dtype=np.int64)
    st_count = np.zeros(n + 1, dtype=np.int64)
    res_b = np.empty(n_pairs, dtype=np.int64)
    n_res = 0
    u = 0
    while u < n_pairs:
        t = pt[order[u]]
        j = pb[order[u]]
        flag = False
        while u < n_pairs and pt[order[u]] == t and pb[order[u]] == j:
            flag |= pf[order[u]]
            u += 1
        if not flag:
            if j < n:
                hit = occludes_one(
                    0.0, 0.0, seg, offsets[j], offsets[j + 1], offsets[t], offsets[t + 1], start[t], width[t]
                )
            else:
                if len(static_first) == 0:
                    static_first, static_recs = _records_by_static_body(rec_edge, kbody, n, n_src)
                    sub = np.empty((m + len(rec), 2, 2))
                hit = _occludes_static(
                    seg, offsets[t], offsets[t + 1], start[t], width[t], dmax[t], rec, rec_edge, kd, kg,
                    static_recs[static_first[j - n] : static_first[j - n + 1]], st_a, st_b, ox, oy, m, sub,
                )  # fmt: skip
            if not hit:
                continue
        res_b[n_res] = j
        n_res += 1
        if j < n:
            occ_count[t + 1] += 1
        else:
            st_count[t + 1] += 1
    for i in range(n):
        occ_count[i + 1] += occ_count[i]
        st_count[i + 1] += st_count[i]
    occ = np.empty(occ_count[n], dtype=np.int64)
    st = np.empty(st_count[n], dtype=np.int64)
    oi = 0
    si = 0
    for r in range(n_res):  # sorted by target, then body: objects before statics
        if res_b[r] < n:
            occ[oi] = res_b[r]
            oi += 1
        else:
            st[si] = res_b[r] - n
            si += 1
    return occ_count, occ, st_count, st


@numba.njit(cache=True)
def _observe_frame(observers, coords, offsets, nxt, ang, transparent, st_tr, st_a, st_b, st_src, st_two, ci, cj):
    k = len(observers)
    n = len(offsets) - 1
    visible = np.empty((k, n))
    width = np.empty((k, n))
    occ_offsets = np.empty((k, n + 1), dtype=np.int64)
    st_offsets = np.empty((k, n + 1), dtype=np.int64)
    occ_cut = np.zeros(k + 1, dtype=np.int64)
    st_cut = np.zeros(k + 1, dtype=np.int64)
    occ_parts = []
    st_parts = []
    for o in range(k):
        vis, wid, oo, occ, so, st = _observe_one(
            observers[o, 0], observers[o, 1], coords, offsets, nxt, ang[o], transparent[o], st_a, st_b, st_src,
            st_two, st_tr[o], ci, cj,
        )  # fmt: skip
        visible[o] = vis
        width[o] = wid
        occ_offsets[o] = oo
        st_offsets[o] = so
        occ_cut[o + 1] = occ_cut[o] + len(occ)
        st_cut[o + 1] = st_cut[o] + len(st)
        occ_parts.append(occ)
        st_parts.append(st)
    occ_all = np.empty(occ_cut[k], dtype=np.int64)
    st_all = np.empty(st_cut[k], dtype=np.int64)
    for o in range(k):
        occ_all[occ_cut[o] : occ_cut[o + 1]] = occ_parts[o]
        st_all[st_cut[o] : st_cut[o + 1]] = st_parts[o]
    return visible, width, occ_offsets, occ_all, occ_cut, st_offsets, st_all, st_cut


# -- the engine --------------------------------------------------------------------------------------------


class SweepEngine:
    """Exact 2D visibility by an angular sweep over front-facing edges (see module docstring)."""

    name = "sweep"
    measure = "radians"

    def __init__(self, statics: StaticOccluders) -> None:
        self.statics = statics
        n_src = statics.n_sources
        # static edges for the sweep: ring edges (one-sided) then wall segments (two-sided)
        ra, rb = edges(statics.rings)
        ring_src = statics.ring_source[ring_ids(statics.rings.offsets)].astype(np.int64)
        walls = np.asarray(statics.segments, dtype=np.float64).reshape(-1, 2, 2)
        self._st_a = np.ascontiguousarray(np.concatenate([ra, walls[:, 0]]), dtype=np.float64).reshape(-1, 2)
        self._st_b = np.ascontiguousarray(np.concatenate([rb, walls[:, 1]]), dtype=np.float64).reshape(-1, 2)
        self._st_src = np.concatenate([ring_src, statics.segment_source]).astype(np.int64)
        self._st_two = np.concatenate([np.zeros(len(ra), dtype=bool), np.ones(len(walls), dtype=bool)])
        # crossing groups: a static polygon's edges never cross each other, a wall's segments may
        group = np.concatenate([ring_src, n_src + np.arange(len(walls), dtype=np.int64)])
        if len(self._st_a):
            self._grid = build_static_grid(self._st_a, self._st_b)
            self._ss = static_crossings(self._st_a, self._st_b, group, *self._grid)
        else:
            self._grid = (np.zeros(3), np.ones(2, dtype=np.int64), np.zeros(2, dtype=np.int64), np.zeros(0, np.int64))
            self._ss = (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64))

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; the frame's edge crossings are found once for all of them."""
        if not viewpoints:
            return []
        return self._observe_arrays(
            objects,
            np.array([v.position for v in viewpoints], dtype=np.float64).reshape(-1, 2),
            np.array([v.transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1),
            np.array([v.static_transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1),
        )

    def _observe_arrays(
        self,
        objects: FrameObjects,
        observers: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> list[Observation]:
        observers = np.ascontiguousarray(observers, dtype=np.float64).reshape(-1, 2)
        coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
        offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
        grid_f, grid_i, cell_off, items = self._grid
        nxt, ci, cj, y, x = prepare_frame(
            observers, coords, offsets, self._st_a, self._st_b, grid_f, grid_i, cell_off, items, *self._ss
        )
        ang = np.arctan2(y, x)
        out = _observe_frame(
            observers,
            coords,
            offsets,
            nxt,
            ang,
            np.ascontiguousarray(transparent, dtype=bool).reshape(len(observers), -1),
            np.ascontiguousarray(static_transparent, dtype=bool).reshape(len(observers), -1),
            self._st_a,
            self._st_b,
            self._st_src,
            self._st_two,
            ci,
            cj,
        )
        visible, width, occ_off, occ, occ_cut, st_off, st, st_cut = out
        return [
            Observation.from_parts(
                visible[k],
                width[k],
                occ_off[k],
                occ[occ_cut[k] : occ_cut[k + 1]],
                st_off[k],
                st[st_cut[k] : st_cut[k + 1]],
                transparent[k],
            )
            for k in range(len(observers))
        ]
