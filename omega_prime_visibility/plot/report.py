"""An interactive HTML report for one recording and one ego: a single self-contained file that works offline.

It holds a frame slider over the scene (drawn as SVG by a few lines of JavaScript from the per-frame outlines and
visibility embedded as JSON), the timeline (:func:`~.timeline.timeline_chart`, rendered by vega-embed, whose
libraries are embedded from ``vl-convert``'s bundle, so no CDN is needed) and the per-target summary table.
"""

from __future__ import annotations

import html
import json
import os
import re
from collections.abc import Sequence
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import polars as pl
import shapely
from tqdm.auto import tqdm

from ..inputs.observers import observer_words
from ..query import Query
from ..table.output import atomic_write, check_output_path
from ._optional import require
from .data import (
    FrameSpec,
    FrameView,
    describe_question,
    frames_table,
    load_source,
    needs_table,
    picture_question,
)
from .frame import picture_viewer
from .painting import NO_REGION
from .report_tables import summary_html, with_any_sensor
from .style import EGO_FACE, REGION_FACE, sensor_colour, visibility_colour
from .timeline import chart_spec, readable, timeline_chart
from .window import AUTO, Window, scene_window

PROGRESS_MIN_FRAMES = 200
SCENE_ASPECT = (1.0, 2.6)  # the scene's width / height, at least and at most


