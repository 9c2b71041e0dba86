"""The output table: one schema for every front end, columns carried by name, and the one place that says what
an engine's :class:`~.engines.Reason` codes mean in the table.

Rows are assembled per (frame, viewpoint) as named flat arrays (:func:`observation_rows`), collected by a
:class:`TableBuilder` into plain numpy arrays (cheap to send between processes) and turned into polars once
(:func:`to_polars`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numba
import numpy as np
import polars as pl
import pyarrow as pa

from .engines import Observation, Reason

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

LIST_COLUMNS = tuple(name for name, dtype in SCHEMA.items() if isinstance(dtype, pl.List))
"""List columns travel as ``(lengths, values)`` pairs of flat arrays."""

Columns = dict[str, np.ndarray | tuple[np.ndarray, np.ndarray]]

_CONTAINS_OBSERVER = int(Reason.CONTAINS_OBSERVER)
_IN_VIEW = int(Reason.IN_VIEW)


def schema(with_ego: bool, with_sensors: bool = False) -> dict[str, pl.DataType]:
    """The table's schema, with or without the ``idx_ego`` column and the sensor columns."""
    out = {}
    for name, dtype in SCHEMA.items():
        if with_ego or name != "idx_ego":
            out[name] = dtype
        if name == "idx" and with_sensors:
            out["sensor"] = SENSOR_SCHEMA["sensor"]
    if with_sensors:
        out.update({k: v for k, v in SENSOR_SCHEMA.items() if k != "sensor"})
    return out


def empty_table(with_ego: bool = False, with_sensors: bool = False) -> pl.DataFrame:
    """A visibility table with no rows."""
    return pl.DataFrame(schema=schema(with_ego, with_sensors))


@numba.njit(cache=True)
def visibility_of(reason, visible_angle, angular_extent):
    """The policy: ``visibility`` of a target from its reason code and angles (any one measure).

    A target that contains the viewpoint, or has nothing in front of it, is exactly 1.0; otherwise the visible
    share of its extent, clipped to [0, 1].
    """
    if reason == _CONTAINS_OBSERVER or reason == _IN_VIEW:
        return 1.0
    share = visible_angle / angular_extent if angular_extent > 0 else 0.0
    return min(max(share, 0.0), 1.0)


@numba.njit(cache=True)
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


@numba.njit(cache=True)
def _rows(
    own,
    reason,
    visible_angle,
    angular_extent,
    occluder_offsets,
    occluders,
    static_offsets,
    statics,
    idx,
    in_view_angle,
    in_fov_angle,
    with_view,
):
    """Rows for every object but the observer's own (row number ``own``), see :func:`observation_rows`."""
    n = len(reason)
    n_rows = n - 1 if 0 <= own < n else n
    row_idx = np.empty(n_rows, dtype=np.int64)
    visibility = np.empty(n_rows)
    in_view = np.empty(n_rows if with_view else 0)
    status = np.empty(n_rows if with_view else 0, dtype=np.int8)
    occluder_counts = np.zeros(n_rows, dtype=np.int64)
    static_counts = np.zeros(n_rows, dtype=np.int64)
    row = 0
    for i in range(n):
        if i == own:
            continue
        row_idx[row] = idx[i]
        if with_view:
            visibility[row], in_view[row], status[row] = view_of(
                reason[i], visible_angle[i], angular_extent[i], in_view_angle[i], in_fov_angle[i]
            )
        else:
            visibility[row] = visibility_of(reason[i], visible_angle[i], angular_extent[i])
        if reason[i] != _CONTAINS_OBSERVER:  # a transparent target lists no occluders
            occluder_counts[row] = occluder_offsets[i + 1] - occluder_offsets[i]
            static_counts[row] = static_offsets[i + 1] - static_offsets[i]
        row += 1
    occluder_idxs = np.empty(occluder_counts.sum(), dtype=np.int64)
    static_idxs = np.empty(static_counts.sum(), dtype=np.int64)
    row = 0
    occluder_at = 0
    static_at = 0
    for i in range(n):
        if i == own:
            continue
        for q in range(occluder_counts[row]):
            occluder_idxs[occluder_at + q] = idx[occluders[occluder_offsets[i] + q]]
        for q in range(static_counts[row]):
            static_idxs[static_at + q] = statics[static_offsets[i] + q]
        occluder_at += occluder_counts[row]
        static_at += static_counts[row]
        row += 1
    return row_idx, visibility, occluder_counts, occluder_idxs, static_counts, static_idxs, in_view, status


