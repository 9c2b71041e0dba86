"""Steps 1 and 2 of the sweep for one observer: front-facing edges, and their bearing intervals cut into pieces.

Everything is shifted so that the observer sits at the origin.

1. *Front-facing edges*: an edge of a ring (material on its left) is kept when the observer lies strictly on
   its right; a two-sided wall segment is kept in the orientation that faces the observer. Edges collinear
   with the observer subtend no angle and are dropped, so are the edges of transparent bodies and static edges
   farther away than the farthest target (they cannot be in front of anything that is reported). A kept edge
   runs counter-clockwise from its start ``p`` to its end ``q`` and subtends less than pi.
2. *Pieces*: each kept edge's bearing interval (a *record*) is cut at the -pi/pi direction (an edge straddling it
   becomes two records) and at the bearings where it crosses an edge of another body. Within a piece no other
   piece starts crossing it, so any two pieces that share directions keep their depth order over all of them.

Angular extents are computed exactly as :func:`...geometry.angular_extent` does (same operations; the
arctangents go through numpy, whose SIMD ``arctan2`` differs from libm's in the last bit).
"""

from __future__ import annotations

import math
from collections import namedtuple

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import TWO_PI, copy_into, group_by_key, prefix_sum, segment_distance2

PI = math.pi

#: One frame's object edges, shared by all its observers. ``coords`` (m, 2) metres and ``offsets`` (n + 1,) are
#: the ragged object rings; edge ``j`` runs from vertex ``j`` to vertex ``following[j]`` and belongs to ring
#: ``ring[j]``; ``cross_first[c]`` and ``cross_second[c]`` are the edge numbers (object edges ``0..m-1``, then
#: static edges ``m + k``) of the pairs of edges of different bodies that cross properly.
FrameEdges = namedtuple("FrameEdges", "coords offsets following ring cross_first cross_second")

#: The recording's static edges, unshifted: ``start`` and ``end`` (s, 2) metres, ``source`` (s,) the static
#: occluder each belongs to, ``two_sided`` (s,) bool: wall segments (else ring edges, material on their left).
StaticEdges = namedtuple("StaticEdges", "start end source two_sided")

#: The kept (front-facing) edges, counter-clockwise as seen by the observer, numbered ``0..k-1``:
#: ``of_edge`` (m + s,) the kept number of every edge of the frame (-1 if dropped); ``start`` and ``end`` (k, 2)
#: the shifted end points ``p`` and ``q`` (metres); ``body`` (k,) the body (objects ``0..n-1``, then static source
#: ``n + source``); ``edge`` (k,) the edge's number among all edges; ``distance`` (k, 2) its nearest and farthest
#: distance from the observer (metres).
KeptEdges = namedtuple("KeptEdges", "of_edge start end body edge distance")

# columns of a record (a kept edge's bearing interval, or half of one straddling -pi/pi): bearings lo < hi
# (radians), the unit directions at lo and at hi
R_LO, R_HI, R_ULX, R_ULY, R_UHX, R_UHY = range(6)
# columns of a piece (a record cut at crossings): bearings lo < hi, unit directions at lo and at hi, the edge's
# direction vector (q - p, metres) and the cross product p x (q - p) (square metres), so that the edge's distance
# along a direction d is ``NUM / (d x (q - p))``
LO, HI, ULX, ULY, UHX, UHY, EX, EY, NUM = range(9)


@njit(cache=True)
def shifted_object_edges(coords, following, ox, oy):
    """Object edges relative to the observer ``(ox, oy)``: shape (m, 2, 2), ``[[x0, y0], [x1, y1]]`` metres."""
    m = len(coords)
    seg = np.empty((m, 2, 2))
    for j in range(m):
        seg[j, 0, 0] = coords[j, 0] - ox
        seg[j, 0, 1] = coords[j, 1] - oy
        seg[j, 1, 0] = coords[following[j], 0] - ox
        seg[j, 1, 1] = coords[following[j], 1] - oy
    return seg


