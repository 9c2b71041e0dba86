"""The exact 3D engine for scenes of boxes and upright prisms: silhouettes in a central projection, measured as
solid angle.

The directions along which a box target is the first thing hit are its silhouette minus, for every other body,
the directions along which that body is entered first: its whole silhouette when it lies wholly nearer, else a
union of half-planes of it (:mod:`..threed.order`). The bodies are the objects' boxes and the static occluders
raised to their heights, cut into convex prisms (:mod:`..threed.bodies`); directions over the full sphere are
drawn on the six faces of a cube around the eye (:mod:`..threed.cube`), subtracted with shapely and measured
exactly.

What is exact and what is not:

- silhouettes, their order and the horizontal field of view (half-planes on each face) are exact to floating
  point, so ``can_see`` and the occluder lists are exact: a strip or a slot of any width is found;
- the vertical field of view's limits (cones) and the range (a sphere, where it cuts a box) are drawn as polygons
  of :data:`~..threed.cube.CURVE_POINTS` vertices (error below 1e-6 of the area near the curve);
- bodies that overlap (a double detection, a railing through a car) are ordered direction by direction: where
  their depths overlap, the directions along which one is entered first are half-planes on each face
  (:mod:`..threed.order`), so they too are exact.

An occluder of a target is a body in front of it along some direction of the target's silhouette that is in
view and within range. Meshes (``static_meshes``) are not convex bodies: scenes with them need the ray engine
(``raycast3d``), which the 3D mode picks for them.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import ClassVar

import numpy as np
import shapely

from ..inputs.objects import FrameObjects
from ..inputs.statics import StaticOccluders
from ..threed.bodies import (
    ConvexBodies,
    bodies_from_boxes,
    concatenate,
    containing_origin,
)
from ..threed.boxes import nearest_distance
from ..threed.cube import silhouettes, solid_angles, view_regions, within_range
from ..threed.faces import BodyLayout, compiled_face, compiled_silhouettes, polygon_face
from ..threed.order import nearest, nearest_bound
from . import Observation, Viewpoint, group_pairs
from .observe3d import StaticPrisms, eye_and_view, observation, own_body

RESIDUE = 1e-9
"""A visible share below this is rounding left by subtracting silhouettes with common edges (a target wholly
behind a body whose outline shares its edge, on a seam between cube faces), not a gap: it counts as 0."""

WHOLE_VIEW = (0.0, math.pi, -math.pi / 2, math.pi / 2)
"""``(heading, half horizontal fov, lowest, highest elevation)`` of an eye that looks all around."""


def _windows(region, ranged: dict, beyond: np.ndarray, f: int) -> np.ndarray:
    """Per target its window on face ``f`` (:mod:`..threed.faces`): the view's ``region``, cut by its part within
    range where ``ranged`` holds it (per face), empty where it lies ``beyond`` the range."""
    windows = np.full(len(beyond), region, dtype=object)
    for t, faces in ranged.items():
        r = faces[f]
        windows[t] = shapely.Polygon() if r is None else r if region is None else r.intersection(region)
    windows[beyond] = shapely.Polygon()
    return windows


def convex_visibility(
    bodies: ConvexBodies,
    measured: np.ndarray,
    *,
    view: tuple[float, float, float, float] = WHOLE_VIEW,
    max_range: float = math.inf,
    near: np.ndarray | None = None,
    parts: list | None = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Exact visible, total, in-view and in-field-of-view solid angle of the ``measured`` bodies seen from the
    origin (the eye; ``bodies`` relative to it, the eye outside every body given), and their occluders.

    Parameters
    ----------
    bodies : ConvexBodies
        Every body that blocks, metres, relative to the eye.
    measured : ndarray of int
        The bodies to measure (targets).
    view : (heading, half horizontal fov, lowest elevation, highest elevation)
        Radians, as :func:`..threed.boxes.view_limits` returns.
    max_range : float
        Metres: a direction sees a target only where it enters it within this distance.
    near : ndarray, shape (len(measured),), optional
        Distance (metres) from the eye to each target's nearest point, when known (else computed).
    parts : list, optional
        Receives ``(target, face, polygon)`` for every visible piece: the directions that see ``measured[target]``
        through cube face ``face``, in that face's coordinates (:mod:`..threed.cube`).

    Returns
    -------
    visible, extent, in_view, in_fov : ndarray, shape (len(measured),)
        Steradians: directions along which the target is the first thing hit, in view and within range; that
        hit the target at all; that hit it in view and within range, occlusion ignored; that hit it in view.
    pair_target, pair_body : ndarray of int
        Occluders: body ``pair_body[k]`` is in front of measured target ``pair_target[k]`` (a position in
        ``measured``) along some direction that sees the target in view and within range.
    """
    measured = np.asarray(measured, dtype=np.int64)
    m = len(measured)
    visible, extent, in_view, in_fov = (np.zeros(m) for _ in range(4))
    pair_target: list[np.ndarray] = []
    pair_body: list[np.ndarray] = []
    if m == 0:
        return visible, extent, in_view, in_fov, np.zeros(0, np.int64), np.zeros(0, np.int64)
    far = np.linalg.norm(bodies.vertices, axis=1)
    farthest = np.zeros(len(bodies))
    np.maximum.at(farthest, bodies.vertex_body, far)
    near = nearest(bodies, measured) if near is None else np.asarray(near, dtype=np.float64)
    lower = nearest_bound(bodies)
    lower[measured] = near
    beyond = near > max_range
    cut = ~beyond & (farthest[measured] > max_range)
    ranged = {int(t): within_range(bodies, int(measured[t]), max_range) for t in np.flatnonzero(cut)}
    within = np.zeros(m, dtype=bool)  # windows within the silhouette: the part within range
    within[list(ranged)] = True
    regions = view_regions(*view)
    layout = BodyLayout.of(bodies) if parts is None else None
    targets_only = None
    for f in range(6):
        region = regions[f]
        if region is not None and (region.is_empty or region.area == 0.0):  # nothing in view: the extent only
            drawn = None if layout is None else compiled_silhouettes(f, bodies, layout)
            if drawn is not None:
                extent += drawn[2][measured]
                continue
            targets_only = bodies.take(measured) if targets_only is None else targets_only
            extent += solid_angles(silhouettes(targets_only, f))
            continue
        windows = _windows(region, ranged, beyond, f)
        face = None
        if layout is not None:
            face = compiled_face(f, bodies, layout, measured, region, windows, lower, farthest, within)
        if face is None:
            face = polygon_face(f, bodies, measured, region, windows, lower, farthest, within, parts)
        extent += face.extent
        in_fov += face.in_fov
        in_view += face.in_view
        visible += face.visible
        pair_target.append(face.pair_target)
        pair_body.append(face.pair_body)
    visible = np.minimum(visible, in_view)
    visible[visible <= RESIDUE * extent] = 0.0  # what the differences of equal edges leave: rounding, not a gap
    pt = np.concatenate(pair_target) if pair_target else np.zeros(0, np.int64)
    pb = np.concatenate(pair_body) if pair_body else np.zeros(0, np.int64)
    return visible, extent, in_view, in_fov, pt.astype(np.int64), pb.astype(np.int64)


