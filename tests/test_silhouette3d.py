"""The exact box engine against paper answers and an independent Monte Carlo ray count."""

from __future__ import annotations

import math

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import cap_directions

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.engines.silhouette3d import box_visibility
from omega_prime_visibility.threed.bodies import prisms_from_footprints
from omega_prime_visibility.threed.boxes import frames, ray_entries
from omega_prime_visibility.threed.cube import SQUARE, solid_angles, view_regions

EYE = np.array([0.0, 0.0, 1.25])


def solid_angle(region: shapely.Geometry | None) -> float:
    """A face's region measured, None standing for the whole face."""
    return float(solid_angles([SQUARE if region is None else region])[0])


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
    vis, ext, _, _, _ = box_visibility(boxes, EYE, max_range=79.0)  # its whole rear face lies within 79 m
    assert vis[0] == pytest.approx(ext[0], rel=1e-12) and vis[1] == ext[1]
    vis, ext, _, _, _ = box_visibility(boxes, EYE, max_range=78.005)  # a disc of 0.88 m around the foot at 78 m
    assert 0.0 < vis[0] < ext[0] and vis[1] == ext[1]


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


def monte_carlo(
    boxes: np.ndarray,
    target: int,
    n: int,
    rng: np.random.Generator,
    max_range: float = math.inf,
    eye: np.ndarray = EYE,
) -> tuple[float, int]:
    """Share of uniformly random directions in a cap around the target's bounding sphere that see it first
    (entered within ``max_range``), among those that hit it."""
    centre, rot, half = frames(boxes)
    dirs = cap_directions(centre[target], np.linalg.norm(half[target]), eye, n, rng)
    hits = np.stack([ray_entries(eye, dirs, centre, rot, half, np.full(n, k)) for k in range(len(boxes))])
    on_target = np.isfinite(hits[target])
    # ties are visible (the definition): nothing entered nearer by more than 1e-9 of the distance
    seen = on_target & (hits.min(axis=0) >= hits[target] * (1 - 1e-9)) & (hits[target] <= max_range)
    return float(seen.sum() / on_target.sum()), int(on_target.sum())


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


def test_a_range_cutting_a_wide_wall_leaves_a_cone() -> None:
    # a 40 m x 40 m face at 10 m straight ahead, range 12 m: the directions entering it within range form the cone
    # of half-angle acos(10 / 12) around the perpendicular (paper: 2 pi (1 - 10 / 12) steradians)
    wall = np.array([box(10.5, 0, 1.25, 1.0, 40, 40)])
    visible, extent, _, _, in_fov = box_visibility(wall, EYE, max_range=12.0)
    assert extent[0] == pytest.approx(rect(-20, 20, -20, 20, 10), rel=1e-12) and in_fov[0] == extent[0]
    assert visible[0] == pytest.approx(2 * math.pi * (1 - 10 / 12), rel=2e-6)


@pytest.mark.parametrize("seed", range(4))
def test_boxes_straddling_the_range_agree_with_monte_carlo(seed: int) -> None:
    # random boxes, the range through the middle of the target (row 0): directions count only where the target
    # is entered within range, others in front of it still block
    rng = np.random.default_rng(seed)
    boxes = disjoint_boxes(rng, 5)
    centre = frames(boxes)[0]
    max_range = float(np.linalg.norm(centre[0] - EYE))
    visible, extent, _, _, _ = box_visibility(boxes, EYE, max_range=max_range)
    share, count = monte_carlo(boxes, 0, 200_000, rng, max_range=max_range)
    sigma = max(math.sqrt(share * (1 - share) / count), 1 / count)
    assert visible[0] / extent[0] == pytest.approx(share, abs=5 * sigma + 1e-6)


