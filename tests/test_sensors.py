"""Sensors: the Sensor type and layouts, and the sensor model in every engine (field of view, range, mounting),
against answers derived on paper and against the brute-force reference."""

from __future__ import annotations

import json
import math
import warnings

import numpy as np
import polars as pl
import pytest
from conftest import boxes_table, scene_table
from reference import occluder_disagreements, reference_visibility, scene_series

from omega_prime_visibility import ENGINES, Sensor, get_visibility_df
from omega_prime_visibility.sensors import read_sensors, resolve_sensors, roof, typical
from omega_prime_visibility.table import STATUSES

ENGINE_NAMES = sorted(ENGINES)
EXACT = {"sweep": 1e-12, "visilibity": 1e-7}  # as in test_engine_contract
N_RAYS = 20000
ROW_TOLERANCE = 5e-4


# -- the Sensor type ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("fields", "message"),
    [
        ({"fov": 0.0}, "fov must be in"),
        ({"fov": 7.0}, "fov must be in"),
        ({"fov": float("nan")}, "fov must be finite"),
        ({"range": -1.0}, "range must be > 0"),
        ({"range": 0.0}, "range must be > 0"),
        ({"range": float("nan")}, "range must be finite"),
        ({"x": float("inf")}, "x must be finite"),
        ({"yaw": "left"}, "yaw must be a number"),
        ({"vertical_fov": 4.0}, "vertical_fov must be in"),
        # a field of view beyond a full turn (half a turn upwards) but within 360 is degrees given for radians
        ({"fov": 90.0}, r"fov must be in \(0, 2π\] radians, not 90.0; 90 looks like degrees \(90° is 1.571\)"),
        ({"vertical_fov": 30.0}, r"not 30.0; 30 looks like degrees \(30° is 0.5236\)"),
        ({"fov": 400.0}, r"not 400.0$"),
        ({"fov": -90.0}, r"not -90.0$"),
    ],
)
def test_invalid_sensor_values_name_the_sensor_and_field(fields, message) -> None:
    with pytest.raises(ValueError, match=message) as info:
        Sensor("cam", **fields)
    assert "'cam'" in str(info.value)


def test_sensor_names_must_be_unique_and_given() -> None:
    with pytest.raises(ValueError, match=r"repeated: \['a'\]"):
        resolve_sensors([Sensor("a"), Sensor("b"), Sensor("a")])
    with pytest.raises(ValueError, match="non-empty string"):
        Sensor("")
    with pytest.raises(ValueError, match="at least one"):
        resolve_sensors([])
    with pytest.raises(ValueError, match="Sensor objects"):
        resolve_sensors([{"name": "a"}])


def test_layouts_scale_with_the_car() -> None:
    small, big = typical(4.0, 1.8), typical(10.0, 2.5)
    assert [s.name for s in small] == [s.name for s in big]
    corner = {s.name: s for s in big}["corner_rear_right"]
    assert (corner.x, corner.y, corner.yaw) == (-5.0, -1.25, pytest.approx(math.radians(-135)))
    assert {s.name: s for s in big}["front_radar"].x == 5.0
    assert roof()[0].fov == 2 * math.pi and math.isinf(roof()[0].range)
    with pytest.raises(ValueError, match="length must be a positive"):
        typical(-1.0, 2.0)


def test_unknown_layout_name() -> None:
    with pytest.raises(ValueError, match=r"unknown sensor layout 'lidar'.*roof.*typical"):
        resolve_sensors("lidar")


def test_sensors_json_file_round_trip_and_errors(tmp_path) -> None:
    good = tmp_path / "s.json"
    good.write_text(json.dumps({"sensors": [s.to_dict() for s in typical()]}))
    assert read_sensors(good) == tuple(typical())
    assert resolve_sensors(str(good)) == tuple(typical())
    for text, message in [
        ("{not json", "not valid JSON"),
        ('{"a": 1}', "must hold a list"),
        ('[{"name": "a", "fov": 0}]', "fov must be in"),
        ('[{"fov": 1}]', "entry 0 has no name"),
        ('[{"name": "a", "colour": "red"}]', "unknown field"),
        ('[{"name": "a"}, {"name": "a"}]', "repeated"),
        ("[3]", "entry 0 is not an object"),
    ]:
        bad = tmp_path / "bad.json"
        bad.write_text(text)
        with pytest.raises(ValueError, match=message) as info:
            read_sensors(bad)
        assert str(bad) in str(info.value)
    with pytest.raises(ValueError, match="cannot read sensors file"):
        read_sensors(tmp_path / "missing.json")


