"""The moving objects of ``osi3.GroundTruth`` messages, decoded from the protobuf wire format at array speed.

Decoding each message into Python objects and reading its fields one by one costs about 15 us per moving object,
most of it in making Python objects; these kernels read the fields the object table needs straight from the bytes
(varints, 64-bit doubles, nested messages; anything else is skipped by its wire type), into columns. The field
numbers are not written here: they come from ASAM's own message descriptors (``osi-python``), see
:func:`field_numbers`. Unset fields read as protobuf's defaults (0), as the generated classes read them.

Bytes that protobuf would refuse (:func:`valid_messages`: a field number 0, a length past the end, anywhere in the
message, nested messages included) are told, never skipped as unknown fields; so is a message without its
timestamp (:func:`lacking`).

Building blocks: :func:`read_varint`, :func:`skip_field`, :func:`next_field`, :func:`read_double`,
:func:`valid_messages`, :func:`lacking`, :func:`object_counts`, :func:`decode_objects`.
"""

from __future__ import annotations

import numpy as np

from .._compiled.kernel import njit

VARINT, FIXED64, LENGTH, FIXED32 = 0, 1, 2, 5
"""Protobuf's wire types used here (groups, 3 and 4, are refused)."""

FIELDS = (
    "GroundTruth.timestamp", "GroundTruth.moving_object", "GroundTruth.host_vehicle_id", "GroundTruth.proj_string",
    "GroundTruth.proj_frame_offset", "Timestamp.seconds", "Timestamp.nanos", "MovingObject.id", "MovingObject.base",
    "MovingObject.type", "MovingObject.vehicle_classification", "Identifier.value", "BaseMoving.dimension",
    "BaseMoving.position", "BaseMoving.orientation", "BaseMoving.velocity", "BaseMoving.acceleration",
    "Dimension3d.length", "Dimension3d.width", "Dimension3d.height", "Vector3d.x", "Vector3d.y", "Vector3d.z",
    "Orientation3d.roll", "Orientation3d.pitch", "Orientation3d.yaw", "VehicleClassification.type",
    "VehicleClassification.role",
)  # fmt: skip
"""The fields read, in the order of the numbers :func:`field_numbers` gives the kernels."""
(GT_TIMESTAMP, GT_MOVING_OBJECT, GT_HOST, GT_PROJ_STRING, GT_PROJ_OFFSET, TS_SECONDS, TS_NANOS, MO_ID, MO_BASE,
 MO_TYPE, MO_CLASS, ID_VALUE, BM_DIMENSION, BM_POSITION, BM_ORIENTATION, BM_VELOCITY, BM_ACCELERATION, D_LENGTH,
 D_WIDTH, D_HEIGHT, V_X, V_Y, V_Z, O_ROLL, O_PITCH, O_YAW, VC_TYPE, VC_ROLE) = range(len(FIELDS))  # fmt: skip

FLOATS = ("x", "y", "z", "vel_x", "vel_y", "vel_z", "acc_x", "acc_y", "acc_z", "length", "width", "height", "roll",
          "pitch", "yaw")  # fmt: skip
"""The float columns :func:`decode_objects` fills, in this order."""
INTS = ("total_nanos", "idx", "type", "role", "subtype")
"""The integer columns :func:`decode_objects` fills, in this order."""
VEHICLE = 2  # osi3.MovingObject.TYPE_VEHICLE: role and subtype are read for vehicles only, else -1

BAD = -1
"""A position returned for bytes that are no valid protobuf message (cut off, or a field of an unexpected wire
type)."""


def field_numbers() -> np.ndarray:
    """The numbers of :data:`FIELDS` in ASAM's ``osi3`` message descriptors (``osi-python``).

    Examples
    --------
    >>> numbers = field_numbers()
    >>> len(numbers) == len(FIELDS), int(numbers[GT_MOVING_OBJECT]) > 0
    (True, True)
    """
    from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]

    moving = GroundTruth.DESCRIPTOR.fields_by_name["moving_object"].message_type
    base = moving.fields_by_name["base"].message_type
    types = {
        "GroundTruth": GroundTruth.DESCRIPTOR,
        "Timestamp": GroundTruth.DESCRIPTOR.fields_by_name["timestamp"].message_type,
        "MovingObject": moving,
        "Identifier": moving.fields_by_name["id"].message_type,
        "BaseMoving": base,
        "Dimension3d": base.fields_by_name["dimension"].message_type,
        "Vector3d": base.fields_by_name["position"].message_type,
        "Orientation3d": base.fields_by_name["orientation"].message_type,
        "VehicleClassification": moving.fields_by_name["vehicle_classification"].message_type,
    }
    return np.array(
        [types[name.split(".")[0]].fields_by_name[name.split(".")[1]].number for name in FIELDS], dtype=np.int64
    )


