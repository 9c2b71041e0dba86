"""The user's entry points: ``get_visibility_df`` and ``get_visibility_df_for_frame``."""

from __future__ import annotations

import math
import numbers
import os
import warnings
from collections.abc import Sequence
from typing import Any, Literal

import polars as pl
import shapely

from .inputs.objects import OnInvalid, VisibilityInputWarning
from .inputs.observers import EgoSpec, SensorSpec, describe_idx  # noqa: F401 (describe_idx: public here too)
from .inputs.roles import RoleSpec, within_frames
from .inputs.scene import as_lazy
from .query import TABLE_KEYWORDS, Query, fold_keywords, resolve
from .table.compute import (  # noqa: F401 (the ways to run a question, importable from here as before)
    CHUNK_FRAMES,
    CHUNK_ROWS,
    PARALLEL_MIN_WORK,
    PROGRESS_MIN_FRAMES,
    auto_workers,
    chunk_size,
    compute,
)
from .table.output import check_dataset_path


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


def get_visibility_df(
    df: Any,
    ego_idx: EgoSpec | None = None,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    epsilon: float | None = None,
    *,
    query: Query | None = None,
    engine: str | None = None,
    progress: bool | None = None,
    on_invalid: OnInvalid | None = None,
    workers: int | None = None,
    output: str | os.PathLike | None = None,
    chunk_frames: int = CHUNK_FRAMES,
    hide_progress: bool | None = None,
    sensors: SensorSpec = None,
    mode: Literal["2d", "3d"] | None = None,
    static_occluder_heights: Sequence[float] | float | None = None,
    static_meshes: Sequence[Any] | None = None,
    map_occluders: str | os.PathLike | bool | None = None,
    occluders: RoleSpec = None,
    targets: RoleSpec = None,
    measure: Literal["angle", "area"] | None = None,
) -> pl.DataFrame | pl.LazyFrame:
    """Visibility and occluders of every object, seen from the ego, in every frame where the ego exists.

    Parameters
    ----------
    df : omega_prime.Recording, polars.DataFrame or polars.LazyFrame (or a pandas DataFrame, a pyarrow Table)
        The moving-object table: ``frame, total_nanos, idx, x, y`` and either a ``polygon`` column (shapely
        polygons) or ``length, width, yaw`` (metres, radians counter-clockwise from +x).
    ego_idx : int, list of int or "all", optional
        The observing object(s); the observer sits at the centre ``(x, y)`` of its bounding box. With more than
        one, the table gains an ``idx_ego`` column (named as in omega-prime's own metrics, so they join). None:
        the recording's host vehicle (an omega-prime Recording names it).
    static_occluder_polys : sequence of shapely geometries, optional
        Static occluders (Polygon, MultiPolygon, LineString, ...), reported by their position in this sequence.
    epsilon : float, optional
        Metres; accepted for compatibility with 0.1.0, where it was VisiLibity's snapping distance; the result here
        is exact and does not depend on it. Must be a non-negative finite number or None.
    query : Query, optional
        The whole question as one value (:class:`~omega_prime_visibility.Query`: every keyword below that shapes
        the table, and ``ego_idx`` and ``static_occluder_polys``); a keyword given beside it must agree with it.
        How to run it (``workers``, ``chunk_frames``, ``progress``, ``output``) stays with the call.
    engine : str, optional
        Registered engine name: in 2D ``"visilibity"`` (the default) or ``"sweep"`` (``ENGINES``); in 3D
        ``"silhouette3d"`` (the default: exact for boxes and static footprints with heights),
        ``"raycast3d"`` (the default where ``static_meshes`` are given), ``"raycast3d-high"`` or
        ``"raycast3d-fast"`` (``ENGINES_3D``).
    progress : bool, optional
        Show a progress bar (drawn once the call has run half a second); by default only for recordings of 200
        frames or more.
    on_invalid : {"warn", "raise"}
        Skip unusable rows (NaN pose, zero-size or invalid outline) with a warning, or raise.
    workers : int, optional
        Processes over which chunks of frames are spread; by default all cores for long jobs (at least
        ``PARALLEL_MIN_WORK`` frame-observer pairs), else 1. The result does not depend on it.
    output : path, optional
        Stream the table to this ``.parquet`` path chunk by chunk (memory stays bounded): a directory of parquet
        parts, one per chunk, each written by the worker that computed it, which ``polars.scan_parquet`` (and
        pandas, pyarrow) read as one table. The path is checked before anything is computed (see
        :func:`check_dataset_path`; a dataset from an earlier run is replaced, a single file refused); other
        suffixes are refused: for CSV, call :func:`~omega_prime_visibility.write_csv` on the returned table. The
        parts are written in a temporary directory beside it, renamed when complete, so a failed or killed run
        leaves no partial result.
    chunk_frames : int
        Frames per chunk of work, at most (fewer when frames yield many rows, see :func:`chunk_size`).
    hide_progress : bool, optional
        0.1.0's name for ``progress=not hide_progress`` (a ValueError if both are given and contradict).
    sensors : "roof", "typical", a .json path, a Sensor or a sequence of Sensors, optional
        Look through these sensors, mounted on every observer (:mod:`omega_prime_visibility.sensors`). A layout
        name is fitted to each observer's own length and width (the median extent of its outline along and across
        its heading), so a truck's bumper radar sits on the truck's bumper. Needs the observers' ``yaw``. None
        (the default): from the observer's centre, all around, without a range limit.
    mode : {"2d", "3d"}
        ``"3d"``: oriented 3D boxes from ``z, length, width, height, roll, pitch, yaw`` seen from the ego's eye
        (its centre, 1.25 m above the ground under it); ``visibility`` is a solid-angle fraction and the table
        gains ``can_see`` (see :mod:`omega_prime_visibility.threed.mode`).
    static_occluder_heights : float or sequence of float, optional
        z (metres) of the tops of ``static_occluder_polys`` (one for all, or one each); in 2D those lower than the
        driver's eye height (1.25 m) are left out, in 3D they are walls of that height (none: 100 m).
    static_meshes : sequence of paths or trimesh.Trimesh, optional
        3D static occluders (any file trimesh loads), numbered after the footprints; 3D only.
    map_occluders : path or True, optional
        An OpenDRIVE map (True: the recording's own) whose road objects (``<object>``) become static occluders
        with their heights, numbered after ``static_occluder_polys``
        (:func:`omega_prime_visibility.threed.mapobjects.read_map_objects`).
    occluders : str, list of str, list of int or polars expression, optional
        Which moving objects may block the view: a group (``"vehicles"``, ``"pedestrians"``, ``"cyclists"``,
        ``"two_wheelers"``, ``"vulnerable"``, ``"animals"``), omega-prime type or subtype names (``"PEDESTRIAN"``,
        ``"HEAVY_TRUCK"``), a list of idx, or a boolean polars expression over the object table
        (:mod:`omega_prime_visibility.inputs.roles`). The others still get rows as targets, but never hide
        anything and are never listed as occluders. None (the default): every object blocks. Static occluders
        always block.
    targets : same forms as ``occluders``, optional
        Which objects get rows (the others still block); work for the others is skipped. None: every object.
    measure : {"angle", "area"}
        What ``visibility`` is a share of: the target's angular extent (the default), or its footprint's area
        (``"area"``: the part of the footprint in no other body's shadow, inside the field of view and range, by
        exact polygon clipping, as openPASS measures it; 2D only, its own engine
        :mod:`omega_prime_visibility.engines.area`). ``in_view`` and ``status`` keep their meaning, in area.

    Returns
    -------
    polars.DataFrame, or polars.LazyFrame scanning the written parquet dataset when ``output`` is given
        One row per (frame, observer, target): ``frame, total_nanos, [idx_ego], idx, occluder_idxs,
        static_occluder_idxs, visibility`` where ``visibility`` in [0, 1] is the fraction of the target's
        angular extent along which it is the first thing hit, and the occluder lists hold, ascending, the
        objects and static occluders hit before the target along at least one direction.

        With sensors, one row per (frame, observer, target, sensor) with a ``sensor`` column (its name) after
        ``idx``, and two more columns: ``in_view``, the share of the target's angular extent (seen from the
        sensor) inside the field of view along which the target is hit within range, ignoring occlusion (so
        ``in_view - visibility`` is the share hidden by occluders and ``1 - in_view`` the share out of view),
        and ``status`` (see ``omega_prime_visibility.table.STATUSES``). ``visibility`` then counts only
        directions inside the field of view whose first hit is the target within range, and an occluder is
        listed only when it is hit before the target along such a direction of the target's (so a body in front
        of a target that lies beyond range is not listed).

    Examples
    --------
    >>> import polars as pl
    >>> objects = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2],
    ...     "x": [0.0, 10.0, 20.0], "y": [0.0, 0.0, 0.0], "length": [4.0, 4.0, 4.0],
    ...     "width": [2.0, 4.0, 2.0], "yaw": [0.0, 0.0, 0.0]})
    >>> get_visibility_df(objects, ego_idx=0).select("idx", "occluder_idxs", "visibility").rows()
    [(1, [], 1.0), (2, [1], 0.0)]

    The same question as one value, asked again with other ways to run it:

    >>> from omega_prime_visibility import Query
    >>> question = Query(observers=0, targets=[2])
    >>> get_visibility_df(objects, query=question, workers=1).select("idx", "visibility").rows()
    [(2, 0.0)]
    """
    check_epsilon(epsilon)
    check_counts(workers=workers, chunk_frames=chunk_frames)
    progress = resolve_progress(progress, hide_progress)
    if output is not None:
        output = check_dataset_path(output)
    question = fold_keywords(
        query,
        ego_idx=ego_idx,
        static_occluder_polys=static_occluder_polys,
        engine=engine,
        on_invalid=on_invalid,
        sensors=sensors,
        mode=mode,
        static_occluder_heights=static_occluder_heights,
        static_meshes=static_meshes,
        map_occluders=map_occluders,
        occluders=occluders,
        targets=targets,
        measure=measure,
    )
    return compute(resolve(question, df), workers=workers, chunk_frames=chunk_frames, progress=progress, output=output)


