"""mode="3d" through get_visibility_df, the Metric and the CLI: hand-made scenes with paper answers, bad input,
static heights, and 2D-vs-3D agreement."""

from __future__ import annotations

import math
import os
import subprocess
import sys
import warnings
from dataclasses import replace
from types import SimpleNamespace

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import REPO

from omega_prime_visibility import VisibilityInputWarning, get_visibility_df
from omega_prime_visibility.engines.registry import get_engine
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.table.pipeline import viewpoints
from omega_prime_visibility.table.rows import observation_rows

EGO = (0.0, 0.0, 4.5, 1.8, 1.5)  # x, y, length, width, height; the eye is 1.25 m above the ground


def table(objects, **extra) -> pl.DataFrame:
    """One frame of boxes ``(x, y, length, width, height[, z, roll, pitch, yaw])`` standing on the ground."""
    rows = []
    for o in objects:
        x, y, length, width, height, *rest = o
        z, roll, pitch, yaw = (list(rest) + [height / 2, 0.0, 0.0, 0.0][len(rest) :])[:4]
        rows.append((x, y, z, length, width, height, roll, pitch, yaw))
    a = np.array(rows, dtype=float)
    return pl.DataFrame(
        {
            "frame": np.zeros(len(a), dtype=np.int64),
            "total_nanos": np.zeros(len(a), dtype=np.int64),
            "idx": np.arange(len(a), dtype=np.int64),
            **{name: a[:, k] for k, name in enumerate(("x", "y", "z", "length", "width", "height"))},
            **{name: a[:, 6 + k] for k, name in enumerate(("roll", "pitch", "yaw"))},
            **extra,
        }
    )


def vis(df: pl.DataFrame, idx: int) -> float:
    return df.filter(pl.col("idx") == idx)["visibility"].item()


def rect(y0: float, y1: float, z0: float, z1: float, d: float) -> float:
    """Solid angle of the rectangle y0..y1, z0..z1 (relative to the eye) on the plane at distance d."""

    def f(y: float, z: float) -> float:
        return math.atan(y * z / (d * math.sqrt(y * y + z * z + d * d)))

    return f(y1, z1) - f(y0, z1) - f(y1, z0) + f(y0, z0)


def test_low_car_behind_taller_car_is_hidden_in_2d_and_3d() -> None:
    df = table([EGO, (10.0, 0, 4.5, 2.0, 1.8), (20.0, 0, 4.0, 1.8, 1.2)])
    flat, solid = get_visibility_df(df, 0), get_visibility_df(df, 0, mode="3d")
    assert vis(flat, 2) == 0.0 and vis(solid, 2) == 0.0
    assert solid.filter(pl.col("idx") == 2)["can_see"].item() is False
    assert solid.columns == [*flat.columns, "can_see"]


def test_tall_truck_behind_low_car_is_seen_over_it_in_3d_only() -> None:
    df = table([EGO, (10.0, 0, 4.0, 2.0, 1.5), (20.0, 0, 8.0, 2.5, 4.0)])
    paper = rect(-1.25, 1.25, 0.5, 2.75, 16) / rect(-1.25, 1.25, -1.25, 2.75, 16)  # above z = 1.75 on its back
    assert vis(get_visibility_df(df, 0), 2) == 0.0
    solid = get_visibility_df(df, 0, mode="3d")
    assert vis(solid, 2) == pytest.approx(paper, abs=0.02)
    assert solid.filter(pl.col("idx") == 2).select("can_see", "occluder_idxs").row(0) == (True, [1])
    assert vis(get_visibility_df(df, 0, mode="3d", engine="silhouette3d"), 2) == pytest.approx(paper, rel=1e-9)


