"""One frame seen from the ego: objects filled by visibility, the visible region, sensors' fields of view, the
occluders of a chosen target, static occluders and map lanes (matplotlib).

Every drawn object carries a ``gid`` naming what it is (``"object 3"``, ``"ego"``, ``"region"``,
``"static 0"``, ``"sensor front_camera"``, ``"lane"``, ``"scale bar"``), so figures can be checked and styled after
the fact. What part of the scene is shown follows :mod:`.window`'s rule.
"""

from __future__ import annotations

import math
import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np
import shapely

from ..query import Query
from ._optional import require
from .data import (
    FrameView,
    FrameViewer,
    Source,
    describe_question,
    frames_table,
    load_source,
    needs_table,
    picture_question,
    sensor_list,
)
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
    sensor_colour,
    visibility_colour,
)
from .window import AUTO, Window, default_reach, scene_window

LABEL_SIZE = 7  # points
SMALL_PX = 7.0
"""Pixels: a road user drawn smaller than this across (a pedestrian, a bicycle far out) is shown as a marker of this
size filled with its colour, as its outline alone would cover its fill."""


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
        engine = ax.figure.get_layout_engine()
        if engine is not None and type(engine).__name__ == "ConstrainedLayoutEngine":
            self._legend = ax.figure.legend(handles=handles, loc="outside lower center", ncol=columns, fontsize=7,
                                            frameon=False)  # fmt: skip
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
            elif idx == self.target:
                edge, lw, ls = TARGET_EDGE, 2.0, "--"
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
                ring = (
                    view.rings[i]
                    if not small
                    else view.position[i]
                    + SMALL_RING
                    * np.array([[np.cos(a), np.sin(a)] for a in np.linspace(0, 2 * np.pi, 24, endpoint=False)])
                    * (ax.get_xlim()[1] - ax.get_xlim()[0])
                    / max(ax.bbox.width, 1.0)
                )
                for colour, width, style in (("white", 4.0, "-"), (TARGET_EDGE, 2.0, "--")):
                    halo = self.patches.Polygon(ring, fill=False, edgecolor=colour, lw=width, ls=style, zorder=2.6)
                    halo.set_gid("target outline")
                    add(ax.add_artist(halo))
        add(ax.plot(*view.observer, marker="*", color="white", mec="black", ms=10, zorder=4)[0])
        if target_row is not None and not shown:
            add(self._pointer(view, target_row, limits))
        for k, s in enumerate(self.sensors):
            self._dynamic.extend(draw_sensor(ax, s, view, sensor_colour(k), limits))
        self._dynamic.extend(self._labels(view, limits))
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
        text = f"target {self.target}" + (f": {seen:.0%}" if np.isfinite(seen) else "") + f", {distance:.0f} m"
        box = {"boxstyle": "round,pad=0.2", "fc": "white", "ec": TARGET_EDGE, "ls": "--"}
        arrow = self.ax.annotate(text, xy=tip, xytext=tail, ha="center", va="center", fontsize=8, zorder=5, bbox=box,
                                 arrowprops={"arrowstyle": "-|>", "color": TARGET_EDGE, "lw": 1.4})  # fmt: skip
        arrow.set_gid("target pointer")
        return arrow

    def _labels(self, view: FrameView, limits: tuple[float, float, float, float]) -> list[Any]:
        """``idx: visibility`` beside each object on the picture (``ego idx`` for the ego), none overlapping
        another: the ego's first, then the target's, then the others from the nearest to the ego; a label that
        finds no free place beside its object is left out."""
        ax = self.ax
        ax.apply_aspect()
        to_pixels = ax.transData.transform
        x0, x1, y0, y1 = limits
        (ax0, ay0), (ax1, ay1) = to_pixels([(x0, y0), (x1, y1)])
        area = (min(ax0, ax1), min(ay0, ay1), max(ax0, ax1), max(ay0, ay1))
        points = LABEL_SIZE * ax.figure.dpi / 72
        distance = np.hypot(*(view.position - view.observer).T)
        order = sorted(
            range(len(view.idx)),
            key=lambda i: (i != view.ego_row, int(view.idx[i]) != self.target, float(distance[i])),
        )
        boxes, sizes, texts = [], [], []
        for i in order:
            idx = int(view.idx[i])
            seen = view.visibility[i]
            text = f"ego {idx}" if i == view.ego_row else f"{idx}: {seen:.0%}" if np.isfinite(seen) else f"{idx}"
            px = to_pixels(view.rings[i])
            boxes.append((px[:, 0].min(), px[:, 1].min(), px[:, 0].max(), px[:, 1].max()))
            sizes.append((0.62 * points * len(text) + 2, 1.25 * points))
            texts.append(text)
        from_pixels = ax.transData.inverted().transform
        shown = [(t, b) for t, b in zip(texts, place_labels(boxes, sizes, area), strict=True) if b is not None]
        backing = {"boxstyle": "square,pad=0.1", "facecolor": "white", "alpha": 0.75, "lw": 0}
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


