"""``occluders=`` and ``targets=``: who may block the view and who gets rows (inputs/roles.py, table/selection.py),
on scenes with answers on paper, on random scenes against the reference, through every engine and path."""

from __future__ import annotations

import math
import re
import warnings

import numpy as np
import polars as pl
import pytest
from conftest import scene_table
from reference import occluder_disagreements, random_scene, reference_visibility

from omega_prime_visibility import ENGINES, VisibilityInputWarning, get_visibility_df
from omega_prime_visibility.inputs.roles import role_mask

N_RAYS = 20000
ROW_TOLERANCE = 5e-4
TINY = 1e-3


def assert_same_rows(got: pl.DataFrame, want: pl.DataFrame) -> None:
    """Equal tables, visibility to 1e-12: a scene without bodies that cannot matter may round differently."""
    shares = [c for c in ("visibility", "in_view") if c in got.columns]
    assert got.drop(shares).rows() == want.drop(shares).rows()
    for c in shares:
        assert np.abs(got[c].to_numpy() - want[c].to_numpy()).max(initial=0.0) < 1e-12, c


def street(**columns) -> pl.DataFrame:
    """Ego (idx 0) at the origin facing +x, a 0.5 m pedestrian (idx 1) 5 m ahead, a 4 m x 2 m car (idx 2) at 15 m."""
    base = {
        "frame": [0, 0, 0],
        "total_nanos": [0, 0, 0],
        "idx": [0, 1, 2],
        "x": [0.0, 5.0, 15.0],
        "y": [0.0, 0.0, 0.0],
        "length": [4.0, 0.5, 4.0],
        "width": [2.0, 0.5, 2.0],
        "yaw": [0.0, 0.0, 0.0],
        "type": [2, 3, 2],
        "subtype": [4, 0, 4],
    }
    return pl.DataFrame({**base, **columns})


# on paper: the car's extent is 2 atan(1/13) (its near face at x = 13), the pedestrian's 2 atan(0.25/4.75), inside it
CAR_BEHIND_PEDESTRIAN = 1 - math.atan(0.25 / 4.75) / math.atan(1 / 13)


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_a_pedestrian_between_the_ego_and_a_car(engine: str) -> None:
    both = get_visibility_df(street(), 0, engine=engine)
    assert both["visibility"].to_list() == pytest.approx([1.0, CAR_BEHIND_PEDESTRIAN], abs=1e-12)
    assert both["occluder_idxs"].to_list() == [[], [1]]
    for choice in ("vehicles", ["VEHICLE"], ["CAR"], [0, 2], pl.col("type") == 2):
        vehicles = get_visibility_df(street(), 0, engine=engine, occluders=choice)
        assert vehicles.select("idx", "occluder_idxs", "visibility").rows() == [(1, [], 1.0), (2, [], 1.0)], choice


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_a_pedestrian_that_may_not_block_is_still_hidden_by_a_car(engine: str) -> None:
    # the pedestrian now stands behind the car: 0.5 m wide at x = 20, fully within the car's shadow
    df = street(x=[0.0, 20.0, 10.0])
    out = get_visibility_df(df, 0, engine=engine, occluders="vehicles")
    assert out.select("idx", "occluder_idxs", "visibility").rows() == [(1, [2], 0.0), (2, [], 1.0)]


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_pedestrians_that_may_not_block_do_not_hide_each_other(engine: str) -> None:
    df = pl.DataFrame(
        {
            "frame": [0] * 4,
            "total_nanos": [0] * 4,
            "idx": [0, 1, 2, 3],
            "x": [0.0, 5.0, 8.0, 12.0],
            "y": [0.0, 0.0, 0.0, 0.1],
            "length": [4.0, 0.5, 0.5, 0.5],
            "width": [2.0, 0.5, 0.5, 0.5],
            "yaw": [0.0] * 4,
            "type": [2, 3, 3, 3],
            "subtype": [4, 0, 0, 0],
        }
    )
    blocking = get_visibility_df(df, 0, engine=engine)
    assert blocking["occluder_idxs"].to_list() == [[], [1], [1, 2]]
    assert blocking["visibility"].to_list()[1] == 0.0
    free = get_visibility_df(df, 0, engine=engine, occluders="vehicles")
    assert free.select("idx", "occluder_idxs", "visibility").rows() == [(1, [], 1.0), (2, [], 1.0), (3, [], 1.0)]


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_targets_give_rows_only_for_those_asked_for_with_the_same_numbers(engine: str) -> None:
    full = get_visibility_df(street(), 0, engine=engine)
    for choice in ("pedestrians", [1], pl.col("type") == 3):
        only = get_visibility_df(street(), 0, engine=engine, targets=choice)
        assert_same_rows(only, full.filter(pl.col("idx") == 1))
    car = get_visibility_df(street(), 0, engine=engine, targets=[2])
    assert_same_rows(car, full.filter(pl.col("idx") == 2))  # the pedestrian, not a target, still blocks


