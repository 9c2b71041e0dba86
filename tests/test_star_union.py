"""The compiled area of a union of star-shaped polygons against shapely's union."""

from __future__ import annotations

import math
import warnings

import numpy as np
import pytest
import shapely
from conftest import scene_table
from reference import scene_series

from omega_prime_visibility import Sensor
from omega_prime_visibility.area import visible_area, visible_area_over_time
from omega_prime_visibility.star_union import star_union_area


def test_two_overlapping_squares() -> None:
    # squares star-shaped around their centres, all around, vertices from bearing -3π/4
    a = np.array([(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)])
    points = np.concatenate([a, a + np.array([1.0, 0.0])])
    starts = np.array([0, 4, 8])
    centers = np.array([(0.0, 0.0), (1.0, 0.0)])
    area = star_union_area(points, starts, centers, np.full(2, -0.75 * math.pi), np.full(2, 2 * math.pi))
    assert area == pytest.approx(6.0, rel=1e-12)  # two 2 m squares overlapping by 1 m x 2 m


def test_a_shared_edge_counts_once() -> None:
    # two wedges from different apexes ending on the same wall x = 10
    first = np.array([(0.0, 0.0), (10.0, -10.0), (10.0, 10.0)])
    second = np.array([(0.0, 1.0), (10.0, -9.0), (10.0, 11.0)])
    points = np.concatenate([first, second])
    centers = np.array([(0.0, 0.0), (0.0, 1.0)])
    area = star_union_area(points, np.array([0, 3, 6]), centers, np.full(2, -math.pi / 4), np.full(2, math.pi / 2))
    want = shapely.union(shapely.Polygon(first), shapely.Polygon(second)).area
    assert area == pytest.approx(want, rel=1e-12)


def _random_sensors(rng: np.random.Generator) -> list[Sensor]:
    """2-6 sensors; some share a position, a range or a wedge edge with another (shared boundaries)."""
    sensors = []
    for k in range(int(rng.integers(2, 7))):
        if sensors and rng.random() < 0.4:  # at an earlier sensor's position, often with its range
            other = sensors[int(rng.integers(len(sensors)))]
            x, y, reach = other.x, other.y, other.range if rng.random() < 0.5 else float(rng.uniform(5, 30))
            yaw = other.yaw + (other.fov / 2 if rng.random() < 0.5 else float(rng.uniform(-1, 1)))
        else:
            x, y, reach, yaw = *rng.uniform(-1.5, 1.5, 2), float(rng.uniform(5, 30)), float(rng.uniform(-3, 3))
        fov = 2 * math.pi if rng.random() < 0.25 else float(rng.uniform(0.3, 5.5))
        sensors.append(Sensor(f"s{k}", x=float(x), y=float(y), yaw=yaw, fov=fov, range=reach))
    return sensors


@pytest.mark.parametrize("seed", [3, 4, 5])
def test_the_area_matches_shapelys_union_on_random_scenes(seed) -> None:
    # visible_area_over_time without a road takes star_union's area; visible_area builds shapely's union
    rng = np.random.default_rng(seed)
    for include_ego, scene in scene_series(rng, 12, True, 8):
        observer, objects, statics, _ = scene
        table = scene_table(observer, objects, include_ego).with_columns(yaw=0.0)
        sensors = _random_sensors(rng)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            fast = visible_area_over_time(table, 0, sensors, statics)["visible_area"][0]
            want = visible_area(table, 0, 0, sensors, statics).area
        assert fast == pytest.approx(want, rel=1e-9, abs=1e-9)