def box_visibility(
    boxes: np.ndarray,
    eye: np.ndarray,
    *,
    transparent: np.ndarray | None = None,
    view: tuple[float, float, float, float] = WHOLE_VIEW,
    max_range: float = math.inf,
    statics: ConvexBodies | None = None,
) -> tuple[np.ndarray, np.ndarray, list[list[int]], np.ndarray, np.ndarray]:
    """Exact visible and total solid angle of every box seen from ``eye``, among ``statics``.

    Parameters
    ----------
    boxes : ndarray, shape (n, 9)
        Oriented boxes (:mod:`..threed.boxes`), metres and radians.
    eye : ndarray, shape (3,)
        The eye point, metres.
    transparent : ndarray of bool, shape (n,), optional
        Boxes that neither block nor are measured (the observer's own body); boxes containing the eye are added.
    view : (heading, half horizontal fov, lowest elevation, highest elevation)
        Radians, as :func:`..threed.boxes.view_limits` returns.
    max_range : float
        Metres.
    statics : ConvexBodies, optional
        Static prisms that block (:func:`..threed.bodies.prisms_from_footprints`), in the boxes' frame; those
        containing the eye are left out.

    Returns
    -------
    visible : ndarray, shape (n,)
        Steradians of directions along which the box is the first thing hit, within view and range.
    extent : ndarray, shape (n,)
        Steradians of directions that hit the box at all.
    occluders : list of lists of int
        Per box, the boxes in front of it along some direction that sees it in view and within range.
    transparent : ndarray of bool, shape (n,)
        The transparent boxes (given, or containing the eye).
    in_fov : ndarray, shape (n,)
        Steradians of the box's directions inside the view, occlusion and range ignored.

    Examples
    --------
    >>> car = [10.0, 0, 0.75, 4, 2, 1.5, 0, 0, 0]
    >>> truck = [20.0, 0, 2.0, 8, 2.5, 4.0, 0, 0, 0]  # 4 m high behind a 1.5 m car
    >>> visible, extent, occ, _, _ = box_visibility(np.array([car, truck]), np.array([0.0, 0, 1.25]))
    >>> round(float(visible[1] / extent[1]), 3), occ
    (0.559, [[], [0]])
    """
    boxes = np.asarray(boxes, dtype=np.float64).reshape(-1, 9)
    result = boxes_among(boxes, np.asarray(eye, dtype=np.float64), transparent, view, max_range, statics)
    visible, extent, _, in_fov, pairs, _, skip = result
    occluders: list[list[int]] = [[] for _ in range(len(boxes))]
    for t, b in zip(*pairs, strict=True):
        occluders[t].append(int(b))
    return visible, extent, [sorted(set(o)) for o in occluders], skip, in_fov


