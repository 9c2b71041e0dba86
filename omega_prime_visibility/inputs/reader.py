"""Reading omega-prime MCAP files straight into the object table, with ``mcap`` and ASAM's ``osi-python``.

omega-prime's ``Recording.from_file`` decodes every object through Python classes and builds the table row by row
(about 80 us a row). :func:`read_mcap` decodes the same ``osi3.GroundTruth`` (or ``osi3.SensorView``) messages
with the upb-backed protobuf classes and builds the columns at once, giving exactly omega-prime's table for the
columns the package uses (same rows, order, dtypes and values: ``total_nanos, idx, x, y, z, vel_*, acc_*,
length, width, height, roll, pitch, yaw, type, role, subtype, frame, vel, acc, polygon``), the host vehicle, and
the map, which is read through omega-prime the first time it is asked for (pictures, map occluders).

What it does not do it leaves to omega-prime (:class:`NotOurs`): recordings with a geographic projection (a
``proj_string``, a frame offset, or a map with a ``geoReference``), which omega-prime converts into the map's
frame; files without OSI ground truth; anything it cannot decode. OSI traces (``.osi``) are read the same way by
:mod:`.osi_trace` into the same :class:`TraceRecording`.
"""

from __future__ import annotations

import functools
import json
import os
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import polars as pl

from .. import _compiled

GROUND_TRUTH, SENSOR_VIEW = "osi3.GroundTruth", "osi3.SensorView"
MAP_TOPICS = ("/ground_truth_map", "ground_truth_map")
"""The topics omega-prime writes and reads an OpenDRIVE map on (``osi3.MapAsamOpenDrive``)."""

OMEGA_PRIME_OPTIONS = {"compute_polygons": True}
"""What :func:`~.io.read_recording` passes to omega-prime's ``Recording.from_file`` (which hands it on to the map
readers: the map read here is the one it reads)."""


READER = "reader"
"""The reader's name for ``omega-prime-visibility compile`` and its compiled marker."""
WHAT = "the MCAP reader's kernels"


class NotOurs(Exception):
    """The file is one this reader leaves to omega-prime (the reason says why)."""


