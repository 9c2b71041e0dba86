"""Visibility over time: the intervals in which each target was visible, and when it was first noticed.

An interval is a run of consecutive frames (frame numbers ``k, k + 1, ...``) in which the target's visibility
exceeds a threshold. A missing frame (the target, or the observer, absent in frame ``k``) ends the run: gaps are
never bridged. A target counts as *noticed* under one of two models:

- ``reaction_time=r``: once it has stayed visible ``r`` seconds within one interval (an unbroken run), as
  occlusion-aware planners model a driver's or a tracker's confirmation time: at the first frame of the run whose
  time lies ``r`` or more after the run's first frame (the elapsed time in the half-open ``[r, inf)``);
- ``notice=(d, w)``: once it has been visible for at least ``d`` seconds within the last ``w`` seconds (nuPlan's
  model with ``(1.0, 1.5)``), so a flicker of a frame or two does not start the count again. The window of a frame
  at time ``t`` is the half-open ``(t - w, t]``; each visible frame in it counts for one frame period of the table
  (the median step between its frame times); missing frames count as not visible.
"""

from __future__ import annotations

import math
import numbers

import polars as pl

from .combine import KEYS, polars_table

NANOS = 1_000_000_000

NUPLAN_NOTICE = (1.0, 1.5)
"""nuPlan's notice model: visible at least 1.0 s within any 1.5 s window (the default of the conflict analysis)."""


def visible_intervals(
    table: pl.DataFrame | pl.LazyFrame,
    threshold: float = 0.0,
    reaction_time: float | None = None,
    *,
    notice: tuple[float, float] | None = None,
) -> pl.DataFrame:
    """Intervals of visibility above ``threshold`` per (observer, target[, sensor]).

    Parameters
    ----------
    table : polars.DataFrame or LazyFrame
        Any visibility table (with or without ``idx_ego`` and ``sensor``; e.g. after
        :func:`~omega_prime_visibility.analysis.combine.seen_by_any`).
    threshold : float
        Visible means ``visibility > threshold``, a share in ``[0, 1)`` (default 0: any part visible).
    reaction_time : float, optional
        Seconds a target must stay visible without a break to count as noticed.
    notice : (float, float), optional
        ``(d, w)``: a target counts as noticed once it was visible for at least ``d`` seconds within the last ``w``
        seconds (``0 < d <= w``), e.g. ``(1.0, 1.5)``. Give ``reaction_time`` or ``notice``, not both.

    Returns
    -------
    polars.DataFrame
        One row per interval: the group columns (``[idx_ego,] idx[, sensor]``), ``start_frame``, ``end_frame``
        (the last visible frame), ``start_nanos``, ``end_nanos``, ``n_frames``, ``duration`` (seconds from the first
        to the last visible frame of the interval, 0 for a single frame), ``first_visible_nanos`` (the group's
        first visible time) and, with ``reaction_time``, ``noticed_frame`` and ``noticed_nanos`` (the first frame
        of the interval at least ``reaction_time`` after its start; null if the interval is shorter) and
        ``first_noticed_nanos`` (the group's first). With ``notice`` the same three columns hold the first frame of
        the interval at which the windowed condition holds. ``notice_model`` names the model used (e.g.
        ``"visible 0.5 s without a break"`` or ``"visible 1.0 s within 1.5 s"``). Sorted by group and start.

    Examples
    --------
    Visible in frames 0-1, hidden in 2, visible in 3-5, then frame 6 is missing and 7 visible (10 Hz):

    >>> t = pl.DataFrame({"frame": [0, 1, 2, 3, 4, 5, 7], "idx": [1] * 7,
    ...     "total_nanos": [f * 100_000_000 for f in [0, 1, 2, 3, 4, 5, 7]],
    ...     "visibility": [0.5, 1.0, 0.0, 0.2, 0.3, 1.0, 1.0]})
    >>> visible_intervals(t, reaction_time=0.2).select("start_frame", "end_frame", "duration", "noticed_frame").rows()
    [(0, 1, 0.1, None), (3, 5, 0.2, 5), (7, 7, 0.0, None)]

    Visible 0.3 s within 0.5 s: frames 0, 1 and 3 are three visible frames within frames 0 to 4, so the target is
    noticed at frame 3, across the hidden frame 2:

    >>> windowed = visible_intervals(t, notice=(0.3, 0.5))
    >>> windowed.select("start_frame", "noticed_frame").rows(), windowed["notice_model"][0]
    ([(0, None), (3, 3), (7, 7)], 'visible 0.3 s within 0.5 s')
    """
    check_threshold(threshold)
    if reaction_time is not None and not (_seconds(reaction_time) and reaction_time >= 0):
        raise ValueError(f"reaction_time must be a non-negative number of seconds or None, not {reaction_time!r}")
    if notice is not None:
        if reaction_time is not None:
            raise ValueError("give reaction_time (an unbroken run) or notice (a window), not both")
        if not (
            isinstance(notice, tuple | list)
            and len(notice) == 2
            and all(_seconds(v) for v in notice)
            and 0 < notice[0] <= notice[1]
        ):
            raise ValueError(
                f"notice takes (seconds visible, window in seconds) with 0 < seconds visible <= window, not {notice!r}"
            )
        notice = (float(notice[0]), float(notice[1]))
        if round(notice[0] * NANOS) < 1:
            raise ValueError(f"notice: {notice[0]!r} s visible is below the tables' resolution of one nanosecond")
    lazy = polars_table(table, "table")
    names = lazy.collect_schema().names()
    missing = [c for c in ("frame", "total_nanos", "idx", "visibility") if c not in names]
    if missing:
        raise ValueError(f"the visibility table lacks the column(s) {missing}")
    lazy = lazy.with_columns(pl.col("total_nanos").cast(pl.Int64))  # unsigned times would wrap in differences
    group = [k for k in KEYS if k in names and k not in ("frame", "total_nanos")]
    visible = pl.col("visibility") > threshold
    starts = visible & (~visible.shift(1).over(group).fill_null(False) | (pl.col("frame").diff().over(group) != 1))
    runs = lazy.select(*group, "frame", "total_nanos", "visibility").sort(*group, "frame")
    if notice is not None:
        runs = runs.with_columns(noticed=_windowed_notice(lazy, group, visible, notice))
    runs = runs.with_columns(run=starts.cum_sum().over(group)).filter(visible)
    aggregations = [
        pl.col("frame").first().alias("start_frame"),
        pl.col("frame").last().alias("end_frame"),
        pl.col("total_nanos").first().alias("start_nanos"),
        pl.col("total_nanos").last().alias("end_nanos"),
        pl.len().alias("n_frames"),
    ]
    if reaction_time is not None or notice is not None:
        if notice is None:
            waited = pl.col("total_nanos") - pl.col("total_nanos").first() >= round(reaction_time * NANOS)
        else:
            waited = pl.col("noticed")
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
    columns = [*group, "start_frame", "end_frame", "start_nanos", "end_nanos", "n_frames", "duration"]
    columns += ["first_visible_nanos"]
    if reaction_time is not None or notice is not None:
        model = (
            f"visible {reaction_time:g} s without a break"
            if notice is None
            else f"visible {notice[0]:g} s within {notice[1]:g} s"
        )
        out = out.with_columns(
            first_noticed_nanos=pl.col("noticed_nanos").min().over(group), notice_model=pl.lit(model)
        )
        columns += ["noticed_frame", "noticed_nanos", "first_noticed_nanos", "notice_model"]
    return out.select(columns).sort(*group, "start_frame").collect()


