"""The exact box engine against paper answers and an independent Monte Carlo ray count."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from omega_prime_visibility.engines.silhouette3d import box_visibility, solid_angle, view_regions
from omega_prime_visibility.threed.boxes import frames, ray_entries

EYE = np.array([0.0, 0.0, 1.25])


def corner_rect(a: float, b: float, d: float) -> float:
    """Solid angle of the rectangle [0, a] x [0, b] in a plane at distance d, one corner at the foot point."""
    return math.atan(a * b / (d * math.sqrt(a * a + b * b + d * d)))


def rect(y0: float, y1: float, z0: float, z1: float, d: float) -> float:
    """Solid angle of the rectangle y0..y1, z0..z1 (relative to the eye) in the plane x = d (signed parts)."""

    def signed(y: float, z: float) -> float:
        return math.copysign(1, y) * math.copysign(1, z) * corner_rect(abs(y), abs(z), d)

    return signed(y1, z1) - signed(y0, z1) - signed(y1, z0) + signed(y0, z0)


def box(x, y, z, length, width, height, roll=0.0, pitch=0.0, yaw=0.0) -> list[float]:
    return [x, y, z, length, width, height, roll, pitch, yaw]


def test_face_on_plate_has_the_rectangle_solid_angle() -> None:
    plate = box(10.0, 0, 1.25, 0.01, 2, 1.5)  # the eye on its axis sees only its 2 x 1.5 front face
    _, extent, _, _, _ = box_visibility(np.array([plate]), EYE)
    assert extent[0] == pytest.approx(4 * corner_rect(1.0, 0.75, 9.995), rel=1e-12)


def test_cube_faces_add_up_to_the_sphere() -> None:
    assert sum(solid_angle(shapely.box(-1, -1, 1, 1)) for _ in range(6)) == pytest.approx(4 * math.pi, rel=1e-14)


def test_low_car_behind_taller_car_is_hidden() -> None:
    boxes = np.array([box(10.0, 0, 0.9, 4.5, 2.0, 1.8), box(20.0, 0, 0.6, 4.0, 1.8, 1.2)])
    visible, extent, occ, _, _ = box_visibility(boxes, EYE)
    assert visible[1] == 0.0 and extent[1] > 0 and occ[1] == [0]


def test_truck_behind_low_car_is_visible_above_it() -> None:
    car = box(10.0, 0, 0.75, 4, 2, 1.5)  # rear face at x = 8, top 1.5 m: hides the truck up to 1.75 m
    truck = box(20.0, 0, 2.0, 8, 2.5, 4.0)  # rear face at x = 16, 2.5 m wide, 4 m high
    visible, extent, occ, _, _ = box_visibility(np.array([car, truck]), EYE)
    # paper: the car's top edge (z = 1.5 at x = 8) meets the truck's face at z = 1.25 + 0.25 * 16 / 8 = 1.75
    assert extent[1] == pytest.approx(rect(-1.25, 1.25, -1.25, 2.75, 16), rel=1e-12)
    assert visible[1] == pytest.approx(rect(-1.25, 1.25, 0.5, 2.75, 16), rel=1e-12)
    assert occ == [[], [0]]


def test_pedestrian_head_visible_over_a_low_wall() -> None:
    wall = box(5.0, 0, 0.5, 0.2, 4, 1.0)  # top edge seen at x = 5.1, z = 1.0
    walker = box(10.0, 0, 0.9, 0.5, 0.5, 1.8)  # front face at x = 9.75
    visible, extent, _, _, _ = box_visibility(np.array([wall, walker]), EYE)
    cut = 1.25 - 0.25 * 9.75 / 5.1
    assert visible[1] / extent[1] == pytest.approx(
        rect(-0.25, 0.25, cut - 1.25, 0.55, 9.75) / rect(-0.25, 0.25, -1.25, 0.55, 9.75), rel=1e-10
    )


def test_rolled_and_pitched_boxes_equal_their_turned_twins() -> None:
    occluder = box(6.0, 0.3, 0.6, 1, 1, 1.2)
    for turned, twin in [
        (box(15.0, 0.5, 1.0, 4, 2.0, 0.5, roll=math.pi / 2), box(15.0, 0.5, 1.0, 4, 0.5, 2.0)),
        (box(15.0, 0.5, 2.0, 4, 2.0, 1.0, pitch=-math.pi / 2), box(15.0, 0.5, 2.0, 1.0, 2.0, 4)),
    ]:
        a = box_visibility(np.array([occluder, turned]), EYE)
        b = box_visibility(np.array([occluder, twin]), EYE)
        assert a[0][1] == pytest.approx(b[0][1], rel=1e-9) and a[1][1] == pytest.approx(b[1][1], rel=1e-9)
        assert 0 < a[0][1] < a[1][1]


def test_roll_about_the_line_of_sight_keeps_the_solid_angle() -> None:
    flat = box(10.0, 0, 1.25, 0.01, 2, 1.0)
    rolled = box(10.0, 0, 1.25, 0.01, 2, 1.0, roll=0.4)
    assert box_visibility(np.array([rolled]), EYE)[1][0] == pytest.approx(
        box_visibility(np.array([flat]), EYE)[1][0], rel=1e-12
    )


def test_eye_inside_a_box() -> None:
    boxes = np.array([box(0.0, 0, 0.75, 4.5, 1.8, 1.5), box(10.0, 0, 0.75, 4, 2, 1.5)])
    visible, extent, occ, transparent, _ = box_visibility(boxes, EYE)
    assert transparent.tolist() == [True, False]
    assert visible[1] == extent[1] > 0 and occ[1] == []


def test_beyond_range_and_above_the_view() -> None:
    boxes = np.array([box(80.0, 0, 0.75, 4, 2, 1.5), box(20.0, 0, 10.0, 1, 3, 1)])  # far car, overhead sign
    vis, ext, _, _, in_fov = box_visibility(boxes, EYE, max_range=50.0)
    assert vis[0] == 0.0 and ext[0] > 0 and vis[1] == ext[1] > 0
    vis, ext, _, _, in_fov = box_visibility(boxes, EYE, view=(0.0, math.pi, math.radians(-10), math.radians(10)))
    assert vis[1] == 0.0 and in_fov[1] == 0.0 and vis[0] == pytest.approx(ext[0], rel=1e-12)
    with pytest.raises(ValueError, match=r"range of 79\.0 m cuts box"):
        box_visibility(boxes, EYE, max_range=79.0)


def test_view_limits_cut_a_symmetric_box_in_half() -> None:
    target = np.array([box(10.0, 0, 1.25, 2, 2, 2)])  # symmetric about y = 0 and about the eye's height
    _, ext, _, _, _ = box_visibility(target, EYE)
    vis, _, _, _, _ = box_visibility(target, EYE, view=(-math.pi / 4, math.pi / 4, -math.pi / 2, math.pi / 2))
    assert vis[0] == pytest.approx(ext[0] / 2, rel=1e-12)  # horizontal limit along +x: exact
    vis, _, _, _, _ = box_visibility(target, EYE, view=(0.0, math.pi, 0.0, math.pi / 2))
    assert vis[0] == pytest.approx(ext[0] / 2, rel=1e-6)  # elevation limit at 0: polygonised cone


def test_view_regions_measure_the_band() -> None:
    low, high = math.radians(-20), math.radians(35)
    total = sum(solid_angle(r) for r in view_regions(0.0, math.pi, low, high))
    assert total == pytest.approx(2 * math.pi * (math.sin(high) - math.sin(low)), rel=1e-6)
    wedge = sum(solid_angle(r) for r in view_regions(1.0, math.radians(60), -math.pi / 2, math.pi / 2))
    assert wedge == pytest.approx(4 * math.pi * 120 / 360, rel=1e-12)


def disjoint_boxes(rng: np.random.Generator, n: int) -> np.ndarray:
    out: list[np.ndarray] = []
    while len(out) < n:
        centre = np.array([rng.uniform(3, 15), rng.uniform(-6, 6), rng.uniform(0, 3)])
        size = rng.uniform([1, 1, 0.5], [4, 3, 3])
        radius = np.linalg.norm(size) / 2
        if np.linalg.norm(centre - EYE) > radius and all(
            np.linalg.norm(centre - b[:3]) > radius + np.linalg.norm(b[3:6]) / 2 for b in out
        ):
            out.append(np.r_[centre, size, rng.uniform(-1, 1, 2), rng.uniform(-3, 3)])
    return np.array(out)


def monte_carlo(boxes: np.ndarray, target: int, n: int, rng: np.random.Generator) -> tuple[float, int]:
    """Share of uniformly random directions in a cap around the target's bounding sphere that see it first."""
    centre, rot, half = frames(boxes)
    axis = centre[target] - EYE
    dist = np.linalg.norm(axis)
    cos_cap = math.cos(math.asin(min(1.0, np.linalg.norm(half[target]) / dist)))
    z = rng.uniform(cos_cap, 1, n)
    phi = rng.uniform(0, 2 * math.pi, n)
    s = np.sqrt(1 - z * z)
    a = axis / dist
    t = np.cross(a, [0.0, 0, 1])
    t /= np.linalg.norm(t)
    dirs = (s * np.cos(phi))[:, None] * t + (s * np.sin(phi))[:, None] * np.cross(a, t) + z[:, None] * a
    hits = np.stack([ray_entries(EYE, dirs, centre, rot, half, np.full(n, k)) for k in range(len(boxes))])
    on_target = np.isfinite(hits[target])
    return float((on_target & (hits.argmin(axis=0) == target)).sum() / on_target.sum()), int(on_target.sum())


