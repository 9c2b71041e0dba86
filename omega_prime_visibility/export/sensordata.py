"""What a sensor sees, as ASAM OSI's ``SensorData`` (``osi-python``): the ideal sensor's output with occlusion.

Per frame and sensor (without sensors: the observer's all-around view from its bounding-box centre), one
``osi3.SensorData`` with

- ``timestamp`` the frame's time, ``sensor_id`` the sensor's position in the list of sensors,
  ``host_vehicle_location`` the observer's box in the world (its idx names the channel);
- ``mounting_position`` the sensor's pose in the observer's frame (x forward, y left, z up) relative to the centre
  of its bounding box (the tables carry no rear-axle offset, OSI's origin of vehicle coordinates);
- ``virtual_detection_area`` the field of view within range (a fan in the sensor's horizontal plane), where the
  sensor has limits;
- a ``moving_object`` per road user the table calls visible or partly visible: ``header.ground_truth_id`` and
  ``header.tracking_id`` its idx (stable over frames, as ground truth gives it), ``existence_probability`` 1,
  ``measurement_state`` measured, and ``base`` its box in the sensor's frame (OSI's parent frame of detected
  objects): position, orientation and dimension.

OSI has no field for how much of an object is seen (an open request in OSI's tracker); the visible share is on
the table channel of the same MCAP, keyed by the same idx, and in the visibility table itself.

:func:`osi_trace_bytes` gives the messages as a single-channel ``.osi`` trace (each message after its length as a
four-byte little-endian unsigned integer).
"""

from __future__ import annotations

import math
import struct
from collections.abc import Iterable

import numpy as np
from osi3.osi_detectedobject_pb2 import DetectedItemHeader
from osi3.osi_sensordata_pb2 import SensorData
from osi3.osi_version_pb2 import DESCRIPTOR as VERSION_DESCRIPTOR
from osi3.osi_version_pb2 import current_interface_version

from ..inputs.sensors import Sensor, sensor_poses
from ..threed.boxes import rotations

_VERSION = VERSION_DESCRIPTOR.GetOptions().Extensions[current_interface_version]
OSI_VERSION = f"{_VERSION.version_major}.{_VERSION.version_minor}.{_VERSION.version_patch}"
"""The OSI version of the messages written (``osi-python``'s)."""

FAN_POINTS = 32
"""Points on the arc of a field of view's fan in ``virtual_detection_area``."""


def sensor_pose(sensor: Sensor | None, ego_box: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The sensor's origin (metres, world) and its axes (columns, world) on the observer's box (x, y, z, length,
    width, height, roll, pitch, yaw); None: the box's centre, along its heading."""
    x, y, z, _, _, height, _, _, yaw = ego_box
    if sensor is None:
        return np.array([x, y, z]), rotations(np.zeros(1), np.zeros(1), np.array([yaw]))[0]
    position, heading = sensor_poses(sensor, np.array([[x, y]]), np.array([yaw]))
    origin = np.array([position[0, 0], position[0, 1], z - height / 2 + sensor.z])
    return origin, rotations(np.zeros(1), np.array([sensor.pitch]), heading)[0]


def sensor_data(
    nanos: int,
    ego: int,
    ego_box: np.ndarray,
    sensor: Sensor | None,
    sensor_id: int,
    seen: Iterable[tuple[int, np.ndarray]],
) -> SensorData:
    """One frame's ``SensorData`` (see the module docstring): ``seen`` holds ``(idx, box)`` of every road user the
    table calls visible or partly visible."""
    message = SensorData()
    message.version.version_major = _VERSION.version_major
    message.version.version_minor = _VERSION.version_minor
    message.version.version_patch = _VERSION.version_patch
    message.timestamp.seconds, message.timestamp.nanos = int(nanos) // 1_000_000_000, int(nanos) % 1_000_000_000
    message.sensor_id.value = int(sensor_id)
    host = message.host_vehicle_location
    hx, hy, hz, hl, hw, hh, hr, hp, hyaw = (float(v) for v in ego_box)
    host.position.x, host.position.y, host.position.z = hx, hy, hz
    host.orientation.roll, host.orientation.pitch, host.orientation.yaw = hr, hp, hyaw
    host.dimension.length, host.dimension.width, host.dimension.height = hl, hw, hh
    origin, axes = sensor_pose(sensor, ego_box)
    if sensor is not None:
        height = float(ego_box[5])
        mount = message.mounting_position
        mount.position.x, mount.position.y, mount.position.z = sensor.x, sensor.y, sensor.z - height / 2
        mount.orientation.yaw, mount.orientation.pitch = sensor.yaw, sensor.pitch
        if sensor.fov < 2 * math.pi and math.isfinite(sensor.range):
            polygon = message.virtual_detection_area.polygon.add()
            polygon.vertex.add()
            for a in np.linspace(-sensor.fov / 2, sensor.fov / 2, FAN_POINTS):
                vertex = polygon.vertex.add()
                vertex.x, vertex.y = sensor.range * math.cos(a), sensor.range * math.sin(a)
    seen = list(seen)
    if not seen:
        return message
    ids = [int(i) for i, _ in seen]
    boxes = np.array([b for _, b in seen], dtype=np.float64).reshape(-1, 9)
    local = (boxes[:, :3] - origin) @ axes  # each centre in the sensor's frame
    turn = np.einsum("ji,njk->nik", axes, rotations(boxes[:, 6], boxes[:, 7], boxes[:, 8]))
    pitch = -np.arcsin(np.clip(turn[:, 2, 0], -1.0, 1.0))
    roll, yaw = np.arctan2(turn[:, 2, 1], turn[:, 2, 2]), np.arctan2(turn[:, 1, 0], turn[:, 0, 0])
    numbers = np.column_stack([local, roll, pitch, yaw, boxes[:, 3:6]]).tolist()
    for idx, (x, y, z, r, p, w, length, width, height) in zip(ids, numbers, strict=True):
        item = message.moving_object.add()
        header = item.header
        header.ground_truth_id.add().value = idx
        header.tracking_id.value = idx
        header.existence_probability = 1.0
        header.measurement_state = DetectedItemHeader.MEASUREMENT_STATE_MEASURED
        header.sensor_id.add().value = int(sensor_id)
        base = item.base
        base.position.x, base.position.y, base.position.z = x, y, z
        base.orientation.roll, base.orientation.pitch, base.orientation.yaw = r, p, w
        base.dimension.length, base.dimension.width, base.dimension.height = length, width, height
    return message


def osi_trace_bytes(messages: Iterable[bytes]) -> bytes:
    """Serialized messages as a single-channel ``.osi`` trace: each after its length (four bytes, little-endian).

    >>> osi_trace_bytes([b"ab", b""])
    b'\\x02\\x00\\x00\\x00ab\\x00\\x00\\x00\\x00'
    """
    return b"".join(struct.pack("<I", len(m)) + m for m in messages)
