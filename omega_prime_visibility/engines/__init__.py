"""Visibility engines: pure computations over one frame's arrays, no polars and no I/O.

Every engine has the same contract, so the front end never asks which one it runs:

- ``Engine(statics)`` is built once per recording from the validated :class:`~..scene.StaticOccluders`;
- ``engine.observe(objects, observer, transparent, static_transparent)`` returns an :class:`Observation`
  for one observer in one frame;
- ``engine.observe_many(objects, observers, transparent, static_transparent)`` does the same for several
  observers of the same frame (engines may share work between them).

A new engine is one module and one line in :data:`ENGINES`.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from ..scene import FrameObjects, StaticOccluders


@dataclass(frozen=True, slots=True)
class Observation:
    """What one observer sees of every object of a frame.

    Attributes
    ----------
    visible_angle : ndarray, shape (n,), float64
        Radians of directions along which the object is the first thing hit.
    angular_extent : ndarray, shape (n,), float64
        Radians of directions that hit the object at all.
    occluder_offsets : ndarray, shape (n + 1,), int64
        Object ``i``'s occluders are ``occluders[occluder_offsets[i]:occluder_offsets[i + 1]]``.
    occluders : ndarray, shape (k,), int64
        Positions (into the frame's object arrays) of objects hit before the target in some direction, ascending.
    static_offsets : ndarray, shape (n + 1,), int64
    static_occluders : ndarray, shape (k2,), int64
        Positions, in the user's static occluder list, of static occluders hit before the target, ascending.

    Entries for objects marked transparent are unspecified; the front end replaces them.
    """

    visible_angle: np.ndarray
    angular_extent: np.ndarray
    occluder_offsets: np.ndarray
    occluders: np.ndarray
    static_offsets: np.ndarray
    static_occluders: np.ndarray


class Engine(Protocol):
    name: str

    def __init__(self, statics: StaticOccluders) -> None: ...

    def observe(
        self,
        objects: FrameObjects,
        observer: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> Observation:
        """One observer (shape (2,), metres); ``transparent`` (n,) and ``static_transparent`` (n_sources,) masks
        mark bodies that neither block nor occlude (the ego itself and bodies containing the observer)."""
        ...

    def observe_many(
        self,
        objects: FrameObjects,
        observers: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> list[Observation]:
        """Several observers (k, 2) of the same frame, masks of shape (k, n) and (k, n_sources)."""
        ...


class EngineBase:
    """Default :meth:`observe_many`: one :meth:`observe` per observer."""

    def observe_many(
        self,
        objects: FrameObjects,
        observers: np.ndarray,
        transparent: np.ndarray,
        static_transparent: np.ndarray,
    ) -> list[Observation]:
        return [
            self.observe(objects, observers[k], transparent[k], static_transparent[k])  # type: ignore[attr-defined]
            for k in range(len(observers))
        ]


def _visilibity() -> type:
    from .visilibity import VisiLibityEngine

    return VisiLibityEngine


def _sweep() -> type:
    from .sweep import SweepEngine

    return SweepEngine


ENGINES: dict[str, Callable[[], type]] = {"visilibity": _visilibity, "sweep": _sweep}


def get_engine(name: str) -> type:
    """The engine class registered under ``name``."""
    try:
        return ENGINES[name]()
    except KeyError:
        raise ValueError(f"unknown engine {name!r}; available: {sorted(ENGINES)}") from None


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
