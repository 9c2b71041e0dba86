"""The MCAP reader of our own: exactly omega-prime's table, on the bundled and shared recordings and on random
recordings written both by omega-prime's writer and straight from ASAM's OSI messages."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import omega_prime
import polars as pl
import pytest
import shapely
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from mcap_protobuf.writer import Writer
from osi3.osi_groundtruth_pb2 import GroundTruth
from osi3.osi_sensorview_pb2 import SensorView
from polars.testing import assert_frame_equal

from omega_prime_visibility.inputs import osi_wire
from omega_prime_visibility.inputs.io import RecordingReadError, read_recording
from omega_prime_visibility.inputs.reader import NotOurs, TraceRecording, decode_table, read_mcap

REPO = Path(__file__).resolve().parents[1]


def omega_primes(path: Path) -> omega_prime.Recording:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return omega_prime.Recording.from_file(str(path), compute_polygons=True)


def assert_same_as_omega_prime(path: Path) -> TraceRecording:
    ours, theirs = read_mcap(path), omega_primes(path)
    columns = [c for c in theirs._df.columns if c not in ("geometry", "polygon")]
    assert_frame_equal(ours.table, theirs._df.select(columns), check_exact=True)  # rows, order, dtypes, values, corners
    assert ours._df.columns == [*columns, "polygon"]  # the shapely outlines when asked for
    mine, omegas = (shapely.get_coordinates(r._df["polygon"].to_numpy()) for r in (ours, theirs))
    assert np.array_equal(mine, omegas)  # the outlines to the bit
    assert ours.host_vehicle_idx == theirs.host_vehicle_idx
    assert type(ours.map).__name__ == type(theirs.map).__name__
    return ours


def test_the_bundled_recording() -> None:
    ours = assert_same_as_omega_prime(REPO / "highway_merge.mcap")
    assert ours._df.height == 1407 and ours.host_vehicle_idx == 0


@pytest.mark.parametrize("engine", ["visilibity", "sweep"])
def test_the_tables_are_omega_primes(engine) -> None:
    """Read by our reader (box corners, no shapely outlines) or by omega-prime: the same table, to the bit."""
    from omega_prime_visibility import get_visibility_df

    path = REPO / "highway_merge.mcap"
    for ego in (0, "all"):
        ours = get_visibility_df(read_mcap(path), ego, engine=engine, progress=False)
        theirs = get_visibility_df(omega_primes(path), ego, engine=engine, progress=False)
        assert_frame_equal(ours, theirs)


def test_the_shared_mcap(shared_data, monkeypatch) -> None:
    """Its OpenDRIVE map has a geoReference: omega-prime projects the objects onto it, so read_recording leaves
    the file to omega-prime; the projection is the identity here, and the decoded columns are omega-prime's."""
    from omega_prime_visibility.inputs import reader

    path = shared_data / "highway_merge.mcap"
    with pytest.raises(NotOurs, match="geoReference"):
        read_mcap(path)
    assert isinstance(read_recording(path), omega_prime.Recording)
    monkeypatch.setattr(reader, "_geo_reference", lambda xml: False)
    ours, theirs = read_mcap(path), omega_primes(path)
    assert_frame_equal(ours.table, theirs._df.select(ours.table.columns))
    assert ours._df.height == 2598 and ours.map.odr_xml == theirs.map.odr_xml


def test_read_recording_takes_it_without_omega_prime(tmp_path) -> None:
    import subprocess
    import sys

    code = (
        "import sys; from omega_prime_visibility import get_visibility_df; "
        "t = get_visibility_df('highway_merge.mcap', engine='sweep', progress=False); "
        "print(t.height, 'omega_prime' in sys.modules)"
    )
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=REPO, timeout=600)
    assert done.stdout.split() == ["1206", "False"], done.stderr


# --- random recordings ------------------------------------------------------------------------------------------

finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)
positive = st.floats(0.05, 30.0)


@st.composite
def moving_objects(draw, idx: int) -> dict:
    kind = draw(st.sampled_from([0, 1, 2, 2, 2, 3, 4]))
    return {
        "idx": idx,
        "type": kind,
        "x": draw(finite), "y": draw(finite), "z": draw(st.floats(-5, 5)),
        "length": draw(positive), "width": draw(positive), "height": draw(positive),
        "yaw": draw(st.floats(-np.pi, np.pi)), "pitch": draw(st.floats(-0.3, 0.3)), "roll": draw(st.floats(-0.3, 0.3)),
        "vel": draw(st.tuples(finite, finite, finite)), "acc": draw(st.tuples(finite, finite, finite)),
        "subtype": draw(st.integers(0, 17)), "role": draw(st.integers(0, 10)),
        "extra": draw(st.booleans()),
    }  # fmt: skip


