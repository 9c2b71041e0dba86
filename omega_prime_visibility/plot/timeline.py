"""A timeline that reads at a glance: per target one band over time, coloured by visibility (or by the sensors'
``status`` where the table has it), the occluders named on hover (altair; PNG/SVG/HTML through vl-convert).

Consecutive frames that look the same (same colour, same occluders) are merged into one interval first, so the
chart holds few rows; tables that still have many go through the vegafusion data transformer.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

import numpy as np
import polars as pl

from ..table.output import atomic_write, check_output_path
from ..table.schema import STATIC_LABEL
from ._optional import require
from .style import STATUS_COLOURS

SUFFIXES = (".png", ".svg", ".html", ".json")
VEGAFUSION_MIN_ROWS = 5000  # altair's own limit for inline data


def timeline_intervals(table: pl.DataFrame, *, by: str = "auto", resolution: float = 0.01) -> pl.DataFrame:
    """Runs of consecutive frames in which a target looks the same, one row per run.

    Parameters
    ----------
    table : polars.DataFrame
        A visibility table (``frame, total_nanos, idx, visibility``; ``idx_ego``, ``sensor``, ``status``,
        ``occluder_idxs``, ``static_occluder_idxs`` and ``seen_by`` are used where present), as
        ``get_visibility_df`` or ``seen_by_any`` give it.
    by : {"auto", "status", "visibility"}
        What the colour shows; ``"auto"`` takes ``status`` when the table has that column.
    resolution : float
        Visibility values closer than this share a run (the colour cannot show the difference).

    Returns
    -------
    polars.DataFrame
        ``target`` (label such as ``"idx 2"``), ``start``, ``end`` (seconds; a frame lasts until the next one),
        ``first_frame``, ``last_frame``, ``visibility`` (mean over the run), ``status`` (if coloured by it),
        ``occluders``, ``static_occluders`` (text, ``"none"`` if empty).

    Examples
    --------
    >>> t = pl.DataFrame({"frame": [0, 1, 2], "total_nanos": [0, 10**8, 2 * 10**8], "idx": [2, 2, 2],
    ...                   "occluder_idxs": [[], [1], [1]], "visibility": [1.0, 0.4, 0.4]})
    >>> timeline_intervals(t).select("first_frame", "last_frame", "occluders").rows()
    [(0, 0, 'none'), (1, 2, '1')]
    """
    colour = _colour_column(table, by)
    keys = [c for c in ("idx_ego", "sensor", "idx") if c in table.columns]
    times = np.unique(table["total_nanos"].to_numpy())
    step = float(np.median(np.diff(times))) / 1e9 if len(times) > 1 else 0.1
    frames = np.unique(table["frame"].to_numpy())
    frame_step = int(np.median(np.diff(frames))) if len(frames) > 1 else 1

    def text(column: str, prefix: str = "") -> pl.Expr:
        if column not in table.columns:
            return pl.lit("none")
        named = pl.concat_str([pl.lit(prefix), pl.element().cast(pl.String)])
        joined = pl.col(column).list.eval(named).list.join(", ")
        return pl.when(pl.col(column).list.len() > 0).then(joined).otherwise(pl.lit("none"))

    shade = (pl.col("visibility") / resolution).round(0) if colour == "visibility" else pl.col("status")
    rows = table.sort([*keys, "frame"]).with_columns(
        occluders=text("occluder_idxs"),
        static_occluders=text("static_occluder_idxs", STATIC_LABEL),
        seen_by=text("seen_by"),
        shade=shade,
    )
    same = [pl.col(c) == pl.col(c).shift(1) for c in (*keys, "shade", "occluders", "static_occluders", "seen_by")]
    contiguous = pl.col("frame") - pl.col("frame").shift(1) == frame_step
    new_run = ~pl.all_horizontal(*same, contiguous).fill_null(False)
    label = pl.concat_str([pl.lit("idx "), pl.col("idx").cast(pl.String)])
    if "sensor" in keys:
        label = pl.concat_str([label, pl.lit(" · "), pl.col("sensor").cast(pl.String)])
    if "idx_ego" in keys:
        label = pl.concat_str([pl.lit("ego "), pl.col("idx_ego").cast(pl.String), pl.lit(" → "), label])
    aggregated = [
        pl.col("total_nanos").min().alias("start") / 1e9,
        (pl.col("total_nanos").max() / 1e9 + step).alias("end"),
        pl.col("frame").min().alias("first_frame"),
        pl.col("frame").max().alias("last_frame"),
        pl.col("visibility").mean(),
        pl.col("occluders").first(),
        pl.col("static_occluders").first(),
        pl.col("seen_by").first(),
    ]
    if colour == "status":
        aggregated.append(pl.col("status").first())
    return (
        rows.with_columns(run=new_run.cum_sum(), target=label)
        .group_by("run", maintain_order=True)
        .agg(pl.col("target").first(), *[pl.col(k).first() for k in keys], *aggregated)
        .drop("run")
    )


def _colour_column(table: pl.DataFrame, by: str) -> str:
    """The column the colour shows, after checking that ``table`` is a visibility table with rows."""
    if not isinstance(table, pl.DataFrame):
        raise ValueError(f"expected a polars DataFrame from get_visibility_df, not {type(table).__name__}")
    missing = [c for c in ("frame", "total_nanos", "idx", "visibility") if c not in table.columns]
    if missing:
        raise ValueError(f"the table lacks column(s) {missing}: give a table from get_visibility_df")
    if table.height == 0:
        raise ValueError("the visibility table is empty: there is no timeline to draw")
    if by == "auto":
        return "status" if "status" in table.columns else "visibility"
    if by not in ("status", "visibility"):
        raise ValueError(f"by must be 'auto', 'status' or 'visibility', not {by!r}")
    if by not in table.columns:
        raise ValueError(f"cannot colour by {by!r}: the table has no such column")
    return by


def timeline_chart(
    table: pl.DataFrame, *, by: str = "auto", title: str | None = None, width: int = 640, band: int = 18
) -> Any:
    """An altair chart: per target a band over time, coloured by visibility (or ``status``), the occluders of each
    stretch named in its tooltip.

    Parameters
    ----------
    table : polars.DataFrame
        A visibility table from :func:`~omega_prime_visibility.get_visibility_df` (any number of observers and
        sensors: each (observer, sensor, target) gets its own band).
    by : {"auto", "status", "visibility"}
        ``"auto"`` colours by ``status`` (visible, partly_visible, occluded, out_of_fov, out_of_range) when the
        table has it, else by ``visibility`` (cividis: dark blue 0 to yellow 1, readable to colour-blind readers).
    title : str, optional
        Chart title; by default it says what is coloured.
    width, band : int
        Chart width and the height of one band, pixels.

    Examples
    --------
    >>> t = pl.DataFrame({"frame": [0, 1], "total_nanos": [0, 10**8], "idx": [1, 1],
    ...                   "occluder_idxs": [[], [3]], "visibility": [1.0, 0.25]})
    >>> spec = timeline_chart(t).to_dict()
    >>> spec["mark"]["type"], spec["encoding"]["color"]["field"]
    ('rect', 'visibility')
    """
    alt = require("altair")
    colour = _colour_column(table, by)
    data = timeline_intervals(table, by=colour)
    # each stretch is drawn a little longer, under the next one, so no hairline gap shows between stretches
    overlap = 0.5 * float((data["end"] - data["start"]).min())
    data = data.with_columns(drawn_end=pl.col("end") + overlap)
    domain = [float(data["start"].min()), float(data["end"].max())]
    # bands grouped by observer, then target; a target's sensors in the order the table gives them
    ranked = data
    if "sensor" in data.columns:
        first_seen = table["sensor"].cast(pl.String).unique(maintain_order=True).to_list()
        ranked = data.with_columns(pl.col("sensor").cast(pl.String).replace_strict(first_seen, range(len(first_seen))))
    order = ranked.sort([c for c in ("idx_ego", "idx", "sensor") if c in data.columns])["target"].unique(
        maintain_order=True
    )
    if colour == "status":
        present = [s for s in STATUS_COLOURS if s in set(data["status"].to_list())] or list(STATUS_COLOURS)
        scale = alt.Scale(domain=present, range=[STATUS_COLOURS[s] for s in present])
        color = alt.Color("status:N", scale=scale, legend=alt.Legend(title="status", orient="bottom"))
        default_title = "status of each target over time"
    else:
        scale = alt.Scale(scheme="cividis", domain=[0, 1])
        legend = alt.Legend(  # in % as the pictures' labels and colour bars say it
            title="visibility (0 % hidden, 100 % fully visible)", orient="bottom", gradientLength=240, format="%"
        )
        color = alt.Color("visibility:Q", scale=scale, legend=legend)
        default_title = "visibility of each target over time"
    tooltip = [
        alt.Tooltip("target:N"),
        alt.Tooltip("start:Q", title="from [s]", format=".2f"),
        alt.Tooltip("end:Q", title="to [s]", format=".2f"),
        alt.Tooltip("first_frame:Q", title="first frame"),
        alt.Tooltip("last_frame:Q", title="last frame"),
        alt.Tooltip("visibility:Q", format=".1%"),
    ]
    if "occluder_idxs" in table.columns:
        tooltip.append(alt.Tooltip("occluders:N", title="hidden by (idx)"))
    if "static_occluder_idxs" in table.columns:
        tooltip.append(alt.Tooltip("static_occluders:N", title="static occluders"))
    if "seen_by" in table.columns:
        tooltip.append(alt.Tooltip("seen_by:N", title="seen by"))
    if colour == "status":
        tooltip.insert(1, alt.Tooltip("status:N"))
    return (
        alt.Chart(data, title=title or default_title)
        .mark_rect(clip=True)
        .encode(
            x=alt.X("start:Q", title="time [s]", scale=alt.Scale(domain=domain, nice=False, zero=False)),
            x2="drawn_end:Q",
            y=alt.Y("target:N", sort=order.to_list(), title=None),
            color=color,
            tooltip=tooltip,
        )
        .properties(width=width, height=alt.Step(band))
    )


TEXT_PX = 12
"""The smallest text of a chart on a page or picture (axis labels, legend), pixels; titles a little larger."""


def readable(chart: Any) -> Any:
    """``chart`` with its axis, legend and title text at least :data:`TEXT_PX` pixels (Vega's defaults, 10 and 11
    px, are too small on a page); a top-level chart (it can no longer be layered)."""
    if getattr(chart, "config", None) not in (None, {}) and not _undefined(chart.config):
        return chart  # configured already
    return (
        chart.configure_axis(labelFontSize=TEXT_PX, titleFontSize=TEXT_PX + 1)
        .configure_legend(labelFontSize=TEXT_PX, titleFontSize=TEXT_PX, titleLimit=0, labelLimit=0)
        .configure_title(fontSize=TEXT_PX + 2)
    )


def _undefined(value: Any) -> bool:
    return type(value).__name__ == "UndefinedType"


def chart_spec(chart: Any) -> tuple[dict, str]:
    """``(spec, mode)`` of an altair chart for vega-embed or vl-convert: Vega-Lite, or for charts with more than
    ``VEGAFUSION_MIN_ROWS`` rows a Vega spec whose data vegafusion has already aggregated."""
    alt = require("altair")
    data = getattr(getattr(chart, "layer", [chart])[0], "data", None)  # a layered chart's data: its first layer's
    if data is not None and hasattr(data, "shape") and data.shape[0] > VEGAFUSION_MIN_ROWS:
        require("vegafusion", "timelines of long tables")
        with alt.data_transformers.enable("vegafusion"):
            return chart.to_dict(format="vega"), "vega"
    return chart.to_dict(), "vega-lite"


def save_timeline(chart: Any, path: str | os.PathLike, *, scale: float = 2.0) -> Path:
    """Write a timeline chart (or any altair chart; a visibility table is turned into one first) to ``.png``,
    ``.svg``, ``.html`` (self-contained, works offline) or ``.json`` (the Vega-Lite or Vega spec).

    ``scale`` multiplies the PNG's pixel size. The path is checked first; the file is written under a temporary name
    and renamed when complete. Returns the path.
    """
    path = check_output_path(path, SUFFIXES)
    if isinstance(chart, pl.DataFrame):
        chart = timeline_chart(chart)
    vlc = require("vl_convert", "exporting charts")
    spec, mode = chart_spec(readable(chart))
    kind = "vega" if mode == "vega" else "vegalite"
    with atomic_write(path) as temp:
        if path.suffix == ".png":
            temp.write_bytes(getattr(vlc, f"{kind}_to_png")(spec, scale=scale))
        elif path.suffix == ".svg":
            temp.write_text(getattr(vlc, f"{kind}_to_svg")(spec))
        elif path.suffix == ".html":
            temp.write_text(getattr(vlc, f"{kind}_to_html")(spec, bundle=True))
        else:
            import json

            temp.write_text(json.dumps(spec))
    return path
