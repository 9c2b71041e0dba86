"""The default engine: VisiLibity1's exact visibility polygon, attributed back to the objects.

Per frame and observer:

1. Everything is shifted so that the observer sits at the origin (precision with large map coordinates).
2. A *valid* VisiLibity environment is built: the blocking bodies (objects, static polygons, wall lines thickened
   to ``2 * wall_half_width``) are merged with shapely, the free space is a box around them minus that union, and
   the connected piece of free space holding the observer becomes the environment: its exterior is the outer
   boundary (counter-clockwise), its interiors the holes (clockwise). Merging overlapping bodies keeps the holes
   disjoint; where two holes would only touch at a point, they are joined by a ``touch_gap`` wide buffer.
3. VisiLibity computes the visibility polygon. Each of its edges either runs along some body's boundary (then it
   lies on exactly one original edge, found as the nearest edge to its midpoint) or points straight at the
   observer (subtends no angle). The angle each body's edges subtend is its visible angle.
4. Occluders: candidate bodies intersect the convex hull of the observer and the target (shapely STRtree); the
   exact pairwise test in :mod:`..occlusion` keeps those really hit before the target.
"""

from __future__ import annotations

import numba
import numpy as np
import shapely
import visilibity as vis

from ..geometry import Rings, angular_extent, edges, ring_ids
from ..occlusion import occludes
from ..scene import FrameObjects, StaticOccluders
from . import EngineBase, Observation, group_pairs

BOX_MARGIN = 10.0  # metres of free space around everything


@numba.njit(cache=True)
def _nearest_body(points, seg, seg_body):
    """For each point, the body owning the nearest segment and the distance to it."""
    body = np.full(len(points), -1, dtype=np.int64)
    dist = np.full(len(points), np.inf)
    for i in range(len(points)):
        px, py = points[i, 0], points[i, 1]
        best = np.inf
        arg = -1
        for j in range(len(seg)):
            ax, ay = seg[j, 0, 0], seg[j, 0, 1]
            ex, ey = seg[j, 1, 0] - ax, seg[j, 1, 1] - ay
            wx, wy = px - ax, py - ay
            ee = ex * ex + ey * ey
            t = (wx * ex + wy * ey) / ee if ee > 0 else 0.0
            t = min(max(t, 0.0), 1.0)
            dx, dy = wx - t * ex, wy - t * ey
            d = dx * dx + dy * dy
            if d < best:
                best = d
                arg = j
        if arg >= 0:
            body[i] = seg_body[arg]
            dist[i] = np.sqrt(best)
    return body, dist


def _vis_polygon(coords: np.ndarray) -> vis.Polygon:
    return vis.Polygon([vis.Point(float(x), float(y)) for x, y in coords])


def _ring_coords(ring: shapely.LinearRing) -> np.ndarray:
    return shapely.get_coordinates(ring)[:-1]