def typed_scene(seed: int, engine: str, n: int = 9):
    """A random reference scene as a table whose objects are typed at random (2: vehicle, 3: pedestrian)."""
    rng = np.random.default_rng(seed)
    scene = random_scene(rng, n, overlap=bool(seed % 2), with_statics=seed % 3 == 0, include_ego=False)
    table = scene_table(scene.observer, scene.objects, include_ego=False)
    kinds = rng.choice([2, 3], size=table.height)
    kinds[0] = 2
    types = {"type": pl.Series(kinds), "subtype": pl.Series(np.where(kinds == 2, 4, 0))}
    return scene, table.with_columns(**types, yaw=pl.Series(rng.uniform(-np.pi, np.pi, table.height)))


@pytest.mark.parametrize("engine", sorted(ENGINES))
@pytest.mark.parametrize("seed", range(8))
def test_random_scenes_with_choices_against_the_reference(engine: str, seed: int) -> None:
    scene, table = typed_scene(seed, engine)
    polygons = list(table["polygon"])
    kinds = table["type"].to_numpy()
    transparent = np.zeros(len(polygons), dtype=bool)
    transparent[0] = True
    ref = reference_visibility(scene.observer, polygons, scene.statics, transparent, N_RAYS, blocking=kinds == 2)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        out = get_visibility_df(table, 0, scene.statics, engine=engine, occluders="vehicles")
        few = get_visibility_df(table, 0, scene.statics, engine=engine, occluders="vehicles", targets=[1, 2, 3])
    assert out["idx"].to_list() == list(range(1, len(polygons)))
    assert_same_rows(few, out.filter(pl.col("idx").is_in([1, 2, 3])))
    for row in out.iter_rows(named=True):
        i = row["idx"]
        assert row["visibility"] == pytest.approx(ref.visibility[i], abs=ROW_TOLERANCE), i
        assert not set(row["occluder_idxs"]) & set(np.flatnonzero(kinds == 3).tolist()), "a pedestrian blocked"
        got, want = set(row["occluder_idxs"]), ref.occluders[i]
        assert not occluder_disagreements(scene.observer, polygons[i], got, want, polygons, TINY), (i, got, want)


@pytest.mark.parametrize("engine", sorted(ENGINES))
def test_choices_through_sensors_and_for_every_observer(engine: str) -> None:
    _scene, table = typed_scene(11, engine, n=10)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for sensors in (None, "typical"):
            full = get_visibility_df(table, "all", engine=engine, sensors=sensors, occluders="vehicles")
            few = get_visibility_df(table, "all", engine=engine, sensors=sensors, occluders="vehicles", targets=[2, 5])
            assert_same_rows(few, full.filter(pl.col("idx").is_in([2, 5])))
            assert full.height == table.height * (table.height - 1) * (1 if sensors is None else 6)
            pedestrians = set(np.flatnonzero(table["type"].to_numpy() == 3).tolist())
            assert not any(set(o) & pedestrians for o in full["occluder_idxs"].to_list())


