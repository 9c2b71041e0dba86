"""The user's entry points: ``get_visibility_df`` and ``get_visibility_df_for_frame``."""

from __future__ import annotations

import math
import multiprocessing
import numbers
import os
import secrets
import warnings
from collections import Counter
from collections.abc import Iterator, Sequence
from concurrent.futures import ProcessPoolExecutor
from contextlib import contextmanager, nullcontext
from pathlib import Path
from typing import Any, Literal

import numpy as np
import polars as pl
import pyarrow.parquet as pq
import shapely
from tqdm.auto import tqdm

from .engines import Observation, get_engine
from .geometry import covers_point
from .scene import (
    FrameObjects,
    ObjectTable,
    OnInvalid,
    StaticOccluders,
    VisibilityInputWarning,
    load_objects,
    load_static_occluders,
)
from .table import TableBuilder, empty_table, observation_rows, to_polars

EgoSpec = int | Sequence[int] | Literal["all"]
PROGRESS_MIN_FRAMES = 200
PARALLEL_MIN_WORK = 5_000  # (frame, observer) pairs from which all cores are used by default
CHUNK_FRAMES = 500


def describe_idx(present: np.ndarray) -> str:
    """The first 20 idx of ``present`` for an error message, with ``...`` when there are more."""
    present = np.asarray(present)
    return f"{present[:20].tolist()}{' ...' if len(present) > 20 else ''}"


def check_output_path(path: str | os.PathLike, suffixes: Sequence[str] = (".parquet",)) -> Path:
    """``path`` as a Path, after checking that a file ending in one of ``suffixes`` can be written there.

    Raises
    ------
    ValueError
        If the suffix is not one of ``suffixes``, the folder is missing or not a folder, the path is a directory
        or a read-only file, or the folder is not writable; the message names the path and the problem.
    """
    path = Path(path)
    if path.suffix not in suffixes:
        hint = ""
        if path.suffix == ".csv":
            hint = "; output= streams parquet: to write CSV, call write_csv on the returned table"
        raise ValueError(f"cannot write {path}: the name must end in {' or '.join(suffixes)}{hint}")
    folder = path.parent
    if not folder.exists():
        raise ValueError(f"cannot write {path}: the folder {folder} does not exist")
    if not folder.is_dir():
        raise ValueError(f"cannot write {path}: {folder} is not a folder")
    if path.is_dir():
        raise ValueError(f"cannot write {path}: it is a directory")
    if path.exists() and not os.access(path, os.W_OK):
        raise ValueError(f"cannot write {path}: the file exists and is read-only")
    # permissions alone do not tell (read-only mounts, /proc, ACLs): create and remove a file to be sure
    probe = _temp_name(path)
    try:
        os.close(os.open(probe, os.O_CREAT | os.O_EXCL | os.O_WRONLY))
        os.remove(probe)
    except OSError as e:
        raise ValueError(f"cannot write {path}: cannot create files in {folder} ({e.strerror or e})") from None
    return path


def _temp_name(path: Path) -> Path:
    """A hidden, unused name next to ``path`` (same folder, so the final rename is atomic)."""
    return path.with_name(f".{path.name}.{os.getpid()}.{secrets.token_hex(4)}.tmp")


@contextmanager
def atomic_write(path: str | os.PathLike) -> Iterator[Path]:
    """Yield a temporary path next to ``path``; rename it to ``path`` on success, remove it on any error.

    So an interrupted or failed run never leaves a half-written file under the final name.
    """
    path = Path(path)
    temp = _temp_name(path)
    try:
        yield temp
        os.replace(temp, path)
    except BaseException:
        temp.unlink(missing_ok=True)
        raise


def resolve_egos(ego_idx: EgoSpec, objects: ObjectTable) -> tuple[np.ndarray, bool]:
    """The observers' idx as an ascending array, and whether the table needs an ``ego_idx`` column."""
    present = np.unique(objects.idx)
    if isinstance(ego_idx, str):
        if ego_idx != "all":
            raise ValueError(f"ego_idx must be an int, a list of ints or 'all', not {ego_idx!r}")
        return present, True
    many = not isinstance(ego_idx, int | np.integer)
    egos = np.unique(np.atleast_1d(np.asarray(ego_idx)))
    if egos.size == 0 or not np.issubdtype(egos.dtype, np.integer):
        raise ValueError(f"ego_idx must be an int, a list of ints or 'all', not {ego_idx!r}")
    missing = egos[~np.isin(egos, present)]
    if len(missing):
        raise ValueError(
            f"ego idx {missing.tolist()} never occurs among the usable rows of the table "
            f"(idx present: {describe_idx(present)})"
        )
    return egos.astype(np.int64), many


