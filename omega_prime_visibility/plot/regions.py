"""The region a picture shades as seen: from the ego's centre all around, or, through sensors, what each sensor
sees from its own pose (its visible region inside its field of view and range), joined over the sensors.

No plotting library is imported here. Metres, radians counter-clockwise from +x.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence

import numpy as np
import shapely

from ..engines import EngineFailure, Viewpoint
from ..engines.sweep import SweepEngine
from ..engines.visilibity import VisiLibityEngine
from ..inputs.objects import FrameObjects
from ..inputs.sensors import Sensor
from ..inputs.statics import StaticOccluders
from ..table.pipeline import viewpoints

FULL_TURN = 2 * math.pi - 1e-9


def field_polygon(position, heading: float, fov: float, reach: float) -> shapely.Polygon:
    """A field of view of ``fov`` radians centred on ``heading`` at ``position``, up to ``reach`` metres: a wedge
    (its arc drawn with chords of at most 1°; a disk for 360°).

    >>> round(field_polygon((0, 0), 0.0, math.pi / 2, 10.0).area / (math.pi * 25), 3)
    1.0
    """
    steps = max(2, math.ceil(math.degrees(min(fov, 2 * math.pi))))
    if fov >= FULL_TURN:
        angles = heading + np.linspace(-math.pi, math.pi, steps, endpoint=False)
        return shapely.Polygon(np.asarray(position) + reach * np.c_[np.cos(angles), np.sin(angles)])
    angles = heading + np.linspace(-fov / 2, fov / 2, steps + 1)
    arc = np.asarray(position) + reach * np.c_[np.cos(angles), np.sin(angles)]
    return shapely.Polygon(np.vstack([position, arc]))


def _visible_region(engine: VisiLibityEngine, objects: FrameObjects, view: Viewpoint) -> shapely.Geometry:
    """VisiLibity's visible region of ``view`` (all around), or, in a frame it cannot compute (a box of thousands
    of kilometres drowns its tolerances), the sweep's outline out to the same box."""
    try:
        return engine.visible_region(objects, view)
    except EngineFailure:
        all_around = dataclasses.replace(view, fov=2 * math.pi, range=math.inf)
        corners = np.concatenate([objects.rings.coords, *[g.reshape(-1, 2) for g in _static_points(engine.statics)]])
        reach = float(np.hypot(*(corners - view.position).T).max()) + engine.box_margin
        outline = SweepEngine(engine.statics).visible_outline(objects, all_around, reach, math.radians(1.0))
        return shapely.Polygon(outline) if len(outline) >= 3 else shapely.Polygon()


def _static_points(statics: StaticOccluders) -> list[np.ndarray]:
    return [statics.rings.coords, statics.segments.reshape(-1, 2)]


def seen_region(
    engine: VisiLibityEngine,
    objects: FrameObjects,
    row: int,
    statics: StaticOccluders,
    sensors: Sequence[Sensor] = (),
) -> shapely.Geometry:
    """What the object at ``row`` sees in this frame: from its centre all around without sensors, else the union
    over the sensors of each one's visible region (from the sensor's pose, the same transparency as the table's)
    inside its field of view and range. Bounded by the engine's box around the scene. Objects that may not block
    (``occluders=``, ``objects.blocks``) hide nothing here either."""
    if not sensors:
        (view,) = viewpoints(objects, np.array([row]), statics)
        return _visible_region(engine, objects, _see_through(view, objects))
    parts = []
    for s, view in zip(sensors, viewpoints(objects, np.array([row]), statics, tuple(sensors)), strict=True):
        region = _visible_region(engine, objects, _see_through(view, objects))
        if s.fov >= FULL_TURN and math.isinf(s.range):
            parts.append(region)
            continue
        x0, y0, x1, y1 = region.bounds
        reach = min(s.range, 2 * math.hypot(x1 - x0, y1 - y0))
        parts.append(shapely.intersection(region, field_polygon(view.position, view.heading, s.fov, reach)))
    return shapely.union_all(parts)


def _see_through(view: Viewpoint, objects: FrameObjects) -> Viewpoint:
    """``view`` with the objects that may not block (``objects.blocks``) transparent as well."""
    if objects.blocks is None:
        return view
    return dataclasses.replace(view, transparent=np.asarray(view.transparent, dtype=bool) | ~objects.blocks)
