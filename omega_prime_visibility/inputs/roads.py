"""The roads of an OpenDRIVE map: reference lines (``line``, ``arc``, ``spiral``, ``poly3``, ``paramPoly3``
geometries, with the elevation profile), how wide each road is, and points along them; what the map checks and
the map's road objects (:mod:`..threed.mapobjects`) are placed with.

Lengths are metres, headings radians counter-clockwise from +x, in the map's frame.
"""

from __future__ import annotations

import math
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np


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


class MapNotice(UserWarning):
    """What map a recording was read with, or that the map given does not fit its objects."""


ROAD_WIDTH = 10.0
"""Metres on each side of a reference line taken as the road where its lanes give no width."""


def road_widths(road: ET.Element) -> tuple[float, float]:
    """How far (metres) a road's lanes reach from its reference line to its left and to its right, at the widest
    lane section: the lanes' widths (``a`` and the cubic at the section's end) summed per side, each side widened
    by the largest lane offset; :data:`ROAD_WIDTH` on both sides where no lane gives a width.

    >>> xml = '<road length="100"><lanes><laneOffset s="0" a="0.5"/><laneSection s="0"><left>'
    >>> xml += '<lane id="1"><width sOffset="0" a="3.5"/></lane></left><right><lane id="-1"><width sOffset="0" a="3"/>'
    >>> xml += '</lane><lane id="-2"><width sOffset="0" a="3"/></lane></right></laneSection></lanes></road>'
    >>> road_widths(ET.fromstring(xml))
    (4.0, 6.5)
    """
    length = _f(road, "length", 0.0)
    sections = sorted(road.findall("lanes/laneSection"), key=lambda e: _f(e, "s"))
    widest = {"left": 0.0, "right": 0.0}
    for k, section in enumerate(sections):
        end = _f(sections[k + 1], "s") if k + 1 < len(sections) else length
        span = max(end - _f(section, "s"), 0.0)
        for side in widest:
            total = 0.0
            for lane in section.findall(f"{side}/lane"):
                widths = [0.0]
                for w in lane.findall("width"):
                    a, b, c, d = (_f(w, name) for name in "abcd")
                    ds = max(span - _f(w, "sOffset"), 0.0)
                    widths += [abs(a), abs(a + b * ds + c * ds**2 + d * ds**3)]
                total += max(widths)
            widest[side] = max(widest[side], total)
    if widest["left"] == widest["right"] == 0.0:
        return ROAD_WIDTH, ROAD_WIDTH
    offset = max((abs(_f(o, "a")) for o in road.findall("lanes/laneOffset")), default=0.0)
    return widest["left"] + offset, widest["right"] + offset