def test_random_disjoint_scenes_agree_with_monte_carlo() -> None:
    rng = np.random.default_rng(7)
    for _ in range(3):
        boxes = disjoint_boxes(rng, 6)
        visible, extent, _, _, _ = box_visibility(boxes, EYE)
        for k in range(len(boxes)):
            share, count = monte_carlo(boxes, k, 100_000, rng)
            sigma = max(math.sqrt(share * (1 - share) / count), 1 / count)
            assert visible[k] / extent[k] == pytest.approx(share, abs=5 * sigma + 1e-9)


def test_boxes_across_cube_faces_agree_with_monte_carlo() -> None:
    # the first box holds the direction (1, 1, 1) from the eye, a corner of three cube faces; the second straddles
    # the +x/+y boundary behind it; the third is near the eye and wraps around more than 90°
    boxes = np.array(
        [
            box(3.0, 3, 4.25, 2, 2, 2, yaw=0.3),
            box(6.0, 6.5, 5.5, 3, 2, 4, roll=0.2),
            box(-1.5, -2.0, 1.0, 2, 1.5, 2.0),
            box(-6.0, -5.0, 3.0, 3, 3, 3),
        ]
    )
    visible, extent, occ, _, _ = box_visibility(boxes, EYE)
    rng = np.random.default_rng(3)
    for k in range(len(boxes)):
        share, count = monte_carlo(boxes, k, 200_000, rng)
        sigma = max(math.sqrt(share * (1 - share) / count), 1 / count)
        assert visible[k] / extent[k] == pytest.approx(share, abs=5 * sigma + 1e-9)
    assert 0 < visible[1] < extent[1] and occ[1] == [0]
    assert 0 < visible[3] < extent[3] and occ[3] == [2]


