"""One frame seen from the ego: objects filled by visibility, the visible region, sensors' fields of view, the
occluders of a chosen target, static occluders and map lanes (matplotlib).

Every drawn object carries a ``gid`` naming what it is (``"object 3"``, ``"ego"``, ``"region"``,
``"static 0"``, ``"sensor front_camera"``, ``"lane"``), so figures can be checked and styled after the fact.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from ..inputs.sensors import sensor_poses
from ._optional import require
from .data import FrameView, FrameViewer, Source, load_source, sensor_list

EGO_FACE, EGO_EDGE = "#1f5fbf", "#0b2f66"
REGION_FACE = "#ffe680"
OCCLUDER_EDGE = "black"
TARGET_EDGE = "#7b2cbf"
STATIC_FACE, STATIC_EDGE = "#bbbbbb", "#555555"
LANE_COLOUR = "#9a9a9a"
SENSOR_COLOURS = ("#1f77b4", "#ff7f0e", "#17becf", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22", "#2ca02c")


class FramePainter:
    """Draws frames of one recording, seen from one ego, onto one matplotlib ``Axes``, frame after frame.

    What does not change between frames (static occluders, lanes, colour bar, legend) is drawn once; :meth:`draw`
    replaces the rest. Used by :func:`plot_frame` (one frame) and :func:`~.animate.animate` (many).
    """

    def __init__(
        self,
        ax: Any,
        source: Source,
        ego_idx: int,
        *,
        target: int | None = None,
        sensors: Any = None,
        view_range: float | None = 80.0,
        cmap: str = "RdYlGn",
        legend: bool = True,
        colorbar: bool = True,
    ) -> None:
        plt = require("matplotlib.pyplot")
        colors = require("matplotlib.colors")
        self.patches = require("matplotlib.patches")
        self.ax, self.source, self.ego_idx, self.target = ax, source, int(ego_idx), target
        self.sensors = sensor_list(sensors, source, ego_idx)  # resolved once, not per frame
        self.view_range = view_range
        self.cmap, self.norm = plt.get_cmap(cmap), colors.Normalize(0.0, 1.0)
        self._dynamic: list[Any] = []
        self._static_patches: dict[int, list[Any]] = {}
        self._draw_lanes()
        self._draw_statics()
        if colorbar:
            mappable = plt.cm.ScalarMappable(norm=self.norm, cmap=self.cmap)
            bar = ax.figure.colorbar(mappable, ax=ax, fraction=0.03, pad=0.01)
            bar.set_label("visibility from the ego (0 hidden, 1 fully visible)", fontsize=8)
            bar.ax.tick_params(labelsize=7)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]")
        ax.set_ylabel("y [m]")
        self._legend = legend

    # -- once per figure --------------------------------------------------------------------------------------
    def _draw_lanes(self) -> None:
        for surface, centre in self.source.lanes:
            for part in getattr(surface, "geoms", [surface] if surface is not None else []):
                p = self.ax.add_patch(
                    self.patches.Polygon(np.asarray(part.exterior.coords), facecolor="#eeeeee", lw=0, zorder=-2)
                )
                p.set_gid("lane")
            for part in getattr(centre, "geoms", [centre] if centre is not None else []):
                (line,) = self.ax.plot(*np.asarray(part.coords).T, color=LANE_COLOUR, lw=0.8, ls=(0, (6, 6)), zorder=-1)
                line.set_gid("lane")

    def _draw_statics(self) -> None:
        for k, g in enumerate(self.source.statics.geometries):
            artists = []
            for part in getattr(g, "geoms", [g]):
                if isinstance(part, shapely.Polygon):
                    patch = self.patches.Polygon(
                        np.asarray(part.exterior.coords), facecolor=STATIC_FACE, hatch="///", edgecolor=STATIC_EDGE
                    )
                    artists.append(self.ax.add_patch(patch))
                elif isinstance(part, shapely.LineString | shapely.LinearRing):
                    artists.extend(self.ax.plot(*np.asarray(part.coords).T, color=STATIC_EDGE, lw=2.5, zorder=1))
            for a in artists:
                a.set_gid(f"static {k}")
            self._static_patches[k] = artists

    def _legend_handles(self, sensors: Sequence[Any]) -> list[Any]:
        P, Line2D = self.patches.Patch, require("matplotlib.lines").Line2D
        handles = [
            P(facecolor=EGO_FACE, edgecolor=EGO_EDGE, label=f"ego (idx {self.ego_idx}), ★ its viewpoint"),
            P(facecolor=REGION_FACE, alpha=0.6, label="seen from the ego"),
        ]
        if self.target is not None:
            handles.append(P(facecolor="none", edgecolor=TARGET_EDGE, lw=2, ls="--", label=f"target idx {self.target}"))
            handles.append(
                P(facecolor="none", edgecolor=OCCLUDER_EDGE, lw=2.5, label=f"occluders of idx {self.target}")
            )
        kinds = {type(part) for g in self.source.statics.geometries for part in getattr(g, "geoms", [g])}
        if shapely.Polygon in kinds:
            handles.append(P(facecolor=STATIC_FACE, edgecolor=STATIC_EDGE, hatch="///", label="static occluder"))
        if kinds & {shapely.LineString, shapely.LinearRing}:
            handles.append(Line2D([], [], color=STATIC_EDGE, lw=2.5, label="wall (static occluder)"))
        if self.source.lanes:
            handles.append(Line2D([], [], color=LANE_COLOUR, lw=0.8, ls=(0, (6, 6)), label="lane (map)"))
        for k, s in enumerate(sensors):
            reach = "unlimited" if math.isinf(s.range) else f"{s.range:g} m"
            colour = SENSOR_COLOURS[k % len(SENSOR_COLOURS)]
            handles.append(
                P(facecolor=colour, alpha=0.25, edgecolor=colour, label=f"{s.name}: {s.fov_degrees:.0f}°, {reach}")
            )
        return handles

    # -- every frame ------------------------------------------------------------------------------------------
    def draw(self, view: FrameView, limits: tuple[float, float, float, float] | None = None) -> None:
        """Draw ``view``, replacing the previous frame; ``limits`` ``(x0, x1, y0, y1)`` metres, else follow the ego."""
        for a in self._dynamic:
            a.remove()
        self._dynamic = []
        ax, add = self.ax, self._dynamic.append
        if limits is None and self.view_range is not None:
            r = self.view_range
            limits = (
                view.observer[0] - r,
                view.observer[0] + r,
                view.observer[1] - 0.35 * r,
                view.observer[1] + 0.35 * r,
            )
        if limits is not None:
            ax.set_xlim(limits[0], limits[1])
            ax.set_ylim(limits[2], limits[3])
        else:
            x0, y0, x1, y1 = shapely.MultiPoint(np.concatenate(view.rings)).buffer(5).bounds
            ax.set_xlim(x0, x1)
            ax.set_ylim(y0, y1)
        for part in getattr(view.region, "geoms", [view.region]):
            region = self.patches.Polygon(np.asarray(part.exterior.coords), facecolor=REGION_FACE, alpha=0.35, lw=0)
            region.set_zorder(0)
            region.set_gid("region")
            add(ax.add_patch(region))
        occluders = set(view.occluders.get(self.target, [])) if self.target is not None else set()
        static_occluders = set(view.static_occluders.get(self.target, [])) if self.target is not None else set()
        for k, artists in self._static_patches.items():
            colour = OCCLUDER_EDGE if k in static_occluders else STATIC_EDGE
            for a in artists:
                (a.set_edgecolor if hasattr(a, "set_edgecolor") else a.set_color)(colour)
        for i, idx in enumerate(view.idx.tolist()):
            if i == view.ego_row:
                face, edge, lw, ls, gid = EGO_FACE, EGO_EDGE, 1.0, "-", "ego"
            else:
                face, edge, lw, ls, gid = self.cmap(self.norm(view.visibility[i])), "#333333", 0.6, "-", f"object {idx}"
            if idx in occluders:
                edge, lw = OCCLUDER_EDGE, 2.5
            elif idx == self.target:
                edge, lw, ls = TARGET_EDGE, 2.0, "--"
            patch = self.patches.Polygon(view.rings[i], facecolor=face, edgecolor=edge, lw=lw, ls=ls, zorder=2)
            patch.set_gid(gid)
            add(ax.add_patch(patch))
            text = f"ego {idx}" if i == view.ego_row else f"{idx}: {view.visibility[i]:.0%}"
            add(self._label(text, view.rings[i], view.position[i]))
        observer = view.observer
        add(ax.plot(*observer, marker="*", color="white", mec="black", ms=10, zorder=4)[0])
        sensors = self.sensors
        for k, s in enumerate(sensors):
            add_all = self._draw_sensor(s, view, SENSOR_COLOURS[k % len(SENSOR_COLOURS)])
            self._dynamic.extend(add_all)
        if self._legend:
            self._legend = False  # drawn once, with the first frame
            handles = self._legend_handles(sensors)
            engine = ax.figure.get_layout_engine()
            if engine is not None and type(engine).__name__ == "ConstrainedLayoutEngine":
                ax.figure.legend(handles=handles, loc="outside lower center", ncol=4, fontsize=7, frameon=False)
            else:  # a figure laid out by the caller: keep the legend inside the axes
                ax.legend(handles=handles, loc="lower left", fontsize=6, framealpha=0.85, ncol=2)
        ax.set_title(
            f"frame {view.frame}, t = {view.total_nanos / 1e9:.2f} s: seen from idx {self.ego_idx}", fontsize=10
        )

    def _label(self, text: str, ring: np.ndarray, centre: np.ndarray) -> Any:
        """The label inside a long object (trucks, buses), else just above it."""
        x0, x1 = self.ax.get_xlim()
        if np.ptp(ring[:, 0]) > 0.06 * abs(x1 - x0):
            xy, offset, va = (centre[0], centre[1]), (0, 0), "center"
        else:
            xy, offset, va = (centre[0], float(ring[:, 1].max())), (0, 2), "bottom"
        halo = [require("matplotlib.patheffects").withStroke(linewidth=2, foreground="white")]
        return self.ax.annotate(
            text, xy, xytext=offset, textcoords="offset points", ha="center", va=va, fontsize=7, zorder=5, clip_on=True,
            path_effects=halo,
        )  # fmt: skip

    def _draw_sensor(self, s: Any, view: FrameView, colour: str) -> list[Any]:
        """The field of view as a translucent wedge and its range as a dashed arc (a circle for 360° sensors)."""
        (pos,), heading = sensor_poses(s, view.observer[None, :], np.array([view.yaw[view.ego_row]]))
        far = math.isinf(s.range)
        radius = 10.0 * (self.view_range or 100.0) if far else s.range
        full = s.fov >= 2 * math.pi - 1e-9
        if full:
            shape = self.patches.Circle(pos, radius)
        else:
            half = math.degrees(s.fov) / 2
            shape = self.patches.Wedge(pos, radius, math.degrees(heading[0]) - half, math.degrees(heading[0]) + half)
        shape.set(facecolor=colour, alpha=0.05 if not full else 0.03, lw=0, zorder=0.5, gid=f"sensor {s.name}")
        out = [self.ax.add_patch(shape)]
        if not full:  # the two edges of the field of view
            for side in (-1, 1):
                a = heading[0] + side * s.fov / 2
                end = pos + radius * np.array([math.cos(a), math.sin(a)])
                out.extend(self.ax.plot([pos[0], end[0]], [pos[1], end[1]], color=colour, lw=0.8, zorder=0.6))
        if not far:
            t1, t2 = (
                (0.0, 360.0) if full else (math.degrees(heading[0] - s.fov / 2), math.degrees(heading[0] + s.fov / 2))
            )
            arc = self.patches.Arc(pos, 2 * radius, 2 * radius, theta1=t1, theta2=t2, color=colour, lw=1.0, ls="--")
            arc.set_gid(f"range {s.name}")
            out.append(self.ax.add_patch(arc))
        out.extend(self.ax.plot(*pos, marker="o", ms=2.5, color=colour, zorder=4))
        return out


def plot_frame(
    df: Any,
    ego_idx: int,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    target: int | None = None,
    sensors: Any = None,
    lanes: Any = True,
    ax: Any = None,
    view_range: float | None = 80.0,
    cmap: str = "RdYlGn",
    legend: bool = True,
    engine: str = "visilibity",
) -> Any:
    """Draw one frame seen from ``ego_idx``; return the matplotlib ``Axes``.

    Parameters
    ----------
    df : omega_prime.Recording, polars DataFrame/LazyFrame or MCAP path
        The moving objects, as for :func:`~omega_prime_visibility.get_visibility_df`.
    ego_idx : int
        The observer; drawn in blue, its viewpoint (the centre of its bounding box) as a star.
    frame : int
        The frame number (not its position); ``ValueError`` if it does not occur or the ego is not in it.
    static_occluder_polys : sequence of shapely geometries, optional
        Drawn hatched (polygons) or as thick grey lines (walls).
    target : int, optional
        Outline this object dashed and its occluders (objects and static occluders) in black.
    sensors : layout name, JSON path, Sensor or sequence of Sensors, optional
        Each sensor's field of view is drawn as a translucent wedge at its pose on the ego, and its range as a
        dashed arc (``"typical"`` and ``"roof"`` are scaled to the ego's outline).
    lanes : bool, map or sequence of shapely geometries
        True draws the lanes of the recording's map underneath, where it has one.
    ax : matplotlib Axes, optional
        Where to draw; a new 10 x 5 inch figure by default.
    view_range : float or None
        Metres shown on each side of the ego along x (0.35 of it along y); None shows the whole frame.
    cmap : str
        Matplotlib colour map of visibility, 0 (hidden) to 1 (fully visible).
    legend : bool
        Add a legend below the axes saying what each colour and outline means.
    engine : str
        Engine of the visibility values (the visible region is always VisiLibity's).

    Objects are filled by their visibility from the ego (colour bar 0..1) and labelled ``idx: visibility``; the
    region visible from the ego is shaded yellow.

    Examples
    --------
    >>> import matplotlib
    >>> matplotlib.use("Agg")
    >>> import polars as pl
    >>> cars = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2],
    ...                      "x": [0.0, 10.0, 20.0], "y": [0.0, 0.0, 0.0], "length": [4.0, 4.0, 4.0],
    ...                      "width": [2.0, 4.0, 2.0], "yaw": [0.0, 0.0, 0.0]})
    >>> ax = plot_frame(cars, 0, 0, target=2)
    >>> sorted(p.get_gid() for p in ax.patches if p.get_gid().startswith("object"))
    ['object 1', 'object 2']
    """
    plt = require("matplotlib.pyplot")
    source = load_source(df, static_occluder_polys, lanes)
    k = source.position_of(frame)
    viewer = FrameViewer(source, ego_idx, engine, margin=2 * (view_range or 100.0))
    view = viewer.view(k)
    if ax is None:
        _, ax = plt.subplots(figsize=(10, 5), layout="constrained")
    painter = FramePainter(ax, source, ego_idx, target=target, sensors=sensors, view_range=view_range, cmap=cmap,
                           legend=legend)  # fmt: skip
    painter.draw(view)
    return ax
