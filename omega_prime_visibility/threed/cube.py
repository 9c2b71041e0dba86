"""Directions from an eye, drawn on the six faces of a cube around it: silhouettes of convex bodies, the view's
region, the part of a body within range, and solid angles.

A direction ``p`` seen through face ``f`` (``forward . p > 0`` and ``|eu . p|, |ev . p| <= forward . p``) is drawn
at ``(u, v) = (eu . p, ev . p) / (forward . p)`` in the square [-1, 1]^2. Central projection maps lines to lines,
so a convex body's directions on a face form a convex polygon, and planar polygons measure exactly as solid
angles (each triangle from the face's centre is a spherical triangle, Van Oosterom and Strackee's formula).
Curved limits (the vertical field of view's cones, the range's sphere) are drawn as polygons of
:data:`CURVE_POINTS` vertices (error below 1e-6 of the area near the curve).

All geometry here is relative to the eye at the origin (metres); faces are :data:`FACES`.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
import shapely

from .bodies import ConvexBodies, entries

CURVE_POINTS = 2048
"""Vertices of a polygon standing for a curved limit (an elevation limit on one face, the range on a plane)."""
MIN_SOLID_ANGLE = 1e-13
"""Steradians; smaller pieces count as empty (about a 3 mm square at 10 km)."""

_UP = np.array([0.0, 0.0, 1.0])
FACES = np.array(
    [
        [[1, 0, 0], [0, 1, 0], [0, 0, 1]],
        [[0, 1, 0], [-1, 0, 0], [0, 0, 1]],
        [[-1, 0, 0], [0, -1, 0], [0, 0, 1]],
        [[0, -1, 0], [1, 0, 0], [0, 0, 1]],
        [[0, 0, 1], [1, 0, 0], [0, 1, 0]],
        [[0, 0, -1], [1, 0, 0], [0, 1, 0]],
    ],
    dtype=np.float64,
)
"""``(forward, eu, ev)`` of the six cube faces; the four side faces have ``ev`` up, so elevation limits on them
are curves ``v = f(u)``."""
SQUARE = shapely.box(-1.0, -1.0, 1.0, 1.0)
_CORNERS_UV = np.array([[1, 1], [1, -1], [-1, 1], [-1, -1]], dtype=np.float64)


def ring_solid_angle(uv: np.ndarray) -> float:
    """Signed solid angle (steradians) of the closed ring ``uv`` (shape (k, 2), on a face at distance 1).

    >>> round(ring_solid_angle(np.array([[-1.0, -1.0], [1, -1], [1, 1], [-1, 1]])) / (4 * math.pi / 6), 12)
    1.0
    """
    return float(_edge_terms(uv, np.roll(uv, -1, axis=0)).sum())


def _edge_terms(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Signed solid angle of the triangle (face centre, a, b) for each row."""
    u0, v0, u1, v1 = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    nb, nc = np.sqrt(u0 * u0 + v0 * v0 + 1), np.sqrt(u1 * u1 + v1 * v1 + 1)
    return 2 * np.arctan2(u0 * v1 - v0 * u1, nb * nc + nb + nc + u0 * u1 + v0 * v1 + 1)


def solid_angles(geometries: np.ndarray) -> np.ndarray:
    """Solid angle (steradians) of each polygonal geometry drawn on one face (holes subtracted, lines and points
    and None count 0), vectorised.

    >>> ring = shapely.box(-1, -1, 1, 1)
    >>> (solid_angles(np.array([ring, ring.difference(shapely.box(-0.5, -0.5, 0.5, 0.5)), None])) > 0).tolist()
    [True, True, False]
    """
    geometries = np.asarray(geometries, dtype=object).reshape(-1)
    out = np.zeros(len(geometries))
    parts, index = geometries, np.arange(len(geometries))
    valid = ~shapely.is_missing(parts)
    parts, index = parts[valid], index[valid]
    polygons, polygon_of = [], []
    while len(parts):
        kind = shapely.get_type_id(parts)
        polygons.append(parts[kind == 3])
        polygon_of.append(index[kind == 3])
        multi = (kind == 6) | (kind == 7)
        parts, sub = shapely.get_parts(parts[multi], return_index=True)
        index = index[multi][sub]
    if not polygons or not sum(len(p) for p in polygons):
        return out
    polygons_arr, polygon_of_arr = np.concatenate(polygons), np.concatenate(polygon_of)
    if not len(polygons_arr):
        return out
    rings, ring_of = shapely.get_rings(polygons_arr, return_index=True)
    exterior = np.r_[True, ring_of[1:] != ring_of[:-1]]
    coords, vertex_ring = shapely.get_coordinates(rings, return_index=True)
    same = vertex_ring[1:] == vertex_ring[:-1]
    terms = _edge_terms(coords[:-1][same], coords[1:][same])
    per_ring = np.abs(np.bincount(vertex_ring[:-1][same], terms, minlength=len(rings)))
    np.add.at(out, polygon_of_arr[ring_of], np.where(exterior, per_ring, -per_ring))
    return np.maximum(out, 0.0)


