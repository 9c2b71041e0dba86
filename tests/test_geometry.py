"""Geometry helpers: angular extent at the -pi/pi wrap, containment, orientation."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from omega_prime_visibility.geometry.rings import Rings, angular_extent, box_rings, orient, signed_area
from omega_prime_visibility.inputs.containment import covers_point, covers_points


def square(x: float, y: float, side: float = 2.0) -> Rings:
    return box_rings(np.array([x]), np.array([y]), np.array([side]), np.array([side]), np.array([0.0]))


@pytest.mark.parametrize(("x", "y"), [(10, 0), (-10, 0), (0, 10), (0, -10), (-10, 1e-9)])
def test_extent_of_square_centred_on_axis(x: float, y: float) -> None:
    start, width, winding = angular_extent(np.zeros(2), square(x, y))
    # near face at distance 9, half side 1
    assert width[0] == pytest.approx(2 * np.arctan2(1, 9))
    centre = np.arctan2(y, x)
    assert np.angle(np.exp(1j * (start[0] + width[0] / 2 - centre))) == pytest.approx(0, abs=1e-9)
    assert winding[0] == 0
    assert -np.pi <= start[0] < np.pi


def test_extent_of_non_convex_ring_wider_than_pi() -> None:
    # a C-shape open towards +x around the observer at the origin
    c = np.array([[5, -5], [5, -4], [-4, -4], [-4, 4], [5, 4], [5, 5], [-5, 5], [-5, -5]], dtype=float)
    rings = Rings(c, np.array([0, len(c)]))
    _, width, winding = angular_extent(np.zeros(2), rings)
    assert winding[0] == 0
    assert width[0] == pytest.approx(2 * np.pi - 2 * np.arctan2(4, 5), abs=1e-9)


def test_covers_point_inside_on_boundary_outside() -> None:
    rings = box_rings(np.array([0.0, 3.0, 10.0]), np.zeros(3), np.array([2.0, 2.0, 2.0]), np.ones(3), np.zeros(3))
    assert covers_point(np.zeros(2), rings).tolist() == [True, False, False]
    assert covers_point(np.array([2.0, 0.0]), rings).tolist() == [False, True, False]  # on the edge of box 1
    assert covers_point(np.array([6.0, 0.0]), rings).tolist() == [False, False, False]


def test_orient_makes_rings_counter_clockwise() -> None:
    cw = Rings(np.array([[0, 0], [0, 1], [1, 1], [1, 0]], dtype=float), np.array([0, 4]))
    assert signed_area(cw)[0] == pytest.approx(-1)
    assert signed_area(orient(cw))[0] == pytest.approx(1)


def test_gather_oriented_against_shapely_on_random_rings() -> None:
    # random star-shaped rings of 4 to 12 vertices, half of them clockwise, at small and map coordinates, gathered
    # in shuffled order from a larger array: each comes out with the vertices shapely's orient gives it, in the
    # orientation asked for, and a reversed ring lists its vertices from last to first
    from omega_prime_visibility.geometry.rings import gather_oriented

    rng = np.random.default_rng(7)
    for shift in (0.0, 5e5):
        sizes = rng.integers(4, 13, 60)
        rings = []
        for k in sizes:
            angle = (np.arange(k) + rng.uniform(0.1, 0.9, k)) * 2 * np.pi / k  # gaps below pi: a simple star
            ring = shift + rng.uniform(-50, 50, 2) + rng.uniform(0.5, 3.0, (k, 1)) * np.c_[np.cos(angle), np.sin(angle)]
            rings.append(ring if rng.random() < 0.5 else ring[::-1])
        coords = np.concatenate([rng.uniform(size=(3, 2)), *rings])
        first = 3 + np.concatenate([[0], np.cumsum(sizes)[:-1]])
        pick = rng.permutation(60)[:45]
        want = rng.random(45) < 0.7
        out = gather_oriented(coords, first[pick], sizes[pick], want)
        assert out.sizes.tolist() == sizes[pick].tolist()
        for i, (p, ccw) in enumerate(zip(pick, want, strict=True)):
            given = rings[p]
            assert shapely.Polygon(given).is_valid
            expected = shapely.geometry.polygon.orient(shapely.Polygon(given), 1.0 if ccw else -1.0)
            flipped = shapely.Polygon(given).exterior.is_ccw != ccw
            assert np.array_equal(out.ring(i), given[::-1] if flipped else given)
            assert shapely.Polygon(out.ring(i)).exterior.is_ccw == expected.exterior.is_ccw


def test_take_keeps_rings_as_they_are_in_the_order_asked() -> None:
    # repeated, reversed and empty selections; clockwise rings stay clockwise (take never orients)
    rings = Rings(np.arange(24, dtype=float).reshape(12, 2), np.array([0, 3, 7, 12]))
    for positions in ([2, 0, 2], [1], [], [0, 1, 2]):
        taken = rings.take(np.array(positions, dtype=np.int64))
        assert len(taken) == len(positions)
        assert [taken.ring(k).tolist() for k in range(len(positions))] == [rings.ring(p).tolist() for p in positions]


def test_covers_points_is_covers_point_for_each_point() -> None:
    rng = np.random.default_rng(3)
    centre = rng.uniform(-5, 5, (30, 2))
    rings = box_rings(centre[:, 0], centre[:, 1], rng.uniform(1, 4, 30), rng.uniform(1, 3, 30), rng.uniform(-3, 3, 30))
    points = np.concatenate([rng.uniform(-6, 6, (40, 2)), rings.coords[:5], (rings.coords[:5] + rings.coords[1:6]) / 2])
    many = covers_points(points, rings)
    assert many.shape == (50, 30) and 0 < many.sum() < many.size
    assert np.array_equal(many, np.array([covers_point(p, rings) for p in points]))
    polygons = shapely.polygons([rings.ring(i) for i in range(30)])
    inside = shapely.contains_xy(polygons[None, :], points[:40, :1], points[:40, 1:])  # random points: off the edges
    assert np.array_equal(many[:40], inside)


def test_orientation_of_a_needle_at_map_coordinates() -> None:
    # a needle 2 m long and 1 µm high at UTM-like coordinates, counter-clockwise: its area (2**-20 m²) is far below
    # the rounding of shoelace terms of absolute coordinates (1e12 m²), which gave 0 and flipped it
    x, y = 5e5, 5.4e6
    ccw = np.array([[x, y], [x + 2.0, y], [x + 1.0, y + 2.0**-20]])
    for ring, area in ((ccw, 2.0**-20), (ccw[::-1].copy(), -(2.0**-20))):
        rings = Rings(ring, np.array([0, 3]))
        assert signed_area(rings)[0] == area
        assert signed_area(orient(rings, True))[0] == 2.0**-20


def test_angular_spans_against_shapely_on_random_rings() -> None:
    # random star-shaped rings and viewpoints inside and outside them: the span holds every direction to the
    # outline (dense points along its edges) and is tight (reached by vertices); near and far are shapely's
    # distances; a ring around or touching its viewpoint spans every direction
    from omega_prime_visibility.geometry.spans import FULL, angular_spans

    rng = np.random.default_rng(4)
    polygons = []
    for _ in range(300):
        k = rng.integers(3, 9)
        angle = np.sort(rng.uniform(0, 2 * np.pi, k))
        radius = rng.uniform(0.5, 6, k)
        polygons.append(rng.uniform(-30, 30, 2) + np.column_stack([np.cos(angle), np.sin(angle)]) * radius[:, None])
    rings = Rings(np.concatenate(polygons), np.r_[0, np.cumsum([len(p) for p in polygons])])
    points = rng.uniform(-36, 36, (300, 2))
    points[:40] = [p.mean(axis=0) for p in polygons[:40]]  # inside their own ring
    centre, half, near, far = angular_spans(points, rings, np.arange(300))
    for k, ring in enumerate(polygons):
        polygon, point = shapely.Polygon(ring), shapely.Point(points[k])
        assert near[k] == pytest.approx(polygon.exterior.distance(point), abs=1e-12)
        assert far[k] == pytest.approx(np.linalg.norm(ring - points[k], axis=1).max(), rel=1e-15)
        if polygon.covers(point):
            assert half[k] == FULL
            continue
        closed = np.vstack([ring, ring[:1]])
        t = np.linspace(0, 1, 50)[:, None, None]
        dense = (closed[:-1] + t * (closed[1:] - closed[:-1])).reshape(-1, 2) - points[k]
        off = (np.arctan2(dense[:, 1], dense[:, 0]) - centre[k] + np.pi) % (2 * np.pi) - np.pi
        assert half[k] < np.pi / 2 * 1.999 or half[k] == FULL
        assert np.abs(off).max() <= half[k] + 1e-12 and np.abs(off).max() == pytest.approx(half[k], abs=1e-12)