@njit(cache=True)
def read_varint(buf: np.ndarray, pos: int, end: int) -> tuple[int, int]:
    """The varint at ``buf[pos]`` as a 64-bit two's complement integer, and the position after it
    (:data:`BAD` when it runs past ``end``)."""
    value = 0
    shift = 0
    while pos < end and shift < 64:
        byte = np.int64(buf[pos])
        pos += 1
        value |= (byte & 0x7F) << shift
        if byte < 0x80:
            return value, pos
        shift += 7
    return 0, BAD


@njit(cache=True)
def skip_field(buf: np.ndarray, pos: int, end: int, wire: int) -> int:
    """The position after a field's value of wire type ``wire`` starting at ``pos`` (:data:`BAD` if none)."""
    if wire == VARINT:
        return read_varint(buf, pos, end)[1]
    if wire == FIXED64:
        return pos + 8 if pos + 8 <= end else BAD
    if wire == FIXED32:
        return pos + 4 if pos + 4 <= end else BAD
    if wire == LENGTH:
        size, pos = read_varint(buf, pos, end)
        return pos + size if pos != BAD and 0 <= size <= end - pos else BAD
    return BAD


@njit(cache=True)
def next_field(buf: np.ndarray, pos: int, end: int) -> tuple[int, int, int, int]:
    """The field starting at ``buf[pos]``: its number, its wire type, where its value starts (a length-delimited
    field's payload, after its length) and the position after it (:data:`BAD` for bytes that are no field; where
    the value starts is then undefined)."""
    key, pos = read_varint(buf, pos, end)
    if pos == BAD:
        return 0, 0, BAD, BAD
    wire = key & 7
    if wire == LENGTH:  # (its length read once, for both positions)
        size, start = read_varint(buf, pos, end)
        return key >> 3, wire, start, start + size if start != BAD and 0 <= size <= end - start else BAD
    return key >> 3, wire, pos, skip_field(buf, pos, end, wire)


def message_schema(descriptor=None) -> np.ndarray:
    """Which fields of each message type below ``osi3.GroundTruth`` (ASAM's descriptors) are messages themselves:
    ``schema[t, n]`` is the type number of field ``n`` of type ``t`` (type 0: ``GroundTruth``), -1 for a field that
    is no message or not declared; what :func:`valid_messages` walks.

    >>> schema = message_schema()
    >>> int(schema[0, field_numbers()[GT_MOVING_OBJECT]]) > 0, int(schema[0, field_numbers()[GT_PROJ_STRING]])
    (True, -1)
    """
    if descriptor is None:
        from osi3.osi_groundtruth_pb2 import GroundTruth  # type: ignore[import-not-found]

        descriptor = GroundTruth.DESCRIPTOR
    types = {descriptor.full_name: 0}
    order = [descriptor]
    for d in order:  # (breadth first: every message type reachable once)
        for f in d.fields:
            if f.message_type is not None and f.message_type.full_name not in types:
                types[f.message_type.full_name] = len(order)
                order.append(f.message_type)
    width = 1 + max((f.number for d in order for f in d.fields), default=0)
    schema = np.full((len(order), width), -1, dtype=np.int64)
    for t, d in enumerate(order):
        for f in d.fields:
            if f.message_type is not None:
                schema[t, f.number] = types[f.message_type.full_name]
    return schema


MAX_FIELD_NUMBER = 2**29 - 1
"""Protobuf's largest field number; 0 is no field number either."""


@njit(cache=True)
def valid_messages(buf: np.ndarray, starts: np.ndarray, ends: np.ndarray, schema: np.ndarray) -> int:
    """The first message (``buf[starts[k]:ends[k]]``) that protobuf would refuse to parse as the schema's root type
    (:func:`message_schema`), nested messages included, or -1 when all parse: a field number 0 or beyond
    :data:`MAX_FIELD_NUMBER`, a wire type that does not exist (6, 7) or a group (3, 4: OSI declares none; such bytes
    go to omega-prime's reader, which decides), a length or a varint past the end of its message."""
    stack_pos = np.empty(64, np.int64)
    stack_end = np.empty(64, np.int64)
    stack_type = np.empty(64, np.int64)
    for k in range(len(starts)):
        depth = 0
        stack_pos[0], stack_end[0], stack_type[0] = starts[k], ends[k], 0
        while depth >= 0:
            pos, end, kind = stack_pos[depth], stack_end[depth], stack_type[depth]
            if pos >= end:
                depth -= 1
                continue
            number, wire, start, after = next_field(buf, pos, end)
            if after == BAD or number <= 0 or number > MAX_FIELD_NUMBER:  # (a 64-bit tag reads negative)
                return k
            stack_pos[depth] = after
            if wire == LENGTH and number < schema.shape[1] and schema[kind, number] >= 0:
                if depth + 1 >= 64:  # deeper than any OSI message nests: no ground truth
                    return k
                depth += 1
                stack_pos[depth], stack_end[depth], stack_type[depth] = start, after, schema[kind, number]
    return -1


