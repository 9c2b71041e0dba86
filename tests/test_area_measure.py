"""``measure="area"`` (engines/area.py, geometry/shadows.py): the share of a footprint in no other body's shadow,
on scenes worked out on paper, on random scenes against dense point sampling, and its errors."""

from __future__ import annotations

import math
import warnings

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table, scene_table
from reference import random_scene, reference_area_visibility

from omega_prime_visibility import Sensor, get_visibility_df
from omega_prime_visibility.geometry.shadows import disc_area, shadow


def rows(table: pl.DataFrame) -> list[tuple]:
    return table.select("idx", "occluder_idxs", "visibility").rows()


def test_a_box_half_in_a_shadow() -> None:
    # the blocker [4, 5] x [-3, 0] shadows y <= 0 behind it; the target [10, 12] x [-1, 1] lies half there
    boxes = [(0, 0, 1, 1, 0), (4.5, -1.5, 1, 3, 0), (11, 0, 2, 2, 0)]
    out = get_visibility_df(boxes_table(boxes), 0, measure="area")
    assert rows(out)[1][:2] == (2, [1])
    assert rows(out)[1][2] == pytest.approx(0.5, abs=1e-12)
    assert rows(out)[0] == (1, [], 1.0)


def test_a_truck_seen_end_on_against_the_angle_measure() -> None:
    # a 12 m x 2.5 m truck from x = 20 to 32 seen end-on; a box at [10, 11] x [-0.2, 2] hides the directions above
    # the ray y = -0.02 x (through its corner (10, -0.2))
    boxes = [(0, 0, 1, 1, 0), (10.5, 0.9, 1, 2.2, 0), (26, 0, 12, 2.5, 0)]
    angle = get_visibility_df(boxes_table(boxes), 0)
    area = get_visibility_df(boxes_table(boxes), 0, measure="area")
    on_paper_angle = (math.atan(1.25 / 20) - math.atan(0.02)) / (2 * math.atan(1.25 / 20))
    hidden_area = 1.25 * 12 + 0.01 * (32**2 - 20**2)  # the integral of 1.25 + 0.02 x from 20 to 32
    assert angle["visibility"][1] == pytest.approx(on_paper_angle, abs=1e-12)
    assert area["visibility"][1] == pytest.approx(1 - hidden_area / 30, abs=1e-12)
    assert area["occluder_idxs"][1].to_list() == [1]


def test_a_target_straddling_the_wedge_edge_and_the_range_circle() -> None:
    sensor = Sensor("camera", fov=math.pi / 2, range=10.0)  # |direction| <= 45 degrees, 10 m
    # the box [5, 7] x [4, 8] is cut by the wedge's edge y = x: inside, the integral of x - 4 from 5 to 7, 4 m²
    # the box [9, 11] x [-1, 1] is cut by the range circle: sqrt(99) + 100 asin(0.1) - 18 m² of it are inside
    boxes = [(0, 0, 1, 1, 0), (6, 6, 2, 4, 0), (10, 0, 2, 2, 0)]
    out = get_visibility_df(boxes_table(boxes), 0, measure="area", sensors=[sensor])
    assert out["in_view"].to_list() == pytest.approx([0.5, (math.sqrt(99) + 100 * math.asin(0.1) - 18) / 4], abs=1e-12)
    assert out["visibility"].to_list() == out["in_view"].to_list()
    assert out["status"].to_list() == ["partly_visible", "partly_visible"]


def test_out_of_view_statuses_keep_their_meaning() -> None:
    sensor = Sensor("camera", fov=math.pi / 2, range=10.0)
    boxes = [(0, 0, 1, 1, 0), (-10, 0, 2, 2, 0), (30, 0, 2, 2, 0), (20, 0, 2, 2, 0), (5, 0, 1, 4, 0)]
    out = get_visibility_df(boxes_table(boxes), 0, measure="area", sensors=[sensor])
    assert out["status"].to_list() == ["out_of_fov", "out_of_range", "out_of_range", "visible"]


def test_disc_area_and_shadows_on_paper() -> None:
    assert disc_area(shapely.box(-3, -3, 3, 3), 2.0) == pytest.approx(4 * math.pi, abs=1e-12)
    ring = shapely.box(-3, -3, 3, 3).difference(shapely.box(-1, -1, 1, 1))  # a hole inside the disc
    assert disc_area(ring, 2.0) == pytest.approx(4 * math.pi - 4, abs=1e-12)
    # a U open towards the viewer: its opening [2, 4] x [-1, 1] (4 m²) is seen, the rest of its hull is not
    u = np.array([[2.0, -2], [5, -2], [5, 2], [2, 2], [2, 1], [4, 1], [4, -1], [2, -1]])
    hull = shapely.convex_hull(shapely.Polygon(u)).exterior.coords[:-1]
    assert disc_area(shadow(u, 50.0), 40.0) == pytest.approx(disc_area(shadow(hull, 50.0), 40.0) - 4, abs=1e-9)
    assert not shadow(u, 50.0).contains(shapely.Point(3, 0))
    assert shadow(u, 50.0).contains(shapely.Point(4.5, 0)) and shadow(u, 50.0).contains(shapely.Point(30, 0))


