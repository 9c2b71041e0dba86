"""Row assembly: what the engines observed, as the table's named flat column arrays (:mod:`.table` says what
they mean), one compiled call per frame (:func:`frame_rows`) or per chunk of frames (:func:`chunk_rows`).

List columns come out as ``(lengths, values)`` pairs; occluder row numbers become ``idx`` values here.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .._compiled.kernel import njit
from ..engines import ChunkObservation, ChunkViewpoints, Observation, Reason
from .schema import Columns, missing_counts, view_of, visibility_of

_CONTAINS_OBSERVER = int(Reason.CONTAINS_OBSERVER)


@njit(cache=True)
def _rows_into(
    out, at, own, reason, visible_angle, angular_extent, occluder_offsets, occluders, static_offsets, statics, idx,
    in_view_angle, in_fov_angle, with_view,
):  # fmt: skip
    """Write the rows of every object but the observer's own (row number ``own``; see :func:`observation_rows`)
    into the arrays ``out`` from the positions ``at`` (rows, occluder entries, static entries), which move on."""
    row_idx, visibility, occluder_counts, occluder_idxs, static_counts, static_idxs, in_view, status = out
    row, occluder_at, static_at = at[0], at[1], at[2]
    for i in range(len(reason)):
        if i == own:
            continue
        row_idx[row] = idx[i]
        if with_view:
            visibility[row], in_view[row], status[row] = view_of(
                reason[i], visible_angle[i], angular_extent[i], in_view_angle[i], in_fov_angle[i]
            )
        else:
            visibility[row] = visibility_of(reason[i], visible_angle[i], angular_extent[i])
        occluder_counts[row] = 0
        static_counts[row] = 0
        if reason[i] != _CONTAINS_OBSERVER:  # a transparent target lists no occluders
            occluder_counts[row] = occluder_offsets[i + 1] - occluder_offsets[i]
            static_counts[row] = static_offsets[i + 1] - static_offsets[i]
        for q in range(occluder_counts[row]):
            occluder_idxs[occluder_at + q] = idx[occluders[occluder_offsets[i] + q]]
        for q in range(static_counts[row]):
            static_idxs[static_at + q] = statics[static_offsets[i] + q]
        occluder_at += occluder_counts[row]
        static_at += static_counts[row]
        row += 1
    at[0], at[1], at[2] = row, occluder_at, static_at


@njit(cache=True)
def _row_arrays(n_rows, n_occluders, n_statics, with_view):
    """Room for ``n_rows`` rows and their occluder entries (the tuple :func:`_rows_into` writes into)."""
    return (
        np.empty(n_rows, dtype=np.int64),
        np.empty(n_rows),
        np.empty(n_rows, dtype=np.int64),
        np.empty(n_occluders, dtype=np.int64),
        np.empty(n_rows, dtype=np.int64),
        np.empty(n_statics, dtype=np.int64),
        np.empty(n_rows if with_view else 0),
        np.empty(n_rows if with_view else 0, dtype=np.int8),
    )


@njit(cache=True)
def _cut(out, at, with_view):
    """The arrays of :func:`_row_arrays` cut to what :func:`_rows_into` wrote."""
    rows, n_occ, n_st = at[0], at[1], at[2]
    return (
        out[0][:rows], out[1][:rows], out[2][:rows], out[3][:n_occ], out[4][:rows], out[5][:n_st],
        out[6][: rows if with_view else 0], out[7][: rows if with_view else 0],
    )  # fmt: skip


@njit(cache=True)
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
    out = _row_arrays(len(reason), occluder_offsets[-1] - occluder_offsets[0], static_offsets[-1] - static_offsets[0],
                      with_view)  # fmt: skip
    at = np.zeros(3, dtype=np.int64)
    _rows_into(out, at, own, reason, visible_angle, angular_extent, occluder_offsets, occluders, static_offsets,
               statics, idx, in_view_angle, in_fov_angle, with_view)  # fmt: skip
    return _cut(out, at, with_view)


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


@njit(cache=True)
def _chunk_rows(
    targets,
    own,
    first_row,
    idx,
    visible_angle,
    angular_extent,
    reason,
    occ_offsets,
    occ,
    st_offsets,
    st,
    in_view_angle,
    in_fov_angle,
    with_view,
):
    """:func:`_rows` for each of ``k`` viewpoints whose targets are ``targets[o]:targets[o + 1]`` of the flat
    per-target arrays (occluder lists as CSR over all targets, see :class:`..engines.ChunkObservation`), the
    objects of viewpoint ``o``'s frame being ``idx[first_row[o]:]``; the rows of all of them in order and their
    number per viewpoint."""
    k = len(own)
    counts = np.zeros(k, dtype=np.int64)
    # room for every target's row and every listed occluder (the observers' own rows are left out as they come)
    out = _row_arrays(targets[k] - targets[0], len(occ), len(st), with_view)
    at = np.zeros(3, dtype=np.int64)
    for o in range(k):
        t0, t1 = targets[o], targets[o + 1]
        before = at[0]
        _rows_into(
            out, at, own[o], reason[t0:t1], visible_angle[t0:t1], angular_extent[t0:t1], occ_offsets[t0 : t1 + 1],
            occ, st_offsets[t0 : t1 + 1], st, idx[first_row[o] : first_row[o] + t1 - t0], in_view_angle[t0:t1],
            in_fov_angle[t0:t1], with_view,
        )  # fmt: skip
        counts[o] = at[0] - before
    row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs, in_view, status = _cut(out, at, with_view)
    return counts, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs, in_view, status


def chunk_rows(
    observation: ChunkObservation,
    viewpoints: ChunkViewpoints,
    owners: np.ndarray,
    idx: np.ndarray,
    frame: np.ndarray,
    total_nanos: np.ndarray,
    sensors: np.ndarray | None = None,
) -> Columns | None:
    """The table's columns for a whole chunk of viewpoints that see all around without range, in one compiled
    call: what :class:`TableBuilder` collects from :func:`frame_rows` frame by frame (None when there are no rows).

    Parameters
    ----------
    observation, viewpoints
        From :meth:`..engines.sweep.SweepEngine.observe_chunk` and :func:`..pipeline.chunk_viewpoints`.
    owners : ndarray of int64, shape (v,)
        Each viewpoint's observer, as a row number of the chunk.
    idx, frame, total_nanos : ndarray of int64
        Per row of the chunk.
    sensors : ndarray of int64, shape (v,), optional
        Each viewpoint's sensor code.
    """
    first_row = owners - viewpoints.own
    counts, row_idx, visibility, occ_n, occ, st_n, st, in_view, status = _chunk_rows(
        viewpoints.target_offsets,
        viewpoints.own,
        first_row,
        idx,
        observation.visible_angle,
        observation.angular_extent,
        observation.reason,
        observation.occluder_offsets,
        observation.occluders,
        observation.static_offsets,
        observation.static_occluders,
        observation.angular_extent,  # all in view, all in the field of view
        observation.angular_extent,
        sensors is not None,
    )
    if not len(row_idx):
        return None
    columns: Columns = {
        "frame": np.repeat(frame[owners], counts),
        "total_nanos": np.repeat(total_nanos[owners], counts),
        "idx_ego": np.repeat(idx[owners], counts),
        "idx": row_idx,
        "visibility": visibility,
        "occluder_idxs": (occ_n, occ),
        "static_occluder_idxs": (st_n, st),
    }
    if sensors is not None:
        columns.update({"sensor": np.repeat(sensors, counts), "in_view": in_view, "status": status})
    return columns


def stacked(arrays: Sequence[np.ndarray], shape: tuple[int, int], dtype: type) -> np.ndarray:
    """``arrays`` (equal lengths) as the rows of one array of ``shape`` (faster than ``np.stack``)."""
    if not len(arrays):
        return np.zeros(shape, dtype=dtype)
    return np.concatenate(arrays).astype(dtype, copy=False).reshape(shape)


def _flat_offsets(offsets: Sequence[np.ndarray], cut: np.ndarray, n: int) -> np.ndarray:
    """Per-observation CSR offsets (each shape (n + 1,)) into lists concatenated at ``cut`` (shape (k + 1,)), as
    one CSR over all ``k * n`` targets, shape (k * n + 1,)."""
    k = len(offsets)
    flat = np.empty(k * n + 1, dtype=np.int64)
    flat[:-1] = (stacked(offsets, (k, n + 1), np.int64)[:, :n] + cut[:k, None]).ravel()
    flat[-1] = cut[k]
    return flat


def count_rows(observations: Sequence[Observation], owns: np.ndarray, n: int, counted: Sequence[str]) -> Columns:
    """The ``counted`` columns (:data:`.schema.COUNT_SCHEMA`) of the rows of ``observations`` (each of ``n``
    objects, the observer ``owns[k]`` left out), null where an observation does not count them."""
    keep = [np.flatnonzero(np.arange(n) != own) for own in np.asarray(owns).tolist()]
    out: Columns = {}
    for name in counted:
        parts = [
            o.counts[name][rows] if o.counts is not None and name in o.counts else missing_counts(name, len(rows))
            for o, rows in zip(observations, keep, strict=True)
        ]
        out[name] = np.concatenate(parts) if parts else missing_counts(name, 0)
    return out


def frame_rows(
    observations: Sequence[Observation],
    owns: np.ndarray,
    idx: np.ndarray,
    sensors: np.ndarray | None = None,
    counted: Sequence[str] = (),
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
    counted : sequence of str
        The count columns to add (:func:`count_rows`).
    """
    k, n = len(observations), len(idx)
    if k == 1:  # one viewpoint (the usual case): its rows as they are
        columns = observation_rows(observations[0], int(owns[0]), idx, with_view=sensors is not None)
        columns["idx_ego"] = np.full(len(columns["idx"]), idx[owns[0]] if owns[0] >= 0 else -1, dtype=np.int64)
        if sensors is not None:
            columns["sensor"] = np.full(len(columns["idx"]), sensors[0], dtype=np.int64)
        columns.update(count_rows(observations, owns, n, counted))
        return columns
    occ = [o.occluders for o in observations]
    st = [o.static_occluders for o in observations]
    occ_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in occ], out=occ_cut[1:])
    st_cut = np.zeros(k + 1, dtype=np.int64)
    np.cumsum([len(a) for a in st], out=st_cut[1:])
    with_view = sensors is not None
    extent = stacked([o.angular_extent for o in observations], (k, n), np.float64).ravel()
    in_view_angle = in_fov_angle = extent
    if with_view:
        in_view_angle = stacked(
            [o.angular_extent if o.in_view_angle is None else o.in_view_angle for o in observations], (k, n), np.float64
        ).ravel()
        in_fov_angle = stacked(
            [o.angular_extent if o.in_fov_angle is None else o.in_fov_angle for o in observations], (k, n), np.float64
        ).ravel()
    owns = np.asarray(owns, dtype=np.int64)
    # the frame's observations as flat arrays over its k * n targets, occluder lists as CSR over all of them
    counts, row_idx, visibility, occ_n, occ_idxs, st_n, st_idxs, in_view, status = _chunk_rows(
        np.arange(k + 1, dtype=np.int64) * n,
        owns,
        np.zeros(k, dtype=np.int64),
        idx,
        stacked([o.visible_angle for o in observations], (k, n), np.float64).ravel(),
        extent,
        stacked([o.reason for o in observations], (k, n), np.int8).ravel(),
        _flat_offsets([o.occluder_offsets for o in observations], occ_cut, n),
        np.concatenate(occ).astype(np.int64, copy=False),
        _flat_offsets([o.static_offsets for o in observations], st_cut, n),
        np.concatenate(st).astype(np.int64, copy=False),
        in_view_angle,
        in_fov_angle,
        with_view,
    )
    columns: Columns = {
        "idx_ego": np.repeat(idx[owns], counts),
        "idx": row_idx,
        "visibility": visibility,
        "occluder_idxs": (occ_n, occ_idxs),
        "static_occluder_idxs": (st_n, st_idxs),
    }
    if with_view:
        columns.update({"sensor": np.repeat(np.asarray(sensors, dtype=np.int64), counts), "in_view": in_view})
        columns["status"] = status
    columns.update(count_rows(observations, owns, n, counted))
    return columns