@njit(cache=True)
def lacking(buf: np.ndarray, starts: np.ndarray, ends: np.ndarray, number: int) -> int:
    """The first message (``buf[starts[k]:ends[k]]``, valid ones) without a top-level field ``number``, or -1."""
    for k in range(len(starts)):
        pos, found = starts[k], False
        while pos < ends[k] and not found:
            field, _wire, _start, pos = next_field(buf, pos, ends[k])
            if pos == BAD:
                return k
            found = field == number
        if not found:
            return k
    return -1


@njit(cache=True)
def read_double(buf: np.ndarray, pos: int, scratch: tuple) -> float:
    """The little-endian 64-bit float at ``buf[pos]`` (``scratch``: one float64 and a view of its 8 bytes, made once
    by the caller and reused: nothing is allocated per value)."""
    value, raw = scratch
    for k in range(8):
        raw[k] = buf[pos + k]
    return value[0]


@njit(cache=True)
def _fields(
    buf: np.ndarray,
    pos: int,
    end: int,
    numbers: np.ndarray,
    index: int,
    out: np.ndarray,
    first: int,
    scratch: tuple,
) -> bool:
    """Read the double fields ``numbers[index:index + k]`` of the message in ``buf[pos:end]`` into
    ``out[first:first + k]`` (k = 3; ``scratch`` as :func:`read_double` takes it); False for bytes that are no
    message."""
    while pos < end:
        number, wire, start, after = next_field(buf, pos, end)
        if after == BAD:
            return False
        for k in range(3):
            if number == numbers[index + k]:
                if wire != FIXED64:
                    return False
                out[first + k] = read_double(buf, start, scratch)
                break
        pos = after
    return pos == end


@njit(cache=True)
def _base(buf: np.ndarray, pos: int, end: int, numbers: np.ndarray, floats: np.ndarray, scratch: tuple) -> bool:
    """Read a ``BaseMoving`` message: its dimension, position, orientation, velocity and acceleration."""
    while pos < end:
        number, wire, start, after = next_field(buf, pos, end)
        if after == BAD:
            return False
        # the sub-message's fields and the first of its three columns in ``floats`` (see FLOATS)
        index, first = -1, -1
        if number == numbers[BM_POSITION]:
            index, first = V_X, 0
        elif number == numbers[BM_VELOCITY]:
            index, first = V_X, 3
        elif number == numbers[BM_ACCELERATION]:
            index, first = V_X, 6
        elif number == numbers[BM_DIMENSION]:
            index, first = D_LENGTH, 9
        elif number == numbers[BM_ORIENTATION]:
            index, first = O_ROLL, 12
        if index >= 0:
            if wire != LENGTH:
                return False
            if not _fields(buf, start, after, numbers, index, floats, first, scratch):
                return False
        pos = after
    return pos == end


@njit(cache=True)
def _varints(buf: np.ndarray, pos: int, end: int, wanted: int, other: int) -> tuple[int, int, bool]:
    """The varint fields numbered ``wanted`` and ``other`` of the message in ``buf[pos:end]`` (0 when unset)."""
    a = b = 0
    while pos < end:
        number, wire, start, after = next_field(buf, pos, end)
        if after == BAD:
            return 0, 0, False
        if number == wanted or number == other:
            if wire != VARINT:
                return 0, 0, False
            value = read_varint(buf, start, end)[0]
            if number == wanted:
                a = value
            else:
                b = value
        pos = after
    return a, b, pos == end


