"""The Metric inside omega-prime's MetricManager, the bundled recording, and the real esmini recordings."""

from __future__ import annotations

import warnings
from importlib.metadata import entry_points

import numpy as np
import omega_prime
import polars as pl
import pytest
import shapely
from conftest import REPO

from omega_prime_visibility import get_visibility_df, metrics, visibility
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.sensors import typical

WALL = shapely.Polygon([(-220, 10), (-120, 10), (-120, 0), (-220, 0)])


@pytest.fixture(scope="module")
def bundled() -> omega_prime.Recording:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return omega_prime.Recording.from_file(str(REPO / "highway_merge.mcap"), compute_polygons=True)


def test_metric_runs_inside_metric_manager(bundled: omega_prime.Recording) -> None:
    manager = omega_prime.metrics.MetricManager(metrics=[visibility, omega_prime.metrics.vel])
    df, properties = manager.compute(bundled, ego_id=0)
    assert "vel" in df.columns
    expected = get_visibility_df(bundled, 0)
    assert properties["visibility"].equals(expected)
    from omega_prime_visibility import occluded_conflicts_metric

    assert metrics == [visibility, occluded_conflicts_metric]  # every Metric of the package, for plugin discovery


def test_metric_passes_static_occluders_and_engine(bundled: omega_prime.Recording) -> None:
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    _, properties = manager.compute(bundled, ego_id=0, static_occluder_polys=[WALL], engine="visilibity")
    assert properties["visibility"].equals(get_visibility_df(bundled, 0, [WALL]))


def test_metric_passes_sensors(bundled: omega_prime.Recording) -> None:
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    _, properties = manager.compute(bundled, ego_id=0, sensors="typical", engine="sweep")
    expected = get_visibility_df(bundled, 0, sensors="typical", engine="sweep")
    assert properties["visibility"].equals(expected)
    assert set(expected["sensor"]) == {s.name for s in typical()}


def test_metric_passes_the_choices(bundled: omega_prime.Recording) -> None:
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    choices = {"occluders": ["CAR"], "targets": [2, 3], "measure": "area"}
    _, properties = manager.compute(bundled, ego_id=0, **choices)
    expected = get_visibility_df(bundled, 0, **choices)
    assert properties["visibility"].equals(expected)
    assert expected["idx"].unique().sort().to_list() == [2, 3]
    assert not expected["occluder_idxs"].list.contains(1).any()  # the truck (HEAVY_TRUCK) may not block
    assert not expected.equals(get_visibility_df(bundled, 0, targets=[2, 3]))


def test_entry_point_is_declared() -> None:
    eps = entry_points(group="omega_prime.plugins.metric")
    assert any(ep.name == "visibility" and ep.load() is visibility for ep in eps)


def test_bundled_recording_has_real_occlusion(bundled: omega_prime.Recording) -> None:
    out = get_visibility_df(bundled, 0)
    frames = bundled._df["frame"].n_unique()
    assert out.height == frames * (bundled._df["idx"].n_unique() - 1)
    # the truck (idx 1) hides the merging cars for a good part of the recording
    hidden = out.filter(pl.col("visibility") == 0.0)
    assert hidden.height > 20
    assert hidden["occluder_idxs"].list.contains(1).any()
    partly = out.filter(pl.col("visibility").is_between(0.01, 0.99))
    assert partly.height > 20


def test_polygon_column_and_boxes_agree(bundled: omega_prime.Recording) -> None:
    df = bundled._df
    from_boxes = get_visibility_df(df.drop("polygon"), 0)
    from_polygons = get_visibility_df(df, 0)
    assert from_boxes.drop("visibility").equals(from_polygons.drop("visibility"))
    assert np.allclose(from_boxes["visibility"], from_polygons["visibility"], atol=1e-9)


