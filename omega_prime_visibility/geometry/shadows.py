"""Exact plane regions for the area measure: the shadow a body casts from a viewpoint, a field-of-view wedge, and
the area of a polygon inside a range circle (shapely polygon clipping and a closed formula, no sampling).

Coordinates here are relative to the viewpoint (the origin), metres; angles are radians counter-clockwise from +x.
Regions reach out to a distance ``reach`` (metres) and are exact within it: a circle's arc is drawn as chords
pushed out so that they never come nearer than ``reach``. A shadow's arc lies beyond its body as well (a wall of a
building that reaches past ``reach``): an arc nearer than part of the body would close the hull in front of it.
"""

from __future__ import annotations

import math

import numpy as np
import shapely

from .rings import Rings

ARC_STEP = math.radians(30.0)
"""Largest angle one chord of an arc spans."""


def _arc(low: float, high: float, reach: float) -> np.ndarray:
    """Points on an arc from direction ``low`` to ``high`` (radians, ``low <= high``) whose chords stay at least
    ``reach`` metres from the origin, shape (k, 2)."""
    steps = max(1, math.ceil((high - low) / ARC_STEP))
    radius = reach / math.cos(0.5 * (high - low) / steps)
    angles = np.linspace(low, high, steps + 1)
    return radius * np.column_stack([np.cos(angles), np.sin(angles)])


def _behind(points: np.ndarray, reach: float) -> shapely.Geometry:
    """The region behind a convex chain or segment ``points`` (shape (k, 2), not containing the origin, spanning
    less than π) out to ``reach``: the convex hull of the points and the arc across their directions."""
    angles = np.arctan2(points[:, 1], points[:, 0])
    mid = angles[0]
    turned = (angles - mid + np.pi) % (2 * np.pi) - np.pi
    arc = _arc(mid + turned.min(), mid + turned.max(), _beyond(np.hypot(points[:, 0], points[:, 1]).max(), reach))
    return shapely.convex_hull(shapely.multipoints(np.concatenate([points, arc])))


def _beyond(farthest: float | np.ndarray, reach: float) -> float | np.ndarray:
    """The radius of a shadow's arc: ``reach``, or farther where the body reaches past it (``farthest``, metres)."""
    return np.maximum(reach, 1.01 * farthest + 1.0)


def shadow(ring: np.ndarray, reach: float, convex: bool | None = None) -> shapely.Geometry:
    """Where a polygon ``ring`` (vertices, shape (k, 2), origin outside) hides what lies behind it, itself included,
    within ``reach`` metres of the origin: every point whose segment from the origin meets the polygon.

    Examples
    --------
    >>> square = np.array([[1.0, -1], [3, -1], [3, 1], [1, 1]])
    >>> region = shadow(square, 10.0)
    >>> bool(region.contains(shapely.Point(9, 0))), bool(region.contains(shapely.Point(9, 9.5)))
    (True, False)
    >>> round(region.intersection(shapely.box(4, 0, 5, 6)).area, 9)  # the cone |y| <= x: 4.5 m² of it
    4.5
    """
    ring = np.asarray(ring, dtype=np.float64)
    polygon = shapely.Polygon(ring)
    if convex is None:
        convex = abs(shapely.convex_hull(polygon).area - polygon.area) <= 1e-9 * max(polygon.area, 1e-12)
    if convex:
        return _behind(ring, reach)
    parts = [polygon] + [_behind(np.array([ring[k], ring[(k + 1) % len(ring)]]), reach) for k in range(len(ring))]
    return shapely.union_all(parts)


ARC_POINTS = 7
"""Points on the arc behind a convex body in :func:`shadows` (six chords: at most 30° each for a span under 180°)."""


