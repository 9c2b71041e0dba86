"""The output table: one schema for every front end, columns carried by name, and the one place that says what
an engine's :class:`~.engines.Reason` codes mean in the table.

Rows are assembled as named flat arrays (:mod:`.rows`), collected by a :class:`TableBuilder` into plain numpy
arrays (cheap to send between processes) and turned into polars once (:func:`to_polars`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import polars as pl
import pyarrow as pa

from .._compiled.kernel import njit
from ..engines import Reason

STATUSES = ("visible", "partly_visible", "occluded", "out_of_fov", "out_of_range")
"""Why a target is seen as it is through a sensor, in :data:`SCHEMA`'s ``status`` column:

- ``visible``: ``visibility`` is 1 (the whole extent is in view and nothing hides any of it; a target containing
  the sensor point is visible too);
- ``partly_visible``: ``0 < visibility < 1``;
- and when nothing of it is seen, the most specific reason, checked in this order: ``out_of_fov`` (no direction
  of its extent lies inside the field of view), ``out_of_range`` (some do, but along none of them is the target
  hit within range), ``occluded`` (it is in view somewhere, but hidden there).
"""
VISIBLE, PARTLY_VISIBLE, OCCLUDED, OUT_OF_FOV, OUT_OF_RANGE = range(len(STATUSES))

SCHEMA: dict[str, pl.DataType] = {
    "frame": pl.Int64(),
    "total_nanos": pl.Int64(),
    "idx_ego": pl.Int64(),
    "idx": pl.Int64(),
    "occluder_idxs": pl.List(pl.Int64()),
    "static_occluder_idxs": pl.List(pl.Int64()),
    "visibility": pl.Float64(),
}
"""Column types of the visibility table. ``idx_ego`` (the observer; named as in omega-prime's own
metrics, e.g. its time gap, so the tables join) is present only when several observers were asked for."""

SENSOR_SCHEMA: dict[str, pl.DataType] = {
    "sensor": pl.String(),
    "in_view": pl.Float64(),
    "status": pl.Enum(STATUSES),
}
"""The columns a table gains when sensors were given: ``sensor`` follows ``idx``, the others come last."""

COUNT_SCHEMA: dict[str, pl.DataType] = {
    "pixels": pl.Int64(),
    "pixels_unoccluded": pl.Int64(),
    "occlusion": pl.Float64(),
    "truncation": pl.Float64(),
    "bbox": pl.Array(pl.Int64(), 4),
    "bbox_unoccluded": pl.Array(pl.Int64(), 4),
    "points": pl.Int64(),
    "points_unoccluded": pl.Int64(),
}
"""A camera's and a lidar's own columns, after the sensor columns (null on the rows of other sensors):

- ``pixels``: pixels whose centre ray meets the target first within range (ties visible); ``pixels_unoccluded``:
  those whose centre ray meets it within range, other bodies ignored;
- ``occlusion``: ``1 - pixels / pixels_unoccluded`` (null when no pixel meets it);
- ``truncation``: the share of the target's solid angle outside the image (its frustum), occlusion ignored;
- ``bbox``, ``bbox_unoccluded``: ``(u0, v0, u1, v1)``, the first and last column and row (inclusive pixel
  indices, from the top-left corner) of those pixels: the visible and the full 2D box (null when empty);
- ``points``, ``points_unoccluded``: a lidar's beams of one turn that meet the target first within range, and
  within range at all.
