"""The sweep engine's class: static edges and their crossings prepared once per recording, then frame by frame
the crossings with the objects (:mod:`.crossings`) and every observer through :func:`.observe.observe_frame`."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ...geometry.kernels import ring_index
from ...geometry.rings import edges, ring_ids
from ...inputs.objects import FrameObjects, ObjectTable
from ...inputs.sensors import TWO_PI
from ...inputs.statics import StaticOccluders
from .. import ChunkObservation, ChunkViewpoints, Observation, Viewpoint
from ..limits import objects_in_view, restrict_observation
from .chunk import bearing_arguments, observe_frames
from .crossings import build_static_grid, prepare_frame, static_crossings
from .observe import observe_frame, outline_one, reason_codes


class SweepEngine:
    """Exact 2D visibility by an angular sweep over front-facing edges (see :mod:`..sweep`)."""

    name = "sweep"
    measure = "radians"
    passive_targets = True  # measured against the blocking bodies' sweep (see .passive)
    chunked = True  # observe_chunk: a chunk of frames in two compiled calls

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
        self._source_edges = statics.source_edges()  # for limited viewpoints (see ...view)

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; the frame's edge crossings are found once for all of them."""
        if not viewpoints:
            return []
        transparent = np.array([v.transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1)
        seen = {k: objects_in_view(objects.rings, v) for k, v in enumerate(viewpoints) if v.limited}
        swept, limits = transparent, None  # None: all see all around, without limit
        if seen:
            swept = transparent.copy()
            for k, one in seen.items():  # objects out of a sensor's view need not be swept for it
                swept[k] |= one.out_of_view(transparent[k])
            limits = np.array([(v.heading - 0.5 * v.fov, v.fov, v.range) for v in viewpoints], dtype=np.float64)
        observations = self._observe_arrays(
            objects,
            np.array([v.position for v in viewpoints], dtype=np.float64).reshape(-1, 2),
            swept,
            np.array([v.static_transparent for v in viewpoints], dtype=bool).reshape(len(viewpoints), -1),
            limits,
            None
            if all(v.passive is None for v in viewpoints)
            else np.array([_passive(v.passive, len(objects)) for v in viewpoints]).reshape(swept.shape),
        )
        for k, one in seen.items():
            view = viewpoints[k]
            observations[k] = restrict_observation(observations[k], one, objects.rings, *self._source_edges, view)
        return observations

    def observe_chunk(self, objects: ObjectTable, viewpoints: ChunkViewpoints) -> ChunkObservation:
        """What every viewpoint of a chunk of frames sees, all around without range, in two compiled calls (see
        :mod:`.chunk`); the numbers of :meth:`observe` frame by frame."""
        coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
        offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
        frame_starts = np.ascontiguousarray(objects.frame_starts, dtype=np.int64)
        positions = np.ascontiguousarray(viewpoints.position, dtype=np.float64).reshape(-1, 2)
        view_starts = np.ascontiguousarray(viewpoints.frame_starts, dtype=np.int64)
        following, cross_offsets, cross_first, cross_second, arg_offsets, y, x = bearing_arguments(
            coords, offsets, frame_starts, view_starts, positions, self._st_a, self._st_b, *self._grid, *self._ss
        )
        out = observe_frames(
            coords,
            offsets,
            frame_starts,
            view_starts,
            positions,
            np.ascontiguousarray(viewpoints.target_offsets, dtype=np.int64),
            np.ascontiguousarray(viewpoints.transparent, dtype=np.bool_),
            _passive(viewpoints.passive, len(viewpoints.transparent)),
            np.ascontiguousarray(viewpoints.static_offsets, dtype=np.int64),
            np.ascontiguousarray(viewpoints.static_inside, dtype=np.int64),
            self.statics.n_sources,
            following,
            cross_offsets,
            cross_first,
            cross_second,
            arg_offsets,
            np.arctan2(y, x),
            self._static_edges,
            self._grid,
        )
        return ChunkObservation(*out)

    def _frame_inputs(self, objects: FrameObjects, observers: np.ndarray) -> tuple:
        """The kernels' per-frame inputs: the frame's edge arrays (a tuple of :class:`.pieces.FrameEdges`' fields)
        and every observer's bearings."""
        coords = np.ascontiguousarray(objects.rings.coords, dtype=np.float64)
        offsets = np.ascontiguousarray(objects.rings.offsets, dtype=np.int64)
        grid_f, grid_i, cell_off, items = self._grid
        nxt, ci, cj, y, x = prepare_frame(
            observers, coords, offsets, self._st_a, self._st_b, grid_f, grid_i, cell_off, items, *self._ss
        )
        return (coords, offsets, nxt, ring_index(offsets), ci, cj), np.arctan2(y, x)

    def _observe_arrays(
        self,
        objects: FrameObjects,
        observers: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
        limits: np.ndarray | None = None,
        passive: np.ndarray | None = None,
    ) -> list[Observation]:
        observers = np.ascontiguousarray(observers, dtype=np.float64).reshape(-1, 2)
        if passive is None:
            passive = np.zeros(np.shape(transparent), dtype=np.bool_)
        if limits is None:  # every observer sees all around, without limit
            limits = np.empty((len(observers), 3))
            limits[:] = (0.0, TWO_PI, np.inf)
        frame_arrays, ang = self._frame_inputs(objects, observers)
        out = observe_frame(
            observers,
            frame_arrays,
            self._static_edges,
            self._grid,
            ang,
            np.ascontiguousarray(transparent, dtype=bool).reshape(len(observers), -1),
            np.ascontiguousarray(passive, dtype=bool).reshape(len(observers), -1),
            np.ascontiguousarray(static_transparent, dtype=bool).reshape(len(observers), -1),
            np.ascontiguousarray(limits, dtype=np.float64).reshape(len(observers), 3),
        )
        visible, width, occ_off, occ, occ_cut, st_off, st, st_cut = out
        reason = reason_codes(occ_off, st_off, transparent)
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

    def visible_outline(
        self, objects: FrameObjects, viewpoint: Viewpoint, radius: float, arc_step: float
    ) -> np.ndarray:
        """Vertices (world frame, metres, counter-clockwise) of the region the viewpoint sees within its field of
        view and within ``radius`` metres (the viewpoint's range, or a bound when it has none); arcs of the
        circle are drawn as chords every ``arc_step`` radians (see :mod:`.outline`)."""
        position = np.ascontiguousarray(viewpoint.position, dtype=np.float64).reshape(1, 2)
        frame_arrays, ang = self._frame_inputs(objects, position)
        outline = outline_one(
            float(position[0, 0]),
            float(position[0, 1]),
            frame_arrays,
            self._static_edges,
            self._grid,
            ang[0],
            np.ascontiguousarray(viewpoint.transparent, dtype=bool),
            np.ascontiguousarray(viewpoint.static_transparent, dtype=bool),
            viewpoint.heading - 0.5 * viewpoint.fov,
            viewpoint.fov,
            float(radius),
            float(arc_step),
        )
        return outline + position


def _passive(passive: np.ndarray | None, n: int) -> np.ndarray:
    """The passive targets' flags as the kernels take them (None: none of the ``n``)."""
    return np.zeros(n, dtype=np.bool_) if passive is None else np.ascontiguousarray(passive, dtype=np.bool_)