@dataclass(eq=False)
class TraceRecording:
    """A recording read by :func:`read_mcap` (or :func:`.osi_trace.read_osi`): what the package uses of an
    ``omega_prime.Recording``.

    Attributes
    ----------
    table : polars.DataFrame
        The moving objects, as omega-prime's ``Recording._df`` holds them but without shapely outlines: the box
        corners are its ``coords`` column (the same numbers); ``_df`` adds the ``polygon`` column when first
        asked for (the engines read the corners and never need it).
    host_vehicle_idx : int or None
    path : Path
        The file it was read from; its map is read from there when first asked for.
    odr_xml : str or None
        The OpenDRIVE map the file carries, if any.

    Anything else an ``omega_prime.Recording`` offers (its methods and attributes) is that of
    :meth:`to_omega_prime`, built on first use.
    """

    table: pl.DataFrame
    host_vehicle_idx: int | None
    path: Path
    odr_xml: str | None = None
    map_name: str | None = None
    _map: Any = field(default=None, repr=False)
    _map_read: bool = field(default=False, repr=False)
    _with_polygons: pl.DataFrame | None = field(default=None, repr=False)
    _omega_prime: Any = field(default=None, repr=False)
    first_ground_truth: bytes | None = field(default=None, repr=False)
    _centre_lines: Any = field(default=None, repr=False)

    def __getattr__(self, name: str) -> Any:
        """omega-prime's own attributes and methods (``plot``, ``to_mcap``, ...), from :meth:`to_omega_prime`.

        Never for a name of this class (a property such as :attr:`map` that fails inside lands here: its own
        error is the one to see), nor for private names (copy's and pickle's probes, a field not set yet); where
        omega-prime cannot build its ``Recording``, an ``AttributeError`` saying why (``hasattr`` is False)."""
        if hasattr(type(self), name):  # a property of ours that failed: raise its own error again, not ours
            return object.__getattribute__(self, name)
        if name.startswith("_") or name in self.__dataclass_fields__:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        if self._omega_prime is None:
            try:
                self._omega_prime = self.to_omega_prime()
            except Exception as error:  # omega-prime's own checks of the table raise many kinds
                raise AttributeError(
                    f"{name!r}: omega-prime could not build its Recording of {self.path.name} ({error})"
                ) from error
        return getattr(self._omega_prime, name)

    @property
    def _df(self) -> pl.DataFrame:
        """omega-prime's table, with the ``polygon`` column of shapely outlines (built on first use)."""
        if self._with_polygons is None:
            import shapely

            corners = self.table["coords"].to_numpy().reshape(self.table.height, 5, 2)
            polygons = pl.Series("polygon", shapely.polygons(corners), dtype=pl.Object)
            self._with_polygons = self.table.with_columns(polygons)
        return self._with_polygons

    @_df.setter
    def _df(self, value: pl.DataFrame) -> None:  # (omega-prime's MetricManager sets it)
        self.table = value
        self._with_polygons = value if "polygon" in value.columns else None
        self._omega_prime = None  # built again from the new table when next asked for

    @property
    def df(self) -> pl.DataFrame:
        return self._df

    @property
    def map(self) -> Any:
        """The recording's map as omega-prime reads it (its OpenDRIVE map, or the lanes of its ground truth), or
        None; read on first use, so a table that needs no map never imports omega-prime."""
        if not self._map_read:
            self._map = self._read_map()
            self._map_read = True
        return self._map

    @map.setter
    def map(self, value: Any) -> None:
        self._map, self._map_read = value, True

    def _read_map(self) -> Any:
        from omega_prime.map_odr import MapOdr

        if self.odr_xml is not None:
            return MapOdr.create(odr_xml=self.odr_xml, name=self.map_name or "")
        from omega_prime.recording import MAP_CLASSES

        for map_class in MAP_CLASSES:  # as omega-prime's from_file does, its failures unsaid
            if self.path.suffix in map_class._supported_file_suffixes:
                try:
                    road_map = map_class.from_file(self.path, parse_map=False, **OMEGA_PRIME_OPTIONS)
                except Exception:  # omega-prime's readers raise many kinds; the next one tries
                    continue
                if road_map is not None:
                    return road_map
        return None

    def picture_lanes(self) -> Any:
        """The lanes a picture draws: the map's (:attr:`map`), but where the file carries no OpenDRIVE map and
        the map is not read yet, the centre lines of its first ground truth decoded without omega-prime, once (see
        :mod:`.centrelines`). They are the lanes omega-prime's map has: read with ``compute_polygons=True``, as
        :data:`OMEGA_PRIME_OPTIONS` and ``Recording.from_file`` read it, its ``MapOsi`` (lane polygons) always
        fails (its ``create`` takes no such keyword) and ``MapOsiCenterline`` is taken."""
        if self._map_read or self.odr_xml is not None or self.first_ground_truth is None:
            return self.map
        if self._centre_lines is None:
            from .centrelines import centre_lines

            self._centre_lines = centre_lines(self.first_ground_truth)
        return self._centre_lines

    def to_omega_prime(self) -> Any:
        """This recording as an ``omega_prime.Recording`` (for omega-prime's own metrics)."""
        import omega_prime

        keep = [c for c in self.table.columns if c not in ("frame", "coords", "vel", "acc")]
        return omega_prime.Recording(self.table.select(keep), map=self.map, host_vehicle_idx=self.host_vehicle_idx)


def read_mcap(path: str | os.PathLike) -> TraceRecording:
    """The recording in the MCAP file ``path``, decoded with ``osi-python``.

    Raises
    ------
    NotOurs
        For a file omega-prime should read instead (see the module's docstring).
    """
    from mcap.reader import make_reader

    path = Path(path)
    with open(path, "rb") as f:
        reader = make_reader(f)
        summary = reader.get_summary()
        if summary is None:
            raise NotOurs("the file has no summary")
        topics = {SENSOR_VIEW: [], GROUND_TRUTH: []}
        map_topics = []
        for channel in summary.channels.values():
            schema = summary.schemas.get(channel.schema_id)
            name = getattr(schema, "name", None)
            if channel.message_encoding != "protobuf" or schema is None:
                continue
            if name in topics:
                topics[name].append(channel.topic)
            elif channel.topic in MAP_TOPICS and name == "osi3.MapAsamOpenDrive":
                map_topics.append(channel.topic)
                map_class = _class_of(schema)
        kind = GROUND_TRUTH if topics[GROUND_TRUTH] else SENSOR_VIEW if topics[SENSOR_VIEW] else None
        if kind is None:
            raise NotOurs("no osi3.GroundTruth or osi3.SensorView channel")
        payloads = [message.data for _, _, message in reader.iter_messages(topics=topics[kind])]
        odr_xml = map_name = None
        if map_topics:
            for _, _, message in reader.iter_messages(topics=map_topics):
                road_map = map_class.FromString(message.data)
                odr_xml, map_name = road_map.open_drive_xml_content, road_map.map_reference
                break
    if odr_xml is not None and _geo_reference(odr_xml):
        raise NotOurs("its OpenDRIVE map has a geoReference (omega-prime projects the objects onto it)")
    if kind == SENSOR_VIEW:  # the ground truth inside each view, as omega-prime takes it
        message_class = _message_class(kind)  # (ground truth is decoded by the package's own reader)
        views = [message_class.FromString(data) for data in payloads]
        payloads = [v.global_ground_truth.SerializeToString() for v in views if v.HasField("global_ground_truth")]
    if not payloads:
        raise NotOurs("no ground truth messages")
    df, host = decode_table(payloads)
    return TraceRecording(df, host, path, odr_xml, map_name, first_ground_truth=payloads[0])


