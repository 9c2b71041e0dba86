"""What the commands share: the one-line error, the parsing of ``--ego``/``--sensors``/``--map``, reading a
recording or static occluders as a shell user's error, and the options run and batch take alike."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Annotated

import typer

from ..engines.registry import ENGINES, ENGINES_3D
from ..inputs.errors import UNSET, OptionError, Setting


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
    from ..inputs.sensor_files import resolve_sensors

    try:
        return resolve_sensors(spec)
    except ValueError as e:
        raise fail(e) from None


def parse_choice(spec: str | None, option: str) -> list[str] | list[int] | None:
    """``--occluders``/``--targets`` as the API's ``occluders``/``targets``: comma-separated names (a group, an
    omega-prime type or subtype) or idx; an unknown name exits with one line before anything is read."""
    if spec is None:
        return None
    parts = [p.strip() for p in spec.split(",") if p.strip()]
    numbers = [re.fullmatch(r"-?\d+", p) is not None for p in parts]
    if not parts or (any(numbers) and not all(numbers)):
        raise fail(f"--{option} takes comma-separated names (e.g. vehicles,BICYCLE) or idx (e.g. 3,7), not {spec!r}")
    if all(numbers):
        return [int(p) for p in parts]
    from ..inputs.roles import check_names

    try:
        check_names(parts, option)
    except ValueError as e:
        raise fail(e) from None
    return parts


def shell_query(
    recording: Path | None,
    *,
    ego: str = "",
    engine: str | None = None,
    static: Path | None = None,
    sensors: str | None = None,
    mode: str = "2d",
    map_path: Path | None = None,
    map_occluders: bool = False,
    occluders: str | None = None,
    targets: str | None = None,
    measure: str = "angle",
):
    """The question of a command (:class:`~omega_prime_visibility.Query`) from the shell's table options, which
    ``run``, ``animate`` and ``report`` take alike; a bad value exits with one line naming the option, before any
    recording is read."""
    from ..query import Query

    observers = parse_ego(ego) if ego else None
    choices = {"occluders": parse_choice(occluders, "occluders"), "targets": parse_choice(targets, "targets")}
    found = load_static(static)
    statics = found.geometries if found is not None else ()
    heights = {"static_heights": found.heights} if found is not None and found.heights is not None else {}
    if map_occluders:
        map_occluders = (resolve_map(recording, map_path) if recording is not None else map_path) or True
    try:
        return Query(
            observers=observers,
            engine=engine,
            mode=mode,
            measure=measure,
            sensors=sensors,
            static_occluders=statics,
            map_occluders=map_occluders or None,
            **heights,
            **choices,
        )
    except OptionError as e:
        raise fail(e) from None


FLAGS = {
    "ego_idx": "--ego",
    "observers": "--ego",
    "static_occluder_polys": "--static",
    "static_occluders": "--static",
    "map_occluders": "--map-occluders",
}
"""The shell's flag of each API option whose name differs (the others: ``--`` and the name, ``_`` as ``-``)."""


def flag(option: str) -> str:
    """The shell's flag of the API option ``option``: ``ego_idx`` is ``--ego``."""
    return FLAGS.get(option, "--" + option.replace("_", "-"))


def shell_spelling(setting: Setting) -> str:
    """A setting as the shell spells it: ``--mode 2d``, ``--map-occluders``, ``--engine`` alone."""
    if setting.value is UNSET or setting.value is True:
        return flag(setting.option)
    if setting.option == "map_occluders":
        return f"--map-occluders --map {setting.value}"
    return f"{flag(setting.option)} {setting.value}"


def fail(error: str | Exception) -> typer.Exit:
    """Print ``error: ...`` to stderr (an :class:`~omega_prime_visibility.OptionError` in the shell's words,
    ``--mode 2d`` for ``mode='2d'``); return the exit to raise (status 2)."""
    if isinstance(error, OptionError):
        message = error.words(shell_spelling, flag(error.option))
    else:
        message = str(error)
    typer.echo(f"error: {message}", err=True)
    return typer.Exit(2)


def resolve_map(path: Path, map_path: Path | None) -> Path | None:
    """``--map`` for the recording ``path``: a ``.json`` map is a list of [trace, map] pairs (as ``batch --map``
    takes it), the trace looked up by its file name; an MCAP file needs no map."""
    if map_path is None or map_path.suffix.lower() != ".json":
        return map_path
    if path.suffix == ".mcap":
        return None
    from ..batch.options import _map_table

    try:
        table = _map_table(str(map_path), map_path.stat().st_mtime_ns)
    except OSError as e:
        raise fail(f"cannot read the map list {map_path}: {e.strerror or e}") from None
    except ValueError as e:
        raise fail(e) from None
    if path.name not in table:
        raise fail(f"the map list {map_path} has no map for {path.name} (it lists {', '.join(sorted(table))})")
    return Path(table[path.name])


