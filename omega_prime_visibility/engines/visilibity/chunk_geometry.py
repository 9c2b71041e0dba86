"""Each viewpoint's geometry over a chunk of frames, in compiled loops: its targets' angular extents and the
edges of all bodies relative to its origin (for :mod:`.chunk`).

The angular extents are :func:`...geometry.angular_extent`'s operations in its order, with numpy's ``arctan2`` and
``mod`` applied to all viewpoints' arguments at once: the numbers are those of the frame-by-frame path to the bit.
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import TWO_PI


def angular_extents(coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes):
    """Every target's angular extent ``(start, width)``, radians (see :func:`...geometry.angular_extent`); the
    arguments as :func:`extent_arguments` takes them."""
    arg_offsets, y, x, first_y, first_x = extent_arguments(
        coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes
    )
    lo, hi = extent_bounds(np.arctan2(y, x), offsets, frame_starts, view_starts, target_offsets, arg_offsets)
    return np.mod(np.arctan2(first_y, first_x) + lo + np.pi, TWO_PI) - np.pi, hi - lo


@njit(cache=True)
def extent_arguments(coords, offsets, frame_starts, view_starts, target_offsets, origins, eyes):
    """The arctangent arguments of :func:`...geometry.angular_extent` for every viewpoint of a chunk.

    Parameters
    ----------
    coords, offsets : ndarray
        The chunk's rings (one per row, metres, world frame).
    frame_starts, view_starts : ndarray, shape (f + 1,), int64
        First row and first viewpoint of each frame.
    target_offsets : ndarray, shape (v + 1,), int64
        First target of each viewpoint (one per object of its frame).
    origins, eyes : ndarray, shape (v, 2)
        Each viewpoint's grid origin, and the viewpoint relative to it, metres.

    Returns
    -------
    arg_offsets : ndarray, shape (v + 1,), int64
    y, x : ndarray, float64
        Per vertex of the viewpoint's frame, the turn from the vertex to its ring's next one: viewpoint ``v``'s are
        ``[arg_offsets[v]:arg_offsets[v + 1]]``.
    first_y, first_x : ndarray, shape (t,)
        Per target, its ring's first vertex relative to the viewpoint.
    """
    n_views = len(eyes)
    arg_offsets = np.zeros(n_views + 1, dtype=np.int64)
    for f in range(len(frame_starts) - 1):
        m = offsets[frame_starts[f + 1]] - offsets[frame_starts[f]]
        for v in range(view_starts[f], view_starts[f + 1]):
            arg_offsets[v + 1] = arg_offsets[v] + m
    y = np.empty(arg_offsets[-1])
    x = np.empty(arg_offsets[-1])
    first_y = np.empty(target_offsets[-1])
    first_x = np.empty(target_offsets[-1])
    for f in range(len(frame_starts) - 1):
        s, e = frame_starts[f], frame_starts[f + 1]
        for v in range(view_starts[f], view_starts[f + 1]):
            gx, gy, ox, oy = origins[v, 0], origins[v, 1], eyes[v, 0], eyes[v, 1]
            k = arg_offsets[v]
            for r in range(s, e):
                a0, a1 = offsets[r], offsets[r + 1]
                for q in range(a0, a1):
                    nq = q + 1 if q + 1 < a1 else a0
                    # (vertex - origin) - eye, as the frame path subtracts them
                    ax, ay = (coords[q, 0] - gx) - ox, (coords[q, 1] - gy) - oy
                    bx, by = (coords[nq, 0] - gx) - ox, (coords[nq, 1] - gy) - oy
                    y[k] = ax * by - ay * bx
                    x[k] = ax * bx + ay * by
                    k += 1
                t = target_offsets[v] + r - s
                first_x[t] = (coords[a0, 0] - gx) - ox
                first_y[t] = (coords[a0, 1] - gy) - oy
    return arg_offsets, y, x, first_y, first_x


@njit(cache=True)
def extent_bounds(step, offsets, frame_starts, view_starts, target_offsets, arg_offsets):
    """Per target, the least and greatest unwrapped bearing of its ring relative to its first vertex (radians,
    0 included), from the turns ``step`` summed over the viewpoint's frame in order (numpy's ``cumsum``)."""
    lo = np.empty(target_offsets[-1])
    hi = np.empty(target_offsets[-1])
    for f in range(len(frame_starts) - 1):
        s, e = frame_starts[f], frame_starts[f + 1]
        for v in range(view_starts[f], view_starts[f + 1]):
            k = arg_offsets[v]
            cum = 0.0
            for r in range(s, e):
                base = cum
                least, most = np.inf, -np.inf
                for _ in range(offsets[r], offsets[r + 1]):
                    cum += step[k]
                    k += 1
                    rel = cum - base
                    least = least if least <= rel else rel
                    most = most if most >= rel else rel
                t = target_offsets[v] + r - s
                lo[t] = least if least <= 0.0 else 0.0
                hi[t] = most if most >= 0.0 else 0.0
    return lo, hi


@njit(cache=True)
def view_segments(coords, offsets, s, e, gx, gy, st_seg, st_source, n_sources):
    """The frame's object edges then the static edges, relative to the origin ``(gx, gy)``, with their body
    numbers (objects ``0 .. n - 1``, then ``n + source``) and per-body offsets."""
    n = e - s
    m_obj = offsets[e] - offsets[s]
    seg = np.empty((m_obj + len(st_seg), 2, 2))
    body = np.empty(m_obj + len(st_seg), dtype=np.int64)
    k = 0
    for r in range(s, e):
        a0, a1 = offsets[r], offsets[r + 1]
        for q in range(a0, a1):
            nq = q + 1 if q + 1 < a1 else a0
            seg[k, 0, 0], seg[k, 0, 1] = coords[q, 0] - gx, coords[q, 1] - gy
            seg[k, 1, 0], seg[k, 1, 1] = coords[nq, 0] - gx, coords[nq, 1] - gy
            body[k] = r - s
            k += 1
    for i in range(len(st_seg)):
        for p in range(2):
            seg[k, p, 0], seg[k, p, 1] = st_seg[i, p, 0] - gx, st_seg[i, p, 1] - gy
        body[k] = n + st_source[i]
        k += 1
    seg_offsets = np.zeros(n + n_sources + 1, dtype=np.int64)
    for j in range(len(body)):
        seg_offsets[body[j] + 1] += 1
    for b in range(n + n_sources):
        seg_offsets[b + 1] += seg_offsets[b]
    return seg, body, seg_offsets


@njit(cache=True)
def static_blocking(static_offsets, static_inside, v, n_sources):
    """Static sources that block viewpoint ``v`` (all but those containing it)."""
    blocking = np.ones(n_sources, dtype=np.bool_)
    for q in range(static_offsets[v], static_offsets[v + 1]):
        blocking[static_inside[q]] = False
    return blocking