def _class_of(schema: Any) -> type:
    """The message class of an MCAP protobuf schema, built from the descriptors the file carries (omega-prime's
    ``osi3.MapAsamOpenDrive`` is not among ASAM's generated classes)."""
    from google.protobuf import descriptor_pb2, descriptor_pool, message_factory

    pool = descriptor_pool.DescriptorPool()
    for file in descriptor_pb2.FileDescriptorSet.FromString(schema.data).file:
        pool.Add(file)
    return message_factory.GetMessageClass(pool.FindMessageTypeByName(schema.name))


def _message_class(kind: str) -> type:
    if kind == GROUND_TRUTH:
        from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]

        return GroundTruth
    from osi3.osi_sensorview_pb2 import SensorView  # type: ignore[import-not-found]

    return SensorView


def _geo_reference(odr_xml: str) -> bool:
    """Whether an OpenDRIVE map's header names a geographic projection (a non-empty ``geoReference``)."""
    header = odr_xml[: odr_xml.find("</header>") + 1] if "</header>" in odr_xml else odr_xml[:20000]
    found = re.search(r"<geoReference[^>]*>(.*?)</geoReference>", header, re.S)
    return found is not None and bool(re.sub(r"<!\[CDATA\[|\]\]>", "", found.group(1)).strip())


def decode_table(messages: list[bytes], projected: bool = True) -> tuple[pl.DataFrame, int | None]:
    """omega-prime's moving-object table of serialised ``osi3.GroundTruth`` messages, and the host vehicle the
    first one names (None if none), decoded by :mod:`.osi_wire`.

    ``projected`` False: omega-prime will not project these messages whatever projection they carry (it projects
    only onto an OpenDRIVE map: an OSI trace read without one keeps its coordinates).

    Raises
    ------
    NotOurs
        When a message carries a projection (``proj_string``, ``proj_frame_offset``), which omega-prime converts
        (unless ``projected`` is False), or is no valid ``GroundTruth``.
    """
    from . import osi_wire

    sizes = np.fromiter((len(m) for m in messages), dtype=np.int64, count=len(messages))
    ends = np.cumsum(sizes)
    starts = ends - sizes
    buf = np.frombuffer(b"".join(messages), dtype=np.uint8)
    numbers, schema = remembered_descriptors()
    beat = None
    if _compiled.progress.ANNOUNCE and _compiled.has_run(READER) is False:
        print(f"omega-prime-visibility: compiling {WHAT}, once per version of the package", file=sys.stderr)
        beat = _compiled.Heartbeat(WHAT).start()
    try:
        invalid = osi_wire.valid_messages(buf, starts, ends, schema)
        untimed = osi_wire.lacking(buf, starts, ends, numbers[osi_wire.GT_TIMESTAMP]) if invalid < 0 else -1
        counts = osi_wire.object_counts(buf, starts, ends, numbers)
        offsets = np.concatenate([[0], np.cumsum(np.maximum(counts, 0))]).astype(np.int64)
        ints, floats, flags, bad = osi_wire.decode_objects(buf, starts, ends, numbers, offsets)
    finally:
        if beat is not None:
            beat.stop()
    _compiled.mark_compiled(READER)
    if invalid >= 0:  # protobuf refuses it: omega-prime's reader says so in its words
        raise NotOurs(f"message {invalid} is no valid protobuf message (as osi3.GroundTruth)")
    if untimed >= 0:  # a ground truth without its time (cut short?): omega-prime's reader decides
        raise NotOurs(f"message {untimed} has no timestamp")
    if (counts < 0).any():
        raise NotOurs(f"message {int(np.argmax(counts < 0))} is no valid osi3.GroundTruth")
    if bad >= 0:
        raise NotOurs(f"message {bad} is no valid osi3.GroundTruth")
    if projected and flags[:, 2].any():
        raise NotOurs("a ground truth message carries a projection")
    columns = {name: ints[:, k] for k, name in enumerate(osi_wire.INTS[:2])}
    columns |= {name: floats[:, k] for k, name in enumerate(osi_wire.FLOATS)}
    columns |= {name: ints[:, k + 2] for k, name in enumerate(osi_wire.INTS[2:])}
    df = pl.DataFrame(columns).sort(["total_nanos", "idx"])
    host = int(flags[0, 1]) if len(flags) and flags[0, 0] else None
    return _as_omega_prime(df), host


