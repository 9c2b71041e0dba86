"""Visibility engines: pure computations over one frame's arrays, no polars and no I/O.

Every engine has the same contract, so the front end never asks which one it runs:

- ``Engine(statics)`` is built once per chunk of frames from the validated :class:`~..scene.StaticOccluders`;
- ``engine.observe(objects, viewpoints)`` returns one :class:`Observation` per :class:`Viewpoint` of the frame
  (engines may share work between the viewpoints of a frame);
- ``Engine.passive_targets`` says whether it measures targets that may not block (``occluders=``) itself;
- ``Engine.measure`` says what its angles are: ``"radians"`` for the 2D engines (a 3D engine measures solid
  angles, ``"steradians"``, with the same occluder layout);
- ``Engine.chunked`` says whether it offers ``engine.observe_chunk(objects, viewpoints)``: a whole chunk of frames
  at once from :class:`ChunkViewpoints` that see all around without range, returning one :class:`ChunkObservation`
  with the same numbers ``observe`` gives frame by frame (an engine with a compiled loop over frames offers it, so
  that small scenes pay no per-frame Python).

An engine that cannot compute a frame exactly raises :class:`EngineFailure`; the pipeline then computes that frame
with :data:`FALLBACK_ENGINE` and says so in a warning.

What the numbers mean in the table (the policy keyed on the :class:`Reason` codes) lives in :mod:`..table`.
Which engines exist, and which one a question takes, lives in :mod:`.registry` (engines never import it): a new
engine is one module and one line in :data:`.registry.ENGINES`.
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import ClassVar, Protocol

import numpy as np

from .._compiled.kernel import njit
from ..inputs.cameras import Pinhole
from ..inputs.lidars import BeamPattern
from ..inputs.objects import FrameObjects
from ..inputs.sensors import DRIVER_EYE_HEIGHT, TWO_PI
from ..inputs.statics import StaticOccluders


class EngineFailure(RuntimeError):
    """An engine cannot compute this frame exactly (VisiLibity, say, when its visibility polygon keeps skipping a
    body, or a viewpoint lies within its walls' thickness); the frame is computed by :data:`FALLBACK_ENGINE`."""


FALLBACK_ENGINE = "sweep"
"""The 2D engine that takes over the frames another engine fails on (exact, and without VisiLibity's thickened
walls and snapping)."""


class Reason(enum.IntEnum):
    """Why a target is seen as it is, one code per target of an :class:`Observation`."""

    IN_VIEW = 0
    """Nothing is hit before the target in any direction of its extent: it is fully visible."""
    OCCLUDED = 1
    """Some body is hit before the target in some direction: partly or wholly hidden."""
    CONTAINS_OBSERVER = 2
    """The target contains (or touches) the viewpoint: it is transparent and counts as fully visible."""


_IN_VIEW, _OCCLUDED, _CONTAINS_OBSERVER = int(Reason.IN_VIEW), int(Reason.OCCLUDED), int(Reason.CONTAINS_OBSERVER)


@dataclass(frozen=True, slots=True)
class Viewpoint:
    """Where one observer looks from in one frame, and what it looks through.

    Attributes
    ----------
    position : ndarray, shape (2,)
        The viewpoint, metres, in the recording's frame.
    heading : float
        Direction the observer faces, radians counter-clockwise from +x (the observing object's yaw).
    own : int
        Position, in the frame's object arrays, of the observing object (it gets no row), or -1.
    transparent : ndarray of bool, shape (n,)
        Objects that neither block nor occlude: the observer's own body and bodies containing the viewpoint.
    static_transparent : ndarray of bool, shape (n_sources,)
        Static occluders containing the viewpoint.
    fov : float
        Horizontal field of view, radians in (0, 2π], centred on ``heading``; 2π looks all around.
    range : float
        Metres (``inf``: no limit); a direction counts only where its first hit lies within this distance.
    height : float
        Metres above the ground of the eye (3D engines only).
    vertical_fov : float
        Radians in (0, π], centred on ``pitch`` (3D engines only).
    pitch : float
        Radians, positive looking down (3D engines only).
    passive : ndarray of bool, shape (n,), or None
        Targets that neither block nor occlude (``occluders=``), each measured against the others that may; only
        for engines with :attr:`Engine.passive_targets` (None: none).
    optics : Pinhole or BeamPattern, optional
        The image of a camera or the beams of a lidar: such a viewpoint counts pixels or beams
        (:mod:`.imaging`), in the 3D mode.
    """

    position: np.ndarray
    heading: float
    own: int
    transparent: np.ndarray
    static_transparent: np.ndarray
    fov: float = TWO_PI
    range: float = math.inf
    height: float = DRIVER_EYE_HEIGHT
    vertical_fov: float = math.pi
    pitch: float = 0.0
    passive: np.ndarray | None = None
    optics: Pinhole | BeamPattern | None = None

    @property
    def limited(self) -> bool:
        """Whether the field of view or the range cuts anything off (else the viewpoint sees as a bare point)."""
        return self.fov < TWO_PI or math.isfinite(self.range)


@dataclass(frozen=True, slots=True)
class Observation:
    """What one viewpoint sees of every object of a frame.

    Attributes
    ----------
    visible_angle : ndarray, shape (n,), float64
        Angle of directions along which the object is the first thing hit (in the engine's ``measure``).
    angular_extent : ndarray, shape (n,), float64
        Angle of directions that hit the object at all.
    reason : ndarray, shape (n,), int8
        A :class:`Reason` code per object.
    occluder_offsets : ndarray, shape (n + 1,), int64
        Object ``i``'s occluders are ``occluders[occluder_offsets[i]:occluder_offsets[i + 1]]``.
    occluders : ndarray, shape (k,), int64
        Row numbers (into the frame's object arrays) of objects hit before the target somewhere, ascending.
    static_offsets : ndarray, shape (n + 1,), int64
    static_occluders : ndarray, shape (k2,), int64
        Positions, in the user's static occluder list, of static occluders hit before the target, ascending.
    in_view_angle : ndarray, shape (n,), or None
        For a limited viewpoint (:attr:`Viewpoint.limited`): angle of directions inside the field of view along
        which the object is hit within range, ignoring occlusion; ``visible_angle`` and the occluder lists then
        count those directions only. None: the whole extent is in view.
    in_fov_angle : ndarray, shape (n,), or None
        Likewise, angle of the extent inside the field of view, range ignored.
    counts : dict of str to ndarray, or None
        A camera's or lidar's own columns by name (:data:`..table.schema.COUNT_SCHEMA`), one entry per object
        (shape (n,) or (n, 4)).

    Entries for objects with ``Reason.CONTAINS_OBSERVER`` are unspecified but for the code itself.
    """

    visible_angle: np.ndarray
    angular_extent: np.ndarray
    reason: np.ndarray
    occluder_offsets: np.ndarray
    occluders: np.ndarray
    static_offsets: np.ndarray
    static_occluders: np.ndarray
    in_view_angle: np.ndarray | None = None
    in_fov_angle: np.ndarray | None = None
    counts: dict[str, np.ndarray] | None = None

    @classmethod
    def from_parts(
        cls,
        visible_angle: np.ndarray,
        angular_extent: np.ndarray,
        occluder_offsets: np.ndarray,
        occluders: np.ndarray,
        static_offsets: np.ndarray,
        static_occluders: np.ndarray,
        transparent: np.ndarray,
        in_view_angle: np.ndarray | None = None,
        in_fov_angle: np.ndarray | None = None,
        counts: dict[str, np.ndarray] | None = None,
    ) -> Observation:
        """An observation whose reason codes follow from the occluder lists and the transparency mask."""
        reason = _reason_codes(occluder_offsets, static_offsets, np.asarray(transparent, dtype=np.bool_))
        return cls(
            visible_angle,
            angular_extent,
            reason,
            occluder_offsets,
            occluders,
            static_offsets,
            static_occluders,
            in_view_angle,
            in_fov_angle,
            counts,
        )


@njit(cache=True, inline="always")
def reason_of(transparent, n_occluders, n_static_occluders):
    """The :class:`Reason` code of a target from whether it contains the viewpoint and its numbers of occluders
    (the one place the codes are decided; every engine's observations go through it)."""
    if transparent:
        return _CONTAINS_OBSERVER
    if n_occluders > 0 or n_static_occluders > 0:
        return _OCCLUDED
    return _IN_VIEW


@njit(cache=True)
def _reason_codes(occluder_offsets, static_offsets, transparent):
    """One :class:`Reason` code per object from its occluder lists and whether it contains the viewpoint."""
    n = len(transparent)
    reason = np.empty(n, dtype=np.int8)
    for i in range(n):
        reason[i] = reason_of(
            transparent[i], occluder_offsets[i + 1] - occluder_offsets[i], static_offsets[i + 1] - static_offsets[i]
        )
    return reason


@dataclass(frozen=True, slots=True)
class ChunkViewpoints:
    """The viewpoints of a chunk of frames, frame by frame, each seeing all around without range.

    Viewpoint ``v`` of frame position ``f`` (``frame_starts[f] <= v < frame_starts[f + 1]``) has a *target* for
    every object of its frame: targets ``target_offsets[v]`` to ``target_offsets[v + 1] - 1``, in the frame's row
    order.

    Attributes
    ----------
    frame_starts : ndarray, shape (f + 1,), int64
        First viewpoint of each frame of the chunk.
    position : ndarray, shape (v, 2), float64
        Metres, in the recording's frame.
    own : ndarray, shape (v,), int64
        Row number, within its frame, of the observing object (it gets no row), or -1.
    target_offsets : ndarray, shape (v + 1,), int64
    transparent : ndarray, shape (t,), bool
        Per target: neither blocks nor occludes (:attr:`Viewpoint.transparent`).
    static_offsets : ndarray, shape (v + 1,), int64
    static_inside : ndarray, int64
        Static occluder sources containing viewpoint ``v``: ``static_inside[static_offsets[v]:static_offsets[v + 1]]``.
    passive : ndarray, shape (t,), bool, or None
        Per target: measured against the others but neither blocks nor occludes (:attr:`Viewpoint.passive`).
    """

    frame_starts: np.ndarray
    position: np.ndarray
    own: np.ndarray
    target_offsets: np.ndarray
    transparent: np.ndarray
    static_offsets: np.ndarray
    static_inside: np.ndarray
    passive: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.own)


