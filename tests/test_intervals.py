"""Visibility over time: intervals, reaction time, gaps of missing frames."""

from __future__ import annotations

import polars as pl
import pytest
from conftest import boxes_table

from omega_prime_visibility import get_visibility_df, visible_intervals

STEP = 100_000_000  # 10 Hz


def moving_scene() -> pl.DataFrame:
    """Ego 0 at the origin, a parked van 1 at x = 10 (5 x 2.5 m) hiding pedestrian 2 (0.5 m square), who walks
    out from behind it along +y at 1 m per frame from y = -2 at x = 15; frame 6 is missing from the recording."""
    frames = []
    for f in [0, 1, 2, 3, 4, 5, 7, 8]:
        frames.append(boxes_table([(0, 0, 4, 2, 0), (10, 0, 5, 2.5, 0), (15, -2 + f, 0.5, 0.5, 0)], frame=f))
    return pl.concat(frames)


def test_a_missing_frame_splits_a_visible_run() -> None:
    # On paper: the van's shadow from the eye at the origin is bounded by its near corners (7.5, +-1.25), i.e.
    # |y| / x < 1/6. The pedestrian in frame f spans x in [14.75, 15.25], y in [f - 2.25, f - 1.75]; its worst
    # corner (14.75, f - 1.75 or f - 2.25) has |y| / x < 1/6 (|y| < 2.458) for f = 0..4: hidden; in frame 5 the
    # corner (14.75, 2.75) gives 0.186 > 1/6: partly visible, and so in frames 7 and 8. The van is never hidden.
    table = get_visibility_df(moving_scene(), 0)
    ped = table.filter(pl.col("idx") == 2).sort("frame")
    assert ped.filter(pl.col("visibility") > 0)["frame"].to_list() == [5, 7, 8]
    assert ped.filter(pl.col("frame") <= 4)["visibility"].to_list() == [0.0] * 5
    # visible in 5, then frame 6 missing, then 7-8: two runs, not one; the van (visible in 0-5, 7-8) likewise.
    # Noticed 0.1 s after the start: frame 8 of the second run (exactly 0.1 s), never in the one-frame first run.
    out = visible_intervals(table, reaction_time=0.1)
    rows = out.select("idx", "start_frame", "end_frame", "n_frames", "noticed_frame", "duration").rows()
    assert rows == [(1, 0, 5, 6, 1, 0.5), (1, 7, 8, 2, 8, 0.1), (2, 5, 5, 1, None, 0.0), (2, 7, 8, 2, 8, 0.1)]
    assert out.filter(pl.col("idx") == 2)["first_visible_nanos"].to_list() == [5 * STEP, 5 * STEP]
    assert out.filter(pl.col("idx") == 2)["first_noticed_nanos"].to_list() == [8 * STEP, 8 * STEP]


def test_hand_made_table() -> None:
    t = pl.DataFrame(
        {
            "frame": [0, 1, 2, 3, 4, 0, 1, 2],
            "total_nanos": [0, STEP, 2 * STEP, 3 * STEP, 4 * STEP, 0, STEP, 2 * STEP],
            "idx_ego": [0] * 8,
            "idx": [1, 1, 1, 1, 1, 2, 2, 2],
            "visibility": [0.0, 0.3, 0.3, 0.05, 0.5, 1.0, 1.0, 1.0],
        }
    )
    out = visible_intervals(t, threshold=0.1, reaction_time=0.1)
    assert out.select("idx_ego", "idx", "start_frame", "end_frame", "n_frames", "noticed_frame").rows() == [
        (0, 1, 1, 2, 2, 2),
        (0, 1, 4, 4, 1, None),
        (0, 2, 0, 2, 3, 1),
    ]
    assert out["first_noticed_nanos"].to_list() == [2 * STEP, 2 * STEP, STEP]
    assert out["first_visible_nanos"].to_list() == [STEP, STEP, 0]
    # never visible: no interval
    assert visible_intervals(t.with_columns(visibility=0.0)).height == 0


def test_with_sensors_groups_per_sensor() -> None:
    from omega_prime_visibility import Sensor

    table = get_visibility_df(moving_scene(), 0, sensors=[Sensor("a"), Sensor("b", range=5.0)])
    out = visible_intervals(table)
    assert set(out["sensor"]) == {"a"}  # nothing lies within 5 m of sensor b


def test_bad_arguments() -> None:
    t = pl.DataFrame({"frame": [0], "total_nanos": [0], "idx": [1], "visibility": [1.0]})
    with pytest.raises(ValueError, match="reaction_time"):
        visible_intervals(t, reaction_time=-1)
    with pytest.raises(ValueError, match="threshold"):
        visible_intervals(t, threshold=float("nan"))
    with pytest.raises(ValueError, match=r"lacks the column\(s\) \['visibility'\]"):
        visible_intervals(t.drop("visibility"))
