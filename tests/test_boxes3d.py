"""boxes3d: OSI's rotation order and signs, corners, ray entries, containment, the eye point."""

from __future__ import annotations

import math

import numpy as np
import pytest

from omega_prime_visibility.threed.boxes import (
    contains,
    corners,
    eye_point,
    farthest_distance,
    nearest_distance,
    ray_box_entry,
    rotations,
    view_limits,
)


def test_signs_follow_osi() -> None:
    x, y, z = np.eye(3)
    # yaw turns +x towards +y, positive pitch lowers the nose, positive roll raises the left side
    assert np.allclose(rotations([0], [0], [math.pi / 2])[0] @ x, y)
    assert np.allclose(rotations([0], [math.pi / 2], [0])[0] @ x, -z)
    assert np.allclose(rotations([math.pi / 2], [0], [0])[0] @ y, z)


def test_order_is_yaw_then_pitch_then_roll() -> None:
    roll, pitch, yaw = 0.3, -0.4, 1.1

    def about(axis: np.ndarray, a: float) -> np.ndarray:  # Rodrigues, independent of the module
        k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
        return np.eye(3) + math.sin(a) * k + (1 - math.cos(a)) * k @ k

    r_yaw = about(np.array([0.0, 0, 1]), yaw)
    r_pitch = about(r_yaw @ [0, 1.0, 0], pitch) @ r_yaw  # about the turned y axis
    expected = about(r_pitch @ [1.0, 0, 0], roll) @ r_pitch  # about the turned x axis
    assert np.allclose(rotations([roll], [pitch], [yaw])[0], expected)


def test_corners_of_a_pitched_box() -> None:
    # a 4 m long, 1 m high slab pitched 90° stands on end: 4 m high, 1 m long
    box = np.array([[0.0, 0, 2, 4, 2, 1, 0, math.pi / 2, 0]])
    c = corners(box)[0]
    assert np.allclose(c.min(axis=0), [-0.5, -1, 0]) and np.allclose(c.max(axis=0), [0.5, 1, 4])


def test_ray_entries_and_distances() -> None:
    box = np.array([10.0, 0, 1, 4, 2, 2, 0, 0, 0])
    assert ray_box_entry(np.zeros(3), np.array([1.0, 0, 0]), box) == pytest.approx(8.0)
    assert ray_box_entry(np.zeros(3), np.array([0.0, 1, 0]), box) == math.inf
    assert ray_box_entry(np.array([10.0, 0, 1]), np.array([1.0, 0, 0]), box) == 0.0  # inside
    assert nearest_distance(box[None], np.array([0.0, 0, 1]))[0] == pytest.approx(8.0)
    assert farthest_distance(box[None], np.zeros(3))[0] == pytest.approx(math.sqrt(144 + 1 + 4))


def test_contains_rotated_box() -> None:
    box = np.array([[0.0, 0, 0, 4, 0.5, 0.5, 0, 0, math.pi / 2]])  # long along y
    assert contains(box, np.array([0.0, 1.9, 0]))[0]
    assert not contains(box, np.array([1.9, 0.0, 0]))[0]


def test_eye_point_and_view() -> None:
    boxes = np.array([[0.0, 0, 5.8, 4, 2, 1.6, 0, 0, 0]])  # a car on a bridge: ground at 5 m
    assert eye_point(np.array([0.0, 0]), 1.25, boxes, 0)[2] == pytest.approx(6.25)
    assert eye_point(np.array([0.0, 0]), 1.25, None, -1)[2] == pytest.approx(1.25)
    heading, half, low, high = view_limits(0.2, math.pi / 2, math.radians(10), math.radians(40))
    assert (heading, half) == (0.2, math.pi / 4)
    assert (low, high) == pytest.approx((math.radians(-30), math.radians(10)))
