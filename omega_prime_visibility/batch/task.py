"""One recording's work in a batch: the task, its result, and :func:`process_file`, which computes the table and
writes it atomically (run in the calling process, a pool worker or a dask worker)."""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass
from pathlib import Path

from .files import OBSERVER_KEY, OPTIONS_KEY, RECORDING_KEY
from .options import FileOptions


@dataclass(frozen=True)
class FileTask:
    """One recording to compute: paths are absolute, so a dask worker sharing the file system finds them."""

    recording: str
    result: str
    options: FileOptions
    fingerprint: str
    workers: int = 1  # processes for this file's frames (more than 1 only when it is the batch's only file)


@dataclass(frozen=True)
class FileResult:
    """A summary row: see ``SUMMARY_SCHEMA``."""

    recording: str
    result: str
    status: str
    rows: int | None = None
    seconds: float = 0.0
    error: str | None = None
    warnings: str | None = None
    observer: str | None = None  # whom it is seen from, in a reader's words (host vehicle idx 87, a fallback, ...)


WARNING_SEPARATOR = " | "
"""Between the warnings of one recording in the summary's ``warnings`` column."""

CURRENT: str | None = None
"""The result this process is computing (a pool worker's SIGTERM handler removes its temporary files)."""


def process_file(task: FileTask) -> FileResult:
    """Compute one recording's visibility table and write it atomically to ``task.result`` with the options in its
    parquet metadata; every error becomes a failed :class:`FileResult` with a one-line message."""
    global CURRENT
    start = time.perf_counter()
    caught: list[warnings.WarningMessage] = []
    try:
        CURRENT = task.result
        with warnings.catch_warnings(record=True) as caught:
            warnings.simplefilter("always")
            rows, observer = _compute_and_write(task)
    except Exception as e:
        message = str(e) if isinstance(e, ValueError) else f"{type(e).__name__}: {e}"
        return FileResult(task.recording, task.result, "failed", None, time.perf_counter() - start, _one_line(message))
    finally:
        CURRENT = None
    notes = sorted({_one_line(str(w.message)) for w in caught if not issubclass(w.category, DeprecationWarning)})
    return FileResult(
        task.recording,
        task.result,
        "done",
        rows,
        time.perf_counter() - start,
        None,
        WARNING_SEPARATOR.join(notes) or None,
        observer,
    )


def _one_line(message: str, limit: int = 500) -> str:
    message = " ".join(message.split())
    return message if len(message) <= limit else message[: limit - 3] + "..."


def _compute_and_write(task: FileTask) -> tuple[int, str]:
    """Compute and write one result; its row count and whom it is seen from, in a reader's words."""
    import json
    from importlib.metadata import version

    import pyarrow.parquet as pq

    from ..inputs.io import read_recording
    from ..query import resolve
    from ..table.compute import compute
    from ..table.output import FileWriter, atomic_write

    options = task.options
    map_path = options.map_for(Path(task.recording))
    recording = read_recording(task.recording, map_path)
    question = options.question(recording, Path(task.recording).name, map_path)
    observers, words = options.observer(recording, Path(task.recording).name)
    Path(task.result).parent.mkdir(parents=True, exist_ok=True)
    metadata = {
        OPTIONS_KEY: task.fingerprint.encode(),
        RECORDING_KEY: task.recording.encode(),
        OBSERVER_KEY: json.dumps({"observers": observers, "words": words}).encode(),
        b"omega_prime_visibility.version": version("omega-prime-visibility").encode(),
    }
    resolved = resolve(question, recording)
    if not (options.conflicts or options.mcap):  # streamed into the result chunk by chunk (every observer: 40 M rows)
        with atomic_write(task.result) as temp:
            compute(resolved, workers=task.workers, progress=False, output_file=temp, metadata=metadata)
            rows = pq.read_metadata(temp).num_rows
            _write_objects(recording, task.result)  # (before the result appears: see _write_objects)
        return rows, words
    table = compute(resolved, workers=task.workers, progress=False)  # (both need the whole table at hand)
    _write_objects(recording, task.result)
    if options.conflicts:  # before the result, as the objects
        conflicts = _conflicts(recording, table, question.observers)
        with atomic_write(conflicts_path(task.result)) as temp:
            conflicts.write_parquet(temp)
    if options.mcap:  # the recording with the answer drawn in (written whole, under a temporary name)
        from ..export.mcap import write_answer_mcap

        drawn = mcap_path(task.result)
        drawn.unlink(missing_ok=True)  # (a stale one, from before this result was recomputed)
        write_answer_mcap(task.recording, recording, table, drawn, question, osi_traces=False)
    arrow = table.to_arrow()
    with atomic_write(task.result) as temp, FileWriter(temp, arrow.schema, {}, metadata) as writer:
        writer.write(arrow)
    return table.height, words


def _write_objects(recording, result: str) -> None:
    """The objects' positions and types beside ``result`` (what campaign statistics need, so they never read the
    recording again): written once the table is computed and before the result takes its name, so that a complete
    result always has its own beside it and a failed recomputation leaves the previous pair as it was."""
    from ..inputs.scene import as_polars
    from ..table.output import atomic_write

    with atomic_write(objects_path(result)) as temp:
        as_polars(recording).select("total_nanos", "idx", "x", "y", "type").write_parquet(temp)


def objects_path(result: str | Path) -> Path:
    """Where batch writes a result's moving objects (``total_nanos, idx, x, y, type``): ``<result>.objects.parquet``."""
    result = Path(result)
    return result.with_name(result.name.removesuffix(".parquet") + ".objects.parquet")


def mcap_path(result: str | Path) -> Path:
    """Where ``batch --mcap`` writes a result's recording with the answer drawn in: ``<result>.mcap`` (without
    the ``.parquet``)."""
    result = Path(result)
    return result.with_name(result.name.removesuffix(".parquet") + ".mcap")


def conflicts_path(result: str | Path) -> Path:
    """Where ``batch --conflicts`` writes a result's occluded conflicts: ``<result>.conflicts.parquet``."""
    result = Path(result)
    return result.with_name(result.name.removesuffix(".parquet") + ".conflicts.parquet")


def _conflicts(recording, table, ego_idx):
    """``occluded_conflicts`` of every ego of the table, with omega-prime's timegaps (a 3 s buffer: the PET)."""
    import polars as pl
    from omega_prime.metrics import MetricManager, distance_traveled, timegaps_and_min_timegaps, vel

    from ..analysis.conflicts import occluded_conflicts

    egos = sorted(table["idx_ego"].unique().to_list()) if "idx_ego" in table.columns else [ego_idx]
    manager = MetricManager(metrics=[vel, distance_traveled, timegaps_and_min_timegaps])
    gaps = pl.concat(
        [manager.compute(recording, ego_id=ego, time_buffer=3e9)[1]["timegaps"] for ego in egos], how="vertical"
    )
    single = None if "idx_ego" in table.columns else ego_idx
    return occluded_conflicts(table, gaps, recording._df, ego_idx=single)