def observation_rows(observation: Observation, own: int, idx: np.ndarray, with_view: bool = False) -> Columns:
    """The table's target columns for one observation: ``idx``, ``visibility`` and the occluder lists, and with
    ``with_view`` also ``in_view`` and ``status`` codes (positions in :data:`STATUSES`).

    Parameters
    ----------
    observation : Observation
        What one viewpoint sees of the ``n`` objects of a frame.
    own : int
        Row number of the observing object, which gets no row (-1: none).
    idx : ndarray, shape (n,), int64
        The objects' idx; occluder row numbers become idx values.
    """
    extent = observation.angular_extent
    in_view_angle = extent if observation.in_view_angle is None else observation.in_view_angle
    in_fov_angle = extent if observation.in_fov_angle is None else observation.in_fov_angle
    row_idx, visibility, occ_n, occ, st_n, st, in_view, status = _rows(
        own,
        observation.reason,
        observation.visible_angle,
        observation.angular_extent,
        observation.occluder_offsets,
        observation.occluders,
        observation.static_offsets,
        observation.static_occluders,
        idx,
        in_view_angle,
        in_fov_angle,
        with_view,
    )
    columns: Columns = {
        "idx": row_idx,
        "visibility": visibility,
        "occluder_idxs": (occ_n, occ),
        "static_occluder_idxs": (st_n, st),
    }
    if with_view:
        columns["in_view"] = in_view
        columns["status"] = status
    return columns


@numba.njit(cache=True)
def _frame_rows(
    owns,
    reason,
    visible_angle,
    angular_extent,
    occ_offsets,
    occ,
    occ_cut,
    st_offsets,
    st,
    st_cut,
    idx,
    in_view_angle,
    in_fov_angle,
    with_view,
    sensor,
):
    """:func:`_rows` for the ``k`` observations of one frame, given stacked (``(k, n)``, ``(k, n + 1)``) and
    concatenated (cut at ``occ_cut``, ``st_cut``) arrays; the rows of all of them in order, their ``idx_ego`` and,
    with ``with_view``, their ``sensor`` code (``sensor[o]`` for observation ``o``)."""
    parts = []
    n_rows = 0
    n_occ = 0
    n_st = 0
    for o in range(len(owns)):
        part = _rows(
            owns[o],
            reason[o],
            visible_angle[o],
            angular_extent[o],
            occ_offsets[o],
            occ[occ_cut[o] : occ_cut[o + 1]],
            st_offsets[o],
            st[st_cut[o] : st_cut[o + 1]],
            idx,
            in_view_angle[o],
            in_fov_angle[o],
            with_view,
        )
        parts.append(part)
        n_rows += len(part[0])
        n_occ += len(part[3])
        n_st += len(part[5])
    row_idx = np.empty(n_rows, dtype=np.int64)
    idx_ego = np.empty(n_rows, dtype=np.int64)
    visibility = np.empty(n_rows)
    occ_n = np.empty(n_rows, dtype=np.int64)
    occ_idxs = np.empty(n_occ, dtype=np.int64)
    st_n = np.empty(n_rows, dtype=np.int64)
    st_idxs = np.empty(n_st, dtype=np.int64)
    in_view = np.empty(n_rows if with_view else 0)
    status = np.empty(n_rows if with_view else 0, dtype=np.int8)
    sensor_code = np.empty(n_rows if with_view else 0, dtype=np.int64)
    at = 0
    occ_at = 0
    st_at = 0
    for o in range(len(owns)):
        part_idx, part_visibility, part_occ_n, part_occ, part_st_n, part_st, part_in_view, part_status = parts[o]
        m = len(part_idx)
        row_idx[at : at + m] = part_idx
        idx_ego[at : at + m] = idx[owns[o]]
        visibility[at : at + m] = part_visibility
        occ_n[at : at + m] = part_occ_n
        st_n[at : at + m] = part_st_n
        occ_idxs[occ_at : occ_at + len(part_occ)] = part_occ
        st_idxs[st_at : st_at + len(part_st)] = part_st
        if with_view:
            in_view[at : at + m] = part_in_view
            status[at : at + m] = part_status
            sensor_code[at : at + m] = sensor[o]
        at += m
        occ_at += len(part_occ)
        st_at += len(part_st)
    return idx_ego, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs, in_view, status, sensor_code


def stacked(arrays: Sequence[np.ndarray], shape: tuple[int, int], dtype: type) -> np.ndarray:
    """``arrays`` (equal lengths) as the rows of one array of ``shape`` (faster than ``np.stack``)."""
    if not len(arrays):
        return np.zeros(shape, dtype=dtype)
    return np.concatenate(arrays).astype(dtype, copy=False).reshape(shape)