def test_sensors_need_a_yaw_column() -> None:
    import shapely

    table = scene_table(np.zeros(2), [shapely.box(-1, -1, 1, 1), shapely.box(9, -1, 11, 1)], True)
    assert "yaw" not in table.columns
    with pytest.raises(ValueError, match="no 'yaw' column"):
        get_visibility_df(table, 0, sensors="roof")


# -- hand-made scenes with answers derived on paper ----------------------------------------------------------------

# a 2 m square whose near side lies 9 m ahead of an observer at the origin (facing +x): its extent is
# [-atan(1/9), atan(1/9)]
SQUARE = [(0, 0, 0.2, 0.2, 0), (10, 0, 2, 2, 0)]
HALF_WIDTH = math.atan(1 / 9)


def one(table: pl.DataFrame, idx: int, sensor: str | None = None) -> dict:
    rows = table.filter(pl.col("idx") == idx)
    if sensor is not None:
        rows = rows.filter(pl.col("sensor") == sensor)
    assert rows.height == 1
    return rows.row(0, named=True)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_target_straddling_the_edge_of_the_field_of_view(engine) -> None:
    # the wedge [0, pi/2] holds exactly the upper half of the square's extent
    wedge = Sensor("s", yaw=math.pi / 4, fov=math.pi / 2)
    out = get_visibility_df(boxes_table(SQUARE), 0, engine=engine, sensors=wedge)
    row = one(out, 1)
    assert row["visibility"] == pytest.approx(0.5, abs=EXACT[engine])
    assert row["in_view"] == pytest.approx(0.5, abs=1e-12)
    assert row["status"] == "partly_visible"
    # a wedge starting a third of the way into the extent, from below
    cut = -HALF_WIDTH + 2 * HALF_WIDTH / 3
    out = get_visibility_df(boxes_table(SQUARE), 0, engine=engine, sensors=Sensor("s", yaw=cut + 1.0, fov=2.0))
    assert one(out, 1)["visibility"] == pytest.approx((HALF_WIDTH - cut) / (2 * HALF_WIDTH), abs=EXACT[engine])


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_target_straddling_the_range_circle(engine) -> None:
    # range 9.05 m: the near side (x = 9) is within range for |y| <= sqrt(9.05^2 - 81); the sides are not
    out = get_visibility_df(boxes_table(SQUARE), 0, engine=engine, sensors=Sensor("s", range=9.05))
    want = math.atan(math.sqrt(9.05**2 - 81) / 9) / HALF_WIDTH
    row = one(out, 1)
    assert row["visibility"] == pytest.approx(want, abs=EXACT[engine])
    assert row["in_view"] == pytest.approx(want, abs=1e-12)
    # range 10.5 m: the whole near side is within range (9^2 + 1 < 10.5^2), so all of the extent is
    row = one(get_visibility_df(boxes_table(SQUARE), 0, engine=engine, sensors=Sensor("s", range=10.5)), 1)
    assert (row["visibility"], row["in_view"], row["status"]) == (1.0, 1.0, "visible")


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_range_cuts_a_target_seen_at_a_slant(engine) -> None:
    # a long wall-like box seen end-on at a slant: x from 5 to 25 at y in [3, 4]; range 10 m. Directions hitting
    # it within range are those of its part inside the disk: the near face y = 3 up to x = sqrt(100 - 9), and
    # the left face x = 5 (y 3..4, all within range as 25 + 16 < 100).
    box = [(0, 0, 0.2, 0.2, 0), (15, 3.5, 20, 1, 0)]
    out = get_visibility_df(boxes_table(box), 0, engine=engine, sensors=Sensor("s", range=10.0))
    lo = math.atan2(3, math.sqrt(91))
    hi = math.atan2(4, 5)
    extent = math.atan2(4, 5) - math.atan2(3, 25)
    row = one(out, 1)
    assert row["in_view"] == pytest.approx((hi - lo) / extent, abs=1e-12)
    assert row["visibility"] == pytest.approx((hi - lo) / extent, abs=EXACT[engine])


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_range_and_occlusion_together(engine) -> None:
    # the slanted box above, in view along [atan2(3, sqrt(91)), atan2(4, 5)]; a small box hides its directions
    # from atan2(1.6, 3.1) on (its lower right corner), so only [atan2(3, sqrt(91)), atan2(1.6, 3.1)] is seen. Its
    # far part, beyond range, is not hidden by that box but must not count.
    box = [(0, 0, 0.2, 0.2, 0), (15, 3.5, 20, 1, 0), (3.0, 2.3, 0.2, 1.4, 0)]
    out = get_visibility_df(boxes_table(box), 0, engine=engine, sensors=Sensor("s", range=10.0))
    extent = math.atan2(4, 5) - math.atan2(3, 25)
    row = one(out, 1)
    assert row["visibility"] == pytest.approx((math.atan2(1.6, 3.1) - math.atan2(3, math.sqrt(91))) / extent, abs=1e-9)
    assert row["occluder_idxs"] == [2]


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_bumper_sensor_sees_past_a_car_that_hides_the_target_from_the_centre(engine) -> None:
    # ego 4 m x 2 m at the origin; blocker 1 m square at (3, 1.5); target 1 m square at (6, 3)
    scene = [(0, 0, 4, 2, 0), (3, 1.5, 1, 1, 0), (6, 3, 1, 1, 0)]
    centre = get_visibility_df(boxes_table(scene), 0, engine=engine)
    assert one(centre, 2)["visibility"] == 0.0
    bumper = get_visibility_df(boxes_table(scene), 0, engine=engine, sensors=Sensor("bumper", x=2.0))
    # from (2, 0): target spans [atan2(2.5, 4.5), pi/4]; the blocker covers it from atan2(1, 1.5) on
    lo = math.atan2(2.5, 4.5)
    want = (math.atan2(1, 1.5) - lo) / (math.pi / 4 - lo)
    row = one(bumper, 2)
    assert row["visibility"] == pytest.approx(want, abs=EXACT[engine])
    assert row["occluder_idxs"] == [1]
    assert (row["in_view"], row["status"]) == (1.0, "partly_visible")


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_target_seen_only_by_the_rear_corner_radar(engine) -> None:
    scene = [(0, 0, 4, 2, 0), (-10, 8, 4, 2, 0)]
    out = get_visibility_df(boxes_table(scene), 0, engine=engine, sensors=typical(4.0, 2.0))
    seen = out.filter(pl.col("visibility") > 0)
    assert seen["sensor"].to_list() == ["corner_rear_left"]
    assert seen["visibility"].to_list() == [1.0]
    assert set(out.filter(pl.col("visibility") == 0)["status"].to_list()) == {"out_of_fov"}


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_status_for_each_case(engine) -> None:
    camera = Sensor("cam", fov=math.radians(90), range=50.0)
    scene = [
        (0, 0, 4, 2, 0),  # 0: ego
        (20, 0, 4, 2, 0),  # 1: visible
        (40, 0, 4, 2, 0),  # 2: occluded by 1
        (20, 20, 4, 2, 0),  # 3: straddles the wedge's left edge (45 degrees): partly visible
        (-20, 0, 4, 2, 0),  # 4: behind: out of the field of view
        (80, -5, 4, 2, 0),  # 5: ahead but beyond 50 m: out of range
    ]
    out = get_visibility_df(boxes_table(scene), 0, engine=engine, sensors=camera)
    want = ["visible", "occluded", "partly_visible", "out_of_fov", "out_of_range"]
    assert out.sort("idx")["status"].to_list() == want
    assert out.schema["status"] == pl.Enum(STATUSES)
    assert one(out, 2)["occluder_idxs"] == [1]
    assert one(out, 4)["in_view"] == 0.0 and one(out, 5)["in_view"] == 0.0
    partly = one(out, 3)
    assert 0.0 < partly["in_view"] < 1.0
    assert partly["visibility"] == pytest.approx(partly["in_view"], abs=EXACT[engine])


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_an_occluder_in_front_of_a_target_beyond_range_is_not_listed(engine) -> None:
    # target 60 m ahead, behind a car at 20 m; range 40 m: the car is in range, the target is not
    scene = [(0, 0, 4, 2, 0), (20, 0, 4, 2, 0), (60, 0, 4, 2, 0)]
    out = get_visibility_df(boxes_table(scene), 0, engine=engine, sensors=Sensor("s", range=40.0))
    row = one(out, 2)
    assert (row["occluder_idxs"], row["status"], row["visibility"]) == ([], "out_of_range", 0.0)
    # and one outside the field of view is not listed either: the target straddles the wedge, the car hides only
    # its outer part
    scene = [(0, 0, 4, 2, 0), (10, 3, 2, 2, 0), (30, 2, 4, 8, 0)]
    narrow = Sensor("s", fov=2 * math.atan2(1.5, 30))
    row = one(get_visibility_df(boxes_table(scene), 0, engine=engine, sensors=narrow), 2)
    assert row["occluder_idxs"] == []
    wide = one(get_visibility_df(boxes_table(scene), 0, engine=engine), 2)
    assert wide["occluder_idxs"] == [1]


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_a_roof_sensor_at_the_centre_gives_the_sensorless_table(engine) -> None:
    rng = np.random.default_rng(5)
    for include_ego, scene in scene_series(rng, 6, True, 9):
        observer, objects, statics, _ = scene
        table = scene_table(observer, objects, include_ego).with_columns(yaw=0.0)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            plain = get_visibility_df(table, 0, statics, engine=engine)
            roofed = get_visibility_df(table, 0, statics, engine=engine, sensors="roof")
        assert roofed.drop("sensor", "in_view", "status").equals(plain)
        assert (roofed["sensor"] == "roof").all() and (roofed["in_view"] == 1.0).all()