@njit(cache=True)
def object_extents(offsets, ang):
    """``geometry.angular_extent`` of the shifted object rings, with the same floating-point operations.

    Parameters
    ----------
    offsets : ndarray, shape (n + 1,), int64
        Ragged rings of ``m`` vertices.
    ang : ndarray, shape (2 m,)
        ``arctan2`` of :func:`.crossings.prepare_frame`'s ``y`` and ``x`` for this observer: the bearing step
        (radians) along every edge, then every vertex's bearing (radians counter-clockwise from +x).

    Returns
    -------
    start, width : ndarray, shape (n,)
        Bearing where each object's extent starts (radians in [-pi, pi)) and its width (radians).
    """
    n = len(offsets) - 1
    m = offsets[n]
    start = np.empty(n)
    width = np.empty(n)
    cum = 0.0
    for i in range(n):
        s, e = offsets[i], offsets[i + 1]
        base = cum
        lo = np.inf
        hi = -np.inf
        for j in range(s, e):
            cum += ang[j]
            relative = cum - base
            lo = min(lo, relative)
            hi = max(hi, relative)
        lo = min(lo, 0.0)
        hi = max(hi, 0.0)
        start[i] = (ang[m + s] + lo + PI) % TWO_PI - PI
        width[i] = hi - lo
    return start, width


@njit(cache=True)
def object_distances(seg, offsets, transparent):
    """Nearest and farthest distance of each object from the observer, and how far targets reach.

    Returns
    -------
    near, far : ndarray, shape (n,)
        Metres, from the shifted edges ``seg`` (m, 2, 2) of the rings ``offsets`` (n + 1,).
    reach2 : float
        Squared distance (square metres) of the farthest point of a non-``transparent`` object, widened by 1e-9
        relative: static edges beyond it are behind everything reported.
    """
    n = len(offsets) - 1
    near = np.empty(n)
    far = np.empty(n)
    reach2 = 0.0
    for i in range(n):
        near2 = np.inf
        far2 = 0.0
        for j in range(offsets[i], offsets[i + 1]):
            ax, ay = seg[j, 0, 0], seg[j, 0, 1]
            near2 = min(near2, segment_distance2(ax, ay, seg[j, 1, 0], seg[j, 1, 1]))
            far2 = max(far2, ax * ax + ay * ay)
        near[i] = math.sqrt(near2)
        far[i] = math.sqrt(far2)
        if not transparent[i]:
            reach2 = max(reach2, far2)
    return near, far, reach2 * (1.0 + 1e-9)


@njit(cache=True, inline="always")
def _set_record(records, r, lo, hi, ulx, uly, uhx, uhy):
    """Write record ``r``: bearings ``lo < hi`` (radians) and the unit directions there."""
    records[r, R_LO], records[r, R_HI] = lo, hi
    records[r, R_ULX], records[r, R_ULY], records[r, R_UHX], records[r, R_UHY] = ulx, uly, uhx, uhy


