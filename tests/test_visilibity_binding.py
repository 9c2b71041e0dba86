"""VisiLibity1, compiled with the package (``engines/visilibity/native``): its binding over flat arrays."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import pytest
import shapely

from omega_prime_visibility.engines.visilibity import _visilibity1
from omega_prime_visibility.engines.visilibity.conversion import (
    Environment,
    vis_polygon,
    vis_polygons_reversed,
    visibility_polygon_coords,
)

ROOM = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
PILLAR = np.array([[4.0, 4.0], [4.0, 6.0], [6.0, 6.0], [6.0, 4.0]])  # clockwise, as holes run


def starting_at_lowest(coords: np.ndarray) -> np.ndarray:
    """The ring's vertices rotated to start at the lowest-leftmost one (rings compare whatever their start)."""
    key = np.round(coords, 9)  # VisiLibity's vertices carry rounding of 1e-15: (10, -2e-16) is not below (0, 0)
    first = np.lexsort((key[:, 0], key[:, 1]))[0]
    return np.roll(coords, -first, axis=0)


def test_a_pillar_in_a_room() -> None:
    # from (2, 5) the rays past the pillar's near corners (4, 4) and (4, 6), of slopes -1/2 and 1/2, meet the far
    # wall x = 10 at y = 1 and y = 9: the room's corners, then the shadow's edges in to the pillar's near face
    got = visibility_polygon_coords([ROOM, PILLAR], 2.0, 5.0, 1e-9)
    want = np.array([[0, 0], [10, 0], [10, 1], [4, 4], [4, 6], [10, 9], [10, 10], [0, 10]], dtype=float)
    assert got.dtype == np.float64 and got.flags.c_contiguous
    np.testing.assert_allclose(starting_at_lowest(got), want, atol=1e-12)
    assert shapely.LinearRing(got).is_ccw


def test_an_l_shaped_room_without_holes() -> None:
    # from (9, 1), in the foot of an L, the ray past the inner corner (2, 2) meets the wall x = 0 at y = 1 + 9/7
    room = np.array([[0, 0], [10, 0], [10, 2], [2, 2], [2, 10], [0, 10]], dtype=float)
    got = visibility_polygon_coords([room], 9.0, 1.0, 1e-9)
    want = np.array([[0, 0], [10, 0], [10, 2], [2, 2], [0, 1 + 9 / 7]])
    np.testing.assert_allclose(starting_at_lowest(got), want, atol=1e-12)
    # from the corner of the L everything is seen
    np.testing.assert_allclose(starting_at_lowest(visibility_polygon_coords([room], 1.0, 1.0, 1e-9)), room, atol=1e-12)


@pytest.mark.parametrize("shift", [0.0, 4096.0, -1024.0 * 600])
def test_a_row_of_pillars_moved_as_a_whole_moves_the_polygon(shift: float) -> None:
    # coordinates relative to a grid origin (the engine's), exact multiples of 1024 m: the same doubles after the shift
    pillars = [PILLAR + np.array([dx, 0.0]) for dx in (0.0, 8.0, 16.0)]
    room = np.array([[-2.0, -2.0], [30.0, -2.0], [30.0, 12.0], [-2.0, 12.0]])
    here = visibility_polygon_coords([room, *pillars], 1.0, 5.0, 1e-9)
    moved = visibility_polygon_coords([room + shift, *(p + shift for p in pillars)], 1.0 + shift, 5.0 + shift, 1e-9)
    np.testing.assert_allclose(moved - shift, here, atol=1e-9 * max(1.0, abs(shift)))
    # the first pillar hides the two behind it: the polygon touches none of their vertices
    assert not any(np.isclose(here, corner).all(axis=1).any() for p in pillars[1:] for corner in p)


def test_an_environment_checks_itself() -> None:
    assert Environment([ROOM, PILLAR]).is_valid(1e-9)
    assert not Environment([ROOM[::-1], PILLAR]).is_valid(1e-9)  # outer boundary clockwise
    assert not Environment([ROOM, PILLAR[::-1]]).is_valid(1e-9)  # hole counter-clockwise
    assert not Environment([ROOM, PILLAR + np.array([20.0, 0.0])]).is_valid(1e-9)  # hole outside
    assert not Environment([ROOM, PILLAR, PILLAR + np.array([1.0, 0.0])]).is_valid(1e-9)  # holes overlap
    assert Environment([ROOM, PILLAR, PILLAR + np.array([-3.0, 0.0])]).h() == 2


def test_conversions_give_float64_arrays_in_order() -> None:
    assert vis_polygon(np.array([[0, 0], [2, 0], [0, 1]])).dtype == np.float64
    coords = np.arange(14, dtype=float).reshape(7, 2)
    first, second = vis_polygons_reversed(coords, np.array([0, 3, 7]), [1, 0])
    assert first.tolist() == coords[3:7][::-1].tolist() and second.tolist() == coords[:3][::-1].tolist()
    assert first.flags.c_contiguous and second.flags.c_contiguous


@pytest.mark.parametrize(
    ("vertices", "counts", "message"),
    [
        (b"", b"", "needs an outer boundary"),
        (ROOM.tobytes(), np.array([3], np.int64).tobytes(), "fewer vertices than given"),
        (ROOM.tobytes(), np.array([4, 3], np.int64).tobytes(), "more vertices than given"),
        (ROOM.tobytes(), np.array([2, 2], np.int64).tobytes(), "at least 3 vertices"),
        (ROOM.tobytes()[:-8], np.array([4], np.int64).tobytes(), "float64 (x, y) pairs"),
        (ROOM.tobytes(), np.array([4], np.int32).tobytes(), "counts int64"),
    ],
)
def test_malformed_arrays_are_refused(vertices: bytes, counts: bytes, message: str) -> None:
    with pytest.raises(ValueError, match=message.replace("(", r"\(").replace(")", r"\)")):
        _visilibity1.visibility_polygon(vertices, counts, 1.0, 1.0, 1e-9)
    with pytest.raises(ValueError):
        _visilibity1.environment_is_valid(vertices, counts, 1e-9)


def test_threads_sweep_at_once_and_agree() -> None:
    # the sweep runs without the GIL: threads share nothing and get each their own polygon
    rng = np.random.default_rng(5)
    pillars = [PILLAR * 0.5 + rng.uniform(0.0, 5.0, 2) * [1.0, 0.0] + [0.0, 2.0 * k] for k in range(4)]
    eyes = [(0.5, 0.5 + 0.25 * k) for k in range(32)]
    alone = [visibility_polygon_coords([ROOM, *pillars], x, y, 1e-9) for x, y in eyes]
    with ThreadPoolExecutor(4) as pool:
        together = list(pool.map(lambda eye: visibility_polygon_coords([ROOM, *pillars], *eye, 1e-9), eyes))
    assert all(np.array_equal(a, b) for a, b in zip(alone, together, strict=True))
