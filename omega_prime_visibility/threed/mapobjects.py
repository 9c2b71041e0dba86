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


def _f(elem: ET.Element, name: str, default: float = 0.0) -> float:
    value = elem.get(name)
    return default if value is None or value == "" else float(value)


class ReferenceLine:
    """A road's reference line and elevation: ``pose(s)`` -> ``(x, y, heading, z)`` arrays."""

    def __init__(self, road: ET.Element) -> None:
        self.geometries = sorted(road.findall("planView/geometry"), key=lambda g: _f(g, "s"))
        if not self.geometries:
            raise ValueError(f"road {road.get('id')} has no planView geometry")
        self.starts = np.array([_f(g, "s") for g in self.geometries])
        self.elevation = sorted(road.findall("elevationProfile/elevation"), key=lambda e: _f(e, "s"))

    def pose(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        s = np.atleast_1d(np.asarray(s, dtype=np.float64))
        which = np.clip(np.searchsorted(self.starts, s, side="right") - 1, 0, len(self.geometries) - 1)
        x, y, hdg = np.empty_like(s), np.empty_like(s), np.empty_like(s)
        for k in np.unique(which):
            sel = which == k
            x[sel], y[sel], hdg[sel] = _geometry_pose(self.geometries[k], s[sel] - self.starts[k])
        z = np.zeros_like(s)
        if self.elevation:
            e_starts = np.array([_f(e, "s") for e in self.elevation])
            idx = np.clip(np.searchsorted(e_starts, s, side="right") - 1, 0, len(self.elevation) - 1)
            for k in np.unique(idx):
                e, sel = self.elevation[k], idx == k
                ds = s[sel] - e_starts[k]
                z[sel] = _f(e, "a") + _f(e, "b") * ds + _f(e, "c") * ds**2 + _f(e, "d") * ds**3
        return x, y, hdg, z


def _geometry_pose(g: ET.Element, ds: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Position and heading at ``ds`` metres along one planView geometry."""
    x0, y0, h, length = _f(g, "x"), _f(g, "y"), _f(g, "hdg"), _f(g, "length")
    kind = next(iter(g), None)
    tag = kind.tag if kind is not None else "line"
    if tag == "arc" and _f(kind, "curvature") != 0.0:
        k = _f(kind, "curvature")
        return x0 + (np.sin(h + k * ds) - math.sin(h)) / k, y0 - (np.cos(h + k * ds) - math.cos(h)) / k, h + k * ds
    if tag in ("spiral", "poly3", "paramPoly3"):
        if tag == "spiral":  # integrate the heading along the arc length
            k0, k1 = _f(kind, "curvStart"), _f(kind, "curvEnd")
            p = np.linspace(0.0, 1.0, 65)[None, :] * ds[:, None]
            heading = k0 * p + (k1 - k0) * p**2 / (2 * max(length, 1e-12))
            u = np.trapezoid(np.cos(heading), p, axis=1)
            v = np.trapezoid(np.sin(heading), p, axis=1)
            local_h = heading[:, -1]
        else:
            if tag == "poly3":
                cu, cv = (0.0, 1.0, 0.0, 0.0), tuple(_f(kind, c) for c in "abcd")
                normalized = False
            else:
                cu = tuple(_f(kind, f"{c}U") for c in "abcd")
                cv = tuple(_f(kind, f"{c}V") for c in "abcd")
                normalized = kind.get("pRange", "normalized") == "normalized"
            u, v, local_h = _cubic_pose(cu, cv, ds, length, normalized, tag == "poly3")
        c, s = math.cos(h), math.sin(h)
        return x0 + u * c - v * s, y0 + u * s + v * c, h + local_h
    return x0 + ds * math.cos(h), y0 + ds * math.sin(h), np.full_like(ds, h)


def _cubic_pose(cu, cv, ds, length, normalized, by_arc_length):
    """Local position and heading of a cubic curve at arc length ``ds``; poly3 is inverted numerically."""

    def at(p):
        return (
            cu[0] + cu[1] * p + cu[2] * p**2 + cu[3] * p**3,
            cv[0] + cv[1] * p + cv[2] * p**2 + cv[3] * p**3,
            math.nan,
        )

    if by_arc_length:  # poly3: parameter u along the local x axis; find u with the arc length ds
        u = np.linspace(0.0, max(length, 1e-9) * 1.5, 2001)
        arc = np.concatenate([[0.0], np.cumsum(np.hypot(np.diff(u), np.diff(at(u)[1])))])
        p = np.interp(ds, arc, u)
    else:
        p = ds / max(length, 1e-12) if normalized else ds
    x, y, _ = at(p)
    du = cu[1] + 2 * cu[2] * p + 3 * cu[3] * p**2
    dv = cv[1] + 2 * cv[2] * p + 3 * cv[3] * p**2
    return x, y, np.arctan2(dv, du)


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