def test_a_range_cutting_a_box_is_exact_in_the_table() -> None:
    # a car along x at 77 to 81 m, seen from 15 m to the side through a 79 m range: its near side runs from 78.3 to
    # 82.2 m, so the range cuts it: the exact engine measures it (no fallback), the ray engine agrees within its
    # sampling error, and a wider range sees all of it
    import polars as pl

    from omega_prime_visibility import Sensor, get_visibility_df

    table = pl.DataFrame(
        {"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, 79.0], "y": [-15.0, 0.0],
         "z": [0.75, 0.75], "length": [4.5, 4.0], "width": [1.8, 2.0], "height": [1.5, 1.5], "roll": [0.0, 0.0],
         "pitch": [0.0, 0.0], "yaw": [0.0, 0.0]}
    )  # fmt: skip
    cut = [Sensor("far", range=79.0)]
    exact = get_visibility_df(table, 0, mode="3d", engine="silhouette3d", sensors=cut, progress=False)
    rays = get_visibility_df(table, 0, mode="3d", engine="raycast3d-high", sensors=cut, progress=False)
    assert 0.0 < exact["visibility"][0] < 1.0 and exact["status"][0] == "partly_visible"
    assert exact["visibility"][0] == pytest.approx(rays["visibility"][0], abs=0.02)
    boxes = np.array([[79.0, 0.0, 0.75, 4.0, 2.0, 1.5, 0, 0, 0]])
    eye = np.array([0.0, -15.0, 1.25])
    rng = np.random.default_rng(5)
    share, count = monte_carlo(boxes, 0, 400_000, rng, max_range=79.0, eye=eye)
    assert exact["visibility"][0] == pytest.approx(share, abs=5 * math.sqrt(share * (1 - share) / count))
    wide = get_visibility_df(table, 0, mode="3d", engine="silhouette3d", sensors=[Sensor("far", range=90.0)])
    assert wide["visibility"][0] == 1.0


def one_frame(boxes: list[list[float]]) -> pl.DataFrame:
    """One frame of 3D boxes (rows of :func:`box`), idx 0, 1, ...; idx 0 is the ego."""
    a = np.array(boxes, dtype=float)
    names = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")
    return pl.DataFrame(
        {"frame": np.zeros(len(a), np.int64), "total_nanos": np.zeros(len(a), np.int64),
         "idx": np.arange(len(a), dtype=np.int64), **{name: a[:, k] for k, name in enumerate(names)}}
    )  # fmt: skip


EGO_BOX = box(0.0, 0, 0.75, 4.5, 1.8, 1.5)  # eye at (0, 0, 1.25): its ground is z = 0


def test_a_car_seen_through_a_twelve_percent_strip_between_two_cars() -> None:
    # two 3 m tall cars (x 8..12) leave a gap |y| < g; the target's rear face (x = 30, |y| < 1, z 0..1.5) is seen
    # where |y| < g * 30 / 12 (the inner rear edges at x = 12 bound the rays), here |y| < 0.12
    g = 0.12 * 12 / 30
    left, right = box(10.0, g + 1, 1.5, 4, 2, 3.0), box(10.0, -g - 1, 1.5, 4, 2, 3.0)
    target = box(32.0, 0, 0.75, 4, 2, 1.5)
    paper = rect(-0.12, 0.12, -1.25, 0.25, 30) / rect(-1, 1, -1.25, 0.25, 30)
    visible, extent, occ, _, _ = box_visibility(np.array([left, right, target]), EYE)
    assert visible[2] / extent[2] == pytest.approx(paper, rel=1e-9) and occ[2] == [0, 1]
    out = get_visibility_df(one_frame([EGO_BOX, left, right, target]), 0, mode="3d", progress=False)
    row = out.filter(pl.col("idx") == 3)
    assert row["visibility"].item() == pytest.approx(paper, rel=1e-9) and row["can_see"].item()
    assert row["occluder_idxs"].item().to_list() == [1, 2]


def slotted_wall(centre: float, slot: float, x0: float = 40.0, depth: float = 0.2) -> shapely.MultiPolygon:
    """A wall x0..x0+depth, y -10..10, as one MultiPolygon with a slot |y - centre| < slot / 2."""
    return shapely.MultiPolygon(
        [shapely.box(x0, -10, x0 + depth, centre - slot / 2), shapely.box(x0, centre + slot / 2, x0 + depth, 10)]
    )


