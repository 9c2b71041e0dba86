"""The VisiLibity engine: environment per frame, checked visibility polygon, attribution (see the package
docstring for the steps)."""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import shapely

from ...geometry.occlusion import occluding_pairs
from ...geometry.rings import Rings, angular_extent, edges, ring_ids
from ...inputs.objects import FrameObjects, ObjectTable
from ...inputs.statics import StaticOccluders, polygonal_and_lineal_parts
from .. import ChunkObservation, ChunkViewpoints, EngineFailure, Observation, Viewpoint, group_pairs
from ..limits import objects_in_view, restrict_observation
from .attribution import attribute_visible_angles
from .chunk import observe_chunk
from .conversion import (
    Environment,
    box_overlaps,
    components,
    exterior_cw,
    grid_origin,
    vis_polygon,
    vis_polygons_reversed,
    visibility_polygon_coords,
)
from .polygon_check import CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE, polygon_fails

BOX_MARGIN = 10.0  # metres of free space around everything
# why a frame fails when the viewpoint is in no body but within a wall's 2 * wall_half_width or a touch_gap
_INSIDE_THICKNESS = "the viewpoint lies within VisiLibity's thickened walls or joined bodies"


class _Unenclosable(Exception):
    """The fast environment does not apply (the observer is enclosed by a group of bodies)."""


