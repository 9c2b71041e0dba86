"""Static occluder files and their heights: GeoJSON properties, WKT columns, JSON lists of {"wkt", "height"},
the note saying where the heights came from, and every shape a file may not have told in one line."""

from __future__ import annotations

import json
import subprocess
import sys

import polars as pl
import pytest
import shapely
from conftest import REPO

from omega_prime_visibility import Query, get_visibility_df
from omega_prime_visibility.inputs.io import RecordingReadError, read_static_file, read_static_occluders

WALL = [[5.0, -3.0], [5.0, 3.0]]


def geojson(*features) -> str:
    return json.dumps({"type": "FeatureCollection", "features": [
        {"type": "Feature", "properties": props, "geometry": {"type": "LineString", "coordinates": coords}}
        for coords, props in features
    ]})  # fmt: skip


@pytest.mark.parametrize(
    ("name", "text", "heights", "said"),
    [
        ("walls.geojson", geojson((WALL, {"height": 1.0}), (WALL, {"height": "2.5"})), (1.0, 2.5), "property 'height'"),
        ("walls.geojson", geojson((WALL, {"name": "x"})), None, None),
        ("city.json", json.dumps([{"wkt": "LINESTRING (5 -3, 5 3)", "height": 1}, {"wkt": "POINT (9 9)", "height": 2}]),
         (1.0, 2.0), "key 'height'"),
        ("walls.wkt", "# heights after the geometry\nLINESTRING (5 -3, 5 3) 1.0\nLINESTRING (5 -3, 5 3);2\n",
         (1.0, 2.0), "the column after each WKT geometry"),
        ("walls.wkt", "LINESTRING (5 -3, 5 3)\n", None, None),
    ],
)  # fmt: skip
def test_heights_are_read_where_files_carry_them(tmp_path, name, text, heights, said) -> None:
    path = tmp_path / name
    path.write_text(text)
    found = read_static_file(path)
    assert found.heights == heights
    assert [g.geom_type for g in found.geometries] == [g.geom_type for g in read_static_occluders(path)]
    if said is None:
        assert found.note is None
    else:
        assert said in found.note and name in found.note


@pytest.mark.parametrize(
    ("name", "text", "words"),
    [
        ("b.json", json.dumps([{"geometry": "x"}]), 'item 0 is no {"wkt": ..., "height": ...} object; it may hold'),
        ("b.json", json.dumps({"buildings": []}), "JSON of no shape it may have: it may hold a GeoJSON"),
        ("b.json", "{not json", "as JSON"),
        ("b.geojson", geojson((WALL, {"height": -1})), "feature 0 has the height -1"),
        ("b.geojson", geojson((WALL, {"height": "tall"})), "feature 0 has a height that is no number ('tall')"),
        ("b.wkt", "LINESTRING (5 -3, 5 3) 0\n", "line 1 has the height '0'"),
        ("b.json", json.dumps([{"wkt": "POLYGON ((0 0, 1"}]), "item 0's wkt"),
        ("b.geojson", geojson((WALL, {"height": 1.0}), (WALL, {})), "1 of 2 occluders have a height (the property"),
        ("b.wkt", "LINESTRING (5 -3, 5 3) 3\nLINESTRING (5 -3, 5 3)\n", "but occluder 1 has none: give every"),
    ],
)
def test_files_of_no_shape_they_may_have_are_one_line(tmp_path, name, text, words) -> None:
    path = tmp_path / name
    path.write_text(text)
    with pytest.raises(RecordingReadError) as caught:
        read_static_file(path)
    assert words in str(caught.value) and str(path) in str(caught.value) and "\n" not in str(caught.value)


def walker_behind_a_wall() -> pl.DataFrame:
    # the ego's eye 1.25 m up at the origin, a 1.8 m pedestrian 10 m ahead behind a wall at x = 5
    rows = [(0, 0.0, 4.5, 1.8, 1.5, 0.75), (1, 10.0, 0.5, 0.5, 1.8, 0.9)]
    return pl.DataFrame(
        [{"frame": 0, "total_nanos": 0, "idx": i, "x": x, "y": 0.0, "z": z, "length": length, "width": width,
          "height": height, "yaw": 0.0, "pitch": 0.0, "roll": 0.0} for i, x, length, width, height, z in rows]
    )  # fmt: skip


def test_the_shell_takes_the_files_heights_in_3d(tmp_path) -> None:
    # a 1 m wall (its height a GeoJSON property) leaves the walker's head seen from the driver's eye in 3D; without
    # the height it blocks up to the sky; the shell says where the heights came from
    wall = tmp_path / "wall.geojson"
    wall.write_text(geojson((WALL, {"height": 1.0})))
    recording = tmp_path / "walker.parquet"
    walker_behind_a_wall().write_parquet(recording)
    expected = get_visibility_df(walker_behind_a_wall(), query=Query(observers=0, mode="3d",
                                 static_occluders=[shapely.LineString(WALL)], static_heights=1.0))  # fmt: skip
    assert 0.2 < expected["visibility"][0] < 0.9
    out = tmp_path / "vis.csv"
    from omega_prime_visibility.cli.common import shell_query

    question = shell_query(None, ego="0", static=wall, mode="3d")
    assert question.static_heights == (1.0,)
    table = get_visibility_df(walker_behind_a_wall(), query=question)
    assert table["visibility"].to_list() == expected["visibility"].to_list()
    done = subprocess.run([sys.executable, "-m", "omega_prime_visibility", "batch", str(REPO / "highway_merge.mcap"),
                           "-o", str(tmp_path / "out"), "--static", str(wall), "--mode", "3d", "--no-progress",
                           "--engine", "silhouette3d"], capture_output=True, text=True)  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "static occluders: heights of 1 of 1 static occluders from the property 'height' of wall.geojson" in (
        done.stdout
    )
    assert not out.exists()
