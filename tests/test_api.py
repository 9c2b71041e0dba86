"""Hand-made scenes with answers derived on paper, through the public front end."""

from __future__ import annotations

import math
import warnings

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table

from omega_prime_visibility import ENGINES as ALL_ENGINES
from omega_prime_visibility import (
    SCHEMA,
    Sensor,
    VisibilityInputWarning,
    get_visibility_df,
    get_visibility_df_for_frame,
)

ENGINES = sorted(ALL_ENGINES)


def row(df: pl.DataFrame, idx: int) -> dict:
    return df.filter(pl.col("idx") == idx).row(0, named=True)


@pytest.mark.parametrize("engine", ENGINES)
def test_free_view_and_fully_hidden(engine: str) -> None:
    # ego at origin; a 4 m wide wall-like car at x=10 hides a 2 m wide car at x=20 completely
    df = get_visibility_df(boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)]), 0, engine=engine)
    assert df.columns == [c for c in SCHEMA if c != "idx_ego"]
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["occluder_idxs"] == []
    assert row(df, 2)["visibility"] == 0.0 and row(df, 2)["occluder_idxs"] == [1]


@pytest.mark.parametrize("engine", ENGINES)
def test_half_hidden_behind_static_wall(engine: str) -> None:
    # target: square side 2 centred at (10, 0); its extent from the origin is symmetric about +x, so a wall
    # along the +x axis between observer and target (y from -5 to 0 at x = 5) hides exactly the lower half.
    wall = shapely.Polygon([(5, -5), (5.1, -5), (5.1, 0), (5, 0)])
    df = get_visibility_df(boxes_table([(0, 0, 1, 1, 0), (10, 0, 2, 2, 0)]), 0, [wall], engine=engine)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=1e-9)
    assert row(df, 1)["static_occluder_idxs"] == [0]
    assert row(df, 1)["occluder_idxs"] == []


@pytest.mark.parametrize("engine", ENGINES)
def test_linestring_wall(engine: str) -> None:
    wall = shapely.LineString([(5, -5), (5, 0)])
    df = get_visibility_df(boxes_table([(0, 0, 1, 1, 0), (10, 0, 2, 2, 0)]), 0, [wall], engine=engine)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=1e-6)
    assert row(df, 1)["static_occluder_idxs"] == [0]


@pytest.mark.parametrize("engine", ENGINES)
@pytest.mark.parametrize("angle", [math.pi, -math.pi + 1e-3, math.pi / 2, -3 * math.pi / 4])
def test_wraparound_and_behind(engine: str, angle: float) -> None:
    # the same scene rotated: a blocker half covering the target; at pi the target straddles the -pi/pi cut
    c, s = math.cos(angle), math.sin(angle)
    boxes = [(0, 0, 1, 1, 0), (10 * c, 10 * s, 2, 2, angle), (5 * c + 2.5 * s, 5 * s - 2.5 * c, 0.2, 5, angle)]
    df = get_visibility_df(boxes_table(boxes), 0, engine=engine)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=1e-9)
    assert row(df, 1)["occluder_idxs"] == [2]


@pytest.mark.parametrize("engine", ENGINES)
def test_object_containing_observer_is_transparent(engine: str) -> None:
    # a big object (idx 1) contains the ego's centre: it is transparent, visibility 1, never an occluder
    boxes = [(0, 0, 4, 2, 0), (1, 0, 10, 6, 0), (20, 0, 4, 2, 0)]
    with pytest.warns(VisibilityInputWarning, match="contains observer"):
        df = get_visibility_df(boxes_table(boxes), 0, engine=engine)
    assert row(df, 1)["visibility"] == 1.0 and row(df, 1)["occluder_idxs"] == []
    assert row(df, 2)["visibility"] == 1.0 and row(df, 2)["occluder_idxs"] == []
    # through two sensors both inside it, it still contains the observer in one frame, not two
    sensors = [Sensor("front", fov=1.0, x=0.5), Sensor("rear", fov=1.0, x=-0.5, yaw=math.pi)]
    with pytest.warns(VisibilityInputWarning, match=r"idx 1 contains observer 0 in 1 frame\(s\)"):
        get_visibility_df(boxes_table(boxes), 0, engine=engine, sensors=sensors)