def test_a_slot_in_one_static_multipolygon_is_found_at_41_positions() -> None:
    # a car at 78..82 m behind a 3 m wall at 40..40.2 m with a slot whose visible strip on the car's rear face
    # (x = 78) is about 1 % of its width: rays through the slot reach y in [a * 78 / 40, b * 78 / 40.2] for a slot
    # [a, b] (a > 0; mirrored for b < 0); the car is seen through it at each of 41 positions across its width
    target = box(80.0, 0, 0.75, 4, 2, 1.5)
    frame = one_frame([EGO_BOX, target])
    slot = 0.0105
    for centre in np.linspace(-0.97, 0.97, 41) * 40 / 78:
        a, b = centre - slot / 2, centre + slot / 2
        lo = a * 78 / (40.0 if a > 0 else 40.2)
        hi = b * 78 / (40.2 if b > 0 else 40.0)
        lo, hi = max(lo, -1.0), min(hi, 1.0)
        paper = rect(lo, hi, -1.25, 0.25, 78) / rect(-1, 1, -1.25, 0.25, 78)
        out = get_visibility_df(
            frame, 0, [slotted_wall(centre, slot)], mode="3d", static_occluder_heights=[3.0], progress=False
        )
        assert out["can_see"].item(), centre
        assert out["visibility"].item() == pytest.approx(paper, rel=1e-8), centre
        assert out["static_occluder_idxs"].item().to_list() == [0]


def fan_solid_angle(points: np.ndarray, eye: np.ndarray) -> float:
    """Solid angle of a planar convex polygon seen from ``eye``: a fan of triangles, Van Oosterom and Strackee."""
    r = points - eye
    total = 0.0
    for k in range(1, len(r) - 1):
        a, b, c = r[0], r[k], r[k + 1]
        la, lb, lc = np.linalg.norm(a), np.linalg.norm(b), np.linalg.norm(c)
        num = abs(np.dot(a, np.cross(b, c)))
        den = la * lb * lc + np.dot(a, b) * lc + np.dot(a, c) * lb + np.dot(b, c) * la
        total += 2 * math.atan2(num, den)
    return total


def test_a_plate_behind_a_slotted_wall_seen_from_above() -> None:
    # Scenic's altitude case: an eye 8 m up looks down over a 5 m wall (x 10..10.2) with a 1 m slot |y| < 0.5 at a
    # flat plate on the ground (x 14..16, |y| < 1, 5 cm high). Every ray to the plate passes the wall below 5 m, so
    # only the slot shows it: on the plate's top (z = 0.05) the part |y| <= 0.5 x / 10.2, on its front face (x = 14)
    # the part |y| <= 0.5 * 14 / 10.2; paper answer by a fan of exact spherical triangles over those polygons
    eye = np.array([0.0, 0.0, 8.0])
    wall = prisms_from_footprints([slotted_wall(0.0, 1.0, x0=10.0)], tops=[5.0], bases=[-1.0])
    plate = np.array([box(15.0, 0, 0.025, 2, 2, 0.05)])
    w14, w16 = 0.5 * 14 / 10.2, 0.5 * 16 / 10.2
    top = np.array([[14, -w14, 0.05], [16, -w16, 0.05], [16, w16, 0.05], [14, w14, 0.05]])
    front = np.array([[14, -w14, 0.0], [14, w14, 0.0], [14, w14, 0.05], [14, -w14, 0.05]])
    top_all = np.array([[14, -1, 0.05], [16, -1, 0.05], [16, 1, 0.05], [14, 1, 0.05]])
    front_all = np.array([[14, -1, 0.0], [14, 1, 0.0], [14, 1, 0.05], [14, -1, 0.05]])
    visible, extent, _, _, _ = box_visibility(plate, eye, statics=wall)
    assert extent[0] == pytest.approx(fan_solid_angle(top_all, eye) + fan_solid_angle(front_all, eye), rel=1e-12)
    assert visible[0] == pytest.approx(fan_solid_angle(top, eye) + fan_solid_angle(front, eye), rel=1e-9)
    closed = prisms_from_footprints([shapely.box(10.0, -10, 10.2, 10)], tops=[5.0], bases=[-1.0])
    assert box_visibility(plate, eye, statics=closed)[0][0] == 0.0


