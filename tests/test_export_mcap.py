"""The MCAP of the answer and the OSI SensorData: strict MCAP, official schemas, the table row by row."""

from __future__ import annotations

import json
import math
import struct
import warnings
from pathlib import Path

import polars as pl
import pytest
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from mcap.reader import make_reader
from mcap.stream_reader import StreamReader
from osi3.osi_sensordata_pb2 import SensorData

from omega_prime_visibility import VisibilityInputWarning, get_visibility_df, read_recording
from omega_prime_visibility.export.mcap import write_mcap
from omega_prime_visibility.export.scene import rgba
from omega_prime_visibility.inputs.sensors import Sensor, camera, lidar
from omega_prime_visibility.plot.style import OKABE_ITO, visibility_colour

REPO = Path(__file__).resolve().parent.parent
MERGE = REPO / "highway_merge.mcap"
SENSORS = (camera("front", 640, 360, math.radians(70), x=1.0, z=1.4), lidar("roof", "vlp16"),
           Sensor("radar", fov=1.0, range=80.0))  # fmt: skip


def messages(path: Path, topics=None) -> list[tuple[str, int, int, bytes]]:
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        return [(c.topic, m.log_time, m.publish_time, m.data) for _, c, m in reader.iter_messages(topics=topics)]


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> tuple[Path, list[Path], pl.DataFrame]:
    folder = tmp_path_factory.mktemp("mcap")
    table = get_visibility_df(MERGE, 0, mode="3d", sensors=list(SENSORS), progress=False)
    paths = write_mcap(MERGE, table, folder / "vis.mcap", ego_idx=0, sensors=SENSORS)
    return paths[0], paths[1:], table


