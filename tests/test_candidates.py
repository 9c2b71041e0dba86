"""Candidate (body, target) pairs from one viewpoint (geometry/candidates.py): over random scenes (boxes, and
L-shaped static bodies) at small and at map coordinates, extents across the +-pi seam and queues of touching extents,
the candidates hold every pair of objects that testing every edge against every target gives, with its certainty
(a static body only where one of its edges comes nearer than the target within the target's bearings); the pairs
accepted at once occlude by the exact test; decided by the exact test, the candidates give exactly the occluders
of every edge's pairs, and the same targets hidden behind one object."""

from __future__ import annotations

import math

import numpy as np
import pytest
import shapely

from omega_prime_visibility.geometry.candidates import MIN_PIECE, candidate_pairs, certainly_occludes
from omega_prime_visibility.geometry.kernels import nearest_offset
from omega_prime_visibility.geometry.occlusion import occludes
from omega_prime_visibility.geometry.rings import Rings, angular_extent


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


def box_edges(cx: float, cy: float, lx: float, ly: float) -> list:
    corners = [
        (cx - lx / 2, cy - ly / 2),
        (cx + lx / 2, cy - ly / 2),
        (cx + lx / 2, cy + ly / 2),
        (cx - lx / 2, cy + ly / 2),
    ]
    return [[corners[k], corners[(k + 1) % 4]] for k in range(4)]


def l_shape_edges(cx: float, cy: float, size: float) -> list:
    """An L-shaped building (concave), ``size`` metres across, its corner at ``(cx, cy)``."""
    a, b = size, size / 3
    ring = [(cx, cy), (cx + a, cy), (cx + a, cy + b), (cx + b, cy + b), (cx + b, cy + a), (cx, cy + a)]
    return [[ring[k], ring[(k + 1) % len(ring)]] for k in range(len(ring))]