"""
CAMERA_COLUMNS = ("pixels", "pixels_unoccluded", "occlusion", "truncation", "bbox", "bbox_unoccluded")
LIDAR_COLUMNS = ("points", "points_unoccluded")


def count_columns(kinds: Sequence[str]) -> tuple[str, ...]:
    """The count columns a table gains from sensors of these kinds (``"camera"``, ``"lidar"``, ``"view"``).

    >>> count_columns(["view", "lidar"]), count_columns(["view"])
    (('points', 'points_unoccluded'), ())
    """
    return (CAMERA_COLUMNS if "camera" in kinds else ()) + (LIDAR_COLUMNS if "lidar" in kinds else ())


def missing_counts(name: str, n: int) -> np.ndarray:
    """``n`` null entries of count column ``name`` as its arrays carry them: -1, NaN, or boxes of -1."""
    if name in ("bbox", "bbox_unoccluded"):
        return np.full((n, 4), -1, dtype=np.int64)
    if COUNT_SCHEMA[name] == pl.Float64():
        return np.full(n, np.nan)
    return np.full(n, -1, dtype=np.int64)


def count_present(name: str, values: np.ndarray) -> np.ndarray:
    """Which entries of count column ``name`` hold a value (see :func:`missing_counts`)."""
    if values.ndim == 2:
        return values[:, 0] >= 0
    if values.dtype.kind == "f":
        return ~np.isnan(values)
    return values >= 0


STATIC_LABEL = "static #"
"""How a person reads a static occluder's entry in ``static_occluder_idxs`` (its position in the list given):
``static #0`` is the first, never a bare number that reads as a count."""


def static_names(positions: Sequence[int] | None) -> str:
    """Static occluders by their positions in the list given, as a person reads them (``"none"`` for none).

    >>> static_names([0, 2]), static_names([])
    ('static #0, static #2', 'none')
    """
    return ", ".join(f"{STATIC_LABEL}{int(k)}" for k in positions or []) or "none"


LIST_COLUMNS = tuple(name for name, dtype in SCHEMA.items() if isinstance(dtype, pl.List))
"""List columns travel as ``(lengths, values)`` pairs of flat arrays."""

Columns = dict[str, np.ndarray | tuple[np.ndarray, np.ndarray]]

_CONTAINS_OBSERVER = int(Reason.CONTAINS_OBSERVER)
_IN_VIEW = int(Reason.IN_VIEW)


def schema(with_ego: bool, with_sensors: bool = False, counted: Sequence[str] = ()) -> dict[str, pl.DataType]:
    """The table's schema, with or without the ``idx_ego`` column and the sensor columns, and with the
    ``counted`` columns of :data:`COUNT_SCHEMA` (:func:`count_columns`)."""
    out = {}
    for name, dtype in SCHEMA.items():
        if with_ego or name != "idx_ego":
            out[name] = dtype
        if name == "idx" and with_sensors:
            out["sensor"] = SENSOR_SCHEMA["sensor"]
    if with_sensors:
        out.update({k: v for k, v in SENSOR_SCHEMA.items() if k != "sensor"})
    out.update({name: COUNT_SCHEMA[name] for name in counted})
    return out


def empty_table(with_ego: bool = False, with_sensors: bool = False, counted: Sequence[str] = ()) -> pl.DataFrame:
    """A visibility table with no rows."""
    return pl.DataFrame(schema=schema(with_ego, with_sensors, counted))


@njit(cache=True)
def visibility_of(reason, visible_angle, angular_extent):
    """The policy: ``visibility`` of a target from its reason code and angles (any one measure).

    A target that contains the viewpoint, or has nothing in front of it, is exactly 1.0; otherwise the visible
    share of its extent, clipped to [0, 1].
    """
    if reason == _CONTAINS_OBSERVER or reason == _IN_VIEW:
        return 1.0
    share = visible_angle / angular_extent if angular_extent > 0 else 0.0
    return min(max(share, 0.0), 1.0)


@njit(cache=True)
def view_of(reason, visible_angle, angular_extent, in_view_angle, in_fov_angle):
    """The policy through a sensor: ``(visibility, in_view, status)`` of a target from its reason code and angles
    (see :data:`STATUSES`). ``in_view`` is the share of the extent in view ignoring occlusion; with nothing in
    front of it, a target is seen along all of it."""
    if reason == _CONTAINS_OBSERVER:
        return 1.0, 1.0, VISIBLE
    in_view = 1.0 if in_view_angle >= angular_extent else max(in_view_angle / angular_extent, 0.0)
    if reason == _IN_VIEW:
        visibility = in_view
    else:
        share = visible_angle / angular_extent if angular_extent > 0 else 0.0
        visibility = min(max(share, 0.0), in_view)
    if visibility >= 1.0:
        status = VISIBLE
    elif visibility > 0.0:
        status = PARTLY_VISIBLE
    elif in_fov_angle <= 0.0:
        status = OUT_OF_FOV
    elif in_view <= 0.0:
        status = OUT_OF_RANGE
    else:
        status = OCCLUDED
    return visibility, in_view, status


