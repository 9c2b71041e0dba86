"""A spinning lidar's counts: per target, the beams of one turn whose first hit within range is it, and those
that meet it within range at all.

Azimuth column ``k`` (``k * azimuth_step`` counter-clockwise from the sensor's heading) is the line of rays
``(cos φ, sin φ, 0) + t (0, 0, 1)`` in the sensor frame (``x`` forward, ``y`` left, ``z`` up its spin axis),
sampled at ``t = tan`` of each elevation (:mod:`.lines`); a body can only meet the columns within its azimuths
(all of them when it lies over or under the sensor), so each column visits only those.

Cost: per column, the bodies within its azimuth (their cross-sections, a sort of their ends, one entry per body
and run); a 128-channel, 2,048-column turn (262,144 beams) never casts its beams one by one.
"""

from __future__ import annotations

import math

import numpy as np

from ..._compiled.kernel import njit
from ...inputs.lidars import BeamPattern
from .camera import line_candidates, new_counts
from .lines import count_line, workspace
from .scene import SensorScene

_TURN = 2 * math.pi


@njit(cache=True)
def _column_ranges(vertices, vstart, step, n_columns):
    """Per body the first and last azimuth column it can meet, unwrapped (``last`` may pass ``n_columns``; last <
    first: none)."""
    n = len(vstart) - 1
    first = np.zeros(n, dtype=np.int64)
    last = np.full(n, n_columns - 1, dtype=np.int64)
    for k in range(n):
        rx = 0.0
        ry = 0.0
        over = False
        for i in range(vstart[k], vstart[k + 1]):
            r = math.hypot(vertices[i, 0], vertices[i, 1])
            if r < 1e-9:
                over = True
                break
            rx += vertices[i, 0] / r
            ry += vertices[i, 1] / r
        if over or math.hypot(rx, ry) < 1e-9:
            continue
        lo = np.inf
        hi = -np.inf
        for i in range(vstart[k], vstart[k + 1]):
            x, y = vertices[i, 0], vertices[i, 1]
            rel = math.atan2(rx * y - ry * x, rx * x + ry * y)
            lo = min(lo, rel)
            hi = max(hi, rel)
        if hi - lo >= math.pi - 1e-9:  # its footprint holds the spin axis: every column
            continue
        base = math.atan2(ry, rx) % _TURN
        c0 = math.floor((base + lo) / step) - 1
        c1 = math.ceil((base + hi) / step) + 1
        if c1 - c0 + 1 >= n_columns:
            continue
        first[k] = c0 % n_columns
        last[k] = first[k] + (c1 - c0)
    return first, last


@njit(cache=True)
def _count_columns(body, target, n_targets, samples, step, n_columns, max_range):
    vertices, vstart = body[0], body[1]
    first_col, last_col = _column_ranges(vertices, vstart, step, n_columns)
    # a body whose columns wrap past the last is listed from its first to the end and from 0 on
    n = len(first_col)
    lo = np.empty(2 * n, dtype=np.int64)
    hi = np.empty(2 * n, dtype=np.int64)
    who = np.empty(2 * n, dtype=np.int64)
    m = 0
    for k in range(n):
        lo[m], hi[m], who[m] = first_col[k], min(last_col[k], n_columns - 1), k
        m += 1
        if last_col[k] >= n_columns:
            lo[m], hi[m], who[m] = 0, last_col[k] - n_columns, k
            m += 1
    cand_offsets, pieces = line_candidates(lo[:m], hi[:m], n_columns)
    cand = who[:m][pieces]
    out = new_counts(n_targets, n, 0, 0)
    work = workspace(body)
    b = np.array([0.0, 0.0, 1.0])
    a = np.zeros(3)
    for c in range(n_columns):
        phi = c * step
        a[0], a[1] = math.cos(phi), math.sin(phi)
        count_line(c, a, b, samples, cand[cand_offsets[c] : cand_offsets[c + 1]], body, target, max_range, out, work)
    return out


def lidar_counts(scene: SensorScene, pattern: BeamPattern, max_range: float) -> dict[str, np.ndarray]:
    """Per target of ``scene`` (in its slot order): ``points`` (beams met first within range),
    ``points_unoccluded`` (met within range), ``points_met`` (met at all, range ignored) and ``hidden_by``
    (targets x bodies: entered before the target along a beam that meets it within range)."""
    n_targets = int((scene.slot >= 0).sum())
    samples = np.tan(np.asarray(pattern.elevations, dtype=np.float64))
    first, unoccluded, met, _, _, hidden_by, _ = _count_columns(
        scene.body_arrays(),
        scene.target_arrays(),
        n_targets,
        samples,
        pattern.azimuth_step,
        pattern.azimuths,
        float(max_range),
    )
    return {"points": first, "points_unoccluded": unoccluded, "points_met": met, "hidden_by": hidden_by}