class VisiLibityEngine:
    """Exact 2D visibility with VisiLibity1 (see module docstring).

    Parameters
    ----------
    statics : StaticOccluders
    epsilon : float
        VisiLibity's snapping distance, metres.
    wall_half_width : float
        Half thickness, metres, given to LineString walls (VisiLibity needs areas).
    touch_gap : float
        Buffer, metres, that joins bodies touching at a single point (only applied where that happens).
    """

    name = "visilibity"
    measure = "radians"
    passive_targets = False
    chunked = True  # observe_chunk: a chunk of frames in compiled loops around VisiLibity's calls

    def __init__(
        self,
        statics: StaticOccluders,
        epsilon: float = 1e-9,
        wall_half_width: float = 1e-8,
        touch_gap: float = 1e-7,
    ) -> None:
        self.statics = statics
        self.epsilon = epsilon
        self.touch_gap = touch_gap
        self.wall_half_width = wall_half_width
        self._origin: np.ndarray | None = None
        self._prepared: dict[tuple[float, float], dict] = {}
        self.box_margin = BOX_MARGIN  # metres of free space around all bodies (the visibility polygon's limit)
        self._source_edges = statics.source_edges()  # every static edge grouped by source, world frame

    # -- static geometry, converted once relative to the origin ------------------------------------------------
    def _use_origin(self, observer: np.ndarray) -> np.ndarray:
        """Switch to the origin of the grid cell holding ``observer`` (results then depend on the observer's
        position only, never on which frames were processed before); return it."""
        origin = grid_origin(observer)
        if self._origin is None or not np.array_equal(origin, self._origin):
            key = (float(origin[0]), float(origin[1]))
            if key not in self._prepared:
                self._prepare_statics(origin)
                self._prepared[key] = {k: getattr(self, k) for k in self._STATE}
            self.__dict__.update(self._prepared[key])
        return self._origin

    def _area_of(self, geometry: shapely.Geometry) -> shapely.Geometry:
        """A static occluder as an area: its polygons, and its lines thickened to ``2 * wall_half_width``."""
        polygons, lines = polygonal_and_lineal_parts(geometry)
        walls = [
            shapely.buffer(line, self.wall_half_width, cap_style="flat", join_style="mitre", mitre_limit=10.0)
            for line in lines
        ]
        return polygons[0] if len(polygons) == 1 and not walls else shapely.union_all([*polygons, *walls])

    _STATE = ("_origin", "_static_shapes", "_static_segments", "_static_segment_source", "_static_cache")

    def _prepare_statics(self, origin: np.ndarray) -> None:
        st = self.statics
        self._origin = origin.copy()
        shifted = shapely.transform(st.geometries, lambda c: c - origin) if st.n_sources else st.geometries
        self._static_shapes = np.array([*map(self._area_of, shifted), None], dtype=object)[:-1]
        seg, offsets = self._source_edges
        self._static_segments = np.ascontiguousarray(seg - origin)
        self._static_segment_source = np.repeat(np.arange(st.n_sources, dtype=np.int64), np.diff(offsets))
        self._static_cache: dict[bytes, tuple] = {}

    def _static_parts(self, static_blocking: np.ndarray) -> tuple:
        """Merged static parts for this set of blocking sources: shapely parts, their boxes, VisiLibity holes."""
        key = np.packbits(static_blocking).tobytes()
        if key not in self._static_cache:
            shapes = self._static_shapes[static_blocking]
            parts = []
            if len(shapes):
                merged = shapely.union_all(shapes)
                parts = list(getattr(merged, "geoms", [merged]))
                if len(parts) > 1 and self._touching(parts):
                    merged = shapely.buffer(merged, self.touch_gap, join_style="mitre")
                    parts = list(getattr(merged, "geoms", [merged]))
            parts_arr = np.array([*parts, None], dtype=object)[:-1]
            bounds = shapely.bounds(parts_arr).reshape(-1, 4) if parts else np.zeros((0, 4))
            holes = [vis_polygon(exterior_cw(p)) for p in parts]
            enclosing = [k for k, p in enumerate(parts) if len(p.interiors)]
            self._static_cache[key] = (parts_arr, bounds, holes, enclosing)
        return self._static_cache[key]

    @staticmethod
    def _touching(parts: list[shapely.Polygon]) -> bool:
        """Whether disjoint parts share a vertex (touch at a point); every ring repeats its first vertex once."""
        coords = np.concatenate([shapely.get_coordinates(p) for p in parts])
        closing = sum(1 + len(p.interiors) for p in parts)
        return len(np.unique(coords, axis=0)) < len(coords) - closing

    # -- one observer ------------------------------------------------------------------------------------------
    def _frame_geometry(self, objects: FrameObjects) -> tuple[Rings, np.ndarray, np.ndarray]:
        """Object rings relative to the origin, and the edges of all bodies (objects, then static sources)."""
        n = len(objects)
        rings = Rings(objects.rings.coords - self._origin, objects.rings.offsets)
        a, b = edges(rings)
        segments = np.concatenate([np.stack([a, b], axis=1), self._static_segments])
        seg_body = np.concatenate([ring_ids(rings.offsets), n + self._static_segment_source])
        seg_offsets = np.zeros(n + self.statics.n_sources + 1, dtype=np.int64)
        np.cumsum(np.bincount(seg_body, minlength=n + self.statics.n_sources), out=seg_offsets[1:])
        return rings, segments, seg_offsets

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint (see :mod:`..engines`)."""
        return [self._observe_one(objects, viewpoint) for viewpoint in viewpoints]

    def observe_chunk(self, objects: ObjectTable, viewpoints: ChunkViewpoints) -> ChunkObservation:
        """What every viewpoint of a chunk of frames sees, all around without range, with compiled loops around
        VisiLibity's calls (see :mod:`.chunk`); the numbers of :meth:`observe` frame by frame."""
        return observe_chunk(self, objects, viewpoints)

    def _observe_one(self, objects: FrameObjects, viewpoint: Viewpoint) -> Observation:
        observer = np.asarray(viewpoint.position, dtype=np.float64)
        transparent, static_transparent = viewpoint.transparent, viewpoint.static_transparent
        seen = objects_in_view(objects.rings, viewpoint) if viewpoint.limited else None
        if seen is not None:  # objects out of the sensor's view change nothing for it
            transparent = transparent | seen.out_of_view(transparent)
        origin = self._use_origin(observer)
        n = len(objects)
        o = observer - origin
        rings, segments, seg_offsets = self._frame_geometry(objects)
        obj_blocking = ~np.asarray(transparent, dtype=bool)
        static_blocking = ~np.asarray(static_transparent, dtype=bool)
        blocking = np.concatenate([obj_blocking, static_blocking])

        start, width, _ = angular_extent(o, rings)
        targets = np.flatnonzero(obj_blocking)
        body, target, hidden = occluding_pairs(o, segments, seg_offsets, blocking, targets, start, width, n)
        is_obj = body < n
        occ_offsets, occ = group_pairs(target[is_obj], body[is_obj], n)
        st_offsets, st = group_pairs(target[~is_obj], body[~is_obj] - n, n)
        if blocking.any():
            # objects hidden behind a single nearer object change nothing in the visibility polygon: leave them out
            in_env = obj_blocking & ~hidden[:n]
            pts = self._checked_points(rings, in_env, static_blocking, o, segments, seg_offsets)
            seg = np.ascontiguousarray(segments - o)
            view = (viewpoint.heading - 0.5 * viewpoint.fov, viewpoint.fov, viewpoint.range)
            occluders = (occ_offsets, occ, st_offsets, st)
            # a target hidden behind a single nearer object sees nothing (none of its edges is first along any ray)
            unhidden = np.flatnonzero(in_env)
            extents = (start, width, ON_EDGE)
            visible = attribute_visible_angles(pts, seg, seg_offsets, unhidden, *extents, *occluders, *view)
        else:
            visible = width.copy()
        observation = Observation.from_parts(visible, width, occ_offsets, occ, st_offsets, st, transparent)
        if viewpoint.limited:
            observation = restrict_observation(observation, seen, objects.rings, *self._source_edges, viewpoint)
        return observation

    def _checked_points(
        self,
        rings: Rings,
        obj_blocking: np.ndarray,
        static_blocking: np.ndarray,
        o: np.ndarray,
        segments: np.ndarray,
        seg_offsets: np.ndarray,
    ) -> np.ndarray:
        """Vertices of the visibility polygon relative to ``o``, checked to lie on the nearest body everywhere.

        VisiLibity's sweep can skip a nearer body (see :mod:`.polygon_check`); such a polygon is computed again
        from smaller groups of holes (:meth:`_region_by_parts`).
        """
        polys = self._build_environment(rings, obj_blocking, static_blocking, o)
        in_env = np.repeat(np.concatenate([obj_blocking, static_blocking]), np.diff(seg_offsets))
        seg = np.ascontiguousarray(segments - o)
        pts = self._polygon_points(polys, o) - o
        if polygon_fails(pts, seg, in_env, CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE):
            holes = [h - o for h in polys[1:]]
            if any(shapely.intersects(shapely.Polygon(hole), shapely.Point(0.0, 0.0)) for hole in holes):
                raise EngineFailure(_INSIDE_THICKNESS)
            region = shapely.orient_polygons(self._region_by_parts(polys[0], polys[1:], holes, o), exterior_cw=False)
            pts = np.ascontiguousarray(shapely.get_coordinates(region.exterior)[:-1])
            if polygon_fails(pts, seg, in_env, CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE):
                raise EngineFailure(
                    "VisiLibity's visibility polygon misses the nearest body, even computed body by body"
                )
        return pts

    def _region_by_parts(
        self, outer: np.ndarray, holes: list[np.ndarray], hole_coords: list[np.ndarray], o: np.ndarray
    ) -> shapely.Polygon:
        """The visibility polygon (relative to ``o``) as the intersection of those of two halves of the holes.

        A point is visible among holes A and B iff it is visible among A and among B, so the region seen among
        all holes is the intersection of the two regions. Each half's polygon is checked against its own holes
        and split again while it fails; the halves are split by bearing, which separates the edges that share
        VisiLibity's queue.
        """
        pts = self._polygon_points([outer, *holes], o) - o
        edges_of = [np.stack([c, np.roll(c, -1, axis=0)], axis=1) for c in hole_coords]
        seg = np.ascontiguousarray(np.concatenate(edges_of)) if edges_of else np.zeros((0, 2, 2))
        if not polygon_fails(pts, seg, np.ones(len(seg), dtype=bool), CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE):
            return shapely.Polygon(pts)
        if len(holes) < 2:
            raise EngineFailure("VisiLibity's visibility polygon misses the nearest body, with one hole")
        centres = np.array([c.mean(axis=0) for c in hole_coords])
        order = np.argsort(np.arctan2(centres[:, 1], centres[:, 0]))
        parts = [order[: len(order) // 2], order[len(order) // 2 :]]
        first, second = (
            self._region_by_parts(outer, [holes[k] for k in part], [hole_coords[k] for k in part], o) for part in parts
        )
        region = shapely.intersection(first, second)
        # rounding can leave specks beside the star-shaped region around the observer: keep the piece holding it
        for piece in getattr(region, "geoms", [region]):
            if shapely.intersects(piece, shapely.Point(0.0, 0.0)):
                return piece
        raise EngineFailure("VisiLibity's visibility polygons of two halves of the holes meet away from the viewpoint")

    def _build_environment(
        self, rings: Rings, obj_blocking: np.ndarray, static_blocking: np.ndarray, o: np.ndarray
    ) -> list[np.ndarray]:
        """The environment's polygons: the outer boundary first, then the holes."""
        try:
            return self._environment(rings, obj_blocking, static_blocking, o)
        except _Unenclosable:
            return self._enclosed_environment(rings, obj_blocking, static_blocking, o)

    def _polygon_points(self, polys: list[np.ndarray], o: np.ndarray) -> np.ndarray:
        """VisiLibity's visibility polygon from ``o`` among ``polys`` (outer boundary first), same frame."""
        return visibility_polygon_coords(polys, float(o[0]), float(o[1]), self.epsilon)

    def environment(self, objects: FrameObjects, viewpoint: Viewpoint) -> tuple[Environment, np.ndarray]:
        """The VisiLibity environment used for this viewpoint, and the origin its coordinates are relative to."""
        observer = np.asarray(viewpoint.position, dtype=np.float64)
        self._use_origin(observer)
        rings = Rings(objects.rings.coords - self._origin, objects.rings.offsets)
        polys = self._build_environment(
            rings, ~viewpoint.transparent, ~viewpoint.static_transparent, observer - self._origin
        )
        return Environment(polys), self._origin

    def visible_region(self, objects: FrameObjects, viewpoint: Viewpoint) -> shapely.Polygon:
        """The region visible from the viewpoint (world coordinates, metres), bounded by a box ``box_margin``
        metres around the scene."""
        observer = np.asarray(viewpoint.position, dtype=np.float64)
        origin = self._use_origin(observer)
        rings, segments, seg_offsets = self._frame_geometry(objects)
        o = observer - origin
        pts = self._checked_points(
            rings, ~viewpoint.transparent, ~viewpoint.static_transparent, o, segments, seg_offsets
        )
        return shapely.Polygon(pts + observer)

    def _environment(
        self, rings: Rings, obj_blocking: np.ndarray, static_blocking: np.ndarray, o: np.ndarray
    ) -> list[np.ndarray]:
        """Holes = groups of overlapping bodies, each merged; raises ``_Unenclosable`` if a group encloses ``o``."""
        parts, part_bounds, part_holes, enclosing = self._static_parts(static_blocking)
        for k in enclosing:
            if shapely.intersects(shapely.Polygon(parts[k].exterior), shapely.Point(o)):
                raise _Unenclosable
        objs = np.flatnonzero(obj_blocking)
        if len(objs):
            lo_o = np.minimum.reduceat(rings.coords, rings.offsets[:-1])[objs]
            hi_o = np.maximum.reduceat(rings.coords, rings.offsets[:-1])[objs]
        else:
            lo_o = hi_o = np.zeros((0, 2))
        lo = np.concatenate([lo_o, part_bounds[:, :2]])
        hi = np.concatenate([hi_o, part_bounds[:, 2:]])
        n_obj = len(objs)
        first, second = box_overlaps(lo, hi)
        holes: list[np.ndarray] = []
        grouped = np.zeros(len(lo), dtype=bool)
        if len(first):
            involved = np.unique(np.concatenate([first, second]))
            shapes = self._shapes(rings, objs, parts, involved, n_obj)
            touching = np.asarray(shapely.intersects(shapes[first], shapes[second]), dtype=bool)
            first, second = first[touching], second[touching]
            if len(first):
                label = components(len(lo), first, second)
                observer = shapely.Point(o)
                for root in np.unique(label[np.concatenate([first, second])]):
                    members = np.flatnonzero(label == root)
                    grouped[members] = True
                    merged = shapely.union_all(shapes[members])
                    holes += self._group_holes(merged, observer)
        bounds_lo = lo.min(axis=0) if len(lo) else o
        bounds_hi = hi.max(axis=0) if len(hi) else o
        holes += vis_polygons_reversed(rings.coords, rings.offsets, objs[~grouped[:n_obj]].tolist())
        holes += [part_holes[k] for k in np.flatnonzero(~grouped[n_obj:])]
        return [self._outer(np.minimum(bounds_lo, o), np.maximum(bounds_hi, o)), *holes]

    def _shapes(self, rings: Rings, objs: np.ndarray, parts: np.ndarray, involved: np.ndarray, n_obj: int):
        shapes = np.empty(n_obj + len(parts), dtype=object)
        obj_involved = involved[involved < n_obj]
        if len(obj_involved):
            sub = rings.take(objs[obj_involved])
            shapes[obj_involved] = shapely.polygons(shapely.linearrings(sub.coords, indices=ring_ids(sub.offsets)))
        shapes[n_obj:] = parts
        return shapes

    def _group_holes(self, merged: shapely.Geometry, point: shapely.Point) -> list[np.ndarray]:
        pieces = list(getattr(merged, "geoms", [merged]))
        if len(pieces) > 1:  # bodies touching at points only: join them by a hair
            merged = shapely.buffer(merged, self.touch_gap, join_style="mitre")
            pieces = list(getattr(merged, "geoms", [merged]))
        if any(len(p.interiors) and shapely.intersects(shapely.Polygon(p.exterior), point) for p in pieces):
            raise _Unenclosable
        return [vis_polygon(exterior_cw(p)) for p in pieces]

    def _outer(self, lo: np.ndarray, hi: np.ndarray) -> np.ndarray:
        (x0, y0), (x1, y1) = lo - self.box_margin, hi + self.box_margin
        return vis_polygon(np.array([[x0, y0], [x1, y0], [x1, y1], [x0, y1]]))

    def _enclosed_environment(
        self, rings: Rings, obj_blocking: np.ndarray, static_blocking: np.ndarray, o: np.ndarray
    ) -> list[np.ndarray]:
        """The general construction: free space = box minus all bodies; keep the piece that holds ``o``."""
        objs = np.flatnonzero(obj_blocking)
        sub = rings.take(objs)
        shapes = list(shapely.polygons(shapely.linearrings(sub.coords, indices=ring_ids(sub.offsets))))
        shapes += list(self._static_shapes[static_blocking])
        merged = shapely.union_all(shapes)
        xmin, ymin, xmax, ymax = shapely.total_bounds(merged)
        lo = np.minimum([xmin, ymin], o) - self.box_margin
        hi = np.maximum([xmax, ymax], o) + self.box_margin
        box = shapely.box(lo[0], lo[1], hi[0], hi[1])
        piece = self._piece_holding(shapely.difference(box, merged), o)
        coords = shapely.get_coordinates(shapely.get_rings(piece))
        if len(np.unique(coords, axis=0)) < len(coords) - 1 - len(piece.interiors):
            merged = shapely.buffer(merged, self.touch_gap, join_style="mitre")
            piece = self._piece_holding(shapely.difference(box, merged), o)
        piece = shapely.orient_polygons(piece, exterior_cw=False)
        polys = [vis_polygon(shapely.get_coordinates(piece.exterior)[:-1])]
        polys += [vis_polygon(shapely.get_coordinates(h)[:-1]) for h in piece.interiors]
        return polys

    @staticmethod
    def _piece_holding(free: shapely.Geometry, o: np.ndarray) -> shapely.Polygon:
        point = shapely.Point(o)
        for piece in getattr(free, "geoms", [free]):
            if shapely.intersects(piece, point):
                return piece
        raise EngineFailure(_INSIDE_THICKNESS)
