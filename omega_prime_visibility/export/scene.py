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
import math
from collections.abc import Sequence

import numpy as np
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

from ..plot.style import OKABE_ITO, visibility_colour
from ..threed.boxes import EDGES, corners

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

    >>> q = quaternion(0.0, 0.0, math.pi / 2)
    >>> round(q.z, 12), round(q.w, 12)
    (0.707106781187, 0.707106781187)
    """
    cr, sr = math.cos(roll / 2), math.sin(roll / 2)
    cp, sp = math.cos(pitch / 2), math.sin(pitch / 2)
    cy, sy = math.cos(yaw / 2), math.sin(yaw / 2)
    return Quaternion(
        w=cr * cp * cy + sr * sp * sy,
        x=sr * cp * cy - cr * sp * sy,
        y=cr * sp * cy + sr * cp * sy,
        z=cr * cp * sy - sr * sp * cy,
    )


def _stamp(nanos: int) -> Timestamp:
    return Timestamp(seconds=int(nanos) // 1_000_000_000, nanos=int(nanos) % 1_000_000_000)


def _value(value: object) -> str:
    if value is None:
        return ""
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, list | tuple | np.ndarray):
        return ", ".join(_value(v) for v in value)
    return str(value)


def frame_update(
    nanos: int,
    boxes: np.ndarray,
    idx: np.ndarray,
    ego: int,
    rows: dict[int, dict],
) -> SceneUpdate:
    """One frame's scene: ``boxes`` (shape (n, 9), :mod:`..threed.boxes`) of the objects ``idx`` at ``nanos``,
    the observer ``ego``, and ``rows`` (the table's row of each target, by idx: its ``visibility``, ``status``,
    ``occluder_idxs``, ...). The update first deletes what the previous frame drew."""
    stamp = _stamp(nanos)
    update = SceneUpdate(deletions=[SceneEntityDeletion(timestamp=stamp, type=SceneEntityDeletion.Type.ALL)])
    hiding = {
        o for row in rows.values() if (row.get("visibility") or 0.0) < 1.0 for o in row.get("occluder_idxs") or []
    }
    outline = corners(boxes) if len(boxes) else np.zeros((0, 8, 3))
    for k, i in enumerate(idx.tolist()):
        x, y, z, length, width, height, roll, pitch, yaw = boxes[k].tolist()
        row = rows.get(i)
        if i == ego:
            colour, label = rgba(OKABE_ITO["vermillion"]), f"{i} observer"
        elif row is not None:
            share = row.get("visibility")
            colour = rgba(visibility_colour(float("nan") if share is None else share), 0.9)
            label = f"{i}: {share:.0%}" if share is not None else f"{i}"
        else:
            colour, label = rgba("#cccccc", 0.6), f"{i}"
        pose = Pose(position=Vector3(x=x, y=y, z=z), orientation=quaternion(roll, pitch, yaw))
        entity = SceneEntity(
            timestamp=stamp,
            frame_id=FRAME_ID,
            id=f"object {i}",
            cubes=[CubePrimitive(pose=pose, size=Vector3(x=length, y=width, z=max(height, FLAT)), color=colour)],
            texts=[
                TextPrimitive(
                    pose=Pose(
                        position=Vector3(x=x, y=y, z=z + max(height, FLAT) / 2 + 0.6), orientation=Quaternion(w=1.0)
                    ),
                    billboard=True,
                    font_size=14.0,
                    scale_invariant=True,
                    color=rgba("#000000"),
                    text=label,
                )
            ],
            metadata=[KeyValuePair(key="idx", value=str(i))]
            + [KeyValuePair(key=key, value=_value(value)) for key, value in (row or {}).items() if key != "idx"],
        )
        if i in hiding:  # it hides some target: outlined in black
            points = [Point3(x=float(p[0]), y=float(p[1]), z=float(p[2])) for p in outline[k]]
            line = LinePrimitive(type=LinePrimitive.Type.LINE_LIST, pose=Pose(orientation=Quaternion(w=1.0)),
                                 thickness=OUTLINE, color=rgba("#000000"), points=points,
                                 indices=EDGES.ravel().tolist())  # fmt: skip
            entity.lines.append(line)
        update.entities.append(entity)
    return update


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