def test_pedestrian_behind_a_low_wall_and_the_2d_height_rule() -> None:
    df = table([EGO, (10.0, 0, 0.5, 0.5, 1.8)])
    wall = shapely.LineString([(5, -3), (5, 3)])
    cut = 1.25 - 0.25 * 9.75 / 5.0  # the wall's top (1 m at x = 5) seen on the walker's front face
    paper = rect(-0.25, 0.25, cut - 1.25, 0.55, 9.75) / rect(-0.25, 0.25, -1.25, 0.55, 9.75)
    solid = get_visibility_df(df, 0, [wall], mode="3d", static_occluder_heights=1.0, engine="raycast3d-high")
    assert vis(solid, 1) == pytest.approx(paper, abs=0.01)
    assert solid["static_occluder_idxs"].to_list() == [[0]]
    # 2D: a 1 m wall is lower than the eye and left out; without a height it blocks; a 2 m one blocks too
    assert vis(get_visibility_df(df, 0, [wall], static_occluder_heights=1.0), 1) == 1.0
    assert vis(get_visibility_df(df, 0, [wall]), 1) == 0.0
    both = get_visibility_df(df, 0, [wall, wall.offset_curve(0.5)], static_occluder_heights=[1.0, 2.0])
    assert vis(both, 1) == 0.0 and both["static_occluder_idxs"].to_list() == [[1]]  # numbered in the full list


def test_2d_height_rule_at_exactly_the_eye_height() -> None:
    # The rule (README: "at least as tall as the eye"): a static footprint blocks in 2D iff its top >= 1.25 m.
    # The walker at x = 10 (0.5 m square) lies wholly behind the 6 m wall at x = 5 (its shadow from the eye at the
    # origin spans |y| <= 3 * 9.75 / 5 > 0.25): a blocking wall hides it (0.0), a left-out one leaves it whole (1.0).
    df = table([EGO, (10.0, 0, 0.5, 0.5, 1.8)])
    wall = shapely.LineString([(5, -3), (5, 3)])
    at_eye = get_visibility_df(df, 0, [wall], static_occluder_heights=1.25)
    assert vis(at_eye, 1) == 0.0 and at_eye["static_occluder_idxs"].to_list() == [[0]]
    assert vis(get_visibility_df(df, 0, [wall], static_occluder_heights=1.24), 1) == 1.0
    # per footprint: of two walls, the one at the eye still blocks when the other (1.0 m) is left out
    assert vis(get_visibility_df(df, 0, [wall, wall], static_occluder_heights=[1.0, 1.25]), 1) == 0.0


def test_missing_3d_columns_are_named() -> None:
    df = table([EGO, (10.0, 0, 4.0, 2.0, 1.5)])
    with pytest.raises(ValueError, match=r"mode='3d' needs the column\(s\) \['height'\]"):
        get_visibility_df(df.drop("height"), 0, mode="3d")
    with pytest.warns(VisibilityInputWarning, match=r"no \['z', 'roll', 'pitch'\].*level.*ground z = 0"):
        out = get_visibility_df(df.drop("z", "roll", "pitch"), 0, mode="3d")
    assert out["visibility"].to_list() == [1.0]
    with pytest.raises(ValueError, match="mode must be '2d' or '3d'"):
        get_visibility_df(df, 0, mode="4d")
    with pytest.raises(ValueError, match="'sweep' is a 2d engine"):
        get_visibility_df(df, 0, mode="3d", engine="sweep")


def test_nan_heights_are_skipped_like_nan_poses() -> None:
    df = table([EGO, (10.0, 0, 4.0, 2.0, 1.8), (20.0, 0, 4.0, 1.8, 1.2)])
    df = df.with_columns(height=pl.when(pl.col("idx") == 1).then(None).otherwise(pl.col("height")))
    with pytest.warns(VisibilityInputWarning, match=r"skipping 1 of 3.*NaN or infinite 3D.*\(frame 0, idx 1\)"):
        out = get_visibility_df(df, 0, mode="3d")
    assert out["idx"].to_list() == [2] and out["visibility"].to_list() == [1.0]
    with pytest.raises(ValueError, match="NaN or infinite 3D"):
        get_visibility_df(df, 0, mode="3d", on_invalid="raise")


def test_heights_copied_from_widths_are_flagged() -> None:
    df = table([EGO, (10.0, 0, 4.0, 2.0, 2.0)]).with_columns(height=pl.col("width"))
    with pytest.warns(VisibilityInputWarning, match="height equals its width"):
        get_visibility_df(df, 0, mode="3d")


