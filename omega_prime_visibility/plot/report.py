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

from ..table.output import atomic_write, check_output_path
from ._optional import require
from .data import FrameSpec, FrameView, FrameViewer, load_source
from .timeline import chart_spec, timeline_chart

# ColorBrewer RdYlGn (11 classes), the frame plot's default colour map: visibility 0 (red) to 1 (green)
RDYLGN = (
    "#a50026 #d73027 #f46d43 #fdae61 #fee08b #ffffbf #d9ef8b #a6d96a #66bd63 #1a9850 #006837".split()
)  # fmt: skip
PROGRESS_MIN_FRAMES = 200


def visibility_colour(v: float) -> str:
    """Hex colour of visibility ``v`` in 0..1 on the RdYlGn scale (linear between its 11 colours).

    >>> visibility_colour(0.0), visibility_colour(1.0), visibility_colour(0.5)
    ('#a50026', '#006837', '#ffffbf')
    """
    if not np.isfinite(v):
        return "#cccccc"
    x = min(max(float(v), 0.0), 1.0) * (len(RDYLGN) - 1)
    k = min(int(x), len(RDYLGN) - 2)
    a = np.array([int(RDYLGN[k][i : i + 2], 16) for i in (1, 3, 5)])
    b = np.array([int(RDYLGN[k + 1][i : i + 2], 16) for i in (1, 3, 5)])
    r, g, bl = np.rint(a + (b - a) * (x - k)).astype(int)
    return f"#{r:02x}{g:02x}{bl:02x}"


