"""The campaign page: one offline HTML page with the occlusion statistics of a batch output folder as charts
(shares by distance band and type, the visibility histogram, who occludes), a table per recording and the occluded
conflicts found (``batch --conflicts``). The vega libraries are embedded, as in the per-recording report."""

from __future__ import annotations

import html
import os
from pathlib import Path
from typing import Any

import polars as pl

from ..analysis.classes import EXACT, describe
from ..table.output import atomic_write, check_output_path
from ._optional import require
from .report import _json_for_script, _script_safe
from .style import CLASS_COLOURS, OKABE_ITO


def write_campaign_page(
    folder: str | os.PathLike, output: str | os.PathLike, *, bands=(20.0, 50.0), partly=EXACT
) -> Path:
    """Write the campaign page of the batch output ``folder`` to ``output`` (``.html``); return its path.

    The page shows :func:`~omega_prime_visibility.campaign_statistics` of the folder (``bands`` and ``partly`` as
    there), and states the definition of its classes. The file is written under a temporary name and renamed when
    complete.
    """
    from ..batch.campaign import campaign_statistics

    output = check_output_path(output, (".html",))
    vlc = require("vl_convert", "the campaign page")
    stats = campaign_statistics(folder, bands=bands, partly=partly)
    charts = {"bands": _bands_chart(stats["by_band"]), "histogram": _histogram_chart(stats["histogram"])}
    charts["occluders"] = _occluders_chart(stats["occluder_types"])
    recordings = stats["by_recording"]
    here = Path(output).resolve().parent
    links = [None if p is None else os.path.relpath(p, here) for p in recordings["mcap"].to_list()]
    recordings = recordings.with_columns(pl.Series("mcap", links, dtype=pl.String))
    if recordings["mcap"].null_count() == recordings.height:  # no batch --mcap: no column of dashes
        recordings = recordings.drop("mcap")
    page = PAGE.format(
        title=html.escape(f"Occlusion over a campaign: {Path(folder).name}"),
        subtitle=html.escape(
            f"{recordings.height} recordings, {int(recordings['rows'].sum())} (frame, target) rows; {describe(partly)}"
        ),
        bundle=_script_safe(vlc.javascript_bundle()),
        charts=_json_for_script(charts),
        recordings=_table_html(recordings, "recordings"),
        conflicts=_table_html(_conflict_rows(stats["conflicts"]), "conflicts")
        if stats["conflicts"].height
        else '<p id="conflicts">No conflicts stored (run <code>batch --conflicts</code> to find them).</p>',
    )
    with atomic_write(output) as temp:
        temp.write_text(page, encoding="utf-8")
    return output


PAGE_WIDTH = 1200
"""Pixels the charts of the campaign page span together (the page's width on a laptop screen)."""
SHARES = ("visible", "partly", "hidden", "out_of_view")
"""The per-recording table's columns that are shares of rows: shown as % as the charts show them."""


def _bands_chart(by_band: pl.DataFrame) -> dict:
    """Stacked shares per distance band, one panel per target type across the page, each bar headed by its number
    of rows; a band without rows of a type says so instead of looking like a bar."""
    alt = require("altair")
    # out of view only where some row was (tables through sensors): a class no row can be in is not listed
    shown = {c: colour for c, colour in CLASS_COLOURS.items() if c != "out_of_view" or by_band[c].max() > 0}
    bands = list(dict.fromkeys(by_band["band"]))
    types = list(dict.fromkeys(by_band["target_type"]))
    if len(types) == 2 and "all" in types:  # one type of target: its panel would repeat "all"
        types = [k for k in types if k != "all"]
        by_band = by_band.filter(pl.col("target_type").is_in(types))
    every = pl.DataFrame({"band": bands}).join(pl.DataFrame({"target_type": types}), how="cross")
    full = every.join(by_band, on=["band", "target_type"], how="left").with_columns(pl.col("rows").fill_null(0))
    long = full.unpivot(index=["band", "target_type", "rows"], on=list(shown), variable_name="class")
    colour = alt.Color("class:N", scale=alt.Scale(domain=list(shown), range=list(shown.values())))
    x = alt.X("band:N", sort=bands, title="distance to the observer", axis=alt.Axis(labelAngle=0))
    bars = (
        alt.Chart()
        .mark_bar()
        .encode(
            x=x,
            y=alt.Y("value:Q", stack="normalize", title="share of rows", axis=alt.Axis(format="%")),
            color=colour,
            order=alt.Order("class_order:Q"),
            tooltip=["band", "target_type", "class", alt.Tooltip("value:Q", format=".1%"), "rows"],
        )
        .transform_filter("datum.rows > 0")
        .transform_calculate(class_order=f"indexof({list(shown)}, datum['class'])")
    )
    counts = (
        alt.Chart()
        .mark_text(baseline="bottom", dy=-3, fontSize=12)
        .encode(x=x, y=alt.datum(1.0), text="label:N")
        .transform_filter("datum['class'] == '" + next(iter(shown)) + "'")
        .transform_calculate(label="datum.rows > 0 ? 'n = ' + format(datum.rows, ',') : 'no rows'")
    )
    width = int(min(max((PAGE_WIDTH - 160) / max(len(types), 1) - 30, 180), 480))
    chart = (
        alt.layer(bars, counts, data=long)
        .properties(width=width, height=260)
        .facet(column=alt.Column("target_type:N", title="target type", sort=types))
    )
    return _readable(chart).configure_legend(labelFontSize=13, titleFontSize=13).to_dict()


