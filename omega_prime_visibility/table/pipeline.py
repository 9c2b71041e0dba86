"""Per-frame orchestration, one place for every front end: loaded objects + statics + observers + an engine ->
named column arrays.

:func:`viewpoints` says where each observer looks from and what is transparent to it, :func:`observe_frame` runs
the engine on one frame, :func:`run_chunk` on a chunk of frames with a fresh engine (so results never depend on
the chunking); when every viewpoint sees all around without range and the engine offers ``observe_chunk``, the
chunk goes through it in one piece (:func:`chunk_viewpoints`, :func:`.rows.chunk_rows`: no per-frame Python, the
same numbers), and :func:`run` spreads chunks over any :class:`concurrent.futures.Executor` (a process pool, a
dask client's executor, or none). Workers return plain numpy arrays and never touch polars.
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from concurrent.futures import Executor
from typing import Any

import numpy as np

from ..engines import FALLBACK_ENGINE, ChunkViewpoints, Engine, EngineFailure, Viewpoint
from ..engines.observe3d import holding_eye, static_heights, statics_holding_eye
from ..engines.registry import get_engine
from ..inputs.containment import covers_points, covers_points_by_frame
from ..inputs.objects import FrameObjects, ObjectTable
from ..inputs.sensors import TWO_PI, Sensor, sensor_poses
from ..inputs.statics import StaticOccluders
from .notices import ContainmentLog
from .rows import chunk_rows, frame_rows
from .schema import Columns, TableBuilder, count_columns
from .selection import (
    chunk_scenes,
    frame_scenes,
    frame_with_passive_targets,
    kept_rows,
    passive_in_place,
    with_passive_targets,
)

SensorSet = Sequence[Sensor] | dict[int, Sequence[Sensor]]
"""Sensors for every observer, or per observer idx (same names, same order)."""


def _check_covered(sensors: dict[int, Sequence[Sensor]], observers: np.ndarray) -> None:
    """Raise unless the per-observer sensor sets name every observer idx in ``observers``."""
    missing = sorted(set(np.unique(observers).tolist()) - set(sensors))
    if missing:
        raise ValueError(f"no sensors given for observer idx {missing[:10]}")


def viewpoints(
    objects: FrameObjects, rows: np.ndarray, statics: StaticOccluders, sensors: SensorSet | None = None
) -> list[Viewpoint]:
    """Viewpoints of the objects at row numbers ``rows`` of this frame: at each bounding-box centre seeing all
    around, or, with ``sensors`` (one sequence for all observers, or one per observer idx, with the same names in
    the same order), one per (observer, sensor) in that order, at the sensor's pose with its field of view and
    range.

    Transparent to each: its own object and every object containing or touching the viewpoint, and the static
    occluders containing it.
    """
    rows = np.asarray(rows, dtype=np.int64)
    if isinstance(sensors, dict):  # each observer with its own sensors (e.g. a layout fitted to its size)
        _check_covered(sensors, objects.idx[rows])
        return [v for row in rows.tolist() for v in viewpoints(objects, [row], statics, sensors[int(objects.idx[row])])]
    if sensors is None:
        owners = rows
        positions = objects.position[rows]
        headings = objects.yaw[rows]
    else:
        owners = np.repeat(rows, len(sensors))
        positions, headings = sensor_poses(sensors, objects.position[rows], objects.yaw[rows])
    transparent = covers_points(positions, objects.rings)
    transparent[np.arange(len(owners)), owners] = True
    static_transparent = statics.containing(positions)
    headings = headings.tolist()
    if sensors is None:
        return [
            Viewpoint(positions[k], headings[k], row, transparent[k], static_transparent[k])
            for k, row in enumerate(owners.tolist())
        ]
    limits = [(s.fov, s.range, s.z, s.vertical_fov, s.pitch) for s in sensors]
    optics = [s.camera if s.camera is not None else s.lidar for s in sensors]
    return [
        Viewpoint(
            positions[k], headings[k], row, transparent[k], static_transparent[k], *limits[k % len(sensors)],
            optics=optics[k % len(sensors)],
        )
        for k, row in enumerate(owners.tolist())
    ]  # fmt: skip


def sensors_per_observer(sensors: SensorSet | None) -> int:
    """Viewpoints per observer: its number of sensors, or 1 without sensors."""
    if sensors is None:
        return 1
    return len(next(iter(sensors.values())) if isinstance(sensors, dict) else sensors)


def _all_sensors(sensors: SensorSet) -> list[Sensor]:
    return [s for one in (sensors.values() if isinstance(sensors, dict) else [sensors]) for s in one]


def unlimited(sensors: SensorSet | None) -> bool:
    """Whether every sensor (if any) sees all around without range, so viewpoints see as bare points (a camera or
    a lidar never does: it counts its own rays)."""
    if sensors is None:
        return True
    return all(s.fov >= TWO_PI and not np.isfinite(s.range) and s.kind == "view" for s in _all_sensors(sensors))


def counted_columns(sensors: SensorSet | None) -> tuple[str, ...]:
    """The count columns (:data:`..schema.COUNT_SCHEMA`) the table gains from these sensors' cameras and lidars."""
    return () if sensors is None else count_columns({s.kind for s in _all_sensors(sensors)})