def test_a_range_cutting_a_box_falls_back_on_the_ray_engine_for_that_viewpoint() -> None:
    # a car along x at 77 to 81 m, seen from 15 m to the side through a 79 m range: its near side runs from 78.3 to
    # 82.2 m, so the range cuts it. No longer refused: that viewpoint is the default ray engine's, row for row (part
    # of the side lies beyond the range); a wider range keeps the exact answer
    import polars as pl

    from omega_prime_visibility import Sensor, get_visibility_df

    table = pl.DataFrame(
        {"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, 79.0], "y": [-15.0, 0.0],
         "z": [0.75, 0.75], "length": [4.5, 4.0], "width": [1.8, 2.0], "height": [1.5, 1.5], "roll": [0.0, 0.0],
         "pitch": [0.0, 0.0], "yaw": [0.0, 0.0]}
    )  # fmt: skip
    cut = [Sensor("far", range=79.0)]
    exact = get_visibility_df(table, 0, mode="3d", engine="silhouette3d", sensors=cut, progress=False)
    rays = get_visibility_df(table, 0, mode="3d", engine="raycast3d", sensors=cut, progress=False)
    assert exact.equals(rays)
    assert 0.0 < exact["visibility"][0] < 1.0 and exact["status"][0] == "partly_visible"
    wide = get_visibility_df(table, 0, mode="3d", engine="silhouette3d", sensors=[Sensor("far", range=90.0)])
    assert wide["visibility"][0] == 1.0
