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

LIST_COLUMNS = tuple(name for name, dtype in SCHEMA.items() if isinstance(dtype, pl.List))
"""List columns travel as ``(lengths, values)`` pairs of flat arrays."""

Columns = dict[str, np.ndarray | tuple[np.ndarray, np.ndarray]]

_CONTAINS_OBSERVER = int(Reason.CONTAINS_OBSERVER)
_IN_VIEW = int(Reason.IN_VIEW)


def schema(with_ego: bool) -> dict[str, pl.DataType]:
    """The table's schema, with or without the ``idx_ego`` column."""
    return {k: v for k, v in SCHEMA.items() if with_ego or k != "idx_ego"}


def empty_table(with_ego: bool = False) -> pl.DataFrame:
    """A visibility table with no rows."""
    return pl.DataFrame(schema=schema(with_ego))


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
def _rows(own, reason, visible_angle, angular_extent, occluder_offsets, occluders, static_offsets, statics, idx):
    """Rows for every object but the observer's own (row number ``own``), see :func:`observation_rows`."""
    n = len(reason)
    n_rows = n - 1 if 0 <= own < n else n
    row_idx = np.empty(n_rows, dtype=np.int64)
    visibility = np.empty(n_rows)
    occluder_counts = np.zeros(n_rows, dtype=np.int64)
    static_counts = np.zeros(n_rows, dtype=np.int64)
    row = 0
    for i in range(n):
        if i == own:
            continue
        row_idx[row] = idx[i]
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
    return row_idx, visibility, occluder_counts, occluder_idxs, static_counts, static_idxs


def observation_rows(observation: Observation, own: int, idx: np.ndarray) -> Columns:
    """The table's target columns for one observation: ``idx``, ``visibility`` and the occluder lists.

    Parameters
    ----------
    observation : Observation
        What one viewpoint sees of the ``n`` objects of a frame.
    own : int
        Row number of the observing object, which gets no row (-1: none).
    idx : ndarray, shape (n,), int64
        The objects' idx; occluder row numbers become idx values.
    """
    row_idx, visibility, occ_n, occ, st_n, st = _rows(
        own,
        observation.reason,
        observation.visible_angle,
        observation.angular_extent,
        observation.occluder_offsets,
        observation.occluders,
        observation.static_offsets,
        observation.static_occluders,
        idx,
    )
    return {"idx": row_idx, "visibility": visibility, "occluder_idxs": (occ_n, occ), "static_occluder_idxs": (st_n, st)}


@numba.njit(cache=True)
def _frame_rows(owns, reason, visible_angle, angular_extent, occ_offsets, occ, occ_cut, st_offsets, st, st_cut, idx):
    """:func:`_rows` for the ``k`` observations of one frame, given stacked (``(k, n)``, ``(k, n + 1)``) and
    concatenated (cut at ``occ_cut``, ``st_cut``) arrays; the rows of all of them in order, and ``idx_ego``."""
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
    at = 0
    occ_at = 0
    st_at = 0
    for o in range(len(owns)):
        part_idx, part_visibility, part_occ_n, part_occ, part_st_n, part_st = parts[o]
        m = len(part_idx)
        row_idx[at : at + m] = part_idx
        idx_ego[at : at + m] = idx[owns[o]]
        visibility[at : at + m] = part_visibility
        occ_n[at : at + m] = part_occ_n
        st_n[at : at + m] = part_st_n
        occ_idxs[occ_at : occ_at + len(part_occ)] = part_occ
        st_idxs[st_at : st_at + len(part_st)] = part_st
        at += m
        occ_at += len(part_occ)
        st_at += len(part_st)
    return idx_ego, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs


def stacked(arrays: Sequence[np.ndarray], shape: tuple[int, int], dtype: type) -> np.ndarray:
    """``arrays`` (equal lengths) as the rows of one array of ``shape`` (faster than ``np.stack``)."""
    if not len(arrays):
        return np.zeros(shape, dtype=dtype)
    return np.concatenate(arrays).astype(dtype, copy=False).reshape(shape)


def frame_rows(observations: Sequence[Observation], owns: np.ndarray, idx: np.ndarray) -> Columns:
    """:func:`observation_rows` for all observations of one frame at once (one compiled call), in order, with an
    ``idx_ego`` column (the observer of each row).

    Parameters
    ----------
    observations : sequence of Observation
        What each viewpoint of the frame sees of its ``n`` objects.
    owns : ndarray of int64, shape (k,)
        Row number of each viewpoint's observing object (it gets no row; -1: none).
    idx : ndarray, shape (n,), int64
        The objects' idx.
    """
    k, n = len(observations), len(idx)
    if k == 1:  # one observer (the usual case): its rows as they are
        columns = observation_rows(observations[0], int(owns[0]), idx)
        columns["idx_ego"] = np.full(len(columns["idx"]), idx[owns[0]] if owns[0] >= 0 else -1, dtype=np.int64)
        return columns
    occ = [o.occluders for o in observations]
    st = [o.static_occluders for o in observations]
    occ_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in occ], out=occ_cut[1:])
    st_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in st], out=st_cut[1:])
    idx_ego, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs = _frame_rows(
        np.asarray(owns, dtype=np.int64),
        stacked([o.reason for o in observations], (k, n), np.int8),
        stacked([o.visible_angle for o in observations], (k, n), np.float64),
        stacked([o.angular_extent for o in observations], (k, n), np.float64),
        stacked([o.occluder_offsets for o in observations], (k, n + 1), np.int64),
        np.concatenate(occ).astype(np.int64, copy=False) if k else np.zeros(0, dtype=np.int64),
        occ_cut,
        stacked([o.static_offsets for o in observations], (k, n + 1), np.int64),
        np.concatenate(st).astype(np.int64, copy=False) if k else np.zeros(0, dtype=np.int64),
        st_cut,
        idx,
    )
    return {
        "idx_ego": idx_ego,
        "idx": row_idx,
        "visibility": visibility,
        "occluder_idxs": (occ_n, occ_idxs),
        "static_occluder_idxs": (st_n, st_idxs),
    }


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


def to_polars(columns: Columns | None, with_ego: bool) -> pl.DataFrame:
    """The visibility table from :meth:`TableBuilder.arrays` output, columns in schema order."""
    if columns is None:
        return empty_table(with_ego)
    target = schema(with_ego)
    data = {name: _list_column(*columns[name]) if name in LIST_COLUMNS else pl.Series(columns[name]) for name in target}
    return pl.DataFrame(data).cast(target)
