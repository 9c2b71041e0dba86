"""Counting rays that lie on one plane through the eye: the building block of the camera and the lidar.

A camera's pixel row and a lidar's azimuth column are each a *line* of rays in one plane through the eye:
``d(t) = a + t b`` (``a ⟂ b``, ``|b| = 1``, in the sensor's frame) at the line's sorted sample parameters ``t_j``
(a camera: ``(u + 0.5 - cx) / fx``; a lidar: ``tan`` of each elevation). The plane cuts every convex body in a
convex polygon (its edges' crossings), so the rays that meet the body are one interval of ``t``
(:func:`body_span`), found exactly from those crossings; which samples it holds is a binary search.

Along a line, the interval ends cut the samples into runs on which the same bodies are met. Two bodies whose
insides do not overlap are met in the same order by every ray of a run (were it otherwise, the segments joining
their entries on two rays would cross, at a point of both), so one ray of the run orders such a pair for the
whole run; only pairs that overlap (a double detection, a box through a wall) are ordered ray by ray. Ranges are
decided ray by ray only for the bodies that straddle the range sphere. The counts are therefore those of casting
every sample ray (the tests check this against a caster that does), at a cost per line of the bodies it meets,
not of its samples.

A target is met *first* along a ray when no other body is entered before it by more than
:data:`..geometry.occlusion.RELATIVE_TOLERANCE` of its distance (ties are visible, as in every engine); a ray
that grazes a body's edge meets it (within :data:`SAMPLE_MARGIN`).
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.occlusion import RELATIVE_TOLERANCE
from .scene import pair_overlaps

SAMPLE_MARGIN = 1e-12
"""A sample within this share (of ``1 + |t|``) outside a body's interval of ``t`` still meets it: a ray along an
edge is a hit, and rounding never drops it."""

_HALF_PI = math.pi / 2


@njit(cache=True)
def body_span(vertices, v0, v1, edges, e0, e1, a, b, norm_a, scratch, side):
    """The interval ``(t_lo, t_hi)`` of rays ``a + t b`` (``a ⟂ b``, ``|b| = 1``) that meet the convex body
    whose vertices are ``vertices[v0:v1]`` and edges ``edges[e0:e1]`` (eye at the origin, outside the body);
    ``t_lo > t_hi`` when none does. ``scratch`` has room for one point per edge and vertex, shape (k, 2), and
    ``side`` for three numbers per vertex, shape (v, 3)."""
    mx = a[1] * b[2] - a[2] * b[1]
    my = a[2] * b[0] - a[0] * b[2]
    mz = a[0] * b[1] - a[1] * b[0]
    count = 0
    for i in range(v0, v1):  # each vertex's side of the plane and its coordinates along a and b, once
        x, y, z = vertices[i, 0], vertices[i, 1], vertices[i, 2]
        r = i - v0
        side[r, 0] = mx * x + my * y + mz * z
        side[r, 1] = (x * a[0] + y * a[1] + z * a[2]) / norm_a
        side[r, 2] = x * b[0] + y * b[1] + z * b[2]
        if side[r, 0] == 0.0:  # on the plane
            scratch[count, 0], scratch[count, 1] = side[r, 1], side[r, 2]
            count += 1
    for k in range(e0, e1):  # and the edges crossing it
        i, j = edges[k, 0] - v0, edges[k, 1] - v0
        si, sj = side[i, 0], side[j, 0]
        if (si < 0.0 < sj) or (sj < 0.0 < si):
            w = si / (si - sj)
            scratch[count, 0] = side[i, 1] + w * (side[j, 1] - side[i, 1])
            scratch[count, 1] = side[i, 2] + w * (side[j, 2] - side[i, 2])
            count += 1
    if count == 0:
        return 1.0, -1.0
    t_lo = np.inf
    t_hi = -np.inf
    ahead = True
    for p in range(count):
        if scratch[p, 0] <= 0.0:
            ahead = False
            break
        t = norm_a * scratch[p, 1] / scratch[p, 0]
        t_lo = min(t_lo, t)
        t_hi = max(t_hi, t)
    if ahead:  # the whole cross-section ahead of the line: its ends are the extreme points
        return t_lo, t_hi
    # a direction inside the cone of the cross-section: the sum of its points' directions
    rx = 0.0
    ry = 0.0
    for p in range(count):
        r = math.hypot(scratch[p, 0], scratch[p, 1])
        if r > 0.0:
            rx += scratch[p, 0] / r
            ry += scratch[p, 1] / r
    if math.hypot(rx, ry) < 1e-12:  # the plane passes (almost) through the eye's side of the body: all of it
        return -np.inf, np.inf
    lo = np.inf
    hi = -np.inf
    p_lo = 0
    p_hi = 0
    for p in range(count):
        rel = math.atan2(rx * scratch[p, 1] - ry * scratch[p, 0], rx * scratch[p, 0] + ry * scratch[p, 1])
        if rel < lo:
            lo, p_lo = rel, p
        if rel > hi:
            hi, p_hi = rel, p
    base = math.atan2(ry, rx)
    for shift in (-2.0 * math.pi, 0.0, 2.0 * math.pi):  # the rays a + t b are the angles (-π/2, π/2)
        low, high = base + lo + shift, base + hi + shift
        if high > -_HALF_PI and low < _HALF_PI:
            t_lo = (
                -np.inf if low <= -_HALF_PI or scratch[p_lo, 0] <= 0.0 else norm_a * scratch[p_lo, 1] / scratch[p_lo, 0]
            )
            t_hi = (
                np.inf if high >= _HALF_PI or scratch[p_hi, 0] <= 0.0 else norm_a * scratch[p_hi, 1] / scratch[p_hi, 0]
            )
            return t_lo, t_hi
    return 1.0, -1.0


@njit(cache=True, inline="always")
def entry(normals, offsets, k, dx, dy, dz):
    """Where the ray along ``(dx, dy, dz)`` from the origin enters body ``k`` (planes ``normals . x <=
    offsets``), in units of the direction's length (0 from inside); the caller knows the ray meets it."""
    t0 = 0.0
    for p in range(normals.shape[1]):
        g = normals[k, p, 0] * dx + normals[k, p, 1] * dy + normals[k, p, 2] * dz
        if g < 0.0:
            t = offsets[k, p] / g
            if t > t0:
                t0 = t
    return t0


