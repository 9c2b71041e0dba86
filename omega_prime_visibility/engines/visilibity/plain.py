"""The plain environment of a viewpoint: the bodies themselves as VisiLibity's holes, built in one compiled call.

The engine's general construction (:meth:`.VisiLibityEngine._build_environment`) merges bodies that meet into one
hole, and cuts the free space out of the bodies when a static part with a courtyard holds the viewpoint. Where no
two bodies meet, it gives the plain environment: the box around everything and the viewpoint (``box_margin``
metres to spare, counter-clockwise), each blocking object's ring reversed (clockwise), then the static parts. In
town most bounding boxes that overlap belong to bodies apart (a car beside an L-shaped building, within its box),
so the test here is exact rather than by boxes: the plain environment is taken when every two bodies whose boxes
overlap lie more than :data:`APART` metres apart (no edges nearer, none inside the other) and the viewpoint lies
that far outside every static part with a courtyard. Anything nearer is left to the general construction, whose
polygons are then the same numbers as the plain ones.
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import copy_into, copy_rows, cross_properly, nearest_offset, reserve, reserve_rows
from ...geometry.rings import ring_covers_point
from .conversion import box_overlaps

APART = 1e-9
"""Metres (coordinates relative to the origin, at most a few kilometres): bodies nearer than this may meet, and
go to the general construction."""


@njit(cache=True)
def rings_apart(coords, a0, a1, b0, b1, apart):
    """Whether the rings ``coords[a0:a1]`` and ``coords[b0:b1]`` (metres, closing vertex not repeated) lie more
    than ``apart`` metres apart: no two edges cross or come that near, and neither ring holds a vertex of the
    other.

    Examples
    --------
    >>> square = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    >>> coords = np.concatenate([square, square + [1.5, 0.0], square * 3.0 - 1.0])
    >>> bool(rings_apart(coords, 0, 4, 4, 8, 1e-9)), bool(rings_apart(coords, 0, 4, 8, 12, 1e-9))
    (True, False)
    """
    limit = apart * apart
    for i in range(a0, a1):
        j = i + 1 if i + 1 < a1 else a0
        ax, ay, bx, by = coords[i, 0], coords[i, 1], coords[j, 0], coords[j, 1]
        for k in range(b0, b1):
            q = k + 1 if k + 1 < b1 else b0
            cx, cy, dx, dy = coords[k, 0], coords[k, 1], coords[q, 0], coords[q, 1]
            if cross_properly(ax, ay, bx, by, cx, cy, dx, dy):
                return False
            for px, py, sx, sy, ex, ey in (
                (cx, cy, ax, ay, bx, by),
                (dx, dy, ax, ay, bx, by),
                (ax, ay, cx, cy, dx, dy),
                (bx, by, cx, cy, dx, dy),
            ):
                ox, oy = nearest_offset(px - sx, py - sy, ex - sx, ey - sy)
                if ox * ox + oy * oy <= limit:
                    return False
    inside_b = ring_covers_point(coords, b0, b1, coords[a0, 0], coords[a0, 1], apart)
    return not inside_b and not ring_covers_point(coords, a0, a1, coords[b0, 0], coords[b0, 1], apart)


@njit(cache=True)
def plain_environment(coords, offsets, s, e, gx, gy, ox, oy, in_env, parts, part_offsets, part_encloses, margin):
    """The plain environment of viewpoint ``(ox, oy)`` (metres, relative to the origin ``(gx, gy)``), if it applies.

    Parameters
    ----------
    coords, offsets : ndarray
        The chunk's object rings (world frame, metres); the frame's objects are rows ``s .. e - 1``.
    in_env : ndarray of bool, shape (e - s,)
        The objects that are holes of the environment.
    parts, part_offsets : ndarray
        The static parts blocking the view, as VisiLibity holes relative to the origin (clockwise, metres): part
        ``k`` is ``parts[part_offsets[k]:part_offsets[k + 1]]``; ``part_encloses`` (bool) marks those with a
        courtyard.
    margin : float
        Metres of free space around everything (the outer box).

    Returns
    -------
    plain : bool
        Whether the plain environment applies (else nothing else is filled in).
    vertices : ndarray, shape (m, 2)
        The outer box, then the holes, back to back (metres, relative to the origin), as ``_visilibity1`` takes them.
    counts : ndarray, shape (h + 1,), int64
        The vertex count of each polygon.
    """
    for k in range(len(part_offsets) - 1):
        if part_encloses[k] and ring_covers_point(parts, part_offsets[k], part_offsets[k + 1], ox, oy, APART):
            return False, np.zeros((0, 2)), np.zeros(0, dtype=np.int64)
    n_objects = 0
    n_vertices = 4 + len(parts)
    for i in range(e - s):
        if in_env[i]:
            n_objects += 1
            n_vertices += offsets[s + i + 1] - offsets[s + i]
    n_holes = n_objects + len(part_offsets) - 1
    vertices = np.empty((n_vertices, 2))
    counts = np.empty(n_holes + 1, dtype=np.int64)
    starts = np.empty(n_holes + 1, dtype=np.int64)  # each polygon's first vertex
    counts[0], starts[0] = 4, 0
    h, at = 1, 4
    for i in range(e - s):
        if in_env[i]:
            a0, a1 = offsets[s + i], offsets[s + i + 1]
            counts[h], starts[h] = a1 - a0, at
            for q in range(a1 - 1, a0 - 1, -1):  # reversed: clockwise
                vertices[at, 0], vertices[at, 1] = coords[q, 0] - gx, coords[q, 1] - gy
                at += 1
            h += 1
    for k in range(len(part_offsets) - 1):
        counts[h], starts[h] = part_offsets[k + 1] - part_offsets[k], at
        for q in range(part_offsets[k], part_offsets[k + 1]):
            vertices[at, 0], vertices[at, 1] = parts[q, 0], parts[q, 1]
            at += 1
        h += 1
    lo = np.empty((n_holes, 2))
    hi = np.empty((n_holes, 2))
    for h in range(n_holes):
        for c in range(2):
            least, most = np.inf, -np.inf
            for q in range(starts[h + 1], starts[h + 1] + counts[h + 1]):
                least = min(least, vertices[q, c])
                most = max(most, vertices[q, c])
            lo[h, c], hi[h, c] = least, most
    first, second = box_overlaps(lo, hi)
    for p in range(len(first)):
        i, j = first[p] + 1, second[p] + 1
        if not rings_apart(vertices, starts[i], starts[i] + counts[i], starts[j], starts[j] + counts[j], APART):
            return False, np.zeros((0, 2)), np.zeros(0, dtype=np.int64)
    x0, y0, x1, y1 = ox, oy, ox, oy
    for h in range(n_holes):
        x0, y0 = min(x0, lo[h, 0]), min(y0, lo[h, 1])
        x1, y1 = max(x1, hi[h, 0]), max(y1, hi[h, 1])
    x0, y0, x1, y1 = x0 - margin, y0 - margin, x1 + margin, y1 + margin
    vertices[0, 0], vertices[0, 1] = x0, y0
    vertices[1, 0], vertices[1, 1] = x1, y0
    vertices[2, 0], vertices[2, 1] = x1, y1
    vertices[3, 0], vertices[3, 1] = x0, y1
    return True, vertices, counts


@njit(cache=True)
def plain_environments(
    views, frame_of_view, frame_starts, target_offsets, in_env, coords, offsets, origins, eyes, parts, part_offsets,
    part_encloses, margin,
):  # fmt: skip
    """:func:`plain_environment` of each viewpoint ``views[i]`` of a chunk (all in one grid cell, whose static parts
    are given, and inside no static occluder), in one call.

    Parameters
    ----------
    views : ndarray, shape (k,), int64
        Viewpoint numbers; ``frame_of_view[v]`` is the frame position of viewpoint ``v``, ``frame_starts`` the
        frames' first rows, ``target_offsets[v]`` its first target (one per object of its frame), ``in_env`` the
        holes of its environment, ``origins[v]`` and ``eyes[v]`` its grid origin and position relative to it.

    Returns
    -------
    plain : ndarray of bool, shape (k,)
    vertex_offsets, count_offsets : ndarray, shape (k + 1,), int64
    vertices, counts : ndarray
        Viewpoint ``views[i]``'s environment (where plain) is ``vertices[vertex_offsets[i]:vertex_offsets[i + 1]]``
        and ``counts[count_offsets[i]:count_offsets[i + 1]]``, as :func:`plain_environment` gives them.
    """
    k = len(views)
    plain = np.zeros(k, dtype=np.bool_)
    vertex_offsets = np.zeros(k + 1, dtype=np.int64)
    count_offsets = np.zeros(k + 1, dtype=np.int64)
    vertices = np.empty((0, 2))
    counts = np.empty(0, dtype=np.int64)
    for i in range(k):
        v = views[i]
        f = frame_of_view[v]
        s, e = frame_starts[f], frame_starts[f + 1]
        t0 = target_offsets[v]
        plain[i], found, found_counts = plain_environment(
            coords, offsets, s, e, origins[v, 0], origins[v, 1], eyes[v, 0], eyes[v, 1], in_env[t0 : t0 + e - s],
            parts, part_offsets, part_encloses, margin,
        )  # fmt: skip
        vertices = reserve_rows(vertices, vertex_offsets[i], vertex_offsets[i] + len(found))
        copy_rows(vertices, vertex_offsets[i], found)
        vertex_offsets[i + 1] = vertex_offsets[i] + len(found)
        counts = reserve(counts, count_offsets[i], count_offsets[i] + len(found_counts))
        copy_into(counts, count_offsets[i], found_counts)
        count_offsets[i + 1] = count_offsets[i] + len(found_counts)
    return plain, vertex_offsets, vertices[: vertex_offsets[k]], count_offsets, counts[: count_offsets[k]]