def test_the_file_is_strict_mcap_and_every_message_decodes_with_the_official_schemas(written) -> None:
    path, _, _ = written
    with open(path, "rb") as f:  # a stream read checks every record and CRC from the first byte to the last
        records = list(StreamReader(f, validate_crcs=True).records)
    assert type(records[-1]).__name__ == "Footer" and any(type(r).__name__ == "ChunkIndex" for r in records)
    with open(path, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        topics = {c.topic: summary.schemas[c.schema_id].name for c in summary.channels.values()}
        metadata = {m.name: m.metadata for m in reader.iter_metadata()}
        for _, channel, message in reader.iter_messages():
            name = topics[channel.topic]
            if name == "foxglove.SceneUpdate":
                SceneUpdate.FromString(message.data)
            elif name == "osi3.SensorData":
                SensorData.FromString(message.data)
                assert message.log_time == message.publish_time
            elif name == "VisibilityRows":
                json.loads(message.data)
    for sensor in ("front", "roof", "radar"):
        assert topics[f"/visibility/ego_0/{sensor}/scene"] == "foxglove.SceneUpdate"
        assert topics[f"/visibility/ego_0/{sensor}/sensor_data"] == "osi3.SensorData"
    osi = metadata["net.asam.osi.trace"]
    assert osi["min_osi_version"] == "3.8.0" and set(osi) >= {"version", "max_osi_version", "max_protobuf_version"}


def test_the_input_channels_are_byte_for_byte_the_inputs(written) -> None:
    path, _, _ = written
    assert messages(path, ["ground_truth"]) == messages(MERGE, ["ground_truth"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        assert read_recording(path).table.equals(read_recording(MERGE).table)


def test_colours_labels_and_metadata_are_the_tables(written) -> None:
    path, _, table = written
    rows = {(r["frame"], r["idx"]): r for r in table.filter(pl.col("sensor") == "front").iter_rows(named=True)}
    times = dict(table.select("total_nanos", "frame").unique().iter_rows())
    checked = 0
    for _, log_time, _, data in messages(path, ["/visibility/ego_0/front/scene"]):
        frame = times[log_time]
        for entity in SceneUpdate.FromString(data).entities:
            idx = int(entity.id.split()[-1])
            meta = {kv.key: kv.value for kv in entity.metadata}
            colour = entity.cubes[0].color
            if idx == 0:
                assert (colour.r, colour.g, colour.b) == pytest.approx(
                    tuple(rgba(OKABE_ITO["vermillion"]).__getattribute__(c) for c in "rgb")
                )
                continue
            row = rows[(frame, idx)]
            want = rgba(visibility_colour(row["visibility"]), 0.9)
            assert (colour.r, colour.g, colour.b, colour.a) == pytest.approx((want.r, want.g, want.b, want.a))
            assert float(meta["visibility"]) == pytest.approx(row["visibility"], rel=1e-5, abs=1e-12)
            assert meta["status"] == row["status"] and meta["pixels"] == str(row["pixels"])
            assert entity.texts[0].text == f"{idx}: {row['visibility']:.0%}"
            checked += 1
    assert checked == len(rows)


def test_sensor_data_holds_what_the_table_calls_seen(written) -> None:
    path, traces, table = written
    times = dict(table.select("total_nanos", "frame").unique().iter_rows())
    for sensor in ("front", "roof", "radar"):
        seen = (
            table.filter((pl.col("sensor") == sensor) & pl.col("status").is_in(["visible", "partly_visible"]))
            .group_by("frame").agg(pl.col("idx").sort())
        )  # fmt: skip
        want = {f: set(i) for f, i in seen.iter_rows()}
        got = {}
        for _, log_time, _, data in messages(path, [f"/visibility/ego_0/{sensor}/sensor_data"]):
            message = SensorData.FromString(data)
            assert message.timestamp.seconds * 10**9 + message.timestamp.nanos == log_time
            ids = {o.header.ground_truth_id[0].value for o in message.moving_object}
            assert all(o.header.tracking_id.value == o.header.ground_truth_id[0].value for o in message.moving_object)
            if ids:
                got[times[log_time]] = ids
        assert got == want
    # the .osi traces: length-prefixed SensorData, one per frame, named after OSI's convention
    names = sorted(p.name for p in traces)
    protobuf = names[0].split("_")[3]
    assert [n.split("_", 1)[1] for n in names] == [
        f"sd_3.8.0_{protobuf}_201_ego0-{s}.osi" for s in ("front", "radar", "roof")
    ]
    for trace in traces:
        blob, at, count = trace.read_bytes(), 0, 0
        while at < len(blob):
            (n,) = struct.unpack_from("<I", blob, at)
            SensorData.FromString(blob[at + 4 : at + 4 + n])
            at, count = at + 4 + n, count + 1
        assert at == len(blob) and count == 201


def test_the_front_cameras_objects_are_in_its_frame(written) -> None:
    path, _, table = written
    frame30 = table.filter((pl.col("frame") == 30) & (pl.col("sensor") == "front"))
    log_time = frame30["total_nanos"][0]
    data = next(d for _, t, _, d in messages(path, ["/visibility/ego_0/front/sensor_data"]) if t == log_time)
    message = SensorData.FromString(data)
    assert message.mounting_position.position.x == 1.0 and message.sensor_id.value == 0
    r = read_recording(MERGE).table.filter(pl.col("frame") == 30)
    ego = r.filter(pl.col("idx") == 0).row(0, named=True)
    for item in message.moving_object:
        obj = r.filter(pl.col("idx") == item.header.ground_truth_id[0].value).row(0, named=True)
        # the sensor 1 m ahead of the ego's centre, 1.4 m above its ground, looking along its heading
        c, s = math.cos(ego["yaw"]), math.sin(ego["yaw"])
        dx, dy = obj["x"] - ego["x"] - c, obj["y"] - ego["y"] - s
        assert item.base.position.x == pytest.approx(c * dx + s * dy, abs=1e-9)
        assert item.base.position.y == pytest.approx(-s * dx + c * dy, abs=1e-9)
        assert item.base.position.z == pytest.approx(obj["z"] - (ego["z"] - ego["height"] / 2 + 1.4), abs=1e-9)
        turned = (obj["yaw"] - ego["yaw"] + math.pi) % (2 * math.pi) - math.pi
        assert item.base.orientation.yaw == pytest.approx(turned, abs=1e-9)
        assert item.base.dimension.length == pytest.approx(obj["length"])


def test_omega_prime_reads_the_written_file(written) -> None:
    import omega_prime

    path, _, _ = written
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        ours = omega_prime.Recording.from_file(str(path))
        theirs = omega_prime.Recording.from_file(str(MERGE))
    assert ours._df.select("idx", "total_nanos", "x", "y").equals(theirs._df.select("idx", "total_nanos", "x", "y"))


def test_bad_calls_are_told(tmp_path, written) -> None:
    path, _, table = written
    with pytest.raises(ValueError, match="exists already"):
        write_mcap(MERGE, table, path, ego_idx=0, sensors=SENSORS)
    with pytest.raises(ValueError, match="Sensor objects of the table's sensors"):
        write_mcap(MERGE, table, tmp_path / "a.mcap", ego_idx=0)
    flat = read_recording(MERGE).table.drop("height")
    plain = get_visibility_df(flat, 0, progress=False)
    with pytest.warns(VisibilityInputWarning) as caught:
        out = write_mcap(flat, plain, tmp_path / "b.mcap", ego_idx=0, osi_traces=False)
    words = [str(w.message) for w in caught]
    assert any("visibility channels only" in w for w in words) and sum("drawn flat" in w for w in words) == 1
    topics = {t for t, *_ in messages(out[0])}
    assert "ground_truth" not in topics and "/visibility/ego_0/scene" in topics
    assert not list(tmp_path.glob("*.part"))


def test_the_observer_has_a_frame_to_follow_and_the_layout_names_the_files_channels(written) -> None:
    from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform

    from omega_prime_visibility.export.layout import lichtblick_layout

    path, _, _ = written
    transforms = [FrameTransform.FromString(d) for *_, d in messages(path, ["/tf"])]
    ego = read_recording(MERGE).table.filter(pl.col("idx") == 0).sort("frame")
    assert len(transforms) == ego.height and {t.child_frame_id for t in transforms} == {"ego_0"}
    assert [t.translation.x for t in transforms] == pytest.approx(ego["x"].to_list())
    topics = {t for t, *_ in messages(path)}
    layout = lichtblick_layout(0, sensor="front", target=2)
    assert set(layout["configById"]["3D!answer"]["topics"]) - {"/visibility/static_occluders"} <= topics
    assert layout["configById"]["3D!answer"]["followTf"] == "ego_0"
    plotted = layout["configById"]["Plot!visibility"]["paths"][0]["value"].split(".rows")[0]
    assert plotted in topics


def test_the_command_line_and_batch_write_it(tmp_path) -> None:
    from typer.testing import CliRunner

    from omega_prime_visibility import run_batch
    from omega_prime_visibility.batch.campaign import campaign_statistics
    from omega_prime_visibility.cli import app

    out = tmp_path / "vis.mcap"
    result = CliRunner().invoke(app, ["run", str(MERGE), "--ego", "0", "-o", str(out), "--no-progress"])
    assert result.exit_code == 0, result.output
    assert "wrote" in result.output and out.is_file() and len(list(tmp_path.glob("*_sd_*.osi"))) == 1
    again = CliRunner().invoke(app, ["run", str(MERGE), "--ego", "0", "-o", str(out), "--no-progress"])
    assert again.exit_code == 2 and "exists already" in again.output
    summary = run_batch(MERGE, tmp_path / "batch", ego=0, mcap=True, workers=1, progress=False)
    assert summary["status"].to_list() == ["done"]
    drawn = tmp_path / "batch" / "highway_merge.mcap.mcap"
    assert messages(drawn, ["ground_truth"]) == messages(MERGE, ["ground_truth"])
    assert campaign_statistics(tmp_path / "batch")["by_recording"]["mcap"].to_list() == [str(drawn.resolve())]


def test_static_occluders_are_drawn_once_extruded_to_their_heights(tmp_path) -> None:
    import shapely

    wall = shapely.box(60, -7, 140, -5.4)
    table = get_visibility_df(MERGE, 0, [wall], progress=False)
    out = write_mcap(MERGE, table, tmp_path / "s.mcap", ego_idx=0, static_occluder_polys=[wall],
                     static_occluder_heights=[1.2], osi_traces=False)  # fmt: skip
    drawn = messages(out[0], ["/visibility/static_occluders"])
    assert len(drawn) == 1
    entity = SceneUpdate.FromString(drawn[0][3]).entities[0]
    heights = {round(p.z, 9) for t in entity.triangles for p in t.points}
    assert heights == {0.0, 1.2} and entity.triangles[0].color.a > 0
    # the top face tiles the footprint: its triangles' areas add up to the wall's
    top = [p for t in entity.triangles for p in t.points if p.z == 1.2][: 2 * 3]
    area = sum(shapely.Polygon([(p.x, p.y) for p in top[k : k + 3]]).area for k in range(0, len(top), 3))
    assert area == pytest.approx(wall.area)


def test_a_2d_answer_draws_the_region_the_observer_sees(tmp_path) -> None:
    import shapely

    from omega_prime_visibility import visible_area

    table = get_visibility_df(MERGE, 0, progress=False)
    out = write_mcap(MERGE, table, tmp_path / "r.mcap", ego_idx=0, osi_traces=False)
    times = dict(table.select("total_nanos", "frame").unique().iter_rows())
    for _, log_time, _, data in messages(out[0], ["/visibility/ego_0/scene"])[::50]:
        region = [e for e in SceneUpdate.FromString(data).entities if e.id == "seen region"]
        assert len(region) == 1
        points = [(p.x, p.y) for p in region[0].triangles[0].points]
        area = sum(shapely.Polygon(points[k : k + 3]).area for k in range(0, len(points), 3))
        assert area == pytest.approx(visible_area(MERGE, 0, times[log_time]).area, rel=1e-9)


def test_the_column_wise_metadata_is_the_rows_own_and_long_values_fall_back() -> None:
    from foxglove_schemas_protobuf.SceneEntity_pb2 import SceneEntity

    from omega_prime_visibility.export.scene import metadata_column, row_metadata

    rows = pl.DataFrame(
        {"idx": [3, 4], "visibility": [0.123456789, float("nan")], "occluder_idxs": [[1, 2], list(range(60))],
         "status": ["partly_visible", "occluded"]}
    )  # fmt: skip
    names = rows.columns
    column = rows.select(metadata_column(rows.schema, names)).to_series().to_list()
    assert column[1] is None  # 60 idx make a value longer than one varint byte: written in Python instead
    for k, row in enumerate(rows.to_dicts()):
        python = row_metadata(
            {**row, "visibility": None if row["visibility"] != row["visibility"] else row["visibility"]}
        )
        for data in filter(None, (python, None if column[k] is None else column[k].encode())):
            meta = {kv.key: kv.value for kv in SceneEntity.FromString(data).metadata}
            assert meta["idx"] == str(row["idx"]) and meta["status"] == row["status"]
            assert meta["occluder_idxs"] == ", ".join(map(str, row["occluder_idxs"]))
            assert meta["visibility"] == ("0.123457" if k == 0 else "")
