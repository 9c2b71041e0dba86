"""One cube face of the exact 3D engine's measure (:func:`..engines.silhouette3d.convex_visibility`): per target
its solid angle on the face, in the field of view, in view and range, visible, and its occluders there.

Two paths give the same numbers: :func:`compiled_face` draws silhouettes and subtracts what hides them in compiled
loops (:mod:`.face_pieces`) and clips to a window with shapely only the targets that straddle it;
:func:`polygon_face` does everything with shapely polygons, and takes a face whose compiled buffers overflow and
every face when the visible pieces themselves are wanted (the pictures, the ray engine's probes).

A target's *window* on a face is where it may be seen: None for the whole face, else a polygon in face
coordinates (the view's region, cut by the range where the range cuts the target; empty where it lies beyond).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
import shapely

from ..geometry.occlusion import RELATIVE_TOLERANCE
from .bodies import ConvexBodies
from .cube import FACES, MIN_SOLID_ANGLE, silhouettes, solid_angles
from .face_pieces import MAX_VERTICES, VISIBLE, face_pieces, face_silhouettes
from .order import entered_before


class FaceMeasure(NamedTuple):
    """Steradians per target on one face (``extent``, ``in_fov``, ``in_view``, ``visible``) and the occluder
    pairs found there (``pair_target`` a position among the targets, ``pair_body`` a body)."""

    extent: np.ndarray
    in_fov: np.ndarray
    in_view: np.ndarray
    visible: np.ndarray
    pair_target: np.ndarray
    pair_body: np.ndarray


class BodyLayout(NamedTuple):
    """The bodies' vertices and edges as runs per body, as the compiled kernels read them."""

    vertex_start: np.ndarray
    edge_start: np.ndarray

    @classmethod
    def of(cls, bodies: ConvexBodies) -> BodyLayout | None:
        """The runs of ``bodies`` (None where vertices or edges are not grouped by body)."""
        if (np.diff(bodies.vertex_body) < 0).any() or (np.diff(bodies.edge_body) < 0).any():
            return None
        at = np.arange(len(bodies) + 1)
        return cls(np.searchsorted(bodies.vertex_body, at), np.searchsorted(bodies.edge_body, at))


def clipped(shapes: np.ndarray, windows: np.ndarray) -> np.ndarray:
    """``shapes ∩ windows`` element-wise, where a window None is everything (contained shapes are not clipped)."""
    out = shapes.copy()
    some = ~shapely.is_missing(windows) & ~shapely.is_missing(shapes)
    if some.any():
        inside = shapely.contains(windows[some], shapes[some])
        at = np.flatnonzero(some)[~inside]
        if len(at):
            out[at] = shapely.intersection(shapes[at], windows[at])
    return out


def _polygons(xy: np.ndarray, starts: np.ndarray) -> np.ndarray:
    """Shapely polygons of the counter-clockwise rings ``xy[starts[k]:starts[k + 1]]``, turned clockwise as
    shapely's own hulls are: GEOS intersects two nearly coincident polygons (a silhouette and its part within
    range, edges 1e-16 apart) into points for some orientations, and the polygon path's is the one it gets right."""
    if len(starts) < 2:
        return np.zeros(0, dtype=object)
    ring = np.repeat(np.arange(len(starts) - 1), np.diff(starts))
    backwards = starts[ring] + starts[ring + 1] - 1 - np.arange(len(ring))
    return shapely.polygons(shapely.linearrings(xy[backwards], indices=ring))


