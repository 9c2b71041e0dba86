"""Small pieces of the VisiLibity environment's construction: overlapping boxes, groups, conversions between
numpy, shapely and VisiLibity polygons."""

from __future__ import annotations

import numba
import numpy as np
import shapely
import visilibity as vis
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components

from ...kernels import MIN_CAPACITY, push_pair


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


def components(n: int, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """Connected-component label of each of ``n`` nodes given undirected edges ``first[k] - second[k]``."""
    graph = coo_matrix((np.ones(len(first)), (first, second)), shape=(n, n))
    return connected_components(graph, directed=False)[1].astype(np.int64)


def vis_polygon(coords: np.ndarray) -> vis.Polygon:
    return vis.Polygon([vis.Point(x, y) for x, y in coords.tolist()])


def polygon_coords(polygon: vis.Polygon) -> np.ndarray:
    return np.array([(polygon[i].x(), polygon[i].y()) for i in range(polygon.n())], dtype=np.float64)


def exterior_cw(polygon: shapely.Polygon) -> np.ndarray:
    """Exterior vertices of a polygon, clockwise, closing vertex dropped."""
    c = shapely.get_coordinates(polygon.exterior)[:-1]
    return c if not shapely.is_ccw(polygon.exterior) else c[::-1]
