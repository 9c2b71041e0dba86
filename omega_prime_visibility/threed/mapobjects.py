"""Road objects of an OpenDRIVE map (``<object>``: railings, barriers, poles, buildings) as static occluders.

Each object becomes a 2D footprint with a base and a top (metres, z up), placed with the road's reference line
(``line``, ``arc``, ``spiral``, ``poly3``, ``paramPoly3`` geometries) and elevation profile:

- an ``<outline>`` (``cornerLocal`` or ``cornerRoad``) gives a polygon; else ``length`` x ``width`` a rectangle
  around the object's position turned by its heading, ``radius`` a 16-sided polygon;
- a ``<repeat>`` with ``distance`` 0 is one continuous object along the road (a polygon band where it has a
  width, else a wall line), with ``distance`` > 0 copies every ``distance`` metres;
- the base is the road's elevation plus ``zOffset``; the top is the base plus ``height`` (a solid from the base
  up; a railing's open space below its rail is not modelled);
- objects without any extent (a pole given as a point) are left out, and so are those without a height.

In 2D the documented height rule (:func:`.statics.blocks_in_2d`) keeps those whose top is at least the
driver's eye height above the road (1.25 m): a 0.8 m railing does not hide a car from a driver.

>>> objs = read_map_objects("../shared/data/e6mini.xodr")  # doctest: +SKIP
>>> sorted({o.type for o in objs})  # doctest: +SKIP
['railing']
"""

from __future__ import annotations

import math
import os
import xml.etree.ElementTree as ET
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shapely

from ..inputs.roads import ReferenceLine, _f

STEP = 1.0
"""Metres between the points of continuous objects along the road."""


@dataclass(frozen=True, slots=True)
class MapObject:
    """One road object as a static occluder: ``footprint`` (shapely Polygon or LineString, metres), ``base`` and
    ``top`` (z, metres), ``height_above_road`` (metres, what the 2D rule compares with the eye height), and the
    map's ``road``, ``id``, ``type`` and ``name``."""

    road: str
    id: str
    type: str
    name: str
    footprint: shapely.Geometry
    base: float
    top: float
    height_above_road: float


def _footprint(obj: ET.Element, ref: ReferenceLine, s: float, t: float, length: float, width: float, radius: float):
    """The footprint of an object at ``(s, t)`` (outline, rectangle or circle), or None without extent."""
    x, y, hdg, _ = (a[0] for a in ref.pose(np.array([s])))
    px, py = x - t * math.sin(hdg), y + t * math.cos(hdg)
    heading = hdg + _f(obj, "hdg")
    local = obj.findall("outline/cornerLocal") or obj.findall("outlines/outline/cornerLocal")
    road = obj.findall("outline/cornerRoad") or obj.findall("outlines/outline/cornerRoad")
    c, sn = math.cos(heading), math.sin(heading)
    if len(local) >= 3:
        pts = [(px + _f(k, "u") * c - _f(k, "v") * sn, py + _f(k, "u") * sn + _f(k, "v") * c) for k in local]
        return shapely.Polygon(pts).buffer(0)
    if len(road) >= 3:
        rs = np.array([_f(k, "s") for k in road])
        rx, ry, rh, _ = ref.pose(rs)
        rt = np.array([_f(k, "t") for k in road])
        return shapely.Polygon(np.column_stack([rx - rt * np.sin(rh), ry + rt * np.cos(rh)])).buffer(0)
    if length > 0 and width > 0:
        corners = np.array([[1, 1], [-1, 1], [-1, -1], [1, -1]]) * [length / 2, width / 2]
        return shapely.Polygon(np.column_stack([px + corners[:, 0] * c - corners[:, 1] * sn,
                                                py + corners[:, 0] * sn + corners[:, 1] * c]))  # fmt: skip
    if radius > 0:
        return shapely.Point(px, py).buffer(radius, quad_segs=4)
    return None


