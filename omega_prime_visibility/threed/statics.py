"""Static occluders in 3D: 2D footprints raised to a height, and meshes from files, as triangles.

A footprint (any geometry :func:`.statics.load_static_occluders` accepts) becomes the vertical walls over its
outline: rings and wall lines are extruded from :data:`BASE` metres (below the ground z = 0) up to the occluder's
height above z = 0. No caps are needed: a ray that enters a closed prism from above leaves it through a wall
before it can reach anything beyond. A footprint without a height stands for something taller than anything on
the road (:data:`DEFAULT_HEIGHT`). Meshes (any file trimesh loads, or a ``trimesh.Trimesh``) are used as they are,
in the recording's coordinates.

>>> import shapely
>>> from omega_prime_visibility.inputs.statics import load_static_occluders
>>> wall = load_static_occluders([shapely.LineString([(0, 5), (10, 5)])])
>>> solids = static_solids(wall, heights=[2.0])
>>> solids.triangles.shape, float(solids.triangles[..., 2].max())
((2, 3, 3), 2.0)
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from ..geometry.rings import edges
from ..inputs.statics import StaticOccluders

DEFAULT_HEIGHT = 100.0
"""Metres: the height of a static occluder given without one (taller than anything on the road)."""
BASE = -1.0
"""Metres: where the walls of a footprint start (below the ground z = 0, so no ray slips under them)."""


@dataclass(frozen=True, slots=True)
class StaticSolids:
    """Triangles of all static occluders in 3D.

    Attributes
    ----------
    triangles : ndarray, shape (k, 3, 3), float64
        Metres, in the recording's frame.
    source : ndarray, shape (k,), int64
        Position of the static occluder each triangle belongs to (footprints first, then meshes).
    heights : ndarray, shape (n_footprints,)
        The height of each footprint, metres above z = 0 (z of its top).
    bases : ndarray, shape (n_footprints,)
        z of each footprint's bottom, metres.
    n_sources : int
        Footprints and meshes together.
    """

    triangles: np.ndarray
    source: np.ndarray
    heights: np.ndarray
    bases: np.ndarray
    n_sources: int


def _quads(segments: np.ndarray, base: np.ndarray, top: np.ndarray) -> np.ndarray:
    """Two triangles per vertical wall over each 2D segment (shape (s, 2, 2)) from ``base`` to ``top`` (shape (s,))."""
    a, b = segments[:, 0], segments[:, 1]
    low_a = np.column_stack([a, base])
    low_b = np.column_stack([b, base])
    high_a = np.column_stack([a, top])
    high_b = np.column_stack([b, top])
    first = np.stack([low_a, low_b, high_b], axis=1)
    second = np.stack([low_a, high_b, high_a], axis=1)
    return np.stack([first, second], axis=1).reshape(-1, 3, 3)


def check_heights(heights: Sequence[float] | float | None, n: int) -> np.ndarray:
    """One height per footprint (metres above z = 0, finite and > BASE); None gives :data:`DEFAULT_HEIGHT`."""
    if heights is None:
        return np.full(n, DEFAULT_HEIGHT)
    values = np.broadcast_to(np.asarray(heights, dtype=np.float64), (n,)) if np.ndim(heights) == 0 else heights
    values = np.asarray(values, dtype=np.float64)
    if values.shape != (n,):
        raise ValueError(f"static_occluder_heights gives {values.size} height(s) for {n} static occluder(s)")
    bad = np.flatnonzero(~np.isfinite(values) | (values <= BASE))
    if len(bad):
        raise ValueError(
            f"static occluder {int(bad[0])} has height {float(values[bad[0]])}: it must be a finite number > {BASE}"
        )
    return values


def load_mesh(mesh: Any) -> np.ndarray:
    """The triangles (shape (k, 3, 3), metres) of a mesh file trimesh loads, or of a ``trimesh.Trimesh``.

    Raises
    ------
    ValueError
        Naming the file, if it does not exist, does not load, or holds no triangles; for anything else given.
    """
    import trimesh

    if isinstance(mesh, trimesh.Trimesh):
        loaded, name = mesh, "the given trimesh.Trimesh"
    elif not isinstance(mesh, str | os.PathLike):
        raise ValueError(f"a static mesh must be a mesh file's path or a trimesh.Trimesh, not {type(mesh).__name__}")
    else:
        path = Path(os.fspath(mesh))
        name = str(path)
        if not path.is_file():
            raise ValueError(f"mesh file {name} does not exist")
        try:
            loaded = trimesh.load(path, force="mesh")
        except Exception as e:  # trimesh raises many kinds for files it cannot read
            raise ValueError(f"cannot load mesh file {name} with trimesh ({type(e).__name__}: {e})") from None
    triangles = np.asarray(getattr(loaded, "triangles", np.zeros((0, 3, 3))), dtype=np.float64).reshape(-1, 3, 3)
    if len(triangles) == 0:
        raise ValueError(f"mesh {name} holds no triangles")
    if not np.isfinite(triangles).all():
        raise ValueError(f"mesh {name} has NaN or infinite vertices")
    return triangles


def static_solids(
    statics: StaticOccluders,
    heights: Sequence[float] | float | None = None,
    meshes: Sequence[Any] = (),
    bases: Sequence[float] | None = None,
) -> StaticSolids:
    """The static occluders' footprints raised from ``bases`` (default :data:`BASE`) to ``heights`` (z of their
    tops, one per footprint or one for all), and ``meshes``.

    Mesh ``k`` is reported as static occluder ``statics.n_sources + k``.
    """
    heights = check_heights(heights, statics.n_sources)
    base = np.full(statics.n_sources, BASE) if bases is None else np.asarray(bases, dtype=np.float64)
    parts, sources = [], []
    if len(statics.rings):
        a, b = edges(statics.rings)
        ring_of_vertex = np.repeat(np.arange(len(statics.rings)), statics.rings.sizes)
        src = statics.ring_source[ring_of_vertex]
        parts.append(_quads(np.stack([a, b], axis=1), base[src], heights[src]))
        sources.append(np.repeat(src, 2))
    if len(statics.segments):
        src = statics.segment_source
        parts.append(_quads(np.asarray(statics.segments, dtype=np.float64), base[src], heights[src]))
        sources.append(np.repeat(src, 2))
    for k, mesh in enumerate(meshes):
        tri = load_mesh(mesh)
        parts.append(tri)
        sources.append(np.full(len(tri), statics.n_sources + k, dtype=np.int64))
    triangles = np.concatenate(parts) if parts else np.zeros((0, 3, 3))
    source = np.concatenate(sources).astype(np.int64) if sources else np.zeros(0, np.int64)
    return StaticSolids(triangles, source, heights, base, statics.n_sources + len(meshes))


def blocks_in_2d(height: float | np.ndarray, eye_height: float, rule_height: float | None = None) -> bool | np.ndarray:
    """The 2D height rule for static occluders: a footprint blocks the 2D view when it is at least as tall as the
    eye (``height >= eye_height``, metres above the ground), or ``rule_height`` when given. ``height`` may be an
    array (one answer per footprint); :func:`.mode.load_statics` applies the rule through this function.

    A 0.8 m railing does not hide a car from a driver's eye at 1.25 m; a 2 m noise barrier does, and so does one
    exactly at the eye.

    >>> blocks_in_2d(0.8, 1.25), blocks_in_2d(2.0, 1.25), blocks_in_2d(1.25, 1.25), blocks_in_2d(float("inf"), 1.25)
    (False, True, True, True)
    """
    return height >= (eye_height if rule_height is None else rule_height)