def silhouettes(bodies: ConvexBodies, f: int) -> np.ndarray:
    """The directions of each body (eye at the origin, outside every body) seen through cube face ``f``: an array
    (n,) of convex shapely polygons in face coordinates, None where the body is not seen through that face."""
    forward, eu, ev = FACES[f]
    n = len(bodies)
    out = np.full(n, None, dtype=object)
    if n == 0:
        return out
    rel = bodies.vertices
    d, u, v = rel @ forward, rel @ eu, rel @ ev
    tol = 1e-12 * np.maximum(np.abs(d), 1.0)
    inside = (d > 0) & (np.abs(u) <= d + tol) & (np.abs(v) <= d + tol)
    points = [np.column_stack([u[inside], v[inside]]) / d[inside, None]]
    owner = [bodies.vertex_body[inside]]
    a, b = bodies.edges[:, 0], bodies.edges[:, 1]
    for g in (d - u, d + u, d - v, d + v):
        ga, gb = g[a], g[b]
        cross = ga * gb < 0
        t = np.where(cross, ga / np.where(cross, ga - gb, 1.0), 0.0)
        dd = d[a] + t * (d[b] - d[a])
        uu = u[a] + t * (u[b] - u[a])
        vv = v[a] + t * (v[b] - v[a])
        ok = cross & (dd > 0) & (np.abs(uu) <= dd * (1 + 1e-9)) & (np.abs(vv) <= dd * (1 + 1e-9))
        points.append(np.clip(np.column_stack([uu[ok], vv[ok]]) / dd[ok, None], -1.0, 1.0))
        owner.append(bodies.edge_body[ok])
    directions = forward + _CORNERS_UV[:, :1] * eu + _CORNERS_UV[:, 1:] * ev
    which = np.tile(np.arange(n), 4)
    hit = np.isfinite(entries(bodies, which, np.repeat(directions, n, axis=0)))
    points.append(np.repeat(_CORNERS_UV, n, axis=0)[hit])
    owner.append(which[hit])
    pts, own = np.concatenate(points), np.concatenate(owner)
    if not len(pts):
        return out
    order = np.argsort(own, kind="stable")
    pts, own = pts[order], own[order]
    present, consecutive = np.unique(own, return_inverse=True)
    hulls = shapely.convex_hull(shapely.multipoints(pts, indices=consecutive))
    keep = (shapely.get_type_id(hulls) == 3) & (solid_angles(hulls) > MIN_SOLID_ANGLE)
    out[present[keep]] = hulls[keep]
    return out


def _half_space(normal: np.ndarray, face: np.ndarray) -> shapely.Geometry:
    """Directions ``p`` with ``normal . p >= 0`` on a cube face."""
    lifted = np.array([[1.0, -1.0, -1.0], [1, 1, -1], [1, 1, 1], [1, -1, 1]])  # (1, u, v): p = face . (1, u, v)
    clipped = clip_plane(lifted, np.array([normal @ face[0], normal @ face[1], normal @ face[2]]))
    return shapely.Polygon(clipped[:, 1:]) if len(clipped) >= 3 else shapely.Polygon()


def _elevation_above(limit: float, f: int) -> shapely.Geometry:
    """Directions of elevation >= ``limit`` (radians) on cube face ``f``, the curved limit as a polygon."""
    if limit <= -math.pi / 2:
        return SQUARE
    if f < 4:  # side face: elevation = atan(v / sqrt(1 + u^2))
        u = np.linspace(-1.0, 1.0, CURVE_POINTS)
        v = np.clip(math.tan(limit) * np.sqrt(1 + u * u), -2.0, 2.0)
        return shapely.Polygon(np.column_stack([np.r_[u, 1, -1], np.r_[v, 3, 3]])).intersection(SQUARE)
    up = f == 4  # top face: elevation = ±atan(1 / r), r = |(u, v)|
    if up and limit <= 0:
        return SQUARE
    if not up and limit >= 0:
        return shapely.Polygon()
    angle = np.linspace(0, 2 * math.pi, 4 * CURVE_POINTS, endpoint=False)
    disk = shapely.Polygon(np.column_stack([np.cos(angle), np.sin(angle)]) / abs(math.tan(limit)))
    return SQUARE.intersection(disk) if up else SQUARE.difference(disk)


