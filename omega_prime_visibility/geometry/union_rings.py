"""The union of star-shaped polygons as a shapely geometry, from its boundary's pieces (compiled).

:func:`.star_union.union_pieces` finds the union's boundary: the pieces of the polygons' edges that no other
polygon covers, each directed as its polygon's edge (counter-clockwise), so the union lies to its left. Chained
end to start they close into rings: counter-clockwise ones are shells, clockwise ones holes, and each hole belongs
to the smallest shell containing it; rings thinner on average than the tolerance of :mod:`.star_union` (1e-10
relative to the coordinates) are slivers of rounding and left out.

A piece's end is a polygon's vertex (exact) or the crossing of two edges, computed the same way from either edge
(:func:`.star_union._add_splits`), so consecutive pieces mostly meet exactly. A piece's successor is the piece
starting nearest its end and within the tolerance of that nearest start (pieces are longer than twice the
tolerance, so a short piece's end is never taken for its own start's point), as far as :data:`MATCH` tolerances
away: three edges crossing at one point up to rounding, the pieces left out for being short, and the hand-overs
between two nearly parallel edges (chords of two range circles, 1e-7 m apart) are bridged. Where several pieces
start at one point (polygons touching at a point, a hole touching the outline) the chain turns as far left as it
can, and a ring coming back to a point it passed is split there: valid polygons' rings touch each other, never
themselves.

The rings' vertices are the polygons' vertices and crossings, so the geometry is as exact as the area
(:mod:`.star_union`: exact edges, the range circles' chords as given). :func:`star_union` checks the geometry's
area against the pieces' (Green's theorem, to :data:`AREA_CHECK` relative) and its validity, and gives None when
either fails or the pieces do not chain, for the caller to fall back on shapely's union (none in 3,600 random
scenes of 2 to 6 sensors, nor on the crowded highway of ``benchmarks/bench_sensors.py``).
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from .._compiled.kernel import njit
from .sorting import argsort_stable
from .star_union import union_pieces

MATCH = 1e3
"""Farthest a piece's successor may start from the piece's end, in tolerances of :mod:`.star_union`."""
AREA_CHECK = 1e-8
"""Relative difference allowed between the geometry's area and the pieces' (beyond ``tolerance x perimeter``): the
pieces' area is off by up to about 4e-9 where two nearly parallel edges hand over, the geometry being right."""


@njit(cache=True, inline="always")
def _left_turn(ix, iy, ox, oy):
    """Clockwise angle (radians, in ``(0, 2π]``) from the reversed incoming direction (ix, iy) to the outgoing
    one (ox, oy): the smallest is the sharpest left turn, the one that keeps the region on the left."""
    phi = math.atan2(-ix * oy + iy * ox, -ix * ox - iy * oy)  # counter-clockwise from (-ix, -iy)
    return 2.0 * math.pi - phi if phi >= 0.0 else -phi


@njit(cache=True)
def _successors(pieces, tol):
    """For each piece the one that follows it on the union's boundary (-1 for all when some end meets no start,
    or the choices are not one to one), and the number of the point each piece starts at when several pieces
    start there (the lowest of their numbers; -1 elsewhere)."""
    m = len(pieces)
    match = MATCH * tol
    order = argsort_stable(pieces[:, 0].copy())
    xs = pieces[order, 0]
    following = np.full(m, -1)
    junction = np.full(m, -1)
    incoming = np.zeros(m, dtype=np.int64)
    for p in range(m):
        ex, ey = pieces[p, 2], pieces[p, 3]
        lo, hi = np.searchsorted(xs, ex - match), np.searchsorted(xs, ex + match, side="right")
        nearest = np.inf
        for s in range(lo, hi):
            q = order[s]
            if q != p:
                nearest = min(nearest, math.hypot(pieces[q, 0] - ex, pieces[q, 1] - ey))
        # the starts at this end: within rounding of the nearest (pieces are longer than 2 tol: a short piece's
        # end is no start of this point)
        best, best_turn, found = -1, 0.0, 0
        for s in range(lo, hi):
            q = order[s]
            if q == p or math.hypot(pieces[q, 0] - ex, pieces[q, 1] - ey) > min(nearest + tol, match):
                continue
            found += 1
            if found == 1:
                best = q
                continue
            if found == 2:  # several pieces start here: the sharpest left turn keeps the union on the left
                best_turn = _turn(pieces, p, best)
            turn = _turn(pieces, p, q)
            if turn < best_turn:
                best, best_turn = q, turn
        if best < 0:
            following[:] = -1
            return following, junction
        following[p] = best
        incoming[best] += 1
        x, y = pieces[p, 0], pieces[p, 1]
        lowest, count = p, 0
        for s in range(np.searchsorted(xs, x - tol), np.searchsorted(xs, x + tol, side="right")):
            q = order[s]
            if abs(pieces[q, 1] - y) <= tol:
                count += 1
                lowest = min(lowest, q)
        if count > 1:
            junction[p] = lowest
    if np.any(incoming != 1):
        following[:] = -1
    return following, junction