@njit(cache=True, inline="always")
def _widen(box, slot, line, j0, j1):
    """Grow the 2D box ``box[slot] = (j_min, line_min, j_max, line_max)`` by samples ``j0..j1`` of ``line``."""
    if box[slot, 0] < 0 or j0 < box[slot, 0]:
        box[slot, 0] = j0
    if box[slot, 1] < 0 or line < box[slot, 1]:
        box[slot, 1] = line
    if j1 > box[slot, 2]:
        box[slot, 2] = j1
    if line > box[slot, 3]:
        box[slot, 3] = line


@njit(cache=True)
def workspace(body):
    """Room for :func:`count_line`'s work on lines among these bodies (``body`` as it takes it), made once."""
    vertices, vstart, edges = body[0], body[1], body[2]
    n = len(vstart) - 1
    most = 1
    for k in range(n):
        most = max(most, vstart[k + 1] - vstart[k])
    return (
        np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n, dtype=np.int64),
        np.empty(2 * n + 1, dtype=np.int64), np.empty(n, dtype=np.int64), np.empty(n),
        np.empty((max(1, 2 * len(edges) + len(vertices)), 2)), np.empty((most, 3)), np.empty(n, dtype=np.int64),
        np.empty((max(1, n * body[4].shape[1]), 2), dtype=np.int64),
    )  # fmt: skip


@njit(cache=True, inline="always")
def _overlapping(body, overlap, g, k, other):
    """Whether target ``g`` (body ``k``) may overlap body ``other``, decided once per scene on first need."""
    if overlap[g, other] < 0:
        vertices, vstart, _, _, normals, offsets, centre, radius = body
        overlap[g, other] = pair_overlaps(vertices, vstart, normals, offsets, centre, radius, k, other)
    return overlap[g, other] == 1