@st.composite
def recordings(draw) -> tuple[list[int], list[list[dict]], int | None]:
    start = draw(st.sampled_from([0, 10**9, 2**32 + 7, 3 * 3600 * 10**9, 2**53 + 1]))
    step = draw(st.sampled_from([10**7, 10**8, 33_333_333]))
    n_frames = draw(st.integers(1, 6))
    ids = draw(st.lists(st.integers(0, 2**40), min_size=1, max_size=8, unique=True))
    frames = []
    for _ in range(n_frames):
        present = draw(st.lists(st.sampled_from(ids), min_size=0, max_size=len(ids), unique=True))
        frames.append([draw(moving_objects(i)) for i in present])
    if not any(frames):
        frames[0] = [draw(moving_objects(ids[0]))]
    host = draw(st.one_of(st.none(), st.sampled_from(ids)))
    return [start + k * step for k in range(n_frames)], frames, host


def ground_truth(nanos: int, objects: list[dict], host: int | None) -> GroundTruth:
    truth = GroundTruth()
    truth.version.version_major = 3
    truth.timestamp.seconds, truth.timestamp.nanos = divmod(nanos, 10**9)
    if host is not None:
        truth.host_vehicle_id.value = host
    for o in objects:
        m = truth.moving_object.add()
        m.id.value = o["idx"]
        base = m.base
        base.position.x, base.position.y, base.position.z = o["x"], o["y"], o["z"]
        base.dimension.length, base.dimension.width, base.dimension.height = o["length"], o["width"], o["height"]
        base.orientation.roll, base.orientation.pitch, base.orientation.yaw = o["roll"], o["pitch"], o["yaw"]
        base.velocity.x, base.velocity.y, base.velocity.z = o["vel"]
        base.acceleration.x, base.acceleration.y, base.acceleration.z = o["acc"]
        m.type = o["type"]
        if o["type"] == 2:  # omega-prime's writer and reader: a classification for vehicles only
            m.vehicle_classification.type, m.vehicle_classification.role = o["subtype"], o["role"]
        if o["extra"]:  # fields the reader skips: a polygon, a model reference, lanes
            point = base.base_polygon.add()
            point.x, point.y = 1.5, -2.5
            m.model_reference = "a car"
            m.assigned_lane_id.add().value = 7
            base.orientation_rate.yaw = 0.25
    return truth


def write_osi(path: Path, times, frames, host, sensor_view: bool = False) -> None:
    with open(path, "wb") as f:
        writer = Writer(f)
        for nanos, objects in zip(times, frames, strict=True):
            truth = ground_truth(nanos, objects, host)
            if sensor_view:
                view = SensorView()
                view.global_ground_truth.CopyFrom(truth)
                writer.write_message("sensor_view", view, log_time=nanos, publish_time=nanos)
            else:
                writer.write_message("ground_truth", truth, log_time=nanos, publish_time=nanos)
        writer.finish()


SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


@SETTINGS
@given(recordings())
def test_random_recordings_written_from_osi_messages(tmp_path, recording) -> None:
    path = tmp_path / "random.mcap"
    write_osi(path, *recording)
    assert_same_as_omega_prime(path)


@SETTINGS
@given(recordings())
def test_random_recordings_written_by_omega_prime(tmp_path, recording) -> None:
    """Written by omega-prime's own writer (vehicles only: it cannot write a pedestrian's missing role)."""
    times, frames, host = recording
    rows = [
        {"total_nanos": t, "idx": o["idx"], "x": o["x"], "y": o["y"], "z": o["z"], "vel_x": o["vel"][0],
         "vel_y": o["vel"][1], "vel_z": o["vel"][2], "acc_x": o["acc"][0], "acc_y": o["acc"][1],
         "acc_z": o["acc"][2], "length": o["length"], "width": o["width"], "height": o["height"],
         "roll": o["roll"], "pitch": o["pitch"], "yaw": o["yaw"], "type": 2, "role": o["role"] % 5,
         "subtype": o["subtype"]}
        for t, objects in zip(times, frames, strict=True) for o in objects
    ]  # fmt: skip
    path = tmp_path / "written.mcap"
    table = pl.DataFrame(rows, schema=omega_prime.schemas.polars_schema)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        omega_prime.Recording(table, host_vehicle_idx=host).to_mcap(path)
    assert_same_as_omega_prime(path)


