"""Small pieces of the VisiLibity environment's construction: overlapping boxes, groups, conversions between
numpy, shapely and VisiLibity polygons."""

from __future__ import annotations

import _visilibity
import numba
import numpy as np
import shapely
import visilibity as vis

from ...kernels import MIN_CAPACITY, push_pair

# SWIG's flat functions, called directly: the proxy classes' Python wrappers cost more than the C++ calls (a
# vis.Point(x, y) is three Python calls); the vector typemaps take the flat functions' objects as they are
_new_point = _visilibity.new_Point
_new_polygon = _visilibity.new_Polygon
_vertex = _visilibity.Polygon___getitem__
_n_vertices = _visilibity.Polygon_n
_x = _visilibity.Point_x
_y = _visilibity.Point_y


@numba.njit(cache=True)
def box_overlaps(lo, hi):
    """Pairs (i, j), i < j, of axis-aligned boxes ``[lo, hi]`` that overlap (sort and sweep on x)."""
    order = np.argsort(lo[:, 0])
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


@numba.njit(cache=True)
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


def vis_polygon(coords: np.ndarray) -> vis.Polygon:
    """A VisiLibity polygon with the vertices ``coords`` (shape (m, 2), metres), in order (the SWIG object itself,
    which ``vis.Environment`` and :func:`polygon_coords` take, without the Python proxy around it)."""
    return _new_polygon([_new_point(x, y) for x, y in coords.tolist()])


def vis_polygons_reversed(coords: np.ndarray, offsets: np.ndarray, which: np.ndarray) -> list[vis.Polygon]:
    """:func:`vis_polygon` of the ragged rings ``which`` (``coords`` (m, 2), ``offsets`` (n + 1,)), each with its
    vertices in reverse order, from one conversion of the coordinates to Python floats."""
    points = coords.tolist()
    bounds = offsets.tolist()
    return [_new_polygon([_new_point(x, y) for x, y in reversed(points[bounds[k] : bounds[k + 1]])]) for k in which]


def polygon_coords(polygon: vis.Polygon) -> np.ndarray:
    """The vertices of a VisiLibity polygon, shape (m, 2), float64."""
    points = [_vertex(polygon, i) for i in range(_n_vertices(polygon))]
    return np.array([(_x(p), _y(p)) for p in points], dtype=np.float64).reshape(-1, 2)


def exterior_cw(polygon: shapely.Polygon) -> np.ndarray:
    """Exterior vertices of a polygon, clockwise, closing vertex dropped."""
    c = shapely.get_coordinates(polygon.exterior)[:-1]
    return c if not shapely.is_ccw(polygon.exterior) else c[::-1]
