"""Combining views over sensors and over observers (``seen_by_any``)."""

from __future__ import annotations

import math

import polars as pl
import pytest
from conftest import boxes_table

from omega_prime_visibility import Sensor, get_visibility_df, seen_by_any

# ego 0 at the origin facing +x; car 1 ahead; car 2 behind the ego; car 3 hidden behind car 1 from the ego
SCENE = [(0, 0, 4, 2, 0), (20, 0, 4, 2, 0), (-20, 0, 4, 2, 0), (40, 0, 4, 2, 0)]
FRONT = Sensor("front", x=2.0, fov=math.radians(90))
REAR = Sensor("rear", x=-2.0, yaw=math.pi, fov=math.radians(90))


def test_combining_over_sensors() -> None:
    per_sensor = get_visibility_df(boxes_table(SCENE), 0, sensors=[REAR, FRONT])
    combined = seen_by_any(per_sensor)
    assert combined.columns == ["frame", "total_nanos", "idx", "visibility", "best_sensor", "seen_by", "in_view"]
    assert combined.rows() == [
        (0, 0, 1, 1.0, "front", ["front"], 1.0),
        (0, 0, 2, 1.0, "rear", ["rear"], 1.0),
        (0, 0, 3, 0.0, "front", [], 1.0),
    ]
    # lazily, the same
    assert seen_by_any(per_sensor.lazy()).collect().equals(combined)


def test_a_target_seen_by_two_sensors_lists_both_sorted_and_keeps_the_best() -> None:
    wide = Sensor("b_wide", fov=2 * math.pi)
    narrow = Sensor("a_narrow", fov=math.atan2(1, 19))  # sees the upper half of car 1 only
    per_sensor = get_visibility_df(boxes_table(SCENE[:2]), 0, sensors=[wide, narrow])
    row = seen_by_any(per_sensor).row(0, named=True)
    assert row["seen_by"] == ["a_narrow", "b_wide"]
    assert (row["visibility"], row["best_sensor"]) == (1.0, "b_wide")


def test_combining_over_observers_answers_is_it_seen_by_anyone() -> None:
    # car 3 is hidden from the ego by car 1 but car 1 sees it; car 1 is hidden from car 2 by the ego (same width)
    table = get_visibility_df(boxes_table(SCENE), "all")
    anyone = seen_by_any(table, over="idx_ego")
    assert anyone.columns == ["frame", "total_nanos", "idx", "visibility", "best_idx_ego", "seen_by"]
    by_idx = {r["idx"]: r for r in anyone.iter_rows(named=True)}
    assert by_idx[3]["seen_by"] == [1]
    assert by_idx[1]["seen_by"] == [0, 3]
    assert by_idx[2]["seen_by"] == [0]


def test_combining_over_sensors_then_observers() -> None:
    table = get_visibility_df(boxes_table(SCENE), "all", sensors=[FRONT, REAR])
    per_observer = seen_by_any(table, "sensor")
    assert "idx_ego" in per_observer.columns and per_observer.height == 12
    anyone = seen_by_any(per_observer, "idx_ego")
    assert anyone.height == 4
    assert anyone.filter(pl.col("idx") == 3)["seen_by"].to_list() == [[1]]


def test_bad_over() -> None:
    table = get_visibility_df(boxes_table(SCENE), 0)
    with pytest.raises(ValueError, match="no 'sensor' column"):
        seen_by_any(table)
    with pytest.raises(ValueError, match="over must be"):
        seen_by_any(table, over="idx")