def random_scene(rng: np.random.Generator, n: int, height: float) -> pl.DataFrame:
    """Disjoint boxes around the ego, all ``height`` tall and standing on the ground."""
    boxes = [EGO[:4]]
    while len(boxes) < n + 1:
        x, y = rng.uniform(-40, 40), rng.uniform(-25, 25)
        length, width = rng.uniform(1, 6), rng.uniform(1, 3)
        r = math.hypot(length, width) / 2
        if all(math.hypot(x - b[0], y - b[1]) > r + math.hypot(b[2], b[3]) / 2 + 0.1 for b in boxes):
            boxes.append((x, y, length, width))
    rows = [
        (*b, height, height / 2, 0.0, 0.0, rng.uniform(-math.pi, math.pi) if k else 0.0) for k, b in enumerate(boxes)
    ]
    return table(rows)


def test_2d_and_3d_agree_where_every_box_is_as_tall_as_the_rest() -> None:
    # equal heights above the eye: hidden / fully seen are the same in 2D and 3D (exact engine)
    rng = np.random.default_rng(5)
    for _ in range(3):
        df = random_scene(rng, 15, 2.0)
        flat = get_visibility_df(df, 0, engine="sweep")["visibility"].to_numpy()
        solid = get_visibility_df(df, 0, mode="3d", engine="silhouette3d")["visibility"].to_numpy()
        assert ((flat == 0) == (solid == 0)).all() and ((flat == 1) == (solid == 1)).all()


def observe_3d(df: pl.DataFrame, engine: str, eye_height: float) -> np.ndarray:
    """Visibility from idx 0 with its eye ``eye_height`` above the ground, through the engine itself."""
    objects = load_objects(df, three_d=True)
    frame = objects.frame_objects(0)
    statics = load_static_occluders(None)
    view = replace(viewpoints(frame, np.array([0]), statics)[0], height=eye_height)
    obs = get_engine(engine)(statics).observe(frame, [view])[0]
    return observation_rows(obs, 0, frame.idx)["visibility"]


def test_2d_and_3d_fractions_agree_for_very_tall_boxes_seen_from_half_way_up() -> None:
    # boxes 1 km tall seen from 500 m up: every azimuth carries (nearly) the same solid angle, so the solid-angle
    # fraction is the 2D angle fraction, up to 1e-3, and the ray engine is within its sampling error
    rng = np.random.default_rng(8)
    errors = []
    for _ in range(3):
        df = random_scene(rng, 20, 1000.0)
        flat = get_visibility_df(df, 0, engine="sweep")["visibility"].to_numpy()
        assert observe_3d(df, "silhouette3d", 500.0) == pytest.approx(flat, abs=1e-3)
        errors.append(np.abs(observe_3d(df, "raycast3d", 500.0) - flat))
    e = np.concatenate(errors)
    assert e.mean() < 0.01 and np.quantile(e, 0.95) < 0.04


def test_metric_in_3d() -> None:
    import omega_prime

    from omega_prime_visibility import visibility

    df = table([EGO, (10.0, 0, 4.0, 2.0, 1.5), (20.0, 0, 8.0, 2.5, 4.0)])
    outlines = [shapely.box(x - length / 2, -width / 2, x + length / 2, width / 2) for x, length, width in
                df.select("x", "length", "width").rows()]  # fmt: skip
    recording = SimpleNamespace(_df=df.with_columns(polygon=pl.Series(outlines, dtype=pl.Object)))
    manager = omega_prime.metrics.MetricManager(metrics=[visibility])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, properties = manager.compute(recording, ego_id=0, mode="3d")
    got = properties["visibility"].sort("idx")
    assert got["can_see"].to_list() == [True, True] and 0 < got["visibility"][1] < 1


def run_cli(*args: str) -> subprocess.CompletedProcess:
    exe = [sys.executable, "-m", "omega_prime_visibility.cli", "run", *args]
    return subprocess.run(exe, capture_output=True, text=True, cwd=REPO, timeout=300)


