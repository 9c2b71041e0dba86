"""Running a resolved question (:func:`~omega_prime_visibility.query.resolve`): how many processes, chunks of
frames, a progress bar, the table gathered in memory or streamed to a parquet dataset. What is computed is the
question's; how it runs is said here and never changes the table."""

from __future__ import annotations

import multiprocessing
import os
import shutil
import tempfile
from collections.abc import Iterator, Mapping
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager
from dataclasses import replace
from pathlib import Path

import polars as pl
import pyarrow as pa

from .._compiled import Heartbeat, announce_compilation, mark_compiled
from ..inputs.objects import ObjectTable
from ..query import Resolved
from ..threed.mode import Finisher, with_can_see
from .output import FileWriter, PartWriter, atomic_directory, join_parts
from .pipeline import ContainmentLog, chunks, counted_columns, run
from .progress import Progress
from .schema import STATUSES, empty_table, to_polars
from .selection import passive_in_place

PROGRESS_MIN_FRAMES = 200
PARALLEL_MIN_WORK = 5_000  # (frame, observer) pairs from which all cores are used by default
CHUNK_FRAMES = 500
CHUNK_ROWS = 250_000  # output rows a chunk aims at, at most: bounds each worker's memory when every object observes


def chunk_size(objects: ObjectTable, n_egos: int, chunk_frames: int, n_sensors: int = 1) -> int:
    """Frames per chunk: ``chunk_frames`` at most, fewer when frames yield many rows (many observers), so that a
    chunk's table stays near :data:`CHUNK_ROWS` rows (about 20 MiB of arrays in the worker).

    Examples
    --------
    >>> import polars as pl
    >>> frames = pl.DataFrame({"frame": [0, 0, 1, 1], "total_nanos": [0, 0, 1, 1], "idx": [0, 1, 0, 1],
    ...     "x": [0.0, 9, 0, 9], "y": [0.0] * 4, "length": [4.0] * 4, "width": [2.0] * 4, "yaw": [0.0] * 4})
    >>> from omega_prime_visibility.inputs.scene import load_objects
    >>> objects = load_objects(frames)
    >>> chunk_size(objects, 2, 500), chunk_size(objects, 2, 500, n_sensors=200_000)
    (500, 1)
    """
    per_frame = len(objects.idx) / max(objects.n_frames, 1)
    rows = per_frame * min(n_egos, per_frame) * n_sensors
    return max(1, min(chunk_frames, int(CHUNK_ROWS // max(rows, 1.0))))


def auto_workers(work: int) -> int:
    """Processes to use for ``work`` (frame, observer) pairs: all cores for long jobs, else one."""
    return max(1, os.cpu_count() or 1) if work >= PARALLEL_MIN_WORK else 1


def compute(
    scene: Resolved,
    *,
    workers: int | None = None,
    chunk_frames: int = CHUNK_FRAMES,
    progress: bool | None = None,
    output: os.PathLike | None = None,
    output_file: os.PathLike | None = None,
    metadata: Mapping[bytes, bytes] | None = None,
) -> pl.DataFrame | pl.LazyFrame:
    """The table of a resolved question (:func:`~omega_prime_visibility.query.resolve`): how to run it
    (``workers``, ``chunk_frames``, ``progress``, a checked ``output`` path) as for :func:`get_visibility_df`.

    ``output_file`` streams the table into that one parquet file instead (the caller's: a temporary name it renames
    when complete, and removes on an error), with ``metadata`` added to its schema's: chunk by chunk in the order they
    are computed when one process computes them, else through a dataset beside it, joined at the end."""
    if output is not None and output_file is not None:
        raise ValueError("compute writes a dataset (output=) or one file (output_file=), not both")
    objects, egos, engine, sensor_set = scene.objects, scene.egos, scene.engine, scene.sensors
    three_d, with_ego = scene.query.three_d, scene.with_ego
    n_workers = auto_workers(objects.n_frames * len(egos)) if workers is None else int(workers)
    n_sensors = 1 if sensor_set is None else len(scene.sensor_names)
    chunk_frames = chunk_size(objects, len(egos), chunk_frames, n_sensors)
    n_workers = min(n_workers, len(chunks(objects.n_frames, chunk_frames, n_workers)))
    path_key = engine if sensor_set is None else f"{engine}+sensors"  # the sensors' path compiles more kernels
    if objects.chosen and not passive_in_place(objects, scene.engine_class):  # so do the views of the choices
        path_key += "+views"
    beat = Heartbeat(f"the {engine} engine's kernels")
    if announce_compilation(engine, scene.engine_class, path_key):  # (the checks are done: work starts here)
        beat.start()  # a line every few seconds until the first frames are done: a first call is never silent
    show = objects.n_frames >= PROGRESS_MIN_FRAMES if progress is None else progress
    bar = Progress(total=objects.n_frames, show=show, desc="visibility", unit="frame")
    containment = ContainmentLog()
    tables: list[pl.DataFrame] = []
    mode = scene.query.mode
    names = scene.sensor_names
    counted = counted_columns(sensor_set)
    finish = Finisher(scene.static_positions, three_d)
    # workers write their own parts (or this process its file): only row counts and containment logs come back here
    streams = output is not None or output_file is not None
    schema = (
        with_can_see(empty_table(with_ego, names is not None, counted), mode).to_arrow().schema if streams else None
    )
    labels = {} if names is None else {"sensor": names, "status": STATUSES}
    with _streamed(finish, schema, labels, output, output_file, metadata, n_workers) as sink:
        try:
            with _executor(n_workers) as pool:
                spread = {"executor": pool, "workers": n_workers, "sink": sink}
                frames = run(objects, scene.statics, egos, engine, chunk_frames=chunk_frames, sensors=sensor_set,
                             **spread)  # fmt: skip
                written = 0
                for n_frames, result, log in frames:
                    beat.stop()
                    containment.merge(log)
                    if sink is not None:
                        written += result
                    else:
                        table = to_polars(finish.columns(result), with_ego, names, counted)
                        tables.append(with_can_see(table, mode))
                    bar.update(n_frames)
        finally:
            beat.stop()
            bar.close()
        if sink is not None and not written:
            sink.write_empty()
    containment.warn(stacklevel=4, static_positions=scene.static_positions)
    mark_compiled(path_key)
    if streams:
        return pl.scan_parquet(output if output is not None else output_file)
    if tables:
        return pl.concat(tables, rechunk=True)
    return with_can_see(empty_table(with_ego, names is not None, counted), mode)


@contextmanager
def _streamed(
    finish: Finisher,
    schema: pa.Schema | None,
    labels: dict,
    output: os.PathLike | None,
    output_file: os.PathLike | None,
    metadata: Mapping[bytes, bytes] | None,
    n_workers: int,
) -> Iterator[Finisher | None]:
    """The sink where the chunks' columns go (None: back to this process as tables), ``finish`` writing to a dataset
    at ``output`` (renamed into place when the block exits without error, removed when it fails) or to the one file
    ``output_file`` (see :func:`compute`)."""
    if output is not None:
        with atomic_directory(output) as temp:
            yield replace(finish, inner=PartWriter(temp, schema, labels))
    elif output_file is None:
        yield None
    elif n_workers <= 1:  # the chunks come in order: straight into the file
        with FileWriter(Path(output_file), schema, labels, metadata) as writer:
            yield replace(finish, inner=writer)
    else:  # the workers' parts beside it (named after it: a batch resumed after a kill removes them), then joined
        path = Path(output_file)
        parts = Path(tempfile.mkdtemp(prefix=f"{path.name}.parts-", suffix=".tmp", dir=path.parent))
        try:
            yield replace(finish, inner=PartWriter(parts, schema, labels))
            join_parts(parts, path, metadata)
        finally:
            shutil.rmtree(parts, ignore_errors=True)


@contextmanager
def _executor(n_workers: int) -> Iterator[ProcessPoolExecutor | None]:
    if n_workers <= 1:
        yield None
        return
    # fork needs no `if __name__ == "__main__"` guard in the user's script; workers use numpy, numba, shapely and
    # VisiLibity only (never polars, whose thread pool does not survive a fork)
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    with ProcessPoolExecutor(n_workers, mp_context=multiprocessing.get_context(method)) as pool:
        try:
            yield pool
        except BaseException:
            pool.shutdown(cancel_futures=True)  # on an error or Ctrl-C, do not compute the chunks still queued
            raise
