"""The visible area: paper answers, and the sweep's outline against VisiLibity's visibility polygon."""

from __future__ import annotations

import math
import warnings

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table, scene_table
from reference import scene_series

from omega_prime_visibility import Sensor
from omega_prime_visibility.analysis import area
from omega_prime_visibility.analysis.area import ARC_STEP, road_outline, visible_area, visible_area_over_time
from omega_prime_visibility.engines.visilibity import VisiLibityEngine
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.table.pipeline import viewpoints

CAMERA = Sensor("cam", fov=math.pi / 2, range=100.0)


def test_a_wall_across_the_view_leaves_a_triangle() -> None:
    wall = shapely.LineString([(10, -20), (10, 20)])
    seen = visible_area(boxes_table([(0, 0, 4, 2, 0)]), 0, 0, CAMERA, [wall])
    assert seen.area == pytest.approx(100.0, rel=1e-12)  # apex (0, 0), base from (10, -10) to (10, 10)
    assert seen.equals(shapely.Polygon([(0, 0), (10, -10), (10, 10)]).normalize()) or seen.symmetric_difference(
        shapely.Polygon([(0, 0), (10, -10), (10, 10)])
    ).area == pytest.approx(0.0, abs=1e-9)


def test_a_car_casts_its_shadow() -> None:
    # a 2 m square 9..11 m ahead seen by a 360° sensor with a 20 m range: the disk minus the shadow, the part of
    # the annulus sector behind the near face; shadow = area of the sector between the two rays through the near
    # corners from the near face out to 20 m, computed here on paper as sector minus the triangle up to the face
    half = math.atan(1 / 9)
    sector = half * 20**2  # (2 half) / 2 * r^2
    triangle = 9 * 1  # apex (0, 0), base from (9, -1) to (9, 1)
    seen = visible_area(boxes_table([(0, 0, 0.2, 0.2, 0), (10, 0, 2, 2, 0)]), 0, 0, Sensor("s", range=20.0))
    disk = math.pi * 400 * (math.sin(ARC_STEP) / ARC_STEP)  # the inscribed polygon's area
    assert seen.area == pytest.approx(disk - (sector - triangle), rel=2e-5)


def test_the_sensors_union() -> None:
    front = Sensor("f", fov=math.pi / 2, range=10.0)
    back = Sensor("b", yaw=math.pi, fov=math.pi / 2, range=10.0)
    table = boxes_table([(0, 0, 0.2, 0.2, 0), (-40, 0, 4, 2, 0)])
    both = visible_area(table, 0, 0, [front, back])
    assert both.area == pytest.approx(2 * visible_area(table, 0, 0, front).area, rel=1e-6)  # chords differ


@pytest.mark.parametrize("seed", [1, 2])
def test_matches_visilibity_visibility_polygon_cut_to_the_view(seed) -> None:
    rng = np.random.default_rng(seed)
    for include_ego, scene in scene_series(rng, 12, True, 10):
        observer, objects, statics, _ = scene
        table = scene_table(observer, objects, include_ego).with_columns(yaw=0.0)
        sensor = Sensor(
            "s",
            yaw=float(rng.uniform(-3, 3)),
            fov=float(rng.uniform(0.5, 2 * math.pi)),
            range=float(rng.uniform(5, 30)),
        )
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            seen = visible_area(table, 0, 0, sensor, statics)
            loaded = load_objects(table)
        st = load_static_occluders(statics)
        one = loaded.frame_objects(0)
        view = viewpoints(one, np.array([0]), st, [sensor])[0]
        engine = VisiLibityEngine(st)
        engine.box_margin = 100.0  # its visibility polygon ends at a box this far around the scene: beyond range
        region = engine.visible_region(one, view)
        o = view.position
        arc = [
            (o[0] + sensor.range * math.cos(t), o[1] + sensor.range * math.sin(t))
            for t in np.linspace(view.heading - sensor.fov / 2, view.heading + sensor.fov / 2, 2000)
        ]
        wedge = shapely.Polygon([tuple(o), *arc]) if sensor.fov < 2 * math.pi else shapely.Polygon(arc)
        want = shapely.intersection(region, wedge)
        assert abs(seen.area - want.area) < 2e-4 * max(want.area, 1.0)
        assert shapely.symmetric_difference(seen, want).area < 2e-4 * max(want.area, 1.0)


