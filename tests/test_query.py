"""The question as one value (query/): checked once with the option's name, a stable text, old keywords folded in,
and the same table whichever way it is asked."""

from __future__ import annotations

import warnings

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import REPO, boxes_table
from polars.testing import assert_frame_equal

from omega_prime_visibility import ENGINES, OptionError, Query, Sensor, get_visibility_df, get_visibility_df_for_frame
from omega_prime_visibility.query import fold_keywords, resolve

STREET = pl.DataFrame(
    {
        "frame": [0, 0, 0, 1, 1, 1],
        "total_nanos": [0, 0, 0, 10**8, 10**8, 10**8],
        "idx": [0, 1, 2, 0, 1, 2],
        "x": [0.0, 10.0, 20.0, 1.0, 10.0, 20.0],
        "y": [0.0, 0.5, 0.0, 0.0, 0.5, 0.0],
        "length": [4.0, 4.0, 4.0, 4.0, 4.0, 4.0],
        "width": [2.0, 3.0, 2.0, 2.0, 3.0, 2.0],
        "yaw": [0.0] * 6,
        "type": [2, 2, 3, 2, 2, 3],
        "subtype": [4, 4, 0, 4, 4, 0],
    }
)
WALL = shapely.box(14.0, 2.0, 15.0, 6.0)


@pytest.mark.parametrize(
    ("options", "option", "words"),
    [
        ({"mode": "4d"}, "mode", "mode must be '2d' or '3d'"),
        ({"engine": "nope"}, "engine", "unknown engine 'nope'"),
        ({"measure": "volume"}, "measure", "unknown measure 'volume'"),
        ({"measure": "area", "engine": "sweep"}, "measure", "has its own exact engine"),
        ({"targets": "lorries"}, "targets", "unknown object kind 'lorries'"),
        ({"occluders": []}, "occluders", "takes a group or type name"),
        ({"sensors": "dashboard"}, "sensors", "dashboard"),
        ({"static_occluders": [shapely.Point(0, 0)]}, "static_occluder_polys", "static occluder 0"),
        ({"static_occluders": [WALL], "static_heights": [1.0, 2.0]}, "static_occluder_heights", r"2 height\(s\)"),
        ({"static_meshes": ["x.stl"]}, "static_meshes", "pass mode='3d'"),
        ({"map_occluders": False}, "map_occluders", "a path, True"),
        ({"on_invalid": "ignore"}, "on_invalid", "'warn'"),
        ({"observers": "ALL"}, "ego_idx", "'all'"),
        ({"observers": [0, 1.5]}, "ego_idx", "list of ints"),
    ],
)
def test_every_option_is_checked_once_and_named(options, option: str, words: str) -> None:
    with pytest.raises(OptionError, match=words) as caught:
        Query(**options)
    assert caught.value.option == option and isinstance(caught.value, ValueError)


def test_one_spelling_one_text() -> None:
    # equal questions give equal texts whatever the spelling; another option gives another text
    a = Query(observers=[2, 0, 2], targets=["CAR", "pedestrians"], occluders=[5, 3], static_occluders=[WALL])
    b = Query(observers=(0, 2), targets=["Pedestrians", "car", "car"], occluders=(3, 5), static_occluders=(WALL,))
    assert a == b and a.text() == b.text()
    assert a.observers == (0, 2) and a.targets == ("CAR", "pedestrians") and a.occluders == (3, 5)
    assert Query(engine="sweep").text() != Query().text()
    assert Query(static_occluders=[shapely.box(0, 0, 1, 1)]).text() != Query(static_occluders=[WALL]).text()
    assert Query(sensors="typical").sensors == "typical"  # a layout stays a name: fitted to each observer
    camera = Sensor("cam", x=1.0, fov=1.0)
    assert Query(sensors=camera).sensors == (camera,) and Query(sensors=[camera]).text() == Query(sensors=camera).text()


def test_a_file_is_in_the_text_by_its_content(tmp_path) -> None:
    road = tmp_path / "road.xodr"
    road.write_text("<OpenDRIVE/>")
    before = Query(map_occluders=road).text()
    road.write_text("<OpenDRIVE><road/></OpenDRIVE>")
    assert Query(map_occluders=road).text() != before