def read_map_objects(path: str | os.PathLike, xml: str | None = None) -> list[MapObject]:
    """The road objects of an OpenDRIVE file (or of its text ``xml``, ``path`` then only names it) as
    :class:`MapObject` s, in file order (repeats expanded).

    Raises
    ------
    ValueError
        Naming the file, if it is missing, not XML, or not OpenDRIVE.
    """
    path = Path(path)
    try:
        root = ET.fromstring(xml) if xml is not None else ET.parse(path).getroot()
    except OSError as e:
        raise ValueError(f"cannot read map {path}: {e.strerror or e}") from None
    except ET.ParseError as e:
        raise ValueError(f"cannot read map {path} as OpenDRIVE (XML error: {e})") from None
    if root.tag != "OpenDRIVE":
        raise ValueError(f"cannot read map {path}: its XML root is <{root.tag}>, not <OpenDRIVE>")
    out: list[MapObject] = []
    for road in root.findall("road"):
        objects = road.findall("objects/object")
        if not objects:
            continue
        ref = ReferenceLine(road)
        for obj in objects:
            out.extend(_expand(obj, ref, road.get("id", "")))
    return out


def _expand(obj: ET.Element, ref: ReferenceLine, road: str) -> list[MapObject]:
    """One object, or its repeated copies, or its continuous band, as map objects."""
    meta = (road, obj.get("id", ""), obj.get("type", ""), obj.get("name", ""))
    repeats = obj.findall("repeat")
    if not repeats:
        height = _f(obj, "height", math.nan)
        geom = _footprint(obj, ref, _f(obj, "s"), _f(obj, "t"), _f(obj, "length"), _f(obj, "width"), _f(obj, "radius"))
        return _made(meta, geom, ref, _f(obj, "s"), _f(obj, "zOffset"), height)
    out = []
    for rep in repeats:
        s0, length, distance = _f(rep, "s"), _f(rep, "length"), _f(rep, "distance")

        def lerp(name: str, fallback: float, s: np.ndarray, rep=rep, s0=s0, length=length) -> np.ndarray:
            a, b = _f(rep, f"{name}Start", fallback), _f(rep, f"{name}End", _f(rep, f"{name}Start", fallback))
            return a + (b - a) * np.clip((s - s0) / max(length, 1e-12), 0, 1)

        if distance <= 0:  # continuous along the road
            s = np.linspace(s0, s0 + length, max(2, math.ceil(length / STEP) + 1))
            x, y, hdg, _ = ref.pose(s)
            t, w = lerp("t", _f(obj, "t"), s), lerp("width", _f(obj, "width"), s)
            if (w > 0).any():
                left = np.column_stack([x - (t + w / 2) * np.sin(hdg), y + (t + w / 2) * np.cos(hdg)])
                right = np.column_stack([x - (t - w / 2) * np.sin(hdg), y + (t - w / 2) * np.cos(hdg)])
                geom = shapely.Polygon(np.concatenate([left, right[::-1]])).buffer(0)
            else:
                geom = shapely.LineString(np.column_stack([x - t * np.sin(hdg), y + t * np.cos(hdg)]))
            height = float(np.max(lerp("height", _f(obj, "height", math.nan), s)))
            out += _made(meta, geom, ref, s0, float(lerp("zOffset", _f(obj, "zOffset"), np.array([s0]))[0]), height)
            continue
        for s in np.arange(s0, s0 + length + 1e-9, distance):
            sa = np.array([s])
            t_k, length_k, width_k, radius_k = (
                float(lerp(k, _f(obj, k), sa)[0]) for k in ("t", "length", "width", "radius")
            )
            geom = _footprint(obj, ref, s, t_k, length_k, width_k, radius_k)
            height = float(lerp("height", _f(obj, "height", math.nan), sa)[0])
            out += _made(meta, geom, ref, s, float(lerp("zOffset", _f(obj, "zOffset"), sa)[0]), height)
    return out


def _made(meta, geom, ref: ReferenceLine, s: float, z_offset: float, height: float) -> list[MapObject]:
    """A map object, or none when it has no extent or no height."""
    if geom is None or geom.is_empty or not math.isfinite(height) or height <= 0:
        return []
    road_z = float(ref.pose(np.array([s]))[3][0])
    base = road_z + min(z_offset, 0.0)
    return [MapObject(*meta, geom, base, road_z + z_offset + height, z_offset + height)]
