"""OSI trace files (``.osi``) read straight into the object table, as :mod:`.reader` reads MCAP files.

An OSI trace is a sequence of serialised messages, each preceded by its length (4 bytes, little-endian). Which
message it holds is taken as omega-prime (through ``betterosi``) takes it: from the trace file naming convention
(``<timestamp>_<type>_..._<name>.osi``, or exactly one type abbreviation among the name's ``_``-separated parts),
else from the first message, which must decode cleanly (no unknown field anywhere) as exactly one of
``osi3.SensorView`` and ``osi3.GroundTruth``. A trace read without a map keeps its coordinates even where its
messages carry a projection (``proj_string``): omega-prime projects only onto an OpenDRIVE map. Anything else
(another message type, an ambiguous first message, a cut file) is left to omega-prime
(:class:`~.reader.NotOurs`), which reads it or says what is wrong.
"""

from __future__ import annotations

import os
import re
from pathlib import Path
from typing import Any

import numpy as np

from .reader import NotOurs, TraceRecording, decode_table

TYPE_ABBREVIATIONS = {
    "gt": "GroundTruth",
    "sv": "SensorView",
    "sd": "SensorData",
    "svc": "SensorViewConfiguration",
    "hvd": "HostVehicleData",
    "tc": "TrafficCommand",
    "tcu": "TrafficCommandUpdate",
    "tu": "TrafficUpdate",
    "mr": "MotionRequest",
    "su": "StreamingUpdate",
}
"""The message types of the ASAM OSI trace file naming convention, by abbreviation."""
_TIMESTAMP = re.compile(r"^\d{8}T\d{6}Z$")


def message_type_from_name(path: str | os.PathLike) -> str | None:
    """The message type a trace file's name gives by the naming convention, or None.

    Examples
    --------
    >>> message_type_from_name("20260920T220305Z_sv_3.7.0_4.24.0_600_city.osi")
    'SensorView'
    >>> message_type_from_name("cut_in_gt.osi"), message_type_from_name("sv_vs_gt.osi")
    ('GroundTruth', None)
    >>> message_type_from_name("pedestrian.osi") is None
    True
    """
    tokens = Path(path).stem.lower().split("_")
    if len(tokens) > 1 and _TIMESTAMP.match(tokens[0].upper()):
        return TYPE_ABBREVIATIONS.get(tokens[1])
    found = {TYPE_ABBREVIATIONS[t] for t in tokens if t in TYPE_ABBREVIATIONS}
    return found.pop() if len(found) == 1 else None


def frames(data: bytes) -> list[bytes]:
    """The messages of a trace, each without its length.

    Raises
    ------
    NotOurs
        If the file ends within a length or a message (omega-prime then says so in its words).

    Examples
    --------
    >>> frames(b"\\x02\\x00\\x00\\x00ab\\x01\\x00\\x00\\x00c")
    [b'ab', b'c']
    """
    out, at = [], 0
    view = memoryview(data)
    while at < len(data):
        if at + 4 > len(data):
            raise NotOurs("the trace ends within a message's length")
        size = int(np.frombuffer(view[at : at + 4], dtype="<u4")[0])
        if at + 4 + size > len(data):
            raise NotOurs("the trace ends within a message")
        out.append(bytes(view[at + 4 : at + 4 + size]))
        at += 4 + size
    return out


def probe(first: bytes) -> str | None:
    """The message type of a trace's first message: the one of ``SensorView`` and ``GroundTruth`` it decodes as
    with no unknown field anywhere, or None if it decodes cleanly as both or neither."""
    from google.protobuf.message import DecodeError
    from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]
    from osi3.osi_sensorview_pb2 import SensorView  # type: ignore[import-not-found]

    clean = []
    for message_class in (SensorView, GroundTruth):
        try:
            message = message_class.FromString(first)
        except DecodeError:
            continue
        if not _has_unknown_fields(message):
            clean.append(message_class.__name__)
    return clean[0] if len(clean) == 1 else None


def _has_unknown_fields(message: Any) -> bool:
    from google.protobuf.unknown_fields import UnknownFieldSet

    if len(UnknownFieldSet(message)):
        return True
    for field, value in message.ListFields():
        if field.message_type is None:
            continue
        if field.message_type.GetOptions().map_entry:
            values = value.values()
        else:
            repeated = field.is_repeated if hasattr(field, "is_repeated") else field.label == field.LABEL_REPEATED
            values = value if repeated else [value]
        if any(hasattr(v, "ListFields") and _has_unknown_fields(v) for v in values):
            return True
    return False


def read_osi(path: str | os.PathLike) -> TraceRecording:
    """The recording in the OSI trace ``path`` (no map given: its lanes, if any, are its map, as omega-prime
    reads them), decoded as :func:`~.reader.read_mcap` decodes an MCAP file.

    Raises
    ------
    NotOurs
        For a trace omega-prime should read instead (see the module's docstring).
    """
    path = Path(path)
    messages = frames(path.read_bytes())
    if not messages:
        raise NotOurs("the trace holds no message")
    kind = message_type_from_name(path) or probe(messages[0])
    if kind == "SensorView":
        from osi3.osi_sensorview_pb2 import SensorView  # type: ignore[import-not-found]

        views = [SensorView.FromString(m) for m in messages]
        if not all(v.HasField("global_ground_truth") for v in views):  # omega-prime skips them, and warns
            raise NotOurs("a sensor view without its ground truth")
        messages = [v.global_ground_truth.SerializeToString() for v in views]
    elif kind != "GroundTruth":
        raise NotOurs(f"the trace's messages are {kind or 'of no type its name or first message tells'}")
    # omega-prime projects onto an OpenDRIVE map only, and a trace read without a map has none (its map is the
    # lanes of its first ground truth): a proj_string in the messages leaves the coordinates as they are
    df, host = decode_table(messages, projected=False)
    return TraceRecording(df, host, path, first_ground_truth=messages[0])
