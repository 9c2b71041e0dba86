"""``animate`` and ``report``: the picture commands, with the checks they share."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..engines.registry import ENGINES, ENGINES_3D
from ..plot.window import AUTO
from .app import app
from .common import (
    MapOccluders,
    Measure,
    Mode,
    Occluders,
    Progress,
    Recording,
    Static,
    Targets,
    default_observer,
    fail,
    load_recording,
    parse_ego,
    resolve_map,
    shell_query,
)


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


def check_view_range(view_range: float | None) -> None:
    """``--view-range``: a positive, finite number of metres (or not given); else one line, before any reading."""
    if view_range is not None and not 0 < view_range < math.inf:
        raise fail(f"--view-range must be a positive number of metres, not {view_range}")


def picture_inputs(recording: Path, output: Path, suffixes: tuple[str, ...], frames: str, ego: str,
                   map_path: Path | None, **table_options):  # fmt: skip
    """A picture command's checks that need no computing (the question of ``table_options``, as ``run`` takes
    them; the output path, frames, ego), then the recording and its observer (``--ego``, else the host vehicle):
    ``(recording, question, frames, note)``, the note saying which observer was chosen when ``--ego`` was not
    given (else None)."""
    from ..table.output import check_output_path

    span, ego_idx = parse_frames(frames), single_ego(ego)
    map_path = resolve_map(recording, map_path)
    question = shell_query(recording, ego="" if ego_idx is None else str(ego_idx), map_path=map_path,
                           **table_options)  # fmt: skip
    try:
        check_output_path(output, suffixes)
    except ValueError as e:
        raise fail(e) from None
    r = load_recording(recording, map_path)
    note = None
    if question.observers is None:
        host, note = default_observer(r, recording)
        question = question.replace(observers=host)
    return r, question, span, note


FramesOption = Annotated[
    str,
    typer.Option(metavar="START:STOP", help="frame numbers START:STOP or START:STOP:STEP (stop excluded); default all"),
]
EgoOption = Annotated[str, typer.Option(metavar="IDX", help="observer idx; default: host vehicle")]
MapOption = Annotated[
    Path | None,
    typer.Option("--map", metavar="MAP", help="OpenDRIVE map for an OSI trace, or a JSON list of [trace, map] pairs"),
]
PictureEngine = Annotated[
    str | None,
    typer.Option(
        metavar="NAME",
        help=f"2D: {', '.join(sorted(ENGINES))} (default visilibity); 3D: {', '.join(sorted(ENGINES_3D))}",
    ),
]
ViewRange = Annotated[
    float | None,
    typer.Option(
        metavar="METRES",
        help="show every road user within this many metres of the ego (default: 50, or through --sensors the"
        " reach of those that look around)",
        show_default=False,
    ),
]


@app.command(short_help="an animated GIF or MP4 of the scene seen from the ego")
def animate(
    recording: Recording,
    output: Annotated[Path, typer.Option("-o", "--output", metavar="PATH", help="write a .gif or .mp4 here")],
    ego: EgoOption = "",
    frames: FramesOption = "",
    fps: Annotated[float, typer.Option(metavar="FPS", help="frames per second")] = 10.0,
    follow: Annotated[bool, typer.Option(help="keep the ego in the middle (--no-follow: one fixed view)")] = True,
    view_range: ViewRange = None,
    target: Annotated[int | None, typer.Option(metavar="IDX", help="outline this idx and its occluders")] = None,
    sensors: Annotated[
        str | None,
        typer.Option(
            metavar="LAYOUT", help="look through sensors ('roof', 'typical' or a .json file): their fields drawn"
        ),
    ] = None,
    engine: PictureEngine = None,
    map_path: MapOption = None,
    static: Static = None,
    mode: Mode = "2d",
    occluders: Occluders = None,
    targets: Targets = None,
    measure: Measure = "angle",
    map_occluders: MapOccluders = False,
    progress: Progress = True,
) -> None:
    """Render the scene seen from the ego, frame by frame, to an animated GIF or an MP4 video."""
    from ..plot import animate as render

    table_options = {"engine": engine, "static": static, "sensors": sensors, "mode": mode, "occluders": occluders,
                     "targets": targets, "measure": measure, "map_occluders": map_occluders}  # fmt: skip
    check_view_range(view_range)
    r, question, span, note = picture_inputs(recording, output, (".gif", ".mp4"), frames, ego, map_path,
                                             **table_options)  # fmt: skip
    if target is not None:
        from ..inputs.observers import describe_idx
        from ..inputs.scene import as_polars

        present = np.unique(as_polars(r)["idx"].to_numpy())
        if target not in present:
            raise fail(f"target idx {target} never occurs in the recording (idx present: {describe_idx(present)})")
    try:
        render(r, None, output, frames=span, fps=fps, follow=follow, view_range=view_range or AUTO, target=target,
               progress=progress, query=question)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(e) from None
    _done(output, note)


@app.command(short_help="an interactive HTML report of one recording, or of a batch output folder")
def report(
    recording: Annotated[
        Path,
        typer.Argument(
            metavar="RECORDING",
            help="omega-prime MCAP file, an OSI trace (.osi) with --map, or a batch output folder (a campaign page)",
        ),
    ],
    output: Annotated[Path, typer.Option("-o", "--output", metavar="PATH", help="write the .html report here")],
    ego: EgoOption = "",
    frames: FramesOption = "",
    view_range: ViewRange = None,
    sensors: Annotated[
        str | None,
        typer.Option(
            metavar="LAYOUT", help="scene, timeline and summary through sensors: 'roof', 'typical' or a .json file"
        ),
    ] = None,
    engine: PictureEngine = None,
    map_path: MapOption = None,
    static: Static = None,
    mode: Mode = "2d",
    occluders: Occluders = None,
    targets: Targets = None,
    measure: Measure = "angle",
    map_occluders: MapOccluders = False,
    progress: Progress = True,
) -> None:
    """Write an interactive HTML report (frame slider, timeline, per-target summary) that works offline; for a batch
    output folder, the campaign page (occlusion statistics by distance and type, per recording, the conflicts)."""
    from ..plot import write_report

    if recording.is_dir():
        given = {"--ego": ego, "--frames": frames, "--sensors": sensors, "--engine": engine, "--map": map_path,
                 "--static": static, "--mode": mode != "2d", "--occluders": occluders, "--targets": targets,
                 "--measure": measure != "angle", "--map-occluders": map_occluders}  # fmt: skip
        used = [flag for flag, value in given.items() if value]
        if used:
            raise fail(f"{' and '.join(used)} apply to one recording; {recording} is a folder (a campaign page)")
        return _campaign_page(recording, output)

    table_options = {"engine": engine, "static": static, "sensors": sensors, "mode": mode, "occluders": occluders,
                     "targets": targets, "measure": measure, "map_occluders": map_occluders}  # fmt: skip
    check_view_range(view_range)
    r, question, span, note = picture_inputs(recording, output, (".html",), frames, ego, map_path, **table_options)
    try:
        write_report(r, None, output, frames=span, view_range=view_range or AUTO, progress=progress,
                     title=recording.name, query=question)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(e) from None
    _done(output, note)


def _done(output: Path, note: str | None) -> None:
    """A picture command's closing lines: which observer, when chosen by default, and what was written."""
    if note is not None:
        typer.echo(note)
    typer.echo(f"wrote {output}")


def _campaign_page(folder: Path, output: Path) -> None:
    """``report FOLDER -o page.html``: the campaign page of a batch output folder."""
    from ..plot.campaign import write_campaign_page
    from ..table.output import check_output_path

    try:
        check_output_path(output, (".html",))
        write_campaign_page(folder, output)
    except (ValueError, ImportError) as e:
        raise fail(e) from None
    typer.echo(f"wrote {output}")