@pytest.mark.parametrize("engine", ENGINES)
def test_static_occluder_containing_observer_is_transparent_and_told(engine: str) -> None:
    # the ego drives out of a building (static occluder 1, x in [-5, 3]) behind a wall (static occluder 0, x = 10):
    # inside it in frames 0 and 1 (centre x = 0, 2), outside in frame 2 (x = 4); the target at x = 20 is behind the
    # wall in every frame, never behind the building
    df = pl.concat([boxes_table([(2.0 * f, 0, 4, 2, 0), (20, 0, 4, 2, 0)], frame=f) for f in range(3)])
    statics = [shapely.LineString([(10, -10), (10, 10)]), shapely.box(-5, -5, 3, 5)]
    message = r"static occluder 1 contains observer 0 in 2 frame\(s\) \(first frame 0\)"
    for sensors in (None, [Sensor("front", fov=1.0, x=0.5), Sensor("rear", fov=1.0, x=-0.5, yaw=math.pi)]):
        with pytest.warns(VisibilityInputWarning, match=message):
            out = get_visibility_df(df, 0, statics, engine=engine, sensors=sensors)
        assert out["visibility"].max() == 0.0  # (behind the rear sensor, out of view: 0 as well)
        listed = out["static_occluder_idxs"].to_list()
        assert all(s == [0] for s in listed) if sensors is None else all(s in ([0], []) for s in listed)
    with warnings.catch_warnings():  # outside the building: nothing to tell
        warnings.simplefilter("error")
        get_visibility_df(df.filter(pl.col("frame") == 2), 0, statics, engine=engine)
    # a low static occluder first in the list, which the 2D height rule leaves out: the building is still named by
    # its position in the user's list, as static_occluder_idxs names the wall
    low = shapely.box(50, 50, 60, 60)
    message = r"static occluder 2 contains observer 0 in 2 frame\(s\)"
    with pytest.warns(VisibilityInputWarning, match=message):
        out = get_visibility_df(df, 0, [low, *statics], engine=engine, static_occluder_heights=[0.5, 10.0, 10.0])
    assert all(s == [1] for s in out["static_occluder_idxs"].to_list())


@pytest.mark.parametrize("engine", ENGINES)
def test_overlapping_objects_and_statics(engine: str) -> None:
    # two overlapping cars at x~10 and a static polygon overlapping one of them, a target behind all
    boxes = [(0, 0, 4, 2, 0), (10, 0.5, 4, 2, 0.3), (10.5, -0.5, 4, 2, -0.2), (30, 0, 4, 16, 0)]
    static = shapely.box(9, -1.5, 12, 1.5)
    df = get_visibility_df(boxes_table(boxes), 0, [static], engine=engine)
    assert 0 < row(df, 3)["visibility"] < 1
    assert row(df, 3)["occluder_idxs"] == [1, 2]
    assert row(df, 3)["static_occluder_idxs"] == [0]


def test_only_ego_frame_and_missing_ego_frames() -> None:
    df = pl.concat([boxes_table([(0, 0, 4, 2, 0)], frame=0), boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)], 1)])
    df = df.vstack(boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)], 2).filter(pl.col("idx") == 1))
    out = get_visibility_df(df, 0)
    assert out["frame"].to_list() == [1]


def test_for_frame_matches_full() -> None:
    df = pl.concat([boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)], f) for f in range(3)])
    one = get_visibility_df_for_frame(df, 0, 1)
    assert one.equals(get_visibility_df(df, 0).filter(pl.col("frame") == 1))
    with pytest.raises(ValueError, match="frame 7 does not occur"):
        get_visibility_df_for_frame(df, 0, 7)


