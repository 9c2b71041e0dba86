"""The answer drawn for Foxglove's 3D panel (Lichtblick's too): one ``foxglove.SceneUpdate`` per frame, built with
Foxglove's own protobuf schemas (``foxglove-schemas-protobuf``).

Every road user is a box with its real extent and orientation (``frame_id`` :data:`FRAME_ID`, the recording's
coordinates, metres), filled in its visibility colour on the pictures' scale (cividis, :mod:`..plot.style`: one
meaning of colour in every view), the observer in vermillion; the bodies in front of a partly or wholly hidden
target are outlined in black; a text over each target gives its idx and visible share. Each entity's metadata
holds its row's numbers (``visibility``, ``status``, ``occluder_idxs``, the camera and lidar counts), so that the
viewer's panels can show them. Static occluders are their footprints extruded to their heights
(:func:`static_update`, written once).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
import polars as pl
import shapely
from foxglove_schemas_protobuf.Color_pb2 import Color
from foxglove_schemas_protobuf.CubePrimitive_pb2 import CubePrimitive
from foxglove_schemas_protobuf.FrameTransform_pb2 import FrameTransform
from foxglove_schemas_protobuf.KeyValuePair_pb2 import KeyValuePair
from foxglove_schemas_protobuf.LinePrimitive_pb2 import LinePrimitive
from foxglove_schemas_protobuf.Point3_pb2 import Point3
from foxglove_schemas_protobuf.Pose_pb2 import Pose
from foxglove_schemas_protobuf.Quaternion_pb2 import Quaternion
from foxglove_schemas_protobuf.SceneEntity_pb2 import SceneEntity
from foxglove_schemas_protobuf.SceneEntityDeletion_pb2 import SceneEntityDeletion
from foxglove_schemas_protobuf.SceneUpdate_pb2 import SceneUpdate
from foxglove_schemas_protobuf.TextPrimitive_pb2 import TextPrimitive
from foxglove_schemas_protobuf.TriangleListPrimitive_pb2 import TriangleListPrimitive
from foxglove_schemas_protobuf.Vector3_pb2 import Vector3
from google.protobuf.timestamp_pb2 import Timestamp

from ..plot.style import OKABE_ITO, visibility_rgb
from ..threed.boxes import EDGES, corners
from .wire import Layout, boolean, delimited, double, key, length_delimited, string, tag, varint

_PAIR = KeyValuePair.DESCRIPTOR

FRAME_ID = "global"
"""The coordinate frame of every entity: the recording's own (x east, y north, z up, metres)."""

FLAT = 0.05
"""Metres: the height a box is drawn with when the recording gives none."""

OUTLINE = 0.08
"""Metres: the width of an occluder's black outline."""


def rgba(hex_colour: str, alpha: float = 1.0) -> Color:
    """A Foxglove colour from ``#rrggbb``.

    >>> c = rgba("#ff8000", 0.5)
    >>> round(c.r, 3), round(c.g, 3), c.b, c.a
    (1.0, 0.502, 0.0, 0.5)
    """
    return Color(r=int(hex_colour[1:3], 16) / 255, g=int(hex_colour[3:5], 16) / 255, b=int(hex_colour[5:7], 16) / 255,
                 a=alpha)  # fmt: skip


def quaternion(roll: float, pitch: float, yaw: float) -> Quaternion:
    """The rotation ``Rz(yaw) Ry(pitch) Rx(roll)`` (OSI's order, radians) as a unit quaternion.

    >>> q = quaternion(0.0, 0.0, np.pi / 2)
    >>> round(q.z, 12), round(q.w, 12)
    (0.707106781187, 0.707106781187)
    """
    x, y, z, w = quaternions(np.array([roll]), np.array([pitch]), np.array([yaw]))[0].tolist()
    return Quaternion(x=x, y=y, z=z, w=w)


def _stamp(nanos: int) -> Timestamp:
    return Timestamp(seconds=int(nanos) // 1_000_000_000, nanos=int(nanos) % 1_000_000_000)


def _value(value: object) -> str:
    """A row's value as the viewer shows it (numbers to six significant digits, lists joined by commas)."""
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list | tuple):
        return ", ".join(map(_value, value)) if value and isinstance(value[0], float | list | tuple) else (
            ", ".join(map(str, value)))  # fmt: skip
    return str(value)


def _vector(slot: str) -> Layout:
    return Layout(Vector3.DESCRIPTOR).doubles(slot, ["x", "y", "z"])


def _pose(position: str, orientation: str) -> Layout:
    rotation = Layout(Quaternion.DESCRIPTOR).doubles(orientation, ["x", "y", "z", "w"])
    return Layout(Pose.DESCRIPTOR).message("position", _vector(position)).message("orientation", rotation)