@njit(cache=True)
def front_facing_edges(seg, ang, frame, statics, object_transparent, static_transparent, ox, oy, reach2, candidates):
    """Step 1: the edges facing the observer at ``(ox, oy)``, counter-clockwise, and their bearing records.

    Parameters
    ----------
    seg : ndarray, shape (m, 2, 2)
        Shifted object edges (:func:`shifted_object_edges`).
    ang : ndarray, shape (2 m,)
        As for :func:`object_extents`; object edges take their vertex bearings from it.
    frame : FrameEdges
    statics : StaticEdges
    object_transparent : ndarray of bool, shape (n,)
    static_transparent : ndarray of bool, shape (n_sources,)
    reach2 : float
        Static edges farther than this squared distance (square metres) are dropped.
    candidates : ndarray, int64
        The static edges to consider (ascending; e.g. :func:`.crossings.statics_near`), the others are dropped.

    Returns
    -------
    kept : KeptEdges
    record_edge : ndarray, shape (r,), int64
        The kept edge of each record, ascending.
    records : ndarray, shape (r, 6)
        Columns ``R_LO .. R_UHY``.
    """
    offsets, following = frame.offsets, frame.following
    n = len(offsets) - 1
    m = len(seg)
    n_edges = m + len(statics.start)
    n_tried = m + len(candidates)
    kept_of_edge = np.full(n_edges, -1, dtype=np.int64)
    kept_start = np.empty((n_tried, 2))
    kept_end = np.empty((n_tried, 2))
    kept_body = np.empty(n_tried, dtype=np.int64)
    kept_edge = np.empty(n_tried, dtype=np.int64)
    kept_distance = np.empty((n_tried, 2))
    record_edge = np.empty(2 * n_tried, dtype=np.int64)
    records = np.empty((2 * n_tried, 6))
    n_kept = 0
    n_rec = 0
    for tried in range(n_tried):
        g = tried if tried < m else m + candidates[tried - m]
        if g < m:
            body = frame.ring[g]
            if object_transparent[body]:
                continue
            ax, ay, bx, by = seg[g, 0, 0], seg[g, 0, 1], seg[g, 1, 0], seg[g, 1, 1]
            two_sided = False
        else:
            s = g - m
            source = statics.source[s]
            if static_transparent[source]:
                continue
            ax, ay = statics.start[s, 0] - ox, statics.start[s, 1] - oy
            bx, by = statics.end[s, 0] - ox, statics.end[s, 1] - oy
            if segment_distance2(ax, ay, bx, by) > reach2:
                continue
            two_sided = statics.two_sided[s]
            body = n + source
        cross = ax * by - ay * bx
        if cross < 0.0:
            px, py, qx, qy = bx, by, ax, ay
            flipped = True
        elif cross > 0.0 and two_sided:
            px, py, qx, qy = ax, ay, bx, by
            flipped = False
        else:
            continue
        if g < m:  # vertex bearings from numpy's arctan2 (the same values as the extents use)
            lo = ang[m + following[g]] if flipped else ang[m + g]
            hi = ang[m + g] if flipped else ang[m + following[g]]
        else:
            lo = math.atan2(py, px)
            hi = math.atan2(qy, qx)
        if py == 0.0 and px < 0.0:
            lo = -PI
        if qy == 0.0 and qx < 0.0:
            hi = PI
        kept_of_edge[g] = n_kept
        kept_edge[n_kept] = g
        kept_start[n_kept, 0], kept_start[n_kept, 1] = px, py
        kept_end[n_kept, 0], kept_end[n_kept, 1] = qx, qy
        kept_body[n_kept] = body
        kept_distance[n_kept, 0] = math.sqrt(segment_distance2(ax, ay, bx, by))
        kept_distance[n_kept, 1] = math.sqrt(max(ax * ax + ay * ay, bx * bx + by * by))
        p_norm = math.sqrt(px * px + py * py)
        q_norm = math.sqrt(qx * qx + qy * qy)
        if py > 0.0 and qy < 0.0:  # straddles the -pi/pi direction
            record_edge[n_rec] = n_kept
            _set_record(records, n_rec, lo, PI, px / p_norm, py / p_norm, -1.0, 0.0)
            n_rec += 1
            record_edge[n_rec] = n_kept
            _set_record(records, n_rec, -PI, hi, -1.0, 0.0, qx / q_norm, qy / q_norm)
            n_rec += 1
        elif lo < hi:
            record_edge[n_rec] = n_kept
            _set_record(records, n_rec, lo, hi, px / p_norm, py / p_norm, qx / q_norm, qy / q_norm)
            n_rec += 1
        n_kept += 1
    kept = KeptEdges(
        kept_of_edge, kept_start[:n_kept], kept_end[:n_kept], kept_body[:n_kept], kept_edge[:n_kept],
        kept_distance[:n_kept],
    )  # fmt: skip
    return kept, record_edge[:n_rec], records[:n_rec]


