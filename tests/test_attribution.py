"""Crediting a visibility polygon's edges to the bodies they lie on (engines/visilibity/attribution.py): the quick
test that a polygon edge and a body edge share no bearings never drops a pair that shares more than a rounding's
worth, over random edges at small and at map-like distances, edges through the observer and shared directions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from omega_prime_visibility.engines.visilibity.attribution import wedges_apart


def shared_bearings(p, q, a, b) -> float:
    """Radians shared by the bearings of ``p q`` and ``a b``, as the attribution measures them (arctangents)."""
    rel_a = math.atan2(p[0] * a[1] - p[1] * a[0], p[0] * a[0] + p[1] * a[1])
    rel_b = rel_a + math.atan2(a[0] * b[1] - a[1] * b[0], a[0] * b[0] + a[1] * b[1])
    span = math.atan2(p[0] * q[1] - p[1] * q[0], p[0] * q[0] + p[1] * q[1])
    return min(max(rel_a, rel_b), span) - max(min(rel_a, rel_b), 0.0)


@pytest.mark.parametrize("scale", [1.0, 3.0e3])
def test_edges_called_apart_share_no_bearings(scale: float) -> None:
    rng = np.random.default_rng(7)
    apart = together = 0
    for _ in range(20000):
        angle = rng.uniform(-math.pi, math.pi)
        span = rng.uniform(1e-6, 3.0)
        p = rng.uniform(1, 50) * scale * np.array([math.cos(angle), math.sin(angle)])
        q = rng.uniform(1, 50) * scale * np.array([math.cos(angle + span), math.sin(angle + span)])
        kind = rng.integers(4)
        if kind == 0:  # an edge starting along the polygon edge's first or last direction
            a = (
                rng.uniform(1, 50)
                * scale
                * (p if rng.random() < 0.5 else q)
                / np.hypot(*(p if rng.random() < 0.5 else q))
            )
            b = rng.uniform(-50, 50, 2) * scale
        elif kind == 1:  # an edge through the observer
            a = rng.uniform(-50, 50, 2) * scale
            b = -a * rng.uniform(0.1, 3)
        else:
            a, b = rng.uniform(-50, 50, (2, 2)) * scale
        called_apart = wedges_apart(*p, *q, *a, *b)
        shared = shared_bearings(p, q, a, b)
        if called_apart:
            apart += 1
            assert shared < 1e-12, (p, q, a, b, shared)
        together += shared > 0
    assert apart > 5000 and together > 5000  # both answers are exercised


def test_on_paper() -> None:
    # the polygon edge from (1, 0) to (0, 1): 0 to 90 degrees
    assert not wedges_apart(1.0, 0.0, 0.0, 1.0, 2.0, 1.0, 1.0, 2.0)  # 27 to 63 degrees, either way round
    assert not wedges_apart(1.0, 0.0, 0.0, 1.0, 1.0, 2.0, 2.0, 1.0)
    assert not wedges_apart(1.0, 0.0, 0.0, 1.0, 3.0, 0.0, -1.0, 1.0)  # 0 to 135 degrees: from the same direction
    assert not wedges_apart(1.0, 0.0, 0.0, 1.0, 1.0, -1.0, 1.0, 1.0)  # -45 to 45 degrees
    assert wedges_apart(1.0, 0.0, 0.0, 1.0, 0.0, 2.0, -1.0, 1.0)  # 90 to 135 degrees: they only touch
    assert wedges_apart(1.0, 0.0, 0.0, 1.0, -1.0, -1.0, 1.0, -2.0)  # 225 to 297 degrees