def _readable(chart: Any) -> Any:
    """Text of at least 12 px in a chart: axes, panel headers."""
    return chart.configure_axis(labelFontSize=12, titleFontSize=13).configure_header(labelFontSize=13, titleFontSize=13)


def _histogram_chart(histogram: pl.DataFrame) -> dict:
    alt = require("altair")
    chart = (
        alt.Chart(histogram)
        .mark_bar(color=OKABE_ITO["blue"])
        .encode(
            x=alt.X("bin_start:Q", bin="binned", title="visibility"),
            x2="bin_end:Q",
            y=alt.Y("share:Q", title="share of rows", axis=alt.Axis(format="%")),
            tooltip=["bin_start", "bin_end", "rows", alt.Tooltip("share:Q", format=".1%")],
        )
        .properties(width=PAGE_WIDTH - 80, height=240)
    )
    return _readable(chart).to_dict()


def _occluders_chart(occluder_types: pl.DataFrame) -> dict:
    alt = require("altair")
    chart = (
        alt.Chart(occluder_types)
        .mark_bar(color=OKABE_ITO["orange"])
        .encode(
            y=alt.Y("occluder_type:N", sort="-x", title="occluder type"),
            x=alt.X("rows:Q", title="rows in which an object of this type hides the target"),
            tooltip=[
                alt.Tooltip("occluder_type:N", title="occluder type"),
                alt.Tooltip("rows:Q", title="rows hidden by this type"),
                alt.Tooltip("occluders:Q", title="occluding objects of this type, summed over rows"),
            ],
        )
        .properties(width=PAGE_WIDTH - 160, height=max(40, 30 * occluder_types.height))
    )
    return _readable(chart).to_dict()


def _conflict_rows(conflicts: pl.DataFrame) -> pl.DataFrame:
    return conflicts.select(
        "recording",
        pl.col("idx_ego").alias("ego"),
        pl.col("idx").alias("target"),
        (pl.col("conflict_nanos") / 1e9).round(2).alias("conflict at (s)"),
        pl.col("timegap").round(2).alias("time gap (s)"),
        pl.col("sight_to_conflict").round(2).alias("seen before (s)"),
        pl.col("notice_to_conflict").round(2).alias("noticed before (s)"),
        pl.col("hidden_seconds").round(2).alias("hidden in the 5 s before (s)"),
        pl.col("hidden_by").list.eval(pl.element().cast(pl.String)).list.join(" ").alias("hidden by (idx)"),
    )


def _table_html(table: pl.DataFrame, element_id: str) -> str:
    """An HTML table; the columns of :data:`SHARES` as percentages (``72.4 %``)."""

    def cell(value: Any, column: str) -> str:
        if value is None:
            return "–"
        if column == "mcap":  # the recording with the answer drawn in, to open in Lichtblick
            return f'<a href="{html.escape(str(value), quote=True)}">{html.escape(Path(str(value)).name)}</a>'
        if column in SHARES and isinstance(value, float | int):
            return f"{100 * value:.1f} %"
        if isinstance(value, float):
            return f"{value:.3f}".rstrip("0").rstrip(".") if abs(value) < 1e6 else f"{value:g}"
        return html.escape(str(value))

    titles = {"mcap": "with the answer drawn in (open in Lichtblick)"}
    head = "".join(f"<th>{html.escape(titles.get(c, c))}</th>" for c in table.columns)
    rows = (
        "".join(f"<td>{cell(v, c)}</td>" for v, c in zip(row, table.columns, strict=True)) for row in table.iter_rows()
    )
    body = "".join(f"<tr>{row}</tr>" for row in rows)
    return f'<table id="{element_id}"><thead><tr>{head}</tr></thead><tbody>{body}</tbody></table>'


PAGE = """<!DOCTYPE html>
<html lang="en">
<head>
<meta charset="utf-8">
<title>{title}</title>
<style>
body {{ font-family: system-ui, sans-serif; margin: 1.5em 2em; color: #222; }}
h1 {{ font-size: 1.5em; margin-bottom: 0.2em; }} .sub {{ color: #555; margin-top: 0; }}
table {{ border-collapse: collapse; font-size: 15px; }} th, td {{ border-bottom: 1px solid #ddd; padding: 3px 8px; }}
th {{ text-align: left; background: #f3f3f3; }} td {{ font-variant-numeric: tabular-nums; }}
section {{ margin: 1.2em 0 2em; }}
</style>
<script>{bundle}</script>
</head>
<body>
<h1>{title}</h1>
<p class="sub">{subtitle}</p>
<section><h2>Visible, partly occluded and hidden, by distance and type</h2><div id="bands"></div></section>
<section><h2>Visibility histogram</h2><div id="histogram"></div></section>
<section><h2>Who occludes</h2><div id="occluders"></div></section>
<section><h2>Per recording</h2>{recordings}</section>
<section><h2>Occluded conflicts</h2>{conflicts}</section>
<script id="chart-data" type="application/json">{charts}</script>
<script>
(() => {{
  const charts = JSON.parse(document.getElementById("chart-data").textContent);
  const names = Object.keys(charts);
  Promise.all(names.map((name) => vegaEmbed("#" + name, charts[name], {{ actions: false, renderer: "svg" }})))
    .then(() => {{ document.body.dataset.charts = "ready"; }})
    .catch((err) => {{ console.error("charts: " + err); }});
}})();
</script>
</body>
</html>
"""
