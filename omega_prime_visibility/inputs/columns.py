"""The moving-object table's columns: which must be there, and that they hold what they are named for (whole
frame numbers, object ids and times; numbers for positions and sizes; times that go with frames)."""

from __future__ import annotations

import warnings

import numpy as np
import polars as pl

from .objects import VisibilityInputWarning

REQUIRED_COLUMNS = ("frame", "total_nanos", "idx", "x", "y")
BOX_COLUMNS = ("length", "width", "yaw")


def check_columns(df: pl.DataFrame) -> bool:
    """Raise on missing columns; return whether outlines come from the ``polygon`` column."""
    missing = [c for c in REQUIRED_COLUMNS if c not in df.columns]
    if missing:
        raise ValueError(
            f"the moving-object table lacks the column(s) {missing}; it needs {list(REQUIRED_COLUMNS)} "
            f"and either 'polygon' or {list(BOX_COLUMNS)} (columns present: {df.columns})"
        )
    use_polygon = "polygon" in df.columns and df["polygon"].dtype == pl.Object
    if not use_polygon and any(c not in df.columns for c in BOX_COLUMNS):
        raise ValueError(
            f"the moving-object table has no 'polygon' column of shapely polygons and lacks "
            f"{[c for c in BOX_COLUMNS if c not in df.columns]} to build box outlines"
        )
    return use_polygon


MAX_COORDINATE = 1e9
"""Metres: positions and outline vertices beyond this are refused (UTM coordinates stay below 1e7 m; far beyond
it, the engines' tolerances lose the cars)."""

WHOLE = {"frame": "frame numbers", "idx": "object ids", "total_nanos": "times in nanoseconds"}


def whole_numbers(df: pl.DataFrame, name: str) -> np.ndarray:
    """Column ``name`` (``frame``, ``idx`` or ``total_nanos``, no nulls) as int64, refusing what is no whole
    number rather than cutting it (frame 0.5 is not frame 0)."""
    column = df[name]
    what = WHOLE[name]
    if column.dtype.is_integer():
        if column.dtype == pl.UInt64 and len(column) and column.max() > np.iinfo(np.int64).max:
            raise ValueError(f"column {name!r} holds {column.max()}, beyond the largest int64 ({what})")
        return column.cast(pl.Int64).to_numpy()
    if column.dtype.is_float():
        values = column.to_numpy()
        bad = ~np.isfinite(values) | (np.abs(values) >= 2.0**63)
        bad[~bad] = values[~bad] != np.round(values[~bad])
        if bad.any():
            k = int(np.flatnonzero(bad)[0])
            raise ValueError(f"column {name!r} must hold whole numbers ({what}), not {float(values[k])!r} (row {k})")
        return values.astype(np.int64)
    example = column.drop_nulls().head(1).to_list()
    raise ValueError(
        f"column {name!r} must hold whole numbers ({what}), not {column.dtype} values"
        + (f" such as {example[0]!r}" if example else "")
    )


def float_columns(df: pl.DataFrame, names: tuple[str, ...]) -> dict[str, np.ndarray]:
    """The columns ``names`` that ``df`` has, as float64 arrays with NaN for nulls (float64 columns without
    nulls as they are: no polars call)."""
    out = {}
    for name in dict.fromkeys(names):
        if name in df.columns:
            column = df[name]
            if not (column.dtype.is_numeric() or column.dtype == pl.Null):
                raise ValueError(f"column {name!r} must hold numbers (metres, radians), not {column.dtype} values")
            if column.dtype != pl.Float64 or column.null_count():
                column = column.cast(pl.Float64).fill_null(np.nan)
            out[name] = column.to_numpy()
    return out


def check_times(frame: np.ndarray, total_nanos: np.ndarray, frame_starts: np.ndarray) -> None:
    """Warn when times do not go with frames (one time per frame, later frames later): durations and notice
    times (``visible_intervals``) rest on them."""
    if len(frame) == 0:
        return
    first = total_nanos[frame_starts[:-1]]
    spread = np.maximum.reduceat(total_nanos, frame_starts[:-1]) - np.minimum.reduceat(total_nanos, frame_starts[:-1])
    problems = []
    if (spread > 0).any():
        k = int(np.flatnonzero(spread > 0)[0])
        problems.append(f"{int((spread > 0).sum())} frame(s) hold rows of different total_nanos (first: frame "
                        f"{frame[frame_starts[k]]})")  # fmt: skip
    late = np.flatnonzero(np.diff(first) <= 0)
    if len(late):
        a, b = frame[frame_starts[late[0]]], frame[frame_starts[late[0] + 1]]
        problems.append(f"total_nanos does not increase from frame {a} to frame {b} ({len(late)} such step(s))")
    if problems:
        warnings.warn(
            "; ".join(problems) + ": durations and notice times computed from them will be wrong",
            VisibilityInputWarning,
            stacklevel=4,
        )
