"""The report's tables: the per-target summary (one definition of hidden, stated under it) and the combined
"any sensor" row of a table through sensors, as the timeline shows it."""

from __future__ import annotations

import html

import polars as pl

from ..analysis.classes import EXACT, describe
from ..analysis.summary import target_summary
from ..table.schema import static_names
from .data import of_best_sensor
from .style import percent


def with_any_sensor(table: pl.DataFrame) -> pl.DataFrame:
    """A per-sensor table with, per (frame, target), one more row: sensor ``"any sensor"``, the best visibility
    over the sensors (as ``seen_by_any`` gives it, the number the scene shows), the occluders of that best sensor
    (what the scene outlines), and
    a status: visible or partly visible by that visibility, else occluded if some sensor is occluded, else out
    of range if some sensor is, else out of view. A table without ``sensor`` is returned as it is."""
    if "sensor" not in table.columns:
        return table
    reason = pl.col("status").cast(pl.String)
    combined = (
        table.group_by("frame", "total_nanos", "idx")
        .agg(
            pl.col("visibility").max(),
            pl.col("in_view").max(),
            of_best_sensor("occluder_idxs"),
            of_best_sensor("static_occluder_idxs"),
            (reason == "occluded").any().alias("occluded"),
            (reason == "out_of_range").any().alias("far"),
        )
        .with_columns(
            sensor=pl.lit(ANY_SENSOR),
            status=pl.when(pl.col("visibility") >= 1.0)
            .then(pl.lit("visible"))
            .when(pl.col("visibility") > 0.0)
            .then(pl.lit("partly_visible"))
            .when(pl.col("occluded"))
            .then(pl.lit("occluded"))
            .when(pl.col("far"))
            .then(pl.lit("out_of_range"))
            .otherwise(pl.lit("out_of_fov")),
        )
    )
    columns = [c for c in table.columns if c in combined.columns]
    per_sensor = table.select(columns).with_columns(pl.col("sensor").cast(pl.String), pl.col("status").cast(pl.String))
    both = pl.concat([combined.select(columns), per_sensor], how="vertical_relaxed")
    return both.sort("frame", "idx", pl.col("sensor") != ANY_SENSOR, maintain_order=True)


ANY_SENSOR = "any sensor"


HEADINGS = {
    "mean_visibility": "mean visibility",
    "min_visibility": "least visibility",
    "visible_share": "visible",
    "partly_hidden_share": "partly hidden",
    "hidden_share": "hidden",
    "out_of_view_share": "out of view",
    "occluders": "hidden by (idx)",
    "static_occluders": "hidden by static occluders",
}
"""The columns of :func:`~omega_prime_visibility.target_summary` as the report heads them."""


def summary_html(table: pl.DataFrame, partly: tuple[float, float] = EXACT) -> str:
    """The per-target summary (:func:`~omega_prime_visibility.target_summary`) as an HTML table: frames, mean and
    least visibility, the share of frames visible,
    partly hidden, hidden and (through sensors) out of view by the one definition of
    :mod:`~omega_prime_visibility.analysis.classes`, stated under the table, and every object and static occluder
    that hid it at some time (static occluders named ``static #k`` by their position in the list given)."""
    summary = (
        target_summary(table, partly=partly)
        .drop("idx_ego", "partly_out_of_view_share", strict=False)
        .rename(HEADINGS, strict=False)
    )
    head = "".join(f"<th>{html.escape(c)}</th>" for c in summary.columns)
    body = []
    for row in summary.iter_rows(named=True):
        cells = []
        for name, value in row.items():
            if name in ("visible", "partly hidden", "hidden", "out of view"):
                text = percent(value)
            elif name in ("mean visibility", "least visibility"):
                text = f"{100 * value:.1f}%"  # in % as the scene and the timeline say it
            elif isinstance(value, float):
                text = f"{value:.3f}"
            elif name == "hidden by static occluders":
                text = static_names(value)
            elif isinstance(value, list):
                text = ", ".join(map(str, value)) or "none"
            else:
                text = str(value)
            cells.append(f"<td>{html.escape(text)}</td>")
        body.append(f"<tr>{''.join(cells)}</tr>")
    note = html.escape(f"Shares of the target's frames; {describe(partly)}.")
    return (
        f'<table id="summary"><thead><tr>{head}</tr></thead><tbody>{"".join(body)}</tbody></table>'
        f'<p class="definition">{note}</p>'
    )