def _colour(slot: str) -> Layout:
    return Layout(Color.DESCRIPTOR).doubles(slot, ["r", "g", "b", "a"])


_TEXT = TextPrimitive.DESCRIPTOR
_ENTITY = SceneEntity.DESCRIPTOR
_UPDATE = SceneUpdate.DESCRIPTOR
CUBE = (
    Layout(CubePrimitive.DESCRIPTOR)
    .message("pose", _pose("position", "orientation"))
    .message("size", _vector("size"))
    .message("color", _colour("colour"))
)
"""A box's bytes: its pose, size and colour (:mod:`.wire`)."""
LABEL = (
    Layout(_TEXT)
    .message("pose", _pose("label_at", "upright"))
    .constant(boolean(_TEXT, "billboard", True) + double(_TEXT, "font_size", 14.0))
    .constant(boolean(_TEXT, "scale_invariant", True))
    .message("color", _colour("black"))
)
"""A label's bytes but its text."""


def quaternions(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """:func:`quaternion` of many rotations, columns ``x, y, z, w``, shape (n, 4)."""
    cr, sr, cp, sp = np.cos(roll / 2), np.sin(roll / 2), np.cos(pitch / 2), np.sin(pitch / 2)
    cy, sy = np.cos(yaw / 2), np.sin(yaw / 2)
    return np.column_stack([sr * cp * cy - cr * sp * sy, cr * sp * cy + sr * cp * sy, cr * cp * sy - sr * sp * cy,
                            cr * cp * cy + sr * sp * sy])  # fmt: skip


_LINE = LinePrimitive.DESCRIPTOR
_POINT = Layout(Point3.DESCRIPTOR)
OUTLINE_LINE = Layout(_LINE).constant(tag(_LINE, "type", 0) + varint(LinePrimitive.Type.LINE_LIST))
OUTLINE_LINE.message("pose", _pose("origin", "upright")).constant(double(_LINE, "thickness", OUTLINE))
for _k in range(8):
    OUTLINE_LINE.message("points", Layout(Point3.DESCRIPTOR).doubles(f"corner{_k}", ["x", "y", "z"]))
OUTLINE_LINE.message("color", _colour("black"))
OUTLINE_LINE.constant(key(_LINE, "indices") + varint(len(b"".join(varint(int(v)) for v in EDGES.ravel())))
                      + b"".join(varint(int(v)) for v in EDGES.ravel()))  # fmt: skip
"""A black outline of a box's 12 edges (``LINE_LIST`` over its 8 corners): the bytes but the corners."""

_KEYS = {name: key(_ENTITY, name) for name in ("metadata", "cubes", "texts", "lines", "id")}
_PAIR_KEY, _PAIR_VALUE = key(KeyValuePair.DESCRIPTOR, "key"), key(KeyValuePair.DESCRIPTOR, "value")
_TEXT_KEY, _ENTITIES_KEY = key(TextPrimitive.DESCRIPTOR, "text"), key(SceneUpdate.DESCRIPTOR, "entities")


def _pair(name: str, value: str) -> bytes:
    return delimited(_KEYS["metadata"], delimited(_PAIR_KEY, name.encode()) + delimited(_PAIR_VALUE, value.encode()))


@dataclass(frozen=True)
class FrameRows:
    """The table's rows of one view in one frame, as :func:`frame_update` draws them.

    Attributes
    ----------
    idx : ndarray of int64
        The targets.
    visibility : ndarray of float64
        Their visibility (NaN: none).
    metadata : list of bytes
        Each row's metadata fields, serialized (:func:`metadata_column`).
    hiding : set of int
        The idx of the bodies in front of a partly or wholly hidden target.
    """

    idx: np.ndarray
    visibility: np.ndarray
    metadata: list[bytes]
    hiding: set[int]


def _text(name: str, dtype: pl.DataType) -> pl.Expr:
    """A column's values as the viewer shows them (numbers to six significant digits, lists joined by commas)."""
    column = pl.col(name)
    if isinstance(dtype, pl.Array):
        column, dtype = column.cast(pl.List(dtype.inner)), pl.List(dtype.inner)
    if isinstance(dtype, pl.List):
        return column.list.eval(pl.element().cast(pl.String)).list.join(", ").fill_null("")
    if dtype.is_float():
        return column.fill_nan(None).round_sig_figs(6).cast(pl.String).fill_null("")
    return column.cast(pl.String).fill_null("")


_BYTE = [chr(k) for k in range(128)]


def _length(text: pl.Expr) -> pl.Expr:
    """The one-byte varint of a text's length in bytes (null from 128 on: such a row is written in Python)."""
    return text.str.len_bytes().replace_strict(list(range(128)), _BYTE, default=None, return_dtype=pl.String)


def metadata_column(schema: dict[str, pl.DataType], names: Sequence[str]) -> pl.Expr:
    """Each row's metadata fields of a ``SceneEntity`` (a ``KeyValuePair`` per column of ``names``), serialized,
    as a string of bytes below 128 (null where a length needs two varint bytes: :func:`row_metadata` then)."""
    pairs = []
    for name in names:
        value = _text(name, schema[name])
        inner = pl.concat_str([pl.lit((_PAIR_KEY + varint(len(name.encode())) + name.encode() + _PAIR_VALUE).decode()),
                               _length(value), value])  # fmt: skip
        pairs.append(pl.concat_str([pl.lit(_KEYS["metadata"].decode()), _length(inner), inner]))
    return pl.concat_str(pairs) if pairs else pl.lit("")


def row_metadata(row: dict) -> bytes:
    """:func:`metadata_column` of one row, in Python (for the rows it cannot write)."""
    return b"".join(_pair(k, _value(v)) for k, v in row.items())


def frame_update(nanos: int, boxes: np.ndarray, idx: np.ndarray, ego: int, rows: FrameRows) -> bytes:
    """One frame's scene, serialized: ``boxes`` (shape (n, 9), :mod:`..threed.boxes`) of the objects ``idx`` at
    ``nanos``, the observer ``ego``, and the view's ``rows``. The update first deletes what the previous frame
    drew. Its bytes are a ``foxglove.SceneUpdate`` (written through :mod:`.wire`, many boxes at once)."""
    stamp = _stamp(nanos)
    deletion = SceneEntityDeletion(timestamp=stamp, type=SceneEntityDeletion.Type.ALL).SerializeToString()
    n = len(idx)
    out = [length_delimited(_UPDATE, "deletions", deletion)]
    if n == 0:
        return b"".join(out)
    ids = idx.tolist()
    where = {i: k for k, i in enumerate(rows.idx.tolist())}
    at = np.array([where.get(i, -1) for i in ids])
    share = np.where(at >= 0, rows.visibility[np.maximum(at, 0)] if len(rows.idx) else np.nan, np.nan)
    colour = np.column_stack([visibility_rgb(share) / 255, np.full(n, 0.9)])
    colour[np.isnan(share)] = [0.8, 0.8, 0.8, 0.6]
    is_ego = idx == ego
    colour[is_ego] = [int(OKABE_ITO["vermillion"][k : k + 2], 16) / 255 for k in (1, 3, 5)] + [1.0]
    height = np.maximum(boxes[:, 5], FLAT)
    centre = boxes[:, :3]
    cubes = CUBE.encode({"position": centre, "orientation": quaternions(boxes[:, 6], boxes[:, 7], boxes[:, 8]),
                         "size": np.column_stack([boxes[:, 3], boxes[:, 4], height]), "colour": colour})  # fmt: skip
    above = centre + np.column_stack([np.zeros((n, 2)), height / 2 + 0.6])
    upright = np.tile([0.0, 0.0, 0.0, 1.0], (n, 1))
    labels = LABEL.encode({"label_at": above, "upright": upright, "black": upright})
    hiding = rows.hiding
    outlines = None
    if hiding:
        points = corners(boxes)
        slots = {f"corner{c}": points[:, c] for c in range(8)}
        outlines = OUTLINE_LINE.encode(slots | {"origin": np.zeros((n, 3)), "upright": upright, "black": upright})
    prefix = length_delimited(_ENTITY, "timestamp", stamp.SerializeToString()) + string(_ENTITY, "frame_id", FRAME_ID)
    cube_key = tag(_ENTITY, "cubes", 2) + varint(CUBE.size)
    for k, i in enumerate(ids):
        a = int(at[k])
        if is_ego[k]:
            text, metadata = f"{i} observer", _pair("idx", str(i))
        elif a >= 0:
            text = f"{i}: {share[k]:.0%}" if share[k] == share[k] else f"{i}"
            metadata = rows.metadata[a]
        else:
            text, metadata = f"{i}", _pair("idx", str(i))
        label = delimited(_KEYS["texts"], labels[k].tobytes() + delimited(_TEXT_KEY, text.encode()))
        lines = delimited(_KEYS["lines"], outlines[k].tobytes()) if i in hiding else b""
        body = b"".join((prefix, delimited(_KEYS["id"], f"object {i}".encode()), metadata, cube_key,
                         cubes[k].tobytes(), label, lines))  # fmt: skip
        out.append(delimited(_ENTITIES_KEY, body))
    return b"".join(out)


_TRIANGLES = TriangleListPrimitive.DESCRIPTOR
_CORNER = Layout(Point3.DESCRIPTOR).doubles("p", ["x", "y", "z"])
_CORNER_KEY = key(_TRIANGLES, "points") + varint(_CORNER.size)
_REGION_POSE = length_delimited(_TRIANGLES, "pose", Pose(orientation=Quaternion(w=1.0)).SerializeToString())
_REGION_COLOUR = length_delimited(_TRIANGLES, "color", rgba(OKABE_ITO["sky blue"], 0.35).SerializeToString())


def region_entity(nanos: int, outlines: Sequence[tuple[np.ndarray, np.ndarray]], ground: float) -> bytes:
    """The regions the observer sees (each an outline star-shaped about its viewpoint, world frame, metres), as a
    fan of triangles from the viewpoint on its ground (``ground`` metres, just above it), serialized as a
    ``SceneUpdate`` entity field (to append to :func:`frame_update`'s bytes)."""
    corners_xy = []
    area = 0.0
    for outline, centre in outlines:
        ring = np.asarray(outline, dtype=np.float64)
        if len(ring) >= 2 and np.array_equal(ring[0], ring[-1]):
            ring = ring[:-1]
        if len(ring) < 2:
            continue
        a, b = ring, np.roll(ring, -1, axis=0)
        fan = np.stack([np.broadcast_to(centre, a.shape), a, b], axis=1)  # (k, 3, 2)
        corners_xy.append(fan.reshape(-1, 2))
        area += 0.5 * float(
            np.sum((a[:, 0] - centre[0]) * (b[:, 1] - centre[1]) - (b[:, 0] - centre[0]) * (a[:, 1] - centre[1]))
        )
    points = np.concatenate(corners_xy) if corners_xy else np.zeros((0, 2))
    xyz = np.column_stack([points, np.full(len(points), ground + 0.02)])
    encoded = _CORNER.encode({"p": xyz}) if len(xyz) else np.zeros((0, _CORNER.size), dtype=np.uint8)
    key_bytes = np.frombuffer(_CORNER_KEY, dtype=np.uint8)
    repeated = np.hstack([np.tile(key_bytes, (len(encoded), 1)), encoded]).tobytes()
    shape = _REGION_POSE + repeated + _REGION_COLOUR
    stamp = length_delimited(_ENTITY, "timestamp", _stamp(nanos).SerializeToString())
    body = (stamp + string(_ENTITY, "frame_id", FRAME_ID) + string(_ENTITY, "id", "seen region")
            + _pair("seen area (m²)", f"{area:.6g}") + delimited(key(_ENTITY, "triangles"), shape))  # fmt: skip
    return delimited(_ENTITIES_KEY, body)


def observer_frame(nanos: int, ego: int, box: np.ndarray) -> FrameTransform:
    """The frame ``ego_<idx>`` of an observer at ``nanos``: its box's centre and orientation in :data:`FRAME_ID`."""
    x, y, z, _, _, _, roll, pitch, yaw = (float(v) for v in box)
    return FrameTransform(timestamp=_stamp(nanos), parent_frame_id=FRAME_ID, child_frame_id=f"ego_{ego}",
                          translation=Vector3(x=x, y=y, z=z), rotation=quaternion(roll, pitch, yaw))  # fmt: skip


def static_update(nanos: int, footprints: Sequence[shapely.Geometry], tops: Sequence[float]) -> SceneUpdate:
    """The static occluders at ``nanos`` (written once; they stay): each footprint extruded from the ground to its
    top (metres), grey; walls (lines) as thin slabs."""
    update = SceneUpdate()
    for k, (geometry, top) in enumerate(zip(footprints, tops, strict=True)):
        top = max(float(top), FLAT) if np.isfinite(top) else 3.0
        shape = geometry.buffer(0.1) if geometry.geom_type in ("LineString", "MultiLineString") else geometry
        points: list[Point3] = []
        for part in getattr(shape, "geoms", [shape]):
            if part.is_empty or part.geom_type != "Polygon":
                continue
            for tri in shapely.get_parts(shapely.constrained_delaunay_triangles(part)):
                a, b, c = np.asarray(tri.exterior.coords)[:3]
                points += [Point3(x=p[0], y=p[1], z=top) for p in (a, b, c)]
            for ring in [part.exterior, *part.interiors]:
                xy = np.asarray(ring.coords)
                for p, q in itertools.pairwise(xy):
                    quad = [(p, 0.0), (q, 0.0), (q, top), (p, 0.0), (q, top), (p, top)]
                    points += [Point3(x=v[0], y=v[1], z=h) for v, h in quad]
        update.entities.append(
            SceneEntity(
                timestamp=_stamp(nanos),
                frame_id=FRAME_ID,
                id=f"static #{k}",
                triangles=[
                    TriangleListPrimitive(
                        pose=Pose(orientation=Quaternion(w=1.0)), points=points, color=rgba("#9e9e9e", 0.85)
                    )
                ],
                metadata=[
                    KeyValuePair(key="static occluder", value=f"#{k}"),
                    KeyValuePair(key="top", value=f"{top:.6g}"),
                ],
            )
        )
    return update
