"""An independent brute-force caster of camera pixels and lidar beams, to check the counting engine against.

Written from scratch with numpy: every pixel's centre ray (or every beam of a lidar's turn) is cast and met with
every box (slab test in the box's own axes) and every upright prism over a convex footprint (the footprint's edge
half-planes and a z slab). Definitions, the package's own (``docs``: Cameras and lidars):

* a ray meets a body where its entry ``t_in <= t_out`` (a graze counts) with ``t_in > 0``;
* a target is met *first* along a ray when no other body is entered before it by more than ``1e-9`` of its
  distance; it counts when, besides, its entry lies within the range (metres);
* the observer's own body never blocks (it is simply not given here).

Camera frame: x right, y down, z forward; pixel (u, v) has its centre ray ``((u + 0.5 - cx) / fx,
(v + 0.5 - cy) / fy, 1)``. Lidar: beam (k, e) along ``(cos e cos(k step), cos e sin(k step), sin e)`` in the
sensor frame (x forward, y left, z up).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

TIE = 1e-9


def world_axes(heading: float, pitch: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Forward, left, up of a sensor with ``heading`` (radians ccw from +x) and ``pitch`` (positive down)."""
    forward = np.array([math.cos(heading) * math.cos(pitch), math.sin(heading) * math.cos(pitch), -math.sin(pitch)])
    left = np.array([-math.sin(heading), math.cos(heading), 0.0])
    return forward, left, np.cross(forward, left)


def camera_rays(width, height, fx, fy, cx, cy, heading, pitch):
    """World directions of every pixel centre, shape (height, width, 3)."""
    forward, left, up = world_axes(heading, pitch)
    u = (np.arange(width) + 0.5 - cx) / fx
    v = (np.arange(height) + 0.5 - cy) / fy
    return forward + u[None, :, None] * (-left) + v[:, None, None] * (-up)


def lidar_rays(elevations, step, heading, pitch):
    """World directions of every beam of a turn, shape (channels, azimuths, 3)."""
    forward, left, up = world_axes(heading, pitch)
    n_az = max(1, math.ceil(2 * math.pi / step - 1e-9))
    phi = np.arange(n_az) * step
    e = np.asarray(elevations, dtype=np.float64)[:, None]
    return (
        (np.cos(e) * np.cos(phi))[..., None] * forward
        + (np.cos(e) * np.sin(phi))[..., None] * left
        + np.sin(e)[..., None] * up
    )


def _box_axes(roll, pitch, yaw):
    cr, sr, cp, sp = math.cos(roll), math.sin(roll), math.cos(pitch), math.sin(pitch)
    cy, sy = math.cos(yaw), math.sin(yaw)
    return np.array(
        [
            [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
            [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
            [-sp, cp * sr, cp * cr],
        ]
    )


def _slabs(origin, rays, normals, lows, highs):
    """Entry and exit of rays (shape (..., 3)) through the slabs ``low <= normal . x <= high``."""
    t_in = np.zeros(rays.shape[:-1])
    t_out = np.full(rays.shape[:-1], np.inf)
    miss = np.zeros(rays.shape[:-1], dtype=bool)
    for normal, low, high in zip(normals, lows, highs, strict=True):
        g = rays @ normal
        o = float(origin @ normal)
        with np.errstate(divide="ignore", invalid="ignore"):
            a = (low - o) / g
            b = (high - o) / g
        inside = low <= o <= high
        lo = np.where(g != 0, np.minimum(a, b), -np.inf if inside else np.inf)
        hi = np.where(g != 0, np.maximum(a, b), np.inf if inside else -np.inf)
        t_in = np.maximum(t_in, lo)
        t_out = np.minimum(t_out, hi)
        if not inside:
            miss |= g == 0
    hit = (t_in <= t_out + TIE * np.maximum(t_out, 1.0)) & ~miss & (t_out > 0)
    return np.where(hit, t_in, np.inf)


def box_entries(origin, rays, box):
    """Entry parameter (units of each ray's length) of ``rays`` from ``origin`` into a box (x, y, z, length, width,
    height, roll, pitch, yaw); inf where it misses."""
    x, y, z, length, width, height, roll, pitch, yaw = box
    axes = _box_axes(roll, pitch, yaw).T  # rows: the box's axes
    centre = np.array([x, y, z])
    half = np.array([length, width, height]) / 2
    c = axes @ centre
    return _slabs(origin, rays, axes, c - half, c + half)


def prism_entries(origin, rays, footprint, base, top):
    """Entry of ``rays`` into the upright prism over the convex ``footprint`` (k, 2) from ``base`` to ``top``."""
    ring = np.asarray(footprint, dtype=np.float64)
    area = 0.5 * np.sum(ring[:, 0] * np.roll(ring[:, 1], -1) - np.roll(ring[:, 0], -1) * ring[:, 1])
    if area < 0:
        ring = ring[::-1]
    normals, lows, highs = [np.array([0.0, 0.0, 1.0])], [base], [top]
    for p, q in zip(ring, np.roll(ring, -1, axis=0), strict=True):
        edge = q - p
        n = np.array([edge[1], -edge[0], 0.0]) / math.hypot(*edge)  # outward for a counter-clockwise ring
        normals.append(n)
        lows.append(-np.inf)
        highs.append(float(n[:2] @ p))
    return _slabs(origin, rays, normals, lows, highs)


@dataclass
class Counts:
    first: np.ndarray  # (targets,) met first within range
    unoccluded: np.ndarray  # (targets,) met within range
    met: np.ndarray  # (targets,) met at all
    first_box: np.ndarray  # (targets, 4) (j0, line0, j1, line1), -1 when empty
    unoccluded_box: np.ndarray
    hidden_by: list  # per target, the set of body numbers entered before it along a counted ray


def cast(origin, rays, boxes, prisms=(), max_range=math.inf):
    """Counts for every box (the targets) among ``boxes`` and ``prisms`` (footprint, base, top) along ``rays``
    (shape (lines, samples, 3): a camera's (rows, columns), a lidar's (channels, azimuths))."""
    origin = np.asarray(origin, dtype=np.float64)
    entries = [box_entries(origin, rays, b) for b in boxes] + [prism_entries(origin, rays, *p) for p in prisms]
    t = np.stack(entries)  # (bodies, lines, samples)
    length = np.linalg.norm(rays, axis=-1)
    n = len(boxes)
    first = np.zeros(n, dtype=np.int64)
    unoccluded = np.zeros(n, dtype=np.int64)
    met = np.zeros(n, dtype=np.int64)
    boxes_first = np.full((n, 4), -1, dtype=np.int64)
    boxes_unoccluded = np.full((n, 4), -1, dtype=np.int64)
    hidden_by = [set() for _ in range(n)]
    for g in range(n):
        mine = t[g]
        hit = np.isfinite(mine)
        met[g] = hit.sum()
        in_range = hit & (mine * length <= max_range)
        unoccluded[g] = in_range.sum()
        before = t < mine[None] * (1 - TIE)
        before[g] = False
        hidden = before.any(axis=0)
        seen = in_range & ~hidden
        first[g] = seen.sum()
        for mask, box in ((seen, boxes_first), (in_range, boxes_unoccluded)):
            lines, samples = np.nonzero(mask)
            if len(lines):
                box[g] = (samples.min(), lines.min(), samples.max(), lines.max())
        for k in np.flatnonzero((before & in_range[None]).any(axis=(1, 2))):
            hidden_by[g].add(int(k))
    return Counts(first, unoccluded, met, boxes_first, boxes_unoccluded, hidden_by)
