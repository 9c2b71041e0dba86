"""Command line: ``omega-prime-visibility run RECORDING --ego 0`` prints or writes the visibility table of one
recording; ``batch INPUTS... -o OUTDIR`` computes many, locally or on a dask cluster; ``animate`` renders a GIF
or MP4, ``report`` an interactive HTML page."""

from __future__ import annotations

import re
import sys
import warnings
from pathlib import Path
from typing import Annotated

import numpy as np
import polars as pl
import pyarrow as pa
import pyarrow.compute as pc
import typer

from .engines import ENGINES, ENGINES_3D

# plain help (no rich markup): option types are shown as the metavars below, never as <str>/<bool> tags, and
# text in square brackets is printed as written
HELP = (
    "Exact visibility of road users in traffic recordings. 'run RECORDING' prints or writes the visibility table"
    " of one recording; 'batch INPUTS -o FOLDER' computes many, locally or on a dask cluster; 'animate' renders a"
    " GIF or MP4 and 'report' an interactive HTML page. Add --help after a command for its options."
)
app = typer.Typer(add_completion=False, no_args_is_help=True, help=HELP, rich_markup_mode=None)
# an argument's metavar names it (RECORDING, INPUTS); typer would add its type as a tag (<path>, <list[str]>)
typer.core.TyperArgument.display_type_rich = lambda self, ctx: None


def _print_version(asked: bool) -> None:
    if asked:
        from . import __version__

        typer.echo(f"omega-prime-visibility {__version__}")
        raise typer.Exit()


@app.callback()
def _options(
    version: Annotated[
        bool, typer.Option("--version", callback=_print_version, is_eager=True, help="print the version and exit")
    ] = False,
) -> None:
    """The options before the command; warnings are shown as one line each, without Python's source line."""
    warnings.showwarning = show_warning


def show_warning(message, category, filename, lineno, file=None, line=None) -> None:
    """A warning as one line on stderr, ``warning: ...``, in place of Python's two lines with file and source."""
    typer.echo(f"warning: {' '.join(str(message).split())}", err=True)


def parse_ego(ego: str) -> int | list[int] | str:
    """``--ego`` as the API's ``ego_idx``; a bad value exits with a one-line error (not typer's boxed one)."""
    if ego == "all":
        return "all"
    try:
        values = [int(v) for v in ego.split(",")]
    except ValueError:
        hint = " (write 'all' in lower case)" if ego.lower() == "all" else ""
        raise fail(f"--ego takes an idx, a comma-separated list of idx, or 'all', not {ego!r}{hint}") from None
    return values[0] if len(values) == 1 else values


def parse_sensors(spec: str | None):
    """``--sensors`` as the API's ``sensors`` (checked before any computing); a bad value exits with one line."""
    if spec is None:
        return None
    from .inputs.sensors import resolve_sensors

    try:
        return resolve_sensors(spec)
    except ValueError as e:
        raise fail(str(e)) from None


def fail(message: str) -> typer.Exit:
    """Print ``error: message`` (in a shell user's words) to stderr; return the exit to raise (status 2)."""
    typer.echo(f"error: {shell_words(message)}", err=True)
    return typer.Exit(2)


def shell_words(message: str) -> str:
    """An API message in a shell user's words: ``mode='3d'`` becomes ``--mode 3d``."""
    return re.sub(r"\bmode='(2d|3d)'", r"--mode \1", message)


def resolve_map(path: Path, map_path: Path | None) -> Path | None:
    """``--map`` for the recording ``path``: a ``.json`` map is a list of [trace, map] pairs (as ``batch --map``
    takes it), the trace looked up by its file name; an MCAP file needs no map."""
    if map_path is None or map_path.suffix.lower() != ".json":
        return map_path
    if path.suffix == ".mcap":
        return None
    from .batch.options import _map_table

    try:
        table = _map_table(str(map_path), map_path.stat().st_mtime_ns)
    except OSError as e:
        raise fail(f"cannot read the map list {map_path}: {e.strerror or e}") from None
    except ValueError as e:
        raise fail(str(e)) from None
    if path.name not in table:
        raise fail(f"the map list {map_path} has no map for {path.name} (it lists {', '.join(sorted(table))})")
    return Path(table[path.name])


def load_recording(path: Path, map_path: Path | None = None):
    """``io.read_recording`` (the map through :func:`resolve_map`), turning a read error into a one-line message
    and exit status 2."""
    from .inputs.io import RecordingReadError, read_recording

    map_path = resolve_map(path, map_path)
    try:
        return read_recording(path, map_path)
    except RecordingReadError as e:
        raise fail(str(e)) from e