def write_report(
    df: Any,
    ego_idx: int | None,
    output: str | os.PathLike,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    query: Query | None = None,
    frames: FrameSpec = None,
    table: pl.DataFrame | None = None,
    sensors: Any = None,
    lanes: Any = True,
    view_range: float | str = AUTO,
    title: str | None = None,
    engine: str | None = None,
    mode: str | None = None,
    progress: bool | None = None,
    occluders: Any = None,
    **question: Any,
) -> Path:
    """Write an interactive, self-contained HTML report of what ``ego_idx`` sees; return its path.

    Parameters
    ----------
    df : omega_prime.Recording, polars DataFrame/LazyFrame or MCAP path
        The moving objects.
    ego_idx : int
        The observer.
    output : path
        Ends in ``.html``; checked before anything is computed, written under a temporary name and renamed.
    static_occluder_polys : sequence of shapely geometries, optional
        As for ``get_visibility_df``.
    frames : slice, range or sequence of frame numbers, optional
        Which frames the slider offers (see :func:`~.animate.animate`); all by default.
    table : polars.DataFrame, optional
        A visibility table to show in the timeline and the summary instead of the one computed here (for
        example one computed elsewhere with sensors); rows of other observers are left out.
    sensors : layout name, JSON path, Sensor or sequence of Sensors, optional
        Look through these sensors (``get_visibility_df(..., sensors=...)``): the scene outlines each sensor's
        field of view and fills the objects by the best visibility over the sensors (as ``seen_by_any`` gives
        it); the timeline and the summary have, per target, that combined row ("any sensor") and one per sensor,
        coloured by ``status``.
    lanes : bool, map or sequence of shapely geometries
        As for :func:`~.frame.plot_frame`.
    view_range : float or "auto"
        The scene shows every object within this many metres of the ego (the window of
        :mod:`omega_prime_visibility.plot.window`, the same rule as :func:`~.frame.plot_frame`'s; "auto", the
        default: 50 m, or through sensors the reach of those that look around).
    title : str, optional
        Heading of the page; by default the recording's file name where known (a path, or a recording read by
        this package).
    engine, mode : str, optional
        As for ``get_visibility_df``; ``mode="3d"`` shows 3D visibility (the scene stays a bird's-eye view).
    occluders : str, sequence or polars expression, optional
        Who may block the view, as for ``get_visibility_df`` (the numbers computed here and the seen region).
    progress : bool, optional
        Show a progress bar while computing; by default for ``PROGRESS_MIN_FRAMES`` frames or more.
    query : Query, optional
        The whole question as one value, and the other table keywords of ``get_visibility_df``, as for
        :func:`~.frame.plot_frame`; the subtitle states it (engine, mode, measure, who may block, whom to look for).
    """
    output = check_output_path(output, (".html",))
    vlc = require("vl_convert", "the HTML report")
    if table is not None and sensors is not None:
        raise ValueError("give either table= or sensors=, not both")
    asked = picture_question(query, ego_idx, static_occluder_polys, engine=engine, mode=mode, sensors=sensors,
                             occluders=occluders, **question)  # fmt: skip
    ego_idx = asked.observers
    if isinstance(df, str | os.PathLike):
        from ..inputs.io import read_recording

        title = Path(df).name if title is None else title
        df = read_recording(df)
    if title is None:  # the file's name where the recording knows it (read by this package)
        path = getattr(df, "path", None)
        title = Path(path).name if isinstance(path, str | os.PathLike) else "recording"
    source = load_source(df, asked, lanes)
    positions = source.positions(frames)
    if asked.sensors is not None or (table is None and needs_table(asked)):  # the table every part shows
        table = frames_table(df, asked, source.frames[positions].tolist())
    if table is not None:
        table = _own_rows(table, ego_idx, pl.Series(source.frames[positions]))
    viewer = picture_viewer(df, source, asked, positions, view_range, table=table)
    show = len(positions) >= PROGRESS_MIN_FRAMES if progress is None else progress
    views = [viewer.view(k) for k in tqdm(positions.tolist(), desc="frames", unit="frame", disable=not show)]
    computed = views_table(views)
    shown = computed if table is None else with_any_sensor(table)
    banded, left_out = most_hidden_targets(shown)
    heading = f"seen from {observer_words(ego_idx, df)}"
    if left_out:
        heading += f": the {banded['idx'].n_unique()} most hidden targets; {left_out} more in the summary below"
    chart = with_time_rule(timeline_chart(banded, title=heading, width=760), views)
    spec, mode = chart_spec(readable(chart))
    window = scene_window(source.objects, ego_idx, positions, viewer.reach, source.lanes.points)
    window = window.fitted(min(max(window.aspect, SCENE_ASPECT[0]), SCENE_ASPECT[1]))
    scene = scene_data(views, source, ego_idx, window, viewer.sensors)
    page = PAGE.format(
        title=html.escape(f"Visibility report: {title}"),
        subtitle=html.escape(
            f"seen from {observer_words(ego_idx, df)}; {len(views)} frames ({views[0].frame} to {views[-1].frame}), "
            f"{len(np.unique(np.concatenate([v.idx for v in views]))) - 1} other objects; {describe_question(asked)}"
        ),
        style=_asset("report.css"),
        bundle=_script_safe(vlc.javascript_bundle()),
        scene=_json_for_script(scene),
        timeline=_json_for_script({"spec": spec, "mode": mode}),
        summary=summary_html(shown),
        code=_asset("report.js"),
        colourbar="".join(f'<span style="background:{visibility_colour(v)}"></span>' for v in np.linspace(0, 1, 21)),
        aspect=f"{window.aspect:.3f}",
        seen=NO_REGION if not viewer.region else "seen by the sensors" if viewer.sensors else "seen from the ego",
        ego_face=EGO_FACE,
        region_face=REGION_FACE if viewer.region else "transparent",
        unseen_key=(
            f'<span><span class="swatch" style="background:white;border:1px solid #999"></span> not seen '
            f"({'white or bare road' if source.lanes.surfaces else 'white'})</span>\n"
            if viewer.region
            else ""
        ),
        sensor_key="".join(
            f'<span class="sensor"><span class="line" style="border-color:{sensor_colour(k)}"></span> '
            f"{html.escape(s.name)}</span>"
            for k, s in enumerate(viewer.sensors)
        ),
    )
    with atomic_write(output) as temp:
        temp.write_text(page, encoding="utf-8")
    return output