@pytest.mark.parametrize("seed", range(16))
@pytest.mark.parametrize("offset", [0.0, 6.0e5], ids=["small", "map coordinates"])
def test_candidates_decide_exactly_the_occluders_of_every_edge(seed: int, offset: float) -> None:
    rng = np.random.default_rng(seed)
    n = int(rng.integers(5, 60))
    centres = rng.uniform(-40, 40, (n, 2))
    if seed % 3 == 0:  # bodies along the -x axis: extents across the +-pi seam
        centres[: n // 2] = np.column_stack([rng.uniform(-40, -5, n // 2), rng.uniform(-1.5, 1.5, n // 2)])
    if seed % 5 == 2:  # a queue: bodies in a row along one bearing, touching extents
        centres[: n // 2] = np.column_stack([np.arange(n // 2) * 5.0 + 6.0, np.zeros(n // 2)])
    sizes = rng.uniform(0.3, 12.0, (n, 2))
    if seed % 5 == 2:
        sizes[: n // 2] = (4.5, 1.8)
    object_rings = [
        np.array(box_edges(cx, cy, lx, ly))[:, 0] for (cx, cy), (lx, ly) in zip(centres, sizes, strict=True)
    ]
    if seed % 4 == 1:  # a U-shaped object round the viewpoint: a concave extent wider than half a turn
        turn = rng.uniform(-math.pi, math.pi)
        u = np.array([(-3, 5), (5, 5), (5, -5), (-3, -5), (-3, -4), (4, -4), (4, 4), (-3, 4)], dtype=float)
        object_rings[0] = u @ np.array([[math.cos(turn), math.sin(turn)], [-math.sin(turn), math.cos(turn)]])
    seg, seg_body = [], []
    for b, ring in enumerate(object_rings):
        seg += [[ring[k], ring[(k + 1) % len(ring)]] for k in range(len(ring))]
        seg_body += [b] * len(ring)
    n_static = int(rng.integers(1 if seed % 4 == 1 else 0, 4))
    for k in range(n_static):  # static bodies (n, n + 1, ...): L-shapes and thin triangles reaching round
        if k == 0 and seed % 4 == 1:  # far beyond one end of the U's extent, near in front of its other arm
            a = turn + math.radians(124.0 + rng.uniform(-1.0, 1.0))
            b = turn - math.radians(110.0 + rng.uniform(-5.0, 5.0))
            ring = [40 * np.array([math.cos(a), math.sin(a)]), 40 * np.array([math.cos(a + 0.02), math.sin(a + 0.02)]),
                    3.5 * np.array([math.cos(b), math.sin(b)])]  # fmt: skip
            edges_of = [[ring[q], ring[(q + 1) % 3]] for q in range(3)]
        else:
            edges_of = l_shape_edges(*rng.uniform(-60, 60, 2), float(rng.uniform(4.0, 30.0)))
        seg += edges_of
        seg_body += [n + k] * len(edges_of)
    seg = np.asarray(seg, dtype=float) + offset
    seg_body = np.asarray(seg_body, dtype=np.int64)
    blocking = np.concatenate([rng.random(n) < 0.85, rng.random(n_static) < 0.9])
    ox = oy = offset
    # bodies containing the viewpoint are transparent to it (the engines' policy), and no target
    rings = [shapely.Polygon(seg[seg_body == b, 0]) for b in range(n + n_static)]
    outside = ~shapely.intersects(rings, shapely.Point(ox, oy))
    blocking &= outside
    coords = np.concatenate(object_rings) + offset
    ring_offsets = np.concatenate([[0], np.cumsum([len(r) for r in object_rings])]).astype(np.int64)
    start, width, _ = angular_extent(np.array([ox, oy]), Rings(coords, ring_offsets))
    if seed % 4 == 1:
        assert width[0] > math.pi and outside[0]
    targets = np.flatnonzero((rng.random(n) < 0.7) & outside[:n]).astype(np.int64)
    body, target, certain, hidden = candidate_pairs(ox, oy, seg, seg_body, blocking, targets, start, width, n)
    want, want_hidden = every_edge(ox, oy, seg, seg_body, blocking, targets, start, width, n)
    found = {(b, t): c for b, t, c in zip(body.tolist(), target.tolist(), certain.tolist(), strict=True)}
    assert len(found) == len(body), "a pair found twice"
    for b, t, c in want:  # every edge's pairs of objects are among the candidates, with the same certainty
        if b < n:
            assert (b, t) in found and found[(b, t)] == c
    assert not any(found[(b, t)] for (b, t) in set(found) - {(b, t) for b, t, _ in want}), "an extra pair accepted"
    seg_offsets = np.zeros(n + n_static + 1, dtype=np.int64)
    np.cumsum(np.bincount(seg_body, minlength=n + n_static), out=seg_offsets[1:])
    origin = np.array([ox, oy])

    def decided(pairs: list[tuple[int, int, bool]]) -> set[tuple[int, int]]:
        b = np.array([p[0] for p in pairs], dtype=np.int64)
        t = np.array([p[1] for p in pairs], dtype=np.int64)
        exact = occludes(origin, seg, seg_offsets, b, t, start, width)
        assert all(exact[[p[2] for p in pairs]]) if pairs else True, "a pair accepted at once does not occlude"
        return {(p[0], p[1]) for p, e in zip(pairs, exact, strict=True) if e}

    assert decided([(b, t, c) for (b, t), c in found.items()]) == decided(want)
    assert np.array_equal(hidden, want_hidden)


def test_a_wall_beside_a_target_is_no_candidate_unless_nearer_within_its_bearings() -> None:
    """On paper: the observer at the origin, a car (a 2 m square) centred at (20, 0): bearings -3.01 to 3.01
    degrees (atan(1 / 19)), farthest point 21.02 m away, nearest 19 m.

    - A wall along the street from (5, 1.2) to (40, 1.2): its nearest point is 5.14 m away and its bearings (1.72 to
      13.5 degrees) meet the car's, but within 1.72 to 3.01 degrees it lies 1.2 / sin(3.01 deg) = 22.85 m away or
      more, behind the car's farthest point: no pair.
    - From (5, 3) to (40, 3): bearings 4.29 to 31 degrees, beside the car's: no pair.
    - From (5, 0.5) to (15, 0.5): bearings 1.91 to 5.71 degrees; within 1.91 to 3.01 degrees it lies 9.5 to 15 m
      away, all of it nearer than the car: a pair, and certain.
    - Across the street, from (10, -3) to (10, 3): a pair, and certain.
    """
    car = [[(19, -1), (21, -1)], [(21, -1), (21, 1)], [(21, 1), (19, 1)], [(19, 1), (19, -1)]]
    angles = np.arctan2([-1, -1, 1, 1], [19, 21, 21, 19])
    start, width = np.array([angles.min()]), np.array([np.ptp(angles)])
    walls = [
        (((5, 1.2), (40, 1.2)), False),
        (((5, 3), (40, 3)), False),
        (((5, 0.5), (15, 0.5)), True),
        (((10, -3), (10, 3)), True),
    ]
    for wall, pair in walls:
        seg = np.array([*car, wall], dtype=float)
        seg_body = np.array([0, 0, 0, 0, 1], dtype=np.int64)
        blocking = np.array([True, True])
        body, _, certain, _ = candidate_pairs(0.0, 0.0, seg, seg_body, blocking, np.array([0]), start, width, 1)
        assert body.tolist() == ([1] if pair else [])
        assert certain.all()


def test_a_wall_meeting_a_wide_target_twice_is_found() -> None:
    """A U-shaped target around the observer's side, (-3, 5), (5, 5), (5, -5), (-3, -5), (-3, -4), (4, -4), (4, 4),
    (-3, 4): its extent runs from -126.9 degrees round through 0 to 126.9 degrees (253.7 degrees), its farthest
    point 7.07 m away. A thin static triangle from 40 m out at 124 to 125 degrees to 3.5 m out at -110 degrees: each
    long edge meets the extent in two pieces, 124 to 126.9 degrees (23 to 40 m away, behind the target) and -126.9
    to -110 degrees (2.9 to 3.5 m away, in front of its arm). The pair is kept and the exact test finds it hides the
    target (judging the first piece alone lost it)."""
    u = np.array([(-3, 5), (5, 5), (5, -5), (-3, -5), (-3, -4), (4, -4), (4, 4), (-3, 4)], dtype=float)
    base = [40 * np.array([np.cos(np.radians(d)), np.sin(np.radians(d))]) for d in (124.0, 125.0)]
    apex = 3.5 * np.array([np.cos(np.radians(-110.0)), np.sin(np.radians(-110.0))])
    triangle = np.array([base[0], base[1], apex])
    seg = np.array(
        [[u[k], u[(k + 1) % len(u)]] for k in range(len(u))] + [[triangle[k], triangle[(k + 1) % 3]] for k in range(3)]
    )
    seg_body = np.array([0] * len(u) + [1] * 3, dtype=np.int64)
    start, width, _ = angular_extent(np.zeros(2), Rings(u, np.array([0, len(u)])))
    assert np.degrees(width[0]) == pytest.approx(253.74, abs=0.01)
    body, target, certain, _ = candidate_pairs(
        0.0, 0.0, seg, seg_body, np.array([True, True]), np.array([0]), start, width, 1
    )
    assert body.tolist() == [1] and not certain[0]
    offsets = np.array([0, len(u), len(u) + 3], dtype=np.int64)
    assert occludes(np.zeros(2), seg, offsets, body, target, start, width).tolist() == [True]


def test_a_static_edge_is_accepted_only_nearer_by_its_margin() -> None:
    """:func:`certainly_occludes` on paper: an object entirely nearer is accepted by any overlap wider than
    MIN_PIECE; a static edge needs 1e-9 rad and to lie a millionth (1e-7) nearer than the target's nearest point."""
    assert certainly_occludes(2 * MIN_PIECE, 9.999, True, 10.0)
    assert not certainly_occludes(MIN_PIECE / 2, 9.0, True, 10.0)
    assert certainly_occludes(2e-9, 10.0 * (1 - 2e-7), False, 10.0)
    assert not certainly_occludes(2e-9, 10.0 * (1 - 5e-8), False, 10.0)
    assert not certainly_occludes(5e-10, 5.0, False, 10.0)
