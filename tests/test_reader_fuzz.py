"""The reader against damaged recordings: seeded mutations of the bundled recording's ground-truth messages
(flipped, cut, inserted and zeroed bytes, a tag turned into field number 0, duplicated and dropped messages),
written into valid MCAP files (so that only the protobuf bytes are damaged) and read both by the package and by
omega-prime's own decoder: the same table or one clear refusal; never a crash, never another table without a word."""

from __future__ import annotations

import warnings
from pathlib import Path

import numpy as np
import omega_prime
import pytest
from mcap.reader import make_reader
from mcap.writer import Writer
from polars.testing import assert_frame_equal

from omega_prime_visibility.inputs.io import RecordingReadError, read_recording

REPO = Path(__file__).resolve().parents[1]
MUTATIONS = ("flip", "cut", "insert", "zero", "field_zero", "duplicate", "drop")
CASES = 28  # four of each kind, seeded


def mutated(path: Path, out: Path, kind: str, rng: np.random.Generator) -> None:
    """``path`` copied to ``out`` record by record, one ground-truth message damaged by ``kind``."""
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        messages = list(reader.iter_messages())
    truths = [
        k for k, (schema, _, _) in enumerate(messages) if schema is not None and schema.name == "osi3.GroundTruth"
    ]
    victim = int(rng.choice(truths))
    with open(out, "wb") as f:
        writer = Writer(f)
        writer.start()
        schema_ids = {s.id: writer.register_schema(s.name, s.encoding, s.data) for s in summary.schemas.values()}
        channel_ids = {
            c.id: writer.register_channel(c.topic, c.message_encoding, schema_ids.get(c.schema_id, 0), c.metadata)
            for c in summary.channels.values()
        }
        for k, (_, channel, message) in enumerate(messages):
            data = bytearray(message.data)
            copies = 1
            if k == victim:
                at = int(rng.integers(0, len(data)))
                if kind == "flip":
                    data[at] ^= int(rng.integers(1, 256))
                elif kind == "cut":
                    data = data[:at]
                elif kind == "insert":
                    data.insert(at, int(rng.integers(0, 256)))
                elif kind == "zero":
                    data[at] = 0
                elif kind == "field_zero":  # the message's first tag becomes field number 0 (its wire type kept)
                    data[0] &= 0x07
                elif kind == "duplicate":
                    copies = 2
                elif kind == "drop":
                    copies = 0
            for _ in range(copies):
                writer.add_message(channel_ids[channel.id], message.log_time, bytes(data), message.publish_time,
                                   message.sequence)  # fmt: skip
        writer.finish()


def omega_primes(path: Path):
    """omega-prime's own reading, or the exception it raises."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return omega_prime.Recording.from_file(str(path), compute_polygons=True)
    except Exception as e:
        return e


@pytest.mark.parametrize("case", range(CASES))
def test_a_damaged_recording_reads_as_omega_prime_reads_it_or_is_refused(case, tmp_path) -> None:
    rng = np.random.default_rng(1000 + case)
    kind = MUTATIONS[case % len(MUTATIONS)]
    path = tmp_path / f"{kind}.mcap"
    mutated(REPO / "highway_merge.mcap", path, kind, rng)
    theirs = omega_primes(path)
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            ours = read_recording(path)
    except RecordingReadError as e:  # one clear line, naming the file
        assert str(path) in str(e) and "\n" not in str(e)
        return
    assert not isinstance(theirs, Exception), f"{kind}: read without a word where omega-prime refuses: {theirs}"
    columns = [c for c in theirs._df.columns if c not in ("geometry", "polygon")]
    assert_frame_equal(ours._df.select(columns), theirs._df.select(columns), check_exact=True)
    assert ours.host_vehicle_idx == theirs.host_vehicle_idx


def test_field_number_zero_is_refused_as_omega_prime_refuses_it(tmp_path) -> None:
    # the case: a tag byte of one ground-truth message turned into field number 0
    path = tmp_path / "zero.mcap"
    mutated(REPO / "highway_merge.mcap", path, "field_zero", np.random.default_rng(3))
    assert isinstance(omega_primes(path), Exception)
    with pytest.raises(RecordingReadError, match=r"zero\.mcap"):
        read_recording(path)