def default_observer(recording, path: Path) -> tuple[int, str]:
    """The host vehicle of ``recording`` (read from ``path``), the observer when ``--ego`` is not given, and the
    line that says so (``observer: host vehicle idx 87 ...``, printed once the command has its answer); a
    recording that names none exits with one line."""
    from ..inputs.roles import kinds_present
    from ..inputs.scene import as_polars

    if recording.host_vehicle_idx is None:
        present = kinds_present(as_polars(recording))
        raise fail(f"{path} names no host vehicle: pass --ego IDX (present: {present})")
    host = int(recording.host_vehicle_idx)
    return host, f"observer: host vehicle idx {host} (the recording's; --ego IDX for another)"


def load_recording(path: Path, map_path: Path | None = None):
    """``io.read_recording`` (the map through :func:`resolve_map`), turning a read error into a one-line message
    and exit status 2."""
    from ..inputs.io import RecordingReadError, read_recording

    map_path = resolve_map(path, map_path)
    try:
        return read_recording(path, map_path)
    except RecordingReadError as e:
        raise fail(e) from e


RUN_OUTPUT = (
    "write the table here instead of printing it: a .parquet path becomes a folder of parquet parts, as the API's"
    " get_visibility_df(output=...) writes it (read it back with polars.read_parquet); a .csv path becomes one"
    " file with the list columns (occluder idx) joined by spaces; a .mcap path a new MCAP file with the recording's"
    " own channels and the answer drawn for Lichtblick, plus OSI SensorData (docs: View it in Lichtblick). (batch"
    " writes one .parquet file per recording.)"
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
    str,
    typer.Option(
        metavar="2d|3d",
        help="2d (bird's-eye view) or 3d (boxes with heights, solid angles from the eye); both exact (the API's"
        " 3D meshes are ray-cast instead)",
    ),
]
MapOccluders = Annotated[
    bool, typer.Option("--map-occluders", help="road objects of the map (--map, or the recording's) as occluders")
]
Static = Annotated[
    Path | None,
    typer.Option(
        "--static",
        metavar="FILE",
        help="static occluders (metres): GeoJSON (heights from a 'height' property), a JSON list of"
        ' {"wkt": ..., "height": ...}, or WKT, one geometry per line, optionally followed by its height',
    ),
]
Sensors = Annotated[
    str | None,
    typer.Option(
        metavar="LAYOUT",
        help="look through sensors: 'roof', 'typical' or a sensors .json file (angles in radians)",
    ),
]
CHOICE_FORMS = (
    "a group (vehicles, pedestrians, cyclists, motorcyclists, two_wheelers, vulnerable, animals, all), omega-prime"
    " type or subtype names (PEDESTRIAN, HEAVY_TRUCK) or idx, comma-separated"
)
Occluders = Annotated[
    str | None,
    typer.Option(metavar="KINDS", help=f"who may block the view: {CHOICE_FORMS}; default: everything"),
]
Targets = Annotated[
    str | None,
    typer.Option(metavar="KINDS", help=f"who gets rows (the others still block): {CHOICE_FORMS}; default: everyone"),
]
Measure = Annotated[
    str,
    typer.Option(
        metavar="angle|area",
        help="visibility as a share of the target's angular extent (angle) or of its footprint's area (area, 2D)",
    ),
]
Recording = Annotated[
    Path,
    typer.Argument(
        metavar="RECORDING", help="omega-prime MCAP file, or an OSI trace (.osi; its OpenDRIVE map with --map)"
    ),
]
Progress = Annotated[bool, typer.Option(help="show a progress bar (once a run has taken half a second)")]


def load_static(path: Path | None):
    """``io.read_static_file`` (geometries, heights where the file gives them), a read error becoming a one-line
    message and exit status 2; where heights were read, says from which property or column."""
    from ..inputs.io import RecordingReadError, read_static_file

    if path is None:
        return None
    try:
        found = read_static_file(path)
    except RecordingReadError as e:
        raise fail(e) from e
    if found.note is not None:
        typer.echo(f"static occluders: {found.note}")
    return found