def compiled_silhouettes(
    f: int, bodies: ConvexBodies, layout: BodyLayout
) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Every body's silhouette on face ``f`` through the compiled kernel: outlines (n, MAX_VERTICES, 2), vertex
    counts (n,) (0: not seen through the face) and solid angles (n,), steradians; None where one overflows."""
    n = len(bodies)
    outlines = np.empty((n, MAX_VERTICES, 2))
    counts = np.zeros(n, np.int64)
    angles = np.zeros(n)
    fitted = face_silhouettes(bodies.vertices, layout.vertex_start, bodies.edges, layout.edge_start, bodies.normals,
                              bodies.offsets, FACES[f], outlines, counts, angles)  # fmt: skip
    return (outlines, counts, angles) if fitted else None


def compiled_face(
    f: int,
    bodies: ConvexBodies,
    layout: BodyLayout,
    measured: np.ndarray,
    region: shapely.Geometry | None,
    windows: np.ndarray,
    lower: np.ndarray,
    farthest: np.ndarray,
    within: np.ndarray,
) -> FaceMeasure | None:
    """Face ``f``'s measure through the compiled kernels; None where a buffer overflows. ``within`` (bool per
    target): its window lies within its silhouette (its part within range), so that its angle in view is the
    window's."""
    m = len(measured)
    face = FACES[f]
    drawn = compiled_silhouettes(f, bodies, layout)
    if drawn is None:
        return None
    outlines, counts, angles = drawn
    seen = counts[measured] >= 3
    extent = np.where(seen, angles[measured], 0.0)
    whole = shapely.is_missing(windows)
    empty = ~whole & shapely.is_empty(windows)
    shapes = np.full(m, None, dtype=object)
    needed = seen & (~whole | (region is not None))
    if needed.any():
        rows = np.flatnonzero(needed)
        sizes = counts[measured[rows]]
        xy = outlines[measured[rows]][np.arange(MAX_VERTICES) < sizes[:, None]]  # the rings, one after the other
        shapes[rows] = _polygons(xy, np.r_[0, np.cumsum(sizes)])
    in_fov = extent.copy()
    if region is not None:
        rows = np.flatnonzero(seen)
        in_fov[rows] = solid_angles(clipped(shapes[rows], np.full(len(rows), region, dtype=object)))
    cut = seen & ~whole & ~empty
    inside = np.zeros(m, dtype=bool)
    inside[cut] = shapely.contains(windows[cut], shapes[cut])
    wanted = cut & ~inside
    in_view = np.where(empty, 0.0, extent)
    by_window = wanted & within
    in_view[by_window] = solid_angles(windows[by_window])
    by_overlay = wanted & ~within
    in_view[by_overlay] = solid_angles(shapely.intersection(shapes[by_overlay], windows[by_overlay]))
    live = seen & ~empty
    result = face_pieces(outlines, counts, measured, live, wanted, bodies.normals, bodies.offsets, lower, farthest,
                         face)  # fmt: skip
    visible, pair_target, pair_body, xy, starts, owners, kinds, fitted = result
    if not fitted:
        return None
    listed = ~wanted[pair_target]
    if wanted.any():
        pieces = _polygons(xy, starts)
        mine = kinds == VISIBLE
        owner_window = owners.copy()
        owner_window[~mine] = pair_target[owners[~mine]]
        angle = solid_angles(clipped(pieces, windows[owner_window]))
        seen_here = np.bincount(owners[mine], angle[mine], minlength=m)
        visible[wanted] = seen_here[wanted]
        hidden = np.bincount(owners[~mine], angle[~mine], minlength=len(pair_target))
        listed |= hidden > MIN_SOLID_ANGLE
    return FaceMeasure(extent, in_fov, in_view, visible, pair_target[listed], pair_body[listed])


