"""The area measure's compiled path, for frames where every body is convex and no static occluder is given: each
target's part in view as convex pieces, minus every shadow that may fall on it (:mod:`..geometry.convex_clip`),
measured exactly inside the range circle. The same numbers as the polygon clipping of :mod:`.area` (which takes
every other frame), in one compiled call per viewpoint."""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit
from ..geometry.convex_clip import clip_line, convex_hull, disc_area, polygon_area, subtract
from ..geometry.kernels import copy_rows, reserve
from ..geometry.shadows import ARC_POINTS
from ..geometry.spans import may_be_in_front

MAX_PIECES = 512
"""Convex pieces one target may be cut into before the general path takes the frame."""
MAX_VERTICES = 64
"""Vertices of one piece at most."""


@njit(cache=True)
def _convex(coords, start, size, tolerance=1e-12):
    """Whether the counter-clockwise ring ``coords[start:start + size]`` is convex (no edge turns right)."""
    for i in range(size):
        a, b, c = start + i, start + (i + 1) % size, start + (i + 2) % size
        e1x, e1y = coords[b, 0] - coords[a, 0], coords[b, 1] - coords[a, 1]
        e2x, e2y = coords[c, 0] - coords[b, 0], coords[c, 1] - coords[b, 1]
        scale = math.hypot(e1x, e1y) * math.hypot(e2x, e2y)
        if e1x * e2y - e1y * e2x < -tolerance * max(scale, 1e-300):
            return False
    return True


@njit(cache=True)
def _shadow(coords, start, size, centre, half, reach, out, points):
    """The convex shadow of the convex ring ``coords[start:start + size]`` with span ``centre ± half`` out to
    ``reach`` (as :func:`..geometry.shadows.shadows` builds it) into ``out``; its count."""
    for i in range(size):
        points[i, 0], points[i, 1] = coords[start + i, 0], coords[start + i, 1]
    step = 2.0 * half / (ARC_POINTS - 1)
    radius = reach / math.cos(0.5 * step)
    for i in range(ARC_POINTS):
        angle = centre - half + step * i
        points[size + i, 0], points[size + i, 1] = radius * math.cos(angle), radius * math.sin(angle)
    return convex_hull(points, size + ARC_POINTS, out)


@njit(cache=True)
def _measure(pieces, counts, n_pieces, radius):
    """Area of the pieces and their area inside the range circle, square metres."""
    whole, inside = 0.0, 0.0
    for p in range(n_pieces):
        whole += abs(polygon_area(pieces[p], counts[p]))
        inside += disc_area(pieces[p], counts[p], radius)
    return whole, inside


