"""Occluded conflicts (analysis/conflicts.py): a pedestrian stepping out from behind a parked van into the ego's
path, a car crossing the ego's path too late to conflict, the Metric beside omega-prime's own, a real trace."""

from __future__ import annotations

import math
import warnings

import polars as pl
import pytest
from conftest import REPO

from omega_prime_visibility import get_visibility_df, occluded_conflicts
from omega_prime_visibility.analysis.conflicts import path_conflicts

STEP = 100_000_000  # 10 Hz
CAR, PEDESTRIAN = 2, 3  # omega-prime's MovingObjectType values


def recording(tracks: dict, frames: int):
    """An omega-prime Recording of boxes moving at constant velocity: ``idx: (x0, y0, length, width, vx, vy,
    type)``, heading along the velocity (or +x when standing)."""
    import omega_prime

    rows = []
    for idx, (x0, y0, length, width, vx, vy, kind) in tracks.items():
        for f in range(frames):
            t = f * STEP / 1e9
            rows.append(
                {"total_nanos": f * STEP, "idx": idx, "x": x0 + vx * t, "y": y0 + vy * t, "z": 0.75, "vel_x": vx,
                 "vel_y": vy, "vel_z": 0.0, "acc_x": 0.0, "acc_y": 0.0, "acc_z": 0.0, "length": length,
                 "width": width, "height": 1.5, "roll": 0.0, "pitch": 0.0,
                 "yaw": math.atan2(vy, vx) if (vx or vy) else 0.0, "type": kind, "role": 0 if kind == CAR else -1,
                 "subtype": 4 if kind == CAR else -1}
            )  # fmt: skip
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return omega_prime.Recording(pl.DataFrame(rows), validate=False)


def timegaps(r, buffer_seconds: float) -> pl.DataFrame:
    from omega_prime.metrics import MetricManager, distance_traveled, timegaps_and_min_timegaps, vel

    manager = MetricManager(metrics=[vel, distance_traveled, timegaps_and_min_timegaps])
    return manager.compute(r, ego_id=0, time_buffer=buffer_seconds * 1e9)[1]["timegaps"]


# The ego 0 (4.5 x 1.8 m) drives along +x at 10 m/s from x = 0; the van 1 is parked at x 20..26, y 1.5..3.5; the
# pedestrian 2 (0.5 m square) walks along -y at 1.5 m/s on x = 30 from y = 4; the car 3 crosses x = 5 along +y at
# 5 m/s from y = -25, long after the ego has passed there.
SCENE = {
    0: (0.0, 0.0, 4.5, 1.8, 10.0, 0.0, CAR),
    1: (23.0, 2.5, 6.0, 2.0, 0.0, 0.0, CAR),
    2: (30.0, 4.0, 0.5, 0.5, 0.0, -1.5, PEDESTRIAN),
    3: (5.0, -25.0, 4.5, 1.8, 0.0, 5.0, CAR),
}


@pytest.fixture(scope="module")
def van_scene():
    r = recording(SCENE, 60)
    return r, timegaps(r, 6.0), get_visibility_df(r, 0, progress=False)