@njit(cache=True)
def crossing_cuts(kept, record_edge, records, cross_first, cross_second):
    """Step 2a: where kept edges of different bodies cross, as cuts of their records.

    Parameters
    ----------
    kept : KeptEdges
    record_edge, records
        From :func:`front_facing_edges`.
    cross_first, cross_second : ndarray, shape (c,), int64
        Edge numbers of the crossing pairs (see :data:`FrameEdges`).

    Returns
    -------
    cut_offsets : ndarray, shape (r + 1,), int64
        Record ``r``'s cuts are rows ``cut_offsets[r]:cut_offsets[r + 1]`` of ``cuts``.
    cuts : ndarray, shape (k, 3)
        Bearing of the crossing (radians, strictly inside the record) and the unit direction there.
    """
    n_kept = len(kept.body)
    n_rec = len(records)
    record_offsets = np.zeros(n_kept + 1, dtype=np.int64)
    for r in range(n_rec):
        record_offsets[record_edge[r] + 1] += 1
    prefix_sum(record_offsets)

    cut_record = np.empty(2 * len(cross_first), dtype=np.int64)
    cut = np.empty((2 * len(cross_first), 3))  # bearing, ux, uy
    n_cut = 0
    for c in range(len(cross_first)):
        e1 = kept.of_edge[cross_first[c]]
        e2 = kept.of_edge[cross_second[c]]
        if e1 < 0 or e2 < 0:
            continue
        p1x, p1y = kept.start[e1, 0], kept.start[e1, 1]
        d1x, d1y = kept.end[e1, 0] - p1x, kept.end[e1, 1] - p1y
        p2x, p2y = kept.start[e2, 0], kept.start[e2, 1]
        d2x, d2y = kept.end[e2, 0] - p2x, kept.end[e2, 1] - p2y
        den = d1x * d2y - d1y * d2x
        if den == 0.0:
            continue
        t = ((p2x - p1x) * d2y - (p2y - p1y) * d2x) / den
        cross_x, cross_y = p1x + t * d1x, p1y + t * d1y
        radius = math.sqrt(cross_x * cross_x + cross_y * cross_y)
        if radius == 0.0:
            continue
        bearing = math.atan2(cross_y, cross_x)
        for e in (e1, e2):
            for r in range(record_offsets[e], record_offsets[e + 1]):
                if records[r, R_LO] < bearing < records[r, R_HI]:
                    cut_record[n_cut] = r
                    cut[n_cut, 0], cut[n_cut, 1], cut[n_cut, 2] = bearing, cross_x / radius, cross_y / radius
                    n_cut += 1
                    break
    cut_offsets, order = group_by_key(cut_record, n_rec, np.arange(n_cut))
    cuts = np.empty((n_cut, 3))
    for s in range(n_cut):
        copy_into(cuts[s], 0, cut[order[s]])
    return cut_offsets, cuts


@njit(cache=True, inline="always")
def _sort_rows_by_bearing(table, start, stop):
    """Stable insertion sort of rows ``start:stop`` of a (k, 3) table by column 0, in place (few rows)."""
    for a in range(start + 1, stop):
        row0, row1, row2 = table[a, 0], table[a, 1], table[a, 2]
        b = a - 1
        while b >= start and table[b, 0] > row0:
            copy_into(table[b + 1], 0, table[b])
            b -= 1
        table[b + 1, 0], table[b + 1, 1], table[b + 1, 2] = row0, row1, row2


@njit(cache=True)
def cut_pieces(kept, record_edge, records, cut_offsets, cuts):
    """Step 2b: the records cut at their cuts (sorted by bearing in place), empty pieces dropped.

    Returns
    -------
    pieces : ndarray, shape (k, 9)
        Columns ``LO .. NUM``.
    body : ndarray, shape (k,), int64
        The body each piece belongs to.
    """
    n_rec = len(records)
    n_max = n_rec + len(cuts)
    pieces = np.empty((n_max, 9))
    body = np.empty(n_max, dtype=np.int64)
    n_piece = 0
    for r in range(n_rec):
        e = record_edge[r]
        s0, s1 = cut_offsets[r], cut_offsets[r + 1]
        _sort_rows_by_bearing(cuts, s0, s1)
        px, py = kept.start[e, 0], kept.start[e, 1]
        ex, ey = kept.end[e, 0] - px, kept.end[e, 1] - py
        num = px * ey - py * ex
        lo, ulx, uly = records[r, R_LO], records[r, R_ULX], records[r, R_ULY]
        for s in range(s0, s1 + 1):
            if s < s1:
                hi, uhx, uhy = cuts[s, 0], cuts[s, 1], cuts[s, 2]
            else:
                hi, uhx, uhy = records[r, R_HI], records[r, R_UHX], records[r, R_UHY]
            if hi > lo:
                pieces[n_piece, LO], pieces[n_piece, HI] = lo, hi
                pieces[n_piece, ULX], pieces[n_piece, ULY] = ulx, uly
                pieces[n_piece, UHX], pieces[n_piece, UHY] = uhx, uhy
                pieces[n_piece, EX], pieces[n_piece, EY], pieces[n_piece, NUM] = ex, ey, num
                body[n_piece] = kept.body[e]
                n_piece += 1
                lo, ulx, uly = hi, uhx, uhy
    return pieces[:n_piece], body[:n_piece]
