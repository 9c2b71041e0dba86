"""A sensor's view limits applied to an engine's observation: which objects are in view at all
(:func:`objects_in_view`), and the visible angles and occluder lists restricted to the field of view and range
(:func:`restrict_observation`), exactly (see :mod:`..geometry.view`)."""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .._compiled.kernel import njit
from ..geometry.kernels import copy_rows
from ..geometry.occlusion import occludes_within
from ..geometry.rings import Rings, angular_extent, next_vertex
from ..geometry.view import view_intervals
from . import Observation, Viewpoint


@njit(cache=True)
def _keep_in_view(
    seg, seg_offsets, static_seg, static_offsets, ox, oy, occ_offsets, occ, st_offsets, st, start, view_offsets, lo, hi
):
    """Occluder lists filtered to bodies hit before the target along an in-view direction (exact).

    ``seg`` (grouped by ``seg_offsets``) are the objects' edges relative to the viewpoint, ``static_seg`` (grouped
    by ``static_offsets``) the static sources' edges in the world frame, the viewpoint at ``(ox, oy)``.
    """
    n = len(seg_offsets) - 1
    keep_occ = np.zeros(len(occ), dtype=np.bool_)
    keep_st = np.zeros(len(st), dtype=np.bool_)
    scratch = np.empty((16, 2, 2))
    for t in range(n):
        a, b = view_offsets[t], view_offsets[t + 1]
        if a == b:
            continue
        t0, t1 = seg_offsets[t], seg_offsets[t + 1]
        for q in range(occ_offsets[t], occ_offsets[t + 1]):
            j = occ[q]
            keep_occ[q] = occludes_within(
                0.0, 0.0, seg, seg_offsets[j], seg_offsets[j + 1], t0, t1, start[t], lo[a:b], hi[a:b]
            )
        for q in range(st_offsets[t], st_offsets[t + 1]):
            # the target's edges, then the static source's, relative to the viewpoint, side by side
            s0, s1 = static_offsets[st[q]], static_offsets[st[q] + 1]
            size = (t1 - t0) + (s1 - s0)
            if len(scratch) < size:
                scratch = np.empty((2 * size, 2, 2))
            for r in range(t1 - t0):
                copy_rows(scratch[r], 0, seg[t0 + r])
            for e in range(s0, s1):
                r = t1 - t0 + e - s0
                for p in range(2):
                    scratch[r, p, 0] = static_seg[e, p, 0] - ox
                    scratch[r, p, 1] = static_seg[e, p, 1] - oy
            keep_st[q] = occludes_within(0.0, 0.0, scratch, t1 - t0, size, 0, t1 - t0, start[t], lo[a:b], hi[a:b])
    return keep_occ, keep_st


@njit(cache=True)
def _filtered(offsets, values, keep):
    """Ragged lists ``values`` (grouped by ``offsets``) with only the entries where ``keep`` is true."""
    out = np.zeros(len(offsets), dtype=np.int64)
    for g in range(len(offsets) - 1):
        count = 0
        for q in range(offsets[g], offsets[g + 1]):
            count += keep[q]
        out[g + 1] = out[g] + count
    return out, values[keep]


class ObjectsInView(NamedTuple):
    """What of a frame's objects lies in a viewpoint's view (see :func:`objects_in_view`)."""

    start: np.ndarray
    """Angular extents' starts, radians, shape (n,)."""
    width: np.ndarray
    """Angular extents' widths, radians, shape (n,)."""
    offsets: np.ndarray
    """CSR offsets (n + 1,) of each object's in-view intervals."""
    lo: np.ndarray
    """In-view intervals' starts, radians relative to the object's ``start``."""
    hi: np.ndarray
    """In-view intervals' ends, likewise."""
    in_fov: np.ndarray
    """Radians of each extent inside the field of view, shape (n,)."""
    in_view: np.ndarray
    """Radians of in-view directions, shape (n,); 0 for objects that cannot matter to this viewpoint."""

    def out_of_view(self, transparent: np.ndarray) -> np.ndarray:
        """Objects (not ``transparent``) hit within range along no direction of the field of view: they can be
        neither seen nor in front of anything that is, so engines may leave them out (shape (n,) bool)."""
        return ~np.asarray(transparent, dtype=bool) & (self.in_view <= 0.0)


def objects_in_view(rings: Rings, viewpoint: Viewpoint) -> ObjectsInView:
    """The in-view directions (:func:`view_intervals`) of a frame's objects (world-frame ``rings``) for one
    viewpoint; transparent objects get none."""
    o = np.asarray(viewpoint.position, dtype=np.float64)
    start, width, _ = angular_extent(o, rings)
    offsets, lo, hi, in_fov, in_view = view_intervals(
        rings.coords - o,
        rings.offsets,
        ~np.asarray(viewpoint.transparent, dtype=bool),
        start,
        width,
        viewpoint.heading - 0.5 * viewpoint.fov,
        viewpoint.fov,
        viewpoint.range,
    )
    return ObjectsInView(start, width, offsets, lo, hi, in_fov, in_view)


def restrict_observation(
    observation: Observation,
    seen: ObjectsInView,
    rings: Rings,
    static_edges: np.ndarray,
    static_offsets: np.ndarray,
    viewpoint: Viewpoint,
) -> Observation:
    """An engine's observation for a limited viewpoint, with in-view angles and the occluders restricted to bodies
    hit before the target along an in-view direction; its ``visible_angle`` (already limited by the engine) is
    kept, capped at the in-view angle, and its reason codes follow from the restricted lists.

    Parameters
    ----------
    observation : Observation
        The engine's result, occluders found over the whole extent (objects out of view may have been left out).
    seen : ObjectsInView
        :func:`objects_in_view` for this viewpoint.
    rings : Rings
        The frame's object rings, metres (world frame).
    static_edges, static_offsets : ndarray
        :meth:`..statics.StaticOccluders.source_edges`.
    viewpoint : Viewpoint
    """

    o = np.asarray(viewpoint.position, dtype=np.float64)
    coords = rings.coords - o
    segments = np.ascontiguousarray(np.stack([coords, coords[next_vertex(rings.offsets)]], axis=1))
    keep_occ, keep_st = _keep_in_view(
        segments,
        np.asarray(rings.offsets, dtype=np.int64),
        static_edges,
        static_offsets,
        float(o[0]),
        float(o[1]),
        observation.occluder_offsets,
        observation.occluders,
        observation.static_offsets,
        observation.static_occluders,
        seen.start,
        seen.offsets,
        seen.lo,
        seen.hi,
    )
    occ_offsets, occ = _filtered(observation.occluder_offsets, observation.occluders, keep_occ)
    st_offsets, st = _filtered(observation.static_offsets, observation.static_occluders, keep_st)
    visible = np.minimum(observation.visible_angle, seen.in_view)
    return Observation.from_parts(
        visible,
        observation.angular_extent,
        occ_offsets,
        occ,
        st_offsets,
        st,
        viewpoint.transparent,
        seen.in_view,
        seen.in_fov,
    )
