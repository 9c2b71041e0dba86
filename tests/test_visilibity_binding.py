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
from omega_prime_visibility.engines.visilibity.polygon_check import (
    CHECK_ABSOLUTE,
    CHECK_RELATIVE,
    ON_EDGE,
    polygon_fails,
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


def ray_ranges(eye: np.ndarray, rings: list[np.ndarray], bearings: np.ndarray) -> np.ndarray:
    """Brute force: the range (metres) from ``eye`` to the nearest edge of ``rings`` along each bearing (radians)."""
    a = np.concatenate([r for r in rings]) - eye
    b = np.concatenate([np.roll(r, -1, axis=0) for r in rings]) - eye
    d = np.stack([np.cos(bearings), np.sin(bearings)], axis=1)[:, None, :]
    edge = (b - a)[None]
    den = d[..., 0] * edge[..., 1] - d[..., 1] * edge[..., 0]
    with np.errstate(divide="ignore", invalid="ignore"):
        t = (a[None, :, 0] * edge[..., 1] - a[None, :, 1] * edge[..., 0]) / den
        s = (a[None, :, 0] * d[..., 1] - a[None, :, 1] * d[..., 0]) / den
    hit = (t > 1e-9) & (s >= 0.0) & (s <= 1.0)
    return np.where(hit, t, np.inf).min(axis=1)


def assert_nearest_everywhere(eye: np.ndarray, outer: np.ndarray, holes: list[np.ndarray], seed: int = 0) -> None:
    """VisiLibity's polygon from ``eye`` passes the engine's exact check and, along 2,000 random bearings, ends
    where a brute-force ray cast meets the nearest body."""
    polygon = visibility_polygon_coords([outer, *holes], float(eye[0]), float(eye[1]), 1e-9)
    edges = [np.stack([h - eye, np.roll(h, -1, axis=0) - eye], axis=1) for h in holes]
    segments = np.ascontiguousarray(np.concatenate(edges))
    blocking = np.ones(len(segments), dtype=bool)
    assert not polygon_fails(
        np.ascontiguousarray(polygon - eye), segments, blocking, CHECK_ABSOLUTE, CHECK_RELATIVE, ON_EDGE
    )
    bearings = np.random.default_rng(seed).uniform(-np.pi, np.pi, 2000)
    np.testing.assert_allclose(
        ray_ranges(eye, [polygon], bearings), ray_ranges(eye, [outer, *holes], bearings), rtol=0, atol=1e-7
    )


def test_the_sweep_takes_the_nearest_edge_after_passing_others() -> None:
    # From the urban junction (scenarios/urban.py), cut down to the five bodies that matter: two parked cars, a
    # pedestrian (0.5 m) behind them and a building front. VisiLibity 1.0.10's sweep, its edge queue ordered at
    # earlier bearings, took the building's edge for the nearest and left the pedestrian out (13 vertices instead
    # of 15); the patched queue (native/visilibity.cpp, Edge_Queue) is reordered at each such event.
    eye = np.array([-27.75, -1.75])
    outer = np.array([[-100.14063152109962, -92.5], [82.5, -92.5], [82.5, 92.5], [-100.14063152109962, 92.5]])
    x1, x2 = -23.808516122699938, -28.00861912967278
    holes = [
        np.array([[-15.5, 7.35], [-20.0, 7.35], [-20.0, 9.15], [-15.5, 9.15]]),
        np.array([[x1, 7.35], [x1 - 4.5, 7.35], [x1 - 4.5, 9.15], [x1, 9.15]]),
        np.array([[x2, 10.2], [x2 - 0.5, 10.2], [x2 - 0.5, 10.7], [x2, 10.7]]),
        np.array([[-42.5, 12.5], [-42.5, 38.5], [-12.5, 38.5], [-12.5, 12.5]]),
        np.array([[12.5, 72.5], [12.5, 82.5], [24.5, 82.5], [24.5, 72.5]]),
    ]
    assert Environment([outer, *holes]).is_valid(1e-9)
    assert len(visibility_polygon_coords([outer, *holes], *eye, 1e-9)) == 15
    assert_nearest_everywhere(eye, outer, holes)


def street(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, list[np.ndarray]]:
    """A random street as the town has them: rows of parked cars (4.5 x 1.8 m) on both sides, pedestrians
    (0.5 m) on the sidewalks behind them, building fronts beyond; the eye in the carriageway. Holes clockwise."""
    boxes = []
    for side in (-1.0, 1.0):
        x = rng.uniform(-40.0, -30.0)
        while x < 40.0:
            boxes.append((x, side * 4.2, 4.5, 1.8))
            x += 4.5 + rng.uniform(0.3, 6.0)
        for x in rng.uniform(-40.0, 40.0, 6):
            boxes.append((x, side * rng.uniform(6.0, 8.5), 0.5, 0.5))
        boxes.append((rng.uniform(-45.0, -5.0), side * 15.0, 30.0, 10.0))
        boxes.append((rng.uniform(5.0, 30.0), side * 14.0, 20.0, 8.0))
    rings, kept = [], []
    for cx, cy, length, width in boxes:
        body = shapely.box(cx - length / 2, cy - width / 2, cx + length / 2, cy + width / 2)
        if all(not body.buffer(0.05).intersects(k) for k in kept):
            kept.append(body)
            rings.append(
                np.asarray(body.exterior.coords)[:-1][::-1]
                if body.exterior.is_ccw
                else np.asarray(body.exterior.coords)[:-1]
            )
    outer = np.array([[-120.0, -120.0], [120.0, -120.0], [120.0, 120.0], [-120.0, 120.0]])
    eye = np.array([rng.uniform(-20.0, 20.0), rng.uniform(-1.5, 1.5)])
    return eye, outer, rings


@pytest.mark.parametrize("seed", range(40))
def test_the_nearest_body_bounds_the_polygon_on_random_streets(seed: int) -> None:
    eye, outer, holes = street(np.random.default_rng(seed))
    assert Environment([outer, *holes]).is_valid(1e-9)
    assert_nearest_everywhere(eye, outer, holes, seed)


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