def chunk_viewpoints(
    objects: ObjectTable, egos: np.ndarray, statics: StaticOccluders, sensors: SensorSet | None = None
) -> tuple[ChunkViewpoints, np.ndarray]:
    """:func:`viewpoints` for every frame of a chunk at once, for viewpoints that see all around without range
    (:func:`unlimited`); also the chunk row of each viewpoint's observer.

    The same viewpoints in the same order (frame by frame, observer by observer, each with its sensors in order)
    and the same transparency.
    """
    is_ego = np.isin(objects.idx, egos)
    rows = np.flatnonzero(is_ego)  # ascending: by frame, then idx
    per_observer = sensors_per_observer(sensors)
    owners = np.repeat(rows, per_observer)
    if sensors is None:
        positions = objects.position[rows]
    elif isinstance(sensors, dict):  # each observer with its own sensors
        _check_covered(sensors, objects.idx[rows])
        positions = np.empty((len(owners), 2))
        for ego, own in sensors.items():
            mine = np.flatnonzero(objects.idx[rows] == ego)
            if len(mine):
                at = (mine[:, None] * per_observer + np.arange(per_observer)).ravel()
                positions[at] = sensor_poses(own, objects.position[rows[mine]], objects.yaw[rows[mine]])[0]
    else:
        positions = sensor_poses(sensors, objects.position[rows], objects.yaw[rows])[0]
    frame_of_row = np.repeat(np.arange(objects.n_frames), np.diff(objects.frame_starts))
    view_starts = np.zeros(objects.n_frames + 1, dtype=np.int64)
    np.cumsum(np.bincount(frame_of_row[owners], minlength=objects.n_frames), out=view_starts[1:])
    own = owners - objects.frame_starts[frame_of_row[owners]]
    transparent, target_offsets = covers_points_by_frame(positions, view_starts, objects.rings, objects.frame_starts)
    transparent[target_offsets[:-1] + own] = True
    inside, source = statics.containing_pairs(positions)
    static_offsets = np.zeros(len(owners) + 1, dtype=np.int64)
    np.cumsum(np.bincount(inside, minlength=len(owners)), out=static_offsets[1:])
    views = ChunkViewpoints(view_starts, positions, own, target_offsets, transparent, static_offsets, source)
    return views, owners


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
    sensors: SensorSet | None = None,
) -> None:
    """Run the engine for every observer (and sensor) present in this frame and add the rows to ``builder``."""
    rows = observer_rows(objects, egos)
    if len(rows) == 0:
        return
    views = viewpoints(objects, rows, statics, sensors)
    holders = []  # (observer idx, containing idx) of every view of the frame, logged once
    for view in views:
        if np.count_nonzero(view.transparent) > 1:  # more than its own body: it is inside some object
            inside = view.transparent.copy()
            inside[view.own] = False
            if objects.boxes3d is not None:  # in 3D only the boxes that hold the eye are transparent
                inside &= holding_eye(view, objects.boxes3d)
            holders += [(objects.idx[view.own], i) for i in objects.idx[inside].tolist()]
    if holders:
        ego, inside_idx = np.array(holders, dtype=np.int64).T
        containment.add_pairs(ego, inside_idx, np.full(len(ego), objects.frame))
    if objects.boxes3d is None:
        sources = [np.flatnonzero(view.static_transparent) for view in views]
    else:  # in 3D a static occluder is transparent only where its prism holds the eye
        tops, bases = static_heights(statics)
        sources = [np.flatnonzero(statics_holding_eye(view, objects.boxes3d, tops, bases)) for view in views]
    ego = np.repeat([objects.idx[view.own] for view in views], [len(k) for k in sources]).astype(np.int64)
    if len(ego):
        containment.add_static_pairs(ego, np.concatenate(sources), np.full(len(ego), objects.frame))
    sensor_codes = None if sensors is None else np.tile(np.arange(sensors_per_observer(sensors)), len(rows))
    counted = counted_columns(sensors)
    if passive_in_place(objects, engine):  # occluders= alone, measured by the engine itself
        views = frame_with_passive_targets(objects, views)
    elif objects.blocks is not None or objects.wanted is not None:  # occluders= or targets= (see .selection)
        scenes, expanded = frame_scenes(objects, views, engine.passive_targets)
        codes = None if sensor_codes is None else sensor_codes[expanded.base]
        parts = [
            frame_rows(
                _observe(engine, statics, scene, [view], containment),
                np.array([view.own]),
                scene.idx,
                None if codes is None else codes[e : e + 1],
                counted,
            )
            for e, (scene, view) in enumerate(scenes)
        ]
        if parts:
            builder.add(kept_rows(_joined(parts), expanded), frame=objects.frame, total_nanos=objects.total_nanos)
        return
    observations = _observe(engine, statics, objects, views, containment)
    owns = np.array([view.own for view in views], dtype=np.int64)
    columns = frame_rows(observations, owns, objects.idx, sensor_codes, counted)
    builder.add(columns, frame=objects.frame, total_nanos=objects.total_nanos)