def test_an_occluder_of_the_part_out_of_view_is_not_listed() -> None:
    # a view of ±40° about +x; the target (x 19..21, y 15..25: bearings 38.3° to 52.8°) straddles its left edge; a
    # post at x 9.9..10.1, y 8.7..9.5 (bearings 40.7° to 43.8°) hides only directions out of view: the target is
    # hidden nowhere in view and the post is not its occluder; a post at y 7..8.2 (34.7° to 39.6°) is
    target = box(20.0, 20.0, 1.25, 2, 10, 4)
    view = (0.0, math.radians(40), -math.pi / 2, math.pi / 2)
    out_of_view = box(10.0, 9.1, 1.25, 0.2, 0.8, 6)
    visible, extent, occ, _, in_fov = box_visibility(np.array([out_of_view, target]), EYE, view=view)
    assert visible[1] == pytest.approx(in_fov[1], rel=1e-12) and 0 < in_fov[1] < extent[1] and occ[1] == []
    in_view = box(10.0, 7.6, 1.25, 0.2, 1.2, 6)
    visible, _, occ, _, in_fov = box_visibility(np.array([in_view, target]), EYE, view=view)
    assert 0 < visible[1] < in_fov[1] and occ[1] == [0]


def test_two_plates_crossing_in_an_x() -> None:
    # a plate across the line of sight at x = 10 (y -1..1) and one slanted through it, from (9, -1) to (11, 1), both
    # 2.5 m high about the eye's height: right of the crossing (y < 0) the slanted one is nearer and, being nearer,
    # covers the first plate's height there; left of it the first plate is nearer. So the first plate is seen
    # exactly on its left half (the solid angle of y 0..1), and each lists the other
    thin = 1e-4
    boxes = np.array([box(10, 0, 1.25, thin, 2, 2.5), box(10, 0, 1.25, 2 * math.sqrt(2), thin, 2.5, yaw=math.pi / 4)])
    visible, extent, occ, _, _ = box_visibility(boxes, EYE)
    assert visible[0] == pytest.approx(rect(0, 1, -1.25, 1.25, 10 - thin / 2), rel=1e-3)
    assert visible[0] / extent[0] == pytest.approx(0.5, abs=1e-4)
    assert occ == [[1], [0]]
    rng = np.random.default_rng(11)
    share, count = monte_carlo(boxes, 1, 200_000, rng)
    assert visible[1] / extent[1] == pytest.approx(share, abs=5 * math.sqrt(share * (1 - share) / count))


@pytest.mark.parametrize("seed", range(3))
def test_random_overlapping_boxes_agree_with_monte_carlo(seed: int) -> None:
    # double detections and bodies pushed into each other: each second box is a copy of an earlier one moved by
    # less than its size and turned, so the two overlap; orders change across their common silhouette
    rng = np.random.default_rng(40 + seed)
    boxes = list(disjoint_boxes(rng, 4))
    for k in range(4):
        twin = boxes[k].copy()
        twin[:3] += rng.uniform(-0.4, 0.4, 3) * boxes[k][3:6]
        twin[6:] += rng.uniform(-0.6, 0.6, 3)
        boxes.append(twin)
    boxes = np.array(boxes)
    visible, extent, occ, _, _ = box_visibility(boxes, EYE)
    for k in range(len(boxes)):
        share, count = monte_carlo(boxes, k, 100_000, rng)
        sigma = max(math.sqrt(share * (1 - share) / count), 1 / count)
        assert visible[k] / extent[k] == pytest.approx(share, abs=5 * sigma + 1e-9), k
    assert all(k + 4 in occ[k] or k in occ[k + 4] for k in range(4))  # each twin hides part of its original


def test_a_car_wholly_behind_a_truck_on_a_seam_of_the_cube_is_not_seen() -> None:
    # at a bearing of about 225° the outlines cross the seam of two cube faces; subtracting silhouettes that share
    # edges there left a residue of 5e-16, which read as can_see
    boxes = np.array(
        [
            box(0.0, 0.0, 0.75, 4.5, 1.8, 1.5),
            box(-8.909397157243445, -9.43376115560983, 2.0, 12.0, 2.5, 4.0, 0.04222857559794996, 0.08641193732267566,
                5.372338767165881),
            box(-25.86163891396498, -27.383729819319804, 0.75, 4.5, 1.8, 1.5, yaw=1.3740907024578561),
        ]
    )  # fmt: skip
    table = pl.DataFrame(
        {"frame": [0] * 3, "total_nanos": [0] * 3, "idx": [0, 1, 2]}
        | {
            name: boxes[:, k]
            for k, name in enumerate(["x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw"])
        }
    )
    out = get_visibility_df(table, 0, mode="3d", progress=False).filter(pl.col("idx") == 2)
    assert out.select("occluder_idxs", "visibility", "can_see").rows() == [([1], 0.0, False)]
    with_sensors = get_visibility_df(table, 0, mode="3d", sensors="roof", progress=False).filter(pl.col("idx") == 2)
    assert with_sensors["status"].to_list() == ["occluded"]


