"""Frame-level preparation for the sweep engine: edge crossings between bodies, found without all-pairs tests.

Objects against objects: sort-and-sweep of bounding boxes along the axis of larger spread. Objects against static
edges: a uniform grid of the static edges, built once per recording. Static against static: once, at construction.
Pairs of edges of *different* bodies that cross properly are returned; the sweep cuts its bearing intervals there.
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import (
    MIN_CAPACITY,
    copy_into,
    cross_properly,
    next_vertex_index,
    prefix_sum,
    push_pair,
    reserve,
)
from ...geometry.sorting import argsort_stable, unique_values

GRID_CELLS = 256  # cells along the longer side of the static edges' grid


# -- crossings ---------------------------------------------------------------------------------------------


@njit(cache=True)
def build_static_grid(a, b):
    """Uniform grid over segments ab: (x0, y0, cell) floats, (nx, ny) ints, CSR cell offsets and items."""
    s = len(a)
    x0 = min(a[:, 0].min(), b[:, 0].min())
    y0 = min(a[:, 1].min(), b[:, 1].min())
    x1 = max(a[:, 0].max(), b[:, 0].max())
    y1 = max(a[:, 1].max(), b[:, 1].max())
    cell = max(max(x1 - x0, y1 - y0) / GRID_CELLS, 1e-6)
    nx = int((x1 - x0) / cell) + 1
    ny = int((y1 - y0) / cell) + 1
    counts = np.zeros(nx * ny + 1, dtype=np.int64)
    for rep in range(2):
        if rep == 1:
            prefix_sum(counts)
            fill = counts[:-1].copy()
            items = np.empty(counts[-1], dtype=np.int64)
        for k in range(s):
            cx0, cx1, cy0, cy1 = _cell_range(
                min(a[k, 0], b[k, 0]), min(a[k, 1], b[k, 1]), max(a[k, 0], b[k, 0]), max(a[k, 1], b[k, 1]),
                x0, y0, cell, nx, ny,
            )  # fmt: skip
            for cy in range(cy0, cy1 + 1):
                for cx in range(cx0, cx1 + 1):
                    c = cy * nx + cx
                    if rep == 0:
                        counts[c + 1] += 1
                    else:
                        items[fill[c]] = k
                        fill[c] += 1
    return np.array([x0, y0, cell]), np.array([nx, ny], dtype=np.int64), counts, items


@njit(cache=True)
def _cell_range(xmin, ymin, xmax, ymax, x0, y0, cell, nx, ny):
    """Grid cells (column range ``cx0..cx1``, row range ``cy0..cy1``, inclusive) covered by a bounding box.

    The box ``[xmin, xmax] x [ymin, ymax]`` and the grid's corner ``(x0, y0)`` and ``cell`` size are in metres; the
    grid has ``nx`` columns and ``ny`` rows; cells outside it are clamped to its border.
    """
    cx0 = min(max(int((xmin - x0) / cell), 0), nx - 1)
    cx1 = min(max(int((xmax - x0) / cell), 0), nx - 1)
    cy0 = min(max(int((ymin - y0) / cell), 0), ny - 1)
    cy1 = min(max(int((ymax - y0) / cell), 0), ny - 1)
    return cx0, cx1, cy0, cy1


@njit(cache=True)
def statics_near(grid_f, grid_i, cell_off, items, ox, oy, radius, n_static):
    """Numbers of the static edges that may come within ``radius`` metres of ``(ox, oy)``, ascending: those
    registered in the grid cells the disk's bounding box touches (all of them when that is most of the grid or
    the radius is infinite)."""
    if n_static == 0:
        return np.zeros(0, dtype=np.int64)
    x0, y0, cell = grid_f[0], grid_f[1], grid_f[2]
    nx, ny = grid_i[0], grid_i[1]
    if not math.isfinite(radius):
        return np.arange(n_static)
    cx0, cx1, cy0, cy1 = _cell_range(ox - radius, oy - radius, ox + radius, oy + radius, x0, y0, cell, nx, ny)
    if 4 * (cx1 - cx0 + 1) * (cy1 - cy0 + 1) > nx * ny:
        return np.arange(n_static)
    total = 0
    for cy in range(cy0, cy1 + 1):
        total += cell_off[cy * nx + cx1 + 1] - cell_off[cy * nx + cx0]
    found = np.empty(total, dtype=np.int64)
    k = 0
    for cy in range(cy0, cy1 + 1):
        a, b = cell_off[cy * nx + cx0], cell_off[cy * nx + cx1 + 1]
        copy_into(found, k, items[a:b])
        k += b - a
    return unique_values(found)


@njit(cache=True)
def static_crossings(a, b, group, grid_f, grid_i, cell_off, items):
    """Pairs (i < j) of static edges of different groups that cross properly."""
    x0, y0, cell = grid_f[0], grid_f[1], grid_f[2]
    nx, ny = grid_i[0], grid_i[1]
    stamp = np.full(len(a), -1, dtype=np.int64)
    first = np.empty(MIN_CAPACITY, dtype=np.int64)
    second = np.empty(MIN_CAPACITY, dtype=np.int64)
    k = 0
    for i in range(len(a)):
        xmin, xmax = min(a[i, 0], b[i, 0]), max(a[i, 0], b[i, 0])
        ymin, ymax = min(a[i, 1], b[i, 1]), max(a[i, 1], b[i, 1])
        cx0, cx1, cy0, cy1 = _cell_range(xmin, ymin, xmax, ymax, x0, y0, cell, nx, ny)
        for cy in range(cy0, cy1 + 1):
            for cx in range(cx0, cx1 + 1):
                c = cy * nx + cx
                for q in range(cell_off[c], cell_off[c + 1]):
                    j = items[q]
                    if j <= i or stamp[j] == i or group[j] == group[i]:
                        continue
                    stamp[j] = i
                    if cross_properly(a[i, 0], a[i, 1], b[i, 0], b[i, 1], a[j, 0], a[j, 1], b[j, 0], b[j, 1]):
                        first, second, k = push_pair(first, second, k, i, j)
    return first[:k].copy(), second[:k].copy()


@njit(cache=True)
def _object_crossings_into(coords, offsets, nxt, bbox, order, axis, state, first, second):
    """The sort-and-sweep of :func:`frame_crossings` over the objects' bounding boxes ``bbox`` (n, 4) sorted by
    their lower bound along ``axis`` (``order``), writing the crossing edge pairs to ``first, second``.

    Resumes at ``state`` (position in ``order``, partner's position or -1 for the next, pairs written) and stops,
    returning False with ``state`` updated, before a pair of objects whose crossings might not fit; True when done.
    """
    n = len(offsets) - 1
    other = 1 - axis
    ii, resume, k = state[0], state[1], state[2]
    while ii < n:
        i = order[ii]
        jj = resume if resume >= 0 else ii + 1
        resume = -1
        while jj < n:
            j = order[jj]
            if bbox[j, axis] > bbox[i, axis + 2]:
                break
            if not (bbox[j, other] > bbox[i, other + 2] or bbox[j, other + 2] < bbox[i, other]):
                if k + (offsets[i + 1] - offsets[i]) * (offsets[j + 1] - offsets[j]) > len(first):
                    state[0], state[1], state[2] = ii, jj, k
                    return False
                for p in range(offsets[i], offsets[i + 1]):
                    pa, pb = p, nxt[p]
                    for q in range(offsets[j], offsets[j + 1]):
                        qa, qb = q, nxt[q]
                        if cross_properly(
                            coords[pa, 0], coords[pa, 1], coords[pb, 0], coords[pb, 1],
                            coords[qa, 0], coords[qa, 1], coords[qb, 0], coords[qb, 1],
                        ):  # fmt: skip
                            first[k] = p
                            second[k] = q
                            k += 1
            jj += 1
        ii += 1
    state[0], state[1], state[2] = ii, -1, k
    return True


@njit(cache=True)
def _static_crossings_into(
    coords, offsets, nxt, bbox, st_a, st_b, grid_f, grid_i, cell_off, items, stamp, state, first, second
):  # fmt: skip
    """The objects (bounding boxes ``bbox`` (n, 4)) against the static edges ``st_a, st_b`` through their grid, for
    :func:`frame_crossings`, writing the crossing edge pairs (object edge, ``m`` + static edge) to ``first,
    second``; ``stamp`` (s,) marks the static edges tried for the current object.

    Resumes at ``state`` (object, pairs written) and stops, returning False with ``state[2]`` the room its next
    object may need, before an object whose crossings might not fit; True when done.
    """
    n = len(offsets) - 1
    m = len(coords)
    x0, y0, cell = grid_f[0], grid_f[1], grid_f[2]
    nx, ny = grid_i[0], grid_i[1]
    gx1, gy1 = x0 + nx * cell, y0 + ny * cell
    i, k = state[0], state[1]
    while i < n:
        if bbox[i, 2] < x0 or bbox[i, 0] > gx1 or bbox[i, 3] < y0 or bbox[i, 1] > gy1:
            i += 1
            continue
        cx0, cx1, cy0, cy1 = _cell_range(bbox[i, 0], bbox[i, 1], bbox[i, 2], bbox[i, 3], x0, y0, cell, nx, ny)
        room = 0  # at most every edge against every static edge registered in its cells
        for cy in range(cy0, cy1 + 1):
            room += cell_off[cy * nx + cx1 + 1] - cell_off[cy * nx + cx0]
        room *= offsets[i + 1] - offsets[i]
        if k + room > len(first):
            state[0], state[1], state[2] = i, k, room
            return False
        for cy in range(cy0, cy1 + 1):
            for cx in range(cx0, cx1 + 1):
                c = cy * nx + cx
                for w in range(cell_off[c], cell_off[c + 1]):
                    t = items[w]
                    if stamp[t] == i:
                        continue
                    stamp[t] = i
                    if (
                        max(st_a[t, 0], st_b[t, 0]) < bbox[i, 0]
                        or min(st_a[t, 0], st_b[t, 0]) > bbox[i, 2]
                        or max(st_a[t, 1], st_b[t, 1]) < bbox[i, 1]
                        or min(st_a[t, 1], st_b[t, 1]) > bbox[i, 3]
                    ):
                        continue
                    for p in range(offsets[i], offsets[i + 1]):
                        pb = nxt[p]
                        if cross_properly(
                            coords[p, 0], coords[p, 1], coords[pb, 0], coords[pb, 1],
                            st_a[t, 0], st_a[t, 1], st_b[t, 0], st_b[t, 1],
                        ):  # fmt: skip
                            first[k] = p
                            second[k] = m + t
                            k += 1
        i += 1
    state[0], state[1] = i, k
    return True


@njit(cache=True)
def frame_crossings(coords, offsets, nxt, st_a, st_b, grid_f, grid_i, cell_off, items, static_first, static_second):
    """Properly crossing edge pairs of different bodies in one frame.

    Edges are numbered object edges first (``0..m-1``), then static edges (``m + k``).
    """
    n = len(offsets) - 1
    m = len(coords)
    bbox = np.empty((n, 4))  # xmin, ymin, xmax, ymax
    for i in range(n):
        x0, y0 = np.inf, np.inf
        x1, y1 = -np.inf, -np.inf
        for v in range(offsets[i], offsets[i + 1]):
            x0, x1 = min(x0, coords[v, 0]), max(x1, coords[v, 0])
            y0, y1 = min(y0, coords[v, 1]), max(y1, coords[v, 1])
        bbox[i, 0], bbox[i, 1], bbox[i, 2], bbox[i, 3] = x0, y0, x1, y1
    first = np.empty(max(MIN_CAPACITY, m), dtype=np.int64)
    second = np.empty(max(MIN_CAPACITY, m), dtype=np.int64)
    k = 0
    if n > 1:
        # sort-and-sweep along the axis where the bodies are spread most
        spread_x = bbox[:, 2].max() - bbox[:, 0].min()
        spread_y = bbox[:, 3].max() - bbox[:, 1].min()
        axis = 0 if spread_x >= spread_y else 1
        order = argsort_stable(bbox[:, axis].copy())
        state = np.array([0, -1, 0], dtype=np.int64)
        # the buffers grow between calls, not inside the sweep: arrays rebound in a loop cost reference counting on
        # every pass
        while not _object_crossings_into(coords, offsets, nxt, bbox, order, axis, state, first, second):
            first = reserve(first, state[2], len(first) + 1)
            second = reserve(second, state[2], len(second) + 1)
        k = state[2]
    if len(st_a):
        stamp = np.full(len(st_a), -1, dtype=np.int64)
        state = np.array([0, k, 0], dtype=np.int64)
        while not _static_crossings_into(
            coords, offsets, nxt, bbox, st_a, st_b, grid_f, grid_i, cell_off, items, stamp, state, first, second
        ):
            first = reserve(first, state[1], state[1] + state[2])
            second = reserve(second, state[1], state[1] + state[2])
        k = state[1]
    total = k + len(static_first)
    cross_first = np.empty(total, dtype=np.int64)
    cross_second = np.empty(total, dtype=np.int64)
    copy_into(cross_first, 0, first[:k])
    copy_into(cross_second, 0, second[:k])
    for r in range(len(static_first)):
        cross_first[k + r] = m + static_first[r]
        cross_second[k + r] = m + static_second[r]
    return cross_first, cross_second


@njit(cache=True)
def prepare_frame(observers, coords, offsets, st_a, st_b, grid_f, grid_i, cell_off, items, static_first, static_second):
    """Frame-level work and the arctangent arguments of every observer (evaluated by numpy's ``arctan2``).

    Parameters
    ----------
    observers : ndarray, shape (k, 2)
        Metres.
    coords, offsets
        The frame's ragged object rings, ``m`` vertices (metres).
    st_a, st_b : ndarray, shape (s, 2)
        Static edges, metres; ``grid_f, grid_i, cell_off, items`` their grid (:func:`build_static_grid`) and
        ``static_first, static_second`` their crossings (:func:`static_crossings`).

    Returns
    -------
    nxt : ndarray, shape (m,), int64
        Following vertex of each vertex's ring: edge ``j`` runs from vertex ``j`` to ``nxt[j]``.
    cross_first, cross_second : ndarray, shape (c,), int64
        Properly crossing pairs of edges of different bodies (object edges ``0..m-1``, then static edges ``m + k``).
    y, x : ndarray, shape (k, 2 m)
        Row ``o``: the cross and dot products of consecutive vertices (``angular_extent``'s steps) for the ``m``
        object edges, then the shifted vertex coordinates (vertex bearings), as seen from observer ``o``.
    """
    m = len(coords)
    nxt = next_vertex_index(offsets)
    cross_first, cross_second = frame_crossings(
        coords, offsets, nxt, st_a, st_b, grid_f, grid_i, cell_off, items, static_first, static_second
    )
    k = len(observers)
    y = np.empty(k * 2 * m)
    x = np.empty(k * 2 * m)
    for o in range(k):
        bearing_arguments_into(y, x, o * 2 * m, coords, nxt, observers[o, 0], observers[o, 1])
    return nxt, cross_first, cross_second, y.reshape(k, 2 * m), x.reshape(k, 2 * m)


@njit(cache=True, inline="always")
def bearing_arguments_into(y, x, at, coords, nxt, ox, oy):
    """Write one observer's arctangent arguments (see :func:`prepare_frame`) to ``y[at:at + 2 m]`` and
    ``x[at:at + 2 m]``: for the ``m`` edges the cross and dot products of their end points, then every vertex
    shifted to the observer ``(ox, oy)`` (metres)."""
    m = len(coords)
    for j in range(m):
        ax, ay = coords[j, 0] - ox, coords[j, 1] - oy
        bx, by = coords[nxt[j], 0] - ox, coords[nxt[j], 1] - oy
        y[at + j] = ax * by - ay * bx
        x[at + j] = ax * bx + ay * by
        y[at + m + j] = ay
        x[at + m + j] = ax