def boxes_among(boxes, eye, transparent, view, max_range, statics, parts=None):
    """:func:`convex_visibility` of ``boxes`` among ``statics`` from ``eye``: per box ``visible, extent, in_view,
    in_fov``, occluder pairs ``(box, box)`` and ``(box, static source)``, and the transparent boxes; ``parts``
    receives the visible pieces as ``(box row, face, polygon)``."""
    n = len(boxes)
    bodies = bodies_from_boxes(boxes).relative_to(eye)
    skip = containing_origin(bodies)
    if transparent is not None:
        skip |= np.asarray(transparent, dtype=bool)
    n_static = 0
    if statics is not None and len(statics):
        rel = statics.relative_to(eye)
        keep = np.flatnonzero(~containing_origin(rel) & _may_block(rel, view, max_range))
        rel = rel.take(keep)
        n_static = len(rel)
        bodies = concatenate(bodies, rel)
    solid = np.r_[np.flatnonzero(~skip), n + np.arange(n_static)]
    bodies = bodies.take(solid)
    measured = np.flatnonzero(solid < n)
    visible, extent, in_view, in_fov = (np.zeros(n) for _ in range(4))
    rows = solid[measured]
    near = nearest_distance(boxes[rows], eye)
    found: list | None = None if parts is None else []
    v, e, iv, fv, pt, pb = convex_visibility(bodies, measured, view=view, max_range=max_range, near=near, parts=found)
    if parts is not None:
        parts.extend((int(rows[t]), f, polygon) for t, f, polygon in found)  # type: ignore[union-attr]
    visible[rows], extent[rows], in_view[rows], in_fov[rows] = v, e, iv, fv
    target, blocker = rows[pt], solid[pb]
    is_box = blocker < n
    static_source = bodies.source[pb[~is_box]]
    return visible, extent, in_view, in_fov, (target[is_box], blocker[is_box]), (target[~is_box], static_source), skip


def _may_block(bodies: ConvexBodies, view: tuple[float, float, float, float], max_range: float) -> np.ndarray:
    """Bodies (relative to the eye) that may block a direction in view within range: their bounding sphere
    reaches within range and into the horizontal field of view."""
    centre, radius = bodies.bounding_spheres()
    dist = np.linalg.norm(centre, axis=1)
    ok = dist - radius <= max_range
    heading, half_fov = view[0], view[1]
    if half_fov < math.pi:
        flat = np.linalg.norm(centre[:, :2], axis=1)
        off = np.abs((np.arctan2(centre[:, 1], centre[:, 0]) - heading + math.pi) % (2 * math.pi) - math.pi)
        spread = np.where(flat > radius, np.arcsin(np.minimum(1.0, radius / np.maximum(flat, 1e-12))), math.pi)
        ok &= off <= half_fov + spread + 1e-9
    return ok


class SilhouetteEngine:
    """The exact engine for boxes and static prisms (see the module docstring); ``measure = "steradians"``."""

    name: ClassVar[str] = "silhouette3d"
    measure: ClassVar[str] = "steradians"
    passive_targets: ClassVar[bool] = False
    chunked: ClassVar[bool] = False

    def __init__(self, statics: StaticOccluders, meshes_elsewhere: bool = False) -> None:
        solids = getattr(statics, "solids", None)
        if solids is not None and solids.n_sources > statics.n_sources and not meshes_elsewhere:
            raise ValueError(
                "the silhouette3d engine measures boxes and static footprints with heights; static_meshes need "
                "the ray engine (engine='raycast3d', the 3D default when meshes are given)"
            )
        self.statics = statics
        self.static_prisms = StaticPrisms(statics)
        self.tops, self.bases, self.prisms = (
            self.static_prisms.tops,
            self.static_prisms.bases,
            self.static_prisms.prisms,
        )

    def prisms_for(self, view: Viewpoint, eye: np.ndarray) -> ConvexBodies | None:
        """The static prisms that block for ``view`` from ``eye`` (:meth:`.observe3d.StaticPrisms.for_view`)."""
        return self.static_prisms.for_view(view, eye)

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; needs the frame's 3D boxes (``objects.boxes3d``)."""
        boxes = getattr(objects, "boxes3d", None)
        if boxes is None:
            raise ValueError("3D engines need the 3D boxes of the objects: load them with three_d=True (mode='3d')")
        out = []
        n = len(objects)
        for view in viewpoints:
            eye, limits = eye_and_view(view, boxes)
            result = boxes_among(boxes, eye, own_body(view, n), limits, view.range, self.prisms_for(view, eye))
            visible, extent, in_view, in_fov, (bt, bb), (st, ss), skip = result
            offsets, occluders = group_pairs(bt, bb, n)
            st_offsets, st_occluders = group_pairs(st, ss, n)
            out.append(
                observation(view, visible, extent, offsets, occluders, st_offsets, st_occluders, skip, in_view, in_fov)
            )
        return out