@pytest.mark.parametrize(
    ("mutate", "message"),
    [
        (lambda d: d.drop("x"), r"lacks the column\(s\) \['x'\]"),
        (lambda d: d.drop("yaw"), "lacks \\['yaw'\\]"),
        (lambda d: d.clear(), "empty"),
        (lambda d: d.vstack(d), "appears more than once"),
    ],
)
def test_bad_tables(mutate, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        get_visibility_df(mutate(boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)])), 0)


def test_unknown_ego() -> None:
    with pytest.raises(ValueError, match=r"ego idx \[5\] never occurs"):
        get_visibility_df(boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)]), 5)


def test_nan_pose_row_is_skipped_with_warning() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (np.nan, 0, 4, 2, 0), (20, 0, 4, 2, 0)])
    with pytest.warns(VisibilityInputWarning, match=r"NaN or infinite position.*idx 1"):
        out = get_visibility_df(df, 0)
    assert out["idx"].to_list() == [2]
    with pytest.raises(ValueError, match="NaN"):
        get_visibility_df(df, 0, on_invalid="raise")


def test_nan_ego_pose_skips_frame() -> None:
    df = pl.concat([boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)], f) for f in range(2)])
    df = df.with_columns(x=pl.when((pl.col("frame") == 0) & (pl.col("idx") == 0)).then(None).otherwise(pl.col("x")))
    with pytest.warns(VisibilityInputWarning):
        out = get_visibility_df(df, 0)
    assert out["frame"].to_list() == [1]


def test_zero_size_box_is_skipped() -> None:
    with pytest.warns(VisibilityInputWarning, match="zero-size"):
        out = get_visibility_df(boxes_table([(0, 0, 4, 2, 0), (9, 0, 0, 2, 0), (20, 0, 4, 2, 0)]), 0)
    assert out["idx"].to_list() == [2]


def test_polygon_column_is_used_and_oriented() -> None:
    # clockwise outlines, as omega-prime produces them, give the same answer as boxes
    base = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)])
    polys = [
        shapely.box(x - 2, y - w / 2, x + 2, y + w / 2, ccw=False) for x, y, w in [(0, 0, 2), (10, 0, 4), (20, 0, 2)]
    ]
    with_poly = base.drop("length", "width", "yaw").with_columns(polygon=pl.Series(polys, dtype=pl.Object))
    assert get_visibility_df(with_poly, 0).equals(get_visibility_df(base, 0))


def test_invalid_polygon_rejected() -> None:
    base = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0)])
    bowtie = shapely.Polygon([(8, -1), (12, 1), (12, -1), (8, 1)])
    polys = [shapely.box(-2, -1, 2, 1), bowtie]
    df = base.with_columns(polygon=pl.Series(polys, dtype=pl.Object))
    with pytest.raises(ValueError, match="invalid"):
        get_visibility_df(df, 0, on_invalid="raise")


@pytest.mark.parametrize(
    ("static", "message"),
    [
        (shapely.Polygon([(0, 0), (1, 1), (1, 0), (0, 1)]), "invalid polygon"),
        (shapely.Point(1, 1), "Point"),
        ("wall", "not a shapely geometry"),
        (shapely.LineString([(1, 1), (1, 1)]), "zero length"),
    ],
)
def test_bad_static_occluders(static, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        get_visibility_df(boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)]), 0, [static])


def test_several_observers() -> None:
    df = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 4, 0), (20, 0, 4, 2, 0)])
    out = get_visibility_df(df, "all")
    assert out.columns == list(SCHEMA)
    assert out.height == 6
    seen_from_2 = out.filter(pl.col("idx_ego") == 2)
    assert row(seen_from_2, 0)["visibility"] == 0.0 and row(seen_from_2, 0)["occluder_idxs"] == [1]
    single = get_visibility_df(df, [0])
    assert single.columns == list(SCHEMA)


