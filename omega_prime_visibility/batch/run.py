"""Visibility over many recordings: one parquet result per recording, computed by local processes or a dask
cluster, written atomically, skipped on a rerun when current, and a summary of every file.

The work for one file is :func:`process_file`, a top-level function of a picklable :class:`FileTask`, so the same
call runs in this process, in a spawn- or forkserver-started process pool, and on dask workers.
"""

from __future__ import annotations

import os
from dataclasses import fields
from pathlib import Path
from typing import TYPE_CHECKING, Any

import polars as pl

from . import execute
from .files import find_recordings, is_current, prepare_output_dir, remove_leftovers, stored_observer
from .options import FileOptions, is_int
from .task import FileResult, FileTask

if TYPE_CHECKING:
    from ..query import Query

SUMMARY_NAME = "_batch_summary.parquet"
SUMMARY_SCHEMA = {
    "recording": pl.String,
    "result": pl.String,
    "status": pl.String,  # done, skipped, failed (interrupted when the run was stopped before the file)
    "rows": pl.Int64,
    "seconds": pl.Float64,
    "error": pl.String,
    "warnings": pl.String,
    "observer": pl.String,  # whom the result is seen from: host vehicle idx 87, idx 0 (fallback: ...), ...
}


class BatchInterrupted(KeyboardInterrupt):
    """The batch was stopped (Ctrl-C, SIGTERM); ``summary`` marks the files not finished as ``interrupted``."""

    def __init__(self, summary: pl.DataFrame):
        super().__init__("batch interrupted; run it again to continue where it stopped")
        self.summary = summary


def run_batch(
    inputs: str | os.PathLike | list[str | os.PathLike],
    output_dir: str | os.PathLike,
    query: Query | None = None,
    *,
    workers: int | None = None,
    scheduler: str | None = None,
    scheduler_file: str | os.PathLike | None = None,
    client: Any = None,
    overwrite: bool = False,
    progress: bool = True,
    **options: Any,
) -> pl.DataFrame:
    """Visibility tables of many recordings, one parquet file each in ``output_dir``, and their summary.

    Each result is written under a temporary name and renamed when complete, with the options in its parquet
    metadata; a rerun skips recordings whose result is complete, newer than the recording and made with the same
    options (``overwrite=True`` recomputes all). A file that cannot be computed is reported and the others go on.

    Parameters
    ----------
    inputs : path, glob pattern or a list of them
        Recordings (any name), folders (searched recursively for ``.mcap`` and ``.osi``) and glob patterns.
    output_dir : path
        Created if missing. Results keep the recordings' paths below the folder they were found in, plus
        ``.parquet``; the summary is written to ``_batch_summary.parquet``.
    query : Query, optional
        The question (:class:`~omega_prime_visibility.Query`) every recording is computed with; its observers
        None (the default) take each recording's host vehicle, its ``map_occluders=True`` the map each recording
        is read with. The keywords below fold into it.
    workers : int, optional
        Local processes over files (default: the cores available); a batch of one file spreads its frames instead.
    scheduler, scheduler_file : str, optional
        Address (``tcp://host:8786``) or scheduler file of an existing dask cluster to compute on instead; its
        workers must see the inputs and ``output_dir`` under the same paths.
    client : dask.distributed.Client, optional
        An existing client to compute through (for notebooks).
    overwrite : bool
        Recompute even current results.
    progress : bool
        Show a progress bar over files.
    **options
        ``map`` (an OpenDRIVE map for OSI traces, or a JSON list of ``[trace, map]`` pairs), ``conflicts`` (also
        write each recording's occluded conflicts), ``fallback_ego`` (the observer of recordings that name no host
        vehicle, where the observers are each recording's host vehicle), and the question's options as keywords (see
        :data:`~.options.BATCH_KEYWORDS`): ``ego`` (default: each recording's host vehicle), ``engine``, ``mode``,
        ``measure``, ``sensors``, ``occluders``, ``targets``, ``static`` (a GeoJSON or WKT file),
        ``map_occluders`` (True: the map each recording is read with).

    Returns
    -------
    polars.DataFrame
        One row per recording, in input order: ``recording`` (absolute path), ``result`` (relative to
        ``output_dir``), ``status`` (done, skipped or failed), ``rows``, ``seconds``, ``error`` (one line, for
        failures), ``warnings``, ``observer`` (whom it is seen from: ``host vehicle idx 87``, ``idx 0 (fallback:
        names no host vehicle)``, ``idx 3``, ``every road user``).

    Raises
    ------
    ValueError
        For bad options or inputs (before anything is computed).
    BatchInterrupted
        When stopped by Ctrl-C or SIGTERM; the summary written so far is attached and saved.

    Examples
    --------
    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as out:
    ...     summary = run_batch("highway_merge.mcap", out, engine="sweep", progress=False)
    ...     again = run_batch("highway_merge.mcap", out, engine="sweep", progress=False)
    >>> summary.select("result", "status", "rows").row(0), again["status"][0]
    (('highway_merge.mcap.parquet', 'done', 1206), 'skipped')
    """
    from tqdm.auto import tqdm

    from ..table.output import atomic_write

    file_options = FileOptions.of(query, **options)
    remote = _check_how(workers, scheduler, scheduler_file, client)
    file_options.check()
    if Path(output_dir).is_file():
        raise ValueError(f"the output folder {output_dir} is a file")
    # recordings first: a typo in the inputs leaves no empty output folder behind
    pairs = find_recordings([inputs] if isinstance(inputs, str | os.PathLike) else list(inputs), Path("."))
    output_dir = Path(os.path.abspath(prepare_output_dir(output_dir)))
    pairs = [(recording, output_dir / result) for recording, result in pairs]
    if any(result == output_dir / SUMMARY_NAME for _, result in pairs):
        raise ValueError(f"a recording's result would overwrite the summary {output_dir / SUMMARY_NAME}")
    fingerprint = file_options.fingerprint()
    results, tasks = _plan(pairs, file_options, fingerprint, overwrite)
    bar = tqdm(total=len(pairs), initial=len(results), desc="recordings", unit="file", disable=not progress)

    def report(result: FileResult) -> None:
        results[result.result] = result
        bar.update(1)

    interrupted = False
    try:
        _execute(tasks, report, workers, remote, client, scheduler, scheduler_file)
    except KeyboardInterrupt:
        interrupted = True
    finally:
        bar.close()
    rows = []
    for recording, result in pairs:
        done = results.get(str(result)) or _unreported(recording, result, fingerprint)
        rows.append({**asdict_shallow(done), "result": result.relative_to(output_dir).as_posix()})
    summary = pl.DataFrame(rows, schema=SUMMARY_SCHEMA)
    with atomic_write(output_dir / SUMMARY_NAME) as temp:
        summary.write_parquet(temp)
    if interrupted:
        raise BatchInterrupted(summary)
    return summary


