"""Drop-in compatibility with the published omega-prime-visibility 0.1.0.

The code strings below are copied verbatim from 0.1.0's README.md and tutorial.ipynb (the sdist on PyPI); they run
here on the bundled ``highway_merge.mcap`` and on the upstream esmini one that 0.1.0 ships (``shared_data``), which
is the recording the published README's table was made from.
"""

from __future__ import annotations

import inspect
import math
import os
import warnings
from pathlib import Path

import omega_prime
import polars as pl
import pytest
import shapely
from conftest import REPO, boxes_table

from omega_prime_visibility import get_visibility_df, get_visibility_df_for_frame, visibility

PUBLISHED_README = """\
from omega_prime_visibility import get_visibility_df
import omega_prime
import shapely

r = omega_prime.Recording.from_file('highway_merge.mcap', compute_polygons=True)

obstruction_poly = shapely.Polygon([
    [-220,10],
    [-120,10],
    [-120,-0],
    [-220,-0],
])
df = get_visibility_df(r._df, ego_idx=0, static_occluder_polys=[obstruction_poly])
"""

PUBLISHED_TUTORIAL_CELLS = [
    """\
from omega_prime_visibility import get_visibility_df
import omega_prime
import shapely""",
    """\
r = omega_prime.Recording.from_file("highway_merge.mcap", compute_polygons=True)""",
    """\
obstruction_poly = shapely.Polygon(
    [
        [-220, 10],
        [-120, 10],
        [-120, -0],
        [-220, -0],
    ]
)
shapely.GeometryCollection(list(r._df.filter(frame=0)["polygon"]) + [obstruction_poly])""",
    """\
df = get_visibility_df(r._df, ego_idx=0, static_occluder_polys=[obstruction_poly])
df""",
    """\
import altair as alt
alt.data_transformers.enable("vegafusion")

alt.Chart(df).mark_line().encode(
    alt.X("frame"), alt.Y("visibility"), alt.Color("idx:N"), tooltip=["idx", "visibility", "frame"]
).properties(title="Visibility of Objects from idx=0")""",
]

# (frame, idx, occluder_idxs, static_occluder_idxs, visibility) as printed in the published README (rounded to 2
# digits by 0.1.0, whose values are off by up to about 0.01 on these rows; ours are exact)
PUBLISHED_README_ROWS = [
    (0, 1, [], [0], 0.42),
    (0, 2, [], [0], 0.0),
    (0, 3, [], [0], 0.0),
    (0, 4, [], [0], 0.0),
    (0, 5, [3], [0], 0.0),
    (1, 1, [], [0], 0.53),
    (1, 2, [], [0], 0.0),
    (1, 3, [], [0], 0.0),
    (1, 4, [], [0], 0.0),
    (1, 5, [3], [0], 0.0),
    (2, 1, [], [0], 0.63),
    (2, 2, [], [0], 0.0),
    (2, 3, [], [0], 0.0),
    (2, 4, [], [0], 0.0),
    (2, 5, [3], [0], 0.0),
    (3, 1, [], [0], 0.74),
    (432, 3, [], [], 1.0),
    (432, 4, [1, 2, 5], [], 0.0),
    (432, 5, [1, 2], [], 0.0),
]
PUBLISHED_COLUMNS = ["frame", "total_nanos", "idx", "occluder_idxs", "static_occluder_idxs", "visibility"]
# a wall that hides part of the bundled recording (the one in our README)
WALL = shapely.LineString([(60, -5.4), (140, -5.4)])


def run_verbatim(cells: list[str], folder: Path) -> dict:
    """Execute the code cells in one namespace with ``folder`` as working directory (files are only read)."""
    cwd = os.getcwd()
    os.chdir(folder)
    namespace: dict = {}
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            for k, cell in enumerate(cells):
                exec(compile(cell, f"published cell {k}", "exec"), namespace)
    finally:
        os.chdir(cwd)
    return namespace


@pytest.fixture(params=["bundled", "upstream"])
def recording_folder(request) -> Path:
    """The folder holding ``highway_merge.mcap``: this repo's, or the upstream one 0.1.0 ships (skipped if absent)."""
    return REPO if request.param == "bundled" else request.getfixturevalue("shared_data")


@pytest.fixture(scope="module")
def bundled() -> omega_prime.Recording:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return omega_prime.Recording.from_file(str(REPO / "highway_merge.mcap"), compute_polygons=True)


