"""Input validation at the edge (scene.py): invalid outlines are kept where they can be, static occluders of every
shapely kind, clear errors for what has no extent. Expected values are derived on paper in the comments."""

from __future__ import annotations

import math
import warnings

import polars as pl
import pytest
import shapely

from omega_prime_visibility import ENGINES, VisibilityInputWarning, get_visibility_df
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders, polygonal_and_lineal_parts

EGO = shapely.box(-2, -1, 2, 1)
BOWTIE = shapely.Polygon([(10, -1), (12, 1), (12, -1), (10, 1), (10, -1)])  # self-crossing: a box, corners swapped
# behind the bow-tie and a little to the left: bearings atan2(1, 21) .. atan2(2, 19) from the origin
TARGET = shapely.box(19, 1, 21, 2)
T_LO, T_HI = math.atan2(1, 21), math.atan2(2, 19)


def table(polygons, boxes: bool = False) -> pl.DataFrame:
    df = pl.DataFrame(
        {
            "frame": [0] * len(polygons),
            "total_nanos": [0] * len(polygons),
            "idx": list(range(len(polygons))),
            "x": [0.0, 11.0, 20.0, 15.0][: len(polygons)],
            "y": [0.0, 0.0, 1.5, 0.0][: len(polygons)],
            "polygon": pl.Series(polygons, dtype=pl.Object),
        }
    )
    if boxes:  # the tracker's own box for the bow-tie: 3 m x 1 m around (11, 0)
        df = df.with_columns(
            length=pl.Series([4.0, 3.0, 2.0, 1.0][: len(polygons)]),
            width=pl.Series([2.0, 1.0, 1.0, 1.0][: len(polygons)]),
            yaw=pl.Series([0.0] * len(polygons)),
        )
    return df


def rows(df: pl.DataFrame) -> dict[int, dict]:
    return {r["idx"]: r for r in df.iter_rows(named=True)}


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_bowtie_without_box_columns_is_repaired_to_its_hull(engine: str) -> None:
    with pytest.warns(VisibilityInputWarning, match=r"1 invalid .* repaired with shapely.make_valid.*idx 1"):
        out = rows(get_visibility_df(table([EGO, BOWTIE, TARGET]), 0, engine=engine))
    assert out[1]["visibility"] == 1.0 and out[1]["occluder_idxs"] == []
    # the hull is the square [10, 12] x [-1, 1]; its corner (10, 1) hides the target up to bearing atan2(1, 10)
    expected = (T_HI - math.atan2(1, 10)) / (T_HI - T_LO)
    assert out[2]["visibility"] == pytest.approx(expected, abs=1e-9)
    assert out[2]["occluder_idxs"] == [1]


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_bowtie_with_box_columns_falls_back_to_the_box(engine: str) -> None:
    with pytest.warns(VisibilityInputWarning, match=r"replaced by their length/width/yaw box.*idx 1"):
        out = rows(get_visibility_df(table([EGO, BOWTIE, TARGET], boxes=True), 0, engine=engine))
    # the box [9.5, 12.5] x [-0.5, 0.5] hides the target up to bearing atan2(0.5, 9.5)
    expected = (T_HI - math.atan2(0.5, 9.5)) / (T_HI - T_LO)
    assert out[2]["visibility"] == pytest.approx(expected, abs=1e-9)
    assert out[1]["visibility"] == 1.0 and out[2]["occluder_idxs"] == [1]


def test_bowtie_hides_what_lies_straight_behind_it() -> None:
    behind = shapely.box(19, -0.5, 21, 0.5)
    with pytest.warns(VisibilityInputWarning):
        out = rows(get_visibility_df(table([EGO, BOWTIE, behind]), 0))
    assert (out[1]["visibility"], out[2]["visibility"], out[2]["occluder_idxs"]) == (1.0, 0.0, [1])


def test_invalid_outline_raises_with_on_invalid_raise() -> None:
    with pytest.raises(ValueError, match=r"invalid.*self-intersecting"):
        get_visibility_df(table([EGO, BOWTIE, TARGET]), 0, on_invalid="raise")


def test_multipolygon_outline_is_repaired_and_unrepairable_ones_skipped() -> None:
    two = shapely.MultiPolygon([shapely.box(10, -1, 11, 1), shapely.box(11.5, -1, 12, 1)])
    flat = shapely.Polygon([(14, 0), (15, 0), (16, 0), (14, 0)])  # no area: nothing to repair
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        out = rows(get_visibility_df(table([EGO, two, TARGET, flat]), 0))
    messages = " ".join(str(w.message) for w in caught)
    assert "skipping 1 of 4" in messages and "zero-size" in messages and "repaired" in messages
    assert set(out) == {1, 2}
    # the multipolygon's hull is again [10, 12] x [-1, 1]
    assert out[2]["visibility"] == pytest.approx((T_HI - math.atan2(1, 10)) / (T_HI - T_LO), abs=1e-9)


