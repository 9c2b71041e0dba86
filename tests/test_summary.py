"""The per-target summary (analysis/summary.py), as ``run`` prints it: shares derived on paper."""

from __future__ import annotations

import polars as pl
import pytest

from omega_prime_visibility import target_summary

LISTS = {"occluder_idxs": pl.List(pl.Int64), "static_occluder_idxs": pl.List(pl.Int64)}


def test_shares_without_sensors() -> None:
    # target 7 over 5 frames: seen whole, half, hidden twice, and 0.999 (partly); target 8 always whole
    table = pl.DataFrame(
        {
            "frame": [0, 1, 2, 3, 4, 0, 1],
            "idx": [7, 7, 7, 7, 7, 8, 8],
            "visibility": [1.0, 0.5, 0.0, 0.0, 0.999, 1.0, 1.0],
            "occluder_idxs": [[], [3], [4, 3], [4], [9], [], []],
            "static_occluder_idxs": [[], [], [], [2], [], [], []],
        },
        schema_overrides=LISTS,
    )
    rows = {row["idx"]: row for row in target_summary(table).iter_rows(named=True)}
    assert list(rows) == [7, 8]
    seven = rows[7]
    assert seven["frames"] == 5
    assert seven["mean_visibility"] == pytest.approx(2.499 / 5, abs=1e-15)
    assert seven["min_visibility"] == 0.0
    assert seven["hidden_share"] == pytest.approx(2 / 5)  # frames 2 and 3: nothing seen
    assert seven["partly_hidden_share"] == pytest.approx(2 / 5)  # frames 1 and 4 (0.999 is partly hidden)
    assert seven["occluders"] == [3, 4, 9] and seven["static_occluders"] == [2]
    assert (rows[8]["hidden_share"], rows[8]["partly_hidden_share"], rows[8]["occluders"]) == (0.0, 0.0, [])
    assert "out_of_view_share" not in target_summary(table).columns


def test_out_of_view_is_not_counted_as_hidden() -> None:
    # through a sensor: a target behind the camera (out_of_fov) or beyond its range is not hidden by anything
    statuses = ["visible", "out_of_fov", "out_of_range", "occluded", "partly_visible", "out_of_fov"]
    table = pl.DataFrame(
        {
            "frame": range(6),
            "idx": [5] * 6,
            "sensor": ["front_camera"] * 6,
            "visibility": [1.0, 0.0, 0.0, 0.0, 0.25, 0.0],
            "in_view": [1.0, 0.0, 0.0, 1.0, 1.0, 0.0],
            "status": pl.Series(statuses).cast(pl.Enum(["visible", "partly_visible", "occluded", "out_of_fov",
                                                         "out_of_range"])),
            "occluder_idxs": [[], [], [], [1], [1], []],
            "static_occluder_idxs": [[]] * 6,
        },
        schema_overrides=LISTS,
    )  # fmt: skip
    row = target_summary(table).row(0, named=True)
    assert (row["idx"], row["sensor"], row["frames"]) == (5, "front_camera", 6)
    assert row["hidden_share"] == pytest.approx(1 / 6)  # only frame 3 is hidden by idx 1
    assert row["out_of_view_share"] == pytest.approx(3 / 6)
    assert row["partly_hidden_share"] == pytest.approx(1 / 6)
    assert row["occluders"] == [1]


def test_keys_of_several_observers_and_a_table_without_columns() -> None:
    table = pl.DataFrame(
        {"idx_ego": [0, 1, 0], "idx": [2, 2, 2], "visibility": [0.0, 1.0, 1.0], "occluder_idxs": [[5], [], []]},
        schema_overrides={"occluder_idxs": pl.List(pl.Int64)},
    )
    summary = target_summary(table)
    assert summary.select("idx_ego", "idx", "frames", "hidden_share").rows() == [(0, 2, 2, 0.5), (1, 2, 1, 0.0)]
    with pytest.raises(ValueError, match="occluder_idxs"):
        target_summary(table.drop("occluder_idxs"))