RUN_OUTPUT = (
    "write the table here instead of printing it: a .parquet path becomes a folder of parquet parts, as the API's"
    " get_visibility_df(output=...) writes it (read it back with polars.read_parquet); a .csv path becomes one"
    " file with the list columns (occluder idx) joined by spaces. (batch writes one .parquet file per recording.)"
)
RUN_MAP = (
    "OpenDRIVE map (.xodr) for an OSI trace, or a JSON list of [trace, map] pairs as batch takes it (the trace is"
    " looked up by its file name). An MCAP file carries its own map. An OSI trace without --map is read without"
    " a map: the visibility is the same, but there are no road objects for --map-occluders."
)

# options shared by run and batch
Ego = Annotated[
    str, typer.Option(metavar="IDX", help="observer idx, comma-separated idx, or 'all'; default: host vehicle")
]
Engine = Annotated[
    str | None,
    typer.Option(
        metavar="NAME",
        help=f"2D: {', '.join(sorted(ENGINES))} (default visilibity); 3D: {', '.join(sorted(ENGINES_3D))}",
    ),
]
Mode = Annotated[
    str, typer.Option(metavar="2d|3d", help="2d (bird's-eye view, exact) or 3d (boxes with heights, ray cast)")
]
MapOccluders = Annotated[
    bool, typer.Option("--map-occluders", help="road objects of the map (--map, or the recording's) as occluders")
]
Static = Annotated[
    Path | None, typer.Option("--static", metavar="FILE", help="static occluders: GeoJSON or WKT file (metres)")
]
Sensors = Annotated[
    str | None,
    typer.Option(
        metavar="LAYOUT",
        help="look through sensors: 'roof', 'typical' or a sensors .json file (angles in radians)",
    ),
]
Recording = Annotated[
    Path, typer.Argument(metavar="RECORDING", help="omega-prime MCAP file, or an OSI trace (.osi) with --map")
]
Progress = Annotated[bool, typer.Option(help="show a progress bar")]


def load_static(path: Path | None) -> list | None:
    """``io.read_static_occluders``, a read error becoming a one-line message and exit status 2."""
    from .inputs.io import RecordingReadError, read_static_occluders

    try:
        return None if path is None else read_static_occluders(path)
    except RecordingReadError as e:
        raise fail(str(e)) from e


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
    rows: Annotated[int, typer.Option(metavar="N", help="rows to print when no output is given")] = 20,
    sensors: Sensors = None,
    mode: Mode = "2d",
    map_occluders: MapOccluders = False,
) -> None:
    """Compute the visibility table of one recording; print it with a per-target summary, or write it."""
    from .api import get_visibility_df
    from .inputs.observers import describe_idx
    from .table.output import atomic_write, check_output_path

    # every check that needs no computing comes first, so a typo never costs a long run
    from .threed.mode import check_mode, resolve_engine

    try:
        mode = check_mode(mode)
        engine = resolve_engine(engine, mode)
    except ValueError as e:
        raise fail(str(e)) from None
    if output is not None:
        try:
            output = check_output_path(output, (".parquet", ".csv"))
        except ValueError as e:
            raise fail(str(e)) from None
    ego_idx = parse_ego(ego) if ego else None
    sensor_set = parse_sensors(sensors)
    statics = load_static(static)
    map_path = resolve_map(recording, map_path)
    r = load_recording(recording, map_path)
    if ego_idx is None and r.host_vehicle_idx is None:
        present = np.unique(r._df["idx"].to_numpy())
        raise fail(f"{recording} names no host vehicle: pass --ego IDX (idx present: {describe_idx(present)})")
    if ego_idx is None:
        ego_idx = int(r.host_vehicle_idx)
    stream = output if output is not None and output.suffix == ".parquet" else None
    try:
        table = get_visibility_df(
            r,
            ego_idx,
            statics,
            engine=engine,
            progress=progress,
            workers=workers,
            output=stream,
            sensors=sensor_set,
            mode=mode,
            map_occluders=(map_path if map_path is not None else True) if map_occluders else None,
        )
        if output is not None and stream is None:
            with atomic_write(output) as temp:
                table.with_columns(
                    pl.col("occluder_idxs", "static_occluder_idxs")
                    .list.eval(pl.element().cast(pl.String))
                    .list.join(" ")
                ).write_csv(temp)
    except ValueError as e:
        raise fail(str(e)) from None
    except OSError as e:  # the disk filled up or the folder vanished while computing
        raise fail(f"cannot write {output}: {e}") from None
    if stream is not None:
        typer.echo(f"wrote {table.select(pl.len()).collect().item()} rows to {output}")
    elif output is not None:
        typer.echo(f"wrote {table.height} rows to {output}")
    else:
        with pl.Config(tbl_rows=rows, tbl_cols=-1, fmt_table_cell_list_len=8):
            typer.echo(table)
        by = [c for c in ("idx_ego", "idx", "sensor") if c in table.columns]
        summary = table.group_by(by).agg(
            pl.col("visibility").mean().alias("mean_visibility"),
            (pl.col("visibility") == 0.0).mean().alias("hidden_share"),
        )
        # (row, occluder) pairs through arrow: polars' own explode warns about a default changing in polars 2
        lists = table["occluder_idxs"].to_arrow()
        lists = pa.concat_arrays(lists.chunks) if isinstance(lists, pa.ChunkedArray) else lists
        pairs = pl.DataFrame({"row": pc.list_parent_indices(lists), "occluders": pc.list_flatten(lists)})
        occluders = (
            table.with_row_index("row")
            .select("row", *by)
            .join(pairs.with_columns(pl.col("row").cast(pl.UInt32)), on="row", how="left")
            .group_by(by)
            .agg(pl.col("occluders").drop_nulls().unique().sort())
        )
        summary = summary.join(occluders, on=by)
        with pl.Config(tbl_rows=-1, fmt_table_cell_list_len=8):
            typer.echo(summary.sort(by))