@njit(cache=True)
def _chain(pieces, tol):
    """Closed rings from ``pieces`` (rows ``x0, y0, x1, y1``): their coordinates (each ring closed by repeating
    its first point), the rings' offsets into them, and False when the pieces do not chain.

    A ring that comes back to a point it passed (a region pinched at a point around a hole, two holes touching)
    is split there: valid polygons' rings touch each other but not themselves."""
    m = len(pieces)
    following, junction = _successors(pieces, tol)
    coords = np.empty((2 * m + 1, 2))
    offsets = np.zeros(m + 1, dtype=np.int64)
    if m == 0 or following[0] < 0:
        return coords[:0], offsets[:1], False
    used = np.zeros(m, dtype=np.bool_)
    at = np.full(m, -1)  # where on the current path each junction lies, by its number
    path = np.empty((m, 2))
    path_junction = np.empty(m, dtype=np.int64)
    r, k = 0, 0
    for first in range(m):
        if used[first]:
            continue
        length, p = 0, first
        while not used[p]:
            used[p] = True
            v = junction[p]
            if v >= 0 and at[v] >= 0:  # back at a point of the path: the loop since then is a ring
                k = _close(path, at[v], length, coords, k)
                r += 1
                offsets[r] = k
                for t in range(at[v] + 1, length):
                    if path_junction[t] >= 0:
                        at[path_junction[t]] = -1
                length = at[v]
            path[length, 0], path[length, 1] = pieces[p, 0], pieces[p, 1]
            path_junction[length] = v
            if v >= 0:
                at[v] = length
            length += 1
            p = following[p]
        k = _close(path, 0, length, coords, k)
        r += 1
        offsets[r] = k
        for t in range(length):
            if path_junction[t] >= 0:
                at[path_junction[t]] = -1
    return coords[:k], offsets[: r + 1], True


@njit(cache=True)
def _close(path, lo, hi, coords, k):
    """Append ``path[lo:hi]`` and its first point again to ``coords`` from row ``k``; the new row count."""
    size = hi - lo
    coords[k : k + size] = path[lo:hi]
    coords[k + size] = path[lo]
    return k + size + 1


@njit(cache=True, inline="always")
def _turn(pieces, a, b):
    """:func:`_left_turn` from piece ``a`` to piece ``b``."""
    return _left_turn(
        pieces[a, 2] - pieces[a, 0],
        pieces[a, 3] - pieces[a, 1],
        pieces[b, 2] - pieces[b, 0],
        pieces[b, 3] - pieces[b, 1],
    )


@njit(cache=True)
def _inside(coords, lo, hi, x, y):
    """Whether (x, y) lies inside the closed ring ``coords[lo:hi]`` (crossing number)."""
    inside = False
    for v in range(lo, hi - 1):
        ax, ay, bx, by = coords[v, 0], coords[v, 1], coords[v + 1, 0], coords[v + 1, 1]
        if (ay > y) != (by > y) and x < ax + (y - ay) * (bx - ax) / (by - ay):
            inside = not inside
    return inside


