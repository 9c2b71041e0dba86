"""An MCAP of the answer, to scrub through in Lichtblick (or Foxglove) beside the recording, and OSI SensorData of
what each sensor sees.

:func:`write_mcap` writes a new file (MCAP files cannot be appended to): the input recording's own records copied
unchanged (its schemas, channels, every message's bytes and times, its attachments and metadata; so it opens as
the same recording in omega-prime, in this package's reader and in the viewer), and, per observer (and sensor,
where there are sensors):

- ``/visibility/ego_<idx>[/<sensor>]/scene``: a ``foxglove.SceneUpdate`` per frame (:mod:`.scene`), with the region
  the observer sees as triangles on the ground (2D);
- ``/visibility/ego_<idx>[/<sensor>]/table``: the frame's rows as JSON (schema ``VisibilityRows``),
  for the plot and table panels: ``.rows[:]{idx==3}.visibility`` plots target 3's visibility over time;
- ``/visibility/ego_<idx>[/<sensor>]/sensor_data``: an ``osi3.SensorData`` per frame (:mod:`.sensordata`), an OSI
  channel of OSI's multi-channel trace format (its schema a FileDescriptorSet with imports, channel metadata
  ``net.asam.osi.trace.channel.osi_version`` and ``...protobuf_version``, ``log_time = publish_time`` = the
  OSI timestamp), with the file's ``net.asam.osi.trace`` metadata record;
- ``/visibility/static_occluders``: the static occluders extruded, once;
- ``/tf``: a ``foxglove.FrameTransform`` per frame and observer, from ``global`` to ``ego_<idx>`` (its box's
  centre and heading), so that the 3D panel can follow the observer.

Every message's ``log_time`` is its frame's ``total_nanos``: the OSI timestamp of the recording's ground truth, so
the viewer's time line lines them up. Beside the MCAP, each SensorData stream is also written as an ``.osi`` trace
named after OSI's convention (``<time>_sd_<osi>_<protobuf>_<frames>_<name>.osi``).
"""

from __future__ import annotations

import json
import os
import warnings
from collections.abc import Sequence
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

import google.protobuf
import numpy as np
import polars as pl
from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from mcap.reader import make_reader
from mcap.writer import CompressionType, Writer
from mcap_protobuf.schema import register_schema
from osi3.osi_sensordata_pb2 import SensorData

from ..inputs.objects import VisibilityInputWarning
from ..inputs.scene import as_lazy
from ..inputs.sensors import Sensor
from .scene import FrameRows, frame_update, metadata_column, observer_frame, region_entity, row_metadata, static_update
from .sensordata import OSI_VERSION, osi_trace_bytes, sensor_data

PROTOBUF_VERSION = google.protobuf.__version__
BOX = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")
SEEN = ("visible", "partly_visible")
ROWS_SCHEMA = {
    "title": "VisibilityRows",
    "description": "One frame of a visibility table: its rows (the table's columns by name).",
    "type": "object",
    "properties": {
        "frame": {"type": "integer"},
        "total_nanos": {"type": "integer"},
        "ego": {"type": "integer"},
        "sensor": {"type": ["string", "null"]},
        "rows": {"type": "array", "items": {"type": "object"}},
    },
}


def _objects(recording: Any) -> pl.DataFrame:
    lazy = as_lazy(recording)
    names = lazy.collect_schema().names()
    if "height" not in names:
        warnings.warn("the recording gives no heights: boxes are drawn flat", VisibilityInputWarning, stacklevel=3)
    fill = {"z": 0.0, "height": 0.0, "roll": 0.0, "pitch": 0.0}
    columns = [pl.col(c).cast(pl.Float64) if c in names else pl.lit(fill[c]).alias(c) for c in BOX]
    return lazy.select(pl.col("frame").cast(pl.Int64), pl.col("total_nanos").cast(pl.Int64),
                       pl.col("idx").cast(pl.Int64), *columns).collect().sort("frame", "idx")  # fmt: skip


def _views(table: pl.DataFrame, ego_idx: int | None) -> pl.DataFrame:
    if "idx_ego" not in table.columns:
        if ego_idx is None:
            raise ValueError("write_mcap needs ego_idx: the table has no idx_ego column")
        table = table.with_columns(idx_ego=pl.lit(int(ego_idx), dtype=pl.Int64))
    if "sensor" not in table.columns:
        table = table.with_columns(sensor=pl.lit(None, dtype=pl.String))
    return table