@njit(cache=True)
def _object(
    buf: np.ndarray, pos: int, end: int, numbers: np.ndarray, ints: np.ndarray, floats: np.ndarray, scratch: tuple
) -> bool:
    """Read a ``MovingObject`` message into one row: ``ints[1:5]`` (idx, type, role, subtype), ``floats``."""
    role = subtype = 0
    while pos < end:
        number, wire, start, after = next_field(buf, pos, end)
        if after == BAD:
            return False
        if number == numbers[MO_TYPE]:
            if wire != VARINT:
                return False
            ints[2] = read_varint(buf, start, end)[0]
        elif number == numbers[MO_ID] or number == numbers[MO_BASE] or number == numbers[MO_CLASS]:
            if wire != LENGTH:
                return False
            if number == numbers[MO_ID]:
                value, _unused, ok = _varints(buf, start, after, numbers[ID_VALUE], -1)
                ints[1] = value
            elif number == numbers[MO_BASE]:
                ok = _base(buf, start, after, numbers, floats, scratch)
            else:
                subtype, role, ok = _varints(buf, start, after, numbers[VC_TYPE], numbers[VC_ROLE])
            if not ok:
                return False
        pos = after
    ints[3] = role if ints[2] == VEHICLE else -1
    ints[4] = subtype if ints[2] == VEHICLE else -1
    return pos == end


@njit(cache=True)
def object_counts(buf: np.ndarray, starts: np.ndarray, ends: np.ndarray, numbers: np.ndarray) -> np.ndarray:
    """The number of moving objects in each message ``buf[starts[m]:ends[m]]`` (-1 for bytes that are no
    message)."""
    counts = np.zeros(len(starts), dtype=np.int64)
    for m in range(len(starts)):
        pos, end = starts[m], ends[m]
        while pos < end:
            number, _wire, _start, pos = next_field(buf, pos, end)
            if pos == BAD:
                break
            if number == numbers[GT_MOVING_OBJECT]:
                counts[m] += 1
        if pos != end:
            counts[m] = -1
    return counts


@njit(cache=True)
def decode_objects(
    buf: np.ndarray, starts: np.ndarray, ends: np.ndarray, numbers: np.ndarray, offsets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray, int]:
    """The moving objects of the messages ``buf[starts[m]:ends[m]]``, message ``m``'s in rows
    ``offsets[m]:offsets[m + 1]`` (from :func:`object_counts`).

    Returns
    -------
    ints : (n, 5) int64
        :data:`INTS`: the message's time in nanoseconds, then each object's ``idx, type, role, subtype``.
    floats : (n, 15) float64
        :data:`FLOATS`.
    flags : (m, 3) int64
        Per message: whether it names a host vehicle, that vehicle's idx, whether it carries a projection
        (``proj_string`` or ``proj_frame_offset``).
    bad : int
        The first message that is no valid ``GroundTruth`` (-1 if none).
    """
    n = offsets[-1]
    ints = np.zeros((n, 5), dtype=np.int64)
    floats = np.zeros((n, 15), dtype=np.float64)
    value = np.zeros(1, dtype=np.float64)
    scratch = (value, value.view(np.uint8))  # (its bytes viewed once: a view for every value cost a tenth)
    flags = np.zeros((len(starts), 3), dtype=np.int64)
    for m in range(len(starts)):
        pos, end, row = starts[m], ends[m], offsets[m]
        seconds = nanos = 0
        while pos < end:
            number, wire, start, after = next_field(buf, pos, end)
            if after == BAD:
                return ints, floats, flags, m
            if number == numbers[GT_MOVING_OBJECT] or number == numbers[GT_TIMESTAMP] or number == numbers[GT_HOST]:
                if wire != LENGTH:
                    return ints, floats, flags, m
                if number == numbers[GT_MOVING_OBJECT]:
                    ok = _object(buf, start, after, numbers, ints[row], floats[row], scratch)
                    row += 1
                elif number == numbers[GT_TIMESTAMP]:
                    seconds, nanos, ok = _varints(buf, start, after, numbers[TS_SECONDS], numbers[TS_NANOS])
                else:
                    flags[m, 1], _unused, ok = _varints(buf, start, after, numbers[ID_VALUE], -1)
                    flags[m, 0] = 1
                if not ok:
                    return ints, floats, flags, m
            elif number == numbers[GT_PROJ_OFFSET]:
                flags[m, 2] = 1
            elif number == numbers[GT_PROJ_STRING]:
                if wire != LENGTH:
                    return ints, floats, flags, m
                for k in range(start, after):  # a string of blanks is none (omega-prime strips it)
                    if buf[k] not in (9, 10, 11, 12, 13, 32):
                        flags[m, 2] = 1
                        break
            pos = after
        ints[offsets[m] : offsets[m + 1], 0] = seconds * 1_000_000_000 + nanos
    return ints, floats, flags, -1