def test_the_pedestrian_behind_the_van(van_scene) -> None:
    # On paper. Conflict: the pedestrian is in the ego's lane (|y| <= 0.9 + 0.25) for t in [1.9, 3.43] s; the ego
    # covers x = 29.75..30.25 for t in [2.75, 3.25] s: both there at once from the first frame the ego reaches it,
    # t = 2.8 s (timegap 0), so the conflict is at 2.8 s.
    # Sight: from the eye (10 t, 0), left of the van, its shadow's lower edge runs through the van's far lower
    # corner (26, 1.5); the pedestrian's lowest far corner (30.25, y - 0.25) is below it when
    # (3.75 - 1.5 t) / (30.25 - 10 t) < 1.5 / (26 - 10 t), i.e. 15 t^2 - 61.5 t + 52.125 < 0: t > 1.197 s. Its top
    # stays inside the upper edge (through (20, 3.5)). First visible at frame 12 (1.2 s), 1.6 s before the conflict,
    # hidden in frames 0-11 (1.2 s) by the van alone. Noticed (1.0 s within 1.5 s: 10 visible frames) at frame 21.
    # Distance at first sight: ego (12, 0), pedestrian (30, 2.2): sqrt(18^2 + 2.2^2).
    r, gaps, vis = van_scene
    out = occluded_conflicts(vis, gaps, r._df, ego_idx=0)
    assert out["idx"].to_list() == [2]  # the car 3 crosses 3.5 s or more after the ego: no conflict within 3 s
    row = out.row(0, named=True)
    assert (row["timegap"], row["ego_nanos"], row["target_nanos"], row["conflict_nanos"]) == (
        0.0,
        28 * STEP,
        28 * STEP,
        28 * STEP,
    )
    assert row["first_visible_nanos"] == 12 * STEP and row["sight_to_conflict"] == pytest.approx(1.6)
    assert row["first_noticed_nanos"] == 21 * STEP and row["notice_to_conflict"] == pytest.approx(0.7)
    assert row["distance_at_sight"] == pytest.approx(math.hypot(18.0, 2.2), abs=1e-9)
    assert (row["hidden"], row["hidden_seconds"], row["hidden_by"], row["hidden_by_static"]) == (
        True,
        pytest.approx(1.2),
        [1],
        [],
    )
    assert row["first_seen_by"] is None and row["notice_model"] == "visible 1 s within 1.5 s"
    # the visibility table agrees with the paper: hidden in 11, seen in 12
    ped = vis.filter(pl.col("idx") == 2).sort("frame")["visibility"].to_list()
    assert ped[11] == 0.0 and ped[12] > 0.0


def test_look_back_and_notice_models(van_scene) -> None:
    r, gaps, vis = van_scene
    # a 1.0 s look-back (frames 18-28) holds no hidden frame
    short = occluded_conflicts(vis, gaps, r._df, ego_idx=0, look_back=1.0).row(0, named=True)
    assert (short["hidden"], short["hidden_seconds"], short["hidden_by"]) == (False, 0.0, [])
    # an unbroken 0.5 s from frame 12: noticed at frame 17; no model: noticed when first seen
    run = occluded_conflicts(vis, gaps, ego_idx=0, notice=None, reaction_time=0.5).row(0, named=True)
    assert run["first_noticed_nanos"] == 17 * STEP and run["distance_at_sight"] is None
    bare = occluded_conflicts(vis, gaps, ego_idx=0, notice=None).row(0, named=True)
    assert bare["first_noticed_nanos"] == 12 * STEP
    # a reaction time given alone replaces the default window; given with a window, it is refused
    alone = occluded_conflicts(vis, gaps, ego_idx=0, reaction_time=0.5).row(0, named=True)
    assert alone["first_noticed_nanos"] == 17 * STEP and alone["notice_model"] == run["notice_model"]
    with pytest.raises(ValueError, match="not both"):
        occluded_conflicts(vis, gaps, ego_idx=0, reaction_time=0.5, notice=(1.0, 1.5))


def test_the_crossing_car_conflicts_only_with_a_larger_pet(van_scene) -> None:
    # car 3 covers y -0.9..0.9 (with its half length 2.25) for t in [4.37, 5.63] s; the ego covered x 4.1..5.9 for
    # t in [0.185, 0.815] s: the least gap is from ego time 0.8 s (frame 8) to the car's first frame there, 4.4 s
    _, gaps, _ = van_scene
    assert path_conflicts(gaps, pet=3.0)["idx"].to_list() == [2]
    wide = path_conflicts(gaps, pet=4.0).filter(pl.col("idx") == 3).row(0, named=True)
    assert (wide["ego_nanos"], wide["target_nanos"]) == (8 * STEP, 44 * STEP)
    assert wide["timegap"] == pytest.approx(3.6) and wide["conflict_nanos"] == 8 * STEP


