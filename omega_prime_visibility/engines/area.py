"""The area measure (``measure="area"``): the share of a target's footprint that lies in no other body's shadow,
inside the field of view and range, by exact polygon clipping (:mod:`..geometry.shadows`), as openPASS's
SensorGeometric2D measures it. Frames of convex bodies without static occluders (boxes, nearly every recording)
take a compiled path with the same numbers (:mod:`.area_pieces`).

It keeps the engine contract with areas for angles: ``visible_angle`` is the visible area, ``angular_extent`` the
footprint's area, ``in_view_angle`` and ``in_fov_angle`` the areas inside the field of view and range, and inside
the field of view (square metres). An occluder is a body whose shadow covers a positive area of the target (more
than :data:`MIN_HIDDEN` of it) inside the field of view and range.

The two measures differ where a target is seen at a slant: a long truck seen end-on covers a small angle, but
most of its footprint lies in its own shadow only, so a car in front of its nose hides much of the angle and
little of the area.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import shapely

from ..geometry.rings import ring_ids
from ..geometry.shadows import disc_area, wall_shadow, wedge
from ..geometry.shadows import shadows as cast_shadows
from ..geometry.spans import angular_spans, overlapping
from ..inputs.objects import FrameObjects
from ..inputs.sensors import TWO_PI
from ..inputs.statics import StaticOccluders
from . import Observation, Viewpoint, group_pairs
from .area_pieces import convex_frame_areas

MIN_HIDDEN = 1e-9
"""Share of a target's area a body must hide to be listed as an occluder (below it: rounding of the clipping)."""


class AreaEngine:
    """Exact 2D area visibility by polygon clipping (see the module docstring)."""

    name = "area"
    measure = "square metres"
    passive_targets = False
    chunked = False
    compiled = True
    """Whether frames without static occluders take the compiled path (:mod:`.area_pieces`); the general path
    (polygon clipping) takes them when False, as the tests compare."""

    def __init__(self, statics: StaticOccluders) -> None:
        self.statics = statics
        self._edges, self._edge_offsets = statics.source_edges()

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One observation per viewpoint (areas in square metres)."""
        return [self._observe_one(objects, view) for view in viewpoints]

    def _observe_one(self, objects: FrameObjects, view: Viewpoint) -> Observation:
        if not self.statics.n_sources and self.compiled:
            fast = self._observe_convex(objects, view)
            if fast is not None:
                return fast
        n = len(objects)
        origin = np.asarray(view.position, dtype=np.float64)
        coords = objects.rings.coords - origin
        polygons = shapely.polygons(shapely.linearrings(coords, indices=ring_ids(objects.rings.offsets)))
        area = shapely.area(polygons)
        active = ~np.asarray(view.transparent, dtype=bool)
        centre, half, near, far, reach = _spans_and_reach(_shifted(objects, origin), active)
        limited = view.limited
        seen = polygons
        if view.fov < TWO_PI:
            seen = shapely.intersection(polygons, wedge(view.heading, view.fov, reach))
        in_fov = _snapped(shapely.area(seen), area)
        in_view = in_fov.copy()
        if math.isfinite(view.range):
            cut = far > view.range  # only targets reaching beyond the range lose area to it
            in_view[cut] = [disc_area(g, view.range) for g in seen[cut]]
        # pairs (target, body) where the body may be in front of the target
        t, b = np.nonzero(
            active[:, None]
            & active[None, :]
            & ~np.eye(n, dtype=bool)
            & overlapping(centre[:, None], half[:, None], centre[None, :], half[None, :])
            & (near[None, :] <= far[:, None] * (1 + 1e-9) + 1e-9)
            & (in_view > 0)[:, None]
        )
        shadows = np.empty(n, dtype=object)
        casting = np.unique(b)
        shifted = _shifted(objects, origin)
        shadows[casting] = cast_shadows(shifted, casting, centre[casting], half[casting], reach)
        st_t, st_s, static_shadows = self._static_pairs(origin, view, reach, seen, active & (in_view > 0))
        # what each body hides (inside the field of view and range): listed when it is more than rounding
        hidden = _areas(shapely.intersection(seen[t], shadows[b]), view.range)
        listed = hidden > MIN_HIDDEN * area[t]
        st_hidden = _areas(shapely.intersection(seen[st_t], static_shadows[st_s]), view.range)
        st_listed = st_hidden > MIN_HIDDEN * area[st_t]
        # what is left: the part in view minus every shadow that may fall on it
        left = seen.copy()
        for targets, regions in ((t, shadows[b]), (st_t, static_shadows[st_s])):
            for k in _rounds(targets):
                left[targets[k]] = shapely.difference(left[targets[k]], regions[k])
        visible = np.where(active, _snapped(_areas(left, view.range), in_view), 0.0)
        occ_offsets, occ = group_pairs(t[listed], b[listed], n)
        st_offsets, st = group_pairs(st_t[st_listed], st_s[st_listed], n)
        return Observation.from_parts(
            visible,
            area,
            occ_offsets,
            occ,
            st_offsets,
            st,
            view.transparent,
            in_view if limited else None,
            in_fov if limited else None,
        )

    def _observe_convex(self, objects: FrameObjects, view: Viewpoint) -> Observation | None:
        """The compiled path (:mod:`.area_pieces`) for a frame without static occluders; None where a body is
        not convex or a target does not fit its buffers."""
        n = len(objects)
        origin = np.asarray(view.position, dtype=np.float64)
        shifted = _shifted(objects, origin)
        active = ~np.asarray(view.transparent, dtype=bool)
        centre, half, near, far, reach = _spans_and_reach(shifted, active)
        area, in_fov, in_view, visible, occ_offsets, occ, fitted = convex_frame_areas(
            np.ascontiguousarray(shifted.coords), shifted.offsets.astype(np.int64), active, centre, half, near, far,
            reach, float(view.range), float(view.heading), min(float(view.fov), TWO_PI), MIN_HIDDEN,
        )  # fmt: skip
        if not fitted:
            return None
        in_fov = _snapped(in_fov, area)
        in_view = np.minimum(_snapped(in_view, in_fov), in_fov)
        visible = np.where(active, _snapped(visible, in_view), 0.0)
        limited = view.limited
        return Observation.from_parts(
            visible, area, occ_offsets, occ, np.zeros(n + 1, np.int64), np.zeros(0, np.int64), view.transparent,
            in_view if limited else None, in_fov if limited else None,
        )  # fmt: skip

    def _static_pairs(
        self, origin: np.ndarray, view: Viewpoint, reach: float, seen: np.ndarray, targets: np.ndarray
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(target, static source) pairs whose source's shadow meets the target's part in view, and the shadows."""
        statics = self.statics
        empty = np.zeros(0, dtype=np.int64)
        if not statics.n_sources or not targets.any():
            return empty, empty, np.empty(0, dtype=object)
        bounds = statics.bounds - np.r_[origin, origin]
        gap = np.hypot(
            np.maximum(0, np.maximum(bounds[:, 0], -bounds[:, 2])),
            np.maximum(0, np.maximum(bounds[:, 1], -bounds[:, 3])),
        )
        near_sources = np.flatnonzero((gap <= reach) & ~np.asarray(view.static_transparent, dtype=bool))
        regions = np.empty(statics.n_sources, dtype=object)
        for s in near_sources.tolist():
            edges = self._edges[self._edge_offsets[s] : self._edge_offsets[s + 1]] - origin
            parts = [wall_shadow(edges, reach), shapely.transform(statics.geometries[s], lambda xy: xy - origin)]
            regions[s] = shapely.union_all(parts)
        t = np.flatnonzero(targets)
        tt, ss = np.repeat(t, len(near_sources)), np.tile(near_sources, len(t))
        meets = shapely.intersects(seen[tt], regions[ss]) if len(tt) else np.zeros(0, dtype=bool)
        return tt[meets], ss[meets], regions