@njit(cache=True)
def hidden_ranges(normals, offsets, k, other, a, b, samples, s, e, ranges, count):
    """Append to ``ranges[count:]`` the runs of samples ``s .. e - 1`` (index pairs ``[j0, j1)``) along which
    body ``other`` is entered before body ``k`` (both met by every ray of the run); the new count.

    Along every ray that meets a body, each of its face planes that the eye lies outside of (``offset < 0``) has
    ``normal . d < 0``, and the entry is the largest ``offset / (normal . d)`` of them; so ``other`` comes first
    (by more than the tolerance) exactly where, for some such face ``p`` of ``k`` and every such face ``q`` of
    ``other``, ``(offset_q normal_p - (1 - tol) offset_p normal_q) . d < 0``: half-lines of ``t`` along the line
    (as :mod:`..threed.order` draws them on the cube), one interval per face of ``k``.
    """
    keep = 1.0 - RELATIVE_TOLERANCE
    for p in range(normals.shape[1]):
        op = offsets[k, p]
        if op >= 0.0:
            continue
        lo = -np.inf
        hi = np.inf
        for q in range(normals.shape[1]):
            oq = offsets[other, q]
            if oq >= 0.0:
                continue
            wx = oq * normals[k, p, 0] - keep * op * normals[other, q, 0]
            wy = oq * normals[k, p, 1] - keep * op * normals[other, q, 1]
            wz = oq * normals[k, p, 2] - keep * op * normals[other, q, 2]
            alpha = wx * a[0] + wy * a[1] + wz * a[2]
            beta = wx * b[0] + wy * b[1] + wz * b[2]
            if beta > 0.0:
                hi = min(hi, -alpha / beta)
            elif beta < 0.0:
                lo = max(lo, -alpha / beta)
            elif alpha >= 0.0:
                lo = np.inf
        if lo < hi:
            j0 = max(s, np.searchsorted(samples, lo, side="right"))
            j1 = min(e, np.searchsorted(samples, hi))
            if j0 < j1:
                ranges[count, 0], ranges[count, 1] = j0, j1
                count += 1
    return count


@njit(cache=True, inline="always")
def _seen(out, g, line, j0, j1):
    """Samples ``j0 .. j1`` of ``line`` meet target ``g`` first: count them, grow its box, label them."""
    first, first_box, labels = out[0], out[3], out[6]
    first[g] += j1 - j0 + 1
    _widen(first_box, g, line, j0, j1)
    if labels.shape[0] > 0:
        labels[line, j0 : j1 + 1] = g


@njit(cache=True)
def _count_visible(ranges, n_ranges, s, e, g, line, out):
    """Count samples ``s .. e - 1`` outside the hidden ``ranges[:n_ranges]`` as seen first by target ``g``."""
    for i in range(1, n_ranges):  # by their starts (a handful)
        j = i
        while j > 0 and ranges[j - 1, 0] > ranges[j, 0]:
            r0, r1 = ranges[j, 0], ranges[j, 1]
            ranges[j, 0], ranges[j, 1] = ranges[j - 1, 0], ranges[j - 1, 1]
            ranges[j - 1, 0], ranges[j - 1, 1] = r0, r1
            j -= 1
    cursor = s
    for i in range(n_ranges):
        if ranges[i, 0] > cursor:
            _seen(out, g, line, cursor, ranges[i, 0] - 1)
        cursor = max(cursor, ranges[i, 1])
    if cursor < e:
        _seen(out, g, line, cursor, e - 1)


