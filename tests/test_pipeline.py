"""Per-frame orchestration (pipeline.py): any Executor gives the same columns, in order; viewpoints."""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

import numpy as np
import polars as pl
import pytest
import shapely
from conftest import boxes_table

from omega_prime_visibility import get_visibility_df
from omega_prime_visibility.engines.registry import get_engine
from omega_prime_visibility.inputs.scene import load_objects
from omega_prime_visibility.inputs.statics import load_static_occluders
from omega_prime_visibility.sensors import Sensor, roof
from omega_prime_visibility.table import LIST_COLUMNS, TableBuilder, to_polars
from omega_prime_visibility.table.pipeline import ContainmentLog, chunks, observe_frame, run, run_chunk, viewpoints
from omega_prime_visibility.table.rows import frame_rows, observation_rows


def moving_scene(frames: int) -> pl.DataFrame:
    return pl.concat(
        [
            boxes_table([(0, 0, 4, 2, 0), (10 + f, 0, 4, 4, 0), (20, 0.5 * f, 4, 2, 0), (5, 8, 4, 2, 1.0)], f)
            for f in range(frames)
        ]
    )


def test_any_executor_gives_the_same_table_in_order() -> None:
    objects = load_objects(moving_scene(23))
    statics = load_static_occluders([shapely.LineString([(15, -3), (15, -1)])])
    egos = np.array([0, 3])

    def table(executor) -> pl.DataFrame:
        parts = list(run(objects, statics, egos, "sweep", chunk_frames=4, executor=executor))
        assert [n for n, _, _ in parts] == [4, 4, 4, 4, 4, 3]
        return pl.concat([to_polars(columns, with_ego=True) for _, columns, _ in parts])

    with ThreadPoolExecutor(2) as pool:
        threaded = table(pool)
    assert threaded.equals(table(None))
    assert threaded.equals(get_visibility_df(moving_scene(23), [0, 3], statics.geometries, engine="sweep"))


def test_viewpoints_mark_the_own_body_and_bodies_containing_the_viewpoint() -> None:
    # the ego (row 0) at the origin lies inside box 1 and on static 0's boundary; box 2 is clear of it
    frame = load_objects(boxes_table([(0, 0, 1, 1, 0.3), (1, 0, 4, 2, 0), (10, 0, 2, 2, 0)])).frame_objects(0)
    statics = load_static_occluders([shapely.box(0, -5, 3, -0.0), shapely.box(-9, 5, -8, 6)])
    (view,) = viewpoints(frame, np.array([0]), statics)
    assert view.own == 0 and view.heading == 0.3 and np.array_equal(view.position, [0.0, 0.0])
    assert view.transparent.tolist() == [True, True, False]
    assert view.static_transparent.tolist() == [True, False]


def test_chunks_cover_every_frame_once_and_balance_over_workers() -> None:
    for n_frames, chunk_frames, workers in [(30_000, 500, 2), (1001, 500, 2), (7, 3, 3), (3, 500, 8), (0, 5, 2)]:
        bounds = chunks(n_frames, chunk_frames, workers)
        sizes = [b - a for a, b in bounds]
        assert [a for a, _ in bounds] == [0, *[b for _, b in bounds]][: len(bounds)] and sum(sizes) == n_frames
        assert all(0 < s <= chunk_frames for s in sizes) and (max(sizes, default=0) - min(sizes, default=0)) <= 1
        assert len(bounds) % workers == 0 or len(bounds) == n_frames
    assert [b - a for a, b in chunks(1001, 500, 2)] == [251, 250, 250, 250]
    assert chunks(1001, 500) == [(0, 500), (500, 1000), (1000, 1001)]  # one worker: as asked


def test_frame_rows_are_the_rows_of_each_observation_in_turn() -> None:
    # four observers, one inside box 1 (transparent to it), walls occluding some targets
    frame = load_objects(moving_scene(3)).frame_objects(2)
    statics = load_static_occluders([shapely.LineString([(15, -3), (15, -1)]), shapely.box(3, 5, 4, 6)])
    views = viewpoints(frame, np.array([0, 1, 2, 3]), statics)
    observations = get_engine("sweep")(statics).observe(frame, views)
    owns = np.array([v.own for v in views])
    batch = frame_rows(observations, owns, frame.idx)
    one_by_one = [observation_rows(o, own, frame.idx) for o, own in zip(observations, owns, strict=True)]
    assert batch["idx_ego"].tolist() == [int(frame.idx[own]) for own in owns for _ in range(len(frame.idx) - 1)]
    for name in ("idx", "visibility"):
        assert np.array_equal(batch[name], np.concatenate([c[name] for c in one_by_one]))
    for name in ("occluder_idxs", "static_occluder_idxs"):
        for part in (0, 1):
            assert np.array_equal(batch[name][part], np.concatenate([c[name][part] for c in one_by_one]))
    assert batch["occluder_idxs"][1].size and batch["static_occluder_idxs"][1].size  # both kinds occur


