"""What the ray engine takes from the exact engine in scenes with meshes.

Meshes only hide more: the directions that see a target among boxes, footprints *and* meshes lie within those
that see it among boxes and footprints alone, which the exact engine gives as polygons on the faces of a cube
around the eye (:func:`..silhouette3d.boxes_among`). So, per target:

- occluder lists of boxes and footprints are the exact engine's (overlap of silhouettes and depth, not which rays
  happened to hit); meshes met first by the sampled rays are added;
- a target the boxes and footprints hide entirely reads 0, and no share is above the exact one;
- a target that a mesh may hide (their bounding spheres' cones from the eye overlap and the mesh begins before
  the target ends), or whose sampled share falls short of the exact one, is probed: rays are cast into each of
  its exact visible pieces (a grid over the piece's bounds fine enough to put about ``probes x probes`` points
  inside it, the setting's; its corners and edge midpoints moved a thousandth of the way towards its centre;
  one point inside it however thin), and its visible solid angle is the sum over its pieces of the piece's
  solid angle times the fraction of its probes (weighted by the solid angle each stands for) that reach the
  target first. A strip between boxes is found at
  any width; a strip between a mesh and another body once it is wider than about 1 / probes of its piece.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import shapely

from ...inputs.objects import FrameObjects
from ...threed.boxes import frames, ray_entries
from ...threed.cube import face_direction, solid_angles
from .. import Observation, Viewpoint, group_pairs
from ..observe3d import eye_and_view, observation, own_body, statics_around_eye
from ..silhouette3d import boxes_among
from .embree import FirstHit, hits_before


def with_exact_parts(engine: Any, objects: FrameObjects, view: Viewpoint, sampled: Observation) -> Observation:
    """``sampled`` (the observation of ``view`` by ``engine``, a :class:`.engine.RaycastEngine`) with the exact
    engine's corrections (module docstring): extents, in-view angles and box and footprint occluders exact,
    shares bounded by the exact ones, targets a mesh may hide probed."""
    boxes = objects.boxes3d
    n = len(boxes)
    eye, limits = eye_and_view(view, boxes)
    parts: list = []
    exact = engine.exact
    result = boxes_among(boxes, eye, own_body(view, n), limits, view.range, exact.prisms_for(view, eye), parts)
    visible_c, extent, in_view, in_fov, (bt, bb), (st, ss), skip = result
    with np.errstate(divide="ignore", invalid="ignore"):
        share_rays = np.where(sampled.angular_extent > 0, sampled.visible_angle / sampled.angular_extent, 0.0)
        share_exact = np.where(extent > 0, visible_c / extent, 0.0)
    share = np.minimum(share_rays, share_exact)
    key = np.repeat(np.arange(n), np.diff(sampled.static_offsets))
    mesh = sampled.static_occluders >= engine.n_footprints
    behind_mesh = _mesh_cones_overlap(engine, boxes, eye)
    behind_mesh[key[mesh]] = True
    differ = np.flatnonzero((behind_mesh | (share_rays < share_exact * (1 - 1e-9))) & (visible_c > 0) & ~skip)
    probed_t, probed_mesh = np.zeros(0, np.int64), np.zeros(0, np.int64)
    if len(differ):
        seen, (probed_t, probed_mesh) = _probe(engine, boxes, eye, view, differ, parts)
        share[differ] = seen / extent[differ]
    offsets, occluders = group_pairs(bt, bb, n)
    st_offsets, st_occluders = group_pairs(
        np.r_[st, key[mesh], probed_t].astype(np.int64),
        np.r_[ss, sampled.static_occluders[mesh], probed_mesh].astype(np.int64),
        n,
    )
    return observation(view, share * extent, extent, offsets, occluders, st_offsets, st_occluders, skip, in_view,
                       in_fov)  # fmt: skip


def mesh_spheres(triangles: np.ndarray, source: np.ndarray, first_mesh: int) -> tuple[np.ndarray, np.ndarray]:
    """Centre (m, 3) and radius (m,) of a sphere around each mesh (static sources from ``first_mesh`` on)."""
    which = source - first_mesh
    m = int(which.max()) + 1 if len(which) and which.max() >= 0 else 0
    centre, radius = np.zeros((m, 3)), np.zeros(m)
    for k in range(m):
        points = triangles[which == k].reshape(-1, 3)
        low, high = points.min(axis=0), points.max(axis=0)
        centre[k] = (low + high) / 2
        radius[k] = np.linalg.norm(points - centre[k], axis=1).max()
    return centre, radius


def _mesh_cones_overlap(engine, boxes: np.ndarray, eye: np.ndarray) -> np.ndarray:
    """Per box, whether some mesh may lie in front of it from ``eye``: the cones from the eye around their
    bounding spheres overlap, and the mesh begins before the box ends."""
    centre, radius = engine.mesh_spheres
    rel_m = centre - eye
    rel_b = boxes[:, :3] - eye
    r_b = np.linalg.norm(boxes[:, 3:6], axis=1) / 2
    d_m, d_b = np.linalg.norm(rel_m, axis=1), np.linalg.norm(rel_b, axis=1)
    cone_m = np.where(d_m > radius, np.arcsin(np.minimum(1.0, radius / np.maximum(d_m, 1e-12))), np.pi)
    cone_b = np.where(d_b > r_b, np.arcsin(np.minimum(1.0, r_b / np.maximum(d_b, 1e-12))), np.pi)
    cos = (rel_b / np.maximum(d_b, 1e-12)[:, None]) @ (rel_m / np.maximum(d_m, 1e-12)[:, None]).T
    apart = np.arccos(np.clip(cos, -1.0, 1.0))
    overlap = (apart <= cone_b[:, None] + cone_m[None, :] + 1e-9) & ((d_m - radius)[None, :] < (d_b + r_b)[:, None])
    return overlap.any(axis=1)


def _probe(engine, boxes, eye, view, targets, parts) -> tuple[np.ndarray, tuple[np.ndarray, np.ndarray]]:
    """Per target in ``targets``, the solid angle (steradians) of its exact visible pieces times the fraction of
    each piece's probe rays that no mesh meets before it (the pieces are where it is the first box or footprint
    hit); and the pairs (target row, mesh number) of the meshes that probe rays meet before it, nearest or not
    (its static occluders)."""
    wanted = {int(t): k for k, t in enumerate(targets)}
    mine = [(wanted[row], f, polygon) for row, f, polygon in parts if row in wanted]
    if not mine:
        return np.zeros(len(targets)), (np.zeros(0, np.int64), np.zeros(0, np.int64))
    directions, piece_of, points = [], [], []
    for k, (_, f, polygon) in enumerate(mine):
        u0, v0, u1, v1 = polygon.bounds
        fill = polygon.area / max((u1 - u0) * (v1 - v0), 1e-300)  # about probes^2 points inside, 4x at most
        side = int(min(4 * engine.probes, np.ceil(engine.probes / np.sqrt(max(fill, 1e-6)))))
        grid = (np.arange(side) + 0.5) / side
        uu, vv = np.meshgrid(u0 + grid * (u1 - u0), v0 + grid * (v1 - v0))
        ring = shapely.get_coordinates(shapely.get_exterior_ring(shapely.get_parts(polygon)))
        centre = shapely.get_coordinates(shapely.centroid(polygon))
        edge_points = np.concatenate([ring, (ring[1:] + ring[:-1]) / 2])
        uv = np.concatenate([np.column_stack([uu.ravel(), vv.ravel()]), centre + (edge_points - centre) * (1 - 1e-3)])
        uv = uv[shapely.contains_xy(polygon, uv[:, 0], uv[:, 1])]
        uv = np.concatenate([uv, shapely.get_coordinates(shapely.point_on_surface(polygon))])
        points.append(uv)
        d = face_direction(f, uv)
        directions.append(d / np.linalg.norm(d, axis=1)[:, None])
        piece_of.append(np.full(len(uv), k))
    dirs, piece = np.concatenate(directions), np.concatenate(piece_of)
    owner = np.array([t for t, _, _ in mine])
    target_of_ray = np.asarray(targets)[owner[piece]]
    # the pieces are where the target is the first box or footprint hit: only a mesh can hide more of them
    static_skip = np.zeros(engine.n_static, dtype=bool)
    static_skip[: len(view.static_transparent)] = statics_around_eye(view, eye, engine.exact.tops, engine.exact.bases)
    is_mesh = engine.static_source >= engine.n_footprints
    if len(engine.static_source):
        is_mesh &= ~static_skip[engine.static_source]
    centre, rot, half = frames(boxes)
    entry = ray_entries(np.zeros(3), dirs, centre - eye, rot, half, target_of_ray)
    scene = FirstHit(engine.static_triangles[is_mesh] - eye)
    ray, mesh = hits_before(scene, engine.static_source[is_mesh], np.zeros((len(dirs), 3)), dirs, entry)
    reached = np.ones(len(dirs), dtype=bool)
    reached[ray] = False
    uv = np.concatenate(points)
    weight = (1.0 + (uv * uv).sum(axis=1)) ** -1.5  # solid angle per unit area of the face at each point
    fraction = np.bincount(piece, weight * reached, len(mine)) / np.bincount(piece, weight, len(mine))
    seen = np.bincount(owner, solid_angles(np.array([p for _, _, p in mine], dtype=object)) * fraction, len(targets))
    return seen, (target_of_ray[ray].astype(np.int64), mesh.astype(np.int64))