def parse_frames(frames: str) -> slice | None:
    """``--frames START:STOP[:STEP]`` (frame numbers, stop excluded, either end may be left out) as a slice."""
    if not frames:
        return None
    parts = frames.split(":")
    try:
        if len(parts) not in (2, 3):
            raise ValueError
        values = [int(p) if p.strip() else None for p in parts]
    except ValueError:
        raise fail(
            f"--frames takes START:STOP or START:STOP:STEP (frame numbers, stop excluded), not {frames!r}"
        ) from None
    if len(values) == 3 and values[2] is not None and values[2] <= 0:
        raise fail(f"--frames: the step must be a positive number of frames, not {values[2]}")
    return slice(*values)


def single_ego(ego: str) -> int | None:
    """``--ego`` for a picture: one idx, or None for the recording's host vehicle."""
    if not ego:
        return None
    value = parse_ego(ego)
    if not isinstance(value, int):
        raise fail(f"--ego takes one idx for a picture, not {ego!r}")
    return value


def picture_inputs(
    recording: Path, output: Path, suffixes: tuple[str, ...], engine: str, frames: str, ego: str, map_path: Path | None
):
    """A picture command's checks that need no computing (engine, output path, frames, ego), then the recording
    and its ego (``--ego``, else the host vehicle): ``(recording, ego_idx, frames)``."""
    from .table.output import check_output_path

    if engine not in ENGINES:
        raise fail(f"unknown engine {engine!r}; available: {sorted(ENGINES)}")
    try:
        check_output_path(output, suffixes)
    except ValueError as e:
        raise fail(str(e)) from None
    span, ego_idx = parse_frames(frames), single_ego(ego)
    r = load_recording(recording, map_path)
    if ego_idx is None:
        if r.host_vehicle_idx is None:
            raise fail("the recording names no host vehicle: pass --ego IDX")
        ego_idx = int(r.host_vehicle_idx)
    return r, ego_idx, span


FramesOption = Annotated[
    str,
    typer.Option(metavar="START:STOP", help="frame numbers START:STOP or START:STOP:STEP (stop excluded); default all"),
]
EgoOption = Annotated[str, typer.Option(metavar="IDX", help="observer idx; default: host vehicle")]
MapOption = Annotated[
    Path | None,
    typer.Option("--map", metavar="MAP", help="OpenDRIVE map for an OSI trace, or a JSON list of [trace, map] pairs"),
]
PictureEngine = Annotated[str, typer.Option(metavar="NAME", help=f"2D engine: {', '.join(sorted(ENGINES))}")]
ViewRange = Annotated[float, typer.Option(metavar="METRES", help="metres shown each side of the ego")]