def test_sensor_views(tmp_path) -> None:
    objects = [{"idx": 4, "type": 3, "x": 1.0, "y": 2.0, "z": 0.9, "length": 0.5, "width": 0.6, "height": 1.8,
                "roll": 0.0, "pitch": 0.0, "yaw": 1.0, "vel": (1.0, 0.0, 0.0), "acc": (0.0, 0.0, 0.0), "subtype": 0,
                "role": 0, "extra": False}]  # fmt: skip
    path = tmp_path / "views.mcap"
    write_osi(path, [0, 10**8], [objects, objects], 4, sensor_view=True)
    ours = assert_same_as_omega_prime(path)
    assert ours._df["role"].to_list() == [-1, -1] and ours._df["frame"].to_list() == [0, 1]


def test_projections_go_to_omega_prime(tmp_path) -> None:
    """A recording with a projection is omega-prime's to convert: read_recording hands it over."""
    path = tmp_path / "projected.mcap"
    truth = ground_truth(0, [], 1)
    truth.proj_string = "+proj=utm +zone=32 +ellps=GRS80 +units=m +no_defs"
    with open(path, "wb") as f:
        writer = Writer(f)
        writer.write_message("ground_truth", truth, log_time=0, publish_time=0)
        writer.finish()
    with pytest.raises(NotOurs, match="projection"):
        read_mcap(path)
    with pytest.raises(NotOurs, match="projection"):
        decode_table([ground_truth(0, [], None).SerializeToString(), truth.SerializeToString()])


def test_bytes_that_are_no_message() -> None:
    good = ground_truth(5, [], 2).SerializeToString()
    for bad in (good[:-1] + b"\xff", b"\x0a\xff\xff", b"\x0f"):  # cut off, a length past the end, wire type 7
        with pytest.raises(NotOurs, match="no valid"):
            decode_table([good, bad])
    assert decode_table([good])[1] == 2


def test_a_double_with_the_wrong_wire_type_is_refused() -> None:
    """A field the reader reads, sent with another wire type: not read as something else."""
    numbers = osi_wire.field_numbers()
    position_x = numbers[osi_wire.V_X]
    vector = bytes([position_x << 3 | osi_wire.VARINT, 5])  # x as a varint
    base = bytes([numbers[osi_wire.BM_POSITION] << 3 | 2, len(vector)]) + vector
    moving = bytes([numbers[osi_wire.MO_BASE] << 3 | 2, len(base)]) + base
    timestamp = bytes([numbers[osi_wire.GT_TIMESTAMP] << 3 | 2, 0])  # (a message without one is refused too)
    truth = timestamp + bytes([numbers[osi_wire.GT_MOVING_OBJECT] << 3 | 2, len(moving)]) + moving
    with pytest.raises(NotOurs, match="no valid"):
        decode_table([truth])


def test_bytes_protobuf_refuses_anywhere_in_a_message_are_refused() -> None:
    # field number 0 at the top and inside a nested message the reader never reads (a lane), a field number past
    # protobuf's largest, and a message without its timestamp: each refused, as protobuf refuses the first three
    from google.protobuf.message import DecodeError

    good = ground_truth(5, [], 2)
    good.lane.add().id.value = 4
    data = good.SerializeToString()
    lane_field = GroundTruth.DESCRIPTOR.fields_by_name["lane"].number
    lane_at = data.index(bytes([lane_field << 3 | 2]))
    inner = data[: lane_at + 2] + bytes([0x00, 0x00]) + data[lane_at + 2 :]  # a field 0 varint inside the lane
    inner = inner[: lane_at + 1] + bytes([inner[lane_at + 1] + 2]) + inner[lane_at + 2 :]  # the lane's length + 2
    top = bytes([0x02, 0x00]) + data  # field 0, an empty length-delimited value
    huge = bytes([0xF8, 0xFF, 0xFF, 0xFF, 0x1F, 0x00]) + data  # field number 2^34 - 1, beyond 2^29 - 1
    negative = data + bytes([0x80] * 9 + [0x01, 0x01])  # a 64-bit tag: its field number reads negative
    for bad in (inner, top, huge, negative):
        with pytest.raises(DecodeError):
            GroundTruth().ParseFromString(bad)
        with pytest.raises(NotOurs, match="no valid protobuf message"):
            decode_table([data, bad])
    untimed = GroundTruth()
    untimed.moving_object.add().id.value = 1
    with pytest.raises(NotOurs, match="message 1 has no timestamp"):
        decode_table([data, untimed.SerializeToString()])
    assert decode_table([data])[1] == 2