# -- random scenes with random sensors: against the reference, and across engines ------------------------------


def random_sensor(rng: np.random.Generator) -> Sensor:
    fov = float(rng.choice([rng.uniform(0.2, 2 * math.pi), 2 * math.pi]))
    max_range = float(rng.choice([rng.uniform(3.0, 40.0), math.inf], p=[0.75, 0.25]))
    return Sensor("s", yaw=float(rng.uniform(-math.pi, math.pi)), fov=fov, range=max_range)


def run_sensor(scene, include_ego: bool, engine: str, sensor: Sensor) -> pl.DataFrame:
    observer, objects, statics, _ = scene
    table = scene_table(observer, objects, include_ego).with_columns(yaw=0.0)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return get_visibility_df(table, 0, statics, engine=engine, sensors=sensor)


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_random_scenes_with_random_sensors_against_reference(engine) -> None:
    rng = np.random.default_rng(20261123)
    errors, problems = [], []
    for include_ego, scene in scene_series(rng, 30, True, 9):
        sensor = random_sensor(rng)
        observer, objects, statics, _ = scene
        out = run_sensor(scene, include_ego, engine, sensor)
        ref_objects = list(scene_table(observer, objects, include_ego)["polygon"])
        transparent = np.zeros(len(ref_objects), dtype=bool)
        transparent[0] = True
        view = {"heading": sensor.yaw, "fov": sensor.fov, "max_range": sensor.range}
        ref = reference_visibility(observer, ref_objects, statics, transparent, n_rays=N_RAYS, **view)
        for row in out.iter_rows(named=True):
            i = row["idx"]
            errors.append(abs(row["visibility"] - ref.visibility[i]))
            errors.append(abs(row["in_view"] - ref.in_view[i]))
            for got, want, bodies in (
                (set(row["occluder_idxs"]), ref.occluders[i], ref_objects),
                (set(row["static_occluder_idxs"]), ref.static_occluders[i], statics),
            ):
                if occluder_disagreements(observer, ref_objects[i], got, want, bodies, 1e-3, **view):
                    problems.append(f"{sensor}: target {i}: engine {sorted(got)} reference {want}")
            if row["visibility"] == 0:
                want_status = "out_of_fov" if ref.in_fov[i] == 0 else "out_of_range" if ref.in_view[i] == 0 else None
                if want_status:
                    assert row["status"] == want_status
    errors = np.asarray(errors)
    assert errors.max() < ROW_TOLERANCE, errors.max()
    assert errors.mean() < 5e-5, errors.mean()
    assert not problems, "\n".join(problems)


