"""The counting engine: what a camera's pixels or a lidar's beams meet, per viewpoint, as an :class:`Observation`
with the sensor's own columns.

The bodies are those of the exact 3D engine (:mod:`..silhouette3d`): each object's box and the static occluders
raised to their heights as convex prisms, seen from the sensor's eye (its height above the ground under its
observer); the observer's own body and the bodies holding the eye never block.

The observation's shares are in the sensor's units, over the target's whole extent (1): a lidar's
``visible_angle`` is the share of the beams meeting the target that meet it first within range, ``in_view_angle``
the share meeting it within range; a camera's are the same shares of its pixels times the share of its solid angle
inside the image (``1 - truncation``). So the table's ``visibility`` of a camera row is ``(1 - occlusion) (1 -
truncation)`` where nothing lies beyond the range, and its ``status`` is ``out_of_fov`` when no pixel centre (no
beam) meets the target at all.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import ClassVar

import numpy as np

from ...inputs.cameras import Pinhole
from ...inputs.objects import FrameObjects
from ...inputs.statics import StaticOccluders
from ...threed.bodies import ConvexBodies, bodies_from_boxes, concatenate, containing_origin
from ...threed.boxes import eye_point, nearest_distance
from .. import Observation, Viewpoint, group_pairs
from ..observe3d import StaticPrisms
from .camera import camera_counts, frustum_planes
from .lidar import lidar_counts
from .scene import SensorScene, sensor_axes, sensor_scene


def _outside_frustum(vertices: np.ndarray, vertex_body: np.ndarray, n: int, planes: np.ndarray) -> np.ndarray:
    """Bodies (vertices in the camera frame) wholly on the outer side of one of the frustum's planes."""
    outside = np.zeros(n, dtype=bool)
    if not len(vertices):
        return outside
    for plane in planes:
        inside = np.zeros(n, dtype=bool)
        np.logical_or.at(inside, vertex_body, vertices @ plane >= -1e-9)
        outside |= ~inside
    return outside