def write_report(
    df: Any,
    ego_idx: int,
    output: str | os.PathLike,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    *,
    frames: FrameSpec = None,
    table: pl.DataFrame | None = None,
    sensors: Any = None,
    lanes: Any = True,
    view_range: float = 60.0,
    title: str | None = None,
    engine: str = "visilibity",
    progress: bool | None = None,
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
        Compute the timeline and the summary through these sensors (``get_visibility_df(..., sensors=...)``): one
        band per (target, sensor), coloured by ``status``. The scene stays the view from the ego's centre.
    lanes : bool, map or sequence of shapely geometries
        As for :func:`~.frame.plot_frame`.
    view_range : float
        Metres shown on each side of the ego in the scene.
    title : str, optional
        Heading of the page; by default the recording's file name where known.
    engine : str
        Engine of the visibility values.
    progress : bool, optional
        Show a progress bar while computing; by default for ``PROGRESS_MIN_FRAMES`` frames or more.
    """
    output = check_output_path(output, (".html",))
    vlc = require("vl_convert", "the HTML report")
    if table is not None and sensors is not None:
        raise ValueError("give either table= or sensors=, not both")
    if isinstance(df, str | os.PathLike):
        from ..inputs.io import read_recording

        title = Path(df).name if title is None else title
        df = read_recording(df)
    title = "recording" if title is None else title
    source = load_source(df, static_occluder_polys, lanes)
    positions = source.positions(frames)
    viewer = FrameViewer(source, ego_idx, engine, margin=2 * view_range)
    show = len(positions) >= PROGRESS_MIN_FRAMES if progress is None else progress
    views = [viewer.view(k) for k in tqdm(positions.tolist(), desc="frames", unit="frame", disable=not show)]
    computed = views_table(views)
    if sensors is not None:
        from ..api import get_visibility_df

        table = get_visibility_df(
            df, ego_idx, static_occluder_polys, engine=engine, sensors=sensors, progress=False
        )  # fmt: skip
    if table is not None:
        table = _own_rows(table, ego_idx, computed["frame"].unique())
    shown = computed if table is None else table
    spec, mode = chart_spec(with_time_rule(timeline_chart(shown, title=f"seen from idx {ego_idx}", width=760), views))
    scene = scene_data(views, source, ego_idx, view_range)
    page = PAGE.format(
        title=html.escape(f"Visibility report: {title}"),
        subtitle=html.escape(
            f"seen from idx {ego_idx}; {len(views)} frames ({views[0].frame} to {views[-1].frame}), "
            f"{len(np.unique(np.concatenate([v.idx for v in views]))) - 1} other objects, engine {engine}"
        ),
        style=_asset("report.css"),
        bundle=_script_safe(vlc.javascript_bundle()),
        scene=_json_for_script(scene),
        timeline=_json_for_script({"spec": spec, "mode": mode}),
        summary=summary_html(shown),
        code=_asset("report.js"),
        colourbar="".join(f'<span style="background:{visibility_colour(v)}"></span>' for v in np.linspace(0, 1, 21)),
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
    return json.dumps(value, separators=(",", ":")).replace("<", "\\u003c")


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


def scene_data(views: list[FrameView], source, ego_idx: int, view_range: float) -> dict:
    """What the page's script draws: per frame the objects (outline, colour, label) and the visible region, cut to
    a box around the ego; once the static occluders and lanes."""
    frames = []
    for v in views:
        ex, ey = v.observer
        box = shapely.box(ex - 3 * view_range, ey - 3 * view_range, ex + 3 * view_range, ey + 3 * view_range)
        region = shapely.intersection(v.region, box).simplify(0.02)
        parts = [p for p in getattr(region, "geoms", [region]) if isinstance(p, shapely.Polygon) and not p.is_empty]
        objects = [
            {
                "idx": idx,
                "ego": i == v.ego_row,
                "vis": None if i == v.ego_row else round(float(v.visibility[i]), 4),
                "fill": "#1f5fbf" if i == v.ego_row else visibility_colour(v.visibility[i]),
                "ring": _coords(v.rings[i]),
                "occluders": v.occluders.get(idx, []),
            }
            for i, idx in enumerate(v.idx.tolist())
        ]
        frames.append(
            {
                "frame": v.frame,
                "t": round(v.total_nanos / 1e9, 3),
                "speed": round(source.ego_speed(ego_idx, v.frame), 2),
                "ego": _coords(v.observer),
                "region": [_coords(p.exterior.coords) for p in parts],
                "objects": objects,
            }
        )
    statics = []
    for g in source.statics.geometries:
        for part in getattr(g, "geoms", [g]):
            if isinstance(part, shapely.Polygon):
                statics.append({"kind": "polygon", "points": _coords(part.exterior.coords)})
            elif isinstance(part, shapely.LineString | shapely.LinearRing):
                statics.append({"kind": "line", "points": _coords(part.coords)})
    lanes = [
        _coords(part.coords)
        for _, centre in source.lanes
        if centre is not None
        for part in getattr(centre, "geoms", [centre])
    ]
    return {"ego": ego_idx, "range": view_range, "frames": frames, "statics": statics, "lanes": lanes}


def summary_html(table: pl.DataFrame) -> str:
    """The per-target summary as an HTML table: frames, mean and least visibility, share of frames hidden and
    partly hidden (or, where the table has the sensors' ``status``, the frames of each status), and every object
    that hid it at some time."""
    by = [c for c in ("idx", "sensor") if c in table.columns]
    aggregations = [
        pl.len().alias("frames"),
        pl.col("visibility").mean().alias("mean visibility"),
        pl.col("visibility").min().alias("least visibility"),
    ]
    if "status" in table.columns:  # the sensors' verdict tells hidden from out of view
        aggregations.append(pl.col("status").value_counts(sort=True).alias("status"))
    else:
        aggregations.append((pl.col("visibility") == 0).mean().alias("hidden"))
        aggregations.append(((pl.col("visibility") > 0) & (pl.col("visibility") < 1)).mean().alias("partly hidden"))
    if "occluder_idxs" in table.columns:
        aggregations.append(pl.col("occluder_idxs").flatten().drop_nulls().unique().sort().alias("hidden by (idx)"))
    summary = table.group_by(by).agg(aggregations).sort(by)
    head = "".join(f"<th>{html.escape(c)}</th>" for c in summary.columns)
    body = []
    for row in summary.iter_rows(named=True):
        cells = []
        for name, value in row.items():
            if name in ("hidden", "partly hidden"):
                text = f"{value:.0%}"
            elif isinstance(value, float):
                text = f"{value:.3f}"
            elif name == "status":
                text = ", ".join(f"{d['status']}: {d['count']}" for d in value)
            elif isinstance(value, list):
                text = ", ".join(map(str, value)) or "none"
            else:
                text = str(value)
            cells.append(f"<td>{html.escape(text)}</td>")
        body.append(f"<tr>{''.join(cells)}</tr>")
    return f'<table id="summary"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'


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
<svg id="scene" xmlns="http://www.w3.org/2000/svg" preserveAspectRatio="xMidYMid meet"></svg>
<div class="legend">
<span class="swatch ego"></span> ego (★ its viewpoint)
<span class="swatch region"></span> seen from the ego
<span id="static-key"><span class="swatch static"></span> static occluder</span>
<span class="bar">visibility 0 {colourbar} 1</span>
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