def with_time_rule(chart: Any, views: list[FrameView]) -> Any:
    """The timeline with a vertical rule at the time of the slider's frame (the Vega signal ``now``, seconds)."""
    alt = require("altair")
    now = alt.param(name="now", value=views[0].total_nanos / 1e9)
    rule = (
        alt.Chart(alt.Data(values=[{}]))
        .mark_rule(color="#222222", strokeWidth=1.5)
        .encode(x=alt.X(datum=alt.ExprRef(expr="now"), type="quantitative"))
    )
    return alt.layer(chart, rule).add_params(now)


def _asset(name: str) -> str:
    return resources.files(__package__).joinpath(name).read_text(encoding="utf-8")


def _script_safe(code: str) -> str:
    """JavaScript that cannot end the ``<script>`` element it is put in (``<\\/`` means ``</`` in JavaScript strings
    and regular expressions alike)."""
    return re.sub(r"</(script)", r"<\\/\1", code, flags=re.IGNORECASE)


def _json_for_script(value: Any) -> str:
    """``value`` as JSON with every ``<`` escaped (``\\u003c``), so it cannot end or open anything in HTML."""
    return json.dumps(value, separators=(",", ":"), allow_nan=False).replace("<", "\\u003c")


MAX_BANDS = 40
"""Targets the report's timeline shows at most (one band each, or one per sensor): the most hidden ones."""


def most_hidden_targets(table: pl.DataFrame, limit: int = MAX_BANDS) -> tuple[pl.DataFrame, int]:
    """The rows of at most ``limit`` targets of ``table``: those longest hidden or partly hidden (the least mean
    visibility first, then idx), and how many targets are left out.

    >>> t = pl.DataFrame({"idx": [1, 1, 2, 2, 3, 3], "visibility": [1.0, 1.0, 0.0, 0.5, 0.2, 1.0]})
    >>> rows, left_out = most_hidden_targets(t, limit=2)
    >>> sorted(set(rows["idx"])), left_out
    ([2, 3], 1)
    """
    means = table.group_by("idx").agg(pl.col("visibility").mean().alias("mean")).sort("mean", "idx")
    if means.height <= limit:
        return table, 0
    kept = means.head(limit)["idx"]
    return table.filter(pl.col("idx").is_in(kept.implode())), means.height - limit


def _own_rows(table: pl.DataFrame, ego_idx: int, frames: pl.Series) -> pl.DataFrame:
    if "idx_ego" in table.columns:
        table = table.filter(pl.col("idx_ego") == ego_idx).drop("idx_ego")
    table = table.filter(pl.col("frame").is_in(frames.implode()))
    if table.height == 0:
        raise ValueError(f"the given table has no rows of ego {ego_idx} in the report's frames")
    return table


def views_table(views: list[FrameView]) -> pl.DataFrame:
    """The visibility table (``frame, total_nanos, idx, occluder_idxs, static_occluder_idxs, visibility``) of the
    computed views."""
    rows = []
    for v in views:
        for i, idx in enumerate(v.idx.tolist()):
            if i != v.ego_row:
                rows.append(
                    (v.frame, v.total_nanos, idx, v.occluders.get(idx, []), v.static_occluders.get(idx, []),
                     float(v.visibility[i]))
                )  # fmt: skip
    schema = {
        "frame": pl.Int64,
        "total_nanos": pl.Int64,
        "idx": pl.Int64,
        "occluder_idxs": pl.List(pl.Int64),
        "static_occluder_idxs": pl.List(pl.Int64),
        "visibility": pl.Float64,
    }
    return pl.DataFrame(rows, schema=schema, orient="row")


def _coords(geometry: Any, digits: int = 2) -> list[list[float]]:
    return np.round(np.asarray(geometry), digits).ravel().tolist()