def test_files_it_cannot_read_go_to_omega_prime(tmp_path) -> None:
    cut = tmp_path / "cut.mcap"
    cut.write_bytes((REPO / "highway_merge.mcap").read_bytes()[:5000])
    with pytest.raises(RecordingReadError, match="truncated"):
        read_recording(cut)


def test_omega_primes_metrics_take_it() -> None:
    """batch --conflicts hands the recording to omega-prime's MetricManager (which sets ``_df``): the same
    timegaps as from omega-prime's own Recording, and the recording's table is still read right after."""
    from omega_prime.metrics import MetricManager, distance_traveled, timegaps_and_min_timegaps, vel

    from omega_prime_visibility import get_visibility_df

    path = REPO / "highway_merge.mcap"
    manager = MetricManager(metrics=[vel, distance_traveled, timegaps_and_min_timegaps])
    ours = read_mcap(path)
    gaps = manager.compute(ours, ego_id=0, time_buffer=3e9)[1]["timegaps"]
    assert_frame_equal(gaps, manager.compute(omega_primes(path), ego_id=0, time_buffer=3e9)[1]["timegaps"])
    before = get_visibility_df(read_mcap(path), 0, engine="sweep", progress=False)
    assert_frame_equal(get_visibility_df(ours, 0, engine="sweep", progress=False), before)


def test_it_offers_the_rest_of_omega_primes_recording() -> None:
    recording = read_mcap(REPO / "highway_merge.mcap")
    assert recording._omega_prime is None  # nothing built yet
    host = recording.host_vehicle  # omega-prime's: the host vehicle's moving object
    assert isinstance(recording._omega_prime, omega_prime.Recording)
    assert host.idx == recording.host_vehicle_idx
    assert sorted(recording.moving_objects) == sorted(recording.table["idx"].unique().to_list())
    with pytest.raises(AttributeError, match="no attribute 'no_such_thing'"):
        recording.no_such_thing  # noqa: B018
    with pytest.raises(AttributeError):
        recording._private  # noqa: B018
    recording._df = recording.table.head(10)  # as omega-prime's MetricManager sets it: built again from it
    assert recording._omega_prime is None and recording.df.height == 10


def test_its_own_errors_stay_its_own() -> None:
    recording = read_mcap(REPO / "highway_merge.mcap")
    broken = TraceRecording(recording.table, 0, Path("nowhere.mcap"))

    def unreadable(self):
        raise AttributeError("the map's reader broke")

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(TraceRecording, "_read_map", unreadable)
        with pytest.raises(AttributeError, match="the map's reader broke"):  # not a recursion through omega-prime
            broken.map  # noqa: B018
    odd = TraceRecording(pl.DataFrame({"idx": [1]}), None, Path("odd.mcap"))
    assert not hasattr(odd, "moving_objects")  # omega-prime cannot build a Recording of it: False, not a crash


@pytest.mark.filterwarnings("ignore:Failed to apply projections")  # omega-prime's, on the bundled recording
def test_a_pictures_lanes_are_omega_primes_centre_lines() -> None:
    ours = read_mcap(REPO / "highway_merge.mcap")
    lanes = ours.picture_lanes()
    assert ours._map_read is False  # read without omega-prime
    theirs = omega_prime.Recording.from_file(str(REPO / "highway_merge.mcap"), compute_polygons=True).map
    assert type(theirs).__name__ == "MapOsiCenterline"
    by_id = {int(lane._osi.id.value): lane for lane in theirs.lanes.values()}
    assert sorted(lanes.lanes) == sorted(by_id) and len(by_id) > 0
    for key, lane in lanes.lanes.items():
        assert np.array_equal(np.asarray(lane.centerline.coords), np.asarray(by_id[key].centerline.coords))
    ours.map = theirs  # once the map is read (or set), a picture takes it
    assert ours.picture_lanes() is theirs