@njit(cache=True)
def count_line(line, a, b, samples, candidates, body, target, max_range, out, work):
    """Count the samples of one line (rays ``a + samples[j] b``) for every target among the ``candidates``
    (body numbers whose line range holds this line).

    ``body`` is ``(vertices, vstart, edges, estart, normals, offsets, centre, radius)`` and ``target`` is
    ``(slot, near, far, overlap)`` of a :class:`.scene.SensorScene`; ``out`` is ``(first, unoccluded, met,
    first_box, unoccluded_box, hidden_by, labels)``. Per target (``slot[body] >= 0``): ``met`` counts the rays that meet
    it, ``unoccluded`` those that meet it within ``max_range`` (metres), ``first`` those that meet it first within
    range; ``first_box`` and ``unoccluded_box`` grow by ``(sample, line)`` of those rays; ``hidden_by[slot, body]``
    is set where ``body`` is entered before the target along a ray that meets the target within range; ``labels``
    (lines x samples, or empty) gets the target number of each sample that meets a target first. ``work`` is
    :func:`workspace`'s.
    """
    vertices, vstart, edges, estart, normals, offsets, _, _ = body
    slot, near, far, overlap = target
    unoccluded, met, unoccluded_box, hidden_by = out[1], out[2], out[4], out[5]
    norm_a = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    k_max = len(candidates)
    bodies, j_lo, j_hi, cuts, active, depth, scratch, sides, overlapping, ranges = work
    m = 0
    reach_lo = len(samples)
    reach_hi = -1
    for blockers in range(2):  # the targets first; then, if any is met, the bodies that only block
        for c in range(k_max):
            k = candidates[c]
            if (slot[k] < 0) != (blockers == 1):
                continue
            v0, v1, e0, e1 = vstart[k], vstart[k + 1], estart[k], estart[k + 1]
            t_lo, t_hi = body_span(vertices, v0, v1, edges, e0, e1, a, b, norm_a, scratch, sides)
            if t_lo > t_hi:
                continue
            lo = np.searchsorted(samples, t_lo - SAMPLE_MARGIN * (1.0 + abs(t_lo)))
            hi = np.searchsorted(samples, t_hi + SAMPLE_MARGIN * (1.0 + abs(t_hi)), side="right") - 1
            if lo > hi or (blockers == 1 and (hi < reach_lo or lo > reach_hi)):
                continue  # no ray, or none shared with a target
            bodies[m], j_lo[m], j_hi[m] = k, lo, hi
            m += 1
            if blockers == 0:
                reach_lo, reach_hi = min(reach_lo, lo), max(reach_hi, hi)
        if m == 0:
            return
    cuts[:m] = j_lo[:m]
    cuts[m : 2 * m] = j_hi[:m] + 1
    cuts[: 2 * m].sort()
    for q in range(2 * m - 1):
        s, e = cuts[q], cuts[q + 1]
        if s == e:
            continue
        n_active = 0
        has_target = False
        for i in range(m):
            if j_lo[i] <= s and j_hi[i] >= e - 1:
                active[n_active] = bodies[i]
                has_target |= slot[bodies[i]] >= 0
                n_active += 1
        if not has_target:
            continue
        t = samples[s]
        dx, dy, dz = a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2]
        for i in range(n_active):
            depth[i] = entry(normals, offsets, active[i], dx, dy, dz)
        for i in range(n_active):
            k = active[i]
            g = slot[k]
            if g < 0:
                continue
            met[g] += e - s
            if near[k] > max_range:
                continue
            hidden = False  # by a body it does not overlap: then on the whole run
            n_overlap = 0
            for o in range(n_active):
                if o != i:
                    if _overlapping(body, overlap, g, k, active[o]):
                        overlapping[n_overlap] = active[o]
                        n_overlap += 1
                    elif depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                        hidden = True
            if far[k] <= max_range:  # wholly within range: every ray of the run meets it within range
                unoccluded[g] += e - s
                _widen(unoccluded_box, g, line, s, e - 1)
                if hidden:
                    for o in range(n_active):
                        if o != i and depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                            hidden_by[g, active[o]] = True
                # the overlapping bodies hide it where their entry comes first: intervals of the line, exactly
                n_ranges = 0
                for q in range(n_overlap):
                    added = hidden_ranges(normals, offsets, k, overlapping[q], a, b, samples, s, e, ranges, n_ranges)
                    if added > n_ranges:
                        hidden_by[g, overlapping[q]] = True
                    n_ranges = added
                if not hidden:
                    _count_visible(ranges, n_ranges, s, e, g, line, out)
                continue
            for j in range(s, e):  # ray by ray
                t = samples[j]
                dx, dy, dz = a[0] + t * b[0], a[1] + t * b[1], a[2] + t * b[2]
                mine = entry(normals, offsets, k, dx, dy, dz)
                if mine * math.sqrt(dx * dx + dy * dy + dz * dz) > max_range:
                    continue
                unoccluded[g] += 1
                _widen(unoccluded_box, g, line, j, j)
                seen = True
                for o in range(n_active):
                    if o == i:
                        continue
                    other = active[o]
                    if overlap[g, other] == 1:
                        if entry(normals, offsets, other, dx, dy, dz) < mine * (1.0 - RELATIVE_TOLERANCE):
                            hidden_by[g, other] = True
                            seen = False
                    elif depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                        hidden_by[g, other] = True
                        seen = False
                if seen:
                    _seen(out, g, line, j, j)
