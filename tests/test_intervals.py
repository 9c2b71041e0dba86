"""Visibility over time: intervals, reaction time, gaps of missing frames."""

from __future__ import annotations

import numpy as np
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
    # visible means visibility > threshold: 1 or more is never visible, below 0 calls hidden visible; a
    # percentage is told as one
    for bad, says in ((1.0, r"in \[0, 1\), not 1.0$"), (-0.1, "not -0.1$"), (50, r"a percentage\? 50 % is 0.5"),
                      (True, "finite number, not True")):  # fmt: skip
        with pytest.raises(ValueError, match=says):
            visible_intervals(t, threshold=bad)
    assert visible_intervals(t, threshold=0.999).height == 1
    with pytest.raises(ValueError, match=r"lacks the column\(s\) \['visibility'\]"):
        visible_intervals(t.drop("visibility"))


def flicker_table(hidden: set[int], absent: set[int] = frozenset(), frames: int = 21, step: int = STEP):
    """Target 1 seen whole in frames 0..frames-1 at ``step`` nanoseconds apart, except hidden ones (visibility 0)
    and absent ones (no row)."""
    kept = [f for f in range(frames) if f not in absent]
    return pl.DataFrame(
        {
            "frame": kept,
            "total_nanos": [f * step for f in kept],
            "idx": [1] * len(kept),
            "visibility": [0.0 if f in hidden else 1.0 for f in kept],
        }
    )


@pytest.mark.parametrize("gap", ["hidden", "absent"])
def test_a_one_frame_flicker_does_not_reset_the_windowed_notice(gap: str) -> None:
    # On paper (10 Hz): visible in frames 0-4, not in 5, visible in 6-20. notice=(1.0, 1.5) needs 10 visible frames
    # (10 x 0.1 s) among the frames of the last 1.5 s, (t - 1.5, t]: 15 frames. At frame 10 (t = 1.0 s) the window
    # holds frames 0-10, ten of them visible: noticed at frame 10, in the second run. The run model
    # (reaction_time=1.0) waits 1.0 s from the second run's start: frame 16. A missing frame counts as not visible.
    table = flicker_table({5}) if gap == "hidden" else flicker_table(set(), absent={5})
    windowed = visible_intervals(table, notice=(1.0, 1.5))
    assert windowed.select("start_frame", "end_frame", "noticed_frame").rows() == [(0, 4, None), (6, 20, 10)]
    assert windowed["first_noticed_nanos"].to_list() == [10 * STEP] * 2
    assert set(windowed["notice_model"]) == {"visible 1 s within 1.5 s"}
    run = visible_intervals(table, reaction_time=1.0)
    assert run.select("start_frame", "noticed_frame").rows() == [(0, None), (6, 16)]
    assert set(run["notice_model"]) == {"visible 1 s without a break"}


def test_windowed_notice_never_reached_and_at_another_frame_rate() -> None:
    # every second frame hidden: at most 8 of any 15 frames visible (0.8 s < 1.0 s): never noticed
    alternating = visible_intervals(flicker_table(set(range(1, 41, 2)), frames=41), notice=(1.0, 1.5))
    assert alternating["noticed_frame"].null_count() == alternating.height == 21
    # 25 Hz (40 ms), one frame in four hidden: 1.0 s is 25 visible frames; the last 1.5 s hold 37 or 38 frames.
    # Frames 3, 7, 11, ... hidden: by frame f, f + 1 - (f + 1) // 4 frames are visible, which first reaches 25 at
    # f = 32 (33 frames, 8 of them hidden; at t = 1.28 s the window (t - 1.5 s, t] still holds frame 0)
    quarter = flicker_table(set(range(3, 60, 4)), frames=60, step=40_000_000)
    noticed = visible_intervals(quarter, notice=(1.0, 1.5))
    assert noticed["first_noticed_nanos"][0] == 32 * 40_000_000
    assert noticed.filter(pl.col("noticed_frame").is_not_null())["noticed_frame"].min() == 32


def test_bad_notice() -> None:
    t = flicker_table(set(), frames=3)
    for bad in [(2.0, 1.0), (0.0, 1.0), (1.0,), (1.0, float("inf")), "1s", (True, 2.0), (1.0, False)]:
        with pytest.raises(ValueError, match="notice takes"):
            visible_intervals(t, notice=bad)
    with pytest.raises(ValueError, match="below the tables' resolution of one nanosecond"):
        visible_intervals(t, notice=(1e-12, 1e-12))
    # numpy numbers are numbers
    assert visible_intervals(t, notice=(np.int64(1), np.float64(1.5))).equals(visible_intervals(t, notice=(1, 1.5)))
    with pytest.raises(ValueError, match="not both"):
        visible_intervals(t, reaction_time=0.5, notice=(1.0, 1.5))


def test_the_window_reaches_back_exactly_its_length() -> None:
    # 10 Hz, notice=(0.5, 1.0): 5 visible frames among the frames of (t - 1.0 s, t]. Visible in 0-3 and from 10 on.
    # At frame 10 (t = 1.0 s) the window is (0.0, 1.0]: frames 1-10, of which 1, 2, 3 and 10 are visible: 4, not
    # noticed (frame 0 lies exactly 1.0 s back, outside). At frame 11 frames 2, 3, 10, 11: 4; at 12: 3, 10-12: 4;
    # at 13: 10-13: 4; at 14: 10-14: 5, noticed.
    table = flicker_table(set(range(4, 10)), frames=16)
    out = visible_intervals(table, notice=(0.5, 1.0))
    assert out.select("start_frame", "noticed_frame").rows() == [(0, None), (10, 14)]