def frame_rows(
    observations: Sequence[Observation], owns: np.ndarray, idx: np.ndarray, sensors: np.ndarray | None = None
) -> Columns:
    """:func:`observation_rows` for all observations of one frame at once (one compiled call), in order, with an
    ``idx_ego`` column (the observer of each row) and, given ``sensors``, ``sensor``, ``in_view`` and ``status``.

    Parameters
    ----------
    observations : sequence of Observation
        What each viewpoint of the frame sees of its ``n`` objects.
    owns : ndarray of int64, shape (k,)
        Row number of each viewpoint's observing object (it gets no row; -1: none).
    idx : ndarray, shape (n,), int64
        The objects' idx.
    sensors : ndarray of int64, shape (k,), optional
        Each viewpoint's sensor code (its position in the list of sensors).
    """
    k, n = len(observations), len(idx)
    if k == 1:  # one viewpoint (the usual case): its rows as they are
        columns = observation_rows(observations[0], int(owns[0]), idx, with_view=sensors is not None)
        columns["idx_ego"] = np.full(len(columns["idx"]), idx[owns[0]] if owns[0] >= 0 else -1, dtype=np.int64)
        if sensors is not None:
            columns["sensor"] = np.full(len(columns["idx"]), sensors[0], dtype=np.int64)
        return columns
    occ = [o.occluders for o in observations]
    st = [o.static_occluders for o in observations]
    occ_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in occ], out=occ_cut[1:])
    st_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in st], out=st_cut[1:])
    extent = stacked([o.angular_extent for o in observations], (k, n), np.float64)
    with_view = sensors is not None
    if with_view:
        in_view_angle = stacked(
            [o.angular_extent if o.in_view_angle is None else o.in_view_angle for o in observations], (k, n), np.float64
        )
        in_fov_angle = stacked(
            [o.angular_extent if o.in_fov_angle is None else o.in_fov_angle for o in observations], (k, n), np.float64
        )
    else:
        in_view_angle = in_fov_angle = extent
    idx_ego, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs, in_view, status, sensor = _frame_rows(
        np.asarray(owns, dtype=np.int64),
        stacked([o.reason for o in observations], (k, n), np.int8),
        stacked([o.visible_angle for o in observations], (k, n), np.float64),
        extent,
        stacked([o.occluder_offsets for o in observations], (k, n + 1), np.int64),
        np.concatenate(occ).astype(np.int64, copy=False) if k else np.zeros(0, dtype=np.int64),
        occ_cut,
        stacked([o.static_offsets for o in observations], (k, n + 1), np.int64),
        np.concatenate(st).astype(np.int64, copy=False) if k else np.zeros(0, dtype=np.int64),
        st_cut,
        idx,
        in_view_angle,
        in_fov_angle,
        with_view,
        np.zeros(k, dtype=np.int64) if sensors is None else np.asarray(sensors, dtype=np.int64),
    )
    columns: Columns = {
        "idx_ego": idx_ego,
        "idx": row_idx,
        "visibility": visibility,
        "occluder_idxs": (occ_n, occ_idxs),
        "static_occluder_idxs": (st_n, st_idxs),
    }
    if with_view:
        columns.update({"sensor": sensor, "in_view": in_view, "status": status})
    return columns


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
    return pl.Series(pa.LargeListArray.from_arrays(pa.array(offsets, pa.int64()), pa.array(values, pa.int64())))


def to_polars(columns: Columns | None, with_ego: bool, sensor_names: Sequence[str] | None = None) -> pl.DataFrame:
    """The visibility table from :meth:`TableBuilder.arrays` output, columns in schema order; ``sensor_names``
    (when sensors were used) turns the ``sensor`` codes into names."""
    with_sensors = sensor_names is not None
    if columns is None:
        return empty_table(with_ego, with_sensors)
    target = schema(with_ego, with_sensors)
    data = {}
    for name in target:
        if name in LIST_COLUMNS:
            data[name] = _list_column(*columns[name])
        elif name == "sensor":
            data[name] = pl.Series(list(sensor_names), dtype=pl.String).gather(columns[name])
        elif name == "status":
            data[name] = pl.Series(STATUSES, dtype=pl.String).gather(columns[name]).cast(target[name])
        else:
            data[name] = pl.Series(columns[name])
    return pl.DataFrame(data).cast(target)
