"""``run``: the visibility table of one recording, printed or written."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import polars as pl
import typer

from .app import app
from .common import (
    RUN_MAP,
    RUN_OUTPUT,
    Ego,
    Engine,
    MapOccluders,
    Measure,
    Mode,
    Occluders,
    Progress,
    Recording,
    Sensors,
    Static,
    Targets,
    default_observer,
    fail,
    load_recording,
    resolve_map,
    shell_query,
)


@app.command(short_help="the visibility table of one recording, printed or written")
def run(
    recording: Recording,
    ego: Ego = "",
    engine: Engine = None,
    output: Annotated[Path | None, typer.Option("-o", "--output", metavar="PATH", help=RUN_OUTPUT)] = None,
    map_path: Annotated[Path | None, typer.Option("--map", metavar="MAP", help=RUN_MAP)] = None,
    static: Static = None,
    workers: Annotated[
        int | None, typer.Option(metavar="N", help="processes (default: all cores for long jobs)")
    ] = None,
    progress: Progress = True,
    rows: Annotated[
        int, typer.Option(metavar="N", help="rows of the table and of the per-target summary to print (no output)")
    ] = 20,
    sensors: Sensors = None,
    mode: Mode = "2d",
    map_occluders: MapOccluders = False,
    occluders: Occluders = None,
    targets: Targets = None,
    measure: Measure = "angle",
) -> None:
    """Compute the visibility table of one recording; print it with a per-target summary, or write it."""
    from ..analysis.summary import DEFINITION, target_summary
    from ..api import get_visibility_df
    from ..table.output import check_dataset_path, check_output_path, write_csv

    # every check that needs no computing comes first, so a typo never costs a long run
    if workers is not None and workers < 1:
        raise fail(f"--workers takes a number of processes, at least 1, not {workers}")
    if rows < 0:
        raise fail(f"--rows takes a number of rows to print, 0 or more, not {rows}")
    if output is not None:
        try:
            output = check_output_path(output, (".parquet", ".csv", ".mcap"))
            if output.suffix == ".parquet":  # a folder of parts: a single file there is refused before reading
                check_dataset_path(output)
            if output.suffix == ".mcap" and output.exists():
                raise ValueError(f"{output} exists already: an MCAP of the answer is written as a new file")
        except ValueError as e:
            raise fail(e) from None
    map_path = resolve_map(recording, map_path)
    question = shell_query(recording, ego=ego, engine=engine, static=static, sensors=sensors, mode=mode,
                           map_path=map_path, map_occluders=map_occluders, occluders=occluders, targets=targets,
                           measure=measure)  # fmt: skip
    r = load_recording(recording, map_path)
    note = None
    if question.observers is None:
        host, note = default_observer(r, recording)
        question = question.replace(observers=host)
    stream = output if output is not None and output.suffix == ".parquet" else None
    try:
        table = get_visibility_df(r, query=question, progress=progress, workers=workers, output=stream)
        if output is not None and output.suffix == ".mcap":
            from ..export.mcap import write_answer_mcap  # (only here: 35 ms of every other run)

            written = write_answer_mcap(recording, r, table, output, question)
        elif output is not None and stream is None:
            write_csv(table, output)
    except ValueError as e:
        raise fail(e) from None
    except OSError as e:  # the disk filled up or the folder vanished while computing
        raise fail(f"cannot write {output}: {e}") from None
    except KeyboardInterrupt:  # (results are written whole or not at all)
        written = f"; nothing was written to {output}" if output is not None else ""
        typer.echo(f"interrupted{written}", err=True)
        raise typer.Exit(130) from None
    if note is not None:
        typer.echo(note)
    if stream is not None:
        typer.echo(f"wrote {table.select(pl.len()).collect().item()} rows to {output}")
    elif output is not None and output.suffix == ".mcap":
        typer.echo(
            f"wrote {output} ({table.height} rows drawn) and {len(written) - 1} OSI SensorData trace(s) beside it"
        )
    elif output is not None:
        typer.echo(f"wrote {table.height} rows to {output}")
    else:
        with pl.Config(tbl_rows=rows, tbl_cols=-1, fmt_table_cell_list_len=8):
            typer.echo(table)
        typer.echo("per target (columns explained in the docs: Definitions):")
        summary = target_summary(table)
        with pl.Config(
            tbl_rows=-1, tbl_cols=-1, fmt_table_cell_list_len=8, tbl_width_chars=200, tbl_hide_dataframe_shape=True
        ):
            typer.echo(summary.head(rows))
        if summary.height > rows:
            typer.echo(f"and {summary.height - rows} more targets (--rows N shows N of them)")
        typer.echo(f"shares of each target's frames; {DEFINITION}")