SMALL_RING = 9.0
"""Pixels: the radius of the dashed ring around a target drawn as a marker (too small for its outline)."""
MIN_MARGIN = 200.0
"""Metres around the ego to which the seen region is computed, at least (a window fitted to a wide page or
picture can be more than twice as wide as the reach)."""
POINTER_INSET = 0.95
"""Where a pointer to a target off the picture sits: this share of the way from the centre to the edge."""


TARGET_REACH = 2.0
"""A picture's reach grows to hold the chosen target up to this many times the reach (beyond, a pointer at the
edge says where it is)."""


def reach_with_target(view: FrameView, target: int | None, reach: float) -> float:
    """``reach``, or as far as the farthest vertex of ``target`` from the ego (and a metre) where that is farther
    but within :data:`TARGET_REACH` times ``reach``."""
    row = view.row_of(target)
    if row is None:
        return reach
    farthest = float(np.hypot(*(view.rings[row] - view.observer).T).max()) + 1.0
    return farthest if reach < farthest <= TARGET_REACH * reach else reach


def on_picture(ring: np.ndarray, limits: tuple[float, float, float, float]) -> bool:
    """Whether any of the outline ``ring`` lies within ``limits`` ``(x0, x1, y0, y1)`` (its bounding box meets
    them).

    >>> on_picture(np.array([[9.0, 0.0], [11.0, 0.0], [11.0, 1.0]]), (0.0, 10.0, -5.0, 5.0))
    True
    """
    x0, x1, y0, y1 = limits
    (a, b), (c, d) = ring.min(axis=0), ring.max(axis=0)
    return bool(c >= x0 and a <= x1 and d >= y0 and b <= y1)


def picture_viewer(
    df: Any, source: Source, question: Query, positions: np.ndarray, view_range: float | None, table: Any = None
) -> FrameViewer:
    """The :class:`~.data.FrameViewer` of a picture of ``question``: its sensors fitted to the ego, its engine;
    where the views cannot compute its numbers themselves (3D, the area measure), the table of the frames at
    ``positions`` computed first."""
    number = isinstance(view_range, numbers.Real) and 0 < view_range < math.inf
    if not (number or view_range is None or view_range == AUTO):
        raise ValueError(f"view_range must be a positive number of metres, 'auto' or None, not {view_range!r}")
    ego_idx = int(question.observers)
    own = sensor_list(source, ego_idx)
    if view_range == AUTO:
        view_range = default_reach(own)
    margin = max(4.0 * (view_range or 100.0), MIN_MARGIN)  # the seen region reaches past any fitted window
    if table is None and needs_table(question):
        FrameViewer(source, ego_idx, "visilibity", margin)  # an absent ego fails before the long computation
        table = frames_table(df, question, source.frames[positions].tolist())
    engine = "visilibity" if table is not None or needs_table(question) else question.engine
    viewer = FrameViewer(source, ego_idx, engine, margin, sensors=own, table=table, region=not question.three_d)
    viewer.reach = view_range  # metres around the ego the window shows (None: the whole frame)
    return viewer


def check_target(source: Source, target: int | None, positions: np.ndarray | None = None) -> None:
    """``ValueError`` unless ``target`` is None or occurs in the frames at ``positions`` (all by default)."""
    if target is None:
        return
    from ..inputs.observers import describe_idx

    objects = source.objects
    if positions is None:
        present = np.unique(objects.idx)
    else:
        present = np.unique(np.concatenate([objects.idx[objects.frame_starts[k] : objects.frame_starts[k + 1]]
                                            for k in np.asarray(positions).tolist()]))  # fmt: skip
    if int(target) not in set(present.tolist()):
        where = "the recording" if positions is None else "the frames drawn"
        raise ValueError(f"target idx {target} never occurs in {where} (idx present: {describe_idx(present)})")


