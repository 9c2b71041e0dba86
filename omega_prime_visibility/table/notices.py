"""What the table's warnings summarise: observers inside objects or static occluders, and frames that needed the
fallback engine, counted over all chunks (workers return their logs, the front end merges them and warns once)."""

from __future__ import annotations

import warnings
from collections import Counter

import numpy as np

from ..engines import FALLBACK_ENGINE
from ..inputs.objects import VisibilityInputWarning

SHOWN = 10
"""Pairs named in a warning; the rest are counted."""


class ContainmentLog:
    """Counts objects and static occluders that contain an observer, and frames computed by the fallback engine,
    for one summarising warning each.

    Examples
    --------
    >>> import numpy as np
    >>> log = ContainmentLog()
    >>> log.add_pairs(np.array([0, 0]), np.array([3, 3]), np.array([7, 8]))
    >>> log.add_static_pairs(np.array([0]), np.array([1]), np.array([9]))
    >>> dict(log.frames), dict(log.static_frames)
    ({(0, 3): 2}, {(0, 1): 1})
    """

    def __init__(self) -> None:
        self.frames: Counter[tuple[int, int]] = Counter()
        self.first: dict[tuple[int, int], int] = {}
        self.static_frames: Counter[tuple[int, int]] = Counter()
        self.static_first: dict[tuple[int, int], int] = {}
        self.fallback_frames = 0
        self.first_fallback: tuple[int, str] | None = None  # (frame, why)

    def add_fallback(self, frame: int, why: str) -> None:
        """A frame the engine failed on (:class:`..engines.EngineFailure` saying ``why``), computed by the fallback."""
        self.fallback_frames += 1
        if self.first_fallback is None:
            self.first_fallback = (int(frame), why)

    def add_pairs(self, ego: np.ndarray, idx: np.ndarray, frame: np.ndarray) -> None:
        """Add many ``(observer idx, containing idx, frame)`` triples (a frame counts once, however many of the
        observer's sensors are inside)."""
        _count(self.frames, self.first, ego, idx, frame)

    def add_static_pairs(self, ego: np.ndarray, source: np.ndarray, frame: np.ndarray) -> None:
        """Add many ``(observer idx, static occluder, frame)`` triples: the static occluder at position ``source``
        of the user's list contains the observer (or one of its sensors) in that frame."""
        _count(self.static_frames, self.static_first, ego, source, frame)

    def merge(self, other: ContainmentLog) -> None:
        self.frames.update(other.frames)
        for key, frame in other.first.items():
            self.first.setdefault(key, frame)
        self.static_frames.update(other.static_frames)
        for key, frame in other.static_first.items():
            self.static_first.setdefault(key, frame)
        self.fallback_frames += other.fallback_frames
        self.first_fallback = self.first_fallback or other.first_fallback

    def warn(self, stacklevel: int = 3, static_positions: np.ndarray | None = None) -> None:
        """Issue the summarising warnings; ``static_positions`` maps the static occluders the engines saw to their
        positions in the user's list (where the 2D height rule left some out; None: the same)."""
        if self.first_fallback is not None:
            frame, why = self.first_fallback
            warnings.warn(
                f"{self.fallback_frames} frame(s) computed with engine={FALLBACK_ENGINE!r} (exact too; the engines "
                f"agree within 1e-6) because the chosen engine could not compute them exactly; first frame {frame}: "
                f"{why}",
                VisibilityInputWarning,
                stacklevel=stacklevel,
            )
        if self.frames:
            warnings.warn(
                "objects containing the observer are treated as transparent (never occluders) and reported with "
                f"visibility 1.0: {_named(self.frames, self.first, 'idx')}",
                VisibilityInputWarning,
                stacklevel=stacklevel,
            )
        if self.static_frames:
            frames, first = self.static_frames, self.static_first
            if static_positions is not None:  # named as the table's static_occluder_idxs name them
                frames = Counter({(e, int(static_positions[s])): c for (e, s), c in frames.items()})
                first = {(e, int(static_positions[s])): f for (e, s), f in first.items()}
            warnings.warn(
                "static occluders containing the observer are treated as transparent (they hide nothing from it): "
                f"{_named(frames, first, 'static occluder')}",
                VisibilityInputWarning,
                stacklevel=stacklevel,
            )


def _count(frames: Counter, first: dict, ego: np.ndarray, holder: np.ndarray, frame: np.ndarray) -> None:
    """Count ``(ego, holder)`` pairs once per frame, keeping the first frame of each."""
    if not len(ego):
        return
    triples = np.unique(np.stack([ego, holder, frame]).astype(np.int64), axis=1)  # sorted: frames ascending
    keys, at, counts = np.unique(triples[:2], axis=1, return_index=True, return_counts=True)
    for (e, i), k, c in zip(keys.T.tolist(), at.tolist(), counts.tolist(), strict=True):
        frames[(e, i)] += c
        first.setdefault((e, i), int(triples[2, k]))


def _named(frames: Counter, first: dict, what: str) -> str:
    """The first :data:`SHOWN` pairs as words, and how many more."""
    parts = [
        f"{what} {i} contains observer {e} in {c} frame(s) (first frame {first[(e, i)]})"
        for (e, i), c in sorted(frames.items())[:SHOWN]
    ]
    more = len(frames) - SHOWN
    return "; ".join(parts) + (f"; and {more} more" if more > 0 else "")
