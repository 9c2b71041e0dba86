"""Convex clipping in compiled loops (:mod:`.geometry.convex_clip`), on hand-made polygons."""

from __future__ import annotations

import numpy as np
import pytest
import shapely

from omega_prime_visibility.geometry.convex_clip import (
    clip_half_plane,
    clip_line,
    convex_hull,
    drop_repeats,
    polygon_area,
    subtract,
)


def pieces_of(*polygons: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    buffer = np.zeros((16, 16, 2))
    counts = np.zeros(16, np.int64)
    for p, polygon in enumerate(polygons):
        buffer[p, : len(polygon)] = polygon
        counts[p] = len(polygon)
    return buffer, counts


def minus(piece: np.ndarray, shape: np.ndarray) -> float:
    """Area (m²) of the convex ``piece`` minus the convex ``shape`` by :func:`subtract`, its pieces disjoint."""
    pieces, counts = pieces_of(piece)
    out, out_counts = np.zeros((16, 16, 2)), np.zeros(16, np.int64)
    made = subtract(pieces, counts, 1, shape, len(shape), out, out_counts, np.zeros((2, 16, 2)))
    drawn = [shapely.Polygon(out[p, : out_counts[p]]) for p in range(made)]
    assert shapely.union_all(drawn).area == pytest.approx(sum(d.area for d in drawn), abs=1e-12)  # disjoint
    return sum(d.area for d in drawn)


SQUARE = np.array([[0.0, 0.0], [4.0, 0.0], [4.0, 4.0], [0.0, 4.0]])


def test_a_square_minus_a_square_across_its_corner() -> None:
    shape = np.array([[2.0, 2.0], [6.0, 2.0], [6.0, 6.0], [2.0, 6.0]])
    assert minus(SQUARE, shape) == pytest.approx(12.0)
    assert minus(SQUARE, SQUARE) == pytest.approx(0.0, abs=1e-12)
    assert minus(SQUARE, shape + 10.0) == pytest.approx(16.0)  # apart: passed on whole


@pytest.mark.parametrize("gap", [0.0, 1e-16, 3e-15])
def test_a_repeated_vertex_of_the_shape_cuts_nothing(gap: float) -> None:
    # the shape's vertex (2, 2) twice, the copy moved by a rounding error in a direction across the square: an
    # edge that short has no direction, and cutting along it kept the whole piece beside the true pieces
    shape = np.array([[2.0, 2.0], [2.0 + gap, 2.0 - gap], [6.0, 2.0], [6.0, 6.0], [2.0, 6.0]])
    assert minus(SQUARE, shape) == pytest.approx(12.0, abs=1e-9)


def test_clip_line_hull_and_area() -> None:
    dst = np.zeros((8, 2))
    k = clip_line(SQUARE, 4, 0.0, 1.0, 4.0, 1.0, True, dst)  # left of the line y = 1, going +x: y >= 1
    assert polygon_area(dst, k) == pytest.approx(12.0)
    points = np.array([[0.0, 0.0], [1.0, 1.0], [2.0, 0.0], [1.0, 0.5], [2.0, 2.0], [0.0, 2.0]])
    out = np.zeros((12, 2))
    m = convex_hull(points, len(points), out)
    assert m == 4 and polygon_area(out, m) == pytest.approx(4.0)


def test_clipping_keeps_the_side_asked_for_and_drops_repeated_vertices() -> None:
    square = np.array([[-1.0, -1.0], [1.0, -1.0], [1.0, 1.0], [-1.0, 1.0]])
    dst = np.empty((8, 2))
    k = clip_half_plane(square, 4, 0.5, -1.0, 0.0, dst)  # 0.5 - u >= 0: u <= 0.5
    assert shapely.Polygon(dst[:k]).area == pytest.approx(3.0) and dst[:k, 0].max() == 0.5
    assert clip_half_plane(square, 4, -2.0, 1.0, 0.0, dst) == 0  # u >= 2: nothing
    ring = np.array([[0.0, 0.0], [1.0, 0.0], [1.0 + 1e-16, 0.0], [1.0, 1.0], [0.0, 1e-17]])
    assert drop_repeats(ring, 5) == 3 and ring[:3].tolist() == [[0.0, 0.0], [1.0, 0.0], [1.0, 1.0]]