class TableBuilder:
    """Collects per-(frame, viewpoint) blocks of named columns and concatenates them once.

    A block gives every column of the schema: arrays of one value per row, list columns as ``(lengths, values)``,
    and scalars (``frame``, ``total_nanos``, ``idx_ego``) that hold for all its rows.
    """

    def __init__(self) -> None:
        self._blocks: list[dict] = []
        self.rows = 0

    def add(self, columns: Columns, **constants: int) -> None:
        """Add the rows of ``columns`` (same length each), with ``constants`` holding for all of them."""
        k = len(columns["idx"])
        if k:
            self._blocks.append((k, columns, constants))
            self.rows += k

    def arrays(self) -> Columns | None:
        """Everything added so far as flat column arrays by name (None when empty); blocks are cleared."""
        if not self._blocks:
            return None
        blocks, self._blocks, self.rows = self._blocks, [], 0
        counts = np.array([k for k, _, _ in blocks])
        out: Columns = {}
        for name in blocks[0][2]:
            out[name] = np.repeat(np.array([c[name] for _, _, c in blocks], dtype=np.int64), counts)
        for name in blocks[0][1]:
            if name in LIST_COLUMNS:
                out[name] = (
                    np.concatenate([b[name][0] for _, b, _ in blocks]),
                    np.concatenate([b[name][1] for _, b, _ in blocks]).astype(np.int64, copy=False),
                )
            else:
                out[name] = np.concatenate([b[name] for _, b, _ in blocks])
        return out


def _list_column(lengths: np.ndarray, values: np.ndarray) -> pl.Series:
    offsets = np.zeros(len(lengths) + 1, dtype=np.int64)
    np.cumsum(lengths, out=offsets[1:])
    return pl.Series(_ArrowArray(pa.LargeListArray.from_arrays(_int64_array(offsets), _int64_array(values))))


class _ArrowArray:
    """An arrow array seen only through the Arrow PyCapsule interface: polars takes it as it is, where a pyarrow
    array given directly passes through a conversion that imports ``pyarrow.compute`` (0.13 s of a short run)."""

    def __init__(self, array: pa.Array) -> None:
        self.array = array

    def __arrow_c_array__(self, requested_schema: object = None) -> tuple[object, object]:
        return self.array.__arrow_c_array__(requested_schema)


def _int64_array(values: np.ndarray) -> pa.Array:
    """``values`` as an arrow int64 array on the same memory (``pyarrow.array`` of a numpy array would import
    pandas, half a second of a short run)."""
    values = np.ascontiguousarray(values, dtype=np.int64)
    return pa.Array.from_buffers(pa.int64(), len(values), [None, pa.py_buffer(values)])


def to_polars(
    columns: Columns | None, with_ego: bool, sensor_names: Sequence[str] | None = None, counted: Sequence[str] = ()
) -> pl.DataFrame:
    """The visibility table from :meth:`TableBuilder.arrays` output, columns in schema order; ``sensor_names``
    (when sensors were used) turns the ``sensor`` codes into names; ``counted`` names the count columns."""
    with_sensors = sensor_names is not None
    if columns is None:
        return empty_table(with_ego, with_sensors, counted)
    target = schema(with_ego, with_sensors, counted)
    data = {}
    for name in target:
        if name in COUNT_SCHEMA:
            values = np.asarray(columns[name])
            series = pl.Series(name, values, dtype=target[name])
            present = count_present(name, values)
            if not present.all():
                series = series.to_frame().select(pl.when(pl.lit(pl.Series(present))).then(pl.col(name))).to_series()
            data[name] = series
        elif name in LIST_COLUMNS:
            data[name] = _list_column(*columns[name])
        elif name == "sensor":
            data[name] = pl.Series(list(sensor_names), dtype=pl.String).gather(columns[name])
        elif name == "status":
            data[name] = pl.Series(STATUSES, dtype=pl.String).gather(columns[name]).cast(target[name])
        else:
            data[name] = pl.Series(columns[name])
    table = pl.DataFrame(data)
    return table if table.schema == target else table.cast(target)  # (a cast costs a polars query even when idle)