def test_through_sensors_out_of_view_is_not_hidden(van_scene) -> None:
    from omega_prime_visibility import Sensor

    r, gaps, _ = van_scene
    # A wide camera (90 deg, 2 m ahead of the centre) has the pedestrian in view while the van hides it; a narrow one
    # (10 deg) has it out of view then (from (2 + 10 t, 0) it lies 7.8 deg or more off the axis until t = 1.2 s),
    # so through the narrow one alone it is never *hidden*, only out of view. The rear radar never sees it.
    wide = [Sensor("wide", x=2.0, fov=math.radians(90)), Sensor("rear", x=-2.0, yaw=math.pi, fov=1.0)]
    narrow = [Sensor("narrow", x=2.0, fov=math.radians(10)), Sensor("rear", x=-2.0, yaw=math.pi, fov=1.0)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the pedestrian stands in the ego's body at the collision
        through_wide = get_visibility_df(r, 0, sensors=wide, progress=False)
        through_narrow = get_visibility_df(r, 0, sensors=narrow, progress=False)
    seen = occluded_conflicts(through_wide, gaps, ego_idx=0).row(0, named=True)
    assert seen["first_seen_by"] == "wide" and seen["hidden"] and seen["hidden_by"] == [1]
    late = occluded_conflicts(through_narrow, gaps, ego_idx=0).row(0, named=True)
    assert late["first_seen_by"] == "narrow" and late["first_visible_nanos"] > 12 * STEP
    assert (late["hidden"], late["hidden_seconds"], late["hidden_by"]) == (False, 0.0, [])


def test_bad_input(van_scene) -> None:
    _, gaps, vis = van_scene
    with pytest.raises(ValueError, match="pass ego_idx"):
        occluded_conflicts(vis, gaps)
    with pytest.raises(ValueError, match=r"lacks the column\(s\) \['occluder_idxs'\]"):
        occluded_conflicts(vis.drop("occluder_idxs"), gaps, ego_idx=0)
    with pytest.raises(ValueError, match="timegaps"):
        occluded_conflicts(vis, gaps.drop("timegap"), ego_idx=0)
    with pytest.raises(ValueError, match="pet"):
        path_conflicts(gaps, pet=-1.0)
    with pytest.raises(ValueError, match="look_back"):
        occluded_conflicts(vis, gaps, ego_idx=0, look_back=float("nan"))
    with pytest.raises(ValueError, match=r"threshold must be a share of the target in \[0, 1\), not 30 \(a percentage"):
        occluded_conflicts(vis, gaps.filter(pl.lit(False)), ego_idx=0, threshold=30)  # (even with no conflict)


def test_the_metric_beside_omega_primes_default_metrics() -> None:
    from omega_prime.metrics import MetricManager
    from omega_prime.metrics.metric_manager import DEFAULT_METRICS

    from omega_prime_visibility import occluded_conflicts_metric, visibility
    from omega_prime_visibility.inputs.io import read_recording

    r = read_recording(REPO / "highway_merge.mcap")
    manager = MetricManager(metrics=[*DEFAULT_METRICS, visibility, occluded_conflicts_metric])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        _, properties = manager.compute(r, ego_id=0, time_buffer=3e9)
    conflicts = properties["occluded_conflicts"]
    assert {"timegaps", "visibility", "occluded_conflicts"} <= set(properties)
    expected = occluded_conflicts(properties["visibility"], properties["timegaps"], r._df, ego_idx=0)
    assert conflicts.equals(expected)
    # the bundled merge: the ego follows car 4 in its lane (the ego reaches its places 1.4 s later) and is passed
    # by car 5 in the left lane (never the same place): one conflict, with car 4, seen throughout
    assert conflicts["idx"].to_list() == [4]
    row = conflicts.row(0, named=True)
    assert row["timegap"] == pytest.approx(-1.4) and not row["hidden"] and row["first_visible_nanos"] == 0


def test_pedestrian_trace_has_no_conflict_and_the_camera_sees_it_from_the_start(shared_data) -> None:
    # esmini's pedestrian.osi: the car (idx 0) stops at (31.9, -23.2) from about 5 s on; the pedestrian (idx 1)
    # crosses the car's line ahead of it (about 6.4 s) but the two outlines never overlap at any pair of times
    # (omega-prime's timegaps with a 30 s buffer are empty): no conflict, whatever the PET.
    from omega_prime_visibility import seen_by_any
    from omega_prime_visibility.inputs.io import read_recording

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(shared_data / "pedestrian.osi", shared_data / "fabriksgatan.xodr")
    gaps = timegaps(r, 30.0)
    assert gaps.height == 0
    vis = get_visibility_df(r, 0, sensors="typical", progress=False)
    assert occluded_conflicts(vis, gaps, r._df, ego_idx=0, pet=30.0).height == 0
    camera = vis.filter(pl.col("idx") == 1, pl.col("sensor") == "front_camera").sort("frame")
    assert camera["visibility"][0] > 0 and camera["status"][0] in ("visible", "partly_visible")
    best = seen_by_any(vis).filter(pl.col("idx") == 1)
    assert (best["visibility"] > 0).all()  # never hidden from every sensor


def test_only_what_happens_before_the_conflict_counts() -> None:
    # a hand-made table: target 2 hidden by 5 in frames 0-5, by 6 in frames 6-9, seen from frame 10; its path
    # conflicts with the ego's at frame 5 (it gets there first, the ego 1 s later). Before the conflict it was never
    # seen: no sight, no notice; hidden 0.5 s (frames 0-4: the conflict frame 5 is not before it), by 5 alone.
    frames = range(15)
    vis = pl.DataFrame(
        {
            "frame": list(frames),
            "total_nanos": [f * STEP for f in frames],
            "idx": [2] * 15,
            "occluder_idxs": [[5]] * 6 + [[6]] * 4 + [[]] * 5,
            "static_occluder_idxs": [[]] * 15,
            "visibility": [0.0] * 10 + [1.0] * 5,
        },
        schema_overrides={"occluder_idxs": pl.List(pl.Int64), "static_occluder_idxs": pl.List(pl.Int64)},
    )
    gaps = pl.DataFrame(
        {"idx_ego": [0], "idx": [2], "total_nanos_ego": [15 * STEP], "timegap": [-1.0], "total_nanos": [5 * STEP]}
    )
    row = occluded_conflicts(vis, gaps, ego_idx=0).row(0, named=True)
    assert row["conflict_nanos"] == 5 * STEP
    assert row["first_visible_nanos"] is None and row["sight_to_conflict"] is None
    assert row["first_noticed_nanos"] is None
    assert (row["hidden"], row["hidden_seconds"], row["hidden_by"]) == (True, pytest.approx(0.5), [5])


def hidden_run(frames: int, period: int, start: int = 0, frame_dtype=pl.Int64, shuffle: bool = False):
    """A target 2 hidden by 5 (in view, nothing seen) in every frame ``0 .. frames - 1`` of ``period`` ns from
    ``start`` ns, and the timegaps of a conflict at the last frame (the ego gets there at that time, timegap 0)."""
    vis = pl.DataFrame(
        {
            "frame": pl.Series(range(frames), dtype=frame_dtype),
            "total_nanos": [start + f * period for f in range(frames)],
            "idx": [2] * frames,
            "occluder_idxs": [[5]] * frames,
            "static_occluder_idxs": [[]] * frames,
            "visibility": [0.0] * frames,
        },
        schema_overrides={"occluder_idxs": pl.List(pl.Int64), "static_occluder_idxs": pl.List(pl.Int64)},
    )
    if shuffle:
        vis = vis.sample(fraction=1.0, shuffle=True, seed=1)
    last = start + (frames - 1) * period
    gaps = pl.DataFrame(
        {"idx_ego": [0], "idx": [2], "total_nanos_ego": [last], "timegap": [0.0], "total_nanos": [last]}
    )
    return vis, gaps


@pytest.mark.parametrize("hz", [1, 10, 100])
@pytest.mark.parametrize("start", [0, 3 * 3600 * 10**9, 2**53 + 1], ids=["zero", "3 hours", "beyond 2^53 ns"])
@pytest.mark.parametrize("frame_dtype", [pl.Int64, pl.UInt32], ids=["Int64", "UInt32"])
def test_hidden_seconds_over_long_windows_never_wrap(hz, start, frame_dtype) -> None:
    # hidden in every frame of 12 minutes: a 10-minute look-back holds exactly 600 s of frames before the conflict
    # ([conflict - 600 s, conflict): 600 * hz frames, each one period). A 32-bit count times the period in ns wraps at
    # 2^32 ns (4.29 s): 51 frames at 10 Hz read 0.805 s before.
    period = 10**9 // hz
    vis, gaps = hidden_run(720 * hz + 1, period, start, frame_dtype, shuffle=hz == 10)
    for look_back in (5.0, 5.1, 600.0):
        row = occluded_conflicts(vis, gaps, ego_idx=0, look_back=look_back, notice=None).row(0, named=True)
        expected = math.floor(look_back * hz + 1e-9) / hz  # frames at conflict - k periods, 1 <= k <= look_back * hz
        assert row["hidden_seconds"] == pytest.approx(expected, rel=1e-12), look_back
        assert row["hidden"] and row["hidden_by"] == [5]


def test_unsigned_times_from_elsewhere_do_not_wrap() -> None:
    # timegaps and a table with UInt64 times (a parquet file from another tool): conflict minus look-back would wrap
    vis, gaps = hidden_run(31, STEP)
    vis = vis.with_columns(pl.col("total_nanos").cast(pl.UInt64))
    gaps = gaps.with_columns(pl.col("total_nanos", "total_nanos_ego").cast(pl.UInt64))
    row = occluded_conflicts(vis, gaps, ego_idx=0).row(0, named=True)
    assert row["hidden_seconds"] == pytest.approx(3.0) and row["conflict_nanos"] == 30 * STEP
    # a look-back of "everything" (longer than int64 nanoseconds) is the whole past, not an empty window
    assert occluded_conflicts(vis, gaps, ego_idx=0, look_back=1e12)["hidden_seconds"][0] == pytest.approx(3.0)


def test_the_look_back_window_is_half_open() -> None:
    # hidden in all 31 frames (0 to 3 s at 10 Hz), conflict at 3.0 s. A 2 s look-back is [1.0, 3.0): frames 10 to 29,
    # 20 frames, 2.0 s. The frame at 1.0 s lies on the lower bound and counts; the frame at the conflict's own time
    # does not (either slip gives 1.9 or 2.1 s).
    vis, gaps = hidden_run(31, STEP)
    row = occluded_conflicts(vis, gaps, ego_idx=0, look_back=2.0).row(0, named=True)
    assert row["hidden_seconds"] == pytest.approx(2.0, abs=1e-12)
    # a look-back a nanosecond short of 2 s leaves out the frame at 1.0 s; a nanosecond longer adds nothing
    assert occluded_conflicts(vis, gaps, ego_idx=0, look_back=1.999999999)["hidden_seconds"][0] == pytest.approx(1.9)
    assert occluded_conflicts(vis, gaps, ego_idx=0, look_back=2.000000001)["hidden_seconds"][0] == pytest.approx(2.0)
    # hidden only at the conflict's time: not hidden before it
    only_last = vis.with_columns(visibility=pl.when(pl.col("frame") == 30).then(0.0).otherwise(1.0))
    assert not occluded_conflicts(only_last, gaps, ego_idx=0)["hidden"][0]


def test_the_pet_window_is_half_open() -> None:
    # |timegap| in [0, pet): a gap of exactly the PET is no conflict, one a nanosecond-scale below it is
    gaps = pl.DataFrame(
        {"idx_ego": [0, 0], "idx": [7, 8], "total_nanos_ego": [0, 0], "timegap": [3.0, -2.999999999],
         "total_nanos": [3 * 10**9, 0]}
    )  # fmt: skip
    assert path_conflicts(gaps, pet=3.0)["idx"].to_list() == [8]
    assert path_conflicts(gaps, pet=3.000000001)["idx"].to_list() == [7, 8]