def test_published_readme_runs_verbatim(recording_folder: Path) -> None:
    ns = run_verbatim([PUBLISHED_README], recording_folder)
    df = ns["df"]
    assert df.columns == PUBLISHED_COLUMNS
    assert df.height > 0
    ours = get_visibility_df(ns["r"], 0, [ns["obstruction_poly"]], progress=False)
    assert df.equals(ours)


def test_published_readme_table_values(shared_data: Path) -> None:
    df = run_verbatim([PUBLISHED_README], shared_data)["df"]
    assert df.height == 2165  # the tutorial's "shape: (2_165, 6)"
    for frame, idx, occluders, statics, vis in PUBLISHED_README_ROWS:
        row = df.filter(frame=frame, idx=idx).row(0, named=True)
        assert (row["occluder_idxs"], row["static_occluder_idxs"]) == (occluders, statics), (frame, idx)
        assert row["visibility"] == pytest.approx(vis, abs=0.011), (frame, idx)


def test_published_tutorial_runs_verbatim(recording_folder: Path) -> None:
    alt = pytest.importorskip("altair")
    try:
        ns = run_verbatim(PUBLISHED_TUTORIAL_CELLS, recording_folder)
    finally:
        alt.data_transformers.enable("default")
    df = ns["df"]
    assert df.columns == PUBLISHED_COLUMNS
    assert df.schema["visibility"] == pl.Float64 and df.schema["occluder_idxs"] == pl.List(pl.Int64)
    assert df.equals(get_visibility_df(ns["r"], 0, [ns["obstruction_poly"]], progress=False))
    if recording_folder != REPO:
        assert df.shape == (2165, 6)
        assert df.filter(frame=0, idx=1)["visibility"].item() == pytest.approx(0.42, abs=0.005)


def test_epsilon_is_accepted_and_has_no_effect(bundled: omega_prime.Recording) -> None:
    df = bundled._df
    expected = get_visibility_df(df, 0, [WALL], progress=False)
    assert expected.filter(pl.col("static_occluder_idxs").list.len() > 0).height > 0  # the wall matters
    assert get_visibility_df(df, 0, [WALL], 1e-6, progress=False).equals(expected)
    assert get_visibility_df(df, ego_idx=0, static_occluder_polys=[WALL], epsilon=1e-6, progress=False).equals(expected)
    assert get_visibility_df(df, 0, [WALL], epsilon=0, progress=False).equals(expected)
    assert get_visibility_df(df, 0, [WALL], epsilon=0.5, progress=False).equals(expected)
    no_wall = get_visibility_df(df, 0, progress=False)
    assert get_visibility_df(df, ego_idx=0, epsilon=1e-6, progress=False).equals(no_wall)


def test_hide_progress_is_the_published_name_of_progress_false(
    bundled: omega_prime.Recording, capsys, monkeypatch
) -> None:
    from omega_prime_visibility.table import progress

    monkeypatch.setattr(progress, "DELAY_S", 0.0)  # (the bar of a call this short is drawn at once)
    df = bundled._df
    assert df["frame"].n_unique() >= 200  # long enough for the bar to show by default
    expected = get_visibility_df(df, 0, progress=False)
    capsys.readouterr()
    hidden = get_visibility_df(df, ego_idx=0, hide_progress=True)
    assert "visibility" not in capsys.readouterr().err
    assert hidden.equals(expected)
    shown = get_visibility_df(df, ego_idx=0, hide_progress=False)
    assert "visibility" in capsys.readouterr().err
    assert shown.equals(expected)
    assert get_visibility_df(df, 0, hide_progress=True, progress=False).equals(expected)


def test_for_frame_accepts_epsilon(bundled: omega_prime.Recording) -> None:
    df = bundled._df
    frame = 30
    expected = get_visibility_df(df, 0, [WALL], progress=False).filter(frame=frame)
    assert get_visibility_df_for_frame(df, 0, frame, [WALL]).equals(expected)
    assert get_visibility_df_for_frame(df, 0, frame, [WALL], 1e-6).equals(expected)
    assert get_visibility_df_for_frame(df, 0, frame, static_occluder_polys=[WALL], epsilon=1e-6).equals(expected)
    first = get_visibility_df(df, 0, [WALL], progress=False).filter(frame=0)
    assert get_visibility_df_for_frame(df, 0, 0, [WALL], 1e-6).equals(first)