def shadows(rings: Rings, bodies: np.ndarray, centre: np.ndarray, half: np.ndarray, reach: float) -> np.ndarray:
    """:func:`shadow` of many bodies at once: ring ``bodies[k]`` of ``rings`` (origin outside each), with its
    angular span ``centre[k] ± half[k]`` (radians, :func:`..spans.angular_spans`); object array of geometries.

    Convex bodies are built in one vectorised call (the hull of their vertices and :data:`ARC_POINTS` arc points);
    others one by one.
    """
    bodies = np.asarray(bodies, dtype=np.int64)
    out = np.empty(len(bodies), dtype=object)
    if not len(bodies):
        return out
    sub = rings.take(bodies)
    sizes = sub.sizes
    owner = np.repeat(np.arange(len(bodies)), sizes)
    polygons = shapely.polygons(shapely.linearrings(sub.coords, indices=owner))
    hull_area = shapely.area(shapely.convex_hull(polygons))
    convex = np.abs(hull_area - shapely.area(polygons)) <= 1e-9 * np.maximum(hull_area, 1e-12)
    step = 2.0 * half / (ARC_POINTS - 1)
    angles = (centre - half)[:, None] + step[:, None] * np.arange(ARC_POINTS)[None, :]
    farthest = np.maximum.reduceat(np.hypot(sub.coords[:, 0], sub.coords[:, 1]), sub.offsets[:-1])
    radius = (_beyond(farthest, reach) / np.cos(0.5 * step))[:, None]
    arc = np.stack([radius * np.cos(angles), radius * np.sin(angles)], axis=-1).reshape(-1, 2)
    points = np.concatenate([sub.coords, arc])
    index = np.concatenate([owner, np.repeat(np.arange(len(bodies)), ARC_POINTS)])
    order = np.argsort(index, kind="stable")
    hulls = shapely.convex_hull(shapely.multipoints(points[order], indices=index[order]))
    out[convex] = hulls[convex]
    for k in np.flatnonzero(~convex).tolist():
        out[k] = shadow(sub.ring(k), reach, convex=False)
    return out


def wall_shadow(segments: np.ndarray, reach: float) -> shapely.Geometry:
    """The shadow of two-sided wall segments (shape (s, 2, 2), not through the origin) within ``reach``."""
    return shapely.union_all([_behind(s, reach) for s in segments]) if len(segments) else shapely.Polygon()


def wedge(heading: float, fov: float, reach: float) -> shapely.Geometry:
    """The field of view ``[heading - fov / 2, heading + fov / 2]`` (radians, ``fov < 2π``) out to ``reach``.

    Examples
    --------
    >>> round(wedge(0.0, math.pi, 3.0).intersection(shapely.box(-2, -2, 2, 2)).area, 12)  # a half plane
    8.0
    """
    arc = _arc(heading - 0.5 * fov, heading + 0.5 * fov, reach)
    return shapely.Polygon(np.concatenate([[[0.0, 0.0]], arc]))


def _segment_disc_area(a: np.ndarray, b: np.ndarray, radius: float) -> np.ndarray:
    """Signed area of the triangle (origin, a, b) inside the circle of ``radius`` about the origin, per row."""

    def sector(p, q):
        return 0.5 * radius * radius * np.arctan2(p[:, 0] * q[:, 1] - p[:, 1] * q[:, 0], np.einsum("ij,ij->i", p, q))

    d = b - a
    qa = np.einsum("ij,ij->i", d, d)
    qb = 2.0 * np.einsum("ij,ij->i", a, d)
    qc = np.einsum("ij,ij->i", a, a) - radius * radius
    root = np.sqrt(np.maximum(qb * qb - 4.0 * qa * qc, 0.0))
    safe = np.where(qa > 0, qa, 1.0)
    t1 = np.clip((-qb - root) / (2.0 * safe), 0.0, 1.0)
    t2 = np.clip((-qb + root) / (2.0 * safe), 0.0, 1.0)
    p1, p2 = a + t1[:, None] * d, a + t2[:, None] * d
    inside = 0.5 * (p1[:, 0] * p2[:, 1] - p1[:, 1] * p2[:, 0])
    return np.where(qa > 0, sector(a, p1) + inside + sector(p2, b), 0.0)


def disc_area(geometry: shapely.Geometry, radius: float) -> float:
    """Area of a (multi)polygon inside the circle of ``radius`` metres about the origin, exactly.

    Examples
    --------
    >>> round(disc_area(shapely.box(-5, -5, 5, 5), 1.0), 12) == round(math.pi, 12)
    True
    >>> round(disc_area(shapely.box(0, 0, 5, 5), 2.0), 12) == round(math.pi, 12)  # a quarter of the disc
    True
    >>> disc_area(shapely.box(0, 0, 1, 1), math.inf)
    1.0
    """
    if geometry.is_empty:
        return 0.0
    if not math.isfinite(radius):
        return float(geometry.area)
    total = 0.0
    for polygon in shapely.get_parts(geometry):
        if polygon.geom_type != "Polygon" or polygon.is_empty:
            continue
        for k, ring in enumerate([polygon.exterior, *polygon.interiors]):
            xy = np.asarray(ring.coords)[:-1]
            if len(xy) < 3:
                continue
            area = abs(float(_segment_disc_area(xy, np.roll(xy, -1, axis=0), radius).sum()))
            total += area if k == 0 else -area
    return max(total, 0.0)
