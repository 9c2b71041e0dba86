"""A chunk of frames through the sweep in two compiled calls, for viewpoints that see all around without range.

Frame by frame, Python around the kernel (slicing the frame, building its viewpoints, packing the rows) costs
more than the sweep itself on small scenes, so a chunk goes through :func:`bearing_arguments` (every frame's
edge crossings and the arctangent arguments of all its viewpoints), numpy's ``arctan2`` over all of them at once
(the bearings must come from numpy's ``arctan2``, as frame by frame, so that the numbers are the same to the
bit), and :func:`observe_frames` (:func:`.observe.observe_frame` on each frame, the results packed as CSR over
the chunk's targets). The numbers are those of :meth:`.SweepEngine.observe` frame by frame.
"""

from __future__ import annotations

import numba
import numpy as np

from ...kernels import reserve, ring_index
from ...sensors import TWO_PI
from .crossings import prepare_frame
from .observe import observe_frame, reason_codes


@numba.njit(cache=True)
def bearing_arguments(
    coords, offsets, frame_starts, view_starts, positions, st_a, st_b, grid_f, grid_i, cell_off, items, ss_a, ss_b
):
    """:func:`.crossings.prepare_frame` for every frame of a chunk that has viewpoints.

    Parameters
    ----------
    coords, offsets : ndarray
        The chunk's ragged object rings (one per row, metres).
    frame_starts : ndarray, shape (f + 1,), int64
        First row of each frame.
    view_starts : ndarray, shape (f + 1,), int64
        First viewpoint of each frame; ``positions`` (shape (v, 2), metres) holds them.
    st_a, st_b, grid_f, grid_i, cell_off, items, ss_a, ss_b
        The static edges, their grid and crossings (see :func:`.crossings.prepare_frame`).

    Returns
    -------
    following : ndarray, shape (m,), int64
        Following vertex of each vertex's ring, numbered within its frame.
    cross_offsets : ndarray, shape (f + 1,), int64
    cross_first, cross_second : ndarray, int64
        Frame ``f``'s crossing pairs are ``[cross_offsets[f]:cross_offsets[f + 1]]`` (frame-local numbering).
    arg_offsets : ndarray, shape (v + 1,), int64
    y, x : ndarray, float64
        Viewpoint ``o``'s arctangent arguments (shape (2 m_f,) for its frame's ``m_f`` vertices) are
        ``[arg_offsets[o]:arg_offsets[o + 1]]``.
    """
    n_frames = len(frame_starts) - 1
    following = np.zeros(offsets[-1] - offsets[0], dtype=np.int64)
    cross_offsets = np.zeros(n_frames + 1, dtype=np.int64)
    cross_first = np.empty(0, dtype=np.int64)
    cross_second = np.empty(0, dtype=np.int64)
    arg_offsets = np.zeros(len(positions) + 1, dtype=np.int64)
    for f in range(n_frames):
        v0, v1 = view_starts[f], view_starts[f + 1]
        for o in range(v0, v1):
            arg_offsets[o + 1] = arg_offsets[o] + 2 * (offsets[frame_starts[f + 1]] - offsets[frame_starts[f]])
    y = np.empty(arg_offsets[-1])
    x = np.empty(arg_offsets[-1])
    n_cross = 0
    for f in range(n_frames):
        v0, v1 = view_starts[f], view_starts[f + 1]
        if v1 > v0:
            s, e = frame_starts[f], frame_starts[f + 1]
            local = offsets[s : e + 1] - offsets[s]
            frame_coords = coords[offsets[s] : offsets[e]]
            nxt, first, second, fy, fx = prepare_frame(
                positions[v0:v1], frame_coords, local, st_a, st_b, grid_f, grid_i, cell_off,
                items, ss_a, ss_b,
            )  # fmt: skip
            following[offsets[s] - offsets[0] : offsets[e] - offsets[0]] = nxt
            cross_first = reserve(cross_first, n_cross, n_cross + len(first))
            cross_second = reserve(cross_second, n_cross, n_cross + len(first))
            cross_first[n_cross : n_cross + len(first)] = first
            cross_second[n_cross : n_cross + len(first)] = second
            n_cross += len(first)
            y[arg_offsets[v0] : arg_offsets[v1]] = fy.ravel()
            x[arg_offsets[v0] : arg_offsets[v1]] = fx.ravel()
        cross_offsets[f + 1] = n_cross
    return following, cross_offsets, cross_first[:n_cross], cross_second[:n_cross], arg_offsets, y, x