def test_cli_mode_3d(tmp_path) -> None:
    out = tmp_path / "v.parquet"
    done = run_cli("highway_merge.mcap", "--ego", "0", "--mode", "3d", "--no-progress", "-o", str(out))
    assert done.returncode == 0, done.stderr
    written = pl.read_parquet(out)
    assert written.columns[-1] == "can_see" and written.height == 1206
    bad = run_cli("highway_merge.mcap", "--ego", "0", "--mode", "3d", "--engine", "visilibity")
    assert bad.returncode == 2 and bad.stderr.startswith("error: --engine: unknown engine 'visilibity' for --mode 3d")
    no_map = run_cli("highway_merge.mcap", "--ego", "0", "--map-occluders")
    assert no_map.returncode == 2 and "OpenDRIVE map" in no_map.stderr


def test_sensors_in_3d_honour_height_vertical_view_and_range() -> None:
    from omega_prime_visibility import Sensor

    # a camera 1.3 m up looking ahead, 60° x 20°, 50 m; a sign 10 m up at 20 m, a car at 30 m, a car at 80 m
    camera = Sensor("cam", x=1.0, fov=math.radians(60), vertical_fov=math.radians(20), range=50.0, z=1.3)
    df = table([EGO, (20.0, 0, 1.0, 3.0, 1.0, 10.0), (30.0, 2.0, 4.5, 1.8, 1.5), (80.0, 0, 4.5, 1.8, 1.5)])
    out = get_visibility_df(df, 0, mode="3d", sensors=[camera]).sort("idx")
    assert out.columns == ["frame", "total_nanos", "idx", "sensor", "occluder_idxs", "static_occluder_idxs",
                           "visibility", "in_view", "status", "can_see"]  # fmt: skip
    assert out["status"].to_list() == ["out_of_fov", "visible", "out_of_range"]
    assert out["can_see"].to_list() == [False, True, False]
    tilted = replace(camera, pitch=math.radians(-25))  # looking up 25°: the sign is in view, the cars are not
    up = get_visibility_df(df, 0, mode="3d", sensors=[tilted]).sort("idx")
    assert up["status"].to_list()[:2] == ["visible", "out_of_fov"]


def test_a_rolled_box_read_from_the_table_on_the_exact_engine() -> None:
    # The occluder at x = 10 is 0.01 m long, 4 m wide and 0.5 m tall, centred 2 m up and rolled by 90 degrees about
    # its forward axis: in the world a post 0.5 m wide (|y| <= 0.25) and 4 m tall (z 0..4). The target at x = 20 is
    # a 0.01 m plate 2 x 2 m centred at the eye's height (1.25 m): from the eye (0, 0, 1.25) its face (x = 19.995)
    # spans |y|, |z - 1.25| <= 1. The post's silhouette (its near face, x = 9.995) projects onto that plane as
    # |y| <= h = 0.25 * 19.995 / 9.995 and z - 1.25 in [-1.25, 2.75] * 19.995 / 9.995, beyond the plate's height:
    # hidden is a strip |y| <= h, |z - 1.25| <= 1. Unrolled (roll ignored), the slab's shadow would start at
    # z - 1.25 = 0.75 * 19.995 / 10.005 > 1, above the plate: visibility 1.
    d = 19.995
    h = 0.25 * d / 9.995
    paper = 1.0 - rect(-h, h, -1.0, 1.0, d) / rect(-1.0, 1.0, -1.0, 1.0, d)
    df = table([EGO, (10.0, 0, 0.01, 4.0, 0.5, 2.0, math.pi / 2), (20.0, 0, 0.01, 2.0, 2.0, 1.25)])
    out = get_visibility_df(df, 0, mode="3d", engine="silhouette3d")
    assert vis(out, 2) == pytest.approx(paper, rel=1e-9)
    assert out.filter(pl.col("idx") == 2)["occluder_idxs"].to_list() == [[1]]


def test_a_sensor_high_enough_sees_over_a_thin_plate() -> None:
    from omega_prime_visibility import Sensor

    # A plate at x = 10 (0.01 m thick, 4 m wide, z 0..2) and a 1 m cube on the ground at x = 30 (x 29.5..30.5).
    # From z = 3.5 the lowest ray, to the cube's bottom front edge (29.5, 0), crosses the plate's far face
    # x = 10.005 at z = 3.5 * (1 - 10.005 / 29.5) = 2.31 > 2: the whole cube is seen, visibility 1. From the eye
    # at 1.25 the highest ray, to the cube's top (z = 1), crosses x = 10 below z = 1.25 < 2, at |y| < 0.5 * 10
    # / 29.5 < 2: the whole cube is hidden, visibility 0.
    df = table([EGO, (10.0, 0, 0.01, 4.0, 2.0), (30.0, 0, 1.0, 1.0, 1.0)])
    for z, want in [(3.5, 1.0), (1.25, 0.0)]:
        for engine in ["silhouette3d", "raycast3d"]:
            out = get_visibility_df(df, 0, mode="3d", engine=engine, sensors=[Sensor("mast", z=z)])
            assert vis(out, 2) == pytest.approx(want, abs=1e-9), (z, engine)


