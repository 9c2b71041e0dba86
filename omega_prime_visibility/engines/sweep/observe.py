"""One frame of the sweep: every observer of the frame, each through steps 1 to 4.

:func:`observe_frame` runs :func:`observe_one` for each observer and packs the ragged occluder lists; the steps
themselves live in :mod:`.pieces` (1, 2), :mod:`.heap_sweep` (3) and :mod:`.occluders` (4).
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...geometry.kernels import copy_into
from .. import reason_of
from .crossings import statics_near
from .heap_sweep import visible_angles
from .occluders import ObjectsSeen, occluders
from .outline import visible_outline
from .passive import passive_angles
from .pieces import (
    FrameEdges,
    StaticEdges,
    crossing_cuts,
    cut_pieces,
    front_facing_edges,
    object_distances,
    object_extents,
    shifted_object_edges,
)


@njit(cache=True)
def observe_one(
    ox, oy, frame, statics, static_grid, ang, object_transparent, object_passive, static_transparent, wedge_start, fov,
    max_range,
):  # fmt: skip
    """What the observer at ``(ox, oy)`` (metres) sees of every object of the frame.

    Parameters
    ----------
    frame : FrameEdges
    statics : StaticEdges
    static_grid : tuple
        :func:`.crossings.build_static_grid` of the static edges.
    ang : ndarray, shape (2 m,)
        This observer's bearings (see :func:`.pieces.object_extents`), radians.
    object_transparent : ndarray of bool, shape (n,)
    object_passive : ndarray of bool, shape (n,)
        Targets that neither block nor occlude, each measured against the others that may (see :mod:`.passive`).
    static_transparent : ndarray of bool, shape (n_sources,)
    wedge_start, fov, max_range : float
        The field of view ``[wedge_start, wedge_start + fov]`` (radians) and the range (metres).

    Returns
    -------
    visible : ndarray, shape (n,)
        Radians along which each object is the first thing hit, within the field of view and range.
    width : ndarray, shape (n,)
        Radians of each object's angular extent.
    occ_offsets, occ, st_offsets, st : ndarray, int64
        Occluding objects and static sources of each object (see :func:`.occluders.occluders`).
    """
    offsets = frame.offsets
    n = len(offsets) - 1
    n_src = len(static_transparent)
    seg = shifted_object_edges(frame.coords, frame.following, ox, oy)
    start, width = object_extents(offsets, ang)
    near, far, reach2 = object_distances(seg, offsets, object_transparent)
    reach2 = min(reach2, max_range * max_range * (1.0 + 1e-9))  # static edges beyond range hide nothing in it
    candidates = statics_near(*static_grid, ox, oy, math.sqrt(reach2), len(statics.start))

    # 1. front-facing edges; 2. their bearing records cut into pieces
    kept, record_edge, records = front_facing_edges(
        seg, ang, frame, statics, object_transparent, static_transparent, ox, oy, reach2, candidates
    )
    cut_offsets, cuts = crossing_cuts(kept, record_edge, records, frame.cross_first, frame.cross_second)
    pieces, body = cut_pieces(kept, record_edge, records, cut_offsets, cuts)

    # 3. the sweep
    if object_passive.any():
        visible = passive_angles(pieces, body, object_passive, n + n_src, wedge_start, fov, max_range)[:n].copy()
    else:
        visible = visible_angles(pieces, body, n + n_src, wedge_start, fov, max_range)[:n].copy()

    # 4. occluders
    objects = ObjectsSeen(seg, offsets, object_transparent, object_passive, start, width, near, far)
    occ_offsets, occ, st_offsets, st = occluders(objects, n_src, kept, record_edge, records, statics, ox, oy)
    return visible, width, occ_offsets, occ, st_offsets, st


@njit(cache=True)
def observe_frame(
    observers, frame_arrays, static_arrays, static_grid, ang, transparent, passive, static_transparent, limits
):
    """:func:`observe_one` for each of the ``k`` observers (shape (k, 2), metres) of one frame.

    ``frame_arrays`` and ``static_arrays`` are plain tuples of the :class:`FrameEdges` and :class:`StaticEdges`
    fields (the named tuples are built here: handing named tuples in from Python costs a type inference per
    call). ``ang`` (k, 2 m), ``transparent`` and ``passive`` (k, n) and ``static_transparent`` (k, n_sources)
    hold one row per observer; ``limits`` (k, 3) each observer's wedge start and field of view (radians) and range
    (metres).

    Returns
    -------
    visible, width : ndarray, shape (k, n)
    occ_offsets : ndarray, shape (k, n + 1), int64
    occ : ndarray, int64
        Observer ``o``'s occluder lists are ``occ[occ_cut[o]:occ_cut[o + 1]]``, indexed by ``occ_offsets[o]``.
    occ_cut : ndarray, shape (k + 1,), int64
    st_offsets, st, st_cut
        Likewise for the static occluders.
    """
    frame = FrameEdges(*frame_arrays)
    statics = StaticEdges(*static_arrays)
    k = len(observers)
    n = len(frame.offsets) - 1
    visible = np.empty((k, n))
    width = np.empty((k, n))
    occ_offsets = np.empty((k, n + 1), dtype=np.int64)
    st_offsets = np.empty((k, n + 1), dtype=np.int64)
    occ_cut = np.zeros(k + 1, dtype=np.int64)
    st_cut = np.zeros(k + 1, dtype=np.int64)
    occ_parts = []
    st_parts = []
    for o in range(k):
        one_visible, one_width, one_occ_offsets, occ, one_st_offsets, st = observe_one(
            observers[o, 0],
            observers[o, 1],
            frame,
            statics,
            static_grid,
            ang[o],
            transparent[o],
            passive[o],
            static_transparent[o],
            limits[o, 0],
            limits[o, 1],
            limits[o, 2],
        )
        copy_into(visible[o], 0, one_visible)
        copy_into(width[o], 0, one_width)
        copy_into(occ_offsets[o], 0, one_occ_offsets)
        copy_into(st_offsets[o], 0, one_st_offsets)
        occ_cut[o + 1] = occ_cut[o] + len(occ)
        st_cut[o + 1] = st_cut[o] + len(st)
        occ_parts.append(occ)
        st_parts.append(st)
    occ_all = np.empty(occ_cut[k], dtype=np.int64)
    st_all = np.empty(st_cut[k], dtype=np.int64)
    for o in range(k):
        copy_into(occ_all, occ_cut[o], occ_parts[o])
        copy_into(st_all, st_cut[o], st_parts[o])
    return visible, width, occ_offsets, occ_all, occ_cut, st_offsets, st_all, st_cut


@njit(cache=True)
def outline_one(
    ox, oy, frame, statics, static_grid, ang, object_transparent, static_transparent, wedge_start, fov, radius, step
):
    """Steps 1 to 3 for the observer at ``(ox, oy)``, then the outline of the region it sees within ``radius``
    metres (see :func:`.outline.visible_outline`; ``frame`` and ``statics`` as plain tuples of the named tuples'
    fields), relative to the observer."""
    frame = FrameEdges(*frame)
    statics = StaticEdges(*statics)
    seg = shifted_object_edges(frame.coords, frame.following, ox, oy)
    reach2 = radius * radius * (1.0 + 1e-9)  # static edges beyond the radius are not seen
    candidates = statics_near(*static_grid, ox, oy, radius, len(statics.start))
    kept, record_edge, records = front_facing_edges(
        seg, ang, frame, statics, object_transparent, static_transparent, ox, oy, reach2, candidates
    )
    cut_offsets, cuts = crossing_cuts(kept, record_edge, records, frame.cross_first, frame.cross_second)
    pieces, _ = cut_pieces(kept, record_edge, records, cut_offsets, cuts)
    return visible_outline(pieces, wedge_start, fov, radius, step)


@njit(cache=True)
def reason_codes(occ_offsets, static_offsets, transparent):
    """The :class:`..Reason` code of every (observer, object), as :meth:`..Observation.from_parts` gives them one
    observer at a time: offsets shape (k, n + 1), ``transparent`` (k, n); shape (k, n), int8."""
    k, n = transparent.shape
    reason = np.empty((k, n), dtype=np.int8)
    for o in range(k):
        for i in range(n):
            reason[o, i] = reason_of(
                transparent[o, i],
                occ_offsets[o, i + 1] - occ_offsets[o, i],
                static_offsets[o, i + 1] - static_offsets[o, i],
            )
    return reason
