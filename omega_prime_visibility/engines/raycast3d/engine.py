"""The 3D ray engine, for scenes with meshes: oriented boxes and static solids in one Embree scene per frame,
adaptive sampling per target, checked against the exact engine for the boxes and footprints.

Without meshes every setting returns the exact engine's answer (:mod:`..silhouette3d`). With meshes:

Per frame, viewpoints that see through the same objects (their own body, boxes containing their eye) share one
Embree scene of every other box and every static triangle, built centred on the first of their eyes. The rays
of all their targets go to Embree in one call per refinement level (:mod:`.sampling`). For every ray that hits
a target (an exact ray-box test in float64), the first body Embree meets decides whether the target is seen
there; boxes entered before the target along in-view rays (exact tests against the boxes whose bounding cones
overlap the target's) are its occluders, and so are static occluders met first.

The sampled ``visibility`` is the ratio of two sums over the same cells (directions that see the target /
directions that hit it), so a target with nothing in front of it is exactly 1. The exact engine, run on the
boxes and footprints alone, then fixes what sampling can miss (:mod:`.meshes`): occluder lists of boxes and
footprints, a target hidden by them, and a visible strip that no first ray met.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar

import numpy as np

from ...inputs.objects import FrameObjects
from ...inputs.statics import StaticOccluders
from ...threed.boxes import _TRIANGLES, contains, corners, frames, ray_entries
from ...threed.statics import static_solids
from .. import Observation, Viewpoint, group_pairs
from ..observe3d import eye_and_view, observation, own_body, statics_around_eye
from ..silhouette3d import SilhouetteEngine
from . import sampling
from .embree import FirstHit, hits_before
from .meshes import mesh_spheres, with_exact_parts


@dataclass(frozen=True, slots=True)
class Setting:
    """How finely targets are sampled: a ``grid x grid`` start on each target, cells split up to ``depth`` times
    where their rays disagree (so ``grid * 2**depth`` rays across the target where it matters); in scenes with
    meshes, ``probes x probes`` probe rays over each exact visible piece of a target a mesh may hide
    (:mod:`.meshes`)."""

    grid: int
    depth: int
    probes: int


PAD = 1e-7
"""Metres added to a target's half-extents when testing whether a ray hits it: rays along the edges of its
sampling rectangle graze its silhouette and count as hits."""

SETTINGS = {"fast": Setting(4, 2, 24), "default": Setting(8, 2, 32), "high": Setting(16, 3, 64)}
"""Named settings; the measured error of each is in the README (``benchmarks/bench_3d.py``)."""


def candidates(
    centres_rel: np.ndarray, radius: np.ndarray, solid: np.ndarray, targets: np.ndarray
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Per target (rows ``targets``), the solid boxes that may lie in front of it from the eye at the origin:
    their bounding spheres' cones overlap and they begin before the target ends. CSR ``(offsets, boxes)``, and
    per entry the box's cone as ``(unit direction, cosine of its angular radius)``, shape (k, 4)."""
    dist = np.linalg.norm(centres_rel, axis=1)
    unit = centres_rel / np.maximum(dist, 1e-12)[:, None]
    cone = np.where(dist > radius, np.arcsin(np.minimum(1.0, radius / np.maximum(dist, 1e-12))), math.pi)
    others = np.flatnonzero(solid)
    cos = np.clip(unit[targets] @ unit[others].T, -1.0, 1.0)
    overlap = np.arccos(cos) <= cone[targets, None] + cone[others][None, :] + 1e-9
    overlap &= (dist[others] - radius[others])[None, :] < (dist[targets] + radius[targets])[:, None]
    overlap &= others[None, :] != targets[:, None]
    offsets = np.zeros(len(targets) + 1, dtype=np.int64)
    np.cumsum(overlap.sum(axis=1), out=offsets[1:])
    boxes = np.broadcast_to(others, overlap.shape)[overlap].astype(np.int64)
    return offsets, boxes, np.column_stack([unit[boxes], np.cos(cone[boxes])])


