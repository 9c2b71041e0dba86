"""One sensor's scene: the frame's convex bodies relative to its eye and turned into its own frame, with what the
counting needs of them (each body's vertex and edge ranges, which are targets, their distances, which pairs
overlap).

Sensor frames: a camera's is OpenCV's (``x`` right, ``y`` down, ``z`` forward); a lidar's is the vehicle's (``x``
forward, ``y`` left, ``z`` up along its spin axis). Both follow from the sensor's heading (radians
counter-clockwise from +x) and pitch (radians, positive looking down).

>>> (np.round(sensor_axes(0.0, 0.0, "camera"), 12) + 0.0).tolist()  # rows: the camera's x, y, z in the world
[[0.0, -1.0, 0.0], [0.0, 0.0, -1.0], [1.0, 0.0, 0.0]]
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from ..._compiled.kernel import njit
from ...threed.bodies import ConvexBodies


def sensor_axes(heading: float, pitch: float, kind: str) -> np.ndarray:
    """The sensor's axes as rows, in world coordinates: world vector ``w`` is ``axes @ w`` in the sensor frame."""
    ch, sh, cp, sp = math.cos(heading), math.sin(heading), math.cos(pitch), math.sin(pitch)
    forward = np.array([ch * cp, sh * cp, -sp])
    left = np.array([-sh, ch, 0.0])
    up = np.cross(forward, left)
    if kind == "camera":
        return np.stack([-left, -up, forward])
    return np.stack([forward, left, up])


@dataclass(frozen=True, slots=True)
class SensorScene:
    """The bodies one sensor sees, in its frame (metres, eye at the origin).

    Attributes
    ----------
    vertices : ndarray, shape (v, 3)
    vstart, estart : ndarray, shape (n + 1,), int64
        Body ``k``'s vertices are ``vertices[vstart[k]:vstart[k + 1]]``, its edges ``edges[estart[k]:...]``.
    edges : ndarray, shape (e, 2), int64
    normals, offsets : ndarray, shape (n, p, 3) and (n, p)
        Face planes ``normals . x <= offsets``.
    slot : ndarray, shape (n,), int64
        The target number of each body (-1: it only blocks).
    near, far : ndarray, shape (n,)
        Metres from the eye to each target's nearest and farthest point (others: 0 and inf).
    overlap : ndarray, shape (t, n), bool
        Whether target ``g``'s inside may overlap body ``k``'s (their order is then decided ray by ray).
    source : ndarray, shape (n,), int64
        What each body stands for, as :class:`..threed.bodies.ConvexBodies` has it.
    """

    vertices: np.ndarray
    vstart: np.ndarray
    edges: np.ndarray
    estart: np.ndarray
    normals: np.ndarray
    offsets: np.ndarray
    slot: np.ndarray
    near: np.ndarray
    far: np.ndarray
    centre: np.ndarray
    radius: np.ndarray
    overlap: np.ndarray
    source: np.ndarray

    def __len__(self) -> int:
        return len(self.slot)

    def body_arrays(self) -> tuple:
        """``(vertices, vstart, edges, estart, normals, offsets, centre, radius)``, as the kernels take them."""
        return (self.vertices, self.vstart, self.edges, self.estart, self.normals, self.offsets, self.centre,
                self.radius)  # fmt: skip

    def target_arrays(self) -> tuple:
        """``(slot, near, far, overlap)``, as the kernels take them."""
        return self.slot, self.near, self.far, self.overlap


def sensor_scene(bodies: ConvexBodies, targets: np.ndarray, axes: np.ndarray, near: np.ndarray) -> SensorScene:
    """``bodies`` (relative to the eye) in the sensor frame of ``axes`` (:func:`sensor_axes`); ``targets`` are
    the positions of the bodies to count for (ascending), ``near`` their nearest distances (metres)."""
    n = len(bodies)
    vertices = np.ascontiguousarray(bodies.vertices @ axes.T)
    normals = np.ascontiguousarray(bodies.normals @ axes.T)
    vstart = np.searchsorted(bodies.vertex_body, np.arange(n + 1)).astype(np.int64)
    estart = np.searchsorted(bodies.edge_body, np.arange(n + 1)).astype(np.int64)
    slot = np.full(n, -1, dtype=np.int64)
    targets = np.asarray(targets, dtype=np.int64)
    slot[targets] = np.arange(len(targets))
    reach = np.linalg.norm(vertices, axis=1)
    far = np.full(n, np.inf)
    far_all = np.zeros(n)
    np.maximum.at(far_all, bodies.vertex_body, reach)
    far[targets] = far_all[targets]
    near_all = np.zeros(n)
    near_all[targets] = near
    offsets = np.ascontiguousarray(bodies.offsets, dtype=np.float64)
    centre, radius = bodies.bounding_spheres()
    centre = np.ascontiguousarray(centre @ axes.T)  # (the sphere turned with the bodies into the sensor frame)
    overlap = np.full((len(targets), n), -1, dtype=np.int8)
    return SensorScene(
        vertices, vstart, np.ascontiguousarray(bodies.edges, dtype=np.int64), estart, normals, offsets, slot,
        near_all, far, centre, radius, overlap, bodies.source,
    )  # fmt: skip


OVERLAP_MARGIN = 1e-6
"""Metres: bodies that only touch (a shared face, within this) do not overlap; their order is the same along every
ray that meets both."""


@njit(cache=True)
def _separated(vertices, vstart, normals, offsets, k, other):
    """Whether some face plane of body ``k`` has all of ``other``'s vertices on or beyond it."""
    for p in range(normals.shape[1]):
        nx, ny, nz, c = normals[k, p, 0], normals[k, p, 1], normals[k, p, 2], offsets[k, p]
        if nx == 0.0 and ny == 0.0 and nz == 0.0:
            continue
        beyond = True
        for i in range(vstart[other], vstart[other + 1]):
            if nx * vertices[i, 0] + ny * vertices[i, 1] + nz * vertices[i, 2] < c - OVERLAP_MARGIN:
                beyond = False
                break
        if beyond:
            return True
    return False


@njit(cache=True)
def pair_overlaps(vertices, vstart, normals, offsets, centre, radius, k, other):
    """Whether the insides of bodies ``k`` and ``other`` may overlap: False when their bounding spheres are apart
    or a face plane of one has all of the other's vertices on or beyond it. Conservative: a pair separated only
    along an edge-edge direction is ordered ray by ray, which costs time, never exactness."""
    d0, d1, d2 = centre[k, 0] - centre[other, 0], centre[k, 1] - centre[other, 1], centre[k, 2] - centre[other, 2]
    if math.sqrt(d0 * d0 + d1 * d1 + d2 * d2) > radius[k] + radius[other] + OVERLAP_MARGIN:
        return False
    if _separated(vertices, vstart, normals, offsets, k, other):
        return False
    return not _separated(vertices, vstart, normals, offsets, other, k)
