"""Reading recordings: omega-prime MCAP files and ASAM OSI traces, with errors that name the file; static occluder
files (:mod:`.static_files`)."""

from __future__ import annotations

import os
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

from .errors import RecordingReadError
from .roads import MapNotice, check_map_fits
from .static_files import read_static_file, read_static_occluders

__all__ = ["MapNotice", "RecordingReadError", "read_recording", "read_static_file", "read_static_occluders"]
"""(The static files' readers and the errors are read from here too, where they were first documented.)"""

NO_MAP = "No map could be found"  # start of omega-prime's warning when no reader could parse the map


def read_recording(path: str | os.PathLike, map_path: str | os.PathLike | None = None) -> Any:
    """A recording with object polygons, from an MCAP file (or an OSI trace with its map): what
    ``omega_prime.Recording.from_file(path, compute_polygons=True)`` gives.

    An MCAP file of OSI ground truth is read by :func:`.reader.read_mcap`, an OSI trace without a map by
    :func:`.osi_trace.read_osi` (the table omega-prime would give, ten times faster, without importing omega-prime,
    and without its warning about projections a map does not need); anything else, and a map given for it, by
    omega-prime's ``Recording.from_file``.

    Parameters
    ----------
    path : str or PathLike
        An omega-prime MCAP file, or an OSI trace (``.osi``).
    map_path : str or PathLike, optional
        The OpenDRIVE map (``.xodr``) of an OSI trace.

    Returns
    -------
    recording
        An ``omega_prime.Recording``, or the reader's :class:`.reader.TraceRecording`, which has its table
        (``_df``), ``host_vehicle_idx`` and ``map``, works in omega-prime's ``MetricManager``, and offers the rest
        of omega-prime's ``Recording`` (built on first use).

    Raises
    ------
    RecordingReadError
        If the file or the map is missing or cannot be parsed (corrupt or truncated MCAP, wrong format, a map
        that is no map); the message names the file and the underlying error.
    """
    path = Path(path)
    if not path.exists():
        raise RecordingReadError(f"{path} does not exist")
    _check_recording_file(path)
    kwargs = {}
    if map_path is not None:
        map_path = Path(map_path)
        if not map_path.is_file():
            raise RecordingReadError(f"map {map_path} {'is not a file' if map_path.exists() else 'does not exist'}")
        if map_path.suffix.lower() in RECORDING_SUFFIXES:
            raise RecordingReadError(
                f"map {map_path} is a recording, not a map: give the OpenDRIVE file (.xodr) the recording was made on"
            )
        kwargs["map_path"] = str(map_path)
    elif path.suffix in (".mcap", ".osi"):  # read straight into columns where omega-prime gives the same table
        if path.suffix == ".mcap":
            from .reader import read_mcap as read_ours
        else:
            from .osi_trace import read_osi as read_ours
        try:
            return read_ours(path)
        except Exception:  # NotOurs (a projection, no OSI ground truth) or a file it cannot decode: omega-prime
            pass  # reads it, or says in its words what is wrong
    import omega_prime  # takes seconds: only once the paths are known to exist

    try:
        # omega-prime only warns when it cannot read the map: record that warning to turn it into an error
        with warnings.catch_warnings(record=True) as caught:
            warnings.filterwarnings("ignore", message="Failed to apply projections")
            warnings.filterwarnings("always", message=NO_MAP)
            recording = omega_prime.Recording.from_file(str(path), compute_polygons=True, **kwargs)
    except Exception as e:  # omega-prime and its readers raise many kinds; report them as one, naming the file
        if _truncated_mcap(path):  # the reader's own words (a record of absurd length) would hide the cause
            raise RecordingReadError(
                f"cannot read {path}: the file is truncated (an MCAP file cut off after {path.stat().st_size} bytes,"
                " before its end; was it still being written or copied?)"
            ) from e
        raise RecordingReadError(f"cannot read {path} as an omega-prime recording ({type(e).__name__}: {e})") from e
    map_failures = [str(w.message) for w in caught if str(w.message).startswith(NO_MAP)]
    for w in caught:  # pass every other warning on to the caller
        if not str(w.message).startswith(NO_MAP):
            warnings.warn_explicit(w.message, w.category, w.filename, w.lineno, source=w.source)
    if map_path is not None:
        root = _check_map(map_path, recording.map, map_failures)
        if path.suffix == ".mcap":
            warnings.warn(
                f"{path.name} is read with the map {map_path.name} given, in place of any map the recording carries",
                MapNotice,
                stacklevel=2,
            )
        check_map_fits(recording, map_path, root)
    return recording


MCAP_MAGIC = b"\x89MCAP0\r\n"

RECORDING_SUFFIXES = (".mcap", ".osi", ".parquet")
"""What omega-prime reads: MCAP files, OSI traces and its own parquet files (the readers go by the suffix)."""


def _check_recording_file(path: Path) -> None:
    """Refuse, naming the cause, what no reader can take: a folder, another kind of file, an empty file, an
    ``.mcap`` file that is no MCAP file (omega-prime's readers would answer with an empty or a raw message)."""
    if path.is_dir():
        raise RecordingReadError(f"{path} is a folder, not a recording file")
    if path.suffix not in RECORDING_SUFFIXES:
        kind = f"{path.suffix!r} files" if path.suffix else "files without an extension"
        raise RecordingReadError(
            f"cannot read {path}: omega-prime reads MCAP files (.mcap), OSI traces (.osi) and its own .parquet "
            f"files, not {kind}"
        )
    try:
        size = path.stat().st_size
        with open(path, "rb") as f:
            head = f.read(len(MCAP_MAGIC))
    except OSError as e:
        raise RecordingReadError(f"cannot read {path} ({e.strerror or e})") from None
    if size == 0:
        raise RecordingReadError(f"cannot read {path}: the file is empty")
    if path.suffix == ".mcap" and head != MCAP_MAGIC:
        raise RecordingReadError(f"cannot read {path}: it is not an MCAP file (not the bytes MCAP files start with)")


def _truncated_mcap(path: Path) -> bool:
    """Whether ``path`` starts as an MCAP file but lacks the magic bytes that end every complete one."""
    try:
        with open(path, "rb") as f:
            head = f.read(len(MCAP_MAGIC))
            f.seek(max(0, path.stat().st_size - len(MCAP_MAGIC)))
            tail = f.read()
    except OSError:
        return False
    return head == MCAP_MAGIC and tail != MCAP_MAGIC


def _check_map(map_path: Path, parsed: Any, failures: list[str]) -> ET.Element | None:
    """Raise RecordingReadError unless omega-prime read ``map_path`` as a map; return an OpenDRIVE map's parsed XML
    (None for other maps)."""
    if parsed is None or failures:
        detail = failures[0][len(NO_MAP) :].strip(": ") if failures else ""
        no_reader = detail in ("", "{}")  # omega-prime found no reader for this kind of file
        reason = f"no map reader for {map_path.suffix!r} files" if no_reader else f"omega-prime: {detail}"
        raise RecordingReadError(f"cannot read map {map_path} ({reason})")
    # OpenDRIVE maps are kept as text until used, so a file that is no OpenDRIVE would only fail later
    odr_xml = getattr(parsed, "odr_xml", None)
    if isinstance(odr_xml, str):
        try:
            root = ET.fromstring(odr_xml)
        except ET.ParseError as e:
            raise RecordingReadError(f"cannot read map {map_path} as OpenDRIVE (XML error: {e})") from None
        if root.tag != "OpenDRIVE":
            raise RecordingReadError(f"cannot read map {map_path}: its XML root is <{root.tag}>, not <OpenDRIVE>")
        return root
    return None
