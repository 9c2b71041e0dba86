"""The compiled area of a union of star-shaped polygons against shapely's union."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

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
