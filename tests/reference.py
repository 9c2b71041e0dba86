"""Independent brute-force reference for 2D visibility, used to check the real engines.

Everything here is written from scratch with numpy (shapely is only used to read the input
geometries and to validate generated scenes), so that it shares no code with the engines under test.

Definitions (angles in radians, counter-clockwise from +x, distances in metres):

* A scene is an observer point ``o``, a list of object polygons (which may overlap each other) and a
  list of static occluders (``Polygon``, ``MultiPolygon``, ``LineString`` or ``MultiLineString``; a
  line string is a thin wall that blocks rays from both sides).  Objects flagged as *transparent*
  never block anything and are never reported as occluders (ego, objects containing the observer).
* The angular extent of a target ``T`` (observer outside ``T``) is the set of directions whose ray
  from ``o`` hits ``T``: an interval ``[start, start + width]`` with ``0 < width < 2*pi``, possibly
  straddling the -pi/pi direction.
* ``visibility(T)`` is the measure of the directions within ``T``'s extent along which the first thing
  hit (among all non-transparent objects and all static occluders) is ``T``, divided by the measure of
  the extent.
* ``occluders(T)`` are the non-transparent objects ``J != T`` that are hit strictly before ``T`` along at
  least one direction inside ``T``'s extent; ``static_occluders(T)`` likewise for static occluders.

The reference is a dense ray cast: for each target, ``n_rays`` rays are cast through the midpoints of
``n_rays`` equal sub-intervals of its extent, and for each ray the nearest hit distance on every
object / static occluder is computed by a vectorised ray-segment intersection over all their edges.
The discretisation error of the fractions is of order ``1 / n_rays``.

The module also provides seeded random scene generators (:func:`random_box`, :func:`random_scene`)
for property tests, and hypothesis strategies (:func:`scenes`) when hypothesis is installed.
"""

from __future__ import annotations

from collections.abc import Iterator, Sequence
from dataclasses import dataclass
from typing import Any, NamedTuple

import numpy as np
import shapely
from shapely import make_valid
from shapely.geometry import LineString, MultiLineString, MultiPolygon, Point, Polygon
from shapely.geometry.base import BaseGeometry

__all__ = [
    "ReferenceResult",
    "Scene",
    "angular_extent_reference",
    "dense_traffic",
    "geometry_segments",
    "long_static_scene",
    "nearest_hit_distances",
    "occluder_disagreements",
    "occlusion_confirmed",
    "random_box",
    "random_scene",
    "random_static",
    "reference_visibility",
    "scene_series",
    "walls_with_needles",
]

TWO_PI = 2.0 * np.pi

#: Relative tolerance used to decide that a hit is *strictly* before another one.
_TIE_RTOL = 1e-9
#: Tolerance on the segment parameter so that rays through a shared vertex hit at least one edge.
_SEG_TOL = 1e-12
#: Upper bound on the number of ray x edge pairs evaluated at once (memory bound).
_CHUNK_PAIRS = 2_000_000


# ----------------------------------------------------------------------------------------------
# Geometry helpers
# ----------------------------------------------------------------------------------------------


def _wrap_angle(a: np.ndarray | float) -> np.ndarray:
    """Wrap angles into ``[-pi, pi)``."""
    return (np.asarray(a, dtype=float) + np.pi) % TWO_PI - np.pi


def _as_geometry(geom: Any) -> BaseGeometry:
    """Convert a shapely geometry or an ``(N, 2)`` vertex array (polygon ring) to a shapely geometry."""
    if isinstance(geom, BaseGeometry):
        return geom
    arr = np.asarray(geom, dtype=float)
    if arr.ndim != 2 or arr.shape[1] != 2 or arr.shape[0] < 3:
        raise TypeError(f"cannot interpret {type(geom).__name__} of shape {arr.shape} as a polygon")
    return Polygon(arr)


def _ring_segments(coords: np.ndarray) -> np.ndarray:
    coords = np.asarray(coords, dtype=float)[:, :2]
    if len(coords) < 2:
        return np.empty((0, 4))
    return np.hstack([coords[:-1], coords[1:]])


def geometry_segments(geom: Any) -> np.ndarray:
    """Return all boundary segments of a geometry.

    Parameters
    ----------
    geom : shapely geometry or array_like
        A ``Polygon`` (exterior and interior rings are used), ``MultiPolygon``, ``LineString``,
        ``LinearRing``, ``MultiLineString`` or ``GeometryCollection`` of those, or an ``(N, 2)``
        array of polygon vertices.

    Returns
    -------
    np.ndarray
        ``(k, 4)`` array of segments ``[x1, y1, x2, y2]``; zero-length segments are dropped.
    """
    geom = _as_geometry(geom)
    if geom.is_empty:
        return np.empty((0, 4))
    if isinstance(geom, Polygon):
        parts = [_ring_segments(np.asarray(geom.exterior.coords))]
        parts += [_ring_segments(np.asarray(r.coords)) for r in geom.interiors]
    elif isinstance(geom, LineString):  # includes LinearRing
        parts = [_ring_segments(np.asarray(geom.coords))]
    elif hasattr(geom, "geoms"):  # MultiPolygon, MultiLineString, GeometryCollection
        parts = [geometry_segments(g) for g in geom.geoms]
    else:
        raise TypeError(f"unsupported geometry type for an occluder: {geom.geom_type}")
    segs = np.vstack([p for p in parts if len(p)] or [np.empty((0, 4))])
    keep = (segs[:, 0] != segs[:, 2]) | (segs[:, 1] != segs[:, 3])
    return segs[keep]


