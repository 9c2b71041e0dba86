"""The per-frame scene arrays every stage after the inputs works on: :class:`ObjectTable` (all frames, sorted by
``(frame, idx)``) and :class:`FrameObjects` (one frame's slice), and the warning raised for problems in the input."""

from __future__ import annotations

from dataclasses import dataclass, fields
from typing import Literal

import numpy as np

from ..geometry.rings import Rings

OnInvalid = Literal["warn", "raise"]


class VisibilityInputWarning(UserWarning):
    """Rows or geometries were skipped, or treated specially, because of a problem in the input."""


@dataclass(frozen=True, slots=True)
class FrameObjects:
    """The objects of one frame as arrays.

    Attributes
    ----------
    frame, total_nanos : int
        Frame number and timestamp (nanoseconds) of the frame.
    idx : ndarray, shape (n,), int64
        Object ids, ascending.
    position : ndarray, shape (n, 2), float64
        Bounding-box centres, metres.
    yaw : ndarray, shape (n,), float64
        Headings, radians counter-clockwise from +x (0 where the table had no ``yaw``).
    rings : Rings
        One counter-clockwise outline per object.
    boxes3d : ndarray, shape (n, 9), or None
        The objects' 3D boxes (:mod:`.threed.boxes`), when loaded with ``three_d=True``.
    blocks : ndarray of bool, shape (n,), or None
        Which objects may block the view (``occluders=``, :mod:`.roles`); None: all.
    wanted : ndarray of bool, shape (n,), or None
        Which objects get rows as targets (``targets=``); None: all.
    """

    frame: int
    total_nanos: int
    idx: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    rings: Rings
    boxes3d: np.ndarray | None = None
    blocks: np.ndarray | None = None
    wanted: np.ndarray | None = None

    def __len__(self) -> int:
        return len(self.idx)


@dataclass(frozen=True, slots=True)
class ObjectTable:
    """A validated moving-object table, sorted by ``(frame, idx)``, with one outline per row."""

    frame: np.ndarray
    total_nanos: np.ndarray
    idx: np.ndarray
    position: np.ndarray
    yaw: np.ndarray
    rings: Rings
    frame_starts: np.ndarray  # (f + 1,) row where each frame starts
    boxes3d: np.ndarray | None = None  # (rows, 9) with three_d=True
    blocks: np.ndarray | None = None  # (rows,) bool: may block the view (None: all), see .roles
    wanted: np.ndarray | None = None  # (rows,) bool: gets rows as a target (None: all)
    heading_known: np.ndarray | None = None  # (rows,) bool: ``yaw`` was given (None: everywhere); else it reads 0

    @property
    def chosen(self) -> bool:
        """Whether ``occluders=`` or ``targets=`` narrowed the default (every object blocks and is a target)."""
        return self.blocks is not None or self.wanted is not None

    @property
    def n_frames(self) -> int:
        return len(self.frame_starts) - 1

    def frame_objects(self, k: int) -> FrameObjects:
        """The ``k``-th frame (0-based position, not the frame number)."""
        s, e = int(self.frame_starts[k]), int(self.frame_starts[k + 1])
        return FrameObjects(
            frame=int(self.frame[s]),
            total_nanos=int(self.total_nanos[s]),
            idx=self.idx[s:e],
            position=self.position[s:e],
            yaw=self.yaw[s:e],
            rings=self.rings.slice(s, e),
            boxes3d=None if self.boxes3d is None else self.boxes3d[s:e],
            blocks=None if self.blocks is None else self.blocks[s:e],
            wanted=None if self.wanted is None else self.wanted[s:e],
        )

    def frame_range(self, start: int, stop: int) -> ObjectTable:
        """Frames ``start`` to ``stop - 1`` (0-based positions) as a table of their own."""
        s, e = int(self.frame_starts[start]), int(self.frame_starts[stop])
        return self._with_rows(slice(s, e), self.rings.slice(s, e), self.frame_starts[start : stop + 1] - s)

    def take_rows(self, rows: np.ndarray) -> ObjectTable:
        """The rows ``rows`` (ascending positions) as a table of their own (frames left empty drop out)."""
        rows = np.asarray(rows, dtype=np.int64)
        frame = self.frame[rows]
        frame_starts = np.concatenate([[0], np.flatnonzero(np.diff(frame)) + 1, [len(frame)]]).astype(np.int64)
        if len(frame) == 0:
            frame_starts = np.zeros(1, dtype=np.int64)
        return self._with_rows(rows, self.rings.take(rows), frame_starts)

    def _with_rows(self, rows: slice | np.ndarray, rings: Rings, frame_starts: np.ndarray) -> ObjectTable:
        """The table of ``rows`` (a slice or positions) with their ``rings`` and ``frame_starts``: every per-row
        field taken by name, so a field added to the table is never dropped here."""
        values = {}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.name == "rings":
                value = rings
            elif f.name == "frame_starts":
                value = frame_starts
            elif value is not None:
                value = value[rows]
            values[f.name] = value
        return ObjectTable(**values)