def test_readme_3d_example_and_picture() -> None:
    import re

    blocks = re.findall(r"```python\n(.*?)```", (REPO / "README.md").read_text(), re.S)
    page = (REPO / "docs" / "3d.md").read_text()
    three_d = next(b for b in re.findall(r"```python\n(.*?)```", page, re.S) if 'mode="3d"' in b)
    namespace: dict = {}
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            exec(compile(blocks[0], "README.md", "exec"), namespace)
            exec(compile(three_d, "README.md", "exec"), namespace)
    finally:
        os.chdir(cwd)
    solid = namespace["solid"]
    assert solid.height == 1206 and solid.columns[-1] == "can_see"
    # the picture's scene: hidden in 2D, 66 % seen in 3D (the README's caption)
    sys.path.insert(0, str(REPO / "scripts"))
    try:
        from threed_picture import table as figure_table
    finally:
        sys.path.pop(0)
    df = figure_table()
    assert vis(get_visibility_df(df, 0), 2) == 0.0
    assert vis(get_visibility_df(df, 0, mode="3d", engine="silhouette3d"), 2) == pytest.approx(0.658, abs=5e-4)


def test_real_trace_in_3d(shared_data) -> None:
    # esmini's highway_merge trace: nothing in front in 2D means nothing in front in 3D; hidden in 3D means hidden in
    # 2D; the ray engine within its measured error of the exact one
    from omega_prime_visibility.inputs.io import read_recording

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(shared_data / "highway_merge.osi", shared_data / "soderleden.xodr")
        flat = get_visibility_df(r, 0, progress=False)
        rays = get_visibility_df(r, 0, mode="3d", progress=False)
        exact = get_visibility_df(r, 0, mode="3d", engine="silhouette3d", progress=False)
    v2, v3, vx = (t.sort("frame", "idx")["visibility"].to_numpy() for t in (flat, rays, exact))
    assert len(v2) == len(v3) == len(vx) > 2000
    assert (vx[v2 == 1] == 1).all() and (v2[vx == 0] == 0).all()
    assert np.abs(v3 - vx).mean() < 0.01


def test_streamed_output_and_workers_give_the_same_3d_table(tmp_path) -> None:
    mcap = REPO / "highway_merge.mcap"
    wall = shapely.LineString([(60, -5.4), (140, -5.4)])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        here = get_visibility_df(mcap, 0, mode="3d", progress=False)
        streamed = get_visibility_df(mcap, 0, mode="3d", output=tmp_path / "a.parquet", workers=2, chunk_frames=50)
        assert streamed.collect().equals(here)
        # the 2D height rule leaves the 1 m copy out; the 3 m one keeps its position in the full list
        kept = get_visibility_df(mcap, 0, [wall, wall], static_occluder_heights=[1.0, 3.0], progress=False)
        parts = get_visibility_df(mcap, 0, [wall, wall], static_occluder_heights=[1.0, 3.0], workers=2,
                                  chunk_frames=50, output=tmp_path / "b.parquet").collect()  # fmt: skip
    assert parts.equals(kept)
    assert sorted(set(kept["static_occluder_idxs"].explode().drop_nulls().to_list())) == [1]


