"""Visibility over time: the intervals in which each target was visible, and when it was first noticed.

An interval is a run of consecutive frames (frame numbers ``k, k + 1, ...``) in which the target's visibility
exceeds a threshold. A missing frame (the target, or the observer, absent in frame ``k``) ends the run: gaps are
never bridged. With a reaction time, a target counts as *noticed* once it has stayed visible that long within
one interval, as occlusion-aware planners model a driver's or a tracker's confirmation time.
"""

from __future__ import annotations

import math

import polars as pl

from .combine import KEYS

NANOS = 1_000_000_000


def visible_intervals(
    table: pl.DataFrame | pl.LazyFrame, threshold: float = 0.0, reaction_time: float | None = None
) -> pl.DataFrame:
    """Intervals of visibility above ``threshold`` per (observer, target[, sensor]).

    Parameters
    ----------
    table : polars.DataFrame or LazyFrame
        Any visibility table (with or without ``idx_ego`` and ``sensor``; e.g. after
        :func:`~omega_prime_visibility.analysis.combine.seen_by_any`).
    threshold : float
        Visible means ``visibility > threshold`` (default: any part visible).
    reaction_time : float, optional
        Seconds a target must stay visible to count as noticed.

    Returns
    -------
    polars.DataFrame
        One row per interval: the group columns (``[idx_ego,] idx[, sensor]``), ``start_frame``, ``end_frame``
        (the last visible frame), ``start_nanos``, ``end_nanos``, ``n_frames``, ``duration`` (seconds from the first
        to the last visible frame of the interval, 0 for a single frame), ``first_visible_nanos`` (the group's
        first visible time) and, with ``reaction_time``, ``noticed_frame`` and ``noticed_nanos`` (the first frame
        of the interval at least ``reaction_time`` after its start; null if the interval is shorter) and
        ``first_noticed_nanos`` (the group's first). Sorted by group and start.

    Examples
    --------
    Visible in frames 0-1, hidden in 2, visible in 3-5, then frame 6 is missing and 7 visible (10 Hz):

    >>> t = pl.DataFrame({"frame": [0, 1, 2, 3, 4, 5, 7], "idx": [1] * 7,
    ...     "total_nanos": [f * 100_000_000 for f in [0, 1, 2, 3, 4, 5, 7]],
    ...     "visibility": [0.5, 1.0, 0.0, 0.2, 0.3, 1.0, 1.0]})
    >>> visible_intervals(t, reaction_time=0.2).select("start_frame", "end_frame", "duration", "noticed_frame").rows()
    [(0, 1, 0.1, None), (3, 5, 0.2, 5), (7, 7, 0.0, None)]
    """
    if not (isinstance(threshold, int | float) and math.isfinite(threshold)):
        raise ValueError(f"threshold must be a finite number, not {threshold!r}")
    if reaction_time is not None and not (
        isinstance(reaction_time, int | float) and math.isfinite(reaction_time) and reaction_time >= 0
    ):
        raise ValueError(f"reaction_time must be a non-negative number of seconds or None, not {reaction_time!r}")
    lazy = table.lazy()
    names = lazy.collect_schema().names()
    missing = [c for c in ("frame", "total_nanos", "idx", "visibility") if c not in names]
    if missing:
        raise ValueError(f"the visibility table lacks the column(s) {missing}")
    group = [k for k in KEYS if k in names and k not in ("frame", "total_nanos")]
    visible = pl.col("visibility") > threshold
    starts = visible & (~visible.shift(1).over(group).fill_null(False) | (pl.col("frame").diff().over(group) != 1))
    runs = (
        lazy.select(*group, "frame", "total_nanos", "visibility")
        .sort(*group, "frame")
        .with_columns(run=starts.cum_sum().over(group))
        .filter(visible)
    )
    aggregations = [
        pl.col("frame").first().alias("start_frame"),
        pl.col("frame").last().alias("end_frame"),
        pl.col("total_nanos").first().alias("start_nanos"),
        pl.col("total_nanos").last().alias("end_nanos"),
        pl.len().alias("n_frames"),
    ]
    if reaction_time is not None:
        waited = pl.col("total_nanos") - pl.col("total_nanos").first() >= round(reaction_time * NANOS)
        aggregations += [
            pl.col("frame").filter(waited).first().alias("noticed_frame"),
            pl.col("total_nanos").filter(waited).first().alias("noticed_nanos"),
        ]
    out = (
        runs.group_by(*group, "run")
        .agg(aggregations)
        .with_columns(duration=(pl.col("end_nanos") - pl.col("start_nanos")) / NANOS)
        .with_columns(first_visible_nanos=pl.col("start_nanos").min().over(group))
    )
    if reaction_time is not None:
        out = out.with_columns(first_noticed_nanos=pl.col("noticed_nanos").min().over(group))
    columns = [*group, "start_frame", "end_frame", "start_nanos", "end_nanos", "n_frames", "duration"]
    columns += ["first_visible_nanos"]
    if reaction_time is not None:
        columns += ["noticed_frame", "noticed_nanos", "first_noticed_nanos"]
    return out.select(columns).sort(*group, "start_frame").collect()
