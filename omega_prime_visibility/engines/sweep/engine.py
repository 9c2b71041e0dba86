"""The sweep engine's class: static edges and their crossings prepared once per recording, then frame by frame
the crossings with the objects (:mod:`.crossings`) and every observer through :func:`.observe.observe_frame`."""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np

from ...geometry import edges, ring_ids
from ...kernels import ring_index
from ...scene import FrameObjects
from ...statics import StaticOccluders
from .. import Observation, Reason, Viewpoint
from .crossings import build_static_grid, prepare_frame, static_crossings
from .observe import observe_frame

_IN_VIEW, _OCCLUDED, _CONTAINS_OBSERVER = int(Reason.IN_VIEW), int(Reason.OCCLUDED), int(Reason.CONTAINS_OBSERVER)


@numba.njit(cache=True)
def _reason_codes_stacked(occ_offsets, static_offsets, transparent):
    """The :class:`..Reason` code of every (observer, object), as :meth:`..Observation.from_parts` gives them one
    observer at a time: offsets shape (k, n + 1), ``transparent`` (k, n); shape (k, n), int8."""
    k, n = transparent.shape
    reason = np.empty((k, n), dtype=np.int8)
    for o in range(k):
        for i in range(n):
            if transparent[o, i]:
                reason[o, i] = _CONTAINS_OBSERVER
            elif occ_offsets[o, i + 1] > occ_offsets[o, i] or static_offsets[o, i + 1] > static_offsets[o, i]:
                reason[o, i] = _OCCLUDED
            else:
                reason[o, i] = _IN_VIEW
    return reason


class SweepEngine:
    """Exact 2D visibility by an angular sweep over front-facing edges (see :mod:`..sweep`)."""

    name = "sweep"
    measure = "radians"

    def __init__(self, statics: StaticOccluders) -> None:
        self.statics = statics
        n_src = statics.n_sources
        # static edges for the sweep: ring edges (one-sided) then wall segments (two-sided)
        ra, rb = edges(statics.rings)
        ring_src = statics.ring_source[ring_ids(statics.rings.offsets)].astype(np.int64)
        walls = np.asarray(statics.segments, dtype=np.float64).reshape(-1, 2, 2)
        self._st_a = np.ascontiguousarray(np.concatenate([ra, walls[:, 0]]), dtype=np.float64).reshape(-1, 2)
        self._st_b = np.ascontiguousarray(np.concatenate([rb, walls[:, 1]]), dtype=np.float64).reshape(-1, 2)
        self._st_src = np.concatenate([ring_src, statics.segment_source]).astype(np.int64)
        self._st_two = np.concatenate([np.zeros(len(ra), dtype=bool), np.ones(len(walls), dtype=bool)])
        # crossing groups: a static polygon's edges never cross each other, a wall's segments may
        group = np.concatenate([ring_src, n_src + np.arange(len(walls), dtype=np.int64)])
        if len(self._st_a):
            self._grid = build_static_grid(self._st_a, self._st_b)
            self._ss = static_crossings(self._st_a, self._st_b, group, *self._grid)
        else:
            self._grid = (np.zeros(3), np.ones(2, dtype=np.int64), np.zeros(2, dtype=np.int64), np.zeros(0, np.int64))
            self._ss = (np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64))
        self._static_edges = (self._st_a, self._st_b, self._st_src, self._st_two)  # StaticEdges' fields

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; the frame's edge crossings are found once for all of them."""
        if not viewpoints:
            return []
        return self._observe_arrays(
            objects,
            np.array([v.position for v in viewpoints], dtype=np.float64).reshape(-1, 2),
            np.array([v.transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1),
            np.array([v.static_transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1),
        )

    def _observe_arrays(
        self,
        objects: FrameObjects,
        observers: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> list[Observation]:
        observers = np.ascontiguousarray(observers, dtype=np.float64).reshape(-1, 2)
        coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
        offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
        grid_f, grid_i, cell_off, items = self._grid
        nxt, ci, cj, y, x = prepare_frame(
            observers, coords, offsets, self._st_a, self._st_b, grid_f, grid_i, cell_off, items, *self._ss
        )
        ang = np.arctan2(y, x)
        out = observe_frame(
            observers,
            (coords, offsets, nxt, ring_index(offsets), ci, cj),
            self._static_edges,
            ang,
            np.ascontiguousarray(transparent, dtype=bool).reshape(len(observers), -1),
            np.ascontiguousarray(static_transparent, dtype=bool).reshape(len(observers), -1),
        )
        visible, width, occ_off, occ, occ_cut, st_off, st, st_cut = out
        reason = _reason_codes_stacked(occ_off, st_off, transparent)
        occ_cut, st_cut = occ_cut.tolist(), st_cut.tolist()
        return [
            Observation(
                visible[k],
                width[k],
                reason[k],
                occ_off[k],
                occ[occ_cut[k] : occ_cut[k + 1]],
                st_off[k],
                st[st_cut[k] : st_cut[k + 1]],
            )
            for k in range(len(observers))
        ]