# Ties: bodies sharing a face plane (a double detection, a box inside another against one of its faces, cars of
# equal height whose roofs meet) are each the first thing hit there, as in 2D; shared edges and corners are ordered
# exactly. Every 3D engine: the exact one, and the ray engine, whose sampled path runs where a mesh is in the scene.
ENGINES_3D = ["silhouette3d", "raycast3d", "raycast3d with a mesh"]


def table_3d(boxes, engine: str, tmp_path, eye_height: float = 1.25) -> pl.DataFrame:
    """The 3D table of one frame of ``boxes`` seen from an ego (idx 0) whose eye is at ``(0, 0, eye_height)``."""
    ego = box(0.0, 0, eye_height - 0.75, 4.5, 1.8, 1.0)  # its ground 1.25 m under the eye
    extra = {}
    if engine == "raycast3d with a mesh":  # far behind the ego: the sampled path runs, the mesh hides nothing
        import trimesh

        path = tmp_path / "far.stl"
        trimesh.creation.box(extents=(1, 1, 1)).apply_translation((-500, 0, 0.5)).export(path)
        extra = {"static_meshes": [path]}
    name = engine.split()[0]
    return get_visibility_df(one_frame([ego, *boxes]), 0, mode="3d", engine=name, progress=False, **extra)


def reference_shares(boxes, eye_height: float = 1.25, n: int = 100_000, seed: int = 0) -> list[tuple[float, float]]:
    """Per box, the Monte Carlo share seen (ties visible) and its standard error."""
    rng = np.random.default_rng(seed)
    out = []
    for k in range(len(boxes)):
        share, count = monte_carlo(np.array(boxes, float), k, n, rng, eye=np.array([0.0, 0.0, eye_height]))
        out.append((share, max(math.sqrt(share * (1 - share) / count), 1 / count)))
    return out


def turned(rng: np.random.Generator, near: float = 8.0, far: float = 25.0) -> np.ndarray:
    """A random box ahead of the eye, turned about all three axes."""
    bearing, dist = rng.uniform(-1.2, 1.2), rng.uniform(near, far)
    return np.r_[dist * math.cos(bearing), dist * math.sin(bearing), rng.uniform(0.3, 2.5),
                 rng.uniform([1, 1, 0.5], [5, 3, 3]), rng.uniform(-0.6, 0.6, 2), rng.uniform(-3, 3)]  # fmt: skip


def sharing_faces(b: np.ndarray, axis: int, shrink: float, side: int) -> np.ndarray:
    """``b`` made shorter along its own ``axis`` (0 length, 1 width, 2 height) by the factor ``shrink``, kept
    against its face on ``side`` (+1 or -1): the two share the other four face planes and that face's plane."""
    _, rot, _ = frames(b[None])
    inner = b.copy()
    inner[3 + axis] *= shrink
    inner[:3] += side * (b[3 + axis] - inner[3 + axis]) / 2 * rot[0][:, axis]
    return inner


@pytest.mark.parametrize("engine", ENGINES_3D)
def test_a_double_detection_hides_nothing_of_itself(engine, tmp_path) -> None:
    # the example: two cars of one box 12 m ahead; each is the first thing hit wherever it is hit
    car = box(12.0, 0, 0.75, 4.5, 1.8, 1.5)
    out = table_3d([car, car], engine, tmp_path)
    assert out.select("idx", "visibility", "can_see", "occluder_idxs").rows() == [
        (1, 1.0, True, []),
        (2, 1.0, True, []),
    ]


@pytest.mark.parametrize("engine", ENGINES_3D)
def test_double_detections_of_every_orientation_are_fully_seen(engine, tmp_path) -> None:
    rng = np.random.default_rng(11)
    for _ in range(6):
        b = turned(rng)
        out = table_3d([b, b], engine, tmp_path, eye_height=rng.uniform(1.0, 20.0))
        assert out["visibility"].to_list() == [1.0, 1.0], b.tolist()
        assert out["occluder_idxs"].to_list() == [[], []]