def random_traffic(rng: np.random.Generator, frames: int, n: int) -> pl.DataFrame:
    """Overlapping boxes in a 24 m square, some frames without some objects (observers included)."""
    parts = []
    for f in range(frames):
        boxes = [
            (*rng.uniform(-12, 12, 2), rng.uniform(1, 6), rng.uniform(0.5, 3), rng.uniform(-np.pi, np.pi))
            for _ in range(n)
        ]
        table = boxes_table(boxes, f)
        parts.append(table.filter(pl.Series(rng.random(n) > 0.15)))
    return pl.concat(parts)


CHUNK_ENGINES = ["sweep", "visilibity"]  # the engines offering observe_chunk


def frame_by_frame(objects, statics, egos, sensors, engine_name="sweep"):
    """The columns and containment log of the per-frame path (what every engine without ``observe_chunk`` uses)."""
    engine = get_engine(engine_name)(statics)
    builder, log = TableBuilder(), ContainmentLog()
    for k in range(objects.n_frames):
        observe_frame(engine, statics, objects.frame_objects(k), egos, builder, log, sensors)
    return builder.arrays(), log


def assert_same_columns(columns, expected) -> None:
    assert columns.keys() == expected.keys()
    for name, values in expected.items():
        pairs = zip(columns[name], values, strict=True) if name in LIST_COLUMNS else [(columns[name], values)]
        for got, want in pairs:
            assert got.dtype == want.dtype and np.array_equal(got, want), name


STATIC_SETS = {
    "box, wall, far box": [
        shapely.box(-3, -3, 3, 3),
        shapely.LineString([(-15, 10), (15, 12)]),
        shapely.box(25, -5, 30, 5),
    ],
    # a courtyard around the whole scene (the VisiLibity environment is then the free space holding the viewpoint)
    "courtyard": [shapely.box(-30, -30, 30, 30).difference(shapely.box(-25, -25, 25, 25))],
    "none": [],
}


@pytest.mark.parametrize("engine", CHUNK_ENGINES)
@pytest.mark.parametrize("statics_name", sorted(STATIC_SETS))
@pytest.mark.parametrize("seed", range(4))
def test_the_chunk_path_gives_the_columns_of_the_frame_by_frame_path(seed: int, statics_name: str, engine: str) -> None:
    # observers inside other boxes and inside static occluders, unlimited sensors off the centre, per-ego sensors
    rng = np.random.default_rng(seed)
    objects = load_objects(random_traffic(rng, 12, 14))
    statics = load_static_occluders(STATIC_SETS[statics_name])
    off_centre = [Sensor("a", x=1.5, y=-0.5, yaw=0.4), Sensor("b", x=-2.0)]
    per_ego = {0: roof(), 3: [Sensor("roof", x=0.7)], 5: roof()}
    contained = 0
    for egos, sensors in [([0], None), ([0, 3, 5], None), ([0, 3, 5], off_centre), ([0, 3, 5], per_ego)]:
        egos = np.array(egos)
        expected, expected_log = frame_by_frame(objects, statics, egos, sensors, engine)
        columns, log = run_chunk(objects, statics, egos, engine, sensors)
        assert_same_columns(columns, expected)
        assert log.frames == expected_log.frames and log.first == expected_log.first
        contained += len(log.frames)
    assert contained  # some observer is inside some box


@pytest.mark.parametrize("engine", CHUNK_ENGINES)
def test_the_chunk_path_without_any_observer_gives_no_rows(engine: str) -> None:
    objects = load_objects(moving_scene(4))
    columns, log = run_chunk(objects, load_static_occluders(None), np.array([99]), engine)
    assert columns is None and not log.frames