def _observe(
    engine: Engine, statics: StaticOccluders, objects: FrameObjects, views: list[Viewpoint], log: ContainmentLog
) -> list:
    """The engine's observations of one frame, or the fallback engine's where it cannot compute the frame; the
    cameras' and lidars' views go to the counting engine (:mod:`..engines.imaging`)."""
    counting = [k for k, view in enumerate(views) if view.optics is not None]
    if counting:
        others = [k for k, view in enumerate(views) if view.optics is None]
        out: list = [None] * len(views)
        for k, seen in zip(
            counting, _imaging_engine(statics).observe(objects, [views[k] for k in counting]), strict=True
        ):
            out[k] = seen
        if others:
            for k, seen in zip(
                others, _observe(engine, statics, objects, [views[k] for k in others], log), strict=True
            ):
                out[k] = seen
        return out
    try:
        return engine.observe(objects, views)
    except EngineFailure as failure:  # e.g. VisiLibity with the viewpoint within a wall's thickness
        log.add_fallback(objects.frame, str(failure))
        return _fallback_engine(statics).observe(objects, views)


_IMAGING: list = []  # [(statics, engine)]: the counting engine for these static occluders, built once


def _imaging_engine(statics: StaticOccluders) -> Engine:
    """The counting engine (:class:`..engines.imaging.ImagingEngine`) for these static occluders."""
    if not _IMAGING or _IMAGING[0][0] is not statics:
        from ..engines.imaging import ImagingEngine

        _IMAGING[:] = [(statics, ImagingEngine(statics))]
    return _IMAGING[0][1]


def _joined(parts: list[Columns]) -> Columns:
    """Blocks of named columns (same names) one after another."""
    builder = TableBuilder()
    for part in parts:
        builder.add(part)
    return builder.arrays() or {name: np.zeros(0, dtype=np.int64) for name in parts[0]}


_FALLBACK: list = []  # [(statics, engine)]: the last fallback engine built, reused while the statics are the same


def _fallback_engine(statics: StaticOccluders) -> Engine:
    """The :data:`..engines.FALLBACK_ENGINE` for these static occluders, built once (a large map's static grid is
    not built again for every frame that needs it)."""
    if not _FALLBACK or _FALLBACK[0][0] is not statics:
        _FALLBACK[:] = [(statics, get_engine(FALLBACK_ENGINE)(statics))]
    return _FALLBACK[0][1]


