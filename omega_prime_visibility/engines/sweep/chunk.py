"""A chunk of frames through the sweep in two compiled calls, for viewpoints that see all around without range.

Frame by frame, Python around the kernel (slicing the frame, building its viewpoints, packing the rows) costs
more than the sweep itself on small scenes, so a chunk goes through :func:`bearing_arguments` (every frame's
edge crossings and the arctangent arguments of all its viewpoints), numpy's ``arctan2`` over all of them at once
(the bearings must come from numpy's ``arctan2``, as frame by frame, so that the numbers are the same to the
bit), and :func:`observe_frames` (:func:`.observe.observe_one` for each viewpoint, the results written as CSR over
the chunk's targets). The numbers are those of :meth:`.SweepEngine.observe` frame by frame.
"""

from __future__ import annotations

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import copy_into, next_vertex_index, reserve
from ...inputs.sensors import TWO_PI
from .. import reason_of
from .crossings import bearing_arguments_into, frame_crossings
from .observe import observe_one
from .pieces import FrameEdges, StaticEdges


@njit(cache=True)
def bearing_arguments(
    coords, offsets, frame_starts, view_starts, positions, st_a, st_b, grid_f, grid_i, cell_off, items, ss_a, ss_b
):
    """What :func:`.crossings.prepare_frame` gives, for every frame of a chunk that has viewpoints.

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
            nxt = next_vertex_index(local)
            first, second = frame_crossings(
                frame_coords, local, nxt, st_a, st_b, grid_f, grid_i, cell_off, items, ss_a, ss_b
            )
            copy_into(following, offsets[s] - offsets[0], nxt)
            cross_first = reserve(cross_first, n_cross, n_cross + len(first))
            cross_second = reserve(cross_second, n_cross, n_cross + len(first))
            copy_into(cross_first, n_cross, first)
            copy_into(cross_second, n_cross, second)
            n_cross += len(first)
            for o in range(v0, v1):  # what prepare_frame gives, written in place
                bearing_arguments_into(y, x, arg_offsets[o], frame_coords, nxt, positions[o, 0], positions[o, 1])
        cross_offsets[f + 1] = n_cross
    return following, cross_offsets, cross_first[:n_cross], cross_second[:n_cross], arg_offsets, y, x


@njit(cache=True)
def observe_frames(
    coords,
    offsets,
    frame_starts,
    view_starts,
    positions,
    target_offsets,
    transparent,
    passive,
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
    """:func:`.observe.observe_one` for every viewpoint of a chunk (arguments as :func:`bearing_arguments` takes
    and returns them, ``ang`` the bearings of ``y, x``; ``transparent`` and ``passive`` per target,
    ``static_inside`` CSR per viewpoint by ``static_offsets``), every viewpoint seeing all around without range; what
    :func:`.observe.observe_frame` and :func:`.observe.reason_codes` give frame by frame, written straight into
    the chunk's arrays.

    Returns
    -------
    visible, width : ndarray, shape (t,)
    reason : ndarray, shape (t,), int8
    occ_offsets, occ, st_offsets, st : ndarray, int64
        CSR over the targets (see :class:`..ChunkObservation`).
    """
    statics = StaticEdges(*static_arrays)
    n_frames = len(frame_starts) - 1
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
    # each frame's ring offsets and ring numbers counted from its own first row, for all frames at once
    local_offsets = np.empty(len(offsets) - 1 + n_frames, dtype=np.int64)
    ring = np.empty(offsets[-1] - offsets[0], dtype=np.int64)
    for f in range(n_frames):
        s, e = frame_starts[f], frame_starts[f + 1]
        for r in range(s, e + 1):
            local_offsets[r + f] = offsets[r] - offsets[s]
        for r in range(s, e):
            ring[offsets[r] - offsets[0] : offsets[r + 1] - offsets[0]] = r - s
    static_transparent = np.zeros(n_sources, dtype=np.bool_)
    for f in range(n_frames):
        v0, v1 = view_starts[f], view_starts[f + 1]
        if v1 == v0:
            continue
        s, e = frame_starts[f], frame_starts[f + 1]
        n = e - s
        vs, ve = offsets[s] - offsets[0], offsets[e] - offsets[0]
        c0, c1 = cross_offsets[f], cross_offsets[f + 1]
        # slices of C-contiguous arrays along their first axis stay C-contiguous: no copies
        frame = FrameEdges(
            coords[offsets[s] : offsets[e]],
            local_offsets[s + f : e + f + 1],
            following[vs:ve],
            ring[vs:ve],
            cross_first[c0:c1],
            cross_second[c0:c1],
        )
        for o in range(v0, v1):
            for q in range(static_offsets[o], static_offsets[o + 1]):
                static_transparent[static_inside[q]] = True
            t0 = target_offsets[o]
            object_transparent = transparent[t0 : t0 + n]
            one_visible, one_width, one_occ_offsets, one_occ, one_st_offsets, one_st = observe_one(
                positions[o, 0], positions[o, 1], frame, statics, static_grid, ang[arg_offsets[o] : arg_offsets[o + 1]],
                object_transparent, passive[t0 : t0 + n], static_transparent, 0.0, TWO_PI, np.inf,
            )  # fmt: skip
            for q in range(static_offsets[o], static_offsets[o + 1]):
                static_transparent[static_inside[q]] = False
            occ = reserve(occ, n_occ, n_occ + len(one_occ))
            st = reserve(st, n_st, n_st + len(one_st))
            copy_into(occ, n_occ, one_occ)
            copy_into(st, n_st, one_st)
            for i in range(n):
                visible[t0 + i] = one_visible[i]
                width[t0 + i] = one_width[i]
                occ_offsets[t0 + i + 1] = n_occ + one_occ_offsets[i + 1]
                st_offsets[t0 + i + 1] = n_st + one_st_offsets[i + 1]
                reason[t0 + i] = reason_of(
                    object_transparent[i],
                    one_occ_offsets[i + 1] - one_occ_offsets[i],
                    one_st_offsets[i + 1] - one_st_offsets[i],
                )
            n_occ += len(one_occ)
            n_st += len(one_st)
    return visible, width, reason, occ_offsets, occ[:n_occ], st_offsets, st[:n_st]