def test_per_observer_sensors_must_cover_every_observer() -> None:
    objects = load_objects(moving_scene(3))
    statics = load_static_occluders(None)
    with pytest.raises(ValueError, match=r"no sensors given for observer idx \[3\]"):
        run_chunk(objects, statics, np.array([0, 3]), "sweep", {0: roof()})
    with pytest.raises(ValueError, match=r"no sensors given for observer idx \[3\]"):
        frame_by_frame(objects, statics, np.array([0, 3]), {0: [Sensor("front", fov=1.0)]})


@pytest.mark.parametrize("engine", CHUNK_ENGINES)
@pytest.mark.parametrize("seed", range(3))
def test_the_chunk_path_on_polygon_columns_far_from_the_origin(seed: int, engine: str) -> None:
    # outlines given as polygons (boxes, regular 12-gons, a few invalid bow-ties repaired), at UTM-like coordinates
    rng = np.random.default_rng(seed)
    rows = []
    for frame in range(8):
        for idx in range(12):
            if idx and rng.random() < 0.1:
                continue
            x, y = 5.0e5 + rng.uniform(-15, 15), 5.4e6 + rng.uniform(-15, 15)
            kind = rng.integers(3)
            if kind == 0:
                outline = shapely.box(x - 2.0, y - 1.0, x + 2.0, y + 1.0)
            elif kind == 1:
                outline = shapely.Point(x, y).buffer(rng.uniform(0.5, 3.0), quad_segs=3)
            else:
                outline = shapely.Polygon([(x, y), (x + 3, y + 2), (x + 3, y), (x, y + 2)])  # a bow-tie
            rows.append(
                {"frame": frame, "total_nanos": frame * 40_000_000, "idx": idx, "x": x, "y": y, "polygon": outline}
            )
    table = pl.DataFrame(rows, schema_overrides={"polygon": pl.Object})
    with pytest.warns(UserWarning):
        objects = load_objects(table)
    statics = load_static_occluders([shapely.LineString([(5.0e5 - 20, 5.4e6 + 16), (5.0e5 + 20, 5.4e6 + 18)])])
    for egos in ([0], [0, 4, 7]):
        egos = np.array(egos)
        expected, expected_log = frame_by_frame(objects, statics, egos, None, engine)
        columns, log = run_chunk(objects, statics, egos, engine)
        assert_same_columns(columns, expected)
        assert log.frames == expected_log.frames
        assert expected["occluder_idxs"][1].size and 0 < np.count_nonzero(expected["visibility"] < 1)


def test_frames_an_engine_fails_on_are_computed_by_the_fallback_and_counted() -> None:
    # frames 0 and 2: the observer 2 nm below a wall, inside VisiLibity's 20 nm thick version of it (it raises
    # EngineFailure); frame 1: 1 m below it. The box above the wall is hidden in every frame, the one below is not
    table = pl.concat(
        [
            boxes_table([(0, y, 1, 1, 0), (0, 10, 2, 2, 0), (0, -10, 2, 2, 0)], f)
            for f, y in enumerate([-2e-9, -1, -2e-9])
        ]
    )
    wall = [shapely.LineString([(-5, 0), (5, 0)])]
    for chunk_frames in (1, 500):  # the warnings of several chunks are summed
        with pytest.warns(
            UserWarning, match=r"2 frame\(s\) computed with engine='sweep'.*first frame 0: the viewpoint lies within"
        ):
            mixed = get_visibility_df(table, 0, wall, engine="visilibity", chunk_frames=chunk_frames)
        assert mixed["visibility"].to_list() == [0.0, 1.0] * 3 and mixed["static_occluder_idxs"].to_list()[0] == [0]
    swept = get_visibility_df(table, 0, wall, engine="sweep")
    alone = get_visibility_df(table.filter(pl.col("frame") == 1), 0, wall, engine="visilibity")
    assert mixed.filter(pl.col("frame") != 1).equals(swept.filter(pl.col("frame") != 1))
    assert mixed.filter(pl.col("frame") == 1).equals(alone)
    objects, statics = load_objects(table), load_static_occluders(wall)
    expected, expected_log = frame_by_frame(objects, statics, np.array([0]), None, "visilibity")
    columns, log = run_chunk(objects, statics, np.array([0]), "visilibity")  # the chunk path falls back too
    assert_same_columns(columns, expected)
    assert log.fallback_frames == expected_log.fallback_frames == 2 and log.first_fallback[0] == 0
