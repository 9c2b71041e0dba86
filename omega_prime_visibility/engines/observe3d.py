"""What the 3D engines share: a viewpoint's eye and view limits, and observations built from solid angles."""

from __future__ import annotations

import math
from dataclasses import fields

import numpy as np

from ..inputs.statics import StaticOccluders
from ..threed.bodies import ConvexBodies, prisms_from_footprints
from ..threed.boxes import contains, eye_point, view_limits
from ..threed.statics import BASE, DEFAULT_HEIGHT
from . import Observation, Reason, Viewpoint

_HAS_VIEW_FIELDS = "in_view_angle" in {f.name for f in fields(Observation)}


def eye_and_view(view: Viewpoint, boxes: np.ndarray) -> tuple[np.ndarray, tuple[float, float, float, float]]:
    """The 3D eye (metres) of ``view`` and its limits ``(heading, half fov, lowest, highest elevation)``."""
    eye = eye_point(view.position, view.height, boxes, view.own)
    return eye, view_limits(view.heading, min(view.fov, 2 * math.pi), view.pitch, view.vertical_fov)


def statics_around_eye(view: Viewpoint, eye: np.ndarray, tops: np.ndarray, bases: np.ndarray) -> np.ndarray:
    """Which static occluders hold the eye (metres): of those whose footprint contains the viewpoint
    (``view.static_transparent``, told in the plane), the ones whose prism also spans the eye's height (``bases``
    to ``tops``, metres, per footprint). They are transparent; a low platform under the eye, or a sign above it,
    blocks as anywhere else."""
    clear = np.asarray(view.static_transparent, dtype=bool).copy()
    n = min(len(clear), len(tops))
    clear[:n] &= (bases[:n] <= eye[2]) & (eye[2] <= tops[:n])
    return clear


def static_heights(statics: StaticOccluders) -> tuple[np.ndarray, np.ndarray]:
    """The top and the base of each static footprint (metres above z = 0): as given with the footprints
    (``statics.solids``), else :data:`.threed.statics.DEFAULT_HEIGHT` and :data:`.threed.statics.BASE`."""
    solids = getattr(statics, "solids", None)
    n = statics.n_sources
    tops = np.full(n, DEFAULT_HEIGHT) if solids is None else np.asarray(solids.heights, dtype=np.float64)
    bases = np.full(n, BASE) if solids is None else np.asarray(solids.bases, dtype=np.float64)
    return tops, bases


class StaticPrisms:
    """The static occluders raised to their heights as convex prisms (:mod:`..threed.bodies`), built once per
    chunk, and those that block for a viewpoint: what the exact 3D engine and the counting engine share.

    Attributes
    ----------
    tops, bases : ndarray
        Metres: each static occluder's top and base (:func:`static_heights`).
    prisms : ConvexBodies or None
        Every footprint's prisms (None without static occluders).
    """

    def __init__(self, statics: StaticOccluders) -> None:
        self.tops, self.bases = static_heights(statics)
        geometries = list(statics.geometries)
        self.prisms = prisms_from_footprints(geometries, self.tops, self.bases) if statics.n_sources else None

    def for_view(self, view: Viewpoint, eye: np.ndarray) -> ConvexBodies | None:
        """The prisms that block for ``view`` from ``eye`` (those of static occluders holding the eye left out:
        :func:`statics_around_eye`)."""
        clear = statics_around_eye(view, eye, self.tops, self.bases)
        if self.prisms is None or not clear.any():
            return self.prisms
        return self.prisms.take(np.flatnonzero(~clear[self.prisms.source]))


def statics_holding_eye(view: Viewpoint, boxes: np.ndarray, tops: np.ndarray, bases: np.ndarray) -> np.ndarray:
    """:func:`statics_around_eye` from the eye of ``view`` among the frame's ``boxes`` (shape (n, 9))."""
    if not np.any(view.static_transparent):
        return np.zeros(len(view.static_transparent), dtype=bool)
    eye, _ = eye_and_view(view, boxes)
    return statics_around_eye(view, eye, tops, bases)


def holding_eye(view: Viewpoint, boxes: np.ndarray) -> np.ndarray:
    """Which boxes (shape (n, 9)) contain or touch the eye of ``view``: in 3D the only ones transparent to it
    besides its own body."""
    eye, _ = eye_and_view(view, boxes)
    return contains(boxes, eye)


def own_body(view: Viewpoint, n: int) -> np.ndarray:
    """The observer's own body as a mask over the frame's ``n`` objects. In 3D only it and the boxes containing
    the eye (tested in 3D by the engines) are transparent: a box whose footprint covers the viewpoint but not the
    eye (an overhead sign, a low object under a raised sensor) is seen and blocks."""
    mask = np.zeros(n, dtype=bool)
    if 0 <= view.own < n:
        mask[view.own] = True
    return mask


def limited(view: Viewpoint) -> bool:
    """Whether the horizontal or vertical field of view or the range cut anything off."""
    return view.fov < 2 * math.pi or math.isfinite(view.range) or view.vertical_fov < math.pi or view.pitch != 0.0


def observation(
    view: Viewpoint,
    visible: np.ndarray,
    extent: np.ndarray,
    occluder_offsets: np.ndarray,
    occluders: np.ndarray,
    static_offsets: np.ndarray,
    static_occluders: np.ndarray,
    transparent: np.ndarray,
    in_view: np.ndarray,
    in_fov: np.ndarray,
) -> Observation:
    """An :class:`Observation` in steradians; ``in_view`` (hit within view and range, occlusion ignored) and
    ``in_fov`` (within the field of view) are passed on where the contract has them, else a target cut off by
    the view is marked occluded so that the table takes its visible share."""
    parts = (visible, extent, occluder_offsets, occluders, static_offsets, static_occluders, transparent)
    if _HAS_VIEW_FIELDS and limited(view):
        return Observation.from_parts(*parts, in_view_angle=in_view, in_fov_angle=in_fov)
    obs = Observation.from_parts(*parts)
    cut = (obs.reason == int(Reason.IN_VIEW)) & (visible < extent * (1 - 1e-12))
    if not cut.any():
        return obs
    reason = obs.reason.copy()
    reason[cut] = int(Reason.OCCLUDED)
    return Observation(visible, extent, reason, occluder_offsets, occluders, static_offsets, static_occluders)