def highway(frames: int) -> pl.DataFrame:
    rng = np.random.default_rng(3)
    base = [(0, 0, 4.5, 1.9, 0)] + [(rng.uniform(-60, 60), 3.5 * rng.integers(-1, 3), 4.5, 1.9, 0) for _ in range(12)]
    tables = []
    for f in range(frames):
        t = boxes_table([(x + 0.5 * f * (k % 3), y, ln, w, yaw) for k, (x, y, ln, w, yaw) in enumerate(base)], f)
        tables.append(t)
    return pl.concat(tables)


@pytest.mark.filterwarnings("ignore::omega_prime_visibility.VisibilityInputWarning")
def test_chunks_workers_and_parquet_output_give_the_same_table(tmp_path) -> None:
    df = highway(30)
    serial = get_visibility_df(df, 0, workers=1)
    chunked = get_visibility_df(df, 0, workers=1, chunk_frames=7)
    assert chunked.equals(serial)
    parallel = get_visibility_df(df, [0, 3], workers=2, chunk_frames=7)
    assert parallel.filter(pl.col("idx_ego") == 0).drop("idx_ego").equals(serial)
    lazy = get_visibility_df(df, 0, workers=1, chunk_frames=4, output=tmp_path / "vis.parquet")
    assert isinstance(lazy, pl.LazyFrame)
    assert lazy.collect().equals(serial)


def test_unknown_engine() -> None:
    with pytest.raises(ValueError, match="unknown engine 'nope'"):
        get_visibility_df(boxes_table([(0, 0, 4, 2, 0), (9, 0, 4, 2, 0)]), 0, engine="nope")


@pytest.mark.parametrize("engine", sorted(ALL_ENGINES))
def test_self_crossing_wall_blocks_its_share(engine: str) -> None:
    # a MultiLineString whose two lines cross just in front of a box: the crossing line's short piece between the
    # vertical line and the observer blocks a sliver of the target. Without noding, the occlusion test, which
    # assumes a body's nearest edge changes only at its vertices, missed that.
    p1 = 10.2 / np.cos(0.0985) * np.array([np.cos(0.0985), np.sin(0.0985)])
    p2 = 9.9 * np.array([np.cos(0.0997), np.sin(0.0997)])
    q0, q1 = p2 + (p2 - p1) * 0.5, p1 + (p1 - p2) * 30
    wall = shapely.MultiLineString([[(10.2, -5), (10.2, 5)], [tuple(q0), tuple(q1)]])
    out = get_visibility_df(boxes_table([(0, 0, 0.2, 0.2, 0), (10.25, 0, 0.5, 2, 0)]), 0, [wall], engine=engine)
    assert row(out, 1)["static_occluder_idxs"] == [0]
    assert row(out, 1)["visibility"] == pytest.approx(0.99753, abs=1e-4)


@pytest.mark.parametrize("engine", ENGINES)
def test_multipolygon_static_occluder_reported_once(engine: str) -> None:
    # two parts of one MultiPolygon: the first hides the lower half of the target (as in the wall test), the
    # second lies far behind the target; the occluder is reported once, by its position in the list
    parts = shapely.MultiPolygon([shapely.box(5, -5, 5.1, 0), shapely.box(30, -3, 31, 3)])
    statics = [shapely.box(0, 20, 1, 21), parts]
    df = get_visibility_df(boxes_table([(0, 0, 1, 1, 0), (10, 0, 2, 2, 0)]), 0, statics, engine=engine)
    assert row(df, 1)["visibility"] == pytest.approx(0.5, abs=1e-9)
    assert row(df, 1)["static_occluder_idxs"] == [1]