def run_chunk(
    objects: ObjectTable,
    statics: StaticOccluders,
    egos: np.ndarray,
    engine: str,
    sensors: SensorSet | None = None,
) -> tuple[Columns | None, ContainmentLog]:
    """All frames of ``objects`` with a fresh engine; plain arrays by column name, and the containment log."""
    eng = get_engine(engine)(statics)
    containment = ContainmentLog()
    if eng.chunked and unlimited(sensors):  # the whole chunk in compiled loops
        views, owners = chunk_viewpoints(objects, egos, statics, sensors)
        per_observer = sensors_per_observer(sensors)
        sensor_codes = None if sensors is None else np.tile(np.arange(per_observer), len(views) // per_observer)
        scenes, seen, expanded = objects, views, None
        if passive_in_place(objects, eng):  # occluders= alone, measured by the engine itself
            seen = with_passive_targets(views, owners, objects)
        elif objects.chosen:  # occluders= or targets= (see .selection)
            scenes, seen, expanded = chunk_scenes(views, owners, objects, eng.passive_targets)
            sensor_codes = None if sensor_codes is None else sensor_codes[expanded.base]
        try:
            observation = eng.observe_chunk(scenes, seen)
        except EngineFailure:  # some frame needs the fallback engine: frame by frame, which finds it
            pass
        else:
            _log_containment(containment, objects, views, owners)
            rows = (scenes.idx, scenes.frame, scenes.total_nanos, sensor_codes)
            seen_owners = owners if expanded is None else seen.target_offsets[:-1] + seen.own
            columns = chunk_rows(observation, seen, seen_owners, *rows)
            if expanded is not None and columns is not None:
                columns = kept_rows(columns, expanded)
                columns = columns if len(columns["idx"]) else None
            return columns, containment
    builder = TableBuilder()
    for k in range(objects.n_frames):
        observe_frame(eng, statics, objects.frame_objects(k), egos, builder, containment, sensors)
    return builder.arrays(), containment


def _log_containment(log: ContainmentLog, objects: ObjectTable, views: ChunkViewpoints, owners: np.ndarray) -> None:
    """Log the objects that contain a viewpoint other than its own body, and the static occluders containing one."""
    hits = np.flatnonzero(views.transparent)
    view = np.searchsorted(views.target_offsets, hits, side="right") - 1
    first_row = owners[view] - views.own[view]  # chunk row of the first object of the viewpoint's frame
    row = first_row + hits - views.target_offsets[view]
    other = row != owners[view]
    log.add_pairs(objects.idx[owners[view[other]]], objects.idx[row[other]], objects.frame[row[other]])
    holder = np.repeat(owners, np.diff(views.static_offsets))  # the observer row of each (viewpoint, source) pair
    log.add_static_pairs(objects.idx[holder], views.static_inside, objects.frame[holder])


def _run_chunk_star(args: tuple) -> tuple[Any, ContainmentLog]:
    *chunk, sink, k = args
    columns, log = run_chunk(*chunk)
    return (columns if sink is None else sink(k, columns)), log


def chunks(n_frames: int, chunk_frames: int, workers: int = 1) -> list[tuple[int, int]]:
    """``(start, stop)`` frame positions of consecutive chunks of at most ``chunk_frames`` frames.

    With several ``workers``, the number of chunks is a multiple of ``workers`` and their sizes differ by at most
    one frame, so that no worker is left idle while another finishes a last, lone chunk.

    Examples
    --------
    >>> chunks(10, 4)
    [(0, 4), (4, 8), (8, 10)]
    >>> chunks(10, 4, workers=2)
    [(0, 3), (3, 6), (6, 8), (8, 10)]
    """
    if workers <= 1 or n_frames == 0:
        return [(k, min(k + chunk_frames, n_frames)) for k in range(0, n_frames, chunk_frames)]
    count = -(-n_frames // chunk_frames)
    count = min(-(-count // workers) * workers, n_frames)
    size, extra = divmod(n_frames, count)
    stops = np.cumsum([size + (k < extra) for k in range(count)]).tolist()
    return list(zip([0, *stops[:-1]], stops, strict=True))


def run(
    objects: ObjectTable,
    statics: StaticOccluders,
    egos: np.ndarray,
    engine: str,
    *,
    chunk_frames: int,
    executor: Executor | None = None,
    workers: int = 1,
    sink: Callable[[int, Columns | None], Any] | None = None,
    sensors: SensorSet | None = None,
) -> Iterator[tuple[int, Any, ContainmentLog]]:
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
        Frames per chunk (at most).
    executor : concurrent.futures.Executor, optional
        Where chunks run (its ``map`` keeps their order); None runs them here, one after another.
    workers : int
        Processes behind ``executor``; the chunks are balanced over them (see :func:`chunks`).
    sink : callable, optional
        Called where the chunk ran (in the worker) as ``sink(k, columns)`` for the ``k``-th chunk (0-based); what
        it returns is yielded instead of the columns (e.g. it writes them to disk and returns a row count, so
        the columns never travel back to this process).
    sensors : sequence of Sensor, optional
        Observe through these sensors (rows gain a ``sensor`` code, their position in this sequence, and the
        ``in_view`` and ``status`` columns); None: from each observer's centre, all around.
    """
    bounds = chunks(objects.n_frames, chunk_frames, workers)
    tasks = ((objects.frame_range(a, b), statics, egos, engine, sensors, sink, k) for k, (a, b) in enumerate(bounds))
    results = executor.map(_run_chunk_star, tasks) if executor is not None else map(_run_chunk_star, tasks)
    for (a, b), (columns, log) in zip(bounds, results, strict=True):
        yield b - a, columns, log
