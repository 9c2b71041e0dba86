"""``statistics``: occlusion statistics over a batch output folder (per recording and overall)."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import polars as pl
import typer

from .app import app
from .common import fail


@app.command(short_help="occlusion statistics over a batch output folder")
def statistics(
    folder: Annotated[Path, typer.Argument(metavar="FOLDER", help="a batch output folder (batch ... -o FOLDER)")],
    bands: Annotated[
        str, typer.Option(metavar="METRES", help="distance band bounds, comma-separated, ascending")
    ] = "20,50",
    partly: Annotated[
        str,
        typer.Option(
            metavar="LOW,HIGH",
            help="bounds of partly hidden on the seen share: at or below LOW hidden, at or above HIGH visible",
        ),
    ] = "0,1",
) -> None:
    """Print how often road users were visible, partly hidden, hidden or out of view (docs: Definitions), per
    recording, by distance band and target type, the visibility histogram, and the types of the objects that
    occluded them."""
    from ..analysis.classes import check_partly, describe
    from ..batch.campaign import campaign_statistics

    try:
        bounds = tuple(float(b) for b in bands.split(","))
    except ValueError:
        raise fail(f"--bands takes distances in metres separated by commas, e.g. 20,50, not {bands!r}") from None
    try:
        partly = check_partly(tuple(float(b) for b in partly.split(",")))
    except ValueError:
        raise fail(
            f"--partly takes two shares LOW,HIGH with 0 <= LOW < HIGH <= 1, e.g. 0.1,0.9, not {partly!r}"
        ) from None
    try:
        stats = campaign_statistics(folder, bands=bounds, partly=partly)
    except ValueError as e:
        raise fail(e) from None
    typer.echo(describe(partly))
    with pl.Config(tbl_rows=-1, tbl_cols=-1, tbl_width_chars=200, tbl_hide_dataframe_shape=True, fmt_str_lengths=80):
        for title, name in (
            ("per recording", "by_recording"),
            ("by distance band and target type", "by_band"),
            ("visibility histogram", "histogram"),
            (
                "who occludes (rows: in which an object of that type hides the target; occluders: such objects "
                "summed over the rows)",
                "occluder_types",
            ),
        ):
            typer.echo(f"{title}:")
            typer.echo(stats[name])
