"""Who observes: the ego specification of the front ends (an idx, a list of idx or ``"all"``) resolved against
the table, and the forms a sensor specification takes."""

from __future__ import annotations

import os
import warnings
from collections.abc import Sequence
from typing import Any, Literal

import numpy as np

from .objects import ObjectTable, OnInvalid, VisibilityInputWarning
from .sensors import Sensor

EgoSpec = int | Sequence[int] | Literal["all"]
SensorSpec = str | os.PathLike | Sensor | Sequence[Sensor] | None


def describe_idx(present: np.ndarray) -> str:
    """The first 20 idx of ``present`` for an error message, with ``...`` when there are more."""
    present = np.asarray(present)
    return f"{present[:20].tolist()}{' ...' if len(present) > 20 else ''}"


def distinct(values: np.ndarray) -> np.ndarray:
    """The distinct values of a 1-D array, ascending: ``np.unique(values)`` without numpy's masked arrays, which
    ``np.unique`` imports on its first call (11 ms of a short run).

    >>> distinct(np.array([4, 1, 4, 2])).tolist()
    [1, 2, 4]
    """
    ordered = np.sort(values)
    keep = np.ones(len(ordered), dtype=bool)
    np.not_equal(ordered[1:], ordered[:-1], out=keep[1:])
    return ordered[keep]


def resolve_egos(ego_idx: EgoSpec, objects: ObjectTable) -> tuple[np.ndarray, bool]:
    """The observers' idx as an ascending array, and whether the table needs an ``idx_ego`` column."""
    present = distinct(objects.idx)
    if isinstance(ego_idx, str):
        if ego_idx != "all":
            raise ValueError(f"ego_idx must be an int, a list of ints or 'all', not {ego_idx!r}")
        return present, True
    many = not isinstance(ego_idx, int | np.integer)
    egos = distinct(np.atleast_1d(np.asarray(ego_idx)))
    if egos.size == 0 or not np.issubdtype(egos.dtype, np.integer):
        raise ValueError(f"ego_idx must be an int, a list of ints or 'all', not {ego_idx!r}")
    missing = egos[~np.isin(egos, present)]
    if len(missing):
        raise ValueError(
            f"ego idx {missing.tolist()} never occurs among the usable rows of the table "
            f"(idx present: {describe_idx(present)})"
        )
    return egos.astype(np.int64), many


def observers_with_heading(objects: ObjectTable, egos: np.ndarray, on_invalid: OnInvalid) -> ObjectTable:
    """Sensors turn with their observer: rows of observers without a heading (``yaw`` NaN or null, with a polygon
    column that needs none for outlines) are skipped with a warning, or raise with ``on_invalid="raise"``."""
    if objects.heading_known is None:
        return objects
    unknown = np.isin(objects.idx, egos) & ~objects.heading_known
    if not unknown.any():
        return objects
    rows = np.flatnonzero(unknown)
    examples = ", ".join(f"(frame {objects.frame[i]}, idx {objects.idx[i]})" for i in rows[:5])
    problem = (
        f"{len(rows)} observer row(s) without a heading (yaw NaN or null), which sensors need to turn with it; "
        f"e.g. {examples}"
    )
    if on_invalid == "raise":
        raise ValueError(problem)
    warnings.warn(f"skipping {problem}", VisibilityInputWarning, stacklevel=4)
    return objects.take_rows(np.flatnonzero(~unknown))


def observer_words(observers: Any, recording: Any) -> str:
    """The observer(s) in a reader's words: ``host vehicle idx 87`` where it is the recording's host vehicle
    (omega-prime's ``host_vehicle_idx``), else ``idx 3``, ``idx [0, 2]`` or ``every road user``.

    >>> class Recording:
    ...     host_vehicle_idx = 87
    >>> observer_words(87, Recording()), observer_words(3, Recording()), observer_words("all", None)
    ('host vehicle idx 87', 'idx 3', 'every road user')
    """
    if isinstance(observers, str):
        return "every road user"
    if isinstance(observers, tuple | list):
        return f"idx {list(observers)}" if len(observers) != 1 else observer_words(observers[0], recording)
    host = getattr(recording, "host_vehicle_idx", None)
    return f"host vehicle idx {observers}" if host is not None and int(host) == int(observers) else f"idx {observers}"
