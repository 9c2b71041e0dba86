"""OSI trace files read straight into the table (inputs/osi_trace.py): exactly omega-prime's table, on the shared
esmini traces and on random traces written from OSI messages."""

from __future__ import annotations

import struct
import warnings
from pathlib import Path

import numpy as np
import pytest
import shapely
from hypothesis import given
from osi3.osi_sensorview_pb2 import SensorView
from polars.testing import assert_frame_equal
from test_reader import SETTINGS, ground_truth, omega_primes, recordings

from omega_prime_visibility.inputs.io import RecordingReadError, read_recording
from omega_prime_visibility.inputs.osi_trace import frames, probe, read_osi
from omega_prime_visibility.inputs.reader import NotOurs, TraceRecording


def write_trace(path: Path, times, objects_by_frame, host, sensor_view: bool = False) -> Path:
    """An OSI trace: each message preceded by its length (4 bytes, little-endian)."""
    with open(path, "wb") as f:
        for nanos, objects in zip(times, objects_by_frame, strict=True):
            message = ground_truth(nanos, objects, host)
            if sensor_view:
                view = SensorView()
                view.global_ground_truth.CopyFrom(message)
                message = view
            data = message.SerializeToString()
            f.write(struct.pack("<I", len(data)) + data)
    return path


def assert_same_as_omega_prime(path: Path) -> TraceRecording:
    ours, theirs = read_osi(path), omega_primes(path)
    columns = [c for c in theirs._df.columns if c not in ("geometry", "polygon")]
    assert_frame_equal(ours.table, theirs._df.select(columns))  # rows, order, dtypes, values, box corners
    mine, omegas = (shapely.get_coordinates(r._df["polygon"].to_numpy()) for r in (ours, theirs))
    assert np.array_equal(mine, omegas)
    assert ours.host_vehicle_idx == theirs.host_vehicle_idx
    assert type(ours.map).__name__ == type(theirs.map).__name__
    return ours


@pytest.mark.parametrize("name", ["acc-test", "alks_cut-in", "highway_merge", "pedestrian"])
def test_the_shared_esmini_traces(shared_data, name: str) -> None:
    ours = assert_same_as_omega_prime(shared_data / f"{name}.osi")
    assert ours.table.height > 0
    assert isinstance(read_recording(shared_data / f"{name}.osi"), TraceRecording)  # the path a user takes


@SETTINGS
@given(recordings())
def test_random_ground_truth_traces(tmp_path, recording) -> None:
    unnamed = write_trace(tmp_path / "random.osi", *recording)  # the type from the first message
    if probe(frames(unnamed.read_bytes())[0]) is None:  # a small message can be a clean SensorView too
        with pytest.raises(ValueError, match="Could not determine the OSI message type"):
            omega_primes(unnamed)  # omega-prime (betterosi) cannot tell either
    else:
        assert_same_as_omega_prime(unnamed)
    assert_same_as_omega_prime(write_trace(tmp_path / "20261128T101500Z_gt_3.7.0_4.24.0_6_x.osi", *recording))


@SETTINGS
@given(recordings())
def test_random_sensor_view_traces(tmp_path, recording) -> None:
    assert_same_as_omega_prime(write_trace(tmp_path / "city_sv.osi", *recording, sensor_view=True))


def test_what_it_leaves_to_omega_prime(tmp_path) -> None:
    objects = [{"idx": 4, "type": 2, "x": 1.0, "y": 2.0, "z": 0.9, "length": 4.5, "width": 1.8, "height": 1.5,
                "roll": 0.0, "pitch": 0.0, "yaw": 1.0, "vel": (1.0, 0.0, 0.0), "acc": (0.0, 0.0, 0.0), "subtype": 3,
                "role": 0, "extra": False}]  # fmt: skip
    trace = write_trace(tmp_path / "cut.osi", [0, 10**8], [objects, objects], 4)
    data = trace.read_bytes()
    trace.write_bytes(data[:-3])  # the last message cut short
    with pytest.raises(NotOurs, match="ends within a message"):
        read_osi(trace)
    with pytest.raises(RecordingReadError, match=r"cut\.osi"), warnings.catch_warnings():
        warnings.simplefilter("ignore")
        read_recording(trace)  # omega-prime's words, naming the file
    named = write_trace(tmp_path / "run_sd.osi", [0], [objects], 4)  # SensorData by its name: not ours
    with pytest.raises(NotOurs, match="SensorData"):
        read_osi(named)
    assert frames(b"") == [] and probe(b"") is None  # an empty message is a clean SensorView and GroundTruth
