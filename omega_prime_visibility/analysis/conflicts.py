"""Occluded conflicts: road users whose path crosses the ego's, and whether they could be seen in time.

Where paths cross comes from omega-prime's ``timegaps`` metric: for each ego time, the other object that occupies the
place the ego occupies then, closest in time, and the time gap (the target's time minus the ego's, seconds; negative
when the target was there first). A pair *conflicts* when the gap is within a post-encroachment time (PET, default 3
s): ``|timegap|`` in ``[0, pet)``; the conflict is the pair's row with the least gap, and its time,
``conflict_nanos``, is when the first of the two reaches the shared place. Before it, from the visibility table: when
the target was first visible and first noticed (a notice model of :func:`~.intervals.visible_intervals`), how much
time that left, how far away it was, and whether and how long it was hidden in a look-back window (default 5 s), and
by whom.

Every time window is half-open, and each frame stands for one frame period from its time on:

- sight and notice count the frames at or before the conflict (a target first seen at the conflict's time has
  0 s left);
- the look-back window holds the frames at times in ``[conflict - look_back, conflict)``: the frame at the
  conflict's own time is not before it, so ``hidden_seconds`` (hidden frames times the frame period) is never more
  than ``look_back``;
- the notice models' windows are those of :func:`~.intervals.visible_intervals`.
"""

from __future__ import annotations

import math

import polars as pl

from .combine import every_listed, polars_table
from .intervals import NANOS, NUPLAN_NOTICE, frame_period, visible_intervals

LONGEST = 2**62
"""The longest look-back window, nanoseconds (146 years: any longer one is the same window, and polars would take
its literal for a 128-bit integer)."""

CONFLICT_COLUMNS = ("idx_ego", "idx", "timegap", "ego_nanos", "target_nanos", "conflict_nanos")


def path_conflicts(timegaps: pl.DataFrame | pl.LazyFrame, pet: float = 3.0) -> pl.DataFrame:
    """One conflict per (ego, target) whose paths cross within ``pet`` seconds.

    Parameters
    ----------
    timegaps : polars.DataFrame or LazyFrame
        omega-prime's ``timegaps`` property (``idx_ego, idx, total_nanos_ego, timegap, total_nanos``), computed with
        a ``time_buffer`` of at least ``pet`` seconds (its default is 2 s).
    pet : float
        Post-encroachment time, seconds: a pair conflicts when ``|timegap| < pet`` (the half-open ``[0, pet)``).

    Returns
    -------
    polars.DataFrame
        ``idx_ego, idx, timegap`` (seconds; negative: the target reached the place first), ``ego_nanos`` and
        ``target_nanos`` (when each occupies it), ``conflict_nanos`` (the earlier of the two), sorted by pair.

    Examples
    --------
    >>> tg = pl.DataFrame({"idx_ego": [0, 0, 0], "idx": [7, 7, 8], "total_nanos_ego": [10, 20, 30],
    ...     "timegap": [-2.5, 1.5, 4.0], "total_nanos": [0, 1_500_000_020, 4_000_000_030]})
    >>> path_conflicts(tg).rows()
    [(0, 7, 1.5, 20, 1500000020, 20)]
    """
    if not (isinstance(pet, int | float) and math.isfinite(pet) and pet >= 0):
        raise ValueError(f"pet must be a non-negative number of seconds, not {pet!r}")
    lazy = polars_table(timegaps, "timegaps")
    missing = [
        c for c in ("idx_ego", "idx", "total_nanos_ego", "timegap", "total_nanos") if c not in lazy.collect_schema()
    ]
    if missing:
        raise ValueError(f"the timegaps table (omega-prime's timegaps property) lacks the column(s) {missing}")
    return (
        lazy.filter(pl.col("timegap").abs() < pet)
        .sort("idx_ego", "idx", pl.col("timegap").abs(), "total_nanos_ego")
        .group_by("idx_ego", "idx", maintain_order=True)
        .first()
        .select(
            "idx_ego",
            "idx",
            "timegap",
            pl.col("total_nanos_ego").cast(pl.Int64).alias("ego_nanos"),  # unsigned times would wrap below
            pl.col("total_nanos").cast(pl.Int64).alias("target_nanos"),
            pl.min_horizontal("total_nanos_ego", "total_nanos").cast(pl.Int64).alias("conflict_nanos"),
        )
        .collect()
    )


