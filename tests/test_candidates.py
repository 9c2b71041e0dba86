"""Candidate (body, target) pairs from one viewpoint (geometry/candidates.py): the edges grouped by bearing give
exactly the pairs, in the same order, that testing every edge against every target gives, over random scenes at
small and at map coordinates, extents across the +-pi seam and near a full turn."""

from __future__ import annotations

import math

import numpy as np
import pytest

from omega_prime_visibility.geometry.candidates import MIN_PIECE, candidate_pairs
from omega_prime_visibility.geometry.kernels import nearest_offset


def wrap(angle: float) -> float:
    return angle - 2 * math.pi * math.floor(angle / (2 * math.pi))


def every_edge(ox, oy, seg, seg_body, blocking, targets, start, width, n_objects):
    """The pairs from a loop over every edge for every target (the definition)."""
    m, n_bodies = len(seg), len(blocking)
    e_start, e_width, e_near = np.empty(m), np.empty(m), np.empty(m)
    near, far = np.full(n_bodies, np.inf), np.zeros(n_bodies)
    for j in range(m):
        ax, ay, bx, by = seg[j, 0, 0] - ox, seg[j, 0, 1] - oy, seg[j, 1, 0] - ox, seg[j, 1, 1] - oy
        span = math.atan2(ax * by - ay * bx, ax * bx + ay * by)
        ta = math.atan2(ay, ax)
        e_start[j], e_width[j] = (ta if span >= 0 else ta + span), abs(span)
        dx, dy = nearest_offset(-ax, -ay, bx - ax, by - ay)
        e_near[j] = math.hypot(dx, dy)
        b = seg_body[j]
        near[b] = min(near[b], e_near[j])
        far[b] = max(far[b], math.hypot(ax, ay), math.hypot(bx, by))
    pairs, hidden, seen = [], np.zeros(n_bodies, dtype=bool), np.full(n_bodies, -1)
    for t in targets:
        for j in range(m):
            b = seg_body[j]
            if b == t or not blocking[b] or seen[b] == t or e_near[j] >= far[t]:
                continue
            rel = wrap(e_start[j] - start[t])
            if rel < width[t] or rel + e_width[j] > 2 * math.pi:
                seen[b] = t
                certain = False
                if b < n_objects and far[b] < near[t]:
                    rel2 = wrap(start[b] - start[t])
                    certain = rel2 < width[t] - MIN_PIECE or rel2 + width[b] > 2 * math.pi + MIN_PIECE
                    if wrap(start[t] - start[b]) + width[t] <= width[b]:
                        hidden[t] = True
                pairs.append((b, t, certain))
    return pairs, hidden


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("offset", [0.0, 6.0e5], ids=["small", "map coordinates"])
def test_bearing_bins_give_exactly_the_pairs_of_every_edge(seed: int, offset: float) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 60))
    centres = rng.uniform(-40, 40, (n, 2))
    if seed % 3 == 0:  # bodies along the -x axis: extents across the +-pi seam
        centres[: n // 2] = np.column_stack([rng.uniform(-40, -5, n // 2), rng.uniform(-1.5, 1.5, n // 2)])
    sizes = rng.uniform(0.3, 12.0, (n, 2))
    seg, seg_body = [], []
    for b, ((cx, cy), (lx, ly)) in enumerate(zip(centres, sizes, strict=True)):
        corners = [
            (cx - lx / 2, cy - ly / 2),
            (cx + lx / 2, cy - ly / 2),
            (cx + lx / 2, cy + ly / 2),
            (cx - lx / 2, cy + ly / 2),
        ]
        for k in range(4):
            seg.append([corners[k], corners[(k + 1) % 4]])
            seg_body.append(b)
    seg = np.asarray(seg, dtype=float) + offset
    seg_body = np.asarray(seg_body, dtype=np.int64)
    blocking = rng.random(n) < 0.85
    ox = oy = offset
    start, width = np.empty(n), np.empty(n)
    for b in range(n):  # each body's extent: its corners' bearings (boxes away from the viewpoint: under pi)
        angles = np.arctan2(seg[seg_body == b, 0, 1] - oy, seg[seg_body == b, 0, 0] - ox)
        order = np.sort(np.mod(angles - angles[0], 2 * math.pi))
        gaps = np.diff(np.concatenate([order, [order[0] + 2 * math.pi]]))
        k = int(np.argmax(gaps))
        start[b] = angles[0] + order[(k + 1) % 4]
        width[b] = 2 * math.pi - gaps[k]
    if seed % 4 == 1:
        width[0] = 2 * math.pi - 1e-10  # an extent all but a full turn
    targets = np.flatnonzero(rng.random(n) < 0.7).astype(np.int64)
    body, target, certain, hidden = candidate_pairs(ox, oy, seg, seg_body, blocking, targets, start, width, n)
    want, want_hidden = every_edge(ox, oy, seg, seg_body, blocking, targets, start, width, n)
    assert list(zip(body.tolist(), target.tolist(), certain.tolist(), strict=True)) == want
    assert np.array_equal(hidden, want_hidden)