class RaycastEngine:
    """Embree ray casting with adaptive sampling (see the module docstring); ``measure = "steradians"``."""

    name: ClassVar[str] = "raycast3d"
    measure: ClassVar[str] = "steradians"
    passive_targets: ClassVar[bool] = False
    chunked: ClassVar[bool] = False
    setting: ClassVar[str] = "default"

    def __init__(self, statics: StaticOccluders) -> None:
        solids = getattr(statics, "solids", None)
        if solids is None:
            solids = static_solids(statics)
        self.static_triangles = solids.triangles
        self.static_source = solids.source
        self.n_footprints = statics.n_sources
        self.n_static = solids.n_sources
        self.exact = SilhouetteEngine(statics, meshes_elsewhere=True)
        self.probes = SETTINGS[self.setting].probes
        self.mesh_spheres = mesh_spheres(self.static_triangles, self.static_source, self.n_footprints)

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` per viewpoint; needs the frame's 3D boxes (``objects.boxes3d``).

        Without meshes, the exact engine's answer; with meshes, the sampled fractions checked against the exact
        answer for the boxes and footprints (:func:`.meshes.with_exact_parts`)."""
        boxes = getattr(objects, "boxes3d", None)
        if boxes is None:
            raise ValueError("3D engines need the 3D boxes of the objects: load them with three_d=True (mode='3d')")
        if self.n_static == self.n_footprints:
            return self.exact.observe(objects, viewpoints)
        sampled = self.sampled(objects, viewpoints)
        return [with_exact_parts(self, objects, view, obs) for view, obs in zip(viewpoints, sampled, strict=True)]

    def sampled(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """The sampled answer alone: one :class:`Observation` per viewpoint, every body ray-cast."""
        boxes = objects.boxes3d
        n = len(boxes)
        frame = frames(boxes)
        box_corners = corners(boxes, frame)
        box_triangles = box_corners[:, _TRIANGLES].reshape(n, 12, 3, 3)
        groups: dict[tuple[bytes, bytes], list[int]] = {}
        eyes, limits, skips = [], [], []
        for k, view in enumerate(viewpoints):
            eye, lim = eye_and_view(view, boxes)
            skip = own_body(view, n) | contains(boxes, eye, frame=frame)
            static_skip = np.zeros(self.n_static, dtype=bool)
            static_skip[: len(view.static_transparent)] = statics_around_eye(
                view, eye, self.exact.tops, self.exact.bases
            )
            eyes.append(eye)
            limits.append(lim)
            skips.append(skip)
            groups.setdefault((skip.tobytes(), static_skip.tobytes()), []).append(k)
        out: list[Observation | None] = [None] * len(viewpoints)
        for (skip_bytes, static_bytes), members in groups.items():
            skip = np.frombuffer(skip_bytes, dtype=bool)
            static_skip = np.frombuffer(static_bytes, dtype=bool)
            origin = eyes[members[0]]
            keep = np.flatnonzero(~skip)
            keep_static = ~static_skip[self.static_source] if len(self.static_source) else np.zeros(0, bool)
            triangles = np.concatenate([box_triangles[keep].reshape(-1, 3, 3), self.static_triangles[keep_static]])
            owner = np.concatenate([np.repeat(keep, 12), n + self.static_source[keep_static]]).astype(np.int64)
            scene = FirstHit(triangles - origin)
            is_mesh = keep_static & (self.static_source >= self.n_footprints)
            meshes = (FirstHit(self.static_triangles[is_mesh] - origin), n + self.static_source[is_mesh])
            group_views = [viewpoints[k] for k in members]
            results = self._sample(
                scene, owner, meshes, boxes, frame, box_corners, skip, origin, [eyes[k] for k in members],
                [limits[k] for k in members], group_views,
            )  # fmt: skip
            for k, obs in zip(members, results, strict=True):
                out[k] = obs
        return out  # type: ignore[return-value]

    def _sample(self, scene, owner, meshes, boxes, frame, box_corners, skip, origin, eyes, limits, views):
        """Sample every target of the viewpoints of one scene (one Embree call per refinement level); a list of
        :class:`Observation`. ``meshes``: the scene of the meshes alone and their owners, where every mesh hit
        before the target along an in-view ray that meets it is listed as its occluder (behind a box or another
        mesh too, as footprints and boxes are listed)."""
        setting = SETTINGS[self.setting]
        n = len(boxes)
        centres, rots, halves = frame
        centres_local = centres - origin
        radius = np.linalg.norm(halves, axis=1)
        solid = ~skip
        targets = np.flatnonzero(solid)
        g = len(views)
        eyes_local = np.array(eyes) - origin
        view_params = np.array([[*lim, view.range] for lim, view in zip(limits, views, strict=True)])
        slot_view = np.repeat(np.arange(g), len(targets))
        slot_target = np.tile(targets, g)
        axes_parts, rect_parts, patch_slot_parts, cand_off_parts, cand_parts, cone_parts = [], [], [], [], [], []
        hull_off_parts, hull_parts = [np.zeros(1, np.int64)], []
        hull_base = 0
        base = 0
        for vi in range(g):
            rel_corners = box_corners[targets] - eyes[vi]
            rel_centres = centres[targets] - eyes[vi]
            rel_boxes = boxes[targets].copy()
            rel_boxes[:, :3] -= eyes[vi]
            axes, rect, which, hull_offsets, hull_uv = sampling.patches(rel_corners, rel_centres, rel_boxes)
            hull_off_parts.append(hull_offsets[1:] + hull_base)
            hull_parts.append(hull_uv)
            hull_base += len(hull_uv)
            axes_parts.append(axes)
            rect_parts.append(rect)
            patch_slot_parts.append(vi * len(targets) + which)
            offsets, cand, cone = candidates(centres - eyes[vi], radius, solid, targets)
            cand_off_parts.append(offsets[:-1] + base)
            cand_parts.append(cand)
            cone_parts.append(cone)
            base += len(cand)
        axes = np.concatenate(axes_parts) if axes_parts else np.zeros((0, 3, 3))
        rect = np.concatenate(rect_parts) if rect_parts else np.zeros((0, 4))
        patch_slot = np.concatenate(patch_slot_parts).astype(np.int64) if patch_slot_parts else np.zeros(0, np.int64)
        cand_offsets = np.concatenate([*cand_off_parts, [base]]).astype(np.int64)
        cand = np.concatenate(cand_parts).astype(np.int64) if cand_parts else np.zeros(0, np.int64)
        cone = np.concatenate(cone_parts) if cone_parts else np.zeros((0, 4))
        hull_offsets = np.concatenate(hull_off_parts).astype(np.int64)
        hull_uv = np.concatenate(hull_parts) if hull_parts else np.zeros((0, 2))
        sums = np.zeros((len(slot_view), 4))
        pair_slots, pair_occs = [], []
        node_patch, node_uv, cell_patch, cell_box, cell_nodes = sampling.grid(rect, setting.grid)
        code = np.zeros(0, np.int64)
        in_fov = np.zeros(0, bool)
        in_range = np.zeros(0, bool)
        all_dirs, all_slots = [], []
        for level in range(setting.depth + 1):
            if len(node_patch):
                dirs = sampling.directions(axes, node_patch, node_uv)
                node_slot = patch_slot[node_patch]
                all_dirs.append(dirs)
                all_slots.append(node_slot)
                prim, tfar = scene.cast(eyes_local[slot_view[node_slot]], dirs)
                c, f, r, ps, po = sampling.label(
                    dirs, node_slot, eyes_local, slot_view, slot_target, view_params, centres_local, rots,
                    halves, halves + PAD, prim, tfar, owner, cand_offsets, cand, cone, n,
                )  # fmt: skip
                code, in_fov, in_range = np.concatenate([code, c]), np.concatenate([in_fov, f]), np.r_[in_range, r]
                pair_slots.append(ps)
                pair_occs.append(po)
            if len(cell_patch) == 0:
                break
            node_patch, node_uv, cell_patch, cell_box, cell_nodes = sampling.refine(
                cell_patch, cell_box, cell_nodes, code, in_fov, in_range, patch_slot, slot_target, sums,
                len(code), level < setting.depth, hull_offsets, hull_uv,
            )  # fmt: skip
        if all_dirs:
            ps, po = _meshes_in_front(meshes, np.concatenate(all_dirs), np.concatenate(all_slots), code, in_fov,
                                      in_range, eyes_local, slot_view, slot_target, frame, origin)  # fmt: skip
            pair_slots.append(ps)
            pair_occs.append(po)
        pair_slot = np.concatenate(pair_slots) if pair_slots else np.zeros(0, np.int64)
        pair_occ = np.concatenate(pair_occs) if pair_occs else np.zeros(0, np.int64)
        out = []
        for vi, view in enumerate(views):
            slots = slice(vi * len(targets), (vi + 1) * len(targets))
            visible, extent, fov, in_view = (np.zeros(n) for _ in range(4))
            extent[targets], visible[targets], fov[targets], in_view[targets] = sums[slots].T
            mine = slot_view[pair_slot] == vi if len(pair_slot) else np.zeros(0, bool)
            key, occ = slot_target[pair_slot[mine]], pair_occ[mine]
            box_off, box_occ = group_pairs(key[occ < n], occ[occ < n], n)
            st_off, st_occ = group_pairs(key[occ >= n], occ[occ >= n] - n, n)
            out.append(observation(view, visible, extent, box_off, box_occ, st_off, st_occ, skip, in_view, fov))
        return out


def _meshes_in_front(meshes, dirs, slots, code, in_fov, in_range, eyes_local, slot_view, slot_target, frame, origin):
    """Pairs (slot, mesh owner) of every mesh hit before the slot's target along a sampled ray that meets the
    target in view and within range."""
    scene, mesh_owner = meshes
    rays = np.flatnonzero((code != sampling.MISS) & in_fov & in_range)
    if not len(rays) or scene.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    centres, rots, halves = frame
    slot = slots[rays]
    view, target = slot_view[slot], slot_target[slot]
    eyes = eyes_local[view]
    limit = np.empty(len(rays))
    for vi in np.unique(view):
        mine = np.flatnonzero(view == vi)
        limit[mine] = ray_entries(eyes_local[vi], dirs[rays[mine]], centres - origin, rots, halves + PAD, target[mine])
    ray, who = hits_before(scene, mesh_owner, eyes, dirs[rays], limit)
    pairs = np.unique(np.column_stack([slot[ray], who]).astype(np.int64).reshape(-1, 2), axis=0)
    return pairs[:, 0], pairs[:, 1]


class HighRaycastEngine(RaycastEngine):
    """:class:`RaycastEngine` at the ``"high"`` setting (a 1 % gap in a car's width at 80 m is found)."""

    name: ClassVar[str] = "raycast3d-high"
    setting: ClassVar[str] = "high"


class FastRaycastEngine(RaycastEngine):
    """:class:`RaycastEngine` at the ``"fast"`` setting."""

    name: ClassVar[str] = "raycast3d-fast"
    setting: ClassVar[str] = "fast"
