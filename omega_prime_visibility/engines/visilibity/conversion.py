"""Small pieces of the VisiLibity environment's construction: overlapping boxes, groups, the environment as the
compiled module takes it (polygons as float64 vertex arrays), and the call to VisiLibity's visibility polygon."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely

from ..._compiled.kernel import njit
from ...geometry.kernels import MIN_CAPACITY, push_pair
from ...geometry.sorting import argsort_stable
from . import _visilibity1  # VisiLibity1 1.0.10 compiled with the package (native/binding.cpp)

ORIGIN_GRID = 1024.0  # metres; coordinates are taken relative to the nearest multiple (precision, caching)


def grid_origin(points: np.ndarray) -> np.ndarray:
    """The multiple of :data:`ORIGIN_GRID` nearest to each point (metres, same shape), which VisiLibity's
    coordinates are taken relative to: results then depend on a viewpoint's position only.

    Zero is always +0.0 (``np.round`` gives -0.0 for small negative coordinates): an exact -0.0 vertex minus the
    origin must not depend on which side of zero the viewpoint lies.

    Examples
    --------
    >>> grid_origin(np.array([[1500.0, -300.0]])).tolist()
    [[1024.0, 0.0]]
    """
    return np.round(points / ORIGIN_GRID) * ORIGIN_GRID + 0.0


@njit(cache=True)
def box_overlaps(lo, hi):
    """Pairs (i, j), i < j, of axis-aligned boxes ``[lo, hi]`` that overlap (sort and sweep on x)."""
    order = argsort_stable(lo[:, 0].copy())
    first = np.empty(MIN_CAPACITY, dtype=np.int64)
    second = np.empty(MIN_CAPACITY, dtype=np.int64)
    k = 0
    for a in range(len(order)):
        i = order[a]
        for b in range(a + 1, len(order)):
            j = order[b]
            if lo[j, 0] > hi[i, 0]:
                break
            if lo[j, 1] <= hi[i, 1] and lo[i, 1] <= hi[j, 1]:
                first, second, k = push_pair(first, second, k, min(i, j), max(i, j))
    return first[:k].copy(), second[:k].copy()


@njit(cache=True)
def components(n, first, second):
    """Connected-component label of each of ``n`` nodes given undirected edges ``first[k] - second[k]``: the
    smallest node of its component (so labels sort as the components' smallest members do)."""
    parent = np.arange(n)
    for k in range(len(first)):
        a, b = first[k], second[k]
        while parent[a] != a:
            a = parent[a]
        while parent[b] != b:
            b = parent[b]
        if a < b:
            parent[b] = a
        elif b < a:
            parent[a] = b
    label = np.empty(n, dtype=np.int64)
    for i in range(n):  # a parent is never larger than its child: roots are resolved before their children
        label[i] = i if parent[i] == i else label[parent[i]]
    return label


def vis_polygon(coords: np.ndarray) -> np.ndarray:
    """A polygon as VisiLibity takes it: its vertices ``coords`` (shape (m, 2), metres), in order, as a C-ordered
    float64 array (the same array when it already is one)."""
    return np.ascontiguousarray(coords, dtype=np.float64)


def vis_polygons_reversed(coords: np.ndarray, offsets: np.ndarray, which: np.ndarray) -> list[np.ndarray]:
    """:func:`vis_polygon` of the ragged rings ``which`` (``coords`` (m, 2), ``offsets`` (n + 1,)), each with its
    vertices in reverse order."""
    bounds = offsets.tolist()
    return [np.ascontiguousarray(coords[bounds[k] : bounds[k + 1]][::-1], dtype=np.float64) for k in which]


@dataclass(frozen=True, eq=False)
class Environment:
    """A VisiLibity environment: the outer boundary (counter-clockwise) and the holes (clockwise), each polygon's
    vertices a float64 array (m, 2), metres, in the frame the observer is given in.

    Examples
    --------
    >>> box = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    >>> hole = np.array([[4.0, 4.0], [4.0, 6.0], [6.0, 6.0], [6.0, 4.0]])
    >>> env = Environment([box, hole])
    >>> env.h(), env.is_valid(1e-9)
    (1, True)
    >>> Environment([box, hole[::-1]]).is_valid(1e-9)  # a hole must run clockwise
    False
    """

    polygons: list[np.ndarray]

    def h(self) -> int:
        """The number of holes (VisiLibity's name)."""
        return len(self.polygons) - 1

    def flat(self) -> tuple[np.ndarray, np.ndarray]:
        """All vertices back to back (float64, (m, 2)) and each polygon's vertex count (int64), as
        ``_visilibity1`` takes them."""
        vertices = np.ascontiguousarray(np.concatenate(self.polygons), dtype=np.float64)
        counts = np.fromiter((len(p) for p in self.polygons), dtype=np.int64, count=len(self.polygons))
        return vertices, counts

    def is_valid(self, epsilon: float) -> bool:
        """VisiLibity's own check (``Environment::is_valid``): every polygon simple and of positive area, the outer
        boundary counter-clockwise, the holes clockwise, inside it and apart from each other, within ``epsilon``."""
        return _visilibity1.environment_is_valid(*self.flat(), epsilon)


def visibility_polygon_coords(environment, x: float, y: float, epsilon: float) -> np.ndarray:
    """Vertices (shape (m, 2), metres, counter-clockwise) of VisiLibity's visibility polygon from ``(x, y)`` in
    ``environment`` (an :class:`Environment` or its list of polygons, outer boundary first).

    Examples
    --------
    A 10 m square room with a 2 m square pillar; from (2, 5) the rays past the pillar's near corners (4, 4) and
    (4, 6) widen its shadow to 8 m at the far wall (x = 10), a trapezoid of (2 + 8) / 2 * 6 = 30 m2 of which the
    pillar takes 4: 100 - 4 - 26 m2 are seen.

    >>> box = np.array([[0.0, 0.0], [10.0, 0.0], [10.0, 10.0], [0.0, 10.0]])
    >>> pillar = np.array([[4.0, 4.0], [4.0, 6.0], [6.0, 6.0], [6.0, 4.0]])
    >>> region = shapely.Polygon(visibility_polygon_coords([box, pillar], 2.0, 5.0, 1e-9))
    >>> round(region.area, 9)
    70.0
    """
    polygons = environment.polygons if isinstance(environment, Environment) else environment
    return visibility_polygon_flat(*Environment(polygons).flat(), x, y, epsilon)


def visibility_polygon_flat(vertices: np.ndarray, counts: np.ndarray, x: float, y: float, epsilon: float) -> np.ndarray:
    """:func:`visibility_polygon_coords` of an environment given as :meth:`Environment.flat` gives it: all
    vertices back to back (float64, C-ordered, (m, 2)) and each polygon's vertex count (int64)."""
    coords = _visilibity1.visibility_polygon(vertices, counts, x, y, epsilon)
    return np.frombuffer(coords, dtype=np.float64).reshape(-1, 2)


def exterior_cw(polygon: shapely.Polygon) -> np.ndarray:
    """Exterior vertices of a polygon, clockwise, closing vertex dropped."""
    c = shapely.get_coordinates(polygon.exterior)[:-1]
    return c if not shapely.is_ccw(polygon.exterior) else c[::-1]
