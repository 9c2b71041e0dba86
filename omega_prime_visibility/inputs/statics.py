"""Static occluders (buildings, walls, guard rails, vegetation): validated once and split into oriented rings and
two-sided wall segments shared by all frames."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import shapely

from ..geometry.rings import Rings, edges, orient, ring_ids, rings_from, signed_area
from .containment import TOUCH_TOLERANCE, points_in_boxes
from .outlines import MIN_AREA


@dataclass(frozen=True, slots=True)
class StaticOccluders:
    """Static geometry shared by all frames.

    Attributes
    ----------
    rings : Rings
        Polygon rings, material on the left (exteriors counter-clockwise, interiors clockwise).
    ring_source : ndarray, shape (r,), int64
        Position, in the user's list, of the occluder each ring comes from.
    segments : ndarray, shape (s, 2, 2), float64
        Two-sided wall segments from LineStrings, ``segments[j] = [[x0, y0], [x1, y1]]``.
    segment_source : ndarray, shape (s,), int64
        Position, in the user's list, of the occluder each segment comes from.
    geometries : ndarray of shapely geometries, shape (n_sources,)
        The occluders as given (validated).
    bounds : ndarray, shape (n_sources, 4)
        ``xmin, ymin, xmax, ymax`` of each occluder, metres.
    solids : threed.statics.StaticSolids or None
        Their 3D triangles with heights, and meshes (``mode="3d"``; see :mod:`.threed.statics`).
    """

    rings: Rings
    ring_source: np.ndarray
    segments: np.ndarray
    segment_source: np.ndarray
    geometries: np.ndarray
    bounds: np.ndarray
    solids: Any = None

    @property
    def n_sources(self) -> int:
        return len(self.geometries)

    def containing(self, points: np.ndarray) -> np.ndarray:
        """Whether each occluder contains or touches each of ``points`` (shape (k, 2), metres), shape
        (k, n_sources) bool (see :meth:`containing_pairs`)."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        inside = np.zeros((len(points), self.n_sources), dtype=bool)
        inside[self.containing_pairs(points)] = True
        return inside

    def containing_pairs(self, points: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(point, source)`` pairs (int64, ordered by point, then source) of occluders containing or touching
        the points (shape (k, 2), metres): passing within :data:`~.containment.TOUCH_TOLERANCE` of them, as for
        objects (a viewpoint on a wall's line up to rounding is on the wall). Only occluders whose bounding box,
        grown by that tolerance, holds a point are tested exactly, so a large map costs little."""
        points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
        if not self.n_sources or not len(points):
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        grown = self.bounds + np.array([-TOUCH_TOLERANCE, -TOUCH_TOLERANCE, TOUCH_TOLERANCE, TOUCH_TOLERANCE])
        v, s = np.nonzero(points_in_boxes(points, grown))
        if not len(v):
            return np.zeros(0, dtype=np.int64), np.zeros(0, dtype=np.int64)
        hit = shapely.dwithin(self.geometries[s], shapely.points(points[v]), TOUCH_TOLERANCE)
        return v[hit].astype(np.int64), s[hit].astype(np.int64)

    def source_edges(self) -> tuple[np.ndarray, np.ndarray]:
        """Every edge (ring edges and wall segments), shape (s, 2, 2) metres, grouped by source: the edges and
        the CSR offsets (shape (n_sources + 1,)) of each source's edges."""
        a, b = edges(self.rings)
        seg = np.concatenate([np.stack([a, b], axis=1), np.asarray(self.segments, dtype=np.float64).reshape(-1, 2, 2)])
        src = np.concatenate([self.ring_source[ring_ids(self.rings.offsets)], self.segment_source]).astype(np.int64)
        order = np.argsort(src, kind="stable")
        offsets = np.zeros(self.n_sources + 1, dtype=np.int64)
        np.cumsum(np.bincount(src, minlength=self.n_sources), out=offsets[1:])
        return np.ascontiguousarray(seg[order]), offsets


def polygonal_and_lineal_parts(geometry: shapely.Geometry) -> tuple[list[shapely.Polygon], list[shapely.LineString]]:
    """The polygons and the lines a geometry is made of; points and empty parts are dropped.

    Collections (what ``shapely.make_valid`` returns) and multi-part geometries are taken apart, LinearRings
    count as closed lines.

    Examples
    --------
    >>> import shapely
    >>> wall = shapely.LineString([(2, 0), (3, 0)])
    >>> g = shapely.GeometryCollection([shapely.box(0, 0, 1, 1), shapely.Point(5, 5), wall])
    >>> [len(parts) for parts in polygonal_and_lineal_parts(g)]
    [1, 1]
    """
    polygons, lines = [], []
    for part in shapely.get_parts(geometry):
        if isinstance(part, shapely.GeometryCollection | shapely.MultiPolygon | shapely.MultiLineString):
            more_polygons, more_lines = polygonal_and_lineal_parts(part)
            polygons += more_polygons
            lines += more_lines
        elif part.is_empty:
            continue
        elif isinstance(part, shapely.Polygon):
            polygons.append(part)
        elif isinstance(part, shapely.LinearRing):
            lines.append(shapely.LineString(part.coords))
        elif isinstance(part, shapely.LineString):
            lines.append(part)
    return polygons, lines


def load_static_occluders(geometries: Sequence[Any] | Any | None) -> StaticOccluders:
    """Validate static occluders and split them into oriented rings and two-sided wall segments.

    Parameters
    ----------
    geometries : sequence of shapely geometries, or None
        Polygons, MultiPolygons (buildings, parked vehicles, vegetation), LineStrings, MultiLineStrings or
        LinearRings (walls, guard rails, two-sided), and collections of them (points in a collection are
        dropped). They are reported by their position in this sequence.

    Raises
    ------
    ValueError
        An entry that is not a shapely geometry, is empty, has no polygonal or lineal part (a Point), holds an
        invalid polygon, or has non-finite coordinates.
    """
    if geometries is None:
        geometries = []
    elif isinstance(geometries, shapely.Geometry):
        geometries = [geometries]
    geoms = list(geometries)
    rings, ring_source, ccw = [], [], []
    segments, segment_source = [], []
    for k, g in enumerate(geoms):
        if not isinstance(g, shapely.Geometry):
            raise ValueError(f"static occluder {k} is not a shapely geometry but {type(g).__name__}")
        if g.is_empty:
            raise ValueError(f"static occluder {k} is empty")
        if not np.isfinite(shapely.get_coordinates(g)).all():
            raise ValueError(f"static occluder {k} has NaN or infinite coordinates")
        polygons, lines = polygonal_and_lineal_parts(g)
        if not polygons and not lines:
            raise ValueError(
                f"static occluder {k} is a {g.geom_type} without polygonal or lineal parts: it has no extent that "
                "could block the view (give walls as LineStrings, buildings as Polygons)"
            )
        for poly in polygons:
            if not poly.is_valid:
                raise ValueError(
                    f"static occluder {k} is or holds an invalid polygon ({shapely.is_valid_reason(poly)}); "
                    "repair it, e.g. with shapely.make_valid"
                )
            if poly.area < MIN_AREA:
                raise ValueError(f"static occluder {k} has a zero-size polygon part")
            for j, ring in enumerate([poly.exterior, *poly.interiors]):
                rings.append(ring)
                ring_source.append(k)
                ccw.append(j == 0)
        if lines:
            # split the lines where they cross each other or themselves: no two edges of one body may cross
            # (occlusion.py)
            noded = shapely.node(shapely.MultiLineString(lines))
            for piece in getattr(noded, "geoms", [noded]):
                c = np.asarray(piece.coords)[:, :2]
                seg = np.stack([c[:-1], c[1:]], axis=1)
                seg = seg[np.hypot(*(seg[:, 1] - seg[:, 0]).T) > 0]
                if len(seg) == 0:
                    raise ValueError(f"static occluder {k} is a line of zero length")
                segments.append(seg)
                segment_source.extend([k] * len(seg))
    ring_arrays = orient(rings_from(rings), np.array(ccw, dtype=bool)) if rings else Rings.empty()
    if len(ring_arrays) and (np.abs(signed_area(ring_arrays)) < MIN_AREA).any():
        raise ValueError("a static occluder has a zero-size ring")
    return StaticOccluders(
        rings=ring_arrays,
        ring_source=np.asarray(ring_source, dtype=np.int64),
        segments=np.concatenate(segments) if segments else np.zeros((0, 2, 2)),
        segment_source=np.asarray(segment_source, dtype=np.int64),
        geometries=np.asarray([*geoms, None], dtype=object)[:-1],
        bounds=shapely.bounds(np.asarray([*geoms, None], dtype=object)[:-1]).reshape(-1, 4),
    )
