"""The pieces of a frame picture that :class:`.frame.FramePainter` puts together: lanes, static occluders, sensors'
fields of view, the scale bar and the legend (matplotlib, imported when called)."""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from ..inputs.sensors import Sensor, sensor_poses
from ..inputs.statics import StaticOccluders
from ._optional import require
from .data import FrameView, Source
from .lanes import Lanes
from .style import (
    EGO_EDGE,
    EGO_FACE,
    LANE_COLOUR,
    LANE_FACE,
    OCCLUDER_EDGE,
    REGION_FACE,
    STATIC_EDGE,
    STATIC_FACE,
    TARGET_EDGE,
    sensor_colour,
)

LANE_DASHES = (0, (6, 6))


def draw_lanes(ax: Any, lanes: Lanes) -> None:
    """The road surface in grey *under* the visible region (which is drawn translucent over it, so a shadow on the
    carriageway shows as grey against the seen region's blue, as clearly as one beside the road shows as white),
    its edges as thin lines and centre lines dashed above the region, under the objects; as collections (fast to
    draw whatever the map's size; they do not change the axes' limits)."""
    collections = require("matplotlib.collections")
    if lanes.surfaces:  # one compound path: holes stay holes (they run the other way round)
        path = require("matplotlib.path").Path
        road = path.make_compound_path(*[path(ring, closed=True) for ring in lanes.surfaces])
        surfaces = collections.PathCollection([road], facecolors=LANE_FACE, linewidths=0, zorder=-4)
        surfaces.set_gid("lane")
        ax.add_collection(surfaces, autolim=False)
        edges = collections.LineCollection(lanes.surfaces, colors=LANE_COLOUR, linewidths=0.5, zorder=-1)
        edges.set_gid("road edge")
        ax.add_collection(edges, autolim=False)
    if lanes.centres:
        lines = collections.LineCollection(lanes.centres, colors=LANE_COLOUR, linewidths=0.8, linestyles=LANE_DASHES,
                                           zorder=-1)  # fmt: skip
        lines.set_gid("lane")
        ax.add_collection(lines, autolim=False)


def draw_statics(ax: Any, statics: StaticOccluders) -> dict[int, list[Any]]:
    """Static occluders: polygons hatched, walls as thick lines; returns the artists of each, by position."""
    patches = require("matplotlib.patches")
    out = {}
    for k, g in enumerate(statics.geometries):
        artists = []
        for part in getattr(g, "geoms", [g]):
            if isinstance(part, shapely.Polygon):
                patch = patches.Polygon(
                    np.asarray(part.exterior.coords), facecolor=STATIC_FACE, hatch="///", edgecolor=STATIC_EDGE
                )
                artists.append(ax.add_patch(patch))
            elif isinstance(part, shapely.LineString | shapely.LinearRing):
                artists.extend(ax.plot(*np.asarray(part.coords).T, color=STATIC_EDGE, lw=2.5, zorder=1))
        for a in artists:
            a.set_gid(f"static {k}")
        out[k] = artists
    return out


def nice_length(width: float) -> float:
    """A round length (1, 2 or 5 times a power of ten) of about a fifth of ``width`` metres, at most that.

    >>> nice_length(160.0), nice_length(37.0), nice_length(9.0)
    (20.0, 5.0, 1.0)
    """
    target = width / 5
    power = 10 ** math.floor(math.log10(target))
    return float(max(m * power for m in (1, 2, 5) if m * power <= target))


class ScaleBar:
    """A scale bar of :func:`nice_length` metres (for a scene ``width`` metres wide) in the lower right corner of
    the scene: a line in data coordinates (so it keeps its length in metres) and its label, moved with the view
    by :meth:`place` (two artists, cheap to draw in every frame of an animation)."""

    def __init__(self, ax: Any, width: float) -> None:
        self.ax, self.length = ax, nice_length(width)
        (self.line,) = ax.plot([], [], color="#222222", lw=2, solid_capstyle="butt", zorder=6, gid="scale bar")
        self.label = ax.text(0, 0, f"{self.length:g} m", ha="center", va="bottom", fontsize=7, zorder=6,
                             gid="scale bar label")  # fmt: skip

    def place(self, limits: tuple[float, float, float, float]) -> None:
        """Put the bar 4 % of the width in from the right and 6 % of the height up from the bottom of ``limits``."""
        x0, x1, y0, y1 = limits
        right, y = x1 - 0.04 * (x1 - x0), y0 + 0.06 * (y1 - y0)
        self.line.set_data([right - self.length, right], [y, y])
        self.label.set_position((right - self.length / 2, y + 0.01 * (y1 - y0)))


def sensor_pose(s: Sensor, view: FrameView) -> tuple[np.ndarray, float]:
    (pos,), heading = sensor_poses(s, view.observer[None, :], np.array([view.yaw[view.ego_row]]))
    return pos, float(heading[0])