def occluded_conflicts(
    visibility: pl.DataFrame | pl.LazyFrame,
    timegaps: pl.DataFrame | pl.LazyFrame,
    objects: pl.DataFrame | pl.LazyFrame | None = None,
    *,
    ego_idx: int | None = None,
    pet: float = 3.0,
    look_back: float = 5.0,
    threshold: float = 0.0,
    reaction_time: float | None = None,
    notice: tuple[float, float] | None = NUPLAN_NOTICE,
) -> pl.DataFrame:
    """For each conflict of :func:`path_conflicts`: could the ego see the target in time?

    Parameters
    ----------
    visibility : polars.DataFrame or LazyFrame
        A visibility table of the ego(s) (``get_visibility_df``'s, with or without ``idx_ego`` and sensors; through
        sensors the best sensor counts, as :func:`~.combine.seen_by_any` gives it).
    timegaps : polars.DataFrame or LazyFrame
        omega-prime's ``timegaps`` property for the same ego(s), with a ``time_buffer`` of at least ``pet``.
    objects : polars.DataFrame or LazyFrame, optional
        The recording's moving-object table (``total_nanos, idx, x, y``, metres) for the distance at first sight.
    ego_idx : int, optional
        The ego, when ``visibility`` has no ``idx_ego`` column (one ego).
    pet, look_back, threshold : float
        Post-encroachment time (s); the window before the conflict searched for hiding (s); visible means
        ``visibility > threshold``.
    reaction_time, notice
        The notice model, as in :func:`~.intervals.visible_intervals`; default nuPlan's ``notice=(1.0, 1.5)``. A
        ``reaction_time`` given alone takes the unbroken-run model instead (``notice=None`` and no
        ``reaction_time``: noticed when first seen).

    Returns
    -------
    polars.DataFrame
        One row per conflict: :data:`CONFLICT_COLUMNS`, then ``first_visible_nanos`` and ``first_noticed_nanos``
        (at or before the conflict; null if never), ``sight_to_conflict`` and ``notice_to_conflict`` (seconds left),
        ``distance_at_sight`` (metres between the centres, when ``objects`` is given), ``first_seen_by`` (the sensor
        that saw it first, through sensors), ``hidden_seconds`` (frames at times in ``[conflict - look_back,
        conflict)`` in which the target was in view but nothing of it seen, times the frame period), ``hidden`` (any),
        ``hidden_by`` and ``hidden_by_static`` (the objects and static occluders in front of it then, ascending) and
        ``notice_model``.
    """
    if not (isinstance(look_back, int | float) and math.isfinite(look_back) and look_back >= 0):
        raise ValueError(f"look_back must be a non-negative number of seconds, not {look_back!r}")
    if reaction_time is not None and notice is NUPLAN_NOTICE:  # a reaction time given alone replaces the default
        notice = None
    if reaction_time is None and notice is None:
        reaction_time = 0.0  # no notice model: noticed when first visible
    conflicts = path_conflicts(timegaps, pet)
    table = _per_frame(polars_table(visibility, "visibility"), ego_idx)
    rows = table.join(conflicts.lazy(), on=["idx_ego", "idx"]).filter(pl.col("total_nanos") <= pl.col("conflict_nanos"))
    visible = pl.col("visibility") > threshold
    sight = (
        rows.filter(visible)
        .group_by("idx_ego", "idx")
        .agg(
            pl.col("total_nanos").min().alias("first_visible_nanos"),
            pl.col("best_sensor").sort_by("total_nanos").first().alias("first_seen_by"),
        )
    )
    noticed = (
        visible_intervals(rows.drop(*CONFLICT_COLUMNS[2:]), threshold, reaction_time, notice=notice)
        .group_by("idx_ego", "idx")
        .agg(pl.col("first_noticed_nanos").min(), pl.col("notice_model").first())
    )
    period = frame_period(table)
    before = pl.col("conflict_nanos") - min(round(look_back * NANOS), LONGEST)
    window = rows.filter(pl.col("total_nanos") >= before, pl.col("total_nanos") < pl.col("conflict_nanos"))
    hiding = window.filter(~visible & pl.col("in_view_any"))
    hidden = hiding.group_by("idx_ego", "idx").agg(
        (pl.len().cast(pl.Int64) * period / NANOS).alias("hidden_seconds"),  # (a UInt32 count would wrap)
        every_listed("occluder_idxs").alias("hidden_by"),
        every_listed("static_occluder_idxs").alias("hidden_by_static"),
    )
    out = (
        conflicts.lazy()
        .join(sight, on=["idx_ego", "idx"], how="left")
        .join(noticed.lazy(), on=["idx_ego", "idx"], how="left")
        .join(hidden, on=["idx_ego", "idx"], how="left")
        .with_columns(
            sight_to_conflict=(pl.col("conflict_nanos") - pl.col("first_visible_nanos")) / NANOS,
            notice_to_conflict=(pl.col("conflict_nanos") - pl.col("first_noticed_nanos")) / NANOS,
            hidden_seconds=pl.col("hidden_seconds").fill_null(0.0),
            hidden_by=pl.col("hidden_by").fill_null([]),
            hidden_by_static=pl.col("hidden_by_static").fill_null([]),
        )
        .with_columns(hidden=pl.col("hidden_seconds") > 0)
    )
    out = out.join(_distance_at_sight(objects, out), on=["idx_ego", "idx"], how="left")
    columns = [*CONFLICT_COLUMNS, "first_visible_nanos", "first_noticed_nanos", "sight_to_conflict"]
    columns += ["notice_to_conflict", "distance_at_sight", "first_seen_by", "hidden_seconds", "hidden", "hidden_by"]
    columns += ["hidden_by_static", "notice_model"]
    return out.select(columns).sort("idx_ego", "idx").collect()


