"""Combining views: is a target seen by *any* of several sensors, or by any of several observers?

:func:`seen_by_any` folds the rows of a visibility table that differ only in one column (``sensor``, or the
observer ``idx_ego``) into one row with the best visibility and the sorted list of those that see the target.
Works on any table of :func:`~omega_prime_visibility.get_visibility_df` (eager or lazy).
"""

from __future__ import annotations

import polars as pl

KEYS = ("frame", "total_nanos", "idx_ego", "idx", "sensor")
"""Columns that identify a row of a visibility table (those present)."""


def polars_table(value: object, name: str) -> pl.LazyFrame:
    """``value`` (a polars DataFrame or LazyFrame) as a LazyFrame; anything else is refused naming ``name``.

    >>> polars_table({"idx": [1]}, "table")
    Traceback (most recent call last):
    ...
    TypeError: table must be a polars DataFrame or LazyFrame (as get_visibility_df returns), not dict
    """
    if isinstance(value, pl.DataFrame | pl.LazyFrame):
        return value.lazy()
    module = type(value).__module__.split(".")[0]
    kind = type(value).__name__ if module == "builtins" else f"{module}.{type(value).__name__}"
    hint = "; convert it with polars.from_pandas" if type(value).__module__.startswith("pandas") else ""
    raise TypeError(f"{name} must be a polars DataFrame or LazyFrame (as get_visibility_df returns), not {kind}{hint}")


def every_listed(column: str) -> pl.Expr:
    """In a ``group_by(...).agg``: every idx that a list column (``occluder_idxs``, ``static_occluder_idxs``) holds
    in the group's rows, once each, ascending.

    >>> t = pl.DataFrame({"idx": [1, 1], "occluder_idxs": [[4, 2], [2]]})
    >>> t.group_by("idx").agg(every_listed("occluder_idxs")).row(0)
    (1, [2, 4])
    """
    return pl.col(column).list.explode(keep_nulls=False, empty_as_null=False).unique().sort()


def seen_by_any(table: pl.DataFrame | pl.LazyFrame, over: str = "sensor") -> pl.DataFrame | pl.LazyFrame:
    """One row per target and remaining key, combined over the values of ``over``.

    Parameters
    ----------
    table : polars.DataFrame or LazyFrame
        A visibility table with the column ``over``.
    over : {"sensor", "idx_ego"}
        Combine over the sensors of each observer, or over the observers (e.g. infrastructure sensors or
        cooperative perception: "is this pedestrian seen by any vehicle?"). To combine over both, call it twice,
        first over ``"sensor"``.

    Returns
    -------
    polars.DataFrame or LazyFrame (as given)
        The remaining key columns (``frame, total_nanos, [idx_ego], idx, [sensor]``), then ``visibility`` (the
        best over ``over``), ``best_<over>`` (whose view that is; ties go to the first in sort order),
        ``seen_by`` (sorted values of ``over`` with visibility > 0, empty when nobody sees it), and ``in_view``
        (the best) when the table has it. Sorted by the key columns.

    Examples
    --------
    >>> t = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [5, 5, 5],
    ...     "sensor": ["radar", "camera", "lidar"], "visibility": [0.0, 0.25, 0.5]})
    >>> seen_by_any(t).select("idx", "visibility", "best_sensor", "seen_by").rows()
    [(5, 0.5, 'lidar', ['camera', 'lidar'])]
    """
    lazy = polars_table(table, "table")
    names = lazy.collect_schema().names()
    if over not in ("sensor", "idx_ego"):
        raise ValueError(f"over must be 'sensor' or 'idx_ego', not {over!r}")
    if over not in names:
        raise ValueError(f"the table has no {over!r} column to combine over (columns: {names})")
    keys = [k for k in KEYS if k in names and k != over]
    aggregations = [
        pl.col("visibility").max(),
        pl.col(over)
        .sort_by([pl.col("visibility"), pl.col(over)], descending=[True, False])
        .first()
        .alias(f"best_{over}"),
        pl.col(over).filter(pl.col("visibility") > 0).sort().alias("seen_by"),
    ]
    if "in_view" in names:
        aggregations.append(pl.col("in_view").max())
    out = lazy.group_by(keys).agg(aggregations).sort(keys)
    return out.collect() if isinstance(table, pl.DataFrame) else out