@pytest.mark.parametrize("engine", ENGINES_3D)
def test_overlapping_cars_of_equal_height_seen_from_above(engine, tmp_path) -> None:
    # from 22 m up, two overlapping 1.5 m cars: where their roofs overlap, both are hit at once on the shared roof
    # plane (both seen); the second car's far part lies under nothing; the first car's near side is in front of
    # the second car's side where the second is lower in the image. The Monte Carlo count with ties decides.
    cars = [box(12.0, 0, 0.75, 4.5, 1.8, 1.5), box(13.0, 0.5, 0.75, 4.5, 1.8, 1.5)]
    out = table_3d(cars, engine, tmp_path, eye_height=22.0)
    for (share, sigma), got in zip(reference_shares(cars, 22.0), out["visibility"], strict=True):
        assert got == pytest.approx(share, abs=5 * sigma + 1e-9)
    assert out["visibility"][0] == 1.0  # nothing is in front of the nearer car anywhere


@pytest.mark.parametrize("engine", ENGINES_3D)
def test_boxes_sharing_face_planes_agree_with_monte_carlo(engine, tmp_path) -> None:
    # a box inside another against one of its faces (sharing five face planes), of every orientation, seen from
    # low and high eyes; against the facing side both are seen in full there, against the far side the inner box
    # is hidden wherever the outer's near face is in front
    rng = np.random.default_rng(5)
    for case in range(6):
        b = turned(rng)
        inner = sharing_faces(b, case % 3, rng.uniform(0.3, 0.8), 1 if case < 3 else -1)
        eye_height = rng.uniform(1.0, 15.0)
        out = table_3d([b, inner], engine, tmp_path, eye_height=eye_height)
        expected = reference_shares([b, inner], eye_height, seed=case)
        for k, ((share, sigma), got) in enumerate(zip(expected, out["visibility"], strict=True)):
            assert got == pytest.approx(share, abs=5 * sigma + 1e-9), (case, k, b.tolist())
        assert out["visibility"][0] == 1.0  # the outer box: nothing of it is behind the inner one


@pytest.mark.parametrize("engine", ENGINES_3D)
def test_boxes_sharing_an_edge_or_a_corner_are_ordered_exactly(engine, tmp_path) -> None:
    # cars touching face to face, along an edge (side by side, one ahead) and at a corner (diagonal neighbours,
    # one stacked on the other): the one in front hides the other where it is nearer, both seen elsewhere
    cases = [
        [box(12.0, 0, 0.75, 4.0, 2.0, 1.5), box(16.0, 0, 0.75, 4.0, 2.0, 1.5)],  # face to face, one behind
        [box(12.0, 1.0, 0.75, 4.0, 2.0, 1.5), box(16.0, -1.0, 0.75, 4.0, 2.0, 1.5)],  # along an edge
        [box(12.0, 1.0, 0.75, 4.0, 2.0, 1.5), box(16.0, -1.0, 2.25, 4.0, 2.0, 1.5)],  # at a corner
        [box(12.0, 1.0, 0.75, 4.0, 2.0, 1.5, yaw=0.4), box(12.0, 1.0, 2.25, 4.0, 2.0, 1.5, yaw=0.4)],  # stacked
    ]
    for k, boxes in enumerate(cases):
        for eye_height in (1.25, 6.0):
            out = table_3d(boxes, engine, tmp_path, eye_height=eye_height)
            expected = reference_shares(boxes, eye_height, seed=k)
            for (share, sigma), got in zip(expected, out["visibility"], strict=True):
                assert got == pytest.approx(share, abs=5 * sigma + 1e-9), (k, eye_height)


def test_the_tie_rule_is_the_2d_engines_own() -> None:
    # a copy moved back by 1e-11 m ties (nearer by under 1e-9 of the distance), by 1e-7 m it is hidden: as in 2D
    for dx, seen in ((0.0, 1.0), (1e-11, 1.0), (1e-7, 0.0)):
        boxes = [EGO_BOX, box(12.0, 0, 0.75, 4.5, 1.8, 1.5), box(12.0 + dx, 0, 0.75, 4.5, 1.8, 1.5)]
        three = get_visibility_df(one_frame(boxes), 0, mode="3d", progress=False)
        two = get_visibility_df(one_frame(boxes), 0, progress=False)
        assert three["visibility"].to_list() == two["visibility"].to_list() == [1.0, seen]
