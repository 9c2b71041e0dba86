"""Oriented 3D boxes: rotations in OSI's order, corners, triangles, ray-box distances and the eye point.

A set of boxes is an array of shape ``(n, 9)``, one row per box, columns :data:`BOX3D_COLUMNS`:
``x, y, z`` the centre of the box (metres, as OSI's ``position`` of a bounding box), ``length, width, height``
its full extents along its own x (forward), y (left) and z (up) axes, and ``roll, pitch, yaw`` (radians).

Orientation follows OSI: the box is turned by ``yaw`` about the world's z axis, then by ``pitch`` about its new
y axis, then by ``roll`` about its new x axis, ``R = Rz(yaw) @ Ry(pitch) @ Rx(roll)``. Signs: positive ``yaw``
turns counter-clockwise seen from above, positive ``pitch`` lowers the nose (the box's +x axis turns towards
-z), positive ``roll`` raises the left side (its +y axis turns towards +z). The ground under an object is at
``z - height / 2`` (its unrotated bottom).

>>> import numpy as np
>>> box = np.array([[10.0, 0.0, 0.75, 4.0, 2.0, 1.5, 0.0, 0.0, 0.0]])
>>> corners(box)[0].min(axis=0).tolist(), corners(box)[0].max(axis=0).tolist()
([8.0, -1.0, 0.0], [12.0, 1.0, 1.5])
>>> float(ray_box_entry(np.zeros(3), np.array([1.0, 0.0, 0.05]), box[0]))
8.0
"""

from __future__ import annotations

import math

import numpy as np

from .._compiled.kernel import njit

BOX3D_COLUMNS = ("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw")
"""Column order of a box array."""

# the 8 corners of the unit box in units of half-extents, and its 12 triangles (outward, counter-clockwise)
_SIGNS = np.array([[sx, sy, sz] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)], dtype=np.float64)
_TRIANGLES = np.array(
    [
        [0, 1, 3], [0, 3, 2],  # -x
        [4, 6, 7], [4, 7, 5],  # +x
        [0, 4, 5], [0, 5, 1],  # -y
        [2, 3, 7], [2, 7, 6],  # +y
        [0, 2, 6], [0, 6, 4],  # -z
        [1, 5, 7], [1, 7, 3],  # +z
    ],
    dtype=np.int64,
)  # fmt: skip
EDGES = np.array([[a, b] for a in range(8) for b in range(a + 1, 8) if bin(a ^ b).count("1") == 1], dtype=np.int64)
"""The 12 edges of a box as pairs of corner numbers."""


def rotations(roll: np.ndarray, pitch: np.ndarray, yaw: np.ndarray) -> np.ndarray:
    """Rotation matrices ``Rz(yaw) @ Ry(pitch) @ Rx(roll)``, shape (n, 3, 3); columns are the box's axes.

    >>> np.round(rotations(np.zeros(1), np.array([np.pi / 2]), np.zeros(1))[0] @ [1, 0, 0], 12).tolist()
    [0.0, 0.0, -1.0]
    """
    roll, pitch, yaw = (np.atleast_1d(np.asarray(a, dtype=np.float64)) for a in (roll, pitch, yaw))
    cr, sr, cp, sp, cy, sy = np.cos(roll), np.sin(roll), np.cos(pitch), np.sin(pitch), np.cos(yaw), np.sin(yaw)
    r = np.empty((len(roll), 3, 3))
    r[:, 0, 0] = cy * cp
    r[:, 0, 1] = cy * sp * sr - sy * cr
    r[:, 0, 2] = cy * sp * cr + sy * sr
    r[:, 1, 0] = sy * cp
    r[:, 1, 1] = sy * sp * sr + cy * cr
    r[:, 1, 2] = sy * sp * cr - cy * sr
    r[:, 2, 0] = -sp
    r[:, 2, 1] = cp * sr
    r[:, 2, 2] = cp * cr
    return r


