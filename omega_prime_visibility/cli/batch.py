"""``batch``: one result per recording into a folder, and the summary it prints."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import polars as pl
import typer

from .app import app
from .common import (
    Ego,
    Engine,
    MapOccluders,
    Measure,
    Mode,
    Occluders,
    Sensors,
    Static,
    Targets,
    fail,
    shell_query,
)


@app.command(short_help="one parquet result per recording into a folder, resumably")
def batch(
    inputs: Annotated[
        list[str],
        typer.Argument(metavar="INPUTS", help="recordings, folders (searched recursively) and glob patterns"),
    ],
    output: Annotated[
        Path, typer.Option("-o", "--output", metavar="FOLDER", help="folder for the results and the summary")
    ],
    ego: Ego = "",
    engine: Engine = None,
    static: Static = None,
    map_path: Annotated[
        Path | None,
        typer.Option(
            "--map",
            metavar="MAP",
            help="OpenDRIVE map for the OSI traces, or a JSON list of [trace, map] pairs (paths relative to it)",
        ),
    ] = None,
    workers: Annotated[
        int | None, typer.Option(metavar="N", help="local processes over files (default: the cores)")
    ] = None,
    sensors: Sensors = None,
    mode: Mode = "2d",
    map_occluders: MapOccluders = False,
    occluders: Occluders = None,
    targets: Targets = None,
    measure: Measure = "angle",
    scheduler: Annotated[
        str | None, typer.Option(metavar="ADDRESS", help="dask scheduler address, e.g. tcp://host:8786")
    ] = None,
    scheduler_file: Annotated[
        Path | None, typer.Option(metavar="FILE", help="dask scheduler file (see dask scheduler --help)")
    ] = None,
    conflicts: Annotated[
        bool,
        typer.Option(
            "--conflicts",
            help="also write each recording's occluded conflicts (PET 3 s) beside its result, as"
            " RESULT.conflicts.parquet",
        ),
    ] = False,
    mcap: Annotated[
        bool,
        typer.Option(
            "--mcap",
            help="also write each recording with the answer drawn in for Lichtblick (its own channels, the scene and"
            " rows per observer and sensor, OSI SensorData) beside its result, as RESULT.mcap",
        ),
    ] = False,
    fallback_ego: Annotated[
        int | None,
        typer.Option(
            metavar="IDX",
            help="without --ego: the observer of recordings that name no host vehicle (esmini's OSI traces; their"
            " first entity, idx 0, is usually the ego); each other recording is seen from its host vehicle",
        ),
    ] = None,
    overwrite: Annotated[bool, typer.Option(help="recompute results that are current")] = False,
    progress: Annotated[bool, typer.Option(help="show a progress bar over files")] = True,
) -> None:
    """Compute one result per recording into the --output folder, resumably, and print a summary of every file.

    Each result is a single .parquet file (run -o x.parquet writes a folder of parquet parts instead; both read
    back with polars.read_parquet). A file whose result is current is skipped; a failed one is named in the
    summary with its reason.

    Exit status: 0 when every file is done or skipped, 1 when some failed, 2 for bad options, 130 when interrupted.
    """
    from ..batch import SUMMARY_NAME, BatchInterrupted, run_batch

    question = shell_query(
        None,
        ego=ego,
        engine=engine,
        static=static,
        sensors=sensors,
        mode=mode,
        map_occluders=map_occluders,  # True: the map each recording is read with
        occluders=occluders,
        targets=targets,
        measure=measure,
    )
    try:
        summary = run_batch(
            inputs,
            output,
            question,
            map=map_path,
            conflicts=conflicts,
            mcap=mcap,
            fallback_ego=fallback_ego,
            workers=workers,
            scheduler=scheduler,
            scheduler_file=scheduler_file,
            overwrite=overwrite,
            progress=progress,
        )
    except BatchInterrupted as e:
        print_summary(e.summary, output / SUMMARY_NAME)
        typer.echo("interrupted: run the same command again to continue where it stopped", err=True)
        raise typer.Exit(130) from None
    except ValueError as e:
        raise fail(e) from None
    print_summary(summary, output / SUMMARY_NAME)
    if (summary["status"] == "failed").any():
        raise typer.Exit(1)


def print_summary(summary: pl.DataFrame, path: Path) -> None:
    """The summary table (failures first), one line per failure with its message, one per warning a recording
    gave (as ``run`` prints them), and one line of counts."""
    order = pl.col("status").replace_strict({"failed": 0, "interrupted": 1}, default=2, return_dtype=pl.Int8)
    shown = summary.sort(order, maintain_order=True).select("result", "status", "observer", "rows", "seconds")
    with pl.Config(tbl_rows=30, tbl_cols=-1, tbl_hide_dataframe_shape=True, fmt_str_lengths=120):
        typer.echo(shown)
    for recording, error in summary.filter(pl.col("status") == "failed").select("recording", "error").iter_rows():
        # each failed path named once: most messages name their file already
        error, name = str(error), Path(recording).name
        if str(recording) in error:
            typer.echo(f"failed: {error}")
        elif error.startswith(f"{name} "):  # a message that names the file by its name alone: the whole path
            typer.echo(f"failed: {recording}{error[len(name) :]}")
        else:
            typer.echo(f"failed: {recording}: {error}")
    from ..batch.task import WARNING_SEPARATOR

    for recording, notes in (
        summary.filter(pl.col("warnings").is_not_null()).select("recording", "warnings").iter_rows()
    ):
        for note in str(notes).split(WARNING_SEPARATOR):  # as run shows them: one line each, with the recording
            typer.echo(f"warning: {recording}: {note}")
    counts = ", ".join(f"{n} {status}" for status, n in summary["status"].value_counts(sort=True).iter_rows())
    typer.echo(f"{summary.height} recordings: {counts}; {summary['seconds'].sum():.1f} s of work; summary in {path}")