def _far(limits: tuple[float, float, float, float]) -> float:
    """A radius that reaches beyond the picture from anywhere on it."""
    return 2.0 * math.hypot(limits[1] - limits[0], limits[3] - limits[2])


def draw_sensor(
    ax: Any, s: Sensor, view: FrameView, colour: str, limits: tuple[float, float, float, float], mount: bool = True
) -> list:
    """A sensor's field of view outlined in ``colour`` (its range as the arc; a circle for a 360° sensor; the two
    edges only when unlimited) and, with ``mount``, a dot at its position. The outline lies under the road users
    (zorder 1.5: a field's edge never crosses a car), above the seen region and the road."""
    patches = require("matplotlib.patches")
    pos, heading = sensor_pose(s, view)
    radius = min(s.range, _far(limits))
    style = {"fill": False, "edgecolor": colour, "lw": 1.4, "zorder": 1.5, "gid": f"sensor {s.name}"}
    if s.fov >= 2 * math.pi - 1e-9:
        shape = patches.Circle(pos, radius, **style)
    else:
        half = math.degrees(s.fov) / 2
        shape = patches.Wedge(pos, radius, math.degrees(heading) - half, math.degrees(heading) + half, **style)
    out = [] if s.fov >= 2 * math.pi - 1e-9 and math.isinf(s.range) else [ax.add_artist(shape)]
    if mount:
        out.extend(ax.plot(*pos, marker="o", ms=3, color=colour, mec="white", mew=0.5, zorder=4, gid="mount"))
    return out


NO_REGION = "3D: seen from the eye (no ground region)"
"""The legend's words where a 3D picture shades no seen region."""


def legend_handles(
    source: Source,
    ego_idx: int,
    target: int | None,
    sensors: Sequence[Sensor],
    hiders: bool = True,
    region: bool = True,
    extent: tuple[float, float, float, float] | None = None,
) -> list[Any]:
    """What each colour and outline means, in few words; sensors by name with their field of view and range;
    ``hiders`` False: the target's occluders are outlined nowhere (nothing hides it), so no "hides" entry;
    ``region`` True: the seen region's tint, and what is not seen (untinted: white, or the bare road surface);
    ``region`` False (3D): no seen region is shaded, and the legend says why; ``extent`` ``(x0, x1, y0, y1)``:
    what the picture shows, so that static occluders and lanes off it get no entry."""
    P, Line2D = require("matplotlib.patches").Patch, require("matplotlib.lines").Line2D
    seen = "seen by the sensors" if sensors else "seen from the ego"
    handles = [P(facecolor=EGO_FACE, edgecolor=EGO_EDGE, label=f"ego {ego_idx} (★ centre)")]
    if region:
        handles.append(P(facecolor=REGION_FACE, label=seen))
        bare = "white or bare road" if source.lanes and source.lanes.surfaces else "white"
        handles.append(P(facecolor="white", edgecolor="#999999", lw=0.6, label=f"not seen ({bare})"))
    else:
        handles.append(P(facecolor="none", edgecolor="none", label=NO_REGION))
    if target is not None:
        handles.append(P(facecolor="none", edgecolor=TARGET_EDGE, lw=2, ls="--", label=f"target {target}"))
        if hiders:
            handles.append(P(facecolor="none", edgecolor=OCCLUDER_EDGE, lw=2.5, label=f"hides {target}"))
    shown = source.statics.geometries
    if extent is not None:
        shown = [g for g in shown if shapely.intersects(g, shapely.box(extent[0], extent[2], extent[1], extent[3]))]
    kinds = {type(part) for g in shown for part in getattr(g, "geoms", [g])}
    if shapely.Polygon in kinds:
        handles.append(P(facecolor=STATIC_FACE, edgecolor=STATIC_EDGE, hatch="///", label="static occluder"))
    if kinds & {shapely.LineString, shapely.LinearRing}:
        handles.append(Line2D([], [], color=STATIC_EDGE, lw=2.5, label="wall"))
    points = source.lanes.points if source.lanes else np.zeros((0, 2))
    if extent is not None and len(points):
        x, y = points[:, 0], points[:, 1]
        points = points[(x >= extent[0]) & (x <= extent[1]) & (y >= extent[2]) & (y <= extent[3])]
    if len(points):
        handles.append(Line2D([], [], color=LANE_COLOUR, lw=0.8, ls=LANE_DASHES, label="lane"))
    for k, s in enumerate(sensors):
        reach = "" if math.isinf(s.range) else f" {s.range:g} m"
        handles.append(Line2D([], [], color=sensor_colour(k), lw=1.6, label=f"{s.name} {s.fov_degrees:.0f}°{reach}"))
    return handles