def plot_frame(
    df: Any,
    ego_idx: int | None,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    query: Query | None = None,
    target: int | None = None,
    sensors: Any = None,
    lanes: Any = True,
    ax: Any = None,
    view_range: float | str | None = AUTO,
    cmap: str = VISIBILITY_CMAP,
    legend: bool = True,
    engine: str | None = None,
    mode: str | None = None,
    table: Any = None,
    occluders: Any = None,
    **question: Any,
) -> Any:
    """Draw one frame seen from ``ego_idx``; return the matplotlib ``Axes``.

    Parameters
    ----------
    df : omega_prime.Recording, polars DataFrame/LazyFrame or MCAP path
        The moving objects, as for :func:`~omega_prime_visibility.get_visibility_df`.
    ego_idx : int
        The observer; drawn in vermillion, its viewpoint (the centre of its bounding box) as a star.
    frame : int
        The frame number (not its position); ``ValueError`` if it does not occur or the ego is not in it.
    static_occluder_polys : sequence of shapely geometries, optional
        Drawn hatched (polygons) or as thick grey lines (walls).
    target : int, optional
        Outline this object dashed and its occluders (objects and static occluders) in black.
    sensors : layout name, JSON path, Sensor or sequence of Sensors, optional
        Look through these sensors: objects are filled by the best visibility over the sensors (what
        ``seen_by_any`` gives), each sensor's field of view is outlined at its pose on the ego in its own colour,
        and the region shaded is what the sensors see, each from its own pose within its field and range
        (``"typical"`` and ``"roof"`` are fitted to the ego's outline).
    lanes : bool, map or sequence of shapely geometries
        True draws the lanes of the recording's map underneath, where it has one.
    ax : matplotlib Axes, optional
        Where to draw; by default a new figure shaped like the window.
    view_range : float, "auto" or None
        The picture shows every object within this many metres of the ego, with the lanes within that distance
        (see :mod:`omega_prime_visibility.plot.window`); "auto" (the default): 50 m, or through sensors the reach
        of those that look around; None shows the whole frame.
    cmap : str
        Matplotlib colour map of visibility, 0 (hidden) to 1 (fully visible); cividis (colour-blind safe) by
        default.
    legend : bool
        Add a legend below the axes saying what each colour and outline means.
    engine, mode : str, optional
        As for ``get_visibility_df`` (the visible region is always VisiLibity's, in bird's-eye view):
        ``mode="3d"`` fills the objects by their 3D visibility.
    table : polars.DataFrame, optional
        A visibility table of this ego computed elsewhere to take the numbers from (per sensor or not).
    occluders : str, sequence or polars expression, optional
        Who may block the view, as for ``get_visibility_df``: the numbers computed here and the region shaded as
        seen honour it (give the choice a ``table=`` was computed with). Default: everything blocks.
    query : Query, optional
        The whole question as one value, as for ``get_visibility_df`` (its observer draws the picture); the other
        table keywords of ``get_visibility_df`` (``targets``, ``measure``, ``map_occluders``,
        ``static_occluder_heights``, ``static_meshes``) are taken too. Objects the question has no row of (not
        among ``targets``) are drawn grey, as context, with their idx.

    Objects are filled by their visibility (colour bar 0..1) and labelled ``idx: visibility`` where the label has
    room; the region visible from the ego is shaded pale blue, and a scale bar gives metres.

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
    asked = picture_question(query, ego_idx, static_occluder_polys, engine=engine, mode=mode, sensors=sensors,
                             occluders=occluders, **question)  # fmt: skip
    ego_idx = asked.observers
    source = load_source(df, asked, lanes)
    k = source.position_of(frame)
    check_target(source, target, np.array([k]))
    viewer = picture_viewer(df, source, asked, np.array([k]), view_range, table=table)
    view = viewer.view(k)
    window = None
    if viewer.reach is not None:
        reach = reach_with_target(view, target, viewer.reach)
        window = scene_window(source.objects, ego_idx, np.array([k]), reach, source.lanes.points)
    if ax is None:
        aspect = min(max(window.aspect if window else 2.0, 0.75), 2.2)
        scene = math.sqrt(40.0 * aspect), math.sqrt(40.0 / aspect)  # about 40 square inches of scene
        _, ax = plt.subplots(figsize=(scene[0] + 1.2, scene[1] + 1.3), layout="constrained")
    hidden_by = view.occluders.get(target, []) or view.static_occluders.get(target, []) if target is not None else []
    row = view.row_of(target)
    if row is not None and window is not None and not on_picture(view.rings[row], window.around(view.observer)):
        hidden_by = []  # the target is off the picture: a pointer, and nothing outlined as what hides it
    painter = FramePainter(ax, source, ego_idx, target=target, sensors=viewer.sensors, window=window, cmap=cmap,
                           legend=legend, hiders=bool(hidden_by), region=viewer.region,
                           choices=describe_question(asked))  # fmt: skip
    painter.fit()
    if window is not None and painter.show_only(painter.window.around(view.observer)):
        painter.fit()  # (the legend changed size: the axes' shape may have too)
    painter.draw(view)
    return ax