@njit(cache=True)
def convex_frame_areas(coords, offsets, active, centre, half, near, far, reach, radius, heading, fov, min_hidden):
    """The area measure of one viewpoint's frame (coordinates relative to the viewpoint; ``fov >= 2 pi`` looks
    all around): per target its footprint's area, the area in the field of view, in view and range, and visible
    (square metres); the occluders as CSR ``(offsets, bodies)``, a body listed where its shadow covers more than
    ``min_hidden`` of the target's area in view and range; and whether the frame fitted (every active ring
    convex, the buffers large enough), else the caller takes the general path."""
    n = len(offsets) - 1
    in_fov, in_view, visible, area = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    occ_offsets = np.zeros(n + 1, np.int64)
    occ = np.empty(16, np.int64)
    n_occ = 0
    largest = 0
    for t in range(n):
        size = offsets[t + 1] - offsets[t]
        largest = max(largest, size)
        area[t] = abs(polygon_area(coords[offsets[t] :], size))
        if active[t] and not _convex(coords, offsets[t], size):
            return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
    a = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    b = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    seen = np.empty((MAX_PIECES, MAX_VERTICES, 2))
    ac = np.zeros(MAX_PIECES, np.int64)
    bc = np.zeros(MAX_PIECES, np.int64)
    seen_c = np.zeros(MAX_PIECES, np.int64)
    scratch = np.empty((2, MAX_VERTICES, 2))
    hull_points = np.empty((largest + ARC_POINTS + 2, 2))
    shadows = np.empty((n, 2 * (largest + ARC_POINTS) + 2, 2))
    shadow_n = np.full(n, -1, np.int64)
    blind = np.empty((ARC_POINTS + 1, 2))
    n_blind = 0
    if np.pi < fov < 2.0 * np.pi:  # the blind wedge (less than π wide) is subtracted
        blind[0, 0], blind[0, 1] = 0.0, 0.0
        gap = 2.0 * np.pi - fov
        step = gap / (ARC_POINTS - 1)
        r = reach / math.cos(0.5 * step)
        for i in range(ARC_POINTS):
            angle = heading + 0.5 * fov + step * i
            blind[i + 1, 0], blind[i + 1, 1] = r * math.cos(angle), r * math.sin(angle)
        n_blind = ARC_POINTS + 1
    for t in range(n):
        occ_offsets[t + 1] = n_occ
        if not active[t]:
            continue
        size = offsets[t + 1] - offsets[t]
        if size > MAX_VERTICES:
            return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
        copy_rows(seen[0], 0, coords[offsets[t] : offsets[t + 1]])
        seen_c[0] = size
        n_seen = 1
        if fov <= np.pi:  # the wedge: left of its right edge, right of its left edge
            m = clip_line(seen[0], size, 0.0, 0.0, math.cos(heading - 0.5 * fov), math.sin(heading - 0.5 * fov),
                          True, scratch[0])  # fmt: skip
            m = clip_line(scratch[0], m, 0.0, 0.0, math.cos(heading + 0.5 * fov), math.sin(heading + 0.5 * fov),
                          False, seen[0])  # fmt: skip
            if m < 0:
                return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
            seen_c[0] = m
            n_seen = 1 if m >= 3 else 0
        elif n_blind:
            n_seen = subtract(seen, seen_c, 1, blind, n_blind, a, ac, scratch)
            if n_seen < 0:
                return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
            for p in range(n_seen):
                copy_rows(seen[p], 0, a[p, : ac[p]])
                seen_c[p] = ac[p]
        in_fov[t], in_view[t] = _measure(seen, seen_c, n_seen, radius)
        for p in range(n_seen):
            copy_rows(a[p], 0, seen[p, : seen_c[p]])
            ac[p] = seen_c[p]
        n_pieces = n_seen
        for body in range(n):
            if body == t or not active[body]:
                continue
            if not may_be_in_front(centre[body], half[body], near[body], centre[t], half[t], far[t]):
                continue
            if shadow_n[body] < 0:
                start, count = offsets[body], offsets[body + 1] - offsets[body]
                shadow_n[body] = _shadow(coords, start, count, centre[body], half[body], reach, shadows[body],
                                         hull_points)  # fmt: skip
                if shadow_n[body] < 0:
                    return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
            shape, ks = shadows[body], shadow_n[body]
            total = 0.0
            for p in range(n_seen):  # what this body hides of the part in view: seen ∩ shadow
                m = seen_c[p]
                copy_rows(scratch[0], 0, seen[p, :m])
                for i in range(ks):
                    j = (i + 1) % ks
                    m = clip_line(scratch[0], m, shape[i, 0], shape[i, 1], shape[j, 0], shape[j, 1], True,
                                  scratch[1])  # fmt: skip
                    if m < 0:
                        return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
                    copy_rows(scratch[0], 0, scratch[1, :m])
                    if m < 3:
                        break
                if m >= 3:
                    total += disc_area(scratch[0], m, radius)
            if total > min_hidden * area[t]:
                occ = reserve(occ, n_occ, n_occ + 1)
                occ[n_occ] = body
                n_occ += 1
            n_pieces = subtract(a, ac, n_pieces, shape, ks, b, bc, scratch)
            if n_pieces < 0:
                return area, in_fov, in_view, visible, occ_offsets, occ[:0], False
            a, b = b, a
            ac, bc = bc, ac
        visible[t] = _measure(a, ac, n_pieces, radius)[1]
        occ_offsets[t + 1] = n_occ
    return area, in_fov, in_view, visible, occ_offsets, occ[:n_occ], True