def _copy_input(source: Path, writer: Writer) -> tuple[dict[str, str] | None, int]:
    """Copy the input MCAP's records into ``writer`` (ids kept in order); its ``net.asam.osi.trace`` record (not
    copied: merged with ours) and its number of messages."""
    osi_record = None
    with open(source, "rb") as f:
        reader = make_reader(f, validate_crcs=True)
        summary = reader.get_summary()
        schemas = {} if summary is None else summary.schemas
        channels = {} if summary is None else summary.channels
        schema_ids = {0: 0}
        for sid in sorted(schemas):
            s = schemas[sid]
            schema_ids[sid] = writer.register_schema(s.name, s.encoding, s.data)
        channel_ids = {}
        for cid in sorted(channels):
            c = channels[cid]
            channel_ids[cid] = writer.register_channel(c.topic, c.message_encoding, schema_ids[c.schema_id], c.metadata)
        count = 0
        for _, channel, message in reader.iter_messages(log_time_order=False):
            writer.add_message(channel_ids[channel.id], message.log_time, message.data, message.publish_time,
                               message.sequence)  # fmt: skip
            count += 1
        for attachment in reader.iter_attachments():
            writer.add_attachment(attachment.create_time, attachment.log_time, attachment.name,
                                  attachment.media_type, attachment.data)  # fmt: skip
        for record in reader.iter_metadata():
            if record.name == "net.asam.osi.trace":
                osi_record = dict(record.metadata)
            else:
                writer.add_metadata(record.name, dict(record.metadata))
    return osi_record, count


def _semver(text: str) -> tuple[int, ...]:
    return tuple(int(p) for p in ([*text.split("."), "0", "0"])[:3] if p.isdigit()) or (0,)


def _osi_record(theirs: dict[str, str] | None) -> dict[str, str]:
    """The file's ``net.asam.osi.trace`` record: the input's, widened to the versions of the SensorData written."""
    ours = {"version": OSI_VERSION, "min_osi_version": OSI_VERSION, "max_osi_version": OSI_VERSION,
            "min_protobuf_version": PROTOBUF_VERSION, "max_protobuf_version": PROTOBUF_VERSION}  # fmt: skip
    if not theirs:
        return ours | {"creation_time": datetime.now(UTC).strftime("%Y-%m-%dT%H:%M:%SZ"),
                       "description": "visibility of the road users, by omega-prime-visibility"}  # fmt: skip
    out = dict(theirs)
    for key, pick in (("min_osi_version", min), ("max_osi_version", max), ("min_protobuf_version", min),
                      ("max_protobuf_version", max)):  # fmt: skip
        given = [v for v in (theirs.get(key), ours[key]) if v]
        out[key] = pick(given, key=_semver)
    out.setdefault("version", OSI_VERSION)
    return out


_NOT_IN_ROWS = frozenset(("frame", "total_nanos", "idx_ego", "sensor"))


def write_mcap(
    recording: Any,
    table: pl.DataFrame,
    output: str | os.PathLike,
    *,
    ego_idx: int | None = None,
    sensors: Sequence[Sensor] = (),
    static_occluder_polys: Sequence[Any] = (),
    static_occluder_heights: Sequence[float] | float | None = None,
    osi_traces: bool = True,
    region: bool | None = None,
) -> list[Path]:
    """Write the MCAP of the answer (see the module docstring) to ``output`` (a new ``.mcap`` path), and with
    ``osi_traces`` an ``.osi`` SensorData trace per view beside it; the paths written, the MCAP first.

    Parameters
    ----------
    recording : MCAP path, omega_prime.Recording or table
        What ``table`` was computed from; an MCAP path is copied into the output. A table in memory has no
        channels to copy: the file then holds the visibility channels only (a warning says so).
    table : polars.DataFrame
        :func:`~omega_prime_visibility.get_visibility_df`'s table (any mode, any observers and sensors).
    ego_idx : int, optional
        The observer, where the table has no ``idx_ego`` column.
    sensors : sequence of Sensor
        The sensors the table was computed with (their mounting goes into SensorData).
    static_occluder_polys, static_occluder_heights
        The static occluders drawn (footprints and tops, metres; none: 3 m).
    region : bool, optional
        Draw the region each observer (sensor) sees, as triangles on its ground; default: for a 2D table of one
        observer (a 3D table's targets are seen over what a region on the ground would call blocked).
    """
    output = Path(output)
    if output.exists():
        raise ValueError(f"{output} exists already: write_mcap writes a new file")
    if not output.parent.is_dir():
        raise ValueError(f"the folder {output.parent} does not exist")
    table = _views(table, ego_idx)
    by_name = {s.name: (k, s) for k, s in enumerate(sensors)}
    missing = sorted({s for s in table["sensor"].unique().to_list() if s is not None} - set(by_name))
    if missing:
        raise ValueError(f"write_mcap needs the Sensor objects of the table's sensors; missing: {missing}")
    source = Path(recording) if isinstance(recording, str | os.PathLike) else None
    if source is not None and source.suffix.lower() != ".mcap":
        source = None  # an OSI trace: nothing to copy
    if source is None:
        warnings.warn("the recording is not an MCAP file: the output holds the visibility channels only, not the "
                      "recording's own ground truth", VisibilityInputWarning, stacklevel=2)  # fmt: skip
    objects = _objects(recording)
    if region is None:
        region = "can_see" not in table.columns and table["idx_ego"].n_unique() <= 1
    regions = _regions(recording, table, by_name, static_occluder_polys, static_occluder_heights) if region else {}
    temporary = output.with_name(output.name + ".part")
    traces: dict[tuple[int, str | None], list[bytes]] = {}
    try:
        with open(temporary, "wb") as f:
            writer = Writer(f, compression=CompressionType.ZSTD)
            writer.start(profile="", library="omega-prime-visibility")
            theirs = _copy_input(source, writer)[0] if source is not None else None
            writer.add_metadata("net.asam.osi.trace", _osi_record(theirs))
            _write_answer(writer, objects, table, by_name, static_occluder_polys, static_occluder_heights, traces,
                          regions)  # fmt: skip
            writer.finish()
        temporary.replace(output)
    finally:
        temporary.unlink(missing_ok=True)
    written = [output]
    if osi_traces:
        stamp = datetime.now(UTC).strftime("%Y%m%dT%H%M%SZ")
        for (ego, sensor), messages in traces.items():
            name = f"ego{ego}" + ("" if sensor is None else f"-{sensor}")
            path = output.with_name(f"{stamp}_sd_{OSI_VERSION}_{PROTOBUF_VERSION}_{len(messages)}_{name}.osi")
            part = path.with_name(path.name + ".part")
            part.write_bytes(osi_trace_bytes(messages))
            part.replace(path)
            written.append(path)
    return written