def check_threshold(threshold: object, name: str = "threshold") -> None:
    """Refuse a visibility threshold that is not a share in ``[0, 1)`` (visible means ``visibility > threshold``;
    1 or more would never be visible, a negative one would call a hidden target visible).

    Examples
    --------
    >>> check_threshold(0.5)
    >>> check_threshold(50)
    Traceback (most recent call last):
    ...
    ValueError: threshold must be a share of the target in [0, 1), not 50 (a percentage? 50 % is 0.5)
    """
    if not (isinstance(threshold, int | float) and not isinstance(threshold, bool) and math.isfinite(threshold)):
        raise ValueError(f"{name} must be a finite number, not {threshold!r}")
    if not 0 <= threshold < 1:
        hint = f" (a percentage? {threshold:g} % is {threshold / 100:g})" if 1 < threshold <= 100 else ""
        raise ValueError(f"{name} must be a share of the target in [0, 1), not {threshold!r}{hint}")


def frame_period(table: pl.LazyFrame) -> int:
    """The median step between a table's frame times, nanoseconds (one second for a single frame time: any period
    will do then)."""
    steps = table.select(pl.col("total_nanos").unique().sort().diff().drop_nulls()).collect().to_series()
    return int(steps.median()) if len(steps) else NANOS


def _seconds(value: object) -> bool:
    """Whether ``value`` is a finite real number (a numpy number too; not a bool)."""
    return isinstance(value, numbers.Real) and not isinstance(value, bool) and math.isfinite(value)


def _windowed_notice(lazy: pl.LazyFrame, group: list[str], visible: pl.Expr, notice: tuple[float, float]) -> pl.Expr:
    """Per row: whether the target was visible for at least ``notice[0]`` seconds within the ``notice[1]`` seconds
    up to this frame's time (each visible frame counting one frame period of the table)."""
    period = frame_period(lazy)
    needed = max(1, math.ceil(round(notice[0] * NANOS) / period - 1e-9))  # visible frames that make d seconds
    window = round(notice[1] * NANOS)
    in_window = visible.cast(pl.Int64).rolling_sum_by("total_nanos", window_size=f"{window}i", closed="right")
    return in_window.over(group) >= needed