def test_metric_accepts_published_ego_idx(bundled: omega_prime.Recording) -> None:
    _, properties = omega_prime.metrics.MetricManager(metrics=[visibility]).compute(bundled, ego_idx=0)
    assert properties["visibility"].equals(get_visibility_df(bundled, 0))
    _, properties = omega_prime.metrics.MetricManager(metrics=[visibility]).compute(
        bundled, ego_idx=0, static_occluder_polys=[WALL], epsilon=1e-6
    )
    assert properties["visibility"].equals(get_visibility_df(bundled, 0, [WALL]))
    # omega-prime's own name still works, next to omega-prime's metrics
    manager = omega_prime.metrics.MetricManager(metrics=[visibility, omega_prime.metrics.vel])
    df, properties = manager.compute(bundled, ego_id=0)
    assert "vel" in df.columns
    assert properties["visibility"].equals(get_visibility_df(bundled, 0))


@pytest.mark.parametrize("kwargs", [{"ego_id": 0, "ego_idx": 0}, {"ego_id": 0, "ego_idx": 1}])
def test_metric_takes_one_ego_name(bundled: omega_prime.Recording, kwargs: dict) -> None:
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    with pytest.raises(ValueError, match=r"one of ego_id .* and ego_idx .*, not both"):
        manager.compute(bundled, **kwargs)


def test_metric_without_an_ego_takes_the_host_vehicle_as_everything_else_does(bundled, tmp_path) -> None:
    # one default everywhere: get_visibility_df(r), the shell and the Metric all look from the host vehicle
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    _, properties = manager.compute(bundled)
    assert bundled.host_vehicle_idx == 0
    assert properties["visibility"].equals(get_visibility_df(bundled)) and properties["visibility"].height == 1206
    # a recording whose host vehicle is another: that one, not idx 0
    other = omega_prime.Recording(bundled._df.drop("polygon", "geometry"), host_vehicle_idx=3, validate=False)
    _, properties = manager.compute(other)
    assert properties["visibility"].equals(get_visibility_df(other, 3))
    assert 3 not in properties["visibility"]["idx"].to_list()
    # a recording naming no host vehicle: one clear line asking for ego_id
    nameless = omega_prime.Recording(bundled._df.drop("polygon", "geometry"), validate=False)
    with pytest.raises(ValueError, match=r"needs an observer: give ego_id=IDX \(the recording names no host vehicle"):
        manager.compute(nameless)
    # called outside a manager with no recording to ask: the same kind of line
    with pytest.raises(ValueError, match=r"needs an observer: give ego_id=IDX"):
        visibility.compute_lazy(df=bundled._df.lazy())


def test_metric_rejects_bad_epsilon(bundled: omega_prime.Recording) -> None:
    with pytest.raises(ValueError, match="epsilon"):
        omega_prime.metrics.MetricManager(metrics=[visibility]).compute(bundled, ego_idx=0, epsilon=-1.0)


@pytest.mark.parametrize("epsilon", [-1e-6, math.nan, math.inf, -math.inf, "1e-6", True, [1e-6]])
def test_bad_epsilon(epsilon: object) -> None:
    table = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)])
    with pytest.raises(ValueError, match="epsilon must be a non-negative finite number or None"):
        get_visibility_df(table, 0, None, epsilon)
    with pytest.raises(ValueError, match="epsilon must be a non-negative finite number or None"):
        get_visibility_df(table, ego_idx=0, epsilon=epsilon)
    with pytest.raises(ValueError, match="epsilon must be a non-negative finite number or None"):
        get_visibility_df_for_frame(table, 0, 0, None, epsilon)


@pytest.mark.parametrize(("progress", "hide_progress"), [(True, True), (False, False)])
def test_contradicting_progress_and_hide_progress(progress: bool, hide_progress: bool) -> None:
    table = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)])
    with pytest.raises(ValueError, match="contradicts hide_progress"):
        get_visibility_df(table, 0, progress=progress, hide_progress=hide_progress)


def test_signatures_positional_order() -> None:
    def positional(func) -> list[str]:
        return [
            p.name
            for p in inspect.signature(func).parameters.values()
            if p.kind in (p.POSITIONAL_ONLY, p.POSITIONAL_OR_KEYWORD)
        ]

    # 0.1.0's positional order; every other option is keyword-only
    assert positional(get_visibility_df) == ["df", "ego_idx", "static_occluder_polys", "epsilon"]
    assert positional(get_visibility_df_for_frame) == ["df", "ego_idx", "frame", "static_occluder_polys", "epsilon"]
    params = inspect.signature(visibility.compute_func).parameters
    assert {"ego_id", "ego_idx", "static_occluder_polys", "epsilon"} <= set(params)
