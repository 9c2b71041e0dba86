"""The exact pairwise "hit before" test (occlusion.py), on bodies whose answer is clear on paper."""

from __future__ import annotations

import numpy as np
import pytest

from omega_prime_visibility.geometry.occlusion import occludes
from omega_prime_visibility.geometry.rings import angular_extent, box_rings, edges, ring_ids


def occluded_by(target: tuple, body: tuple) -> bool:
    """Whether box ``body`` is hit strictly before box ``target`` somewhere, seen from the origin.

    Boxes are ``(x, y, length, width)`` with yaw 0; body 0 is the target, body 1 the candidate occluder.
    """
    boxes = np.array([target, body], dtype=float)
    rings = box_rings(boxes[:, 0], boxes[:, 1], boxes[:, 2], boxes[:, 3], np.zeros(2))
    a, b = edges(rings)
    segments = np.stack([a, b], axis=1)
    offsets = np.array([0, 4, 8])
    assert np.array_equal(np.bincount(ring_ids(rings.offsets)), [4, 4])
    start, width, _ = angular_extent(np.zeros(2), rings)
    return bool(occludes(np.zeros(2), segments, offsets, np.array([1]), np.array([0]), start, width)[0])


@pytest.mark.parametrize(
    ("body", "expected"),
    [
        ((10, 0, 2, 2), True),  # straight in front
        ((10, 1.2, 2, 2), True),  # its corner (11, 0.2) at bearing 0.018 rad enters the target's upper part
        ((10, 1.9, 2, 2), False),  # beside: from bearing atan(0.9 / 11) = 0.082 rad; the target's |bearing| <= 0.053
        ((30, 0, 2, 2), False),  # behind
        ((20, 0, 2, 2), False),  # the same box: equal distances are not "before"
        ((20, 2, 2, 2), False),  # shares the target's upper edge line: touches, never strictly before
    ],
)
def test_pairs(body: tuple, expected: bool) -> None:
    assert occluded_by((20, 0, 2, 2), body) is expected


def test_no_pairs() -> None:
    empty = np.zeros(0, dtype=np.int64)
    assert occludes(np.zeros(2), np.zeros((0, 2, 2)), np.zeros(1, np.int64), empty, empty, empty, empty).shape == (0,)