def test_every_object_blocking_gives_the_default_table() -> None:
    _scene, table = typed_scene(4, "sweep", n=12)
    for engine in sorted(ENGINES):
        default = get_visibility_df(table, "all", engine=engine)
        chosen = get_visibility_df(table, "all", engine=engine, occluders="all", targets=list(range(table.height)))
        assert_same_rows(chosen, default)


@pytest.mark.parametrize(
    ("choice", "message"),
    [
        ("lorries", "unknown object kind 'lorries'"),
        ([7, 99], r"idx \[7, 99\] never occur"),
        (pl.col("x") + 1, "must give a boolean per row"),
        (pl.col("nope") == 1, "cannot be evaluated"),
        (pl.col("x").max() > 0, "one value per row"),
        ([1, "CAR"], "not a mix"),
        (3.5, "takes a group or type name"),
    ],
)
def test_bad_choices_are_one_clear_error(choice, message: str) -> None:
    with pytest.raises(ValueError, match=message):
        get_visibility_df(street(), 0, occluders=choice)
    with pytest.raises(ValueError, match="targets"):
        get_visibility_df(street(), 0, targets=choice)


def test_names_need_the_type_columns() -> None:
    with pytest.raises(ValueError, match=r"needs the column\(s\) \['subtype'\]"):
        get_visibility_df(street().drop("subtype"), 0, occluders="vehicles")
    assert get_visibility_df(street().drop("subtype"), 0, occluders="pedestrians").height == 2


def test_groups_on_paper() -> None:
    df = pl.DataFrame(
        {
            "idx": range(8),
            "type": [2, 2, 2, 2, 2, 3, 4, 0],
            "subtype": [4, 7, 11, 10, 15, 0, 0, 0],  # car, truck, bicycle, motorbike, wheelchair, pedestrian, ...
        }
    )
    assert np.flatnonzero(role_mask(df, "vehicles", "o")).tolist() == [0, 1]
    assert np.flatnonzero(role_mask(df, "cyclists", "o")).tolist() == [2]
    assert np.flatnonzero(role_mask(df, "two_wheelers", "o")).tolist() == [2, 3]
    assert np.flatnonzero(role_mask(df, "vulnerable", "o")).tolist() == [2, 3, 4, 5]
    assert np.flatnonzero(role_mask(df, ["animals", "HEAVY_TRUCK"], "o")).tolist() == [1, 6]
    assert np.flatnonzero(role_mask(df, "Pedestrian", "o")).tolist() == [5]


def test_null_types_and_subtypes() -> None:
    # a vehicle of unknown (null) subtype is a vehicle and of no named subtype; a row of null type matches no name
    df = pl.DataFrame({"idx": range(4), "type": [2, 2, None, 3], "subtype": [None, 11, None, None]})
    assert np.flatnonzero(role_mask(df, "vehicles", "o")).tolist() == [0]
    assert np.flatnonzero(role_mask(df, "two_wheelers", "o")).tolist() == [1]
    assert np.flatnonzero(role_mask(df, "vulnerable", "o")).tolist() == [1, 3]
    assert np.flatnonzero(role_mask(df, ["VEHICLE", "PEDESTRIAN"], "o")).tolist() == [0, 1, 3]
    # on a street: the car of null subtype (idx 1) still hides the car behind it under occluders="vehicles"
    base = {"frame": [0] * 3, "total_nanos": [0] * 3, "idx": [0, 1, 2], "x": [0.0, 10.0, 20.0], "y": [0.0] * 3}
    base |= {"length": [4.0] * 3, "width": [2.0] * 3, "yaw": [0.0] * 3, "type": [2, 2, 2], "subtype": [4, None, 4]}
    out = get_visibility_df(pl.DataFrame(base), 0, occluders="vehicles")
    assert out.select("idx", "occluder_idxs", "visibility").rows() == [(1, [], 1.0), (2, [1], 0.0)]