@pytest.mark.parametrize("seed", range(6))
def test_random_scenes_against_point_sampling(seed: int) -> None:
    rng = np.random.default_rng(seed)
    scene = random_scene(rng, 7, overlap=bool(seed % 2), with_statics=seed % 3 == 0, include_ego=False)
    table = scene_table(scene.observer, scene.objects, include_ego=False)
    polygons = list(table["polygon"])
    transparent = np.zeros(len(polygons), dtype=bool)
    transparent[0] = True
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = get_visibility_df(table, 0, scene.statics, measure="area")
    shares, hiders = reference_area_visibility(scene.observer, polygons, scene.statics, transparent, n_side=300)
    for row in out.iter_rows(named=True):
        i = row["idx"]
        assert row["visibility"] == pytest.approx(shares[i], abs=1e-3), i  # 300 x 300 points: about 3e-4
        sampled = {k for k, share in hiders[i].items() if share > 0.002}
        listed = set(row["occluder_idxs"]) | {-1 - s for s in row["static_occluder_idxs"]}
        assert sampled <= listed, (i, sampled, listed)
        assert {k for k in listed if hiders[i].get(k, 0.0) == 0.0} <= set(), (i, listed, hiders[i])


@pytest.mark.parametrize(
    "building",
    [shapely.box(-50, 8, 50, 20), shapely.LineString([(-50, 8), (50, 8)]), shapely.box(-60, -30, -5, -12)],
)
def test_a_building_behind_the_target_hides_nothing(building) -> None:
    # the buildings lie beyond the targets and reach far past them (past the farthest moving body): from the
    # origin, every segment to a point of the targets stays on the near side, so both are fully seen (a shadow's
    # arc drawn nearer than the building's far corners once closed it in front of the building: 0.0 and 0.44)
    boxes = [(0, 0, 1, 1, 0), (15, 5, 4.5, 1.8, 0), (-10, -10, 4.5, 1.8, 0)]
    for sensors in (None, [Sensor("camera", fov=2 * math.pi - 0.1, range=25.0)]):
        out = get_visibility_df(boxes_table(boxes), 0, [building], measure="area", sensors=sensors)
        assert out["visibility"].to_list() == [1.0, 1.0]
        assert out["static_occluder_idxs"].to_list() == [[], []]


@pytest.mark.parametrize("seed", range(4))
def test_random_scenes_with_long_buildings_against_point_sampling(seed: int) -> None:
    # cars within 30 m among buildings and walls 100 to 400 m long, which reach far beyond every car
    rng = np.random.default_rng(100 + seed)
    cars, statics = [], []
    while len(cars) < 6:
        x, y = rng.uniform(-30, 30, 2)
        car = shapely.affinity.rotate(shapely.box(x - 2.2, y - 0.9, x + 2.2, y + 0.9), rng.uniform(0, 180))
        if car.distance(shapely.Point(0, 0)) > 3 and all(car.distance(c) > 0.5 for c in cars):
            cars.append(car)
    while len(statics) < 3:
        x, y = rng.uniform(-40, 40, 2)
        length, angle = rng.uniform(100, 400), rng.uniform(0, math.pi)
        end = (x + length * math.cos(angle), y + length * math.sin(angle))
        body = shapely.LineString([(x, y), end])
        body = body if len(statics) == 0 else body.buffer(rng.uniform(1, 6), cap_style="flat")
        if body.distance(shapely.Point(0, 0)) > 2 and all(body.distance(c) > 0.3 for c in cars):
            statics.append(body)
    table = scene_table(np.zeros(2), cars, include_ego=False)
    out = get_visibility_df(table, 0, statics, measure="area")
    transparent = np.zeros(len(cars) + 1, dtype=bool)
    transparent[0] = True
    shares, hiders = reference_area_visibility(np.zeros(2), list(table["polygon"]), statics, transparent, n_side=300)
    assert len(out) == 6
    for row in out.iter_rows(named=True):
        i = row["idx"]
        assert row["visibility"] == pytest.approx(shares[i], abs=1e-3), i
        listed = set(row["occluder_idxs"]) | {-1 - s for s in row["static_occluder_idxs"]}
        assert {k for k, share in hiders[i].items() if share > 0.002} <= listed, (i, listed, hiders[i])
        assert all(hiders[i].get(k, 0.0) > 0.0 for k in listed), (i, listed, hiders[i])


