"""The ``visibility`` and ``occluded_conflicts_metric`` Metrics for omega-prime's metric pipeline.

>>> import omega_prime
>>> from omega_prime_visibility import visibility
>>> manager = omega_prime.metrics.MetricManager(metrics=[visibility])  # doctest: +SKIP
>>> df, properties = manager.compute(recording, ego_id=0)  # doctest: +SKIP
>>> properties["visibility"]  # the table of get_visibility_df  # doctest: +SKIP
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

import polars as pl
import shapely
from omega_prime.metrics import metric

from .analysis.conflicts import occluded_conflicts
from .analysis.intervals import NUPLAN_NOTICE, check_threshold
from .api import get_visibility_df
from .inputs.objects import OnInvalid
from .inputs.observers import EgoSpec, SensorSpec
from .inputs.roles import RoleSpec
from .query import Query


@metric(computes_properties=["visibility"])
def visibility(
    df: pl.LazyFrame,
    /,
    ego_id: EgoSpec | None = None,
    static_occluder_polys: Sequence[shapely.Geometry] | None = None,
    engine: str | None = None,
    progress: bool | Literal[False] = False,
    on_invalid: OnInvalid | None = None,
    ego_idx: EgoSpec | None = None,
    epsilon: float | None = None,
    mode: Literal["2d", "3d"] | None = None,
    static_occluder_heights: Sequence[float] | float | None = None,
    map_occluders: str | None = None,
    sensors: SensorSpec = None,
    occluders: RoleSpec = None,
    targets: RoleSpec = None,
    measure: Literal["angle", "area"] | None = None,
    query: Query | None = None,
    static_meshes: Sequence[Any] | None = None,
) -> tuple[pl.LazyFrame, dict[str, pl.LazyFrame]]:
    """Visibility of every object from ``ego_id`` (one idx, a list, or ``"all"``) in every frame.

    The property ``"visibility"`` is the table of :func:`omega_prime_visibility.get_visibility_df`; the
    object table passes through unchanged. The perspective parameter is named ``ego_id`` as in omega-prime's
    own metrics, so one ``MetricManager.compute(r, ego_id=...)`` call serves them all.

    Without ``ego_id``, the recording's host vehicle is the observer, as for ``get_visibility_df`` and the shell
    (``MetricManager.compute(r)``: the host vehicle of ``r``).

    For 0.1.0 callers, ``ego_idx`` is accepted instead of ``ego_id`` (give at most one of them), and ``epsilon``
    (metres) is accepted for compatibility with 0.1.0, where it was VisiLibity's snapping distance; the result here
    is exact and does not depend on it. ``sensors`` (a layout name, a JSON file or Sensor objects) looks through
    sensors, as in :func:`~omega_prime_visibility.get_visibility_df`.

    ``mode="3d"`` (with ``static_occluder_heights`` and ``map_occluders``, an OpenDRIVE path) gives the 3D table of
    :func:`omega_prime_visibility.get_visibility_df` (with ``can_see``). ``occluders`` (who may block the view),
    ``targets`` (who gets rows) and ``measure`` (``"angle"`` or ``"area"``) are those of
    :func:`~omega_prime_visibility.get_visibility_df`. ``query`` (a :class:`~omega_prime_visibility.Query`) gives
    the whole question as one value instead (its observers, or ``ego_id``).
    """
    # ValueError, not TypeError: omega-prime relabels a metric's TypeError as "Missing parameter"
    if query is not None and ego_id is None and ego_idx is None:
        ego_id = query.observers
    if ego_id is not None and ego_idx is not None:
        raise ValueError(
            "the visibility Metric takes one of ego_id (omega-prime's name) and ego_idx (0.1.0's name), not both"
        )
    if ego_id is None and ego_idx is None:  # the host vehicle, as get_visibility_df and the shell take it
        ego_id = _host_vehicle_of_the_pipeline()
    table = get_visibility_df(
        df,
        ego_idx if ego_id is None else ego_id,
        static_occluder_polys,
        epsilon,
        engine=engine,
        progress=progress,
        on_invalid=on_invalid,
        mode=mode,
        static_occluder_heights=static_occluder_heights,
        map_occluders=map_occluders,
        sensors=sensors,
        occluders=occluders,
        targets=targets,
        measure=measure,
        static_meshes=static_meshes,
        query=query,
    )
    return df, {"visibility": table.lazy()}


def _host_vehicle_of_the_pipeline() -> int:
    """The host vehicle of the recording that omega-prime's ``MetricManager.compute`` is computing, the observer
    when no ``ego_id`` is given (the manager hands a metric the object table only: it is read from the manager's
    call, found on the stack); ``ValueError`` where there is none."""
    import sys

    from omega_prime.metrics.metric_manager import MetricManager

    frame = sys._getframe(1)
    while frame is not None and frame.f_code is not MetricManager.compute.__code__:
        frame = frame.f_back
    recording = frame.f_locals.get("r") if frame is not None else None
    host = getattr(recording, "host_vehicle_idx", None)
    if host is None:
        where = "the recording names no host vehicle" if recording is not None else "no recording names its host"
        raise ValueError(f"the visibility Metric needs an observer: give ego_id=IDX ({where})")
    return int(host)


@metric(requires_properties=["timegaps", "visibility"], computes_properties=["occluded_conflicts"])
def occluded_conflicts_metric(
    df: pl.LazyFrame,
    /,
    timegaps: pl.LazyFrame,
    visibility: pl.LazyFrame,
    ego_id: int | None = None,
    pet: float = 3.0,
    look_back: float = 5.0,
    visibility_threshold: float = 0.0,
    reaction_time: float | None = None,
    notice: tuple[float, float] | None = NUPLAN_NOTICE,
) -> tuple[pl.LazyFrame, dict[str, pl.LazyFrame]]:
    """Road users whose path conflicts with the ego's, and whether the ego could see them in time.

    The property ``"occluded_conflicts"`` is :func:`omega_prime_visibility.occluded_conflicts` of omega-prime's
    ``timegaps`` property and this package's ``visibility`` property, so the manager orders it after both:

    >>> from omega_prime.metrics.metric_manager import DEFAULT_METRICS  # doctest: +SKIP
    >>> manager = MetricManager(metrics=[*DEFAULT_METRICS, visibility, occluded_conflicts_metric])  # doctest: +SKIP
    >>> df, properties = manager.compute(recording, ego_id=0, time_buffer=3e9)  # doctest: +SKIP

    Give omega-prime's ``time_buffer`` (nanoseconds; its default is 2 s) at least ``pet`` seconds, or conflicts
    with a larger gap are never seen.
    """
    check_threshold(visibility_threshold, "visibility_threshold")
    conflicts = occluded_conflicts(
        visibility,
        timegaps,
        df,
        ego_idx=ego_id if isinstance(ego_id, int) else None,
        pet=pet,
        look_back=look_back,
        threshold=visibility_threshold,
        reaction_time=reaction_time,
        notice=notice,
    )
    return df, {"occluded_conflicts": conflicts.lazy()}


metrics = [visibility, occluded_conflicts_metric]
"""All metrics of this package, for omega-prime's plugin discovery."""