def road_points(root: ET.Element, spacing: float = 2.0) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Points every ``spacing`` metres (at most) along every road's reference line, the line's heading there, and
    per point its road's :func:`road_widths` (shape (k, 2): left, right); roads whose geometry cannot be read are
    left out.

    >>> xml = '<OpenDRIVE><road length="10"><planView><geometry s="0" x="0" y="0" hdg="0" length="10"><line/>'
    >>> xml += '</geometry></planView></road></OpenDRIVE>'
    >>> points, heading, half = road_points(ET.fromstring(xml), spacing=5.0)
    >>> points.tolist(), heading.tolist(), half.tolist()
    ([[0.0, 0.0], [5.0, 0.0], [10.0, 0.0]], [0.0, 0.0, 0.0], [[10.0, 10.0], [10.0, 10.0], [10.0, 10.0]])
    """
    points, headings, halves = [], [], []
    for road in root.iter("road"):
        try:
            line = ReferenceLine(road)
            ends = [_f(g, "s") + _f(g, "length") for g in line.geometries]
            total = max(_f(road, "length", 0.0), max(ends))
            if not (math.isfinite(total) and total >= 0):
                continue
            s = np.linspace(0.0, total, math.ceil(total / spacing) + 1)
            x, y, heading, _ = line.pose(s)
        except (ValueError, TypeError, ZeroDivisionError):
            continue
        ok = np.isfinite(x) & np.isfinite(y) & np.isfinite(heading)
        points.append(np.column_stack([x[ok], y[ok]]))
        headings.append(heading[ok])
        halves.append(np.tile(road_widths(road), (int(ok.sum()), 1)))
    if not points:
        return np.zeros((0, 2)), np.zeros(0), np.zeros((0, 2))
    return np.concatenate(points), np.concatenate(headings), np.concatenate(halves)


OFF_ROAD = 2.0
"""Metres beyond a road's lanes (:func:`.roads.road_widths`, on the side of the reference line a position lies)
at which a position is *off the map*."""
OFF_MAP_SHARE = 0.2
"""Share of the sampled positions off the map at which a map is told not to fit the recording."""
ALIGNED = 0.5
"""Sine of the largest angle between a vehicle's heading and a road's at which it drives along that road (30°)."""
SAMPLES = 20
"""Positions of each moving object that the map check looks at, spread over its rows."""


def check_map_fits(recording: Any, map_path: Path, root: ET.Element | None = None) -> None:
    """Warn when the OpenDRIVE map given does not fit the recording's moving objects: a map that is not the trace's
    own (or in another frame) would draw its lanes elsewhere and put its road objects in the wrong place.

    Each object's positions (:data:`SAMPLES` of them) are compared with points every 2 m along the roads'
    reference lines: a position is *on the map* where it lies beside such a point (within 2 m along the line) and
    within the road's lanes on that side plus :data:`OFF_ROAD` metres and, for a vehicle (omega-prime's type 2)
    whose heading is known, heads along that road (either way, within 30°: a trace on another map's road that
    happens to cross it is not on it); the map is told not to fit when :data:`OFF_MAP_SHARE` of the positions or
    more are off it (a :class:`MapNotice`). ``root``: the map's XML, parsed already.
    """
    from scipy.spatial import cKDTree

    if root is None:
        odr_xml = getattr(recording.map, "odr_xml", None)
        if not isinstance(odr_xml, str):
            return
        root = ET.fromstring(odr_xml)
    points, headings, halves = road_points(root)
    names = recording._df.columns
    df = recording._df.select("idx", "x", "y", *(c for c in ("yaw", "type") if c in names)).drop_nulls(
        ["idx", "x", "y"]
    )
    if not len(points) or df.height == 0:
        return
    rows = df.sort("idx", maintain_order=True)
    starts = np.flatnonzero(np.r_[True, np.diff(rows["idx"].to_numpy()) != 0])
    ends = np.r_[starts[1:], rows.height]
    spread = [np.linspace(a, b - 1, SAMPLES).astype(np.int64) for a, b in zip(starts, ends, strict=True)]
    picks = np.unique(np.concatenate(spread))
    xy = rows.select("x", "y").to_numpy()[picks]
    finite = np.isfinite(xy).all(axis=1)
    picks, xy = picks[finite], xy[finite]
    if not len(picks):
        return
    reach = float(np.hypot(halves.max(), 2.0)) + OFF_ROAD
    near = cKDTree(points).query_ball_point(xy, reach)
    vehicle = rows["type"].to_numpy()[picks] == 2 if "type" in names else np.zeros(len(picks), dtype=bool)
    yaw = rows["yaw"].cast(float).fill_null(np.nan).to_numpy()[picks] if "yaw" in names else np.full(len(picks), np.nan)
    vehicle &= np.isfinite(yaw)  # the heading test only where a heading is known
    on = np.zeros(len(picks), dtype=bool)
    for k, found in enumerate(near):
        found = np.asarray(found, dtype=np.int64)
        if not len(found):
            continue
        dx, dy = (xy[k] - points[found]).T
        c, s = np.cos(headings[found]), np.sin(headings[found])
        along, left = c * dx + s * dy, c * dy - s * dx  # in the road's frame at each point
        side = np.where(left >= 0, halves[found, 0], halves[found, 1])
        close = (np.abs(along) <= 2.0) & (np.abs(left) <= side + OFF_ROAD)
        if vehicle[k]:
            close &= np.abs(np.sin(headings[found] - yaw[k])) <= ALIGNED
        on[k] = close.any()
    off = ~on
    if off.mean() >= OFF_MAP_SHARE:
        k = int(np.flatnonzero(off)[0])
        idx = rows["idx"][int(picks[k])]
        objects = len(np.unique(rows["idx"].to_numpy()[picks[off]]))
        warnings.warn(
            f"the map {map_path.name} does not fit the recording: {off.mean():.0%} of its objects' positions "
            f"({objects} of {len(starts)} objects) lie off every road of it (more than {OFF_ROAD:g} m beyond "
            f"its lanes, or driving across them; e.g. idx {idx} at ({xy[k, 0]:.0f}, {xy[k, 1]:.0f}) m): is it this "
            "trace's map? Lanes in pictures and --map-occluders would come from the wrong map",
            MapNotice,
            stacklevel=3,
        )
