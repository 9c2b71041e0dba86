"""Object outlines as rings: shapely polygons (omega-prime's ``polygon`` column) or box corners (its ``coords``
column, as the MCAP reader gives them), read at array speed, invalid ones replaced or repaired.

- :func:`polygon_rings`: rings of a column of shapely outlines;
- :func:`corner_rings`: rings of box corners (the same rings, without making polygons);
- :func:`corners_column`: a table's box corners, where it has them instead of polygons.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import polars as pl
import shapely

from ..geometry.rings import Rings, box_rings, convex_quadrilaterals, gather_oriented
from .objects import OnInvalid

MIN_AREA = 1e-6  # m²; smaller polygons are "zero-size"


def _repaired_outline(geometry: Any) -> shapely.Polygon | None:
    """One simple polygon for an invalid or multi-part outline, or None when it has no area.

    ``shapely.make_valid`` keeps what the outline covers; of that only the polygonal part counts. One part is
    used as it is (its exterior), several parts (a bow-tie becomes two triangles) by their convex hull: a body
    is one outline here, and a self-crossing outline is nearly always a box with two corners swapped.
    """
    polygons = [g for g in shapely.get_parts(shapely.make_valid(geometry)) if isinstance(g, shapely.Polygon)]
    polygons = [g for g in polygons if not g.is_empty and g.area >= MIN_AREA]
    if not polygons:
        return None
    return shapely.Polygon(polygons[0].exterior) if len(polygons) == 1 else shapely.MultiPolygon(polygons).convex_hull


POLYGON, MULTIPOLYGON = 3, 6  # shapely.get_type_id


def _type_ids(polygons: np.ndarray) -> np.ndarray:
    """``shapely.get_type_id`` of every entry, -1 for None or anything that is not a shapely geometry."""
    try:
        return shapely.get_type_id(polygons)
    except TypeError:  # some entry is not a geometry at all
        is_geometry = np.array([isinstance(p, shapely.Geometry) for p in polygons], dtype=bool)
        return np.where(is_geometry, shapely.get_type_id(np.where(is_geometry, polygons, None)), -1)


def polygon_rings(
    polygons: np.ndarray, candidate: np.ndarray, boxes: tuple[np.ndarray, ...] | None, on_invalid: OnInvalid
) -> tuple[Rings, np.ndarray, list[str], list[str], np.ndarray]:
    """Exterior rings of the usable outlines among the ``candidate`` rows.

    Invalid or multi-part outlines are replaced by the row's box where ``boxes`` (``x, y, length, width, yaw``
    per row, for :func:`~.geometry.box_rings`; NaN where unusable) gives one, else repaired
    (:func:`_repaired_outline`); with ``on_invalid="raise"`` they raise instead. Returns the rings of the usable
    rows (in row order), the mask of usable rows, the reasons for skipped rows, notes on replaced outlines and the
    rows whose outline was replaced.

    Read at array speed: the coordinates of all polygons come out of one ``shapely.get_coordinates`` call, and
    outlines that are strictly convex quadrilaterals (as boxes are) are known valid and large enough without
    asking GEOS (:func:`~.geometry.convex_quadrilaterals`); only the other rows go through ``shapely.is_valid``
    and ``shapely.area``.
    """
    type_id = _type_ids(polygons)
    polygonal = candidate & ((type_id == POLYGON) | (type_id == MULTIPOLYGON))
    reasons, notes = [], []
    if (candidate & ~polygonal).any():
        reasons.append(f"{int((candidate & ~polygonal).sum())} outline(s) not a shapely Polygon")
    geoms = np.where(polygonal, polygons, None)
    single = polygonal & (type_id == POLYGON)
    single_geoms = np.where(single, geoms, None)
    n_coords = shapely.get_num_coordinates(single_geoms)
    plain = single & (shapely.get_num_interior_rings(single_geoms) == 0)
    coords = shapely.get_coordinates(single_geoms)
    first = np.zeros(len(polygons), dtype=np.int64)  # each row's first coordinate in ``coords``
    np.cumsum(n_coords[:-1], out=first[1:])
    quad = np.flatnonzero(plain & (n_coords == 5))
    sure = np.zeros(len(polygons), dtype=bool)
    sure[quad] = convex_quadrilaterals(coords, first[quad], MIN_AREA)
    finite = _finite_outlines(geoms, polygonal, single, coords, first, n_coords)
    simple = sure.copy()
    check = np.flatnonzero(single & ~sure & finite)
    simple[check] = shapely.is_valid(geoms[check])
    broken = np.flatnonzero(polygonal & ~simple)
    if len(broken) and on_invalid == "raise":
        why = shapely.is_valid_reason(geoms[broken[0]]) if finite[broken[0]] else "a NaN or infinite vertex"
        raise ValueError(
            f"{len(broken)} invalid (e.g. self-intersecting) or multi-part polygon outline(s), first in row "
            f"{int(broken[0])}: {why}"
        )
    outline = geoms.copy()
    from_box = []
    if boxes is not None and len(broken):  # the boxes of the broken rows only
        broken_boxes = box_rings(*(values[broken] for values in boxes))
        for k, i in enumerate(broken.tolist()):
            if np.isfinite(broken_boxes.ring(k)).all():
                outline[i] = shapely.Polygon(broken_boxes.ring(k))
                from_box.append(i)
    replaced_by_box = set(from_box)
    repaired = [i for i in broken if i not in replaced_by_box]
    for i in repaired:
        outline[i] = _repaired_outline(geoms[i]) if finite[i] else None  # GEOS cannot repair infinite vertices
    if from_box:
        notes.append(f"{len(from_box)} invalid or multi-part outline(s) replaced by their length/width/yaw box")
    fixed = [i for i in repaired if outline[i] is not None]
    if fixed:
        notes.append(
            f"{len(fixed)} invalid or multi-part outline(s) repaired with shapely.make_valid (one part kept as "
            "it is, several by their convex hull)"
        )
    usable = polygonal.copy()
    usable[[i for i in repaired if outline[i] is None]] = False
    measure = np.flatnonzero(usable & ~sure)  # the ``sure`` rows are known to have finite areas >= MIN_AREA
    area = shapely.area(outline[measure])
    small = np.zeros(len(polygons), dtype=bool)
    small[measure] = ~np.isfinite(area) | (area < MIN_AREA)
    if (polygonal & ~small & ~usable).any() or small.any():
        reasons.append(f"{int((polygonal & ~usable).sum() + small.sum())} zero-size or non-finite polygon(s)")
    good = usable & ~small
    # plain polygons that were kept as they are: their coordinates are those of their exterior ring
    direct = good & plain
    direct[broken] = False
    other = np.flatnonzero(good & ~direct)
    extra, extra_which = shapely.get_coordinates(shapely.get_exterior_ring(outline[other]), return_index=True)
    extra_sizes = np.bincount(extra_which, minlength=len(other))
    source_first = first.copy()
    sizes = n_coords.copy()
    source_first[other] = len(coords) + np.concatenate([[0], np.cumsum(extra_sizes)[:-1]]).astype(np.int64)
    sizes[other] = extra_sizes
    rows = np.flatnonzero(good)
    source = np.concatenate([coords, extra]) if len(extra) else coords
    rings = gather_oriented(source, source_first[rows], sizes[rows] - 1)  # the closing vertex is not repeated
    return rings, good, reasons, notes, broken[good[broken]]


def corners_column(df: pl.DataFrame) -> np.ndarray | None:
    """The box corners of a table without shapely outlines whose ``coords`` column holds them as omega-prime does
    (1 x 5 points per row, the first repeated last), as an (n, 5, 2) array; None for any other table."""
    if "polygon" in df.columns or "coords" not in df.columns or df["coords"].dtype != pl.Array(pl.Float64, (1, 5, 2)):
        return None
    corners = df["coords"].to_numpy().reshape(df.height, 5, 2)
    # writable, as shapely's coordinates are: the kernels then run on the signatures compiled for them
    return corners if corners.flags.writeable else corners.copy()


def corner_rings(
    corners: np.ndarray, candidate: np.ndarray, boxes: tuple[np.ndarray, ...] | None, on_invalid: OnInvalid
) -> tuple[Rings, np.ndarray, list[str], list[str], np.ndarray]:
    """:func:`polygon_rings` of the outlines whose corners are ``corners`` (n, 5, 2), without making shapely
    polygons when every candidate is a strictly convex quadrilateral of the minimum area (as boxes are): the same
    rings, from the same numbers. Any other outline among them: the polygons are made and read as a polygon
    column would be."""
    coords = corners.reshape(-1, 2)
    first = np.arange(len(corners), dtype=np.int64) * 5
    rows = np.flatnonzero(candidate)
    if convex_quadrilaterals(coords, first[rows], MIN_AREA).all():
        rings = gather_oriented(coords, first[rows], np.full(len(rows), 4, dtype=np.int64))
        return rings, candidate.copy(), [], [], np.zeros(0, dtype=np.int64)
    return polygon_rings(shapely.polygons(corners), candidate, boxes, on_invalid)


def _finite_outlines(geoms, polygonal, single, coords, first, n_coords) -> np.ndarray:
    """Per row, whether its outline's vertices are all finite (``coords``/``first``/``n_coords``: the plain
    polygons' coordinates, as :func:`polygon_rings` reads them; multi-part outlines read here)."""
    finite = np.ones(len(geoms), dtype=bool)
    rows = np.flatnonzero(single & (n_coords > 0))
    if len(rows):
        finite[rows] = np.logical_and.reduceat(np.isfinite(coords).all(axis=1), first[rows])
    multi = np.flatnonzero(polygonal & ~single)
    if len(multi):
        points, which = shapely.get_coordinates(geoms[multi], return_index=True)
        bad = np.zeros(len(multi), dtype=bool)
        np.logical_or.at(bad, which, ~np.isfinite(points).all(axis=1))
        finite[multi] = ~bad
    return finite
