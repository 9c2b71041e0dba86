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

import numba
import numpy as np

from ...geometry.occlusion import RELATIVE_TOLERANCE

SAMPLE_MARGIN = 1e-12
"""A sample within this share (of ``1 + |t|``) outside a body's interval of ``t`` still meets it: a ray along an
edge is a hit, and rounding never drops it."""

_HALF_PI = math.pi / 2


@numba.njit(cache=True)
def body_span(vertices, v0, v1, edges, e0, e1, a, b, norm_a, scratch):
    """The interval ``(t_lo, t_hi)`` of rays ``a + t b`` (``a ⟂ b``, ``|b| = 1``) that meet the convex body
    whose vertices are ``vertices[v0:v1]`` and edges ``edges[e0:e1]`` (eye at the origin, outside the body);
    ``t_lo > t_hi`` when none does. ``scratch`` has room for one point per edge and vertex, shape (k, 2)."""
    mx = a[1] * b[2] - a[2] * b[1]
    my = a[2] * b[0] - a[0] * b[2]
    mz = a[0] * b[1] - a[1] * b[0]
    count = 0
    for i in range(v0, v1):  # the vertices on the plane
        s = mx * vertices[i, 0] + my * vertices[i, 1] + mz * vertices[i, 2]
        if s == 0.0:
            scratch[count, 0] = (vertices[i, 0] * a[0] + vertices[i, 1] * a[1] + vertices[i, 2] * a[2]) / norm_a
            scratch[count, 1] = vertices[i, 0] * b[0] + vertices[i, 1] * b[1] + vertices[i, 2] * b[2]
            count += 1
    for k in range(e0, e1):  # and the edges crossing it
        i, j = edges[k, 0], edges[k, 1]
        si = mx * vertices[i, 0] + my * vertices[i, 1] + mz * vertices[i, 2]
        sj = mx * vertices[j, 0] + my * vertices[j, 1] + mz * vertices[j, 2]
        if (si < 0.0 < sj) or (sj < 0.0 < si):
            w = si / (si - sj)
            qx = vertices[i, 0] + w * (vertices[j, 0] - vertices[i, 0])
            qy = vertices[i, 1] + w * (vertices[j, 1] - vertices[i, 1])
            qz = vertices[i, 2] + w * (vertices[j, 2] - vertices[i, 2])
            scratch[count, 0] = (qx * a[0] + qy * a[1] + qz * a[2]) / norm_a
            scratch[count, 1] = qx * b[0] + qy * b[1] + qz * b[2]
            count += 1
    if count == 0:
        return 1.0, -1.0
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


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True, inline="always")
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


@numba.njit(cache=True)
def count_line(
    line, a, b, samples, candidates, vertices, vstart, edges, estart, normals, offsets,
    slot, near, far, max_range, overlap, first, unoccluded, met, first_box, unoccluded_box, hidden_by, scratch,
):  # fmt: skip
    """Count the samples of one line (rays ``a + samples[j] b``) for every target among the ``candidates``
    (body numbers whose row or column range holds this line).

    Per target (``slot[body] >= 0``): ``met`` counts the rays that meet it, ``unoccluded`` those that meet it within
    ``max_range`` (metres), ``first`` those that meet it first within range; ``first_box`` and ``unoccluded_box``
    grow by ``(sample, line)`` of those rays; ``hidden_by[slot, body]`` is set where ``body`` is entered before
    the target along a ray that meets the target within range. ``near`` and ``far`` are each body's nearest and
    farthest distance (metres); ``overlap[slot, body]`` says whether a target's inside overlaps the body's.
    """
    norm_a = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    len(samples)
    k_max = len(candidates)
    bodies = np.empty(k_max, dtype=np.int64)
    j_lo = np.empty(k_max, dtype=np.int64)
    j_hi = np.empty(k_max, dtype=np.int64)
    m = 0
    any_target = False
    for c in range(k_max):
        k = candidates[c]
        t_lo, t_hi = body_span(
            vertices, vstart[k], vstart[k + 1], edges, estart[k], estart[k + 1], a, b, norm_a, scratch
        )
        if t_lo > t_hi:
            continue
        lo = np.searchsorted(samples, t_lo - SAMPLE_MARGIN * (1.0 + abs(t_lo)))
        hi = np.searchsorted(samples, t_hi + SAMPLE_MARGIN * (1.0 + abs(t_hi)), side="right") - 1
        if lo > hi:
            continue
        bodies[m], j_lo[m], j_hi[m] = k, lo, hi
        any_target |= slot[k] >= 0
        m += 1
    if not any_target:
        return
    cuts = np.empty(2 * m, dtype=np.int64)
    cuts[:m] = j_lo[:m]
    cuts[m:] = j_hi[:m] + 1
    cuts.sort()
    active = np.empty(m, dtype=np.int64)
    depth = np.empty(m)
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
            hidden = False  # by a body it does not overlap: then on the whole run
            mixed = far[k] > max_range and near[k] <= max_range  # straddles the range: ray by ray
            for o in range(n_active):
                if o != i:
                    if overlap[g, active[o]]:
                        mixed = True
                    elif depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                        hidden = True
            if not mixed:
                if near[k] > max_range:
                    continue
                unoccluded[g] += e - s
                _widen(unoccluded_box, g, line, s, e - 1)
                if hidden:
                    for o in range(n_active):
                        if o != i and depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                            hidden_by[g, active[o]] = True
                else:
                    first[g] += e - s
                    _widen(first_box, g, line, s, e - 1)
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
                    if overlap[g, other]:
                        if entry(normals, offsets, other, dx, dy, dz) < mine * (1.0 - RELATIVE_TOLERANCE):
                            hidden_by[g, other] = True
                            seen = False
                    elif depth[o] < depth[i] * (1.0 - RELATIVE_TOLERANCE):
                        hidden_by[g, other] = True
                        seen = False
                if seen:
                    first[g] += 1
                    _widen(first_box, g, line, j, j)