def test_engines_agree_with_random_mounted_sensors() -> None:
    rng = np.random.default_rng(11)
    for include_ego, scene in scene_series(rng, 30, True, 10):
        sensors = [
            Sensor(
                f"s{k}",
                x=float(rng.uniform(-1, 1)),
                y=float(rng.uniform(-1, 1)),
                yaw=float(rng.uniform(-math.pi, math.pi)),
                fov=float(rng.uniform(0.3, 2 * math.pi)),
                range=float(rng.choice([rng.uniform(3.0, 40.0), math.inf])),
            )
            for k in range(3)
        ]
        a, b = (run_sensor(scene, include_ego, engine, sensors) for engine in ("sweep", "visilibity"))
        assert a.drop("visibility", "in_view").equals(b.drop("visibility", "in_view"))
        assert np.abs(a["visibility"].to_numpy() - b["visibility"].to_numpy()).max(initial=0) < 1e-6
        assert np.array_equal(a["in_view"].to_numpy(), b["in_view"].to_numpy())


@pytest.mark.parametrize("engine", ENGINE_NAMES)
def test_a_layout_by_name_is_fitted_to_each_observer(engine) -> None:
    # a 12 m x 2.5 m truck (idx 0) and a 4 m x 1.8 m car (idx 1) seeing each other and a third car
    scene = [(0, 0, 12, 2.5, 0.3), (30, 6, 4, 1.8, -0.2), (15, -8, 4.5, 2, 1.0)]
    table = boxes_table(scene)
    by_name = get_visibility_df(table, "all", engine=engine, sensors="typical")
    truck = get_visibility_df(table, 0, engine=engine, sensors=typical(12, 2.5))
    car = get_visibility_df(table, 1, engine=engine, sensors=typical(4, 1.8))
    assert by_name.filter(pl.col("idx_ego") == 0).drop("idx_ego").equals(truck)
    assert by_name.filter(pl.col("idx_ego") == 1).drop("idx_ego").equals(car)
    assert not truck.equals(get_visibility_df(table, 0, engine=engine, sensors=typical()))


@pytest.mark.parametrize(("x", "y", "target"), [(2.5, 0.0, (0.0, 5.0)), (0.0, 2.5, (-5.0, 0.0))])
def test_mounting_offset_on_an_ego_turned_by_90_degrees(x, y, target) -> None:
    # The ego faces +y (yaw 90 degrees): its forward x = 2.5 is world (0, 2.5) and its left y = 2.5 is world
    # (-2.5, 0). A 0.5 m square target 2.5 m further out along the same direction lies 2.25..2.8 m from the
    # sensor, within its 3 m range: visibility 1. Applied in world axes the sensor would sit at (2.5, 0) resp.
    # (0, 2.5), turned the wrong way at (0, -2.5) resp. (2.5, 0): every one at least 5.2 m from the target, out of
    # range (visibility 0).
    table = boxes_table([(0, 0, 4.5, 1.8, math.pi / 2), (*target, 0.5, 0.5, 0)])
    row = one(get_visibility_df(table, 0, sensors=[Sensor("s", x=x, y=y, range=3.0)]), 1)
    assert (row["visibility"], row["status"]) == (pytest.approx(1.0, abs=1e-12), "visible")