def angular_extent_reference(observer: Any, polygon: Any) -> tuple[float, float]:
    """Angular extent of a polygon as seen from an observer outside it.

    The vertex angles are unwrapped along the exterior ring (each edge subtends less than pi as
    the observer is not on it), so the result is robust to the -pi/pi wrap.

    Parameters
    ----------
    observer : array_like
        Observer position ``(2,)``.
    polygon : shapely.Polygon or array_like
        The target polygon (or its ``(N, 2)`` vertices).

    Returns
    -------
    tuple of float
        ``(start, width)`` in radians with ``start`` in ``[-pi, pi)`` and ``0 < width < 2*pi``; the
        extent is ``[start, start + width]`` (``start + width`` may exceed pi).

    Raises
    ------
    ValueError
        If the observer is inside or on the boundary of the polygon.
    """
    o = np.asarray(observer, dtype=float).reshape(2)
    poly = _as_geometry(polygon)
    if not isinstance(poly, Polygon):
        raise TypeError(f"angular extent needs a Polygon, got {poly.geom_type}")
    if poly.intersects(Point(o)):
        raise ValueError("observer is inside or on the boundary of the polygon")
    ring = np.asarray(poly.exterior.coords, dtype=float)[:, :2]
    ang = np.arctan2(ring[:, 1] - o[1], ring[:, 0] - o[0])
    steps = _wrap_angle(np.diff(ang))
    unwrapped = ang[0] + np.concatenate([[0.0], np.cumsum(steps)])
    lo, hi = float(unwrapped.min()), float(unwrapped.max())
    width = hi - lo
    if not 0.0 < width < TWO_PI:
        raise ValueError(f"degenerate angular extent width {width}")
    return float(_wrap_angle(lo)), width