class _ContainmentLog:
    """Counts objects that contain an observer, for one summarising warning."""

    def __init__(self) -> None:
        self.frames: Counter[tuple[int, int]] = Counter()
        self.first: dict[tuple[int, int], int] = {}

    def add(self, ego: int, idx: np.ndarray, frame: int) -> None:
        for i in idx.tolist():
            self.frames[(ego, i)] += 1
            self.first.setdefault((ego, i), frame)

    def merge(self, other: _ContainmentLog) -> None:
        self.frames.update(other.frames)
        for key, frame in other.first.items():
            self.first.setdefault(key, frame)

    def warn(self) -> None:
        if not self.frames:
            return
        parts = [
            f"idx {i} contains observer {e} in {c} frame(s) (first frame {self.first[(e, i)]})"
            for (e, i), c in sorted(self.frames.items())[:10]
        ]
        more = len(self.frames) - 10
        warnings.warn(
            "objects containing the observer are treated as transparent (never occluders) and reported with "
            f"visibility 1.0: {'; '.join(parts)}{f'; and {more} more' if more > 0 else ''}",
            VisibilityInputWarning,
            stacklevel=3,
        )


def transparency_masks(
    objects: FrameObjects, positions: np.ndarray, statics: StaticOccluders
) -> tuple[np.ndarray, np.ndarray]:
    """Bodies that neither block nor occlude, for observers at the centres of the objects at ``positions``.

    Returns ``transparent`` of shape (k, n): each observer's own object and every object containing or touching
    its observer point; and ``static_transparent`` of shape (k, n_sources): static occluders containing it.
    """
    positions = np.asarray(positions, dtype=np.int64)
    transparent = np.empty((len(positions), len(objects)), dtype=bool)
    static_transparent = np.zeros((len(positions), statics.n_sources), dtype=bool)
    for k, p in enumerate(positions):
        observer = objects.position[p]
        transparent[k] = covers_point(observer, objects.rings)
        transparent[k, p] = True
        if statics.n_sources:
            static_transparent[k] = shapely.intersects(statics.geometries, shapely.Point(observer))
    return transparent, static_transparent


def observe_frame(
    engine: Any,
    statics: StaticOccluders,
    objects: FrameObjects,
    egos: np.ndarray,
    builder: TableBuilder,
    containment: _ContainmentLog,
) -> None:
    """Run the engine for every observer present in this frame and add the rows to ``builder``."""
    n = len(objects)
    pos = np.minimum(np.searchsorted(objects.idx, egos), max(n - 1, 0))
    pos = pos[objects.idx[pos] == egos] if n else pos[:0]
    if len(pos) == 0:
        return
    observers = objects.position[pos]
    transparent, static_transparent = transparency_masks(objects, pos, statics)
    results: list[Observation] = engine.observe_many(objects, observers, transparent, static_transparent)
    for k, (p, obs) in enumerate(zip(pos, results, strict=True)):
        rows, vis, occ_off, occ, st_off, st, any_inside = observation_rows(
            p,
            obs.visible_angle,
            obs.angular_extent,
            obs.occluder_offsets,
            obs.occluders,
            obs.static_offsets,
            obs.static_occluders,
            transparent[k],
            objects.idx,
        )
        if any_inside:
            inside = transparent[k].copy()
            inside[p] = False
            containment.add(int(objects.idx[p]), objects.idx[inside], objects.frame)
        builder.add(objects.frame, objects.total_nanos, int(objects.idx[p]), rows, vis, occ_off, occ, st_off, st)


def _run_chunk(
    objects: ObjectTable, statics: StaticOccluders, egos: np.ndarray, engine: str, with_ego: bool
) -> tuple[tuple[np.ndarray, ...] | None, _ContainmentLog]:
    """All frames of ``objects`` with a fresh engine (so results never depend on how frames were chunked).

    Returns plain arrays (see :meth:`TableBuilder.arrays`): worker processes never touch polars."""
    eng = get_engine(engine)(statics)
    builder = TableBuilder(with_ego=with_ego)
    containment = _ContainmentLog()
    for k in range(objects.n_frames):
        observe_frame(eng, statics, objects.frame_objects(k), egos, builder, containment)
    return builder.arrays(), containment