def _street(**columns) -> pl.DataFrame:
    """The ego and two cars in a row, 10 m apart (the second hidden behind the first), with ``columns`` replaced."""
    base = {"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2], "x": [0.0, 10.0, 20.0], "y": [0.0] * 3}
    return pl.DataFrame(base | {"length": [4.0] * 3, "width": [2.0] * 3, "yaw": [0.0] * 3} | columns)


@pytest.mark.parametrize(
    ("columns", "message"),
    [
        ({"frame": [0.0, 0.5, 0.5]}, r"column 'frame' must hold whole numbers \(frame numbers\), not 0.5 \(row 1\)"),
        ({"idx": [0.5, 1.5, 2.5]}, r"column 'idx' must hold whole numbers \(object ids\), not 0.5"),
        ({"idx": ["a", "b", "c"]}, r"column 'idx' must hold whole numbers \(object ids\), not String values"),
        ({"total_nanos": [0.0, float("nan"), 0.0]}, r"column 'total_nanos' must hold whole numbers"),
        ({"x": ["a", "b", "c"]}, r"column 'x' must hold numbers \(metres, radians\), not String"),
        ({"idx": pl.Series([0, 1, 2**64 - 1], dtype=pl.UInt64)}, r"beyond the largest int64"),
    ],
)
def test_columns_that_are_no_numbers_are_refused_not_cut(columns: dict, message: str) -> None:
    # frame 0.5 is not frame 0, idx 0.5 is not idx 0: a silent cut merged frames and renamed objects
    with pytest.raises(ValueError, match=message):
        get_visibility_df(_street(**columns), 0)


def test_whole_floats_are_whole_numbers() -> None:
    out = get_visibility_df(_street(idx=[0.0, 1.0, 2.0], frame=[3.0, 3.0, 3.0]), 0)
    assert out.select("frame", "idx", "occluder_idxs", "visibility").rows() == [(3, 1, [], 1.0), (3, 2, [1], 0.0)]


def test_positions_beyond_a_billion_metres_and_infinite_vertices_are_skipped() -> None:
    with pytest.warns(VisibilityInputWarning, match=r"1 position\(s\) beyond 1e\+09 m.*\(frame 0, idx 2\)"):
        out = get_visibility_df(_street(x=[0.0, 10.0, 1e15]), 0)
    assert out.select("idx", "visibility").rows() == [(1, 1.0)]
    polygons = [shapely.box(-2, -1, 2, 1), shapely.Polygon([(9, -1), (11, -1), (math.inf, 1), (9, 1)])]
    polygons.append(shapely.box(19, -1, 21, 1))
    table = _street().drop("length", "width").with_columns(polygon=pl.Series(polygons, dtype=pl.Object))
    with pytest.warns(VisibilityInputWarning, match=r"skipping 1 of 3.*non-finite.*\(frame 0, idx 1\)"):
        out = get_visibility_df(table, 0)
    assert out.select("idx", "visibility").rows() == [(2, 1.0)]
    with pytest.raises(ValueError, match="a NaN or infinite vertex"):
        get_visibility_df(table, 0, on_invalid="raise")


def test_boxes_of_negative_size_are_skipped_and_a_table_with_no_usable_row_is_refused() -> None:
    # a negative length and width multiply to a positive area: still no box (broken data), skipped and told
    with pytest.warns(
        VisibilityInputWarning, match=r"skipping 1 of 3.*1 zero-size or negative box.*\(frame 0, idx 1\)"
    ):
        out = get_visibility_df(_street(length=[4.0, -4.0, 4.0], width=[2.0, -2.0, 2.0]), 0)
    assert out.select("idx", "visibility").rows() == [(2, 1.0)]
    # nothing usable at all: the reason, not an ego that never occurs
    for columns in ({"yaw": [math.nan] * 3}, {"width": [0.0] * 3}, {"x": [math.inf] * 3}):
        with pytest.raises(ValueError, match=r"none of the 3 object row\(s\) is usable: 3 "):
            get_visibility_df(_street(**columns), 0)


def test_an_observer_without_a_heading_cannot_turn_its_sensors() -> None:
    # with a polygon column no yaw is needed for outlines, but sensors turn with their observer: a NaN yaw is not 0
    polygons = [shapely.box(-2, -1, 2, 1), shapely.box(-12, -1, -8, 1), shapely.box(8, -1, 12, 1)]
    table = _street(x=[0.0, -10.0, 10.0], yaw=[math.nan, 0.0, 0.0]).drop("length", "width")
    table = table.with_columns(polygon=pl.Series(polygons, dtype=pl.Object))
    assert get_visibility_df(table, 0)["visibility"].to_list() == [1.0, 1.0]  # no sensors: no heading needed
    camera = Sensor("camera", fov=1.0)
    with pytest.warns(VisibilityInputWarning, match=r"skipping 1 observer row\(s\) without a heading.*idx 0"):
        assert get_visibility_df(table, 0, sensors=[camera]).height == 0
    with pytest.raises(ValueError, match="without a heading"):
        get_visibility_df(table, 0, sensors=[camera], on_invalid="raise")


def test_times_that_do_not_go_with_frames_are_told() -> None:
    base = {"frame": [0, 0, 1, 1], "idx": [0, 1, 0, 1], "x": [0.0, 10.0, 0.0, 10.0], "y": [0.0] * 4}
    base |= {"length": [4.0] * 4, "width": [2.0] * 4, "yaw": [0.0] * 4}
    with pytest.warns(VisibilityInputWarning, match="total_nanos does not increase from frame 0 to frame 1"):
        get_visibility_df(pl.DataFrame(base | {"total_nanos": [100, 100, 50, 50]}), 0)
    with pytest.warns(VisibilityInputWarning, match=r"1 frame\(s\) hold rows of different total_nanos"):
        get_visibility_df(pl.DataFrame(base | {"total_nanos": [100, 101, 200, 200]}), 0)


@pytest.mark.parametrize(
    ("kwargs", "message"),
    [
        ({"workers": 0}, "workers takes a whole number, at least 1, not 0"),
        ({"workers": 2.5}, "workers takes a whole number, at least 1, not 2.5"),
        ({"chunk_frames": 1.5}, "chunk_frames takes a whole number, at least 1, not 1.5"),
        ({"on_invalid": "ignore"}, "on_invalid takes 'warn'"),
    ],
)
def test_bad_options_are_one_clear_error(kwargs: dict, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        get_visibility_df(_street(), 0, **kwargs)


def test_bad_frame_arguments_for_one_frame() -> None:
    with pytest.raises(ValueError, match="frame takes a frame number"):
        get_visibility_df_for_frame(_street(), 0, "0")
    with pytest.raises(ValueError, match="column 'frame' must hold whole numbers"):
        get_visibility_df_for_frame(_street(frame=["0", "0", "0"]), 0, 0)


def test_pandas_and_pyarrow_tables_are_read_as_polars_would_be() -> None:
    pd = pytest.importorskip("pandas")
    pa = pytest.importorskip("pyarrow")
    boxes = _street()
    polygons = [shapely.box(-2, -1, 2, 1), shapely.box(8, -1, 12, 1), shapely.box(18, -1, 22, 1)]
    outlines = pd.DataFrame(boxes.drop("length", "width").to_dict(as_series=False) | {"polygon": polygons})
    expected = get_visibility_df(boxes, 0)
    for table in (boxes.to_pandas(), pa.Table.from_pandas(boxes.to_pandas()), outlines):
        assert get_visibility_df(table, 0).equals(expected)
    with pytest.raises(TypeError, match="a polars, pandas or pyarrow table of moving objects"):
        get_visibility_df([1, 2], 0)


def test_an_ego_absent_from_the_frame_asked_for_is_named() -> None:
    table = pl.concat([_street(), _street(frame=[1, 1, 1]).filter(pl.col("idx") != 0)])
    with pytest.raises(ValueError, match=r"ego idx \[0\] not present in frame 1 \(idx there: \[1, 2\]\)"):
        get_visibility_df_for_frame(table, 0, 1)
    assert get_visibility_df_for_frame(table, 1, 1).select("idx", "visibility").rows() == [(2, 1.0)]


def test_visible_area_refuses_a_frame_that_is_no_number() -> None:
    from omega_prime_visibility import visible_area

    with pytest.raises(ValueError, match="frame takes a frame number"):
        visible_area(_street(), 0, None)
