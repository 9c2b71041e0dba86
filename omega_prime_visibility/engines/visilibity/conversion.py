"""Small pieces of the VisiLibity environment's construction: overlapping boxes, groups, conversions between
numpy, shapely and VisiLibity polygons."""

from __future__ import annotations

import ctypes

import _visilibity
import numba
import numpy as np
import shapely
import visilibity as vis

from ...geometry.kernels import MIN_CAPACITY, argsort_stable, push_pair

# SWIG's flat functions, called directly: the proxy classes' Python wrappers cost more than the C++ calls (a
# vis.Point(x, y) is three Python calls); the vector typemaps take the flat functions' objects as they are
_new_point = _visilibity.new_Point
_new_polygon = _visilibity.new_Polygon
_vertex = _visilibity.Polygon___getitem__
_n_vertices = _visilibity.Polygon_n
_x = _visilibity.Point_x
_y = _visilibity.Point_y
_new_environment = _visilibity.new_Environment
_new_visibility_polygon = _visilibity.new_Visibility_Polygon
# A VisiLibity Polygon holds only ``std::vector<Point> vertices_`` (no virtual methods, so no vtable before it) and
# a Point only ``double x_, y_``: the vector's first two words are pointers to the first vertex and past the last,
# and the vertices are (x, y) float64 pairs in between. Reading them there takes one call instead of three per
# vertex; :func:`_memory_layout_holds` checks the layout on a known polygon first and every read checks the count.
_VECTOR_BOUNDS = ctypes.c_size_t * 2
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


@numba.njit(cache=True)
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
    """The vertices of a VisiLibity polygon (or visibility polygon, the SWIG object), shape (m, 2), float64.

    Read from the polygon's vertex array in memory when its layout is the one checked at import, else (or if the
    count disagrees with ``Polygon::n``) vertex by vertex through SWIG; both give the same numbers.

    Examples
    --------
    >>> polygon_coords(vis_polygon(np.array([[0.0, 0.0], [2.0, 0.0], [0.0, 1.5]]))).tolist()
    [[0.0, 0.0], [2.0, 0.0], [0.0, 1.5]]
    >>> polygon_coords(vis.Polygon([vis.Point(1.0, 1.0), vis.Point(3.0, 1.0), vis.Point(1.0, 4.0)])).tolist()
    [[1.0, 1.0], [3.0, 1.0], [1.0, 4.0]]
    """
    polygon = getattr(polygon, "this", polygon)  # the SWIG object inside a proxy class
    coords = _vertex_array(polygon, _n_vertices(polygon)) if _READ_MEMORY else None
    return coords if coords is not None else _coords_through_swig(polygon)


def _vertex_array(polygon, n: int) -> np.ndarray | None:
    """The polygon's vertex array read in memory, shape (n, 2); None unless its two bounding words are aligned
    and span exactly ``n`` vertices (nothing is followed before that)."""
    begin, end = _VECTOR_BOUNDS.from_address(int(polygon))
    if begin == 0 or begin % 8 or end - begin != 16 * n:
        return None
    return np.frombuffer(ctypes.string_at(begin, end - begin), dtype=np.float64).reshape(-1, 2)


def _coords_through_swig(polygon: vis.Polygon) -> np.ndarray:
    points = [_vertex(polygon, i) for i in range(_n_vertices(polygon))]
    return np.array([(_x(p), _y(p)) for p in points], dtype=np.float64).reshape(-1, 2)


def _memory_layout_holds() -> bool:
    """Whether a polygon's vertex array is where :func:`polygon_coords` reads it (checked on a known polygon: the
    two words span exactly its vertices, and they hold its coordinates)."""
    known = np.array([[0.5, -1.25], [3.0, 0.125], [-2.0, 7.5]])
    polygon = vis_polygon(known)
    found = _vertex_array(polygon, len(known))
    return found is not None and np.array_equal(found, known) and np.array_equal(_coords_through_swig(polygon), known)


def visibility_polygon_coords(environment, x: float, y: float, epsilon: float) -> np.ndarray:
    """Vertices (shape (m, 2), metres, counter-clockwise) of VisiLibity's visibility polygon from ``(x, y)`` in
    ``environment`` (a list of SWIG polygons, outer boundary first, or a built environment)."""
    if isinstance(environment, list):
        environment = _new_environment(environment)
    return polygon_coords(_new_visibility_polygon(_new_point(x, y), environment, epsilon))


def exterior_cw(polygon: shapely.Polygon) -> np.ndarray:
    """Exterior vertices of a polygon, clockwise, closing vertex dropped."""
    c = shapely.get_coordinates(polygon.exterior)[:-1]
    return c if not shapely.is_ccw(polygon.exterior) else c[::-1]


_READ_MEMORY = _memory_layout_holds()
