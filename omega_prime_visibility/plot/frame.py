"""One frame seen from the ego (:func:`plot_frame`), and what every picture shares before drawing: the viewer of a
picture's question (:func:`picture_viewer`, its reach), the check of a target. The drawing itself is
:class:`~.painter.FramePainter`'s; what part of the scene is shown follows :mod:`.window`'s rule.
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
from .painter import FramePainter, on_picture
from .style import (
    VISIBILITY_CMAP,
)
from .window import AUTO, default_reach, scene_window

MIN_MARGIN = 200.0
"""Metres around the ego to which the seen region is computed, at least (a window fitted to a wide page or
picture can be more than twice as wide as the reach)."""
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
    return FrameViewer(
        source, ego_idx, engine, margin, sensors=own, table=table, region=not question.three_d, reach=view_range
    )


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
