"""Protobuf's wire format for many messages of one fixed layout at once, from the official schemas' descriptors.

A frame of a town has hundreds of boxes: building each ``CubePrimitive`` as a protobuf object costs more than
computing the table. A message whose fields are all fixed-width numbers (a ``Vector3``, a ``Pose``, a whole
``CubePrimitive``) has the same bytes around its numbers every time: :class:`Layout` lays them out once, from the
field numbers of Foxglove's (or any) descriptors, and writes the numbers of ``n`` messages into an ``(n, size)``
byte array with numpy. Every field is written, zeros too (valid protobuf: a decoder reads the same message); the
tests decode the result with the official classes.

>>> from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
>>> layout = Layout(Vector3.DESCRIPTOR).doubles("v", ["x", "y", "z"])
>>> rows = layout.encode({"v": np.array([[1.0, 2.0, 3.0]])})
>>> Vector3.FromString(rows[0].tobytes()).y
2.0
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import numpy as np
from google.protobuf.descriptor import Descriptor

LENGTH, FIXED64, VARINT = 2, 1, 0


def varint(value: int) -> bytes:
    """``value`` (>= 0) as a protobuf varint.

    >>> varint(1), varint(300)
    (b'\\x01', b'\\xac\\x02')
    """
    if value < _SMALL:
        return _VARINTS[value]
    return _varint(value)


def _varint(value: int) -> bytes:
    out = bytearray()
    while True:
        byte = value & 0x7F
        value >>= 7
        if value:
            out.append(byte | 0x80)
        else:
            out.append(byte)
            return bytes(out)


_SMALL = 1 << 14
_VARINTS = [_varint(k) for k in range(_SMALL)]  # the lengths of every small message, ready


def tag(descriptor: Descriptor, field: str, wire: int) -> bytes:
    """The key of ``field`` of the message ``descriptor`` with wire type ``wire``."""
    return varint((descriptor.fields_by_name[field].number << 3) | wire)


def key(descriptor: Descriptor, field: str) -> bytes:
    """The key of a length-delimited ``field`` (a string, bytes or a message), to use with :func:`delimited`."""
    return tag(descriptor, field, LENGTH)


def delimited(field_key: bytes, payload: bytes) -> bytes:
    """A length-delimited field from its :func:`key` and its ``payload`` (the fast path of loops)."""
    n = len(payload)
    return field_key + (_VARINTS[n] if n < _SMALL else _varint(n)) + payload


def length_delimited(descriptor: Descriptor, field: str, payload: bytes) -> bytes:
    """``field`` (a string, bytes or a message) holding ``payload``."""
    return delimited(key(descriptor, field), payload)


def string(descriptor: Descriptor, field: str, text: str) -> bytes:
    """A string field."""
    return length_delimited(descriptor, field, text.encode())


def double(descriptor: Descriptor, field: str, value: float) -> bytes:
    """A double field."""
    return tag(descriptor, field, FIXED64) + struct.pack("<d", value)


def boolean(descriptor: Descriptor, field: str, value: bool) -> bytes:
    """A bool field."""
    return tag(descriptor, field, VARINT) + (b"\x01" if value else b"\x00")


class Layout:
    """The bytes of one message type with every field fixed: constant bytes and slots of doubles, by name."""

    def __init__(self, descriptor: Descriptor) -> None:
        self.descriptor = descriptor
        self.parts: list[bytes | tuple[str, int]] = []  # constant bytes, or (slot name, column)

    @property
    def size(self) -> int:
        return sum(len(p) if isinstance(p, bytes) else 8 for p in self.parts)

    def constant(self, data: bytes) -> Layout:
        self.parts.append(data)
        return self

    def doubles(self, slot: str, fields: Sequence[str]) -> Layout:
        """Double fields ``fields`` in order, their values the columns of slot ``slot``."""
        for k, field in enumerate(fields):
            self.parts.append(tag(self.descriptor, field, FIXED64))
            self.parts.append((slot, k))
        return self

    def message(self, field: str, inner: Layout) -> Layout:
        """The sub-message ``field``, laid out by ``inner`` (its slots become this layout's)."""
        self.parts.append(tag(self.descriptor, field, LENGTH) + varint(inner.size))
        self.parts.extend(inner.parts)
        return self

    def encode(self, slots: dict[str, np.ndarray]) -> np.ndarray:
        """The bytes of ``n`` messages, shape (n, size) uint8; ``slots`` maps each slot to an array (n, columns)."""
        n = len(next(iter(slots.values())))
        out = np.empty((n, self.size), dtype=np.uint8)
        at = 0
        for part in self.parts:
            if isinstance(part, bytes):
                out[:, at : at + len(part)] = np.frombuffer(part, dtype=np.uint8)
                at += len(part)
            else:
                name, column = part
                values = np.ascontiguousarray(np.asarray(slots[name], dtype="<f8")[:, column])
                out[:, at : at + 8] = values.view(np.uint8).reshape(n, 8)
                at += 8
        return out