def _run_chunk_star(args: tuple) -> tuple[tuple[np.ndarray, ...] | None, _ContainmentLog]:
    return _run_chunk(*args)


def _chunks(n_frames: int, chunk_frames: int) -> list[tuple[int, int]]:
    return [(k, min(k + chunk_frames, n_frames)) for k in range(0, n_frames, chunk_frames)]


def check_epsilon(epsilon: object) -> None:
    """0.1.0's ``epsilon``: ``None`` or a non-negative finite number (it has no effect here)."""
    if epsilon is None:
        return
    if isinstance(epsilon, bool) or not isinstance(epsilon, numbers.Real) or not math.isfinite(epsilon) or epsilon < 0:
        raise ValueError(f"epsilon must be a non-negative finite number or None, not {epsilon!r}")


def resolve_progress(progress: bool | None, hide_progress: bool | None) -> bool | None:
    """``progress`` with 0.1.0's ``hide_progress`` folded in (``hide_progress=True`` means ``progress=False``)."""
    if hide_progress is None:
        return progress
    if progress is not None and bool(progress) == bool(hide_progress):
        raise ValueError(f"progress={progress!r} contradicts hide_progress={hide_progress!r}; give only progress")
    return not hide_progress


def auto_workers(work: int) -> int:
    """Processes to use for ``work`` (frame, observer) pairs: all cores for long jobs, else one."""
    return max(1, os.cpu_count() or 1) if work >= PARALLEL_MIN_WORK else 1


def get_visibility_df(
    df: Any,
    ego_idx: EgoSpec,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    epsilon: float | None = None,
    *,
    engine: str = "visilibity",
    progress: bool | None = None,
    on_invalid: OnInvalid = "warn",
    workers: int | None = None,
    output: str | os.PathLike | None = None,
    chunk_frames: int = CHUNK_FRAMES,
    hide_progress: bool | None = None,
) -> pl.DataFrame | pl.LazyFrame:
    """Visibility and occluders of every object, seen from the ego, in every frame where the ego exists.

    Parameters
    ----------
    df : omega_prime.Recording, polars.DataFrame or polars.LazyFrame
        The moving-object table: ``frame, total_nanos, idx, x, y`` and either a ``polygon`` column (shapely
        polygons) or ``length, width, yaw`` (metres, radians counter-clockwise from +x).
    ego_idx : int, list of int or "all"
        The observing object(s); the observer sits at the centre ``(x, y)`` of its bounding box. With more than
        one, the table gains an ``ego_idx`` column.
    static_occluder_polys : sequence of shapely geometries, optional
        Static occluders (Polygon, MultiPolygon, LineString, ...), reported by their position in this sequence.
    epsilon : float, optional
        Metres; accepted for compatibility with 0.1.0, where it was VisiLibity's snapping distance; the result here
        is exact and does not depend on it. Must be a non-negative finite number or None.
    engine : str
        Registered engine name (``"visilibity"``, the default; see ``omega_prime_visibility.ENGINES``).
    progress : bool, optional
        Show a progress bar; by default only for long recordings.
    on_invalid : {"warn", "raise"}
        Skip unusable rows (NaN pose, zero-size or invalid outline) with a warning, or raise.
    workers : int, optional
        Processes over which chunks of frames are spread; by default all cores for long jobs (at least
        ``PARALLEL_MIN_WORK`` frame-observer pairs), else 1. The result does not depend on it.
    output : path, optional
        Stream the table to this ``.parquet`` file chunk by chunk (memory stays bounded). The path is checked
        before anything is computed (see :func:`check_output_path`); other suffixes are refused: for CSV, call
        ``write_csv`` on the returned table. The file is written under a temporary name in the same folder and
        renamed when complete, so a failed run leaves no partial file.
    chunk_frames : int
        Frames per chunk of work.
    hide_progress : bool, optional
        0.1.0's name for ``progress=not hide_progress`` (a ValueError if both are given and contradict).

    Returns
    -------
    polars.DataFrame, or polars.LazyFrame scanning the written parquet file when ``output`` is given
        One row per (frame, observer, target): ``frame, total_nanos, [ego_idx], idx, occluder_idxs,
        static_occluder_idxs, visibility`` where ``visibility`` in [0, 1] is the fraction of the target's
        angular extent along which it is the first thing hit, and the occluder lists hold, ascending, the
        objects and static occluders hit before the target along at least one direction.

    Examples
    --------
    >>> import polars as pl
    >>> objects = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2],
    ...     "x": [0.0, 10.0, 20.0], "y": [0.0, 0.0, 0.0], "length": [4.0, 4.0, 4.0],
    ...     "width": [2.0, 4.0, 2.0], "yaw": [0.0, 0.0, 0.0]})
    >>> get_visibility_df(objects, ego_idx=0).select("idx", "occluder_idxs", "visibility").rows()
    [(1, [], 1.0), (2, [1], 0.0)]
    """
    check_epsilon(epsilon)
    progress = resolve_progress(progress, hide_progress)
    if output is not None:
        output = check_output_path(output)
    objects = load_objects(df, on_invalid=on_invalid)
    statics = load_static_occluders(static_occluder_polys)
    egos, with_ego = resolve_egos(ego_idx, objects)
    get_engine(engine)  # unknown names fail here, not in a worker
    if chunk_frames < 1:
        raise ValueError(f"chunk_frames must be at least 1, not {chunk_frames}")
    chunks = _chunks(objects.n_frames, chunk_frames)
    n_workers = auto_workers(objects.n_frames * len(egos)) if workers is None else max(1, int(workers))
    n_workers = min(n_workers, len(chunks))
    show = objects.n_frames >= PROGRESS_MIN_FRAMES if progress is None else progress
    tasks = ((objects.frame_range(a, b), statics, egos, engine, with_ego) for a, b in chunks)
    bar = tqdm(total=objects.n_frames, disable=not show, desc="visibility", unit="frame")
    containment = _ContainmentLog()
    tables: list[pl.DataFrame] = []
    writer = None
    with atomic_write(output) if output is not None else nullcontext() as temp:
        try:
            with _executor(n_workers) as pool:
                results = pool.map(_run_chunk_star, tasks) if pool else map(_run_chunk_star, tasks)
                for (a, b), (arrays, log) in zip(chunks, results, strict=True):
                    containment.merge(log)
                    table = to_polars(arrays, with_ego)
                    if temp is not None:
                        arrow = table.to_arrow()
                        writer = writer or pq.ParquetWriter(str(temp), arrow.schema)
                        writer.write_table(arrow)
                    else:
                        tables.append(table)
                    bar.update(b - a)
        finally:
            bar.close()
            if writer is not None:
                writer.close()
        if temp is not None and writer is None:
            empty_table(with_ego).write_parquet(temp)
    containment.warn()
    if output is not None:
        return pl.scan_parquet(output)
    return pl.concat(tables, rechunk=True) if tables else empty_table(with_ego)