def test_type_columns_of_text_are_one_clear_error() -> None:
    with pytest.raises(ValueError, match="reads the column 'type' as omega-prime's integer codes, but it holds String"):
        get_visibility_df(street().with_columns(pl.col("type").cast(pl.String)), 0, occluders="vehicles")


def test_idx_for_one_frame_are_those_of_the_recording() -> None:
    # idx 2 is in frame 0 only: in frame 1 it selects nothing, it is not refused; an idx of no frame is
    from omega_prime_visibility import get_visibility_df_for_frame

    df = pl.DataFrame(
        {"frame": [0, 0, 0, 1, 1], "total_nanos": [0, 0, 0, 1, 1], "idx": [0, 1, 2, 0, 1], "x": [0.0, 10, 20, 0, 10]}
        | {"y": [0.0] * 5, "length": [4.0] * 5, "width": [2.0] * 5, "yaw": [0.0] * 5}
    )
    assert get_visibility_df_for_frame(df, 0, 1, targets=[2]).height == 0
    assert get_visibility_df_for_frame(df, 0, 1, targets=np.array([1, 2])).select("idx").rows() == [(1,)]
    assert get_visibility_df_for_frame(df, 0, 0, occluders=[2]).select("idx", "occluder_idxs").rows() == [
        (1, []),
        (2, []),
    ]
    with pytest.raises(ValueError, match=r"idx \[7\] never occur"):
        get_visibility_df_for_frame(df, 0, 1, targets=[1, 7])
    with pytest.raises(TypeError, match=r"for_frame\(\) got an unexpected keyword argument .occluder."):
        get_visibility_df_for_frame(df, 0, 1, occluder=[1])


@pytest.mark.parametrize("offset", [(0.0, 0.0), (5.0e5, 5.4e6)], ids=["small", "map"])
@pytest.mark.parametrize("seed", range(6))
def test_passive_targets_of_the_sweep_agree_with_views_of_their_own(seed: int, offset: tuple) -> None:
    """The sweep measures the targets that may not block itself (engines/sweep/passive.py); VisiLibity gives each
    group of them a view of its own (table/selection.py): two independent routes to the same numbers, on crowded
    random scenes with overlapping bodies and static occluders, every object an observer, at small and at map
    coordinates (and through sensors, the frame-by-frame path)."""
    import shapely

    rng = np.random.default_rng(100 + seed)
    scene = random_scene(rng, 16, overlap=True, with_statics=seed % 2 == 0, include_ego=False)
    moved = [shapely.affinity.translate(p, *offset) for p in scene.objects]
    statics = [shapely.affinity.translate(s, *offset) for s in scene.statics]
    table = scene_table(np.asarray(scene.observer) + offset, moved, include_ego=False)
    kinds = np.where(rng.random(table.height) < 0.4, 3, 2)
    table = table.with_columns(
        type=pl.Series(kinds),
        subtype=pl.Series(np.where(kinds == 2, 4, 0)),
        yaw=pl.Series(rng.uniform(-3, 3, len(kinds))),
    )
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for sensors in (None, "typical") if seed < 2 else (None,):
            ego = "all" if sensors is None else 0
            got = get_visibility_df(table, ego, statics, engine="sweep", occluders="vehicles", sensors=sensors)
            want = get_visibility_df(table, ego, statics, engine="visilibity", occluders="vehicles", sensors=sensors)
            keys = [c for c in ("idx_ego", "sensor", "idx", "status") if c in got.columns]
            assert got.select(keys).rows() == want.select(keys).rows()
            assert np.abs(got["visibility"].to_numpy() - want["visibility"].to_numpy()).max() < 2e-6
            pedestrians = set(np.flatnonzero(kinds == 3).tolist())
            for a, b in zip(got["occluder_idxs"].to_list(), want["occluder_idxs"].to_list(), strict=True):
                assert not set(a) & pedestrians
                assert set(a) == set(b)


