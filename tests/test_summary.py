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


def test_a_target_cut_by_the_field_of_view_is_not_partly_hidden() -> None:
    # through a sensor, with nothing in front: frame 0 all in view, frames 1-2 half of it beyond the field of view's
    # edge (visibility == in_view == 0.5, status partly_visible), frame 3 out of view. Then with a car in front of it:
    # frame 4 half in view and half of that hidden (partly hidden, and partly out of view), frame 5 in view, hidden
    statuses = ["visible", "partly_visible", "partly_visible", "out_of_fov", "partly_visible", "occluded"]
    table = pl.DataFrame(
        {
            "frame": range(6),
            "idx": [1] * 6,
            "sensor": ["front_radar"] * 6,
            "visibility": [1.0, 0.5, 0.5, 0.0, 0.25, 0.0],
            "in_view": [1.0, 0.5, 0.5, 0.0, 0.5, 1.0],
            "status": pl.Series(statuses).cast(pl.Enum(["visible", "partly_visible", "occluded", "out_of_fov",
                                                         "out_of_range"])),
            "occluder_idxs": [[], [], [], [], [4], [4]],
            "static_occluder_idxs": [[]] * 6,
        },
        schema_overrides=LISTS,
    )  # fmt: skip
    row = target_summary(table).row(0, named=True)
    assert row["visible_share"] == pytest.approx(3 / 6)  # frames 0, 1, 2: all of the part in view is seen
    assert row["partly_hidden_share"] == pytest.approx(1 / 6)  # frame 4 only: something in front
    assert row["hidden_share"] == pytest.approx(1 / 6)  # frame 5
    assert row["out_of_view_share"] == pytest.approx(1 / 6)  # frame 3
    assert row["partly_out_of_view_share"] == pytest.approx(3 / 6)  # frames 1, 2, 4
    shares = ("visible_share", "partly_hidden_share", "hidden_share", "out_of_view_share")
    assert sum(row[k] for k in shares) == pytest.approx(1.0)  # the classes part the frames
    # other bounds: seen share 0.5 (frame 4) is hidden when at most half seen counts as hidden
    loose = target_summary(table, partly=(0.5, 0.9)).row(0, named=True)
    assert (loose["partly_hidden_share"], loose["hidden_share"]) == (0.0, pytest.approx(2 / 6))


@pytest.mark.parametrize("partly", [(0.5, 0.5), (-0.1, 1.0), (0.0, 1.5), (0.9, 0.1), (True, 1.0), "0,1"])
def test_bounds_are_checked(partly) -> None:
    table = pl.DataFrame({"idx": [1], "visibility": [1.0], "occluder_idxs": [[]]}, schema_overrides=LISTS)
    with pytest.raises(ValueError, match="partly"):
        target_summary(table, partly=partly)
