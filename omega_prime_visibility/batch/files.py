"""Which files a batch reads and writes: recordings found under the inputs, the result each one gets, whether a
result is complete and current, and the leftovers of interrupted runs."""

from __future__ import annotations

import glob
import os
import shutil
import warnings
from collections import defaultdict
from pathlib import Path

import pyarrow as pa
import pyarrow.parquet as pq

from ..table.output import is_dataset

RECORDING_SUFFIXES = (".mcap", ".osi")  # what a folder or a glob contributes; files named directly may be anything
OPTIONS_KEY = b"omega_prime_visibility.options"
RECORDING_KEY = b"omega_prime_visibility.recording"
OBSERVER_KEY = b"omega_prime_visibility.observer"
"""Parquet metadata of a result: JSON ``{"observers": 87, "words": "host vehicle idx 87"}``, whom it is seen from."""


def find_recordings(inputs: list[str | os.PathLike], output_dir: Path) -> list[tuple[Path, Path]]:
    """``(recording, result)`` pairs for files, folders (searched recursively) and glob patterns, in input order.

    A folder or a glob contributes its files ending in ``.mcap`` or ``.osi`` (hidden files and folders left out);
    a file named directly is taken whatever its name. Each result sits in ``output_dir`` at the recording's path
    relative to the folder (or the fixed part of the glob) it was found under, plus ``.parquet``; a file named
    directly gets its own name. Recordings that would get the same result name (``a/x.mcap`` and ``b/x.mcap``
    named directly) keep their path below their closest common folder instead, so results never collide.

    Raises
    ------
    ValueError
        If an input does not exist, a folder cannot be read, or no recording is found at all.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as d:
    ...     for name in ("a/x.mcap", "b/x.mcap", "b/notes.txt"):
    ...         (Path(d) / name).parent.mkdir(exist_ok=True)
    ...         (Path(d) / name).touch()
    ...     pairs = find_recordings([Path(d) / "a" / "x.mcap", Path(d) / "b"], Path("out"))
    ...     [str(result) for _, result in pairs]
    ['out/a/x.mcap.parquet', 'out/b/x.mcap.parquet']
    """
    # one task per file, however many names lead to it; each named by the path given (a symbolic link stays the
    # link: messages and the summary name what the user gave)
    by_file: dict[Path, Path] = {}  # resolved recording -> the path given, made absolute
    found: dict[Path, Path] = {}  # the path given -> name relative to its root
    for item in inputs:
        for recording, relative in _expand(str(item)):
            given = Path(os.path.abspath(recording))
            first = by_file.setdefault(recording.resolve(), given)
            if first == given:
                found.setdefault(given, relative)
            else:
                warnings.warn(
                    f"{given} is the same file as {first}: computed once, as {first.name}",
                    BatchNotice,
                    stacklevel=2,
                )
    if not found:
        raise ValueError(f"no recordings ({', '.join(RECORDING_SUFFIXES)}) found in {', '.join(map(str, inputs))}")
    by_name: dict[Path, list[Path]] = defaultdict(list)
    for recording, relative in found.items():
        by_name[relative].append(recording)
    for recordings in by_name.values():
        if len(recordings) > 1:  # same name from different places: name each below their common folder
            common = Path(os.path.commonpath([r.parent for r in recordings]))
            for r in recordings:
                found[r] = r.relative_to(common)
    return [(recording, output_dir / f"{relative}.parquet") for recording, relative in found.items()]


class BatchNotice(UserWarning):
    """Something about a batch's inputs worth a line: two names of one file, computed once."""


def _expand(item: str) -> list[tuple[Path, Path]]:
    path = Path(item)
    if path.is_file():
        return [(path, Path(path.name))]
    if path.is_dir():
        return _walk(path)
    if glob.has_magic(item):
        base = _fixed_prefix(item)
        pairs = []
        for match in sorted(glob.glob(item, recursive=True)):
            match = Path(match)
            if match.is_dir():
                pairs += [(r, r.relative_to(base)) for r, _ in _walk(match)]
            elif match.suffix in RECORDING_SUFFIXES:
                pairs.append((match, match.relative_to(base)))
        if not pairs:
            raise ValueError(f"no recordings match {item}")
        return pairs
    raise ValueError(f"input {item} does not exist")