def test_valid_outlines_are_used_unchanged_and_silently() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        objects = load_objects(table([EGO, shapely.box(10, -1, 12, 1), TARGET]))
    ring = objects.rings.ring(1)
    assert sorted(map(tuple, ring.tolist())) == [(10.0, -1.0), (10.0, 1.0), (12.0, -1.0), (12.0, 1.0)]


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_geometry_collection_static_uses_polygons_and_lines(engine: str) -> None:
    # make_valid's answer for a bow-tie wall, a line and a stray point: the triangles and the line block, the point not
    repaired = shapely.make_valid(shapely.Polygon([(10, -1), (12, 1), (12, -1), (10, 1)]))
    collection = shapely.GeometryCollection(
        [*repaired.geoms, shapely.LineString([(15, -5), (15, 5)]), shapely.Point(3, 0)]
    )
    objects = table([EGO, shapely.box(19, -0.5, 21, 0.5)])
    out = rows(get_visibility_df(objects, 0, [collection], engine=engine))
    assert out[1]["visibility"] == 0.0 and out[1]["static_occluder_idxs"] == [0]
    statics = load_static_occluders([collection])
    assert len(statics.rings) == 2 and len(statics.segments) == 1 and set(statics.ring_source) == {0}


@pytest.mark.parametrize(
    ("static", "message"),
    [
        (shapely.Point(1, 1), "Point without polygonal or lineal parts"),
        (shapely.MultiPoint([(1, 1), (2, 2)]), "MultiPoint without polygonal or lineal parts"),
        (shapely.GeometryCollection([shapely.Point(1, 1)]), "GeometryCollection without polygonal"),
        (shapely.GeometryCollection([shapely.Polygon([(0, 5), (1, 6), (1, 5), (0, 6)])]), "invalid polygon"),
        (shapely.GeometryCollection(), "empty"),
    ],
)
def test_static_occluders_without_extent_are_refused(static, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        load_static_occluders([static])


def test_polygonal_and_lineal_parts_of_nested_collections() -> None:
    ring = shapely.LinearRing([(0, 0), (1, 0), (1, 1)])
    nested = shapely.GeometryCollection(
        [shapely.MultiPolygon([shapely.box(0, 0, 1, 1), shapely.box(2, 0, 3, 1)]), shapely.GeometryCollection([ring])]
    )
    polygons, lines = polygonal_and_lineal_parts(nested)
    assert [p.area for p in polygons] == [1.0, 1.0]
    assert len(lines) == 1 and lines[0].is_closed


@pytest.mark.parametrize("yaws", [[90.0, 180.0, -90.0], [0.0, 45.0, 10.0]])
def test_headings_in_degrees_are_told(yaws) -> None:
    # omega-prime's yaw is radians in [-pi, pi]: 90, 180 or 45 on an object are degrees
    df = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2], "x": [0.0, 10.0, 20.0],
                       "y": [0.0, 0.0, 0.0], "length": [4.0] * 3, "width": [2.0] * 3, "yaw": yaws})  # fmt: skip
    largest = max(yaws, key=abs)
    with pytest.warns(VisibilityInputWarning, match=rf"beyond a full turn \(up to {largest:g}\).*looks like degrees"):
        load_objects(df)


def test_headings_within_a_turn_say_nothing() -> None:
    # radians anywhere in [-2 pi, 2 pi] (an unwrapped 6 rad too) are plausible headings
    df = pl.DataFrame({"frame": [0, 0, 0], "total_nanos": [0, 0, 0], "idx": [0, 1, 2], "x": [0.0, 10.0, 20.0],
                       "y": [0.0, 0.0, 0.0], "length": [4.0] * 3, "width": [2.0] * 3,
                       "yaw": [-math.pi, 6.0, 2 * math.pi]})  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        load_objects(df)


def test_a_part_of_the_table_keeps_every_per_row_field() -> None:
    # frames 1..2 of three, and some rows: every per-row field comes along (the heading flags were once dropped)
    from dataclasses import fields

    import numpy as np

    boxes = [shapely.box(x, -1, x + 4, 1) for x in (0.0, 10.0, 20.0)]
    df = pl.DataFrame(
        {"frame": [0, 0, 0, 1, 1, 1, 2, 2, 2], "total_nanos": [0, 0, 0, 1, 1, 1, 2, 2, 2], "idx": [0, 1, 2] * 3,
         "x": [2.0, 12.0, 22.0] * 3, "y": [0.0] * 9, "yaw": [0.0, float("nan"), 0.0] * 3,
         "polygon": pl.Series(boxes * 3, dtype=pl.Object)}
    )  # fmt: skip
    objects = load_objects(df, occluders=[1], targets=[2])
    assert objects.heading_known is not None and objects.blocks is not None and objects.wanted is not None
    s, e = int(objects.frame_starts[1]), int(objects.frame_starts[3])
    for part, rows in (
        (objects.frame_range(1, 3), np.arange(s, e)),
        (objects.take_rows(np.array([1, 4, 7])), [1, 4, 7]),
    ):
        for f in fields(objects):
            whole, got = getattr(objects, f.name), getattr(part, f.name)
            if f.name == "rings":
                assert [got.ring(k).tolist() for k in range(len(rows))] == [whole.ring(r).tolist() for r in rows]
            elif f.name != "frame_starts" and whole is not None:
                assert np.array_equal(got, whole[rows]), f.name
