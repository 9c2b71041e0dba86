"""The part of the scene a picture shows: one rule for the frame plot, the animation and the report's scene.

The window is shaped by what lies within ``view_range`` metres of the ego (the centre of its bounding box): the
whole outline of every object that comes that near, and the map's lanes within that distance, in the frames drawn
(one frame for a picture, all of them for an animation or a report, so the scale stays put while the window
follows the ego). It bounds them tightly, so it is offset from the ego where the scene is (at the start of a road,
the road ahead fills the picture instead of an empty half behind the ego). A road running north-south gives a
tall window, a highway a wide one, a junction a square one. Then the shorter side is widened to the shape of the
picture, never cut: every object within ``view_range`` of the ego is on the picture, whichever way the road runs.

By default (:func:`default_reach`) the reach is :data:`DEFAULT_REACH`, a street's worth, or through sensors the
reach of those that look around.

No plotting library is imported here. Lengths in metres, in the recording's frame.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..inputs.objects import ObjectTable

MIN_SHARE = 0.3  # neither half side is shorter than this share of the view range
PAD = 3.0  # metres around the outermost outline
DEFAULT_REACH = 50.0
"""Metres around the ego a picture shows by default: the road users of a street or a junction, a few car lengths
ahead and behind on a highway, each large enough to read."""
AROUND = math.radians(90.0)
"""A sensor whose field of view is wider than this looks around (corner radars, a roof lidar), not far ahead."""
AUTO = "auto"
"""``view_range`` chosen by :func:`default_reach`."""


def default_reach(sensors: Sequence[Any] = ()) -> float:
    """The reach of a picture's window, metres: without sensors :data:`DEFAULT_REACH`; through sensors the
    longest finite range of those that look around (wider than :data:`AROUND`; a long-range radar's narrow
    beam would shrink everything near the ego), else of all of them.

    >>> from omega_prime_visibility.sensors import typical
    >>> default_reach(), default_reach(typical())
    (50.0, 80.0)
    """
    for chosen in ([s for s in sensors if s.fov > AROUND], list(sensors)):
        ranges = [s.range for s in chosen if math.isfinite(s.range)]
        if ranges:
            return float(max(ranges))
    return DEFAULT_REACH


@dataclass(frozen=True)
class Window:
    """Half the width (along x) and half the height (along y) of the view, and where its centre lies from the ego
    (``dx``, ``dy``), metres.

    >>> Window(10.0, 2.0).fitted(2.0)
    Window(half_width=10.0, half_height=5.0, dx=0.0, dy=0.0)
    >>> Window(10.0, 2.0, dx=4.0).around((100.0, 0.0))
    (94.0, 114.0, -2.0, 2.0)
    """

    half_width: float
    half_height: float
    dx: float = 0.0
    dy: float = 0.0

    def fitted(self, aspect: float) -> Window:
        """The window widened along its shorter side to ``aspect`` = width / height (never narrowed)."""
        if not np.isfinite(aspect) or aspect <= 0:
            return self
        if self.half_width / self.half_height < aspect:
            return Window(self.half_height * aspect, self.half_height, self.dx, self.dy)
        return Window(self.half_width, self.half_width / aspect, self.dx, self.dy)

    def around(self, ego) -> tuple[float, float, float, float]:
        """Limits ``(x0, x1, y0, y1)`` of this window around the ego at ``ego``."""
        x, y = float(ego[0]) + self.dx, float(ego[1]) + self.dy
        return (x - self.half_width, x + self.half_width, y - self.half_height, y + self.half_height)

    @property
    def aspect(self) -> float:
        """Width / height."""
        return self.half_width / self.half_height


def ego_rows(objects: ObjectTable, ego_idx: int, positions: np.ndarray) -> np.ndarray:
    """Row of the ego in each frame position of ``positions`` (-1 where it is absent)."""
    out = np.full(len(positions), -1, dtype=np.int64)
    for j, k in enumerate(np.asarray(positions).tolist()):
        s, e = objects.frame_starts[k], objects.frame_starts[k + 1]
        hit = np.flatnonzero(objects.idx[s:e] == ego_idx)
        if len(hit):
            out[j] = s + hit[0]
    return out


def near_offsets(objects: ObjectTable, ego_idx: int, positions: np.ndarray, view_range: float) -> np.ndarray:
    """Offsets from the ego's centre (metres, shape (m, 2)) of every outline vertex of each object that comes within
    ``view_range`` of it in the frames at ``positions``, the ego's own outline included.

    An object counts when its centre is nearer than ``view_range`` plus its farthest vertex from its centre (so
    every object whose outline reaches the disk counts, and a few that only come close to it)."""
    egos = ego_rows(objects, ego_idx, positions)
    found = [np.zeros((0, 2))]
    offsets = objects.rings.offsets
    for k, ego in zip(np.asarray(positions).tolist(), egos.tolist(), strict=True):
        if ego < 0:
            continue
        s, e = objects.frame_starts[k], objects.frame_starts[k + 1]
        coords = objects.rings.coords[offsets[s] : offsets[e]]
        row = np.repeat(np.arange(s, e), np.diff(offsets[s : e + 1]))
        centre = objects.position[ego]
        reach = np.zeros(e - s)
        np.maximum.at(reach, row - s, np.hypot(*(coords - objects.position[row]).T))
        near = np.hypot(*(objects.position[s:e] - centre).T) - reach <= view_range
        found.append(coords[near[row - s]] - centre)
    return np.concatenate(found)


def lane_offsets(points: np.ndarray, centres: np.ndarray, view_range: float) -> np.ndarray:
    """Offsets of the lane ``points`` within ``view_range`` of any of the ``centres`` (from that centre)."""
    if len(points) == 0 or len(centres) == 0:
        return np.zeros((0, 2))
    found = [np.zeros((0, 2))]
    for c in np.unique(np.round(centres, 1), axis=0):  # positions to 0.1 m: enough for a window
        d = points - c
        found.append(d[np.einsum("ij,ij->i", d, d) <= view_range * view_range])
    return np.concatenate(found)


def scene_window(
    objects: ObjectTable,
    ego_idx: int,
    positions: np.ndarray,
    view_range: float,
    lane_points: np.ndarray | None = None,
) -> Window:
    """The window (before fitting to the picture's shape) of the frames at ``positions`` seen from ``ego_idx``.

    Examples
    --------
    >>> import polars as pl
    >>> from ..inputs.scene import load_objects
    >>> street = load_objects(pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [0, 1],
    ...     "x": [0.0, 0.0], "y": [0.0, 47.0], "length": [4.0, 1.0], "width": [2.0, 1.0], "yaw": [1.57, 0.0]}))
    >>> w = scene_window(street, 0, np.array([0]), 60.0)
    >>> w.half_width, w.dx, round(w.half_height, 2), round(w.dy, 2)  # offset north, where the pedestrian is
    (18.0, 0.0, 27.75, 22.75)
    """
    if not (np.isfinite(view_range) and view_range > 0):
        raise ValueError(f"view_range must be a positive number of metres, not {view_range!r}")
    near = near_offsets(objects, ego_idx, positions, view_range)
    if lane_points is not None and len(lane_points):
        centres = objects.position[ego_rows(objects, ego_idx, positions)]
        near = np.concatenate([near, lane_offsets(lane_points, centres, view_range)])
    low = near.min(axis=0) - PAD if len(near) else np.zeros(2)
    high = near.max(axis=0) + PAD if len(near) else np.zeros(2)
    half, centre = (high - low) / 2, (high + low) / 2
    floor = MIN_SHARE * view_range
    return Window(max(float(half[0]), floor), max(float(half[1]), floor), float(centre[0]), float(centre[1]))


def path_limits(
    objects: ObjectTable, ego_idx: int, positions: np.ndarray, window: Window
) -> tuple[float, float, float, float]:
    """One view for all frames: the ego's path over ``positions`` with ``window`` around every point of it."""
    rows = ego_rows(objects, ego_idx, positions)
    path = objects.position[rows[rows >= 0]]
    shift = np.array([window.dx, window.dy])
    (x0, y0), (x1, y1) = path.min(axis=0) + shift, path.max(axis=0) + shift
    return x0 - window.half_width, x1 + window.half_width, y0 - window.half_height, y1 + window.half_height
