"""The output table: one schema for every front end, assembled once from flat per-frame arrays."""

from __future__ import annotations

from dataclasses import dataclass, field

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
                np.full(k, frame, dtype=np.int64),
                np.full(k, total_nanos, dtype=np.int64),
                np.full(k, ego_idx, dtype=np.int64),
                np.asarray(idx, dtype=np.int64),
                np.asarray(visibility, dtype=np.float64),
                np.diff(occluder_offsets),
                np.asarray(occluder_idxs, dtype=np.int64),
                np.diff(static_offsets),
                np.asarray(static_idxs, dtype=np.int64),
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
        cols = tuple(np.concatenate(c) for c in zip(*self._blocks, strict=True))
        self._blocks.clear()
        self.rows = 0
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