@app.command(short_help="an animated GIF or MP4 of the scene seen from the ego")
def animate(
    recording: Recording,
    output: Annotated[Path, typer.Option("-o", "--output", metavar="PATH", help="write a .gif or .mp4 here")],
    ego: EgoOption = "",
    frames: FramesOption = "",
    fps: Annotated[float, typer.Option(metavar="FPS", help="frames per second")] = 10.0,
    follow: Annotated[bool, typer.Option(help="keep the ego in the middle (--no-follow: one fixed view)")] = True,
    view_range: ViewRange = 60.0,
    target: Annotated[int | None, typer.Option(metavar="IDX", help="outline this idx and its occluders")] = None,
    sensors: Annotated[
        str | None, typer.Option(metavar="LAYOUT", help="sensor layout to draw: 'roof', 'typical' or a .json file")
    ] = None,
    engine: PictureEngine = "visilibity",
    map_path: MapOption = None,
    progress: Progress = True,
) -> None:
    """Render the scene seen from the ego, frame by frame, to an animated GIF or an MP4 video."""
    from .plot import animate as render

    r, ego_idx, span = picture_inputs(recording, output, (".gif", ".mp4"), engine, frames, ego, map_path)
    if target is not None:
        from .inputs.observers import describe_idx

        present = np.unique(r._df["idx"].to_numpy())
        if target not in present:
            raise fail(f"target idx {target} never occurs in the recording (idx present: {describe_idx(present)})")
    try:
        render(r, ego_idx, output, frames=span, fps=fps, follow=follow, view_range=view_range, target=target,
               sensors=sensors, engine=engine, progress=progress)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(str(e)) from None
    typer.echo(f"wrote {output}")


@app.command(short_help="an interactive HTML report of one recording")
def report(
    recording: Recording,
    output: Annotated[Path, typer.Option("-o", "--output", metavar="PATH", help="write the .html report here")],
    ego: EgoOption = "",
    frames: FramesOption = "",
    view_range: ViewRange = 60.0,
    sensors: Annotated[
        str | None,
        typer.Option(metavar="LAYOUT", help="timeline and summary through sensors: 'roof', 'typical' or a .json file"),
    ] = None,
    engine: PictureEngine = "visilibity",
    map_path: MapOption = None,
    progress: Progress = True,
) -> None:
    """Write an interactive HTML report (frame slider, timeline, per-target summary) that works offline."""
    from .plot import write_report

    sensor_set = parse_sensors(sensors)
    r, ego_idx, span = picture_inputs(recording, output, (".html",), engine, frames, ego, map_path)
    try:
        write_report(r, ego_idx, output, frames=span, view_range=view_range, engine=engine, progress=progress,
                     title=recording.name, sensors=sensor_set)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(str(e)) from None
    typer.echo(f"wrote {output}")


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
    scheduler: Annotated[
        str | None, typer.Option(metavar="ADDRESS", help="dask scheduler address, e.g. tcp://host:8786")
    ] = None,
    scheduler_file: Annotated[
        Path | None, typer.Option(metavar="FILE", help="dask scheduler file (see dask scheduler --help)")
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
    from .batch import SUMMARY_NAME, BatchInterrupted, run_batch

    options = {"ego": parse_ego(ego) if ego else None, "engine": engine, "static": static, "map": map_path}
    options.update(sensors=sensors, mode=mode, map_occluders=map_occluders)
    try:
        summary = run_batch(
            inputs,
            output,
            workers=workers,
            scheduler=scheduler,
            scheduler_file=scheduler_file,
            overwrite=overwrite,
            progress=progress,
            **options,
        )
    except BatchInterrupted as e:
        print_summary(e.summary, output / SUMMARY_NAME)
        typer.echo("interrupted: run the same command again to continue where it stopped", err=True)
        raise typer.Exit(130) from None
    except ValueError as e:
        raise fail(str(e)) from None
    print_summary(summary, output / SUMMARY_NAME)
    if (summary["status"] == "failed").any():
        raise typer.Exit(1)


def print_summary(summary: pl.DataFrame, path: Path) -> None:
    """The summary table (failures first), one line per failure with its message, and one line of counts."""
    order = pl.col("status").replace_strict({"failed": 0, "interrupted": 1}, default=2, return_dtype=pl.Int8)
    shown = summary.sort(order, maintain_order=True).select("result", "status", "rows", "seconds")
    with pl.Config(tbl_rows=30, tbl_cols=-1, tbl_hide_dataframe_shape=True, fmt_str_lengths=120):
        typer.echo(shown)
    for recording, error in summary.filter(pl.col("status") == "failed").select("recording", "error").iter_rows():
        # each failed path named once: most messages name their file already
        typer.echo(f"failed: {error}" if str(recording) in str(error) else f"failed: {recording}: {error}")
    counts = ", ".join(f"{n} {status}" for status, n in summary["status"].value_counts(sort=True).iter_rows())
    typer.echo(f"{summary.height} recordings: {counts}; {summary['seconds'].sum():.1f} s of work; summary in {path}")


@app.command(short_help="list the available engines")
def engines() -> None:
    """List the available engines."""
    for name in sorted(ENGINES):
        typer.echo(name)
    for name in sorted(ENGINES_3D):
        typer.echo(f"{name} (--mode 3d)")


def main() -> None:
    app(sys.argv[1:])


if __name__ == "__main__":
    main()
