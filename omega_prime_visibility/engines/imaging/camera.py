"""A pinhole camera's counts: per target, the pixels whose centre ray meets it first, meets it at all, and its
truncation by the image border.

Pixel row ``v`` is the line of rays ``(t, y_v, 1)`` in the camera frame (``y_v = (v + 0.5 - cy) / fy``) sampled at
``t_u = (u + 0.5 - cx) / fx`` (:mod:`.lines`); a body can only meet the rows between its vertices' image rows
(all of them when it reaches behind the camera), so each row visits only those. Truncation is by solid angle:
``1 -`` the steradians of the target inside the frustum (the four planes through the eye and the image's edges)
over all of its steradians (:mod:`.solid_angle`), so it holds for a target partly behind the camera too.

Cost: per row, the bodies whose image rows hold it (their cross-sections, a sort of their ends, one entry per body
and run); rays are cast one by one only where two bodies overlap or a target straddles the range. A 1920 x 1080
image never visits its 2 million pixels one by one.
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...inputs.cameras import Pinhole
from .lines import count_line, workspace
from .scene import SensorScene
from .solid_angle import body_solid_angles


@njit(cache=True)
def _row_ranges(vertices, vstart, fy, cy, height, planes):
    """Per body the first and last pixel row it can meet (last < first: none, as for a body wholly outside one of
    the frustum's ``planes``)."""
    n = len(vstart) - 1
    first = np.zeros(n, dtype=np.int64)
    last = np.full(n, height - 1, dtype=np.int64)
    for k in range(n):
        outside = False
        for p in range(len(planes)):
            out = True
            for i in range(vstart[k], vstart[k + 1]):
                if planes[p, 0] * vertices[i, 0] + planes[p, 1] * vertices[i, 1] + planes[p, 2] * vertices[i, 2] >= 0:
                    out = False
                    break
            if out:
                outside = True
                break
        if outside:
            last[k] = -1
            continue
        lo = np.inf
        hi = -np.inf
        ahead = 0
        for i in range(vstart[k], vstart[k + 1]):
            z = vertices[i, 2]
            if z > 0.0:
                ahead += 1
                y = vertices[i, 1] / z
                lo = min(lo, y)
                hi = max(hi, y)
        if ahead == 0:
            last[k] = -1  # wholly behind the camera plane
        elif ahead == vstart[k + 1] - vstart[k]:
            first[k] = max(0, math.floor(lo * fy + cy - 0.5) - 1)
            last[k] = min(height - 1, math.ceil(hi * fy + cy - 0.5) + 1)
    return first, last


@njit(cache=True)
def line_candidates(first, last, n_lines):
    """CSR of the bodies each line may meet, from each body's first and last line: ``(offsets, bodies)``."""
    offsets = np.zeros(n_lines + 1, dtype=np.int64)
    for k in range(len(first)):
        for line in range(max(first[k], 0), min(last[k], n_lines - 1) + 1):
            offsets[line + 1] += 1
    for line in range(n_lines):
        offsets[line + 1] += offsets[line]
    bodies = np.empty(offsets[-1], dtype=np.int64)
    fill = offsets[:-1].copy()
    for k in range(len(first)):
        for line in range(max(first[k], 0), min(last[k], n_lines - 1) + 1):
            bodies[fill[line]] = k
            fill[line] += 1
    return offsets, bodies


@njit(cache=True)
def new_counts(n_targets, n_bodies, lines, samples):
    """Zeroed ``(first, unoccluded, met, first_box, unoccluded_box, hidden_by, labels)`` for
    :func:`.lines.count_line`; ``labels`` is ``lines x samples`` of -1 (an empty array when ``lines`` is 0)."""
    return (
        np.zeros(n_targets, dtype=np.int64), np.zeros(n_targets, dtype=np.int64), np.zeros(n_targets, dtype=np.int64),
        np.full((n_targets, 4), -1, dtype=np.int64), np.full((n_targets, 4), -1, dtype=np.int64),
        np.zeros((n_targets, n_bodies), dtype=np.bool_), np.full((lines, samples), -1, dtype=np.int32),
    )  # fmt: skip


@njit(cache=True)
def _count_rows(body, target, n_targets, fx, fy, cx, cy, width, height, planes, max_range, label):
    vertices, vstart = body[0], body[1]
    samples = (np.arange(width) + 0.5 - cx) / fx
    first_row, last_row = _row_ranges(vertices, vstart, fy, cy, height, planes)
    cand_offsets, cand = line_candidates(first_row, last_row, height)
    out = new_counts(n_targets, len(vstart) - 1, height if label else 0, width if label else 0)
    work = workspace(body)
    b = np.array([1.0, 0.0, 0.0])
    a = np.array([0.0, 0.0, 1.0])
    for v in range(height):
        a[1] = (v + 0.5 - cy) / fy
        count_line(v, a, b, samples, cand[cand_offsets[v] : cand_offsets[v + 1]], body, target, max_range, out, work)
    return out


def frustum_planes(image: Pinhole) -> np.ndarray:
    """Inward normals (camera frame) of the four planes through the eye and the image's left, right, top and
    bottom edges: a direction ``d`` is in the image when ``planes @ d >= 0``, shape (4, 3)."""
    return np.array(
        [
            [1.0, 0.0, image.cx / image.fx],
            [-1.0, 0.0, (image.width - image.cx) / image.fx],
            [0.0, 1.0, image.cy / image.fy],
            [0.0, -1.0, (image.height - image.cy) / image.fy],
        ]
    )


def camera_counts(scene: SensorScene, image: Pinhole, max_range: float, labels: bool = False) -> dict[str, np.ndarray]:
    """Per target of ``scene`` (in its slot order): ``pixels`` (met first within range), ``pixels_unoccluded``
    (met within range), ``pixels_met`` (met at all, range ignored), ``bbox`` and ``bbox_unoccluded`` (``(u0,
    v0, u1, v1)`` inclusive, -1 when empty), ``truncation`` (share of its solid angle outside the image), and
    ``hidden_by`` (targets x bodies: entered before the target along a pixel ray that meets it within range); with
    ``labels``, also ``labels``: the image (height x width, int32) of the target each pixel meets first (-1: none).
    """
    n_targets = int((scene.slot >= 0).sum())
    first, unoccluded, met, first_box, unoccluded_box, hidden_by, label_image = _count_rows(
        scene.body_arrays(),
        scene.target_arrays(),
        n_targets,
        image.fx,
        image.fy,
        image.cx,
        image.cy,
        image.width,
        image.height,
        frustum_planes(image),
        float(max_range),
        labels,
    )
    targets = np.flatnonzero(scene.slot >= 0)
    if np.array_equal(targets, np.arange(n_targets)):  # the targets come first (as the engine lays them out)
        target_vstart, target_vertices = scene.vstart[: n_targets + 1], scene.vertices[: scene.vstart[n_targets]]
    else:
        target_vstart = np.r_[0, np.cumsum(np.diff(scene.vstart)[targets])].astype(np.int64)
        pieces = [scene.vertices[scene.vstart[k] : scene.vstart[k + 1]] for k in targets]
        target_vertices = np.concatenate(pieces or [np.zeros((0, 3))])
    whole, inside = body_solid_angles(
        target_vertices, target_vstart, scene.normals[targets], scene.offsets[targets], frustum_planes(image)
    )
    with np.errstate(divide="ignore", invalid="ignore"):
        truncation = np.where(whole > 0, np.clip(1.0 - inside / whole, 0.0, 1.0), 1.0)
    out = {
        "pixels": first,
        "pixels_unoccluded": unoccluded,
        "pixels_met": met,
        "bbox": first_box,
        "bbox_unoccluded": unoccluded_box,
        "truncation": truncation,
        "hidden_by": hidden_by,
    }
    if labels:
        out["labels"] = label_image
    return out