class VisiLibityEngine(EngineBase):
    """Exact 2D visibility with VisiLibity1 (see module docstring).

    Parameters
    ----------
    statics : StaticOccluders
    epsilon : float
        VisiLibity's snapping distance, metres.
    wall_half_width : float
        Half thickness, metres, given to LineString walls (VisiLibity needs areas).
    touch_gap : float
        Buffer, metres, that joins obstacles touching at a single point (only applied when needed).
    """

    name = "visilibity"

    def __init__(
        self,
        statics: StaticOccluders,
        epsilon: float = 1e-9,
        wall_half_width: float = 1e-6,
        touch_gap: float = 1e-7,
    ) -> None:
        self.statics = statics
        self.epsilon = epsilon
        self.touch_gap = touch_gap
        n_src = statics.n_sources
        parts: list[list[shapely.Geometry]] = [[] for _ in range(n_src)]
        for k, g in enumerate(statics.geometries):
            if isinstance(g, shapely.Polygon | shapely.MultiPolygon):
                parts[k].append(g)
            else:
                parts[k].append(
                    shapely.buffer(g, wall_half_width, cap_style="flat", join_style="mitre", mitre_limit=10.0)
                )
        self._static_polygons = np.array([shapely.union_all(p) for p in parts] + [None], dtype=object)[:-1]
        # static edges per source: ring edges and wall segments, grouped by source
        a, b = edges(statics.rings)
        ring_seg = np.stack([a, b], axis=1)
        seg = np.concatenate([ring_seg, statics.segments])
        src = np.concatenate([statics.ring_source[ring_ids(statics.rings.offsets)], statics.segment_source])
        order = np.argsort(src, kind="stable")
        self._static_segments = seg[order].reshape(-1, 2, 2)
        self._static_segment_source = src[order].astype(np.int64)

    def observe(
        self,
        objects: FrameObjects,
        observer: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> Observation:
        n = len(objects)
        n_src = self.statics.n_sources
        origin = np.asarray(observer, dtype=np.float64)
        # bodies: objects 0..n-1, then static sources n..n+n_src-1; all shifted so the observer is at the origin
        coords = objects.rings.coords - origin
        obj_ids = ring_ids(objects.rings.offsets)
        a, b = edges(objects.rings)
        obj_seg = np.stack([a - origin, b - origin], axis=1)
        static_seg = self._static_segments - origin
        segments = np.concatenate([obj_seg, static_seg])
        seg_body = np.concatenate([obj_ids, n + self._static_segment_source])
        seg_offsets = np.zeros(n + n_src + 1, dtype=np.int64)
        np.cumsum(np.bincount(seg_body, minlength=n + n_src), out=seg_offsets[1:])

        polygons = shapely.polygons(shapely.linearrings(coords, indices=obj_ids))
        static_polygons = shapely.transform(self._static_polygons, lambda c: c - origin)
        body_polygons = np.concatenate([polygons, static_polygons])
        blocking = np.concatenate([~np.asarray(transparent, bool), ~np.asarray(static_transparent, bool)])

        zero = np.zeros(2)
        start, width, _ = angular_extent(zero, Rings(coords, objects.rings.offsets))
        if blocking.any():
            visible = self._visible_angles(body_polygons[blocking], segments, seg_body, blocking, n)
        else:
            visible = width.copy()

        occ_offsets, occ, st_offsets, st = self._occluders(
            body_polygons, blocking, transparent, segments, seg_offsets, start, width, n
        )
        return Observation(visible, width, occ_offsets, occ, st_offsets, st)

    # -- step 2 and 3 ------------------------------------------------------------------------------------------
    def _environment(self, obstacles: np.ndarray) -> vis.Environment:
        merged = shapely.union_all(obstacles)
        xmin, ymin, xmax, ymax = shapely.total_bounds(merged)
        r = max(abs(xmin), abs(ymin), abs(xmax), abs(ymax)) + BOX_MARGIN
        box = shapely.box(-r, -r, r, r)
        free = shapely.difference(box, merged)
        piece = self._piece_with_origin(free)
        rings = [piece.exterior, *piece.interiors]
        ring_coords = [_ring_coords(ring) for ring in rings]
        allc = np.concatenate(ring_coords)
        if len(np.unique(allc, axis=0)) < len(allc):
            # bodies touching at a point: join them by a hair so that the holes stay disjoint
            merged = shapely.buffer(merged, self.touch_gap, join_style="mitre")
            piece = self._piece_with_origin(shapely.difference(box, merged))
        piece = shapely.orient_polygons(piece, exterior_cw=False)
        polys = [_vis_polygon(_ring_coords(piece.exterior))]
        polys += [_vis_polygon(_ring_coords(hole)) for hole in piece.interiors]
        return vis.Environment(polys)

    @staticmethod
    def _piece_with_origin(free: shapely.Geometry) -> shapely.Polygon:
        origin = shapely.Point(0.0, 0.0)
        for piece in getattr(free, "geoms", [free]):
            if shapely.intersects(piece, origin):
                return piece
        raise RuntimeError("internal error: the observer is not in free space although no body contains it")

    def _visible_angles(
        self,
        obstacles: np.ndarray,
        segments: np.ndarray,
        seg_body: np.ndarray,
        blocking: np.ndarray,
        n: int,
    ) -> np.ndarray:
        env = self._environment(obstacles)
        vp = vis.Visibility_Polygon(vis.Point(0.0, 0.0), env, self.epsilon)
        m = vp.n()
        pts = np.array([(vp[i].x(), vp[i].y()) for i in range(m)], dtype=np.float64).reshape(-1, 2)
        a, b = pts, np.roll(pts, -1, axis=0)
        span = np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1])
        keep = span > 0.0
        mid = 0.5 * (a[keep] + b[keep])
        use = blocking[seg_body]
        body, dist = _nearest_body(mid, np.ascontiguousarray(segments[use]), seg_body[use])
        on_body = dist <= 1e-6 * np.maximum(1.0, np.hypot(mid[:, 0], mid[:, 1])) + 1e-5
        body = body[on_body]
        return np.bincount(body, weights=span[keep][on_body], minlength=len(blocking))[:n]

    # -- step 4 ------------------------------------------------------------------------------------------------
    def _occluders(
        self,
        body_polygons: np.ndarray,
        blocking: np.ndarray,
        transparent: np.ndarray,
        segments: np.ndarray,
        seg_offsets: np.ndarray,
        start: np.ndarray,
        width: np.ndarray,
        n: int,
    ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        targets = np.flatnonzero(~np.asarray(transparent, bool))
        candidates = np.flatnonzero(blocking)
        empty = np.zeros(n + 1, dtype=np.int64), np.zeros(0, dtype=np.int64)
        if len(targets) == 0 or len(candidates) == 0:
            return (*empty, *empty)
        tree = shapely.STRtree(body_polygons[candidates])
        hulls = shapely.convex_hull(shapely.union(body_polygons[targets], shapely.Point(0.0, 0.0)))
        t_pos, c_pos = tree.query(hulls, predicate="intersects")
        target, body = targets[t_pos], candidates[c_pos]
        keep = target != body
        target, body = target[keep], body[keep]
        hit = occludes(np.zeros(2), segments, seg_offsets, body, target, start, width)
        target, body = target[hit], body[hit]
        is_obj = body < n
        occ_offsets, occ = group_pairs(target[is_obj], body[is_obj], n)
        st_offsets, st = group_pairs(target[~is_obj], body[~is_obj] - n, n)
        return occ_offsets, occ, st_offsets, st