def polygon_face(
    f: int,
    bodies: ConvexBodies,
    measured: np.ndarray,
    region: shapely.Geometry | None,
    windows: np.ndarray,
    lower: np.ndarray,
    farthest: np.ndarray,
    within: np.ndarray,
    parts: list | None = None,
) -> FaceMeasure:
    """Face ``f``'s measure with shapely polygons; ``within`` as for :func:`compiled_face` (such a target's window
    stands for its silhouette: intersecting the two, 1e-16 apart along their common edges, is what GEOS may get
    wrong); ``parts`` receives ``(target, f, polygon)`` for every visible piece."""
    m = len(measured)
    extent, in_fov, in_view, visible = (np.zeros(m) for _ in range(4))
    no_pairs = np.zeros(0, np.int64)
    sil = silhouettes(bodies, f)
    seen_t = np.flatnonzero(~shapely.is_missing(sil[measured]))
    if not len(seen_t):
        return FaceMeasure(extent, in_fov, in_view, visible, no_pairs, no_pairs)
    shapes = sil[measured[seen_t]]
    extent[seen_t] = solid_angles(shapes)
    windows = windows[seen_t]
    in_fov[seen_t] = solid_angles(clipped(shapes, np.full(len(seen_t), region, dtype=object)))
    inner = within[seen_t]
    drawn = shapes.copy()  # what may be seen: the silhouette, or the window lying within it
    drawn[inner] = windows[inner]
    windows = windows.copy()
    windows[inner] = None
    in_view[seen_t] = solid_angles(clipped(drawn, windows))
    present = np.flatnonzero(~shapely.is_missing(sil))
    tree = shapely.STRtree(sil[present])
    live = np.flatnonzero(~shapely.is_empty(windows))  # (nothing is seen through an empty window)
    ti, bj = tree.query(shapes[live], predicate="intersects")
    ti, bj = live[ti], present[bj]
    other = bj != measured[seen_t[ti]]
    ti, bj = ti[other], bj[other]
    pair_target, pair_body = no_pairs, no_pairs
    pieces = drawn.copy()
    if len(ti):
        ti, bj, front = _blockers(bodies, measured[seen_t], shapes, sil, ti, bj, f, lower, farthest)
        overlap = shapely.intersection(drawn[ti], front)  # what the body hides, listed above MIN_SOLID_ANGLE
        listed = solid_angles(clipped(overlap, windows[ti])) > MIN_SOLID_ANGLE
        pair_target, pair_body = seen_t[ti[listed]], bj[listed]
    if len(ti):
        order = np.argsort(ti, kind="stable")
        ti, front = ti[order], front[order]
        starts = np.flatnonzero(np.r_[True, ti[1:] != ti[:-1]])
        groups = np.split(front, starts[1:])
        blockers = np.array([shapely.union_all(g) for g in groups], dtype=object)
        hit = ti[starts]
        pieces[hit] = shapely.difference(drawn[hit], blockers)
    seen_parts = clipped(pieces, windows)
    visible[seen_t] = solid_angles(seen_parts)
    if parts is not None:
        for k in np.flatnonzero(~shapely.is_empty(seen_parts)):
            parts.append((int(seen_t[k]), f, seen_parts[k]))
    return FaceMeasure(extent, in_fov, in_view, visible, pair_target, pair_body)


def _blockers(bodies, targets, shapes, sil, ti, bj, f, lower, farthest):
    """Of the pairs (``shapes[ti]``, body ``bj``) whose silhouettes intersect, those whose interiors meet and where
    body ``bj`` is in front of the target ``targets[ti]`` along some direction, with the directions where it is (on
    face ``f``): its whole silhouette where it lies wholly nearer (its farthest point before the target's nearest),
    else the region of :func:`.order.entered_before` (exact also for bodies that overlap)."""
    meet = shapely.relate_pattern(shapes[ti], sil[bj], "T********")
    ti, bj = ti[meet], bj[meet]
    target = targets[ti]
    ahead = farthest[bj] < lower[target] * (1.0 - RELATIVE_TOLERANCE)  # (nearer by the tie rule's margin)
    unsure = ~ahead & ~(farthest[target] < lower[bj])
    front = np.full(len(ti), None, dtype=object)
    front[ahead] = sil[bj[ahead]]
    for k in np.flatnonzero(unsure):
        front[k] = shapely.intersection(sil[bj[k]], entered_before(bodies, int(bj[k]), int(target[k]), f))
    keep = ahead.copy()
    keep[unsure] = solid_angles(shapely.intersection(shapes[ti[unsure]], front[unsure])) > MIN_SOLID_ANGLE
    return ti[keep], bj[keep], front[keep]
