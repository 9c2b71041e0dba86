"""The lanes of a recording's map, prepared once per map for drawing: outlines and centre lines simplified to what a
picture can show, and points along them that tell the window which way the road runs.

An OpenDRIVE map's lanes come as polygons with hundreds of thousands of vertices (a few centimetres apart);
drawn as they are, one picture took seconds to tens of seconds. Simplified within :data:`TOLERANCE` metres they keep
a few hundred vertices and look the same. The preparation is cached per map object (the last
:data:`CACHE_SIZE` maps), so every picture of a loaded recording after the first reuses it.

No plotting library is imported here.
"""

from __future__ import annotations

from collections import OrderedDict
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import shapely

TOLERANCE = 0.05  # metres: far below a pixel at any view range a picture uses
POINT_SPACING = 5.0  # metres between the points that shape the window
CACHE_SIZE = 4


@dataclass
class Lanes:
    """Lanes ready to draw.

    Attributes
    ----------
    surfaces : list of ndarray, shape (k, 2)
        Rings of the road surface (the union of the lane surfaces, so overlapping lanes are not shaded twice):
        each polygon's exterior counter-clockwise, then its holes clockwise, metres.
    centres : list of ndarray, shape (k, 2)
        Centre lines (or other lines given as lanes), metres.
    points : ndarray, shape (m, 2)
        Points along all of them, at most :data:`POINT_SPACING` metres apart.
    """

    surfaces: list[np.ndarray] = field(default_factory=list)
    centres: list[np.ndarray] = field(default_factory=list)
    points: np.ndarray = field(default_factory=lambda: np.zeros((0, 2)))

    def __bool__(self) -> bool:
        return bool(self.surfaces or self.centres)


_CACHE: OrderedDict[int, tuple[Any, Lanes]] = OrderedDict()  # id(map) -> (the map, kept alive; its lanes)


def prepared_lanes(lanes: Any) -> Lanes:
    """The lanes of ``lanes`` (a map with a ``lanes`` dict, a sequence of shapely geometries, None/False for none),
    simplified; maps are prepared once and cached.

    >>> len(prepared_lanes([shapely.LineString([(0, 0), (0.01, 0.001), (20, 0)])]).centres[0])
    2
    """
    if lanes is None or lanes is False:
        return Lanes()
    if not hasattr(lanes, "lanes"):
        return _prepare(_given_shapes(lanes))
    hit = _CACHE.get(id(lanes))
    if hit is not None and hit[0] is lanes:
        _CACHE.move_to_end(id(lanes))
        return hit[1]
    prepared = _prepare(_map_shapes(lanes))
    _CACHE[id(lanes)] = (lanes, prepared)
    while len(_CACHE) > CACHE_SIZE:
        _CACHE.popitem(last=False)
    return prepared


def _map_shapes(road_map: Any) -> list[shapely.Geometry]:
    out = []
    for lane in road_map.lanes.values():
        for name in ("polygon", "centerline"):
            g = getattr(lane, name, None)
            if isinstance(g, shapely.Geometry) and not g.is_empty:
                out.append(g)
            elif g is not None and name == "centerline" and len(np.asarray(g)) >= 2:  # an array of points
                out.append(shapely.LineString(np.asarray(g)[:, :2]))
    return out


def _given_shapes(lanes: Sequence[Any]) -> list[shapely.Geometry]:
    out = []
    for g in lanes:
        if not isinstance(g, shapely.Geometry):
            raise ValueError(f"lanes must be shapely geometries or a map with lanes, not {type(g).__name__}")
        out.append(g)
    return out


def _prepare(shapes: list[shapely.Geometry]) -> Lanes:
    if not shapes:
        return Lanes()
    simple = shapely.simplify(np.asarray(shapes, dtype=object), TOLERANCE)
    polygons, centres = [], []
    for g in simple:
        for part in getattr(g, "geoms", [g]):
            if isinstance(part, shapely.Polygon) and not part.is_empty:
                polygons.append(part)
            elif isinstance(part, shapely.LineString | shapely.LinearRing) and not part.is_empty:
                centres.append(np.asarray(part.coords)[:, :2])
    surfaces = []
    if polygons:
        road = shapely.union_all(shapely.make_valid(np.asarray(polygons, dtype=object)))
        for part in getattr(road, "geoms", [road]):
            if isinstance(part, shapely.Polygon) and not part.is_empty:
                part = shapely.geometry.polygon.orient(part, 1.0)
                surfaces.extend(np.asarray(ring.coords)[:, :2] for ring in (part.exterior, *part.interiors))
    points = shapely.get_coordinates(shapely.segmentize(simple, POINT_SPACING))
    return Lanes(surfaces, centres, points)
