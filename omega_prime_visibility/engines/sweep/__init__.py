"""An exact angular-sweep engine in numba: visible angles in O(N log N) per observer, no polygon clipping.

Per frame (shared by all observers of the frame), on the unshifted coordinates (:mod:`.crossings`):

- the pairs of edges of *different* bodies that cross properly (objects against objects by sort-and-sweep of
  their bounding boxes along the axis of larger spread, objects against static edges through a uniform grid
  built once per recording; static against static crossings are found once, in the constructor).

Per observer, with everything shifted so that the observer sits at the origin (:mod:`.observe`):

1. *Front-facing edges* (:mod:`.pieces`): the edges facing the observer, oriented counter-clockwise; edges of
   transparent bodies and static edges beyond the farthest target are dropped.
2. *Pieces* (:mod:`.pieces`): each kept edge's bearing interval cut at the -pi/pi direction and where it crosses
   an edge of another body, so that any two pieces sharing directions keep their depth order over all of them.
3. *Sweep* (:mod:`.heap_sweep`): start and end events sorted by bearing, the active pieces in an indexed binary
   heap; between two consecutive event bearings the heap's top is the nearest piece and the interval's angle is
   credited to its body.
4. *Occluders* (:mod:`.occluders`): candidates from overlapping bearing intervals, accepted at once when clearly
   in front, otherwise decided (:mod:`.decide`) by the exact pairwise test of :mod:`...occlusion`.

Modules: :mod:`.engine` (the :class:`SweepEngine` class), :mod:`.crossings`, :mod:`.observe`, :mod:`.pieces`,
:mod:`.heap_sweep`, :mod:`.occluders`, :mod:`.decide`; shared numba helpers are in
:mod:`omega_prime_visibility.geometry.kernels`.
"""

from __future__ import annotations

from .engine import SweepEngine

__all__ = ["SweepEngine"]