def frames(boxes: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Centres (n, 3), rotations (n, 3, 3) and half-extents (n, 3) of ``boxes``, each C-contiguous (so the
    compiled kernels taking them are compiled once, whatever the number of boxes)."""
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 9)
    return np.ascontiguousarray(boxes[:, 0:3]), rotations(boxes[:, 6], boxes[:, 7], boxes[:, 8]), boxes[:, 3:6] / 2


def corners(boxes: np.ndarray, frame: tuple | None = None) -> np.ndarray:
    """The 8 corners of each box, shape (n, 8, 3), metres; corner ``k`` has signs ``_SIGNS[k]`` (x, y, z).
    ``frame``: :func:`frames` of ``boxes`` when already known."""
    centre, rot, half = frames(boxes) if frame is None else frame
    local = _SIGNS[None, :, :] * half[:, None, :]
    return centre[:, None, :] + np.einsum("nij,nkj->nki", rot, local)


def triangles(boxes: np.ndarray) -> np.ndarray:
    """The 12 triangles of each box's surface, shape (n, 12, 3, 3)."""
    return corners(boxes)[:, _TRIANGLES]


def contains(boxes: np.ndarray, point: np.ndarray, tolerance: float = 1e-9, frame: tuple | None = None) -> np.ndarray:
    """Which boxes contain (or touch) ``point`` (shape (3,)), shape (n,) bool.

    >>> contains(np.array([[0.0, 0, 0.75, 4, 2, 1.5, 0, 0, 0]]), np.array([1.0, 0.5, 1.25])).tolist()
    [True]
    """
    centre, rot, half = frames(boxes) if frame is None else frame
    local = np.einsum("nji,nj->ni", rot, np.asarray(point, dtype=np.float64)[None, :] - centre)
    return (np.abs(local) <= half + tolerance).all(axis=1)


@njit(cache=True, inline="always")
def _slab(origin, direction, centre, rot, half):
    """Entry and exit distances of the ray ``origin + t * direction`` (t >= 0) through a box; (inf, -inf): missed."""
    t0, t1 = 0.0, np.inf
    for k in range(3):
        o = 0.0
        d = 0.0
        for j in range(3):
            o += rot[j, k] * (origin[j] - centre[j])
            d += rot[j, k] * direction[j]
        if d == 0.0:
            if abs(o) > half[k]:
                return np.inf, -np.inf
            continue
        a = (-half[k] - o) / d
        b = (half[k] - o) / d
        if a > b:
            a, b = b, a
        t0 = max(t0, a)
        t1 = min(t1, b)
    if t0 > t1:
        return np.inf, -np.inf
    return t0, t1


@njit(cache=True)
def ray_entries(origin, directions, centres, rots, halves, which):
    """Entry distance of every ray (rows of ``directions``, any length) into box ``which[i]``; inf where missed.

    Distances are in units of the direction's length (metres for unit directions).
    """
    out = np.empty(len(directions))
    for i in range(len(directions)):
        b = which[i]
        out[i] = _slab(origin, directions[i], centres[b], rots[b], halves[b])[0]
    return out


def ray_box_entry(origin: np.ndarray, direction: np.ndarray, box: np.ndarray) -> float:
    """Distance along ``direction`` (a unit vector) from ``origin`` to where the ray enters ``box`` (one row,
    shape (9,)); 0 when ``origin`` is inside, inf when the ray misses it."""
    centre, rot, half = frames(box)
    d = np.asarray(direction, dtype=np.float64).reshape(1, 3)
    return float(ray_entries(np.asarray(origin, dtype=np.float64), d, centre, rot, half, np.zeros(1, np.int64))[0])


def nearest_distance(boxes: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distance (metres) from ``point`` to the nearest point of each box (0 inside), shape (n,)."""
    centre, rot, half = frames(boxes)
    local = np.einsum("nji,nj->ni", rot, np.asarray(point, dtype=np.float64)[None, :] - centre)
    return np.linalg.norm(np.maximum(np.abs(local) - half, 0.0), axis=1)


def farthest_distance(boxes: np.ndarray, point: np.ndarray) -> np.ndarray:
    """Distance (metres) from ``point`` to the farthest corner of each box, shape (n,)."""
    return np.linalg.norm(corners(boxes) - np.asarray(point, dtype=np.float64), axis=2).max(axis=1)


def eye_point(position: np.ndarray, height: float, boxes: np.ndarray | None, own: int) -> np.ndarray:
    """The 3D eye of a viewpoint at ``position`` (x, y) and ``height`` metres above the ground under the
    observing object (row ``own`` of ``boxes``: its ``z - height / 2``), or above z = 0 without one.

    >>> eye_point(np.array([1.0, 2.0]), 1.25, np.array([[0, 0, 0.8, 4, 2, 1.6, 0, 0, 0]]), 0).tolist()
    [1.0, 2.0, 1.25]
    """
    ground = 0.0 if boxes is None or own < 0 else float(boxes[own, 2] - boxes[own, 5] / 2)
    return np.array([float(position[0]), float(position[1]), ground + float(height)])


def view_limits(heading: float, fov: float, pitch: float, vertical_fov: float) -> tuple[float, float, float, float]:
    """The view as ``(heading, half horizontal fov, lowest elevation, highest elevation)``, radians.

    A direction is in view when its azimuth is within the half fov of ``heading`` and its elevation (angle above
    the horizontal plane) lies between the two limits; ``pitch`` (positive looking down) tilts the vertical
    band, which is clipped to [-π/2, π/2].
    """
    low = max(-math.pi / 2, -pitch - vertical_fov / 2)
    high = min(math.pi / 2, -pitch + vertical_fov / 2)
    return heading, fov / 2, low, high