def test_a_passive_target_of_two_arms_is_counted_once() -> None:
    """A U-shaped object that may not block, its base towards the ego and its arms behind it (the arms' inner
    edges face the ego behind the base: its own edges share bearings), behind a car that covers its lower half:
    on paper half of it is seen, each bearing counted once."""
    import shapely

    u_shape = shapely.Polygon([(10, -2), (14, -2), (14, -1), (11, -1), (11, 1), (14, 1), (14, 2), (10, 2)])
    car = shapely.box(5, -3, 6, 0)  # covers the bearings below the +x axis, in front of the U
    table = scene_table((0.0, 0.0), [u_shape, car], include_ego=False)
    table = table.with_columns(type=pl.Series([2, 3, 2]), subtype=pl.Series([4, 0, 4]))
    for engine in sorted(ENGINES):
        out = get_visibility_df(table, 0, engine=engine, occluders="vehicles").sort("idx")
        u = out.filter(pl.col("idx") == 1).row(0, named=True)
        assert u["visibility"] == pytest.approx(0.5, abs=1e-12), engine  # symmetric about the axis: half hidden
        assert u["occluder_idxs"] == [2]
        car_row = out.filter(pl.col("idx") == 2).row(0, named=True)
        assert car_row["visibility"] == pytest.approx(1.0) and car_row["occluder_idxs"] == []


@pytest.mark.parametrize(
    ("targets", "said"),
    [
        ("animals", "targets=['animals'] matches no object of the recording"),
        ([0], "targets=[0] matches only the observer(s) [0]"),
        (pl.col("length") > 100, "targets='expression: "),
    ],
)
def test_targets_that_match_nothing_are_told(targets, said: str) -> None:
    # an empty table is never silent: the warning names what was asked and what the recording holds
    with pytest.warns(VisibilityInputWarning, match=re.escape(said)) as caught:
        table = get_visibility_df(street(), 0, targets=targets, progress=False)
    assert table.height == 0
    if "no object" in said:
        assert "present: VEHICLE idx [0, 2]; PEDESTRIAN idx [1]" in str(caught[0].message)


@pytest.mark.parametrize(
    ("occluders", "said"),
    [
        ("cyclists", "occluders=['cyclists'] matches no object of the recording"),
        ("animals", "occluders=['animals'] matches no object of the recording"),
        ([0], "occluders=[0] matches only the observer 0"),
        (pl.col("length") > 100, "occluders='expression: "),
    ],
)
def test_occluders_that_match_nothing_are_told(occluders, said: str) -> None:
    # as for targets: a choice that leaves no road user to block is never silent, and the table is still whole
    with pytest.warns(VisibilityInputWarning, match=re.escape(said)) as caught:
        table = get_visibility_df(street(), 0, occluders=occluders, progress=False)
    assert table.height == 2 and (table["occluder_idxs"].list.len() == 0).all()
    if "no object" in said:
        assert "present: VEHICLE idx [0, 2]; PEDESTRIAN idx [1]" in str(caught[0].message)


def test_occluders_that_match_nothing_are_told_on_the_shell(tmp_path) -> None:
    import subprocess
    import sys

    from conftest import REPO

    done = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility", "run", str(REPO / "highway_merge.mcap"), "--ego", "0",
         "--occluders", "cyclists", "--rows", "1"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert done.returncode == 0, done.stderr
    assert "occluders=['cyclists'] matches no object of the recording" in done.stderr


def test_a_frame_where_only_the_observer_of_the_chosen_occluders_is_left_says_nothing() -> None:
    # told for the whole recording (here: nothing to tell), never again for one of its frames
    from omega_prime_visibility import get_visibility_df_for_frame

    two = pl.concat([street(), street(frame=[1, 1, 1]).filter(pl.col("idx") != 2)])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        get_visibility_df_for_frame(two, 0, 1, occluders=[0, 2])


def test_occluders_that_match_some_object_say_nothing() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert get_visibility_df(street(), 0, occluders="pedestrians", progress=False).height == 2


def test_targets_that_match_some_object_say_nothing() -> None:
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        assert get_visibility_df(street(), 0, targets="pedestrians", progress=False)["idx"].to_list() == [1]