def _as_omega_prime(df: pl.DataFrame) -> pl.DataFrame:
    """The columns omega-prime's ``Recording`` adds: ``frame`` (UInt32, the rank of the time), the norms ``vel``
    and ``acc``, and ``coords``, the box outline (1 x 5 corners, x and y), computed with the expressions of
    omega-prime's ``bbx_to_polygon``, so that the numbers are the same to the bit."""
    df = df.with_columns(
        (pl.col("total_nanos").rank("dense") - 1).cast(pl.UInt32).alias("frame"),
        (pl.col("vel_x") ** 2 + pl.col("vel_y") ** 2).sqrt().alias("vel"),
        (pl.col("acc_x") ** 2 + pl.col("acc_y") ** 2).sqrt().alias("acc"),
    )
    if df.height == 0:  # (reshaping nothing is refused)
        return df.with_columns(pl.Series("coords", [], dtype=pl.Array(pl.Float64, (1, 5, 2))))
    # omega-prime's expressions, the sine and cosine from polars, the arithmetic in numpy (the same operations on
    # the same numbers; polars' nested lists took a third of a second on 150,000 rows)
    turn = df.select(pl.col("yaw").cos().alias("cos"), pl.col("yaw").sin().alias("sin"))
    cos, sin = turn["cos"].to_numpy(), turn["sin"].to_numpy()
    half_length, half_width = df["length"].to_numpy() / 2, df["width"].to_numpy() / 2
    dxl, dxw, dyl, dyw = half_length * cos, half_width * sin, half_length * sin, half_width * cos
    corners = [
        (dxl - dxw, dyl + dyw),
        (dxl + dxw, dyl - dyw),
        (-dxl + dxw, -dyl - dyw),
        (-dxl - dxw, -dyl + dyw),
        (dxl - dxw, dyl + dyw),
    ]
    x, y = df["x"].to_numpy(), df["y"].to_numpy()
    ring = np.empty((df.height, 1, 5, 2))
    for k, (dx, dy) in enumerate(corners):
        ring[:, 0, k, 0] = x + dx
        ring[:, 0, k, 1] = y + dy
    return df.with_columns(pl.Series("coords", ring, dtype=pl.Array(pl.Float64, (1, 5, 2))))


@functools.cache
def remembered_descriptors() -> tuple[np.ndarray, np.ndarray]:
    """:func:`.osi_wire.field_numbers` and :func:`.osi_wire.message_schema`, read from osi-python's descriptors
    once per version of osi-python (and of the kernels' sources) and remembered beside the kernels' cache
    (importing the descriptors is 20 ms of a short call).

    >>> from omega_prime_visibility.inputs.osi_wire import field_numbers, message_schema
    >>> numbers, schema = remembered_descriptors()
    >>> bool((numbers == field_numbers()).all()), bool((schema == message_schema()).all())
    (True, True)
    """
    import osi3  # type: ignore[import-not-found]  (its version only: quick)

    from .osi_wire import FIELDS, field_numbers, message_schema

    # (per version of osi-python and of the package's kernels' sources, which read them)
    memo = _compiled.cache_base() / "osi-descriptors" / f"{osi3.__version__}-{_compiled.remembered_sources_key()}.json"
    try:
        known = json.loads(memo.read_text(encoding="ascii"))
        numbers, shape, entries = np.array(known["numbers"]), tuple(known["shape"]), np.array(known["schema"])
        if known["fields"] == list(FIELDS) and numbers.shape == (len(FIELDS),) and numbers.dtype == np.int64:
            schema = np.full(shape, -1, dtype=np.int64)
            schema[entries[:, 0], entries[:, 1]] = entries[:, 2]
            return numbers, schema
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError, IndexError):
        pass
    numbers, schema = field_numbers(), message_schema()
    entries = np.argwhere(schema >= 0)
    entries = np.column_stack([entries, schema[schema >= 0]]).tolist()
    known = {"fields": list(FIELDS), "numbers": numbers.tolist(), "shape": list(schema.shape), "schema": entries}
    try:
        memo.parent.mkdir(parents=True, exist_ok=True)
        partial = memo.with_name(f"{memo.name}.{os.getpid()}.partial")
        partial.write_text(json.dumps(known), encoding="ascii")
        os.replace(partial, memo)  # (whole or not at all)
    except OSError:
        pass
    return numbers, schema


def warm_up() -> None:
    """Decode one made-up message, so that the reader's kernels are compiled (``omega-prime-visibility
    compile``)."""
    from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]

    from . import osi_wire

    truth = GroundTruth()
    truth.timestamp.seconds, truth.host_vehicle_id.value = 1, 3
    moving = truth.moving_object.add()
    moving.id.value, moving.type, moving.base.position.x = 3, osi_wire.VEHICLE, 1.0
    moving.vehicle_classification.role = 1
    decode_table([truth.SerializeToString()])