def _per_frame(table: pl.LazyFrame, ego_idx: int | None) -> pl.LazyFrame:
    """One row per (frame, ego, target): the best sensor's visibility, which sensor, whether any sensor had the
    target in view, and every occluder any sensor listed."""
    names = table.collect_schema().names()
    missing = [c for c in ("frame", "total_nanos", "idx", "visibility", "occluder_idxs") if c not in names]
    if missing:
        raise ValueError(f"the visibility table lacks the column(s) {missing}")
    if "idx_ego" not in names:
        if ego_idx is None:
            raise ValueError("the visibility table has no idx_ego column: pass ego_idx (the observer it was made for)")
        table = table.with_columns(idx_ego=pl.lit(ego_idx, dtype=pl.Int64))
    if "static_occluder_idxs" not in names:
        table = table.with_columns(static_occluder_idxs=pl.lit([], dtype=pl.List(pl.Int64)))
    table = table.with_columns(pl.col("total_nanos").cast(pl.Int64))  # unsigned times would wrap in differences
    sensors = "sensor" in names
    in_view = pl.col("in_view") > 0 if "in_view" in names else pl.lit(True)
    return table.group_by("frame", "total_nanos", "idx_ego", "idx").agg(
        pl.col("visibility").max(),
        (pl.col("sensor").sort_by("visibility", descending=True).first() if sensors else pl.lit(None, pl.String)).alias(
            "best_sensor"
        ),
        in_view.any().alias("in_view_any"),
        every_listed("occluder_idxs"),
        every_listed("static_occluder_idxs"),
    )


def _distance_at_sight(objects: pl.DataFrame | pl.LazyFrame | None, conflicts: pl.LazyFrame) -> pl.LazyFrame:
    """``idx_ego, idx, distance_at_sight``: metres between the centres at the first visible time (null without
    ``objects``)."""
    keys = conflicts.select("idx_ego", "idx", "first_visible_nanos")
    if objects is None:
        return keys.select("idx_ego", "idx", distance_at_sight=pl.lit(None, pl.Float64))
    positions = objects.lazy().select("total_nanos", "idx", "x", "y")
    return (
        keys.join(positions, left_on=["first_visible_nanos", "idx"], right_on=["total_nanos", "idx"], how="left")
        .join(
            positions.rename({"x": "x_ego", "y": "y_ego", "idx": "idx_ego"}),
            left_on=["first_visible_nanos", "idx_ego"],
            right_on=["total_nanos", "idx_ego"],
            how="left",
        )
        .select(
            "idx_ego",
            "idx",
            distance_at_sight=((pl.col("x") - pl.col("x_ego")) ** 2 + (pl.col("y") - pl.col("y_ego")) ** 2).sqrt(),
        )
    )