def test_over_time_with_a_road() -> None:
    frames = pl.concat([boxes_table([(f, 0, 4, 2, 0), (f + 15, 0, 4, 4, 0)], frame=f) for f in range(3)])
    road = shapely.box(-50, -3.5, 100, 3.5)
    out = visible_area_over_time(frames, 0, CAMERA, road=road)
    assert out.columns == ["frame", "total_nanos", "visible_area", "hidden_road_area"]
    for row in out.iter_rows(named=True):
        seen = visible_area(frames, 0, row["frame"], CAMERA)
        assert row["visible_area"] == pytest.approx(seen.area, rel=1e-12)
        assert row["hidden_road_area"] == pytest.approx(road.area - road.intersection(seen).area, rel=1e-9)
    assert visible_area_over_time(frames, 0, CAMERA).columns == ["frame", "total_nanos", "visible_area"]
    for bad in ("road", shapely.LineString([(0, 0), (9, 0)])):  # the road has an area: its outline
        with pytest.raises(ValueError, match="road must be a shapely Polygon or MultiPolygon"):
            visible_area_over_time(frames, 0, CAMERA, road=bad)


def test_a_crowded_road_with_the_typical_set(monkeypatch) -> None:
    # 40 cars on four lanes around the ego (some overlapping), the typical 6-sensor layout: the union built from
    # the pieces is shapely's, with no fallback
    rng = np.random.default_rng(11)
    frames = []
    for f in range(4):
        cars = [(0.0, 0.0, 4.5, 1.9, 0.0)]
        cars += [(x, 3.5 * lane + rng.uniform(-0.4, 0.4), 4.5, 1.9, rng.uniform(-0.03, 0.03))
                 for x, lane in zip(rng.uniform(-80, 80, 39), rng.integers(-1, 3, 39), strict=True)]  # fmt: skip
        frames.append(boxes_table(cars, frame=f))
    table = pl.concat(frames)
    road = shapely.box(-100, -5.25, 100, 8.75)
    fallbacks = area.UNION_FALLBACKS["shapely"]
    out = visible_area_over_time(table, 0, "typical", road=road)
    got = [visible_area(table, 0, f, "typical") for f in range(4)]
    assert area.UNION_FALLBACKS["shapely"] == fallbacks
    monkeypatch.setattr(area, "star_union", lambda *args, **kwargs: (None, 0.0))
    for f, seen in enumerate(got):
        want = visible_area(table, 0, f, "typical")
        assert shapely.is_valid(seen) and len(shapely.get_parts(seen)) == len(shapely.get_parts(want))
        assert shapely.symmetric_difference(seen, want).area <= 1e-9 * want.area
        assert out["hidden_road_area"][f] == pytest.approx(shapely.difference(road, want).area, rel=1e-9)
    assert area.UNION_FALLBACKS["shapely"] == fallbacks + 4  # the forced ones, counted


def test_road_outline_from_an_opendrive_map(shared_data) -> None:
    import omega_prime

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = omega_prime.Recording.from_file(
            str(shared_data / "pedestrian.osi"), map_path=str(shared_data / "fabriksgatan.xodr"), compute_polygons=True
        )
    road = road_outline(r)
    assert road is not None and road.area > 1000
    car = r._df.filter(pl.col("idx") == 0)
    out = visible_area_over_time(r.__class__(car.drop("frame", "polygon", strict=False), validate=False), 0, "typical")
    assert out.height == car.height and "hidden_road_area" not in out.columns


def test_bad_frame_and_ego() -> None:
    table = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)])
    with pytest.raises(ValueError, match="frame 5 does not occur"):
        visible_area(table, 0, 5)
    with pytest.raises(ValueError, match="never occurs"):
        visible_area(table, 7, 0)
    with pytest.raises(ValueError, match="one idx"):
        visible_area(table, [0, 1], 0)


def test_the_area_follows_the_whole_question() -> None:
    # a 0.8 m rail is below the driver's eye: the table leaves it out in 2D, and so does the seen region; a 3 m
    # wall stays; the same from one value of the question; 3D has no region on the ground
    from omega_prime_visibility import OptionError, Query, visible_area

    objects = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1], "x": [0.0, -30.0],
                            "y": [0.0, 0.0], "length": [4.0, 4.0], "width": [2.0, 2.0], "yaw": [0.0, 0.0]})  # fmt: skip
    wall = [shapely.box(10, -5, 10.5, 5)]
    cam = Sensor("cam", fov=math.pi / 2, range=20.0)
    open_view = visible_area(objects, 0, 0, sensors=cam)
    rail = visible_area(objects, 0, 0, sensors=cam, static_occluder_polys=wall, static_occluder_heights=0.8)
    assert rail.symmetric_difference(open_view).area < 1e-9
    high = visible_area(objects, 0, 0, sensors=cam, static_occluder_polys=wall, static_occluder_heights=3.0)
    assert high.area < open_view.area - 1.0
    question = Query(observers=0, sensors=cam, static_occluders=wall, static_heights=3.0)
    assert visible_area(objects, None, 0, query=question).symmetric_difference(high).area < 1e-9
    with pytest.raises(OptionError, match=r"no region on the ground|has none"):
        visible_area(objects, None, 0, query=question.replace(mode="3d", engine=None))