def test_area_in_map_coordinates_is_the_same() -> None:
    boxes = [(0, 0, 1, 1, 0), (10.5, 0.9, 1, 2.2, 0), (26, 0, 12, 2.5, 0.1), (15, -3, 4, 2, -0.3)]
    near = get_visibility_df(boxes_table(boxes), 0, measure="area")
    far = get_visibility_df(
        boxes_table([(x + 512_345.0, y + 5_432_100.0, *rest) for x, y, *rest in boxes]), 0, measure="area"
    )
    assert rows(far)[0][:2] == rows(near)[0][:2]
    assert np.abs(far["visibility"].to_numpy() - near["visibility"].to_numpy()).max() < 1e-9


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"measure": "volume"}, "unknown measure 'volume'"),
        ({"measure": "area", "mode": "3d"}, "measure='area' measures footprints in 2D"),
        ({"measure": "area", "engine": "sweep"}, "has its own exact engine"),
    ],
)
def test_bad_measures_are_one_clear_error(kwargs, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        get_visibility_df(boxes_table([(0, 0, 1, 1, 0), (5, 0, 1, 1, 0)]), 0, **kwargs)


@pytest.mark.parametrize("seed", range(8))
def test_the_compiled_path_agrees_with_polygon_clipping(seed: int, monkeypatch) -> None:
    # frames of convex boxes (overlapping too) take the compiled path; the same frames forced onto the general path
    # (shapely's clipping) give the same numbers, whatever the field of view (under, at and over 180°, all round),
    # the range and the coordinates (map coordinates too)
    from omega_prime_visibility.engines import Viewpoint
    from omega_prime_visibility.engines import area as area_engine
    from omega_prime_visibility.geometry.rings import box_rings
    from omega_prime_visibility.inputs.objects import FrameObjects
    from omega_prime_visibility.inputs.statics import load_static_occluders

    rng = np.random.default_rng(seed)
    n = 25
    shift = np.array([512_345.0, 5_432_100.0]) if seed % 2 else np.zeros(2)
    xy = rng.uniform(-40, 40, (n, 2))
    xy[0] = 0.0
    size = rng.uniform([1.0, 0.5], [12.0, 3.0], (n, 2))
    yaw = rng.uniform(-np.pi, np.pi, n)
    rings = box_rings(xy[:, 0] + shift[0], xy[:, 1] + shift[1], size[:, 0], size[:, 1], yaw)
    frame = FrameObjects(0, 0, np.arange(n), xy + shift, yaw, rings)
    engine = area_engine.AreaEngine(load_static_occluders(None))
    fov, max_range = [(math.radians(70), 30.0), (math.pi, math.inf), (math.radians(250), 25.0), (2 * math.pi, 20.0)][
        seed % 4
    ]
    transparent = np.zeros(n, dtype=bool)
    transparent[0] = True
    view = Viewpoint(xy[0] + shift, rng.uniform(-np.pi, np.pi), 0, transparent, np.zeros(0, bool), fov, max_range)
    fast = engine._observe_convex(frame, view)
    monkeypatch.setattr(area_engine.AreaEngine, "compiled", False)
    slow = engine.observe(frame, [view])[0]
    assert fast is not None
    assert np.abs(fast.visible_angle - slow.visible_angle).max() <= 1e-9 * slow.angular_extent.max()
    assert np.abs(fast.angular_extent - slow.angular_extent).max() <= 1e-9 * slow.angular_extent.max()
    assert (fast.reason == slow.reason).all()
    for name in ("in_view_angle", "in_fov_angle"):
        a, b = getattr(fast, name), getattr(slow, name)
        assert (a is None) == (b is None) and (a is None or np.abs(a - b)[1:].max() <= 1e-9 * b.max()), name
    assert fast.occluders.tolist() == slow.occluders.tolist()
    assert fast.occluder_offsets.tolist() == slow.occluder_offsets.tolist()
    assert 0 < (slow.visible_angle[1:] < slow.angular_extent[1:] * 0.999).sum()  # something is hidden


def test_a_non_convex_body_takes_the_general_path() -> None:
    # an L-shaped body: the compiled path declines the frame (None) and the general path measures it
    from omega_prime_visibility.engines import Viewpoint
    from omega_prime_visibility.engines.area import AreaEngine
    from omega_prime_visibility.geometry.rings import Rings, orient
    from omega_prime_visibility.inputs.objects import FrameObjects
    from omega_prime_visibility.inputs.statics import load_static_occluders

    ego = [(-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5)]
    ell = [(10, -3), (11, -3), (11, -1), (10.5, -1), (10.5, 3), (10, 3)]  # a notch at y > -1, x 10.5..11
    box = [(20, -1), (22, -1), (22, 1), (20, 1)]
    coords = np.array(ego + ell + box, dtype=float)
    rings = orient(Rings(coords, np.array([0, 4, 10, 14])))
    frame = FrameObjects(0, 0, np.arange(3), np.array([[0.0, 0], [10.5, 0], [21, 0]]), np.zeros(3), rings)
    view = Viewpoint(np.zeros(2), 0.0, 0, np.array([True, False, False]), np.zeros(0, bool))
    engine = AreaEngine(load_static_occluders(None))
    assert engine._observe_convex(frame, view) is None
    obs = engine.observe(frame, [view])[0]
    # the L hides the box wholly: its thin bar x 10..10.5 spans |y| <= 3 at 10 m, the box |y| <= 1 at 20..22 m
    assert obs.visible_angle[2] == 0.0 and obs.occluders.tolist() == [1]
