"""The area an observer's sensors see, and the road area hidden from them, per frame.

For one frame, :func:`visible_area` is the union over the sensors of the region each sees: its visibility
polygon (static occluders included) cut to its field of view and its range. Edges along road users and static
occluders are exact; the range circle is drawn as chords every :data:`ARC_STEP` radians (area error about
5e-5 relative). A sensor without a range sees up to a circle :data:`UNBOUNDED_MARGIN` metres beyond the farthest road
user of the frame. :func:`visible_area_over_time` gives the areas per frame as a table, with the hidden part of
the road when the recording's map has lane polygons (OpenDRIVE maps do) or a road outline is given.

The union is not built by shapely: :mod:`.star_union` (compiled) finds the pieces of the sensors' edges that no
other sensor's region covers, the union's boundary, and sums their Green's-theorem terms for the area, which is all
:func:`visible_area_over_time` needs without a road; :func:`visible_area`, and :func:`visible_area_over_time` with a
road, chain the same pieces into the union's rings (:mod:`.union_rings`). Both agree with shapely's union of the
same polygons to about 1e-13 relative (rarely up to about 4e-9 for the area, where two sensors' range chords
nearly coincide), so the error bound above holds for both; when the rings fail their checks (validity, area) the
frame's union is shapely's (counted in :data:`UNION_FALLBACKS`). For the ``typical`` set on a crowded highway
(``benchmarks/bench_sensors.py``, CPU time per frame, the sensors' outlines included): 1.1 ms for the area, 1.5 ms
with the road's hidden area (3.1 ms with shapely's union).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
from collections import Counter
from collections.abc import Iterator, Sequence
from typing import Any

import numpy as np
import polars as pl
import shapely

from ..engines import Viewpoint
from ..engines.sweep import SweepEngine
from ..geometry.star_union import star_union_area
from ..geometry.union_rings import star_union
from ..inputs.errors import OptionError, Setting
from ..inputs.objects import FrameObjects, ObjectTable, OnInvalid
from ..inputs.observers import SensorSpec
from ..inputs.roles import RoleSpec
from ..inputs.sensors import Sensor
from ..inputs.statics import StaticOccluders
from ..query import Query, fold_keywords, resolve
from ..table.pipeline import observer_rows, viewpoints

ARC_STEP = math.radians(1.0)
"""Radians between the points drawn on range circles (the chords lose a share of about ``ARC_STEP² / 6`` of a
circular sector's area, 5e-5 at 1°)."""
UNBOUNDED_MARGIN = 10.0
"""Metres beyond the farthest road user up to which a sensor without range sees."""
UNION_FALLBACKS: Counter[str] = Counter()
"""How often :func:`visible_area` and :func:`visible_area_over_time` built a union with shapely because the
boundary pieces of :mod:`.star_union` did not chain into a valid geometry of the right area (key ``"shapely"``)."""


def road_outline(recording: Any) -> shapely.Geometry | None:
    """The union of the lane polygons of a recording's map, or None when it has no map with lane polygons.

    Reads ``recording.map.lanes[...].polygon`` (omega-prime's OpenDRIVE maps carry them).
    """
    lanes = getattr(getattr(recording, "map", None), "lanes", None)
    if not lanes:
        return None
    polygons = [getattr(lane, "polygon", None) for lane in (lanes.values() if hasattr(lanes, "values") else lanes)]
    polygons = [p for p in polygons if isinstance(p, shapely.Geometry) and not p.is_empty]
    if not polygons:
        return None
    return shapely.union_all(shapely.make_valid(np.array(polygons, dtype=object)))


def _outlines(
    engine: SweepEngine,
    objects: FrameObjects,
    statics: StaticOccluders,
    row: int,
    sensors: Sequence[Sensor] | None,
) -> list[tuple[np.ndarray, Viewpoint]]:
    """The outline (world frame, metres, see :meth:`SweepEngine.visible_outline`) of the region each sensor of the
    object at row ``row`` sees in this frame, with the sensor's viewpoint."""
    views = viewpoints(objects, np.array([row]), statics, sensors)
    if objects.blocks is not None:  # occluders=: the others neither block nor hide
        views = [dataclasses.replace(v, transparent=v.transparent | ~objects.blocks) for v in views]
    coords = objects.rings.coords
    out = []
    for view in views:
        radius = view.range
        if not math.isfinite(radius):
            radius = float(np.sqrt(((coords - view.position) ** 2).sum(axis=1).max())) + UNBOUNDED_MARGIN
        out.append((engine.visible_outline(objects, view, radius, ARC_STEP), view))
    return out


def _regions(outlines: list[tuple[np.ndarray, Viewpoint]]) -> shapely.Geometry:
    """The union of the regions of :func:`_outlines`."""
    polygons = []
    for outline, _ in outlines:
        polygon = shapely.Polygon(outline) if len(outline) >= 3 else shapely.Polygon()
        # star-shaped by construction; only spikes of zero width along a ray can make it invalid
        polygons.append(polygon if shapely.is_valid(polygon) else shapely.make_valid(polygon))
    return polygons[0] if len(polygons) == 1 else shapely.union_all(polygons)


def _star_polygons(outlines: list[tuple[np.ndarray, Viewpoint]], origin: np.ndarray) -> tuple[np.ndarray, ...]:
    """The regions of :func:`_outlines` as :func:`.star_union.star_union_area` takes them, relative to ``origin``
    (a point near the regions, world frame, metres: small coordinates round less)."""
    points = [outline - origin for outline, _ in outlines]
    starts = np.zeros(len(points) + 1, dtype=np.int64)
    starts[1:] = np.cumsum([len(p) for p in points])
    centers = np.array([view.position - origin for _, view in outlines], dtype=np.float64).reshape(-1, 2)
    fovs = np.array([view.fov for _, view in outlines], dtype=np.float64)
    # the outline starts at the field of view's start, or at bearing -π all around (see visible_outline)
    bases = np.array([view.heading - 0.5 * view.fov for _, view in outlines], dtype=np.float64)
    bases[fovs >= 2 * math.pi] = -math.pi
    return np.concatenate(points).reshape(-1, 2), starts, centers, bases, fovs


def _union_area(outlines: list[tuple[np.ndarray, Viewpoint]], origin: np.ndarray) -> float:
    """The area of :func:`_regions` (square metres) without building it (:mod:`.star_union`); ``origin`` as for
    :func:`_star_polygons`."""
    return star_union_area(*_star_polygons(outlines, origin))


def _union(outlines: list[tuple[np.ndarray, Viewpoint]], origin: np.ndarray) -> shapely.Geometry:
    """:func:`_regions`, built from the boundary pieces :mod:`.star_union` finds (:mod:`.union_rings`), or by
    shapely's union when they do not make a valid geometry of the right area (counted in :data:`UNION_FALLBACKS`);
    ``origin`` as for :func:`_star_polygons`."""
    if len(outlines) > 1:
        geometry, _ = star_union(*_star_polygons(outlines, origin), origin=origin)
        if geometry is not None:
            return geometry
        UNION_FALLBACKS["shapely"] += 1
    return _regions(outlines)


def _prepare(df: Any, ego_idx: Any, static_occluder_polys: Any, query: Query | None, keywords: dict):
    """The objects, static occluders and the ego's sensors of the question (as ``get_visibility_df`` reads it:
    the map's road objects and the 2D height rule included); one observer, 2D."""
    if ego_idx is not None and (isinstance(ego_idx, bool) or not isinstance(ego_idx, int | np.integer)):
        raise ValueError(f"ego_idx must be one idx (an int), not {ego_idx!r}")
    question = fold_keywords(query, ego_idx=ego_idx, static_occluder_polys=static_occluder_polys, **keywords)
    if question.three_d:
        raise OptionError(
            "mode",
            "the visible area is a region on the ground: {three_d} has none; use {two_d}",
            three_d=Setting("mode", "3d"),
            two_d=Setting("mode", "2d"),
        )
    if question.observers is not None and not isinstance(question.observers, int):
        raise OptionError.plain("ego_idx", f"ego_idx must be one idx (an int), not {question.observers!r}")
    scene = resolve(question, df)
    ego = int(scene.egos[0])
    sensors = scene.sensors[ego] if isinstance(scene.sensors, dict) else scene.sensors
    return scene.objects, scene.statics, sensors, ego


def visible_area(
    df: Any,
    ego_idx: int | None,
    frame: int,
    sensors: SensorSpec = None,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    query: Query | None = None,
    on_invalid: OnInvalid | None = None,
    occluders: RoleSpec = None,
    **question: Any,
) -> shapely.Geometry:
    """The region the ego's sensors see in one frame (world frame, metres).

    Parameters
    ----------
    df, static_occluder_polys, on_invalid
        As for :func:`~omega_prime_visibility.get_visibility_df`.
    ego_idx : int
        The observing object.
    frame : int
        A frame number of the table.
    sensors : layout name, JSON path, Sensor or Sensors, optional
        None: the ego's centre, all around (up to :data:`UNBOUNDED_MARGIN` beyond the farthest road user).
    occluders : optional
        Which objects may block the view, as for :func:`~omega_prime_visibility.get_visibility_df` (None: all).
    query : Query, optional
        The whole question as one value, and the other table keywords of ``get_visibility_df``
        (``map_occluders``, ``static_occluder_heights``: static occluders lower than the driver's eye are left
        out, as the table leaves them out); 2D only.

    Returns
    -------
    shapely Polygon or MultiPolygon
        The union of the sensors' regions (one sensor: its region as it is), built from the uncovered pieces of
        their edges (see the module's notes); polygons touch each other or their holes at points at most.

    Examples
    --------
    A 90° camera with a 10 m range and nothing in front of it sees a quarter disk:

    >>> import polars as pl
    >>> from omega_prime_visibility import Sensor
    >>> objects = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, -30.0],
    ...     "y": [0.0, 0.0], "length": [4.0, 4.0], "width": [2.0, 2.0], "yaw": [0.0, 0.0]})
    >>> seen = visible_area(objects, 0, 0, sensors=Sensor("cam", fov=math.pi / 2, range=10.0))
    >>> round(seen.area / (math.pi * 100 / 4), 3)
    1.0
    """
    keywords = {"sensors": sensors, "on_invalid": on_invalid, "occluders": occluders, **question}
    objects, statics, sensor_set, ego_idx = _prepare(df, ego_idx, static_occluder_polys, query, keywords)
    if isinstance(frame, bool) or not isinstance(frame, numbers.Integral):
        raise ValueError(f"frame takes a frame number (a whole number), not {frame!r}")
    k = np.searchsorted(objects.frame[objects.frame_starts[:-1]], frame)
    if k >= objects.n_frames or objects.frame[objects.frame_starts[k]] != frame:
        raise ValueError(f"frame {frame} does not occur in the table")
    one = objects.frame_objects(int(k))
    rows = observer_rows(one, np.array([ego_idx], dtype=np.int64))
    if len(rows) == 0:
        raise ValueError(f"ego idx {ego_idx} is not present in frame {frame}")
    return _union(_outlines(SweepEngine(statics), one, statics, int(rows[0]), sensor_set), one.position[int(rows[0])])


def visible_area_over_time(
    df: Any,
    ego_idx: int | None,
    sensors: SensorSpec = None,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    road: shapely.Geometry | None = None,
    query: Query | None = None,
    on_invalid: OnInvalid | None = None,
    occluders: RoleSpec = None,
    **question: Any,
) -> pl.DataFrame:
    """Per frame where the ego exists: ``frame, total_nanos, visible_area`` (square metres, see
    :func:`visible_area`) and, with a road outline (``road``, or the lane polygons of the recording's map),
    ``hidden_road_area``: the road's area outside the seen region (square metres). ``occluders``, ``query`` and
    the other table keywords as for :func:`visible_area`.
    """
    if road is None:
        road = road_outline(df)
    elif not isinstance(road, shapely.Polygon | shapely.MultiPolygon):
        raise ValueError(f"road must be a shapely Polygon or MultiPolygon (the road's outline, metres), not {road!r}")
    keywords = {"sensors": sensors, "on_invalid": on_invalid, "occluders": occluders, **question}
    objects: ObjectTable
    objects, statics, sensor_set, ego_idx = _prepare(df, ego_idx, static_occluder_polys, query, keywords)
    engine = SweepEngine(statics)
    frames, nanos, areas, hidden = [], [], [], []
    ego = np.array([ego_idx], dtype=np.int64)
    for k in range(objects.n_frames):
        one = objects.frame_objects(k)
        rows = observer_rows(one, ego)
        if len(rows) == 0:
            continue
        outlines = _outlines(engine, one, statics, int(rows[0]), sensor_set)
        frames.append(one.frame)
        nanos.append(one.total_nanos)
        if road is None:  # only the area: no geometry needed
            areas.append(_union_area(outlines, one.position[int(rows[0])]))
        else:
            seen = _union(outlines, one.position[int(rows[0])])
            areas.append(seen.area)
            hidden.append(shapely.difference(road, seen).area)
    table = {"frame": frames, "total_nanos": nanos, "visible_area": areas}
    if road is not None:
        table["hidden_road_area"] = hidden
    schema = {"frame": pl.Int64, "total_nanos": pl.Int64, "visible_area": pl.Float64, "hidden_road_area": pl.Float64}
    return pl.DataFrame(table, schema={k: v for k, v in schema.items() if k in table})


def visible_outlines(
    df: Any,
    ego_idx: int | None,
    sensors: SensorSpec = None,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    query: Query | None = None,
    **question: Any,
) -> Iterator[tuple[int, list[tuple[np.ndarray, np.ndarray]]]]:
    """``(frame, outlines)`` for every frame where the ego exists: per sensor (one without sensors) the outline of
    the region it sees (world frame, metres, counter-clockwise, shape (k, 2)) and its viewpoint (shape (2,)); each
    region is star-shaped about its viewpoint (its union is :func:`visible_area`'s region). One reading of the
    recording, for pictures and viewers that draw the regions.

    >>> import polars as pl
    >>> objects = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, -30.0],
    ...     "y": [0.0, 0.0], "length": [4.0, 4.0], "width": [2.0, 2.0], "yaw": [0.0, 0.0]})
    >>> [(f, len(views)) for f, views in visible_outlines(objects, 0)]
    [(0, 1)]
    """
    keywords = {"sensors": sensors, **question}
    objects, statics, sensor_set, ego_idx = _prepare(df, ego_idx, static_occluder_polys, query, keywords)
    engine = SweepEngine(statics)
    ego = np.array([ego_idx], dtype=np.int64)
    for k in range(objects.n_frames):
        one = objects.frame_objects(k)
        rows = observer_rows(one, ego)
        if len(rows):
            outlines = _outlines(engine, one, statics, int(rows[0]), sensor_set)
            yield int(one.frame), [(outline, np.asarray(view.position)) for outline, view in outlines]
