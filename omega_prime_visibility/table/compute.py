"""Running a resolved question (:func:`~omega_prime_visibility.query.resolve`): how many processes, chunks of
frames, a progress bar, the table gathered in memory or streamed to a parquet dataset. What is computed is the
question's; how it runs is said here and never changes the table."""

from __future__ import annotations

import multiprocessing
import os
from collections.abc import Iterator
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager, nullcontext

import polars as pl
from tqdm.auto import tqdm

from .._compiled import Heartbeat, announce_compilation, mark_compiled
from ..inputs.objects import ObjectTable
from ..query import Resolved
from ..threed.mode import Finisher, with_can_see
from .output import PartWriter, atomic_directory
from .pipeline import ContainmentLog, chunks, counted_columns, run
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
) -> pl.DataFrame | pl.LazyFrame:
    """The table of a resolved question (:func:`~omega_prime_visibility.query.resolve`): how to run it
    (``workers``, ``chunk_frames``, ``progress``, a checked ``output`` path) as for :func:`get_visibility_df`."""
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
    bar = tqdm(total=objects.n_frames, disable=not show, desc="visibility", unit="frame")
    containment = ContainmentLog()
    tables: list[pl.DataFrame] = []
    mode = scene.query.mode
    with atomic_directory(output) if output is not None else nullcontext() as temp:
        # workers write their own parts: only row counts and containment logs come back here
        names = scene.sensor_names
        counted = counted_columns(sensor_set)
        labels = {} if names is None else {"sensor": names, "status": STATUSES}
        finish = Finisher(scene.static_positions, three_d)
        sink = None
        if temp is not None:
            schema = with_can_see(empty_table(with_ego, names is not None, counted), mode).to_arrow().schema
            sink = Finisher(scene.static_positions, three_d, PartWriter(temp, schema, labels))
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
    if output is not None:
        return pl.scan_parquet(output)
    if tables:
        return pl.concat(tables, rechunk=True)
    return with_can_see(empty_table(with_ego, names is not None, counted), mode)


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