def _fixed_prefix(pattern: str) -> Path:
    """The folder a glob pattern starts from: its leading parts without wildcards."""
    parts = []
    for part in Path(pattern).parts[:-1]:
        if glob.has_magic(part):
            break
        parts.append(part)
    return Path(*parts) if parts else Path(".")


def _walk(folder: Path) -> list[tuple[Path, Path]]:
    def refuse(error: OSError) -> None:
        raise ValueError(f"cannot read input folder {error.filename} ({error.strerror or error})")

    pairs = []
    for root, dirs, files in os.walk(folder, onerror=refuse):
        dirs[:] = sorted(d for d in dirs if not d.startswith("."))
        for name in sorted(files):
            if not name.startswith(".") and Path(name).suffix in RECORDING_SUFFIXES:
                path = Path(root) / name
                pairs.append((path, path.relative_to(folder)))
    return pairs


def prepare_output_dir(output_dir: str | os.PathLike) -> Path:
    """``output_dir`` as a Path, created if missing (its parent must exist: a mistyped path does not grow a new
    tree of folders), after checking that files can be written in it.

    Raises
    ------
    ValueError
        If it is a file, its parent folder does not exist, it cannot be created, or it is not writable.
    """
    output_dir = Path(output_dir)
    if output_dir.exists() and not output_dir.is_dir():
        raise ValueError(f"the output folder {output_dir} is a file")
    if is_dataset(output_dir):
        raise ValueError(
            f"the output folder {output_dir} holds the parquet parts of one table (run -o or output= wrote it), not "
            "batch results: choose another folder"
        )
    parent = output_dir.absolute().parent
    if not output_dir.exists() and not parent.is_dir():
        raise ValueError(f"cannot write results to {output_dir}: the folder {parent} does not exist")
    try:
        output_dir.mkdir(exist_ok=True)
        probe = output_dir / f".write-probe.{os.getpid()}.tmp"
        probe.touch()
        probe.unlink()
    except OSError as e:
        raise ValueError(f"cannot write in the output folder {output_dir} ({e.strerror or e})") from None
    return output_dir


def remove_leftovers(result: Path) -> int:
    """Remove temporary files an interrupted run left beside ``result`` (a killed process cannot clean up), its
    siblings' (``<result>.objects.parquet``, ``<result>.conflicts.parquet``) included.

    Only one batch at a time may write into an output folder. Returns how many were removed.
    """
    removed = 0
    stem = glob.escape(result.name.removesuffix(".parquet"))
    for temp in result.parent.glob(f".{stem}.*.tmp") if result.parent.is_dir() else ():
        if temp.is_dir():  # a streamed result's parts
            shutil.rmtree(temp, ignore_errors=True)
        else:
            temp.unlink(missing_ok=True)
        removed += 1
    return removed


def is_current(result: Path, recording: Path, fingerprint: str) -> int | None:
    """The row count of ``result`` if it is complete, newer than ``recording`` and computed with ``fingerprint``;
    else None (missing, truncated, older than the recording, or made with other options)."""
    try:
        if result.stat().st_mtime_ns < recording.stat().st_mtime_ns:
            return None
        meta = pq.read_metadata(result)
    except (OSError, ValueError, pa.ArrowException):
        return None
    stored = (meta.metadata or {}).get(OPTIONS_KEY)
    return meta.num_rows if stored is not None and stored.decode() == fingerprint else None


def stored_observer(result: Path) -> tuple[object, str] | None:
    """Whom a result is seen from (``observers`` as the question takes them, and in a reader's words), as batch
    stored it; None for a result written before it stored them, or not readable."""
    import json

    try:
        stored = (pq.read_metadata(result).metadata or {}).get(OBSERVER_KEY)
        values = json.loads(stored) if stored is not None else None
    except (OSError, ValueError, pa.ArrowException):
        return None
    if not isinstance(values, dict) or "observers" not in values:
        return None
    observers = values["observers"]
    return (tuple(observers) if isinstance(observers, list) else observers), str(values.get("words", ""))