@contextmanager
def _executor(n_workers: int) -> Iterator[ProcessPoolExecutor | None]:
    if n_workers <= 1:
        yield None
        return
    # fork needs no `if __name__ == "__main__"` guard in the user's script; workers use numpy, numba, shapely and
    # VisiLibity only (never polars, whose thread pool does not survive a fork)
    method = "fork" if "fork" in multiprocessing.get_all_start_methods() else "spawn"
    with ProcessPoolExecutor(n_workers, mp_context=multiprocessing.get_context(method)) as pool:
        yield pool


def get_visibility_df_for_frame(
    df: Any,
    ego_idx: EgoSpec,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    epsilon: float | None = None,
    *,
    engine: str = "visilibity",
    on_invalid: OnInvalid = "warn",
) -> pl.DataFrame:
    """:func:`get_visibility_df` for a single frame number (same parameters and columns; ``epsilon`` likewise has
    no effect).

    Raises
    ------
    ValueError
        If the frame does not occur in the table.
    """
    check_epsilon(epsilon)
    table = df._df if hasattr(df, "_df") and not isinstance(df, pl.DataFrame | pl.LazyFrame) else df
    lazy = table.lazy() if isinstance(table, pl.DataFrame) else table
    if not isinstance(lazy, pl.LazyFrame):
        raise TypeError(f"expected an omega_prime.Recording or a polars DataFrame/LazyFrame, got {type(df)!r}")
    if "frame" not in lazy.collect_schema().names():
        raise ValueError("the moving-object table lacks the column 'frame'")
    one = lazy.filter(pl.col("frame") == frame).collect()
    if one.height == 0:
        raise ValueError(f"frame {frame} does not occur in the table")
    return get_visibility_df(one, ego_idx, static_occluder_polys, engine=engine, progress=False, on_invalid=on_invalid)