def test_the_bundled_recording_has_real_heights_and_3d_uses_them() -> None:
    """The scenario writes each object's own height (omega-prime 0.3.7's writer would copy the width): the truck
    idx 1 is 4 m high and stands on the road; in frame 30 it hides the merging car idx 2 entirely in 3D as in 2D
    (a 1.5 m car right behind a 4 m box, seen from 1.25 m), and in 3D no row warns about copied heights."""
    from omega_prime_visibility.inputs.io import read_recording

    r = read_recording(REPO / "highway_merge.mcap")
    boxes = r._df.group_by("idx").agg(pl.col("height", "width", "z").first()).sort("idx")
    assert boxes.filter(pl.col("idx") == 1).row(0) == (1, 4.0, 2.55, 2.0)  # height, width, z = height / 2
    assert (boxes["height"] != boxes["width"]).all()
    with warnings.catch_warnings():
        warnings.simplefilter("error", VisibilityInputWarning)
        solid = get_visibility_df(r, 0, mode="3d", engine="silhouette3d", progress=False)
    at30 = {row["idx"]: row for row in solid.filter(pl.col("frame") == 30).iter_rows(named=True)}
    assert (at30[2]["visibility"], at30[2]["can_see"], at30[2]["occluder_idxs"]) == (0.0, False, [1])
    assert at30[1]["visibility"] == 1.0 and at30[4]["visibility"] == 1.0


def boxes3d_table(rows: list[list[float]]) -> pl.DataFrame:
    """One frame of 3D boxes ``x, y, z, length, width, height, roll, pitch, yaw``; idx = position."""
    columns = ["x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw"]
    arr = np.asarray(rows, dtype=float)
    return pl.DataFrame(
        {"frame": [0] * len(arr), "total_nanos": [0] * len(arr), "idx": list(range(len(arr)))}
        | {c: arr[:, k] for k, c in enumerate(columns)}
    )


@pytest.mark.parametrize("engine", ["silhouette3d", "raycast3d"])
def test_a_low_platform_under_the_eye_blocks_and_a_building_around_it_does_not(engine: str) -> None:
    # a 1 m platform whose footprint covers the ego, the eye 1.25 m up above it: it hides the lower part of the car
    # 20 m away exactly as the same platform beginning 3 m ahead does, and draws no containment warning; a 10 m
    # building around the eye is transparent, and told
    cars = boxes3d_table([[0, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0], [20, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0]])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        under = get_visibility_df(cars, 0, [shapely.box(-5, -5, 12, 5)], static_occluder_heights=[1.0], mode="3d",
                                  engine=engine, progress=False)  # fmt: skip
    ahead = get_visibility_df(cars, 0, [shapely.box(3, -5, 12, 5)], static_occluder_heights=[1.0], mode="3d",
                              engine=engine, progress=False)  # fmt: skip
    assert under["static_occluder_idxs"].to_list() == [[0]] and 0.3 < under["visibility"][0] < 0.5
    assert under["visibility"][0] == pytest.approx(ahead["visibility"][0], abs=1e-12)
    told = r"static occluder 1 contains observer 0 in 1 frame\(s\) \(first frame 0\)"
    with pytest.warns(VisibilityInputWarning, match=told):
        statics = [shapely.box(30, -5, 40, 5), shapely.box(-5, -5, 12, 5)]  # (the first one beyond the car)
        around = get_visibility_df(cars, 0, statics, static_occluder_heights=[1.0, 10.0], mode="3d", engine=engine,
                                   progress=False)  # fmt: skip
    assert around.select("static_occluder_idxs", "visibility").rows() == [([], 1.0)]


def test_a_box_over_the_eye_is_not_said_to_be_transparent() -> None:
    # an overhead sign 5.5 to 6.5 m up over the ego blocks the box above it and draws no containment warning; a
    # box that holds the eye still does
    sign = boxes3d_table(
        [[0, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0], [0, 0, 6, 4, 4, 1, 0, 0, 0], [0, 0, 9, 1, 1, 1, 0, 0, 0]]
    )
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        out = get_visibility_df(sign, 0, mode="3d", progress=False)
    assert out.select("idx", "occluder_idxs", "visibility").rows() == [(1, [], 1.0), (2, [1], 0.0)]
    around = boxes3d_table([[0, 0, 0.75, 4.5, 1.8, 1.5, 0, 0, 0], [0, 0, 1.5, 6, 6, 3, 0, 0, 0]])
    with pytest.warns(VisibilityInputWarning, match="contain"):
        get_visibility_df(around, 0, mode="3d", progress=False)