class ImagingEngine:
    """Counts pixels and beams (see the module docstring); built once per chunk from the static occluders."""

    name: ClassVar[str] = "imaging"
    measure: ClassVar[str] = "share"
    passive_targets: ClassVar[bool] = False
    chunked: ClassVar[bool] = False

    def __init__(self, statics: StaticOccluders) -> None:
        self.statics = statics
        self.static_prisms = StaticPrisms(statics)

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One :class:`Observation` (with ``counts``) per camera or lidar viewpoint of this frame."""
        boxes = getattr(objects, "boxes3d", None)
        if boxes is None:
            raise ValueError("cameras and lidars need the 3D boxes of the objects: pass mode='3d'")
        world = bodies_from_boxes(boxes)  # once for all the frame's sensors
        return [self._observe(boxes, world, view) for view in viewpoints]

    def _scene(self, boxes: np.ndarray, world: ConvexBodies, view: Viewpoint) -> tuple[SensorScene, np.ndarray]:
        """The sensor's scene (targets first: the frame's boxes but the observer's and those holding the eye,
        then the static prisms that may block) and the object row of each target."""
        optics = view.optics
        if optics is None:
            raise ValueError("the imaging engine counts for cameras and lidars only")
        is_camera = isinstance(optics, Pinhole)
        eye = eye_point(view.position, view.height, boxes, view.own)
        axes = sensor_axes(view.heading, view.pitch, "camera" if is_camera else "lidar")
        boxes_rel = world.relative_to(eye)
        skip = containing_origin(boxes_rel)
        if 0 <= view.own < len(boxes):
            skip[view.own] = True
        rows = np.flatnonzero(~skip)
        bodies = boxes_rel.take(rows)
        prisms = self.static_prisms.for_view(view, eye)
        if prisms is not None and len(prisms):
            rel = prisms.relative_to(eye)
            keep = ~containing_origin(rel)
            if is_camera:  # only what reaches into the image can block a pixel
                turned = rel.vertices @ axes.T
                keep &= ~_outside_frustum(turned, rel.vertex_body, len(rel), frustum_planes(optics))
            bodies = concatenate(bodies, rel.take(np.flatnonzero(keep)))
        near = nearest_distance(boxes[rows], eye)
        return sensor_scene(bodies, np.arange(len(rows)), axes, near), rows

    def _observe(
        self, boxes: np.ndarray, world: ConvexBodies, view: Viewpoint, labels: bool = False, scene: tuple = ()
    ) -> Observation:
        n = len(boxes)
        scene, rows = scene or self._scene(boxes, world, view)
        is_camera = isinstance(view.optics, Pinhole)
        if is_camera:
            counts = camera_counts(scene, view.optics, view.range, labels)
            met, unoccluded, first = counts["pixels_met"], counts["pixels_unoccluded"], counts["pixels"]
            share_in = np.where(met > 0, 1.0 - counts["truncation"], 0.0)
        else:
            counts = lidar_counts(scene, view.optics, view.range)
            met, unoccluded, first = counts["points_met"], counts["points_unoccluded"], counts["points"]
            share_in = (met > 0).astype(np.float64)
        with np.errstate(divide="ignore", invalid="ignore"):
            in_view = np.where(met > 0, share_in * unoccluded / met, 0.0)
            visible = np.where(met > 0, share_in * first / met, 0.0)
        target, body = np.nonzero(counts.pop("hidden_by"))
        is_box = body < len(rows)
        offsets, occluders = group_pairs(rows[target[is_box]], rows[body[is_box]], n)
        st_offsets, st_occluders = group_pairs(rows[target[~is_box]], scene.source[body[~is_box]], n)
        columns = _per_object(counts, rows, n, is_camera)
        if labels:  # the object row each pixel meets first (-1: none)
            columns["labels"] = np.where(counts["labels"] >= 0, rows[np.maximum(counts["labels"], 0)], -1)
        full = np.zeros(n)
        full[rows] = visible
        seen = np.zeros(n)
        seen[rows] = in_view
        inside = np.zeros(n)
        inside[rows] = share_in
        transparent = np.ones(n, dtype=bool)
        transparent[rows] = False
        return Observation.from_parts(
            full, np.ones(n), offsets, occluders, st_offsets, st_occluders, transparent, seen, inside, columns
        )

    def picture(self, objects: FrameObjects, view: Viewpoint) -> tuple[Observation, SensorScene, np.ndarray]:
        """What a camera's picture needs: its :class:`Observation` (its ``counts`` with ``labels``, the image of
        the object row each pixel meets first), its scene in the camera frame, and the object row of each of the
        scene's targets (the bodies after them are static prisms)."""
        boxes = getattr(objects, "boxes3d", None)
        if boxes is None or not isinstance(view.optics, Pinhole):
            raise ValueError("a camera picture needs a camera among the sensors and mode='3d'")
        world = bodies_from_boxes(boxes)
        scene, rows = self._scene(boxes, world, view)
        return self._observe(boxes, world, view, labels=True, scene=(scene, rows)), scene, rows


def _per_object(counts: dict[str, np.ndarray], rows: np.ndarray, n: int, is_camera: bool) -> dict[str, np.ndarray]:
    """The sensor's columns per object of the frame (those it does not count: 0 pixels, no boxes)."""
    out = {}
    names = ("pixels", "pixels_unoccluded") if is_camera else ("points", "points_unoccluded")
    for name in names:
        column = np.zeros(n, dtype=np.int64)
        column[rows] = counts[name]
        out[name] = column
    if is_camera:
        unoccluded = out["pixels_unoccluded"]
        with np.errstate(divide="ignore", invalid="ignore"):
            out["occlusion"] = np.where(unoccluded > 0, 1.0 - out["pixels"] / unoccluded, np.nan)
        truncation = np.full(n, np.nan)
        truncation[rows] = counts["truncation"]
        out["truncation"] = truncation
        for name in ("bbox", "bbox_unoccluded"):
            box = np.full((n, 4), -1, dtype=np.int64)
            box[rows] = counts[name]
            out[name] = box
    return out
