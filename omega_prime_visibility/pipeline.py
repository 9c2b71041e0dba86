"""Per-frame orchestration, one place for every front end: loaded objects + statics + observers + an engine ->
named column arrays.

:func:`viewpoints` says where each observer looks from and what is transparent to it, :func:`observe_frame` runs
the engine on one frame, :func:`run_chunk` on a chunk of frames with a fresh engine (so results never depend on
the chunking), and :func:`run` spreads chunks over any :class:`concurrent.futures.Executor` (a process pool, a
dask client's executor, or none). Workers return plain numpy arrays and never touch polars.
"""

from __future__ import annotations

import warnings
from collections import Counter
from collections.abc import Iterator, Sequence
from concurrent.futures import Executor

import numpy as np

from .engines import Engine, Viewpoint, get_engine
from .geometry import covers_point
from .scene import FrameObjects, ObjectTable, VisibilityInputWarning
from .sensors import Sensor, sensor_poses
from .statics import StaticOccluders
from .table import Columns, TableBuilder, observation_rows


class ContainmentLog:
    """Counts objects that contain an observer, for one summarising warning."""

    def __init__(self) -> None:
        self.frames: Counter[tuple[int, int]] = Counter()
        self.first: dict[tuple[int, int], int] = {}

    def add(self, ego: int, idx: np.ndarray, frame: int) -> None:
        for i in idx.tolist():
            self.frames[(ego, i)] += 1
            self.first.setdefault((ego, i), frame)

    def merge(self, other: ContainmentLog) -> None:
        self.frames.update(other.frames)
        for key, frame in other.first.items():
            self.first.setdefault(key, frame)

    def warn(self, stacklevel: int = 3) -> None:
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
            stacklevel=stacklevel,
        )


def viewpoints(
    objects: FrameObjects, rows: np.ndarray, statics: StaticOccluders, sensors: Sequence[Sensor] | None = None
) -> list[Viewpoint]:
    """Viewpoints of the objects at row numbers ``rows`` of this frame: at each bounding-box centre seeing all
    around, or, with ``sensors``, one per (observer, sensor) in that order, at the sensor's pose with its field
    of view and range.

    Transparent to each: its own object and every object containing or touching the viewpoint, and the static
    occluders containing it.
    """
    out = []
    for row in np.asarray(rows, dtype=np.int64).tolist():
        if sensors is None:
            poses = [(objects.position[row], float(objects.yaw[row]), None)]
        else:
            poses = []
            for sensor in sensors:
                position, heading = sensor_poses(sensor, objects.position[row], objects.yaw[row : row + 1])
                poses.append((position[0], float(heading[0]), sensor))
        for position, heading, sensor in poses:
            transparent = covers_point(position, objects.rings)
            transparent[row] = True
            static_transparent = statics.containing(position)
            view = Viewpoint(position, heading, row, transparent, static_transparent)
            if sensor is not None:
                view = Viewpoint(
                    position,
                    heading,
                    row,
                    transparent,
                    static_transparent,
                    sensor.fov,
                    sensor.range,
                    sensor.z,
                    sensor.vertical_fov,
                    sensor.pitch,
                )
            out.append(view)
    return out


def observer_rows(objects: FrameObjects, egos: np.ndarray) -> np.ndarray:
    """Row numbers, in this frame, of the observers ``egos`` (idx) that are present in it."""
    n = len(objects)
    if n == 0:
        return np.zeros(0, dtype=np.int64)
    rows = np.minimum(np.searchsorted(objects.idx, egos), n - 1)
    return rows[objects.idx[rows] == egos]


def observe_frame(
    engine: Engine,
    statics: StaticOccluders,
    objects: FrameObjects,
    egos: np.ndarray,
    builder: TableBuilder,
    containment: ContainmentLog,
    sensors: Sequence[Sensor] | None = None,
) -> None:
    """Run the engine for every observer (and sensor) present in this frame and add the rows to ``builder``."""
    rows = observer_rows(objects, egos)
    if len(rows) == 0:
        return
    views = viewpoints(objects, rows, statics, sensors)
    per_observer = 1 if sensors is None else len(sensors)
    for k, (view, observation) in enumerate(zip(views, engine.observe(objects, views), strict=True)):
        ego = int(objects.idx[view.own])
        inside = view.transparent.copy()
        inside[view.own] = False
        if inside.any():
            containment.add(ego, objects.idx[inside], objects.frame)
        constants = {"frame": objects.frame, "total_nanos": objects.total_nanos, "idx_ego": ego}
        if sensors is None:
            builder.add(observation_rows(observation, view.own, objects.idx), **constants)
        else:
            columns = observation_rows(observation, view.own, objects.idx, with_view=True)
            builder.add(columns, **constants, sensor=k % per_observer)


def run_chunk(
    objects: ObjectTable,
    statics: StaticOccluders,
    egos: np.ndarray,
    engine: str,
    sensors: Sequence[Sensor] | None = None,
) -> tuple[Columns | None, ContainmentLog]:
    """All frames of ``objects`` with a fresh engine; plain arrays by column name, and the containment log."""
    eng = get_engine(engine)(statics)
    builder = TableBuilder()
    containment = ContainmentLog()
    for k in range(objects.n_frames):
        observe_frame(eng, statics, objects.frame_objects(k), egos, builder, containment, sensors)
    return builder.arrays(), containment


def _run_chunk_star(args: tuple) -> tuple[Columns | None, ContainmentLog]:
    return run_chunk(*args)


def chunks(n_frames: int, chunk_frames: int) -> list[tuple[int, int]]:
    """``(start, stop)`` frame positions of consecutive chunks of at most ``chunk_frames`` frames."""
    return [(k, min(k + chunk_frames, n_frames)) for k in range(0, n_frames, chunk_frames)]


def run(
    objects: ObjectTable,
    statics: StaticOccluders,
    egos: np.ndarray,
    engine: str,
    *,
    chunk_frames: int,
    executor: Executor | None = None,
    sensors: Sequence[Sensor] | None = None,
) -> Iterator[tuple[int, Columns | None, ContainmentLog]]:
    """Observe every frame, chunk by chunk, in order; yields ``(frames in the chunk, columns, containment log)``.

    Parameters
    ----------
    objects, statics
        The loaded scene (:func:`..scene.load_objects`, :func:`..scene.load_static_occluders`).
    egos : ndarray of int64
        The observers' idx, ascending.
    engine : str
        A registered engine name; every chunk builds its own engine, so the result never depends on chunking.
    chunk_frames : int
        Frames per chunk.
    executor : concurrent.futures.Executor, optional
        Where chunks run (its ``map`` keeps their order); None runs them here, one after another.
    sensors : sequence of Sensor, optional
        Observe through these sensors (rows gain a ``sensor`` code, their position in this sequence, and the
        ``in_view`` and ``status`` columns); None: from each observer's centre, all around.
    """
    bounds = chunks(objects.n_frames, chunk_frames)
    tasks = ((objects.frame_range(a, b), statics, egos, engine, sensors) for a, b in bounds)
    results = executor.map(_run_chunk_star, tasks) if executor is not None else map(_run_chunk_star, tasks)
    for (a, b), (columns, log) in zip(bounds, results, strict=True):
        yield b - a, columns, log