def write_answer_mcap(
    path: Any, recording: Any, table: pl.DataFrame, output: Path, question: Any, osi_traces: bool = True
) -> list[Path]:
    """:func:`write_mcap` for a front end's question (a :class:`~omega_prime_visibility.Query`): its observer,
    its sensors (a layout fitted to the observer's size) and its static occluders; ``path`` is the recording's
    file (copied where it is an MCAP), ``recording`` what was read from it."""
    from ..query import resolve

    scene = resolve(question, recording)
    observers = scene.egos.tolist()
    sensors = scene.sensors
    if isinstance(sensors, dict):
        sensors = sensors[observers[0]] if len(sensors) == 1 else next(iter(sensors.values()))
    statics = list(question.static_occluders or ())
    source = path if isinstance(path, str | os.PathLike) and Path(path).suffix.lower() == ".mcap" else recording
    return write_mcap(source, table, output, ego_idx=observers[0] if len(observers) == 1 else None,
                      sensors=tuple(sensors or ()), static_occluder_polys=statics,
                      static_occluder_heights=question.static_heights, osi_traces=osi_traces)  # fmt: skip


def _regions(recording, table, by_name, statics, heights) -> dict:
    """``{(ego, sensor): {frame: outlines}}`` of every view of the table (:func:`..analysis.area.visible_outlines`)."""
    from ..analysis.area import visible_outlines

    out = {}
    for ego, sensor in table.select("idx_ego", "sensor").unique().rows():
        view = None if sensor is None else [by_name[sensor][1]]
        out[(ego, sensor)] = dict(visible_outlines(recording, int(ego), view, list(statics) or None,
                                                  static_occluder_heights=heights))  # fmt: skip
    return out