def check_counts(**counts: Any) -> None:
    """Each of ``counts`` None or a whole number of at least 1 (``workers``, ``chunk_frames``).

    >>> check_counts(workers=0)
    Traceback (most recent call last):
    ...
    ValueError: workers takes a whole number, at least 1, not 0
    """
    for name, value in counts.items():
        if value is not None and (isinstance(value, bool) or not isinstance(value, numbers.Integral) or value < 1):
            raise ValueError(f"{name} takes a whole number, at least 1, not {value!r}")


def get_visibility_df_for_frame(
    df: Any,
    ego_idx: EgoSpec | None,
    frame: int,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    epsilon: float | None = None,
    *,
    query: Query | None = None,
    **keywords: Any,
) -> pl.DataFrame:
    """:func:`get_visibility_df` for a single frame number (same parameters, ``query`` too, and columns;
    ``epsilon`` likewise has no effect).

    Raises
    ------
    ValueError
        If the frame does not occur in the table, or an observer is not in it.
    """
    keywords.pop("progress", None)
    for name in keywords:
        if name not in TABLE_KEYWORDS:
            raise TypeError(f"get_visibility_df_for_frame() got an unexpected keyword argument {name!r}")
    check_epsilon(epsilon)
    question = fold_keywords(query, ego_idx=ego_idx, static_occluder_polys=static_occluder_polys, **keywords)
    lazy = as_lazy(df)
    names = lazy.collect_schema().names()
    if "frame" not in names:
        raise ValueError("the moving-object table lacks the column 'frame'")
    if isinstance(frame, bool) or not isinstance(frame, numbers.Integral):
        raise ValueError(f"frame takes a frame number (a whole number), not {frame!r}")
    frame_type = lazy.collect_schema()["frame"]
    if not frame_type.is_numeric():
        raise ValueError(f"column 'frame' must hold whole numbers (frame numbers), not {frame_type} values")
    one = lazy.filter(pl.col("frame") == frame).collect()
    if one.height == 0:
        raise ValueError(f"frame {frame} does not occur in the table")
    if "idx" in names:
        question = within_recording(question, lazy)
    observers = question.observers
    if observers is None and getattr(df, "host_vehicle_idx", None) is not None:  # (else resolve tells)
        observers = int(df.host_vehicle_idx)
        question = question.replace(observers=observers)
    egos = [observers] if isinstance(observers, int) else list(observers) if isinstance(observers, tuple) else []
    present = set(one["idx"].cast(pl.Int64, strict=False).to_list()) if "idx" in names else set()
    absent = sorted(set(egos) - present) if present else []
    if absent:  # (an ego that occurs nowhere is told by get_visibility_df)
        raise ValueError(f"ego idx {absent} not present in frame {frame} (idx there: {sorted(present)[:20]})")
    with warnings.catch_warnings():  # an idx of the recording absent from this frame is no mistake
        warnings.filterwarnings(
            "ignore", r"(targets|occluders)=.* matches (no object|only the observer)", VisibilityInputWarning
        )
        scene = resolve(question, one)
    return compute(scene, workers=1, progress=False)


def within_recording(question: Query, lazy: pl.LazyFrame) -> Query:
    """``question`` for a part of a recording (some of its frames): a list of idx in ``occluders`` or ``targets``
    is checked against the whole recording's idx and becomes an expression, so an idx absent from the part
    selects nothing there rather than being refused."""
    listed = [o for o in ("occluders", "targets") if not isinstance(getattr(question, o), pl.Expr | str | None)]
    if not listed:
        return question
    all_idx = lazy.select(pl.col("idx").unique()).collect()["idx"].to_numpy()
    return question.replace(**{o: within_frames(getattr(question, o), all_idx, o) for o in listed})