@lru_cache(maxsize=64)
def view_regions(heading: float, half_fov: float, low: float, high: float) -> tuple[shapely.Geometry | None, ...]:
    """Per cube face, the directions in view as a polygon in face coordinates (None: the whole face; an empty
    polygon: none of it). ``heading`` and ``half_fov`` in radians counter-clockwise from +x, ``low`` and ``high``
    the elevation limits (radians above the horizontal). Cached: a sensor's regions are built once."""
    out: list[shapely.Geometry | None] = []
    left = np.array([math.cos(heading + half_fov), math.sin(heading + half_fov), 0.0])
    right = np.array([math.cos(heading - half_fov), math.sin(heading - half_fov), 0.0])
    n_left, n_right = np.cross(left, _UP), np.cross(_UP, right)  # p . n >= 0 on the inner side of each limit
    for f, face in enumerate(FACES):
        region = None
        if half_fov < math.pi:
            a, b = _half_space(n_left, face), _half_space(n_right, face)
            region = a.intersection(b) if half_fov <= math.pi / 2 else a.union(b)
        if low > -math.pi / 2:
            above = _elevation_above(low, f)
            region = above if region is None else region.intersection(above)
        if high < math.pi / 2:
            below = SQUARE.difference(_elevation_above(high, f))
            region = below if region is None else region.intersection(below)
        if region is not None:
            if SQUARE.difference(region).area <= 1e-15:  # the whole face, up to rounding
                region = None
            else:
                shapely.prepare(region)
        out.append(region)
    return tuple(out)


def within_range(bodies: ConvexBodies, b: int, max_range: float) -> list[shapely.Geometry | None]:
    """Per cube face, the directions along which body ``b`` (eye at the origin, outside it) is entered within
    ``max_range`` metres, as a polygon in face coordinates (None: not seen through that face within range).

    The entry point lies on a face of the body turned towards the eye; the points of that face's plane within
    range form a disc around the eye's foot on the plane, so the directions sought are the union, over the faces
    turned towards the eye, of the central projections of (face polygon ∩ disc)."""
    pieces: list[np.ndarray] = []
    for p in range(bodies.normals.shape[1]):
        c = bodies.offsets[b, p]
        ids = bodies.faces[b, p]
        ids = ids[ids >= 0]
        h = -c  # distance from the eye to the plane, positive on the side the eye looks at
        if len(ids) < 3 or h <= 0 or h >= max_range:
            continue
        normal = bodies.normals[b, p]
        foot = c * normal
        e1 = np.cross(normal, [0.0, 0.0, 1.0] if abs(normal[2]) < 0.9 else [1.0, 0.0, 0.0])
        e1 /= np.linalg.norm(e1)
        e2 = np.cross(normal, e1)
        corners3 = bodies.vertices[ids]
        flat = shapely.Polygon(np.column_stack([corners3 @ e1, corners3 @ e2]))
        radius = math.sqrt(max_range * max_range - h * h)
        angle = np.linspace(0, 2 * math.pi, CURVE_POINTS, endpoint=False)
        disc = shapely.Polygon(np.column_stack([np.cos(angle), np.sin(angle)]) * radius)
        near = flat.convex_hull.intersection(disc)
        if not isinstance(near, shapely.Polygon) or near.is_empty:
            continue
        ab = np.asarray(near.exterior.coords)[:-1]
        pieces.append(foot + ab[:, :1] * e1 + ab[:, 1:] * e2)
    out: list[shapely.Geometry | None] = []
    for forward, eu, ev in FACES:
        drawn = []
        for piece in pieces:
            for m in (forward - eu, forward + eu, forward - ev, forward + ev):
                piece = clip_plane(piece, m)
                if len(piece) < 3:
                    break
            else:
                d = piece @ forward
                polygon = shapely.Polygon(np.column_stack([piece @ eu, piece @ ev]) / d[:, None])
                if polygon.is_valid and polygon.area > 0:
                    drawn.append(polygon)
        out.append(shapely.union_all(drawn) if drawn else None)
    return out


def clip_plane(polygon: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Convex 3D ``polygon`` (k, 3) clipped to ``m . x >= 0``."""
    g = polygon @ m
    out = []
    k = len(polygon)
    for i in range(k):
        j = (i + 1) % k
        if g[i] >= 0:
            out.append(polygon[i])
        if (g[i] >= 0) != (g[j] >= 0):
            out.append(polygon[i] + (polygon[j] - polygon[i]) * (g[i] / (g[i] - g[j])))
    return np.array(out).reshape(-1, 3)


def face_direction(f: int, uv: np.ndarray) -> np.ndarray:
    """Directions (k, 3), not unit, of the points ``uv`` (k, 2) on cube face ``f``."""
    forward, eu, ev = FACES[f]
    return forward + uv[:, :1] * eu + uv[:, 1:] * ev
