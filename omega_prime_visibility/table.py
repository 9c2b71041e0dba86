"""The output table: one schema for every front end, assembled once from flat per-frame arrays."""

from __future__ import annotations

from dataclasses import dataclass, field

import numba
import numpy as np
import polars as pl
import pyarrow as pa

SCHEMA: dict[str, pl.DataType] = {
    "frame": pl.Int64(),
    "total_nanos": pl.Int64(),
    "ego_idx": pl.Int64(),
    "idx": pl.Int64(),
    "occluder_idxs": pl.List(pl.Int64()),
    "static_occluder_idxs": pl.List(pl.Int64()),
    "visibility": pl.Float64(),
}
"""Column types of the visibility table. ``ego_idx`` is present only when several observers were asked for."""


def schema(with_ego: bool) -> dict[str, pl.DataType]:
    """The table's schema, with or without the ``ego_idx`` column."""
    return {k: v for k, v in SCHEMA.items() if with_ego or k != "ego_idx"}


def empty_table(with_ego: bool = False) -> pl.DataFrame:
    """A visibility table with no rows."""
    return pl.DataFrame(schema=schema(with_ego))


@numba.njit(cache=True)
def observation_rows(p, visible, extent, occ_off, occ, st_off, st, transparent, idx):
    """Rows for every object but the observer's own (position ``p``) from one observation.

    Visibility is ``visible / extent`` clipped to [0, 1], exactly 1.0 for transparent objects (they contain the
    observer) and for objects with nothing hit before them; occluder positions become idx values, and the lists
    of transparent objects are emptied. Returns ``idx, visibility, occluder_offsets, occluder_idxs,
    static_offsets, static_idxs`` for the ``n - 1`` rows, and whether any other object contains the observer.
    """
    n = len(visible)
    rows = n - 1
    row_idx = np.empty(rows, dtype=np.int64)
    any_inside = False
    vis = np.empty(rows)
    oo = np.zeros(rows + 1, dtype=np.int64)
    so = np.zeros(rows + 1, dtype=np.int64)
    r = 0
    for i in range(n):
        if i == p:
            continue
        inside = transparent[i]
        any_inside |= inside
        row_idx[r] = idx[i]
        no = 0 if inside else occ_off[i + 1] - occ_off[i]
        ns = 0 if inside else st_off[i + 1] - st_off[i]
        oo[r + 1] = oo[r] + no
        so[r + 1] = so[r] + ns
        v = visible[i] / extent[i] if extent[i] > 0 else 0.0
        vis[r] = 1.0 if (inside or (no == 0 and ns == 0)) else min(max(v, 0.0), 1.0)
        r += 1
    oi = np.empty(oo[rows], dtype=np.int64)
    si = np.empty(so[rows], dtype=np.int64)
    r = 0
    for i in range(n):
        if i == p:
            continue
        for q in range(oo[r + 1] - oo[r]):
            oi[oo[r] + q] = idx[occ[occ_off[i] + q]]
        for q in range(so[r + 1] - so[r]):
            si[so[r] + q] = st[st_off[i] + q]
        r += 1
    return row_idx, vis, oo, oi, so, si, any_inside


def _list_column(offsets: np.ndarray, values: np.ndarray) -> pl.Series:
    arr = pa.LargeListArray.from_arrays(pa.array(offsets, pa.int64()), pa.array(values, pa.int64()))
    return pl.Series(arr)


@dataclass
class TableBuilder:
    """Collects per-(frame, observer) result blocks and builds the polars table once.

    Each block holds ``k`` rows as flat arrays; list columns arrive as offsets of shape (k + 1,) and values.
    """

    with_ego: bool = False
    _blocks: list[tuple[np.ndarray, ...]] = field(default_factory=list)
    rows: int = 0

    def add(
        self,
        frame: int,
        total_nanos: int,
        ego_idx: int,
        idx: np.ndarray,
        visibility: np.ndarray,
        occluder_offsets: np.ndarray,
        occluder_idxs: np.ndarray,
        static_offsets: np.ndarray,
        static_idxs: np.ndarray,
    ) -> None:
        k = len(idx)
        if k == 0:
            return
        self._blocks.append(
            (
                frame,
                total_nanos,
                ego_idx,
                k,
                idx,
                visibility,
                occluder_offsets,
                occluder_idxs,
                static_offsets,
                static_idxs,
            )
        )
        self.rows += k

    def arrays(self) -> tuple[np.ndarray, ...] | None:
        """Everything added so far as flat column arrays (None when empty); blocks are cleared.

        ``(frame, total_nanos, ego_idx, idx, visibility, occluder_counts, occluders, static_counts, statics)``:
        plain numpy, cheap to send between processes; :func:`to_polars` turns it into the table.
        """
        if not self._blocks:
            return None
        frame, nanos, ego, k, idx, vis, occ_off, occ, st_off, st = zip(*self._blocks, strict=True)
        self._blocks.clear()
        self.rows = 0
        k = np.asarray(k)
        cols = (
            np.repeat(np.asarray(frame, dtype=np.int64), k),
            np.repeat(np.asarray(nanos, dtype=np.int64), k),
            np.repeat(np.asarray(ego, dtype=np.int64), k),
            np.concatenate(idx).astype(np.int64, copy=False),
            np.concatenate(vis).astype(np.float64, copy=False),
            np.concatenate([np.diff(o) for o in occ_off]),
            np.concatenate(occ).astype(np.int64, copy=False),
            np.concatenate([np.diff(o) for o in st_off]),
            np.concatenate(st).astype(np.int64, copy=False),
        )
        return cols

    def build(self) -> pl.DataFrame:
        """The table of everything added so far (blocks are cleared)."""
        return to_polars(self.arrays(), self.with_ego)


def to_polars(cols: tuple[np.ndarray, ...] | None, with_ego: bool) -> pl.DataFrame:
    """The visibility table from :meth:`TableBuilder.arrays` output."""
    if cols is None:
        return empty_table(with_ego)
    frame, nanos, ego, idx, visibility, occ_n, occ, st_n, st = cols
    occ_off = np.concatenate([[0], np.cumsum(occ_n)])
    st_off = np.concatenate([[0], np.cumsum(st_n)])
    data = {
        "frame": pl.Series(frame),
        "total_nanos": pl.Series(nanos),
        "ego_idx": pl.Series(ego),
        "idx": pl.Series(idx),
        "occluder_idxs": _list_column(occ_off, occ),
        "static_occluder_idxs": _list_column(st_off, st),
        "visibility": pl.Series(visibility),
    }
    return pl.DataFrame({k: data[k] for k in schema(with_ego)}).cast(schema(with_ego))