def test_old_keywords_fold_into_the_value() -> None:
    assert fold_keywords(None, ego_idx=[1, 0], engine="sweep", mode=None) == Query(observers=(0, 1), engine="sweep")
    given = Query(observers=0, engine="sweep", targets="pedestrians")
    assert fold_keywords(given, engine="sweep", targets=["PEDESTRIANS"], ego_idx=0) is given  # agreeing: fine
    for keyword, value in (("engine", "visilibity"), ("ego_idx", 1), ("targets", "vehicles"), ("mode", "3d")):
        with pytest.raises(OptionError, match=keyword):
            fold_keywords(given, **{keyword: value})
    # expressions compare by their text (never with ==, which builds another expression)
    cars = Query(observers=0, occluders=pl.col("type") == 2)
    assert fold_keywords(cars, occluders=pl.col("type") == 2) is cars
    with pytest.raises(OptionError, match=r"occluders=<expression .*3.*> contradicts the query's occluders=<expr"):
        fold_keywords(cars, occluders=pl.col("type") == 3)
    with pytest.raises(OptionError, match="contradicts"):
        fold_keywords(cars, occluders="vehicles")
    with pytest.raises(TypeError, match=r"must be an omega_prime_visibility\.Query"):
        fold_keywords({"engine": "sweep"})
    with pytest.raises(TypeError, match="unexpected keyword argument 'speed'"):
        fold_keywords(None, speed=3)


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_the_same_table_whichever_way_it_is_asked(engine: str) -> None:
    keywords = get_visibility_df(STREET, "all", [WALL], engine=engine, targets=[1, 2], occluders="vehicles")
    question = Query(observers="all", static_occluders=[WALL], engine=engine, targets=[1, 2], occluders="vehicles")
    assert_frame_equal(get_visibility_df(STREET, query=question), keywords)
    assert_frame_equal(get_visibility_df(STREET, query=question, workers=2, chunk_frames=1), keywords)
    one = get_visibility_df_for_frame(STREET, None, 1, query=question)
    assert_frame_equal(one, keywords.filter(pl.col("frame") == 1))
    # a keyword that agrees with the query may be given beside it; one that contradicts it is refused
    assert_frame_equal(get_visibility_df(STREET, "all", [WALL], query=question, engine=engine), keywords)
    with pytest.raises(OptionError, match="ego_idx=0 contradicts the query's observers='all'"):
        get_visibility_df(STREET, 0, query=question)


def test_the_host_vehicle_observes_when_no_observer_is_given() -> None:
    from omega_prime_visibility.inputs.io import read_recording

    r = read_recording(REPO / "highway_merge.mcap")
    assert r.host_vehicle_idx is not None
    assert_frame_equal(get_visibility_df(r), get_visibility_df(r, int(r.host_vehicle_idx)))
    # a plain table names no host vehicle: the error says what the recording holds, types and idx
    with pytest.raises(OptionError, match=r"names no host vehicle \(present: VEHICLE idx \[0, 1\]; PEDESTRIAN idx"):
        get_visibility_df(STREET)


def test_the_resolved_question() -> None:
    scene = resolve(Query(observers=[0, 1], sensors="typical", static_occluders=[WALL]), STREET)
    assert scene.egos.tolist() == [0, 1] and scene.with_ego and scene.engine == "visilibity"
    assert set(scene.sensors) == {0, 1} and scene.sensor_names[0] == "front_camera"  # fitted to each observer
    assert len(scene.statics.geometries) == 1
    assert scene.objects.n_frames == 2 and scene.static_positions is None


def test_the_metric_takes_the_question() -> None:
    from omega_prime.metrics import MetricManager

    from omega_prime_visibility import visibility
    from omega_prime_visibility.inputs.io import read_recording

    r = read_recording(REPO / "highway_merge.mcap")
    question = Query(observers=0, engine="sweep", targets="vehicles")
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, properties = MetricManager(metrics=[visibility]).compute(r, query=question)
    table = properties["visibility"].lazy().collect()
    assert_frame_equal(table, get_visibility_df(r, query=question))
    assert np.unique(table["idx"]).tolist() == [1, 2, 3, 4, 5, 6]


def test_boxes_and_a_static_wall_through_a_query_in_3d() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (20, 0, 4, 2, 0)]).with_columns(
        z=pl.lit(0.75), height=pl.lit(1.5), roll=pl.lit(0.0), pitch=pl.lit(0.0)
    )
    low = Query(observers=0, mode="3d", static_occluders=[shapely.box(10, -5, 10.5, 5)], static_heights=0.8)
    seen = get_visibility_df(df, query=low)["visibility"][0]
    assert 0.0 < seen < 1.0  # over a 0.8 m rail from the eye at 1.25 m
    assert_frame_equal(
        get_visibility_df(df, query=low),
        get_visibility_df(df, 0, [shapely.box(10, -5, 10.5, 5)], mode="3d", static_occluder_heights=0.8),
    )
