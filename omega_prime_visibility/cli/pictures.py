"""``animate`` and ``report``: the picture commands, with the checks they share."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated

import numpy as np
import typer

from ..engines import ENGINES, ENGINES_3D
from .app import app
from .common import (
    Mode,
    Occluders,
    Progress,
    Recording,
    Static,
    fail,
    load_recording,
    load_static,
    parse_choice,
    parse_ego,
    parse_sensors,
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


def picture_inputs(
    recording: Path,
    output: Path,
    suffixes: tuple[str, ...],
    engine: str | None,
    frames: str,
    ego: str,
    map_path: Path | None,
    mode: str = "2d",
):
    """A picture command's checks that need no computing (mode and engine, output path, frames, ego), then the
    recording and its ego (``--ego``, else the host vehicle): ``(recording, ego_idx, frames, engine)``."""
    from ..table.output import check_output_path
    from ..threed.mode import check_mode, resolve_engine

    try:
        engine = resolve_engine(engine, check_mode(mode))
        check_output_path(output, suffixes)
    except ValueError as e:
        raise fail(str(e)) from None
    span, ego_idx = parse_frames(frames), single_ego(ego)
    r = load_recording(recording, map_path)
    if ego_idx is None:
        if r.host_vehicle_idx is None:
            raise fail("the recording names no host vehicle: pass --ego IDX")
        ego_idx = int(r.host_vehicle_idx)
    return r, ego_idx, span, engine


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
    progress: Progress = True,
) -> None:
    """Render the scene seen from the ego, frame by frame, to an animated GIF or an MP4 video."""
    from ..plot import animate as render

    parse_sensors(sensors)  # a bad layout or file fails here; a layout name is fitted to the ego later
    blocking = parse_choice(occluders, "occluders")
    statics = load_static(static)
    r, ego_idx, span, engine = picture_inputs(recording, output, (".gif", ".mp4"), engine, frames, ego, map_path, mode)
    if target is not None:
        from ..inputs.observers import describe_idx

        present = np.unique(r._df["idx"].to_numpy())
        if target not in present:
            raise fail(f"target idx {target} never occurs in the recording (idx present: {describe_idx(present)})")
    try:
        render(r, ego_idx, output, statics, frames=span, fps=fps, follow=follow, view_range=view_range,
               target=target, sensors=sensors, engine=engine, mode=mode, progress=progress,
               occluders=blocking)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(str(e)) from None
    typer.echo(f"wrote {output}")


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
    view_range: ViewRange = 60.0,
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
    progress: Progress = True,
) -> None:
    """Write an interactive HTML report (frame slider, timeline, per-target summary) that works offline; for a batch
    output folder, the campaign page (occlusion statistics by distance and type, per recording, the conflicts)."""
    from ..plot import write_report

    if recording.is_dir():
        given = {"--ego": ego, "--frames": frames, "--sensors": sensors, "--engine": engine, "--map": map_path,
                 "--static": static, "--mode": mode != "2d", "--occluders": occluders}  # fmt: skip
        used = [flag for flag, value in given.items() if value]
        if used:
            raise fail(f"{' and '.join(used)} apply to one recording; {recording} is a folder (a campaign page)")
        return _campaign_page(recording, output)

    parse_sensors(sensors)  # a bad layout or file fails here; a layout name is fitted to the ego later
    blocking = parse_choice(occluders, "occluders")
    statics = load_static(static)
    r, ego_idx, span, engine = picture_inputs(recording, output, (".html",), engine, frames, ego, map_path, mode)
    try:
        write_report(r, ego_idx, output, statics, frames=span, view_range=view_range, engine=engine, mode=mode,
                     progress=progress, title=recording.name, sensors=sensors, occluders=blocking)  # fmt: skip
    except (ValueError, ImportError) as e:
        raise fail(str(e)) from None
    typer.echo(f"wrote {output}")


def _campaign_page(folder: Path, output: Path) -> None:
    """``report FOLDER -o page.html``: the campaign page of a batch output folder."""
    from ..plot.campaign import write_campaign_page
    from ..table.output import check_output_path

    try:
        check_output_path(output, (".html",))
        write_campaign_page(folder, output)
    except (ValueError, ImportError) as e:
        raise fail(str(e)) from None
    typer.echo(f"wrote {output}")