def _shifted(objects: FrameObjects, origin: np.ndarray):
    """The objects' rings relative to ``origin``."""
    return type(objects.rings)(objects.rings.coords - origin, objects.rings.offsets)


def _spans_and_reach(shifted, active: np.ndarray):
    """The bodies' spans from the viewpoint (:func:`..geometry.spans.angular_spans` of rings relative to it) and
    how far regions must reach (metres): beyond the farthest active body."""
    n = len(shifted)
    centre, half, near, far = angular_spans(np.zeros((n, 2)), shifted, np.arange(n))
    reach = 1.01 * float(far[active].max()) + 1.0 if active.any() else 1.0
    return centre, half, near, far, reach


def _snapped(part: np.ndarray, whole: np.ndarray) -> np.ndarray:
    """``part``, set to ``whole`` where it falls short of it by rounding only (a relative 1e-12), so that a target
    wholly in view reads exactly 1."""
    return np.where(part >= whole * (1 - 1e-12), whole, part)


def _areas(geometries: np.ndarray, radius: float) -> np.ndarray:
    """Area of each geometry inside the range circle (all of it without range), square metres."""
    if not math.isfinite(radius):
        return shapely.area(geometries) if len(geometries) else np.zeros(0)
    return np.array([disc_area(g, radius) for g in geometries], dtype=np.float64)


def _rounds(targets: np.ndarray) -> list[np.ndarray]:
    """Positions into ``targets`` split into rounds in which every target occurs at most once (so that one
    vectorised difference per round applies every region to its target)."""
    if not len(targets):
        return []
    order = np.argsort(targets, kind="stable")
    sorted_targets = targets[order]
    first = np.r_[0, np.flatnonzero(np.diff(sorted_targets)) + 1]
    rank = np.arange(len(targets)) - np.repeat(first, np.diff(np.r_[first, len(targets)]))
    return [order[rank == k] for k in range(int(rank.max()) + 1)]