@dataclass(frozen=True, slots=True)
class ChunkObservation:
    """What every viewpoint of a :class:`ChunkViewpoints` sees: the fields of :class:`Observation` for all its
    targets one after another (shape (t,)), their occluder lists as CSR over the targets.

    Attributes
    ----------
    visible_angle, angular_extent : ndarray, shape (t,), float64
    reason : ndarray, shape (t,), int8
    occluder_offsets : ndarray, shape (t + 1,), int64
        Target ``t``'s occluders are ``occluders[occluder_offsets[t]:occluder_offsets[t + 1]]``: row numbers within
        its frame, ascending.
    occluders : ndarray, int64
    static_offsets : ndarray, shape (t + 1,), int64
    static_occluders : ndarray, int64
        Positions in the user's static occluder list, ascending per target.
    """

    visible_angle: np.ndarray
    angular_extent: np.ndarray
    reason: np.ndarray
    occluder_offsets: np.ndarray
    occluders: np.ndarray
    static_offsets: np.ndarray
    static_occluders: np.ndarray


class Engine(Protocol):
    """The engine contract (see the module docstring)."""

    name: ClassVar[str]
    measure: ClassVar[str]
    passive_targets: ClassVar[bool]
    """Whether the engine measures :attr:`Viewpoint.passive` targets itself (else the front end gives each group
    of them a view of its own, see :mod:`..table.selection`)."""
    chunked: ClassVar[bool]
    """Whether the engine offers ``observe_chunk`` (a whole chunk of frames at once, see the module docstring)."""

    def __init__(self, statics: StaticOccluders) -> None: ...

    def observe(self, objects: FrameObjects, viewpoints: Sequence[Viewpoint]) -> list[Observation]:
        """One observation per viewpoint of this frame."""
        ...


def group_pairs(key: np.ndarray, value: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Offsets and values, grouped by ``key`` in ``range(n)`` and sorted ascending within each group."""
    order = np.lexsort((value, key))
    key, value = key[order], value[order]
    if len(key):
        keep = np.ones(len(key), dtype=bool)
        keep[1:] = (key[1:] != key[:-1]) | (value[1:] != value[:-1])
        key, value = key[keep], value[keep]
    offsets = np.zeros(n + 1, dtype=np.int64)
    np.cumsum(np.bincount(key, minlength=n), out=offsets[1:])
    return offsets, value.astype(np.int64)


REGISTRY_NAMES = ("ENGINES", "ENGINES_3D", "ENGINES_AREA", "get_engine")
"""Names of :mod:`.registry` importable from here too (documented paths): loaded on first use, so that this
contract never imports the registry."""


def __getattr__(name: str):
    if name in REGISTRY_NAMES:
        from . import registry

        return getattr(registry, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
