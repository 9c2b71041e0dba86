"""Visibility over time: intervals, reaction time, gaps of missing frames."""

from __future__ import annotations

import polars as pl
import pytest
from conftest import boxes_table

from omega_prime_visibility import get_visibility_df, visible_intervals

STEP = 100_000_000  # 10 Hz


def moving_scene() -> pl.DataFrame:
    """Ego 0 at the origin, a parked van 1 at x = 10 hiding pedestrian 2, who walks out from behind it along +y
    at 1 m per frame from y = -4; frame 6 is missing from the recording."""
    frames = []
    for f in [0, 1, 2, 3, 4, 5, 7, 8]:
        frames.append(boxes_table([(0, 0, 4, 2, 0), (10, 0, 5, 2.5, 0), (15, -4 + f, 0.5, 0.5, 0)], frame=f))
    return pl.concat(frames)


def test_intervals_with_a_gap_and_reaction_time() -> None:
    table = get_visibility_df(moving_scene(), 0)
    ped = table.filter(pl.col("idx") == 2).sort("frame")
    visible_frames = ped.filter(pl.col("visibility") > 0)["frame"].to_list()
    # hidden while its whole extent lies within the van's (|y| < 1.875 at x = 15 ... ) then visible
    assert visible_frames == [k for k in [0, 1, 2, 3, 4, 5, 7, 8] if k in visible_frames]
    out = visible_intervals(table, reaction_time=0.15).filter(pl.col("idx") == 2)
    starts = out["start_frame"].to_list()
    # the missing frame 6 splits what would otherwise be one run
    assert 7 in starts
    assert all(e < 6 or s > 6 for s, e in zip(out["start_frame"], out["end_frame"], strict=True))
    first = out.row(0, named=True)
    assert first["first_visible_nanos"] == first["start_nanos"] == visible_frames[0] * STEP
    assert first["duration"] == pytest.approx((first["end_frame"] - first["start_frame"]) * 0.1)
    # noticed 0.15 s after the start: two frames later, if the interval lasts that long
    for row in out.iter_rows(named=True):
        want = row["start_frame"] + 2 if row["end_frame"] >= row["start_frame"] + 2 else None
        assert row["noticed_frame"] == want


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
