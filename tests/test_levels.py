"""The datasets' occlusion levels from camera and lidar counts: each threshold at its edge."""

from __future__ import annotations

import math

import polars as pl
import pytest

from omega_prime_visibility import camera_visibility, get_visibility_df, kitti_levels, lidar_levels
from omega_prime_visibility.inputs.sensors import camera, lidar


def camera_rows(occlusion, truncation, height, frames=None) -> pl.DataFrame:
    n = len(occlusion)
    unoccluded = [100 if o is not None else 0 for o in occlusion]
    pixels = [round(100 * (1 - o)) if o is not None else 0 for o in occlusion]
    return pl.DataFrame(
        {"frame": frames or list(range(n)), "idx": [1] * n, "sensor": ["cam"] * n, "pixels": pixels,
         "pixels_unoccluded": unoccluded, "occlusion": occlusion, "truncation": truncation,
         "bbox_unoccluded": [[0, 0, 10, h] if h is not None else None for h in height]},
        schema_overrides={"bbox_unoccluded": pl.Array(pl.Int64, 4), "occlusion": pl.Float64},
    )  # fmt: skip


def test_kitti_classes_at_their_limits() -> None:
    rows = camera_rows(
        occlusion=[0.0, 0.0, 0.0, 0.3, 0.3, 0.8, 0.8, 0.8, None, 0.0],
        truncation=[0.15, 0.16, 0.0, 0.30, 0.31, 0.50, 0.51, 0.0, 0.0, 0.0],
        height=[40, 40, 39, 25, 25, 25, 25, 24, None, 40],
    )
    out = kitti_levels(rows)
    assert out["kitti_occluded"].to_list() == [0, 0, 0, 1, 1, 2, 2, 2, 3, 0]
    assert out["kitti_difficulty"].to_list() == [
        "easy", "moderate", "moderate", "moderate", "hard", "hard", None, None, None, "easy",
    ]  # fmt: skip
    assert kitti_levels(rows, occluded_bounds=(0.35, 0.9))["kitti_occluded"].to_list()[3:6] == [0, 0, 1]
    with pytest.raises(ValueError, match="occluded_bounds"):
        kitti_levels(rows, occluded_bounds=(0.6, 0.5))


def test_nuscenes_and_t4_levels_pool_the_cameras() -> None:
    # one target seen by two cameras: 30 of 100 and 50 of 100 pixels: 40 % pooled, token 1 (0-40 %, closed above)
    rows = pl.DataFrame(
        {"frame": [0, 0, 1, 2, 3, 4], "idx": [1] * 6, "sensor": ["a", "b", "a", "a", "a", "a"],
         "pixels": [30, 50, 61, 100, 9, 0], "pixels_unoccluded": [100, 100, 100, 100, 100, 0]}
    )  # fmt: skip
    out = camera_visibility(rows).sort("frame")
    assert out["visible_share"].to_list()[:4] == [0.4, 0.61, 1.0, 0.09]
    assert out["nuscenes_visibility"].to_list() == ["1", "3", "4", "1", None]
    assert out["t4_visibility"].cast(pl.String).to_list() == ["partial", "most", "full", "none", "unavailable"]


def test_waymo_and_argoverse_levels_by_lidar_points() -> None:
    rows = pl.DataFrame({"frame": [0, 1, 2, 3], "idx": [1] * 4, "points": [0, 1, 5, 6]})
    out = lidar_levels(rows).sort("frame")
    assert out["waymo_level"].to_list() == [None, "LEVEL_2", "LEVEL_2", "LEVEL_1"]
    assert out["av2_kept"].to_list() == [False, True, True, True]
    assert lidar_levels(rows, waymo_level2_points=0)["waymo_level"].to_list()[1] == "LEVEL_1"


def test_levels_of_a_real_table_and_a_table_without_cameras() -> None:
    table = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, 15.0], "y": [0.0, 0.0],
                          "z": [0.75, 0.75], "length": [4.5, 4.0], "width": [1.8, 1.8], "height": [1.5, 1.5],
                          "yaw": [0.0, 0.0]})  # fmt: skip
    sensors = [camera("c", 1242, 375, math.radians(60)), lidar("l", "vlp16")]
    out = get_visibility_df(table, 0, mode="3d", sensors=sensors)
    assert kitti_levels(out).filter(pl.col("sensor") == "c")["kitti_difficulty"].to_list() == ["easy"]
    assert lidar_levels(out)["num_lidar_pts"].to_list()[0] > 5
    with pytest.raises(ValueError, match="camera or lidar sensor"):
        kitti_levels(get_visibility_df(table, 0, progress=False))