def _write_answer(writer, objects, table, by_name, statics, heights, traces, regions) -> None:
    """The visibility channels, frame by frame."""
    scene_schema = register_schema(writer, SceneUpdate)
    transform_channel = writer.register_channel("/tf", "protobuf", register_schema(writer, FrameTransform))
    sensor_schema = register_schema(writer, SensorData)
    rows_schema = writer.register_schema("VisibilityRows", "jsonschema", json.dumps(ROWS_SCHEMA).encode())
    views = table.select("idx_ego", "sensor").unique(maintain_order=True).sort("idx_ego", "sensor").rows()
    channels = {}
    osi_meta = {"net.asam.osi.trace.channel.osi_version": OSI_VERSION,
                "net.asam.osi.trace.channel.protobuf_version": PROTOBUF_VERSION}  # fmt: skip
    for ego, sensor in views:
        base = f"/visibility/ego_{ego}" + ("" if sensor is None else f"/{sensor}")
        about = f"what {'observer ' + str(ego) if sensor is None else sensor + ' of observer ' + str(ego)} sees"
        channels[(ego, sensor)] = (
            writer.register_channel(f"{base}/scene", "protobuf", scene_schema),
            writer.register_channel(f"{base}/table", "json", rows_schema),
            writer.register_channel(
                f"{base}/sensor_data",
                "protobuf",
                sensor_schema,
                osi_meta | {"net.asam.osi.trace.channel.description": about},
            ),
        )
        traces[(ego, sensor)] = []
    if statics:
        first = int(objects["total_nanos"].min()) if objects.height else 0
        tops = np.broadcast_to(np.asarray(3.0 if heights is None else heights, dtype=np.float64), (len(statics),))
        channel = writer.register_channel("/visibility/static_occluders", "protobuf", scene_schema)
        writer.add_message(channel, first, static_update(first, list(statics), tops).SerializeToString(), first)
    parts = _prepared(table).partition_by("frame", "idx_ego", "sensor", as_dict=True)
    for (frame,), frame_objects in objects.partition_by("frame", as_dict=True, maintain_order=True).items():
        nanos = int(frame_objects["total_nanos"][0])
        idx = frame_objects["idx"].to_numpy()
        boxes = frame_objects.select(BOX).to_numpy()
        for ego in sorted({ego for ego, _ in channels}):  # each observer's own frame, for the viewer to follow
            if ego in idx:
                pose = observer_frame(nanos, ego, boxes[int(np.flatnonzero(idx == ego)[0])])
                writer.add_message(transform_channel, nanos, pose.SerializeToString(), nanos)
        for (ego, sensor), (scene_id, table_id, data_id) in channels.items():
            if ego not in idx:
                continue
            rows, json_rows, seen_idx = _view_rows(parts.get((frame, ego, sensor)))
            scene = frame_update(nanos, boxes, idx, ego, rows)
            seen_region = regions.get((ego, sensor), {}).get(frame)
            ego_box = boxes[int(np.flatnonzero(idx == ego)[0])]
            if seen_region is not None:
                scene += region_entity(nanos, seen_region, float(ego_box[2] - ego_box[5] / 2))
            writer.add_message(scene_id, nanos, scene, nanos)
            head = json.dumps({"frame": int(frame), "total_nanos": nanos, "ego": int(ego), "sensor": sensor})
            message = head[:-1] + ', "rows": [' + ",".join(json_rows) + "]}"
            writer.add_message(table_id, nanos, message.encode(), nanos)
            seen = [(i, boxes[k]) for k, i in enumerate(idx.tolist()) if i in seen_idx]
            k, s = by_name.get(sensor, (0, None))
            data = sensor_data(nanos, ego, ego_box, s, k, seen).SerializeToString()
            writer.add_message(data_id, nanos, data, nanos)
            traces[(ego, sensor)].append(data)


def _prepared(table: pl.DataFrame) -> pl.DataFrame:
    """The table with each row's entity metadata (``_meta``, :func:`.scene.metadata_column`) and JSON (``_json``)
    built column-wise, once."""
    shown = [c for c in table.columns if c not in _NOT_IN_ROWS]
    schema = table.schema
    floats = [c for c in shown if schema[c].is_float()]
    clean = table.with_columns(pl.col(floats).fill_nan(None)) if floats else table
    return clean.with_columns(_meta=metadata_column(schema, shown), _json=pl.struct(shown).struct.json_encode())


def _view_rows(part: pl.DataFrame | None) -> tuple[FrameRows, list[str], set[int]]:
    """One view's rows of one frame: what the scene draws, the rows' JSON, and the idx the sensor sees."""
    if part is None or part.is_empty():
        return FrameRows(np.zeros(0, dtype=np.int64), np.zeros(0), [], set()), [], set()
    idx = part["idx"].to_numpy()
    visibility = part["visibility"].fill_null(float("nan")).to_numpy()
    metadata = part["_meta"].to_list()
    if any(m is None for m in metadata):  # a value too long for the column-wise path
        shown = [c for c in part.columns if c not in _NOT_IN_ROWS and not c.startswith("_")]
        full = part.select(shown).to_dicts()
        metadata = [row_metadata(full[k]) if m is None else m.encode() for k, m in enumerate(metadata)]
    else:
        metadata = [m.encode() for m in metadata]
    hidden = visibility < 1.0
    hiding = {o for lst in part["occluder_idxs"].filter(pl.Series(hidden)).to_list() for o in lst or []}
    if "status" in part.columns:
        seen = part["status"].cast(pl.String).is_in(list(SEEN)).to_numpy()
    else:
        seen = visibility > 0.0
    return FrameRows(idx, visibility, metadata, hiding), part["_json"].to_list(), set(idx[seen].tolist())