def _edge_intervals(o: np.ndarray, segs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Angular interval ``[start, start + width]`` subtended by each segment, and an 'always keep' mask."""
    a1 = np.arctan2(segs[:, 1] - o[1], segs[:, 0] - o[0])
    a2 = np.arctan2(segs[:, 3] - o[1], segs[:, 2] - o[0])
    delta = _wrap_angle(a2 - a1)
    start = a1 + np.minimum(delta, 0.0)
    width = np.abs(delta)
    # Segments touching the observer or (nearly) passing through it: angles are unreliable.
    r1 = np.hypot(segs[:, 0] - o[0], segs[:, 1] - o[1])
    r2 = np.hypot(segs[:, 2] - o[0], segs[:, 3] - o[1])
    always = (r1 < 1e-9) | (r2 < 1e-9) | (width > np.pi - 1e-6)
    return start, width, always


def _ray_segment_distances(o: np.ndarray, angles: np.ndarray, segs: np.ndarray) -> np.ndarray:
    """Hit distance of every ray on every segment, ``inf`` where it misses. Shape ``(n_rays, k)``."""
    dx = np.cos(angles)[:, None]
    dy = np.sin(angles)[:, None]
    px, py = segs[:, 0] - o[0], segs[:, 1] - o[1]
    ex, ey = segs[:, 2] - segs[:, 0], segs[:, 3] - segs[:, 1]
    # o + t d = p + s e  =>  t = (w x e) / (d x e),  s = (w x d) / (d x e),  with w = p - o.
    denom = dx * ey - dy * ex
    num_t = px * ey - py * ex
    num_s = px * dy - py * dx
    with np.errstate(divide="ignore", invalid="ignore"):
        t = num_t / denom
        s = num_s / denom
    seg_len = np.hypot(ex, ey)
    ok = (np.abs(denom) > 1e-14 * seg_len) & (t > 0.0) & (s >= -_SEG_TOL) & (s <= 1.0 + _SEG_TOL)
    return np.where(ok, t, np.inf)


def _owner_distances(
    o: np.ndarray, angles: np.ndarray, segs: np.ndarray, owner: np.ndarray, n_owners: int
) -> np.ndarray:
    """Nearest hit distance per ray and owner. ``segs`` must be sorted by ``owner``."""
    out = np.full((len(angles), n_owners), np.inf)
    if len(segs) == 0 or len(angles) == 0:
        return out
    present, first = np.unique(owner, return_index=True)
    chunk = max(1, _CHUNK_PAIRS // len(segs))
    for i in range(0, len(angles), chunk):
        t = _ray_segment_distances(o, angles[i : i + chunk], segs)
        out[i : i + chunk, present] = np.minimum.reduceat(t, first, axis=1)
    return out


def nearest_hit_distances(observer: Any, geometries: Sequence[Any], angles: Any) -> np.ndarray:
    """Distance from the observer to the nearest boundary hit of each geometry along each ray.

    Parameters
    ----------
    observer : array_like
        Observer position ``(2,)``.
    geometries : sequence of shapely geometries or vertex arrays
        Polygons (all rings), multi-polygons, line strings or multi-line strings.
    angles : array_like
        Ray directions in radians, shape ``(m,)``.

    Returns
    -------
    np.ndarray
        ``(m, len(geometries))`` distances, ``inf`` where the ray misses the geometry.
    """
    o = np.asarray(observer, dtype=float).reshape(2)
    angles = np.atleast_1d(np.asarray(angles, dtype=float))
    seg_list = [geometry_segments(g) for g in geometries]
    owner = np.concatenate([np.full(len(s), i) for i, s in enumerate(seg_list)] or [np.empty(0, int)])
    segs = np.vstack(seg_list) if seg_list else np.empty((0, 4))
    return _owner_distances(o, angles, segs, owner.astype(int), len(seg_list))


# ----------------------------------------------------------------------------------------------
# Reference visibility
# ----------------------------------------------------------------------------------------------


@dataclass
class ReferenceResult:
    """Result of :func:`reference_visibility`.

    Attributes
    ----------
    visibility : np.ndarray
        ``(n_objects,)`` visible fraction of each object's angular extent in ``[0, 1]``; ``nan`` for
        transparent objects.
    occluders : list of dict
        Per object, ``{object position: fraction of the extent along which it is hit strictly before
        the object}``; only positive fractions are listed, empty for transparent objects.
    static_occluders : list of dict
        Per object, ``{position in the static list: blocked fraction}``, as for ``occluders``.
    angular_extent : np.ndarray
        ``(n_objects,)`` width of each object's angular extent in radians (``nan`` when the observer
        is inside a transparent object).
    extent_start : np.ndarray
        ``(n_objects,)`` start angle of each extent in ``[-pi, pi)`` (``nan`` as above).
    in_view : np.ndarray
        ``(n_objects,)`` fraction of the extent inside the field of view along which the object itself is hit
        within range (occlusion ignored); 1 without a sensor model, ``nan`` for transparent objects.
    in_fov : np.ndarray
        ``(n_objects,)`` fraction of the extent inside the field of view (range ignored).
    """

    visibility: np.ndarray
    occluders: list[dict[int, float]]
    static_occluders: list[dict[int, float]]
    angular_extent: np.ndarray
    extent_start: np.ndarray
    in_view: np.ndarray
    in_fov: np.ndarray


def _interval_overlaps(s1: float, w1: float, s2: np.ndarray, w2: np.ndarray, margin: float) -> np.ndarray:
    """Whether circular intervals ``[s2, s2 + w2]`` intersect ``[s1, s1 + w1]`` (with a margin)."""
    x = (s2 - s1) % TWO_PI
    return (x <= w1 + margin) | (x + w2 >= TWO_PI - margin)


def reference_visibility(
    observer: Any,
    objects: Sequence[Any],
    statics: Sequence[Any] = (),
    transparent: Any = None,
    n_rays: int = 20000,
    prefilter: bool = True,
    heading: float = 0.0,
    fov: float = TWO_PI,
    max_range: float = np.inf,
    blocking: Any = None,
) -> ReferenceResult:
    """Brute-force visibility of every object by dense ray casting.

    With a sensor model (``fov`` < 2 pi or a finite ``max_range``) a ray counts only when it lies inside the
    field of view ``[heading - fov / 2, heading + fov / 2]`` and hits the target within ``max_range``; the
    visibility is the fraction of the extent's rays that count and are not blocked, and occluders are counted on
    counting rays only.

    Parameters
    ----------
    observer : array_like
        Observer position ``(2,)``.
    objects : sequence of shapely.Polygon or array_like
        Object footprints (may overlap each other). The observer must be outside every
        non-transparent object.
    statics : sequence of shapely geometries
        Static occluders: ``Polygon``, ``MultiPolygon``, ``LineString`` or ``MultiLineString``.
    transparent : array_like of bool, optional
        ``(n_objects,)`` mask of objects that never block and are never occluders (ego, objects
        containing the observer). Their visibility is ``nan``. Default: none transparent.
    n_rays : int
        Number of rays per target (midpoints of equal sub-intervals of its extent).
    prefilter : bool
        Skip edges whose angular interval does not meet the target's extent (pure speed-up; the
        result is identical up to floating point).
    blocking : array_like of bool, optional
        ``(n_objects,)`` mask of objects that may block (``occluders=``); the others are still measured as
        targets, against the blocking ones only, and are never occluders. Default: all may block.

    Returns
    -------
    ReferenceResult
        Visibility fractions, occluders with blocked fractions and angular extents.

    Raises
    ------
    ValueError
        If the observer is inside or on a non-transparent object, or ``n_rays < 1``.
    """
    if n_rays < 1:
        raise ValueError("n_rays must be >= 1")
    o = np.asarray(observer, dtype=float).reshape(2)
    objs = [_as_geometry(g) for g in objects]
    stats = [_as_geometry(g) for g in statics]
    n_obj, n_stat = len(objs), len(stats)
    if transparent is None:
        transp = np.zeros(n_obj, dtype=bool)
    else:
        transp = np.asarray(transparent, dtype=bool).reshape(-1)
        if transp.shape != (n_obj,):
            raise ValueError(f"transparent mask has shape {transp.shape}, expected ({n_obj},)")

    starts = np.full(n_obj, np.nan)
    widths = np.full(n_obj, np.nan)
    pt = Point(o)
    for i, g in enumerate(objs):
        if not isinstance(g, Polygon):
            raise TypeError(f"object {i} is a {g.geom_type}, expected a Polygon")
        if g.intersects(pt):
            if not transp[i]:
                raise ValueError(f"observer is inside or on non-transparent object {i}")
            continue
        starts[i], widths[i] = angular_extent_reference(o, g)

    blocks = np.ones(n_obj, dtype=bool) if blocking is None else np.asarray(blocking, dtype=bool).reshape(-1)
    # Blockers: non-transparent objects (owner ids 0..n_obj-1) then statics (n_obj..n_obj+n_stat-1); objects
    # that may not block come last, each measured as a target only.
    owners = [i for i in range(n_obj) if not transp[i] and blocks[i]] + list(range(n_obj, n_obj + n_stat))
    n_blockers = len(owners)
    owners += [i for i in range(n_obj) if not transp[i] and not blocks[i]]
    geoms = objs + stats
    seg_list = [geometry_segments(geoms[k]) for k in owners]
    owner_col = np.concatenate([np.full(len(s), c, dtype=int) for c, s in enumerate(seg_list)] or [np.empty(0, int)])
    segs = np.vstack(seg_list) if seg_list else np.empty((0, 4))
    col_of = {k: c for c, k in enumerate(owners)}
    e_start, e_width, e_always = _edge_intervals(o, segs)

    visibility = np.full(n_obj, np.nan)
    in_view = np.full(n_obj, np.nan)
    in_fov = np.full(n_obj, np.nan)
    occ: list[dict[int, float]] = [{} for _ in range(n_obj)]
    socc: list[dict[int, float]] = [{} for _ in range(n_obj)]
    for i in range(n_obj):
        if transp[i]:
            continue
        start, width = starts[i], widths[i]
        angles = start + (np.arange(n_rays) + 0.5) * (width / n_rays)
        if prefilter:
            keep = e_always | _interval_overlaps(start, width, e_start, e_width, 1e-9)
            keep |= owner_col == col_of[i]
        else:
            keep = np.ones(len(segs), dtype=bool)
        keep &= (owner_col < n_blockers) | (owner_col == col_of[i])  # bodies that may not block never do
        dist = _owner_distances(o, angles, segs[keep], owner_col[keep], len(owners))
        d_t = dist[:, col_of[i]]
        if not np.all(np.isfinite(d_t)):  # pragma: no cover - would indicate a bug in the extent
            raise RuntimeError(f"{np.sum(~np.isfinite(d_t))} rays inside the extent of object {i} miss it")
        blocked = dist < (d_t - _TIE_RTOL * (1.0 + d_t))[:, None]
        blocked[:, col_of[i]] = False
        inside_fov = (angles - (heading - fov / 2)) % TWO_PI <= fov if fov < TWO_PI else np.ones(n_rays, dtype=bool)
        counts = inside_fov & (d_t <= max_range)
        blocked &= counts[:, None]
        in_fov[i] = np.count_nonzero(inside_fov) / n_rays
        in_view[i] = np.count_nonzero(counts) / n_rays
        visibility[i] = in_view[i] - np.count_nonzero(blocked.any(axis=1)) / n_rays
        frac = np.count_nonzero(blocked, axis=0) / n_rays
        for c in np.flatnonzero(frac):
            k = owners[c]
            if k < n_obj:
                occ[i][k] = float(frac[c])
            else:
                socc[i][k - n_obj] = float(frac[c])
    return ReferenceResult(
        visibility=visibility,
        occluders=occ,
        static_occluders=socc,
        angular_extent=widths,
        extent_start=starts,
        in_view=in_view,
        in_fov=in_fov,
    )


# ----------------------------------------------------------------------------------------------
# Random scene generators
# ----------------------------------------------------------------------------------------------


class Scene(NamedTuple):
    """A random scene (unpack as ``observer, objects, statics, transparent = scene``)."""

    observer: np.ndarray
    objects: list[Polygon]
    statics: list[BaseGeometry]
    transparent: np.ndarray


def _place(local: np.ndarray, center: Any, yaw: float) -> np.ndarray:
    c, s = np.cos(yaw), np.sin(yaw)
    rot = np.array([[c, -s], [s, c]])
    return local @ rot.T + np.asarray(center, dtype=float).reshape(2)


def _rect(length: float, width: float) -> np.ndarray:
    hl, hw = length / 2.0, width / 2.0
    return np.array([[-hl, -hw], [hl, -hw], [hl, hw], [-hl, hw]])


def random_box(
    rng: np.random.Generator,
    center: Any = (0.0, 0.0),
    yaw: float | None = None,
    length: float | None = None,
    width: float | None = None,
) -> Polygon:
    """Random oriented rectangle of car / truck size.

    Parameters
    ----------
    rng : np.random.Generator
        Random generator.
    center : array_like
        Box centre ``(2,)``.
    yaw : float, optional
        Heading in radians; uniform in ``[-pi, pi)`` if not given.
    length, width : float, optional
        Box dimensions in metres. If not given, a car (length 3-5.5 m, width 1.5-2.1 m) is drawn with
        probability 0.7, otherwise a truck / bus (length 5.5-18 m, width 2.1-2.6 m).

    Returns
    -------
    shapely.Polygon
        Counter-clockwise rectangle.
    """
    truck = rng.random() < 0.3
    if length is None:
        length = rng.uniform(5.5, 18.0) if truck else rng.uniform(3.0, 5.5)
    if width is None:
        width = rng.uniform(2.1, 2.6) if truck else rng.uniform(1.5, 2.1)
    if yaw is None:
        yaw = rng.uniform(-np.pi, np.pi)
    return Polygon(_place(_rect(length, width), center, yaw))


def random_static(rng: np.random.Generator, center: Any = (0.0, 0.0), kind: str | None = None) -> BaseGeometry:
    """Random static occluder around ``center``.

    Parameters
    ----------
    rng : np.random.Generator
        Random generator.
    center : array_like
        Approximate centre ``(2,)``.
    kind : str, optional
        One of ``"box"``, ``"L"``, ``"U"``, ``"star"`` (non-convex star-shaped polygon),
        ``"multipolygon"``, ``"line"``, ``"multiline"``; random if not given.

    Returns
    -------
    shapely geometry
        A valid ``Polygon``, ``MultiPolygon``, ``LineString`` or ``MultiLineString``.
    """
    kinds = ("box", "L", "U", "star", "multipolygon", "line", "multiline")
    if kind is None:
        kind = str(rng.choice(kinds))
    yaw = rng.uniform(-np.pi, np.pi)
    if kind == "box":
        return Polygon(_place(_rect(rng.uniform(4, 30), rng.uniform(4, 20)), center, yaw))
    if kind in ("L", "U"):
        a, b = rng.uniform(8, 25), rng.uniform(8, 25)
        t = rng.uniform(2, min(a, b) / 3)
        if kind == "L":
            loc = [(0, 0), (a, 0), (a, t), (t, t), (t, b), (0, b)]
        else:
            loc = [(0, 0), (a, 0), (a, b), (a - t, b), (a - t, t), (t, t), (t, b), (0, b)]
        local = np.array(loc, dtype=float) - [a / 2, b / 2]
        return Polygon(_place(local, center, yaw))
    if kind == "star":
        k = int(rng.integers(5, 11))
        ang = np.sort(rng.uniform(0, TWO_PI, k))
        while np.min(np.diff(np.r_[ang, ang[0] + TWO_PI])) < 0.05:
            ang = np.sort(rng.uniform(0, TWO_PI, k))
        rad = rng.uniform(2, 10, k)
        local = np.c_[rad * np.cos(ang), rad * np.sin(ang)]
        return Polygon(_place(local, center, yaw))
    if kind == "multipolygon":
        n = int(rng.integers(2, 4))
        parts, x = [], 0.0
        for _ in range(n):
            length, width = rng.uniform(3, 12), rng.uniform(3, 12)
            parts.append(_rect(length, width) + np.array([x + length / 2, 0.0]))
            x += length + rng.uniform(1, 6)
        shift = np.array([x / 2, 0.0])
        return MultiPolygon([Polygon(_place(p - shift, center, yaw)) for p in parts])
    if kind == "line":
        n = int(rng.integers(2, 5))
        steps = rng.uniform(4, 15, n - 1)
        turns = np.cumsum(np.r_[0.0, rng.uniform(-np.pi / 2, np.pi / 2, n - 2)])
        local = np.vstack([[0.0, 0.0], np.cumsum(np.c_[steps * np.cos(turns), steps * np.sin(turns)], 0)])
        return LineString(_place(local - local.mean(axis=0), center, yaw))
    if kind == "multiline":
        lines = []
        for _ in range(int(rng.integers(2, 4))):
            p = rng.uniform(-10, 10, 2)
            a = rng.uniform(0, TWO_PI)
            q = p + rng.uniform(4, 12) * np.array([np.cos(a), np.sin(a)])
            lines.append(_place(np.array([p, q]), center, yaw))
        return MultiLineString(lines)
    raise ValueError(f"unknown static kind {kind!r}")


def _polar(o: np.ndarray, dist: float, ang: float) -> np.ndarray:
    return o + dist * np.array([np.cos(ang), np.sin(ang)])


def random_scene(
    rng: np.random.Generator,
    n_objects: int,
    overlap: bool = True,
    with_statics: bool = True,
    include_ego: bool = False,
    radius: float = 60.0,
    n_statics: int | None = None,
    p_wrap: float = 0.2,
    p_behind: float = 0.3,
    clearance: float = 0.3,
    max_tries: int = 2000,
) -> Scene:
    """Seeded random traffic scene for property tests.

    Parameters
    ----------
    rng : np.random.Generator
        Random generator (the scene is a deterministic function of its state).
    n_objects : int
        Number of road users besides the ego.
    overlap : bool
        If True, objects may overlap each other and static occluders (and some are placed on purpose
        so that they overlap another object). If False, no two objects / static occluders intersect.
    with_statics : bool
        Whether to generate static occluders (a mix of boxes, L / U shaped and star-shaped non-convex
        polygons, multi-polygons, line strings and multi-line strings).
    include_ego : bool
        If True, object 0 is the ego box, which contains the observer and is marked transparent.
    radius : float
        Objects' centres are within this distance of the observer.
    n_statics : int, optional
        Number of static occluders (default: 1-5 if ``with_statics``).
    p_wrap : float
        Probability that an object is placed straddling the -pi/pi direction (directly at -x of the
        observer).
    p_behind : float
        Probability that an object is placed behind an already placed object (partially or fully
        occluded by it).
    clearance : float
        Minimum distance from the observer to every non-transparent object and static occluder;
        the observer is never inside any of them.
    max_tries : int
        Attempts per element before giving up with ``RuntimeError``.

    Returns
    -------
    Scene
        ``(observer, objects, statics, transparent)``; ``len(objects) == n_objects + include_ego``
        and ``transparent`` is True only for the ego.
    """
    o = rng.uniform(-100.0, 100.0, 2)
    pt = Point(o)
    objects: list[Polygon] = []
    statics: list[BaseGeometry] = []

    if include_ego:
        yaw = rng.uniform(-np.pi, np.pi)
        length, width = rng.uniform(3.5, 5.2), rng.uniform(1.6, 2.0)
        local_obs = np.array([rng.uniform(-0.3, 0.3) * length, rng.uniform(-0.3, 0.3) * width])
        center = o - _place(local_obs[None], (0.0, 0.0), yaw)[0]
        ego = random_box(rng, center, yaw, length, width)
        assert ego.contains(pt)
        objects.append(ego)

    def clear_of_observer(g: BaseGeometry) -> bool:
        return g.is_valid and not g.intersects(pt) and g.distance(pt) >= clearance

    if with_statics:
        n_st = int(rng.integers(1, 6)) if n_statics is None else n_statics
        for _ in range(n_st):
            for _ in range(max_tries):
                ang = np.pi + rng.uniform(-0.1, 0.1) if rng.random() < p_wrap else rng.uniform(-np.pi, np.pi)
                g = random_static(rng, _polar(o, rng.uniform(8.0, radius + 10.0), ang))
                if not clear_of_observer(g):
                    continue
                if not overlap and any(g.intersects(h) for h in [*statics, *objects]):
                    continue
                statics.append(g)
                break
            else:
                raise RuntimeError("could not place a static occluder")

    others: list[tuple[float, float]] = []  # (distance, angle) of placed road users' centres
    for _ in range(n_objects):
        for _ in range(max_tries):
            u = rng.random()
            if u < p_wrap:
                center = _polar(o, rng.uniform(4.0, radius), np.pi + rng.uniform(-0.1, 0.1))
            elif u < p_wrap + p_behind and others:
                d_ref, a_ref = others[int(rng.integers(len(others)))]
                dist = d_ref + rng.uniform(3.0, 25.0)
                if dist > radius:
                    continue
                center = _polar(o, dist, a_ref + rng.uniform(-1.0, 1.0) * np.arctan2(2.5, d_ref))
            elif overlap and u < p_wrap + p_behind + 0.15 and others:
                d_ref, a_ref = others[int(rng.integers(len(others)))]
                center = _polar(o, d_ref, a_ref) + rng.uniform(-2.5, 2.5, 2)
            else:
                center = _polar(o, rng.uniform(3.0, radius), rng.uniform(-np.pi, np.pi))
            box = random_box(rng, center)
            if not clear_of_observer(box):
                continue
            if not overlap and any(box.intersects(h) for h in [*statics, *objects]):
                continue
            objects.append(box)
            rel = np.asarray(center) - o
            others.append((float(np.hypot(*rel)), float(np.arctan2(rel[1], rel[0]))))
            break
        else:
            raise RuntimeError("could not place an object")

    transparent = np.zeros(len(objects), dtype=bool)
    if include_ego:
        transparent[0] = True
    return Scene(o, objects, statics, transparent)


def long_static_scene(rng: np.random.Generator, n_objects: int = 25, n_statics: int = 3, radius: float = 90.0) -> Scene:
    """Long thin static occluders (noise barriers, guard rails, kerbs) among scattered, sometimes overlapping cars.

    The family that made VisiLibity's sweep skip a nearer car: its queue of edges ordered by range goes stale
    when long edges stay in it over a wide bearing range (see ``engines/visilibity/polygon_check.py``). The ego
    (object 0, transparent) contains the observer; statics are 0.2-0.8 m wide polygons or LineStrings 40-160 m long, in
    any direction, clear of the observer; cars are placed anywhere within ``radius``.
    """
    o = rng.uniform(-50.0, 50.0, 2)
    pt = Point(o)
    ego = random_box(rng, o, rng.uniform(-np.pi, np.pi), 4.6, 1.9)
    statics: list[BaseGeometry] = []
    while len(statics) < n_statics:
        centre = _polar(o, rng.uniform(5.0, radius), rng.uniform(-np.pi, np.pi))
        length, yaw = rng.uniform(40.0, 160.0), rng.uniform(-np.pi, np.pi)
        if rng.random() < 0.5:
            g: BaseGeometry = Polygon(_place(_rect(length, rng.uniform(0.2, 0.8)), centre, yaw))
        else:
            bend = rng.uniform(-0.3, 0.3)
            local = np.array([[-length / 2, 0.0], [0.0, bend * length / 4], [length / 2, 0.0]])
            g = LineString(_place(local, centre, yaw))
        if not g.intersects(pt) and g.distance(pt) >= 0.5 and not g.intersects(ego):
            statics.append(g)
    objects: list[Polygon] = [ego]
    while len(objects) < n_objects + 1:
        box = random_box(rng, _polar(o, rng.uniform(4.0, radius), rng.uniform(-np.pi, np.pi)))
        if not box.intersects(pt) and box.distance(pt) >= 0.3:
            objects.append(box)
    transparent = np.zeros(len(objects), dtype=bool)
    transparent[0] = True
    return Scene(o, objects, statics, transparent)


# ----------------------------------------------------------------------------------------------
# Hypothesis strategies (optional)
# ----------------------------------------------------------------------------------------------

try:  # pragma: no cover - depends on the environment
    from hypothesis import strategies as st
except ImportError:  # pragma: no cover
    st = None


def dense_traffic(
    rng: np.random.Generator, n_objects: int = 40, pairs: int = 8, offset: Any = (0.0, 0.0)
) -> np.ndarray:
    """One frame of dense highway traffic as trackers deliver it: ``(x, y, length, width, yaw)`` rows, the ego
    (row 0) at ``offset``, cars and trucks within ±60 m on five lanes with lateral noise, overlapping at random,
    plus ``pairs`` bodies laid on an edge of a random car: their edge on its edge's line (exactly, or 0 to 50 µm
    off to either side), parallel or turned by 1e-9 to 1e-8 rad, inside the car or outside touching it, some
    followed by a third body on the same line.

    Parameters
    ----------
    rng : numpy.random.Generator
    n_objects : int
        Rows before the laid bodies and their followers.
    pairs : int
    offset : array_like
        Added to every position (metres): map coordinates such as UTM's for ``(5e5, 5.4e6)``.

    Returns
    -------
    ndarray, shape (k, 5)
        Metres, radians counter-clockwise from +x.
    """
    boxes = [(0.0, 0.0, 4.5, 1.8, rng.normal(0, 0.01))]
    lanes = np.array([-7.0, -3.5, 0.0, 3.5, 7.0])
    while len(boxes) < n_objects - 2 * pairs:
        truck = rng.random() >= 0.8
        length, width = (rng.uniform(8, 16), 2.5) if truck else (4.5, 1.8)
        boxes.append((rng.uniform(-60, 60), rng.choice(lanes) + rng.normal(0, 0.2), length, width, rng.normal(0, 0.02)))
    for _ in range(pairs):
        ax, ay, al, aw, ayaw = boxes[1 + rng.integers(len(boxes) - 1)]
        kind = rng.integers(4)
        delta = 0.0 if kind == 0 else rng.uniform(0, 50e-6) * rng.choice([-1, 1])
        turn = 0.0 if rng.random() < 0.5 else rng.choice([-1, 1]) * rng.choice([1e-9, 3e-9, 1e-8])
        side = rng.choice([-1, 1])
        bl, bw = rng.uniform(3.0, 6.0), rng.uniform(1.0, 2.2)
        along = rng.uniform(-al, al) * (0.3 if kind == 3 else 1.0)
        across = side * (aw / 2 + delta - bw / 2) if rng.random() >= 0.3 else side * (aw / 2 + delta + bw / 2)
        c, s = np.cos(ayaw), np.sin(ayaw)
        boxes.append((ax + c * along - s * across, ay + s * along + c * across, bl, bw, ayaw + turn))
        if rng.random() < 0.5:  # a third body on the same line further along
            along += rng.choice([-1, 1]) * rng.uniform(2, 6)
            across = side * (aw / 2 + rng.uniform(0, 20e-6) - bw / 2)
            boxes.append((ax + c * along - s * across, ay + s * along + c * across, bl, bw, ayaw - turn))
    out = np.array(boxes)
    out[:, :2] += np.asarray(offset, dtype=float)
    return out


def walls_with_needles(rng: np.random.Generator, n_objects: int = 11) -> Scene:
    """A scene of static walls with degenerate geometry around the observer at the origin: three walls each
    with a needle (a spike going out and coming back on itself: a line string ``a, foot, tip, foot, b``, or a
    polygon with such a spike repaired by ``shapely.make_valid`` into a polygon and lines), three boxes with a
    corner each on one ray from the observer (sight lines grazing collinear corners, on alternating sides),
    and ``n_objects`` cars clear of the walls, some of them on that ray beyond the corners. Object 0 is the ego.
    """
    statics: list[BaseGeometry] = []
    while len(statics) < 3:
        c = rng.uniform(-20, 20, 2)
        d = rng.normal(size=2)
        d /= np.linalg.norm(d)
        n = np.array([-d[1], d[0]]) * rng.choice([-1, 1])
        a, b = c - d * rng.uniform(3, 8), c + d * rng.uniform(3, 8)
        foot = c + d * rng.uniform(-2, 2)
        tip = foot + n * rng.uniform(0.5, 4)
        if rng.random() < 0.5:
            wall = LineString([a, foot, tip, foot, b])
        else:
            wall = make_valid(Polygon([a, foot, tip, foot, b, b - 0.3 * n, a - 0.3 * n]))
        if wall.distance(Point(0.0, 0.0)) > 0.5:  # (a wall through the observer is transparent to it)
            statics.append(wall)
    angle = rng.uniform(-np.pi, np.pi)
    u = np.array([np.cos(angle), np.sin(angle)])
    v = np.array([-u[1], u[0]])
    for k, r in enumerate(rng.uniform(3, 25, 3)):
        p, side = u * r, v * (1 if k % 2 else -1)
        statics.append(Polygon([p, p + 1.5 * u, p + 1.5 * u + side, p + side]))
    objects: list[BaseGeometry] = [Polygon(_rect(0.2, 0.2))]
    while len(objects) < n_objects + 1:
        if rng.random() < 0.3:  # on the ray through the corners
            car = Polygon(_place(_rect(2.0, 1.0), u * rng.uniform(27, 35), rng.uniform(0, np.pi)))
        else:
            centre = rng.uniform(-30, 30, 2)
            if np.hypot(*centre) < 2.0:
                continue
            car = Polygon(_place(_rect(4.0, 1.8), centre, rng.uniform(0, np.pi)))
        if not any(car.intersects(s) for s in statics):
            objects.append(car)
    transparent = np.zeros(len(objects), dtype=bool)
    transparent[0] = True
    return Scene(np.zeros(2), objects, statics, transparent)


def occlusion_confirmed(
    observer: Any,
    target: Any,
    occluder: Any,
    n_rays: int = 100_000,
    heading: float = 0.0,
    fov: float = TWO_PI,
    max_range: float = np.inf,
) -> bool:
    """Whether ``occluder`` is hit strictly before ``target`` along some ray, by dense rays aimed at the part of
    the target's extent that the occluder's vertices can reach (for slivers thinner than a scene-wide ray cast);
    with a sensor model, only rays inside the field of view that hit the target within range count.
    """
    o = np.asarray(observer, dtype=float).reshape(2)
    start, width = angular_extent_reference(o, target)
    segs = geometry_segments(occluder)
    verts = np.concatenate([segs[:, :2], segs[:, 2:]])
    rel = np.mod(np.arctan2(verts[:, 1] - o[1], verts[:, 0] - o[0]) - start, TWO_PI)
    inside = rel[rel <= width]
    lo = min(inside.min(initial=width), 0.0 if (rel > width).any() else width)
    hi = max(inside.max(initial=0.0), width if (rel > width).any() else 0.0)
    if hi <= lo:
        return False
    angles = start + lo + (np.arange(n_rays) + 0.5) * (hi - lo) / n_rays
    # and one ray through the middle of each piece between the bearings of both bodies' vertices and of the points
    # where their outlines cross: within a piece neither the order of the two nor their nearest edges change, so
    # a sliver of any width is found (a corner of one body reaching into the other, say)
    crossings = shapely.get_coordinates(_as_geometry(target).boundary.intersection(_as_geometry(occluder).boundary))
    critical = np.concatenate([verts, geometry_segments(target)[:, :2], crossings]).reshape(-1, 2)
    cut = np.mod(np.arctan2(critical[:, 1] - o[1], critical[:, 0] - o[0]) - start, TWO_PI)
    cut = np.unique(np.concatenate([[0.0, width], cut[cut <= width]]))
    middles = 0.5 * (cut[1:] + cut[:-1])[np.diff(cut) > 1e-13]
    angles = np.concatenate([angles, start + middles])
    d = nearest_hit_distances(o, [target, occluder], angles)
    d_t, d_j = d[:, 0], d[:, 1]
    counts = np.isfinite(d_t) & (d_t <= max_range)
    if fov < TWO_PI:
        counts &= (angles - (heading - fov / 2)) % TWO_PI <= fov
    return bool((counts & (d_j < d_t - _TIE_RTOL * (1.0 + d_t))).any())


def occluder_disagreements(
    observer: Any,
    target: Any,
    got: set[int],
    want: dict[int, float],
    bodies: Sequence[Any],
    must_fraction: float,
    **sensor: float,
) -> set[int]:
    """Occluders on which an engine (``got``) and the reference (``want``: blocked fractions) really disagree.

    The engine must list every occluder blocking at least ``must_fraction`` of the target's extent; one it lists
    that the reference's rays did not see counts only if :func:`occlusion_confirmed` (given the same ``sensor``
    keywords: ``heading``, ``fov``, ``max_range``) finds no ray either.
    """
    missing = {k for k, f in want.items() if f >= must_fraction} - got
    extra = {k for k in got - set(want) if not occlusion_confirmed(observer, target, bodies[k], **sensor)}
    return missing | extra


def scene_series(rng: np.random.Generator, count: int, overlap: bool, max_objects: int) -> Iterator[tuple[bool, Scene]]:
    """``count`` random scenes for engine checks: ``(include_ego, scene)``, the ego in every other scene, statics
    in two of three, 2 to ``max_objects - 1`` road users."""
    for k in range(count):
        include_ego = bool(k % 2)
        n = int(rng.integers(2, max_objects))
        yield include_ego, random_scene(rng, n, overlap=overlap, with_statics=k % 3 != 0, include_ego=include_ego)


if st is not None:
    __all__ += ["scenes"]

    @st.composite
    def scenes(
        draw: Any,
        min_objects: int = 1,
        max_objects: int = 8,
        overlap: bool | None = None,
        with_statics: bool | None = None,
        include_ego: bool | None = None,
    ) -> Scene:
        """Hypothesis strategy drawing a :func:`random_scene` (``None`` flags are drawn at random).

        Parameters
        ----------
        draw : callable
            Supplied by hypothesis.
        min_objects, max_objects : int
            Range of the number of road users besides the ego.
        overlap, with_statics, include_ego : bool, optional
            Fixed flags for :func:`random_scene`; drawn with ``st.booleans()`` when ``None``.

        Returns
        -------
        Scene
            ``(observer, objects, statics, transparent)``.
        """
        seed = draw(st.integers(0, 2**32 - 1))
        n = draw(st.integers(min_objects, max_objects))
        flags = [draw(st.booleans()) if f is None else f for f in (overlap, with_statics, include_ego)]
        return random_scene(
            np.random.default_rng(seed), n, overlap=flags[0], with_statics=flags[1], include_ego=flags[2]
        )


# ----------------------------------------------------------------------------------------------
# The area measure, by dense point sampling of each footprint
# ----------------------------------------------------------------------------------------------


def reference_area_visibility(
    observer: Any,
    objects: Sequence[Any],
    statics: Sequence[Any] = (),
    transparent: Any = None,
    n_side: int = 200,
    heading: float = 0.0,
    fov: float = TWO_PI,
    max_range: float = np.inf,
) -> tuple[np.ndarray, list[dict[int, float]]]:
    """Share of each object's footprint seen from ``observer``, by sampling: the points of an ``n_side`` x
    ``n_side`` grid over its bounding box that lie inside it, each seen when it is inside the field of view and
    range and the segment from the observer to it meets no other non-transparent object or static occluder.

    Returns the shares (``nan`` for transparent objects) and, per object, the share of its points each other body
    hides (objects by position; statics as ``-1 - position``). The sampling error of a share is of the order of
    the shadow edges' length times the grid spacing over the area.
    """
    import shapely

    o = np.asarray(observer, dtype=float).reshape(2)
    objs = [_as_geometry(g) for g in objects]
    transp = np.zeros(len(objs), dtype=bool) if transparent is None else np.asarray(transparent, dtype=bool)
    bodies = [(k, g) for k, g in enumerate(objs) if not transp[k]] + [
        (-1 - k, _as_geometry(g)) for k, g in enumerate(statics)
    ]
    shares = np.full(len(objs), np.nan)
    hiders: list[dict[int, float]] = [{} for _ in objs]
    for i, target in enumerate(objs):
        if transp[i]:
            continue
        x0, y0, x1, y1 = target.bounds
        gx, gy = np.meshgrid(np.linspace(x0, x1, n_side + 2)[1:-1], np.linspace(y0, y1, n_side + 2)[1:-1])
        points = np.column_stack([gx.ravel(), gy.ravel()])
        points = points[shapely.contains_xy(target, points[:, 0], points[:, 1])]
        rel = points - o
        angle = np.arctan2(rel[:, 1], rel[:, 0])
        inside = np.ones(len(points), dtype=bool)
        if fov < TWO_PI:
            inside &= (angle - (heading - fov / 2)) % TWO_PI <= fov
        inside &= np.hypot(rel[:, 0], rel[:, 1]) <= max_range
        sight = shapely.linestrings(np.stack([np.broadcast_to(o, points.shape), points], axis=1))
        hidden = np.zeros(len(points), dtype=bool)
        for k, body in bodies:
            if k == i:
                continue
            by = shapely.intersects(sight, body) & inside
            if by.any():
                hiders[i][k] = float(by.mean())
            hidden |= by
        shares[i] = float((inside & ~hidden).mean())
    return shares, hiders
