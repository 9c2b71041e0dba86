"""Drawing frames onto a matplotlib ``Axes``, frame after frame: :class:`FramePainter`, which :func:`~.frame.plot_frame`
and :func:`~.animate.animate` share (objects filled by visibility, the visible region, sensors' fields of view, the
occluders of a chosen target, a pointer to a target off the picture, static occluders, lanes, legend, scale bar).

Every drawn object carries a ``gid`` naming what it is (``"object 3"``, ``"ego"``, ``"region"``,
``"static 0"``, ``"sensor front_camera"``, ``"lane"``, ``"scale bar"``, ``"target pointer"``), so figures can be
checked and styled after the fact.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from ._optional import require
from .data import FrameView, Source
from .labels import place_labels
from .painting import ScaleBar, draw_lanes, draw_sensor, draw_statics, legend_handles
from .style import (
    EGO_EDGE,
    EGO_FACE,
    OCCLUDER_EDGE,
    REGION_ALPHA,
    REGION_FACE,
    STATIC_EDGE,
    TARGET_EDGE,
    VISIBILITY_CMAP,
    percent,
    sensor_colour,
    visibility_colour,
)
from .window import Window

LABEL_SIZE = 7  # points
LABEL_PAD = 0.15  # the label's white backing around its text, in font sizes
OUTLINE_PX = 2.0  # pixels an object's outline reaches beyond its ring (half the widest outline's width, and a margin)
SMALL_PX = 7.0
"""Pixels: a road user drawn smaller than this across (a pedestrian, a bicycle far out) is shown as a marker of this
size filled with its colour, as its outline alone would cover its fill."""
EGO_DETAIL_PX = 40.0
"""Pixels: an ego drawn smaller than this across (a sensors' reach of 80 m) gets no dots at its sensors' mounts (the
fields of view start there) and a star of :data:`STAR_SHARE` of its size (4 points at least), so its colour stays
in sight."""
STAR_SHARE = 0.4
STAR_PT = 10.0  # points: the star at the ego's centre where the ego is large enough


def renderer_of(figure: Any) -> Any:
    """The renderer that lays out ``figure``'s text: its canvas's (Agg, cairo), else the one matplotlib itself
    uses to lay out a figure whose canvas draws none of its own (a ``Figure`` made without pyplot, svg, pdf)."""
    get = getattr(figure.canvas, "get_renderer", None)
    return get() if get is not None else figure._get_renderer()


def drawn_sizes(ax: Any, rings: Sequence[np.ndarray]) -> np.ndarray:
    """How many pixels each outline spans at most on ``ax`` (after its limits are set)."""
    ax.apply_aspect()
    to_pixels = ax.transData.transform
    return np.array([float(np.ptp(to_pixels(r), axis=0).max()) if len(r) else 0.0 for r in rings])


class FramePainter:
    """Draws frames of one recording, seen from one ego, onto one matplotlib ``Axes``, frame after frame.

    What does not change between frames (static occluders, lanes, colour bar, legend, scale bar) is drawn once;
    :meth:`draw` replaces the rest. Used by :func:`plot_frame` (one frame), :func:`~.animate.animate` (many).

    ``window`` (see :mod:`.window`) is widened to the axes' shape by :meth:`fit` before the first frame.
    """

    def __init__(
        self,
        ax: Any,
        source: Source,
        ego_idx: int,
        *,
        target: int | None = None,
        sensors: Sequence[Any] = (),
        window: Window | None = None,
        cmap: str = VISIBILITY_CMAP,
        legend: bool = True,
        colorbar: bool = True,
        legend_columns: int = 4,
        hiders: bool = True,
        region: bool = True,
        choices: str = "",
    ) -> None:
        plt = require("matplotlib.pyplot")
        colors = require("matplotlib.colors")
        self.patches = require("matplotlib.patches")
        self.ax, self.source, self.ego_idx, self.target = ax, source, int(ego_idx), target
        self.sensors = tuple(sensors)
        self.window = window
        self.choices = choices  # the question's choices in words, under the title
        self.hiders = hiders
        try:
            self.cmap = plt.get_cmap(cmap)
        except ValueError:
            raise ValueError(f"cmap {cmap!r} is not a matplotlib colour map (e.g. 'cividis', 'viridis')") from None
        self.norm = colors.Normalize(0.0, 1.0)
        self._dynamic: list[Any] = []
        self._label_pool: list[Any] = []
        self._text_sizes: dict[str, tuple[float, float]] = {}
        self._scale: Any = None
        draw_lanes(ax, source.lanes)
        self._static_patches = draw_statics(ax, source.statics)
        if colorbar:
            mappable = plt.cm.ScalarMappable(norm=self.norm, cmap=self.cmap)
            bar = ax.figure.colorbar(mappable, ax=ax, fraction=0.03, pad=0.01)
            seen = "best sensor" if self.sensors else "ego"
            bar.set_label(f"visibility ({seen})", fontsize=8)
            bar.set_ticks([0, 0.25, 0.5, 0.75, 1.0], labels=["0 %", "25 %", "50 %", "75 %", "100 %"])
            bar.ax.tick_params(labelsize=7)
        ax.set_aspect("equal")
        ax.set_xlabel("x [m]", fontsize=8)
        ax.set_ylabel("y [m]", fontsize=8)
        ax.tick_params(labelsize=7)
        self._legend_options = (region, legend_columns)
        self._legend: Any = None
        if legend:
            self._add_legend(None)

    def _add_legend(self, extent: tuple[float, float, float, float] | None) -> None:
        ax, (region, columns) = self.ax, self._legend_options
        handles = legend_handles(self.source, self.ego_idx, self.target, self.sensors, hiders=self.hiders,
                                 region=region, extent=extent)  # fmt: skip
        figure = ax.figure
        engine = figure.get_layout_engine()
        if engine is not None and type(engine).__name__ == "ConstrainedLayoutEngine":
            renderer = renderer_of(figure)
            for ncol in range(min(columns, len(handles)), 0, -1):  # as many columns as the figure's width holds
                self._legend = figure.legend(handles=handles, loc="outside lower center", ncol=ncol, fontsize=7,
                                             frameon=False)  # fmt: skip
                if ncol == 1 or self._legend.get_window_extent(renderer).width <= 0.98 * figure.bbox.width:
                    break
                self._legend.remove()
        else:  # a figure laid out by the caller: keep the legend inside the axes
            self._legend = ax.legend(handles=handles, loc="lower left", fontsize=6, framealpha=0.85, ncol=2)

    def show_only(self, extent: tuple[float, float, float, float]) -> bool:
        """Keep in the legend only the static occluders and lanes within ``extent`` ``(x0, x1, y0, y1)``, all the
        picture (or animation) will show; True if the legend changed (then :meth:`fit` again: its size may
        have)."""
        if self._legend is None:
            return False
        before = [t.get_text() for t in self._legend.get_texts()]
        wanted = legend_handles(self.source, self.ego_idx, self.target, self.sensors, hiders=self.hiders,
                                region=self._legend_options[0], extent=extent)  # fmt: skip
        if [h.get_label() for h in wanted] == before:
            return False
        self._legend.remove()
        self._add_legend(extent)
        return True

    def fit(self) -> Window | None:
        """Widen the window to the shape the layout gives the axes, and put the scale bar in; returns the window."""
        if self.window is None:
            return None
        if self._scale is not None:  # fitted again (the legend changed): the old bar, unplaced, would upset the layout
            self._scale.line.remove()
            self._scale.label.remove()
            self._scale = None
        fig = self.ax.figure
        engine = fig.get_layout_engine()
        if engine is not None:
            engine.execute(fig)
        box = self.ax.get_position(original=True)
        width, height = fig.get_size_inches()
        self.window = self.window.fitted((box.width * width) / (box.height * height))
        self._scale = ScaleBar(self.ax, 2 * self.window.half_width)
        return self.window

    # -- every frame ------------------------------------------------------------------------------------------
    def draw(self, view: FrameView, limits: tuple[float, float, float, float] | None = None, title: str = "") -> None:
        """Draw ``view``, replacing the previous frame; ``limits`` ``(x0, x1, y0, y1)`` metres, else the window
        around the ego (else, without a window, the whole frame)."""
        for a in self._dynamic:
            a.remove()
        self._dynamic = []
        ax, add = self.ax, self._dynamic.append
        if limits is None and self.window is not None:
            limits = self.window.around(view.observer)
        if limits is None:
            x0, y0, x1, y1 = shapely.MultiPoint(np.concatenate(view.rings)).buffer(5).bounds
            limits = (x0, x1, y0, y1)
        ax.set_xlim(limits[0], limits[1])
        ax.set_ylim(limits[2], limits[3])
        if self._scale is not None:
            self._scale.place(limits)
        path = require("matplotlib.path").Path
        for part in getattr(view.region, "geoms", [view.region]):
            if isinstance(part, shapely.Polygon) and not part.is_empty:  # holes stay holes (they run the other way)
                part = shapely.geometry.polygon.orient(part, 1.0)
                rings = [path(np.asarray(r.coords), closed=True) for r in (part.exterior, *part.interiors)]
                patch = self.patches.PathPatch(path.make_compound_path(*rings), facecolor=REGION_FACE, lw=0,
                                               alpha=REGION_ALPHA, zorder=-3)  # fmt: skip
                patch.set_gid("region")
                add(ax.add_artist(patch))  # (add_artist: no data limits to update)
        target_row = view.row_of(self.target)
        shown = target_row is not None and on_picture(view.rings[target_row], limits)
        # what hides the target is outlined only where the target is on the picture (else a pointer says where)
        occluders = set(view.occluders.get(self.target, [])) if shown and self.hiders else set()
        static_occluders = set(view.static_occluders.get(self.target, [])) if shown and self.hiders else set()
        for k, artists in self._static_patches.items():
            colour = OCCLUDER_EDGE if k in static_occluders else STATIC_EDGE
            for a in artists:
                (a.set_edgecolor if hasattr(a, "set_edgecolor") else a.set_color)(colour)
        size = drawn_sizes(ax, view.rings)
        for i, idx in enumerate(view.idx.tolist()):
            if i == view.ego_row:
                face, edge, lw, ls, gid = EGO_FACE, EGO_EDGE, 1.0, "-", "ego"
            else:
                seen = view.visibility[i]  # NaN: the table has no row of it (not among the targets): context
                face = self.cmap(self.norm(seen)) if np.isfinite(seen) else visibility_colour(seen)
                edge, lw, ls, gid = "#333333", 0.6, "-", f"object {idx}"
            if idx in occluders:
                edge, lw = OCCLUDER_EDGE, 2.5
            patch = self.patches.Polygon(view.rings[i], facecolor=face, edgecolor=edge, lw=lw, ls=ls, zorder=2)
            patch.set_gid(gid)
            add(ax.add_artist(patch))
            if size[i] < SMALL_PX:  # a pedestrian or a motorbike far out: its outline would cover its fill
                patch.set_linewidth(0.0)
                marker = ax.plot(*view.position[i], marker="o", ms=SMALL_PX * 72 / ax.figure.dpi, mfc=face,
                                 mec=edge, mew=min(lw, 1.0), ls="none", zorder=2.5)[0]  # fmt: skip
                marker.set_gid(f"{gid} marker")
                add(marker)
            if idx == self.target and idx not in occluders:  # a white ring under the dashes: seen on a dark fill
                small = size[i] < SMALL_PX
                per_pixel = (ax.get_xlim()[1] - ax.get_xlim()[0]) / max(ax.bbox.width, 1.0)  # metres
                if small:
                    circle = [[np.cos(a), np.sin(a)] for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)]
                    ring = view.position[i] + SMALL_RING * per_pixel * np.array(circle)
                else:  # around the body, not on it: a thin target (a motorbike) keeps its fill in sight
                    around = HALO_PT / 2 * ax.figure.dpi / 72 * per_pixel
                    body = shapely.Polygon(view.rings[i]).buffer(around, join_style="mitre")
                    ring = np.asarray(body.exterior.coords)[:-1]
                for colour, width, style in (("white", HALO_PT, "-"), (TARGET_EDGE, 2.0, "--")):
                    halo = self.patches.Polygon(ring, fill=False, edgecolor=colour, lw=width, ls=style, zorder=2.6)
                    halo.set_gid("target outline")
                    add(ax.add_artist(halo))
        ego_px = size[view.ego_row] if view.ego_row is not None else np.inf
        star = STAR_PT if ego_px >= EGO_DETAIL_PX else max(4.0, STAR_SHARE * ego_px * 72 / ax.figure.dpi)
        add(ax.plot(*view.observer, marker="*", color="white", mec="black", ms=star, mew=0.8, zorder=4, gid="star")[0])
        if target_row is not None and not shown:
            add(self._pointer(view, target_row, limits))
        for k, s in enumerate(self.sensors):
            mount = ego_px >= EGO_DETAIL_PX
            self._dynamic.extend(draw_sensor(ax, s, view, sensor_colour(k), limits, mount=mount))
        self._dynamic.extend(self._labels(view, limits, occluders))
        title = title or f"frame {view.frame}, t = {view.total_nanos / 1e9:.2f} s, seen from idx {self.ego_idx}"
        ax.set_title(f"{title}\n{self.choices}" if self.choices else title, fontsize=9)

    def _pointer(self, view: FrameView, row: int, limits: tuple[float, float, float, float]) -> Any:
        """An arrow at the picture's edge towards the target off the picture, with its idx, visibility and
        distance from the ego."""
        x0, x1, y0, y1 = limits
        centre = np.array([(x0 + x1) / 2, (y0 + y1) / 2])
        towards = view.position[row] - centre
        half = np.array([(x1 - x0) / 2, (y1 - y0) / 2]) * POINTER_INSET
        scale = np.min(np.where(np.abs(towards) > 0, half / np.maximum(np.abs(towards), 1e-12), np.inf))
        tip, tail = centre + towards * scale, centre + towards * scale * 0.7
        distance = float(np.hypot(*(view.position[row] - view.observer)))
        seen = view.visibility[row]
        text = f"target {self.target}" + (f": {percent(seen)}" if np.isfinite(seen) else "") + f", {distance:.0f} m"
        box = {"boxstyle": "round,pad=0.2", "fc": "white", "ec": TARGET_EDGE, "ls": "--"}
        arrow = self.ax.annotate(text, xy=tip, xytext=tail, ha="center", va="center", fontsize=8, zorder=5, bbox=box,
                                 arrowprops={"arrowstyle": "-|>", "color": TARGET_EDGE, "lw": 1.4})  # fmt: skip
        arrow.set_gid("target pointer")
        return arrow

    def _labels(self, view: FrameView, limits: tuple[float, float, float, float], hiders: set[int]) -> list[Any]:
        """``idx: visibility`` beside each object on the picture (``ego idx`` for the ego), none overlapping
        another label nor covering another object: the ego's first, then the target's, then the others from the
        nearest to the ego. Only the ego's, the target's and those of what ``hiders`` it may cover another object
        where no clear place is left; any other label without a clear place is left out (see
        :func:`~.labels.place_labels`)."""
        ax = self.ax
        ax.apply_aspect()
        to_pixels = ax.transData.transform
        x0, x1, y0, y1 = limits
        (ax0, ay0), (ax1, ay1) = to_pixels([(x0, y0), (x1, y1)])
        area = (min(ax0, ax1), min(ay0, ay1), max(ax0, ax1), max(ay0, ay1))
        distance = np.hypot(*(view.position - view.observer).T)
        order = sorted(
            range(len(view.idx)),
            key=lambda i: (i != view.ego_row, int(view.idx[i]) != self.target, float(distance[i])),
        )
        boxes, sizes, texts, cover = [], [], [], []
        for i in order:
            idx = int(view.idx[i])
            seen = view.visibility[i]
            text = f"ego {idx}" if i == view.ego_row else f"{idx}: {percent(seen)}" if np.isfinite(seen) else f"{idx}"
            px = to_pixels(view.rings[i])
            (bx0, by0), (bx1, by1) = px.min(axis=0), px.max(axis=0)
            cx, cy, half = (bx0 + bx1) / 2, (by0 + by1) / 2, SMALL_PX / 2  # a small one is drawn as its marker
            bx0, by0 = min(bx0, cx - half) - OUTLINE_PX, min(by0, cy - half) - OUTLINE_PX  # with its outline
            bx1, by1 = max(bx1, cx + half) + OUTLINE_PX, max(by1, cy + half) + OUTLINE_PX
            boxes.append((bx0, by0, bx1, by1))
            sizes.append(self._text_size(text))
            texts.append(text)
            cover.append(i == view.ego_row or idx == self.target or idx in hiders)
        from_pixels = ax.transData.inverted().transform
        places = place_labels(boxes, sizes, area, cover)
        shown = [(t, b) for t, b in zip(texts, places, strict=True) if b is not None]
        backing = {"boxstyle": f"square,pad={LABEL_PAD}", "facecolor": "white", "alpha": 0.75, "lw": 0}
        while len(self._label_pool) < len(shown):  # text artists are reused from frame to frame: far faster
            self._label_pool.append(ax.text(0, 0, "", ha="center", va="center", fontsize=LABEL_SIZE, zorder=5,
                                            clip_on=True, bbox=backing, gid="label"))  # fmt: skip
        for k, label in enumerate(self._label_pool):
            if k < len(shown):
                text, box = shown[k]
                label.set_text(text)
                label.set_position(from_pixels(((box[0] + box[2]) / 2, (box[1] + box[3]) / 2)))
            label.set_visible(k < len(shown))
        return []

    def _text_size(self, text: str) -> tuple[float, float]:
        """Pixels (width, height) a label takes with its white backing, as the renderer lays the text out
        (measured once per text: labels repeat from frame to frame)."""
        size = self._text_sizes.get(text)
        if size is None:
            figure = self.ax.figure
            renderer = renderer_of(figure)
            font = require("matplotlib.font_manager").FontProperties(size=LABEL_SIZE)
            width, height, _ = renderer.get_text_width_height_descent(text, font, ismath=False)
            pad = 2 * LABEL_PAD * LABEL_SIZE * figure.dpi / 72  # the backing's pad, on both sides
            size = self._text_sizes[text] = (width + pad, max(height, LABEL_SIZE * figure.dpi / 72) + pad)
        return size


HALO_PT = 4.0
"""Points: the white halo under a target's dashed outline, drawn around the target (so its fill stays in sight)."""
SMALL_RING = 9.0
"""Pixels: the radius of the dashed ring around a target drawn as a marker (too small for its outline)."""
POINTER_INSET = 0.95
"""Where a pointer to a target off the picture sits: this share of the way from the centre to the edge."""


def on_picture(ring: np.ndarray, limits: tuple[float, float, float, float]) -> bool:
    """Whether any of the outline ``ring`` lies within ``limits`` ``(x0, x1, y0, y1)`` (its bounding box meets
    them).

    >>> on_picture(np.array([[9.0, 0.0], [11.0, 0.0], [11.0, 1.0]]), (0.0, 10.0, -5.0, 5.0))
    True
    """
    x0, x1, y0, y1 = limits
    (a, b), (c, d) = ring.min(axis=0), ring.max(axis=0)
    return bool(c >= x0 and a <= x1 and d >= y0 and b <= y1)
