"""The question resolved against one recording: the objects read once, the static occluders built once, the
observers, sensors and engine settled. Every stage after ``inputs/`` takes this one value.

>>> import polars as pl
>>> from omega_prime_visibility.query import Query
>>> objects = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, 10.0],
...     "y": [0.0, 0.0], "length": [4.0, 4.0], "width": [2.0, 2.0], "yaw": [0.0, 0.0]})
>>> scene = resolve(Query(observers=0, sensors="roof"), objects)
>>> scene.egos.tolist(), scene.with_ego, [s.name for s in scene.sensors[0]], scene.engine
([0], False, ['roof'], 'visilibity')
"""

from __future__ import annotations

import os
import warnings
from dataclasses import dataclass
from typing import Any

import numpy as np
import polars as pl

from ..engines import Engine
from ..engines.registry import get_engine
from ..inputs.errors import OptionError
from ..inputs.io import read_recording
from ..inputs.objects import ObjectTable, VisibilityInputWarning
from ..inputs.observers import describe_idx, observers_with_heading, resolve_egos
from ..inputs.roles import describe as describe_choice
from ..inputs.roles import kinds_present
from ..inputs.scene import as_lazy, as_polars, load_objects, observer_sizes
from ..inputs.sensors import Sensor, fitted_layout, is_layout
from ..inputs.statics import StaticOccluders
from ..threed.mode import load_statics
from .question import Query


@dataclass(frozen=True)
class Resolved:
    """A :class:`~.question.Query` resolved against one recording.

    Attributes
    ----------
    query : Query
    objects : ObjectTable
        The usable moving objects, grouped by frame (observers without a heading dropped where sensors need one).
    statics : StaticOccluders
        The static occluders the engines see (the user's, the map's road objects, meshes in 3D).
    static_positions : ndarray or None
        In 2D, where the height rule left some out: each seen static occluder's position in the full list.
    egos : ndarray of int64
        The observers, ascending.
    with_ego : bool
        Whether the table has an ``idx_ego`` column (several observers were asked for).
    sensors : tuple of Sensor, dict of idx to tuple of Sensor, or None
        The sensors (a layout fitted to each observer's size).
    engine : str
    engine_class : type of Engine
    """

    query: Query
    objects: ObjectTable
    statics: StaticOccluders
    static_positions: np.ndarray | None
    egos: np.ndarray
    with_ego: bool
    sensors: tuple[Sensor, ...] | dict[int, tuple[Sensor, ...]] | None
    engine: str
    engine_class: type[Engine]

    @property
    def sensor_names(self) -> list[str] | None:
        """The sensors' names in order (the first observer's, for a per-observer layout)."""
        if self.sensors is None:
            return None
        first = next(iter(self.sensors.values())) if isinstance(self.sensors, dict) else self.sensors
        return [s.name for s in first]


def resolve(query: Query, recording: Any) -> Resolved:
    """Read ``recording`` (an omega-prime Recording, a polars or pandas table) once for ``query``.

    Raises
    ------
    ValueError
        A table that cannot be used (see ``load_objects``), an observer that never occurs, sensors without the
        observers' heading, no observer given for a table without a host vehicle.
    """
    q = query
    if isinstance(recording, str | os.PathLike):  # read once: its host vehicle and map are needed too
        recording = read_recording(recording)
    objects = load_objects(
        recording, on_invalid=q.on_invalid, three_d=q.three_d, occluders=q.occluders, targets=q.targets
    )
    if q.sensors is not None and not _has_yaw(recording):
        raise OptionError.plain(
            "sensors", "sensors need the observers' heading: the moving-object table has no 'yaw' column"
        )
    statics, static_positions = load_statics(
        list(q.static_occluders) or None,
        q.mode,
        q.static_heights,
        q.static_meshes,
        q.map_occluders,
        recording,
    )
    observers = host_vehicle(recording, objects) if q.observers is None else q.observers
    egos, with_ego = resolve_egos(list(observers) if isinstance(observers, tuple) else observers, objects)
    wanted = np.unique(objects.idx[objects.wanted]) if objects.wanted is not None else None
    if wanted is not None and len(wanted) == 1 and np.isin(wanted, egos).all():  # (several see each other)
        warnings.warn(
            f"targets={describe_choice(q.targets)!r} matches only the observer(s) {egos.tolist()[:10]}, which are "
            "never their own targets, so the table has no rows",
            VisibilityInputWarning,
            stacklevel=3,
        )
    blockers = np.unique(objects.idx[objects.blocks]) if objects.blocks is not None else None
    if blockers is not None and len(blockers) == 1 and np.isin(blockers, egos).all() and len(egos) == 1:
        warnings.warn(
            f"occluders={describe_choice(q.occluders)!r} matches only the observer {egos.tolist()[0]}, which never "
            "blocks its own view, so no road user blocks it (only static occluders do)",
            VisibilityInputWarning,
            stacklevel=3,
        )
    sensors: Any = q.sensors
    if sensors is not None:  # sensors turn with their observer
        objects = observers_with_heading(objects, egos, q.on_invalid)
    if is_layout(sensors):  # fitted to each observer's own size
        sensors = fitted_layout(sensors, observer_sizes(objects, egos))
    return Resolved(q, objects, statics, static_positions, egos, with_ego, sensors, q.engine, get_engine(q.engine))


def host_vehicle(recording: Any, objects: ObjectTable) -> int:
    """The observer when none is given: the recording's host vehicle (omega-prime's ``host_vehicle_idx``)."""
    host = getattr(recording, "host_vehicle_idx", None)
    if host is not None:
        return int(host)
    present = np.unique(objects.idx)
    try:
        kinds = kinds_present(as_polars(recording))
    except (TypeError, ValueError, pl.exceptions.PolarsError):
        kinds = f"idx {describe_idx(present)}"
    raise OptionError.plain(
        "ego_idx", f"give the observer's idx; the recording names no host vehicle (present: {kinds})"
    )


def _has_yaw(recording: Any) -> bool:
    """Whether the moving-object input has a ``yaw`` column (a Recording always has)."""
    try:
        return "yaw" in as_lazy(recording).collect_schema().names()
    except (TypeError, ValueError):
        return True