@numba.njit(cache=True)
def observe_frames(
    coords,
    offsets,
    frame_starts,
    view_starts,
    positions,
    target_offsets,
    transparent,
    static_offsets,
    static_inside,
    n_sources,
    following,
    cross_offsets,
    cross_first,
    cross_second,
    arg_offsets,
    ang,
    static_arrays,
    static_grid,
):
    """:func:`.observe.observe_frame` for every frame of a chunk (arguments as :func:`bearing_arguments` takes and
    returns them, ``ang`` the bearings of ``y, x``; ``transparent`` per target, ``static_inside`` CSR per viewpoint
    by ``static_offsets``), every viewpoint seeing all around without range.

    Returns
    -------
    visible, width : ndarray, shape (t,)
    reason : ndarray, shape (t,), int8
    occ_offsets, occ, st_offsets, st : ndarray, int64
        CSR over the targets (see :class:`..ChunkObservation`).
    """
    n_targets = target_offsets[-1]
    visible = np.empty(n_targets)
    width = np.empty(n_targets)
    reason = np.empty(n_targets, dtype=np.int8)
    occ_offsets = np.zeros(n_targets + 1, dtype=np.int64)
    st_offsets = np.zeros(n_targets + 1, dtype=np.int64)
    occ = np.empty(0, dtype=np.int64)
    st = np.empty(0, dtype=np.int64)
    n_occ = 0
    n_st = 0
    for f in range(len(frame_starts) - 1):
        v0, v1 = view_starts[f], view_starts[f + 1]
        if v1 == v0:
            continue
        k = v1 - v0
        s, e = frame_starts[f], frame_starts[f + 1]
        n = e - s
        local = offsets[s : e + 1] - offsets[s]
        m = local[-1]
        vs = offsets[s] - offsets[0]
        c0, c1 = cross_offsets[f], cross_offsets[f + 1]
        # slices of C-contiguous arrays along their first axis stay C-contiguous: no copies
        frame_arrays = (
            coords[offsets[s] : offsets[e]],
            local,
            following[vs : vs + m],
            ring_index(local),
            cross_first[c0:c1],
            cross_second[c0:c1],
        )
        frame_ang = ang[arg_offsets[v0] : arg_offsets[v1]].reshape(k, 2 * m)
        frame_transparent = transparent[target_offsets[v0] : target_offsets[v1]].reshape(k, n)
        frame_static = np.zeros((k, n_sources), dtype=np.bool_)
        for o in range(k):
            for q in range(static_offsets[v0 + o], static_offsets[v0 + o + 1]):
                frame_static[o, static_inside[q]] = True
        limits = np.empty((k, 3))
        for o in range(k):
            limits[o, 0], limits[o, 1], limits[o, 2] = 0.0, TWO_PI, np.inf
        out = observe_frame(
            positions[v0:v1],
            frame_arrays,
            static_arrays,
            static_grid,
            frame_ang,
            frame_transparent,
            frame_static,
            limits,
        )
        f_visible, f_width, f_occ_offsets, f_occ, f_occ_cut, f_st_offsets, f_st, f_st_cut = out
        f_reason = reason_codes(f_occ_offsets, f_st_offsets, frame_transparent)
        occ = reserve(occ, n_occ, n_occ + len(f_occ))
        st = reserve(st, n_st, n_st + len(f_st))
        occ[n_occ : n_occ + len(f_occ)] = f_occ
        st[n_st : n_st + len(f_st)] = f_st
        for o in range(k):
            t0 = target_offsets[v0 + o]
            for i in range(n):
                visible[t0 + i] = f_visible[o, i]
                width[t0 + i] = f_width[o, i]
                reason[t0 + i] = f_reason[o, i]
                occ_offsets[t0 + i + 1] = n_occ + f_occ_cut[o] + f_occ_offsets[o, i + 1]
                st_offsets[t0 + i + 1] = n_st + f_st_cut[o] + f_st_offsets[o, i + 1]
        n_occ += len(f_occ)
        n_st += len(f_st)
    return visible, width, reason, occ_offsets, occ[:n_occ], st_offsets, st[:n_st]