@njit(cache=True)
def _assemble(coords, offsets, tol):
    """Polygons from closed rings: coordinates ordered polygon by polygon (shell, then its holes), the rings'
    offsets into them, the polygons' offsets into the rings, the rings' total area (square metres) and perimeter
    (metres), and False when a hole lies in no shell. Rings thinner than ``tol`` on average are left out."""
    r = len(offsets) - 1
    areas = np.zeros(r)
    keep = np.zeros(r, dtype=np.bool_)
    total, perimeter = 0.0, 0.0
    for g in range(r):
        twice, length = 0.0, 0.0
        for v in range(offsets[g], offsets[g + 1] - 1):
            ax, ay, bx, by = coords[v, 0], coords[v, 1], coords[v + 1, 0], coords[v + 1, 1]
            twice += ax * by - ay * bx
            length += math.sqrt((bx - ax) ** 2 + (by - ay) ** 2)
        areas[g] = 0.5 * twice
        keep[g] = abs(areas[g]) > tol * length
        total += areas[g]
        perimeter += length
    owner = np.full(r, -1)  # the shell each kept hole belongs to
    for h in range(r):
        if not keep[h] or areas[h] > 0.0:
            continue
        a, b = offsets[h], offsets[h] + 1  # a point on the hole's longest edge: not on any shell (they do not cross)
        for v in range(offsets[h] + 1, offsets[h + 1] - 1):
            if (coords[v + 1, 0] - coords[v, 0]) ** 2 + (coords[v + 1, 1] - coords[v, 1]) ** 2 > (
                coords[b, 0] - coords[a, 0]
            ) ** 2 + (coords[b, 1] - coords[a, 1]) ** 2:
                a, b = v, v + 1
        x, y = 0.5 * (coords[a, 0] + coords[b, 0]), 0.5 * (coords[a, 1] + coords[b, 1])
        for g in range(r):
            if keep[g] and areas[g] > 0.0 and (owner[h] < 0 or areas[g] < areas[owner[h]]):
                if _inside(coords, offsets[g], offsets[g + 1], x, y):
                    owner[h] = g
        if owner[h] < 0:
            return coords[:0], offsets[:1], offsets[:1], total, perimeter, False
    out = np.empty_like(coords)
    rings = np.zeros(r + 1, dtype=np.int64)
    polygons = np.zeros(r + 1, dtype=np.int64)
    n, k, p = 0, 0, 0
    for g in range(r):
        if not keep[g] or areas[g] < 0.0:
            continue
        for h in range(-1, r):
            ring = g if h < 0 else h  # the shell first, then its holes
            if h < 0 or owner[h] == g:
                size = offsets[ring + 1] - offsets[ring]
                out[n : n + size] = coords[offsets[ring] : offsets[ring + 1]]
                n += size
                k += 1
                rings[k] = n
        p += 1
        polygons[p] = k
    return out[:n], rings[: k + 1], polygons[: p + 1], total, perimeter, True


def star_union(points, starts, centers, bases, fovs, origin=(0.0, 0.0)) -> tuple[shapely.Geometry | None, float]:
    """The union of star-shaped polygons (see :func:`.star_union.star_union_area` for the parameters), shifted by
    ``origin`` (metres), and its area (square metres).

    Returns
    -------
    geometry : shapely Polygon or MultiPolygon, or None
        None when the boundary's pieces did not make valid polygons of the union's area: the caller falls back on
        shapely's union.
    area : float
        The union's area from :func:`.star_union.union_pieces`, whatever the geometry.
    """
    area, pieces, tol = union_pieces(points, starts, centers, bases, fovs, True)
    if len(pieces) == 0 and area == 0.0:  # no polygon of three vertices
        return shapely.Polygon(), area
    coords, offsets, chained = _chain(pieces, tol)
    if not chained or len(offsets) < 2:
        return None, area
    coords, rings, polygons, total, perimeter, assembled = _assemble(coords, offsets, tol)
    if not assembled or len(polygons) < 2 or abs(total - area) > AREA_CHECK * abs(area) + tol * perimeter:
        return None, area
    coords = coords + np.asarray(origin, dtype=np.float64)
    if len(polygons) == 2:
        geometry = shapely.from_ragged_array(shapely.GeometryType.POLYGON, coords, (rings, polygons))[0]
    else:
        parts = np.array([0, len(polygons) - 1], dtype=np.int64)
        geometry = shapely.from_ragged_array(shapely.GeometryType.MULTIPOLYGON, coords, (rings, polygons, parts))[0]
    return (geometry if shapely.is_valid(geometry) else None), area