def scene_data(views: list[FrameView], source, ego_idx: int, window: Window, sensors: Sequence[Any] = ()) -> dict:
    """What the page's script draws: per frame the objects (outline, colour, label), the visible region (cut to
    a box around the ego) and the sensors' poses; once the window, the sensors, the static occluders and lanes."""
    from .painting import sensor_pose

    frames = []
    for v in views:
        ex, ey = v.observer
        reach = 3 * max(window.half_width, window.half_height)
        box = shapely.box(ex - reach, ey - reach, ex + reach, ey + reach)
        region = shapely.intersection(v.region, box).simplify(0.02)
        parts = [p for p in getattr(region, "geoms", [region]) if isinstance(p, shapely.Polygon) and not p.is_empty]
        objects = [
            {
                "idx": idx,
                "ego": i == v.ego_row,
                # no number (None, JSON's null) for the ego and for objects the table has no row of
                "vis": None if i == v.ego_row or not np.isfinite(v.visibility[i]) else round(float(v.visibility[i]), 4),
                "fill": EGO_FACE if i == v.ego_row else visibility_colour(v.visibility[i]),
                "ring": _coords(v.rings[i]),
                "occluders": v.occluders.get(idx, []),
                "statics": v.static_occluders.get(idx, []),
            }
            for i, idx in enumerate(v.idx.tolist())
        ]
        poses = []
        for s in sensors:
            pos, heading = sensor_pose(s, v)
            poses.append([round(float(pos[0]), 2), round(float(pos[1]), 2), round(heading, 4)])
        frames.append(
            {
                "frame": v.frame,
                "t": round(v.total_nanos / 1e9, 3),
                "speed": round(source.ego_speed(ego_idx, v.frame), 2),
                "ego": _coords(v.observer),
                "region": [[_coords(r.coords) for r in (p.exterior, *p.interiors)] for p in parts],
                "objects": objects,
                "sensors": poses,
            }
        )
    statics = []
    for g in source.statics.geometries:
        for part in getattr(g, "geoms", [g]):
            if isinstance(part, shapely.Polygon):
                statics.append({"kind": "polygon", "points": _coords(part.exterior.coords)})
            elif isinstance(part, shapely.LineString | shapely.LinearRing):
                statics.append({"kind": "line", "points": _coords(part.coords)})
    sensor_info = [
        {"name": s.name, "fov": s.fov, "range": None if np.isinf(s.range) else s.range, "colour": sensor_colour(k)}
        for k, s in enumerate(sensors)
    ]
    return {
        "ego": ego_idx,
        "window": [round(v, 2) for v in (window.half_width, window.half_height, window.dx, window.dy)],
        "frames": frames,
        "statics": statics,
        "lanes": [_coords(c) for c in source.lanes.centres],
        "surfaces": [_coords(c) for c in source.lanes.surfaces],
        "sensors": sensor_info,
    }


PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>{style}</style>
<script>{bundle}</script>
</head>
<body>
<h1>{title}</h1>
<p class="sub">{subtitle}</p>
<section>
<h2>Scene</h2>
<div class="controls">
<button id="play" type="button">play</button>
<input id="slider" type="range" min="0" max="0" value="0" step="1" aria-label="frame">
<span id="frame-label"></span>
</div>
<svg id="scene" xmlns="http://www.w3.org/2000/svg" preserveAspectRatio="xMidYMid meet"
 style="aspect-ratio: {aspect}"></svg>
<div class="legend">
<span><span class="swatch" style="background:{ego_face}"></span> ego (★ its centre)</span>
<span><span class="swatch" style="background:{region_face}"></span> {seen}</span>
{unseen_key}<span id="static-key"><span class="swatch static"></span> static occluder</span>
{sensor_key}
<span class="bar">visibility 0 % {colourbar} 100 %</span>
<span class="hint">hover an object for its occluders</span>
</div>
</section>
<section>
<h2>Timeline</h2>
<div id="timeline"></div>
</section>
<section>
<h2>Per-target summary</h2>
{summary}
</section>
<script id="scene-data" type="application/json">{scene}</script>
<script id="timeline-data" type="application/json">{timeline}</script>
<script>{code}</script>
</body>
</html>
"""