def _check_how(workers: Any, scheduler: Any, scheduler_file: Any, client: Any) -> bool:
    """Check how the batch is to run (local processes, or one way to a dask cluster); whether it is remote."""
    if workers is not None and (not is_int(workers) or workers < 1):
        raise ValueError(f"workers must be a whole number of at least 1, not {workers!r}")
    remote = [k for k, v in (("scheduler", scheduler), ("scheduler_file", scheduler_file), ("client", client)) if v]
    if len(remote) > 1:
        raise ValueError(f"give one of scheduler, scheduler_file and client, not {' and '.join(remote)}")
    if remote and workers is not None:
        raise ValueError("workers counts local processes: on a dask cluster its own workers do the work")
    return bool(remote)


def _plan(
    pairs: list[tuple[Path, Path]], options: FileOptions, fingerprint: str, overwrite: bool
) -> tuple[dict[str, FileResult], list[FileTask]]:
    """The results already current (skipped), by result path, and the tasks for the others (their leftovers
    from a killed run removed)."""
    results: dict[str, FileResult] = {}
    tasks = []
    for recording, result in pairs:
        remove_leftovers(result)
        rows = None if overwrite else is_current(result, recording, fingerprint)
        if rows is not None:
            stored = stored_observer(result)
            observer = stored[1] if stored is not None else None
            results[str(result)] = FileResult(str(recording), str(result), "skipped", rows, observer=observer)
        else:
            tasks.append(FileTask(str(recording), str(result), options, fingerprint))
    return results, tasks


def _execute(tasks, report, workers, remote, client, scheduler, scheduler_file) -> None:
    """Compute ``tasks`` on a dask cluster or local processes, calling ``report`` with each result; SIGTERM
    stops it as Ctrl-C does (KeyboardInterrupt)."""
    n_workers = workers or execute.available_cores()
    own_client = None
    try:
        with execute.sigterm_as_interrupt():
            if remote:
                client = client or (own_client := execute.connect(scheduler, scheduler_file))
                execute.run_dask(tasks, client, report)
            elif len(tasks) == 1:  # one file: its frames over the cores, as get_visibility_df does
                execute.run_here([FileTask(**{**asdict_shallow(tasks[0]), "workers": n_workers})], report)
            elif n_workers == 1:
                execute.run_here(tasks, report)
            else:
                execute.run_local(tasks, n_workers, report)
    finally:
        if own_client is not None:
            own_client.close()


def _unreported(recording: Path, result: Path, fingerprint: str) -> FileResult:
    """The summary row of a file whose result was not reported before an interruption: done if its complete
    result is on disk (a worker finished it as the stop came), so that the summary says what the disk holds;
    else interrupted."""
    rows = is_current(result, recording, fingerprint)
    status = "interrupted" if rows is None else "done"
    return FileResult(str(recording), str(result), status, rows)


def asdict_shallow(instance: Any) -> dict[str, Any]:
    """A dataclass's fields as a dict, values not copied (``dataclasses.asdict`` would copy nested options)."""
    return {f.name: getattr(instance, f.name) for f in fields(instance)}