def test_upstream_recording_with_wall(shared_data) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = omega_prime.Recording.from_file(str(shared_data / "highway_merge.mcap"), compute_polygons=True)
    out = get_visibility_df(r, 0, [WALL])
    first = out.filter((pl.col("frame") == 0) & (pl.col("idx") == 1)).row(0, named=True)
    # the upstream README rounds this to 0.42
    assert first["visibility"] == pytest.approx(0.42, abs=0.01)
    assert first["static_occluder_idxs"] == [0]


@pytest.mark.parametrize(
    ("trace", "xodr"),
    [
        ("acc-test.osi", "straight_500m.xodr"),
        ("alks_cut-in.osi", "straight_500m.xodr"),
        ("pedestrian.osi", "fabriksgatan.xodr"),
        ("highway_merge.osi", "soderleden.xodr"),
    ],
)
def test_real_osi_traces(shared_data, trace: str, xodr: str) -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = omega_prime.Recording.from_file(
            str(shared_data / trace), map_path=str(shared_data / xodr), compute_polygons=True
        )
    objects = load_objects(r)
    ego = int(objects.idx[0])
    out = get_visibility_df(r, "all" if trace == "pedestrian.osi" else ego)
    assert out.height > 0
    assert out["visibility"].is_between(0.0, 1.0).all()
    assert out["visibility"].is_nan().sum() == 0
    # through the typical sensor set, with both engines agreeing
    views = [get_visibility_df(r, ego, sensors="typical", engine=e) for e in ("sweep", "visilibity")]
    from_ego = out.filter(pl.col("idx_ego") == ego) if "idx_ego" in out.columns else out
    assert views[0].height == 6 * from_ego.height
    assert views[0].drop("visibility").equals(views[1].drop("visibility"))
    assert (views[0]["visibility"] - views[1]["visibility"]).abs().max() < 1e-6
    assert (views[0]["visibility"] <= views[0]["in_view"]).all()


def test_path_input_and_corrupt_file(tmp_path) -> None:
    from omega_prime_visibility.inputs.io import RecordingReadError

    table = get_visibility_df(str(REPO / "highway_merge.mcap"), 0, progress=False)
    assert table.height == 1206
    bad = tmp_path / "truncated.mcap"
    bad.write_bytes((REPO / "highway_merge.mcap").read_bytes()[:5000])
    with pytest.raises(RecordingReadError, match=r"truncated\.mcap"):
        get_visibility_df(bad, 0)
    with pytest.raises(RecordingReadError, match="does not exist"):
        get_visibility_df(tmp_path / "missing.mcap", 0)


def test_map_that_is_missing_or_no_map(tmp_path, shared_data) -> None:
    from omega_prime_visibility.inputs.io import RecordingReadError, read_recording

    trace = shared_data / "pedestrian.osi"
    with pytest.raises(RecordingReadError, match=r"map .*nowhere\.xodr does not exist"):
        read_recording(trace, tmp_path / "nowhere.xodr")
    (tmp_path / "notes.txt").write_text("not a map")
    with pytest.raises(RecordingReadError, match=r"cannot read map .*notes\.txt \(no map reader for '\.txt' files\)"):
        read_recording(trace, tmp_path / "notes.txt")
    assert type(read_recording(trace, shared_data / "fabriksgatan.xodr").map).__name__ == "MapOdr"


def test_a_map_given_for_an_mcap_file_is_told(tmp_path) -> None:
    # an MCAP file carries its own map: a map given with it replaces that, and the reader says so in one line
    from omega_prime_visibility.inputs.io import MapNotice, read_recording

    road = tmp_path / "road.xodr"
    road.write_text(
        '<?xml version="1.0"?><OpenDRIVE><header revMajor="1" revMinor="6"/><road name="r" length="600" id="1" '
        'junction="-1"><planView><geometry s="0" x="-300" y="0" hdg="0" length="600"><line/></geometry></planView>'
        "</road></OpenDRIVE>"
    )
    with pytest.warns(MapNotice, match=r"highway_merge\.mcap is read with the map road\.xodr given, in place of"):
        r = read_recording(REPO / "highway_merge.mcap", road)
    assert type(r.map).__name__ == "MapOdr"
