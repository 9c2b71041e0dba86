"""The front ends' 3D mode in one place: which engine, which static occluders (heights, meshes, map objects),
and the ``can_see`` column.

``mode="3d"`` computes, per (frame, target), the solid-angle fraction of the target's directions along which it
is hit first, within range and inside the view, from the ego's eye (its centre at :data:`DRIVER_EYE_HEIGHT` above
the ground under it, ``z - height / 2``), plus ``can_see`` (Scenic's yes/no: some such direction exists).
Static occluders get heights (``static_occluder_heights``: z of their tops; none: :data:`.statics.DEFAULT_HEIGHT`),
meshes (``static_meshes``: files trimesh loads) and an OpenDRIVE map's road objects (``map_occluders``). In 2D,
footprints with a height below the eye (:func:`.statics.blocks_in_2d`) are left out; the table still numbers
static occluders by their position in the full list (the user's, then the map's, then the meshes).
"""

from __future__ import annotations

import os
import warnings
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any, Literal

import numpy as np
import polars as pl
import shapely

from ..inputs.errors import OptionError, Setting
from ..inputs.objects import VisibilityInputWarning
from ..inputs.sensors import DRIVER_EYE_HEIGHT
from ..inputs.statics import StaticOccluders, load_static_occluders
from .statics import blocks_in_2d, check_heights, static_solids

Mode = Literal["2d", "3d"]
"""Bird's-eye view or boxes with heights."""


def load_statics(
    polys: Sequence[Any] | Any | None,
    mode: Mode,
    heights: Sequence[float] | float | None = None,
    meshes: Sequence[Any] = (),
    map_path: str | os.PathLike | bool | None = None,
    recording: Any = None,
) -> tuple[StaticOccluders, np.ndarray | None]:
    """Static occluders for ``mode``, and (2D only, when some were left out by the height rule) the position in
    the full list of each static occluder the engines see. ``map_path`` True: the OpenDRIVE map of
    ``recording`` (an ``omega_prime.Recording``)."""
    from .mapobjects import read_map_objects

    user = [] if polys is None else [polys] if isinstance(polys, shapely.Geometry) else list(polys)
    n_user = len(user)
    tops = check_heights(heights, n_user)
    bases = np.full(n_user, np.nan)
    above_road = tops.copy()
    map_objects = [] if map_path is None else read_map_objects(*map_source(map_path, recording))
    geoms = user + [m.footprint for m in map_objects]
    tops = np.concatenate([tops, [m.top for m in map_objects]])
    bases = np.concatenate([bases, [m.base for m in map_objects]])
    above_road = np.concatenate([above_road, [m.height_above_road for m in map_objects]])
    meshes = list(meshes or ())
    if map_path is not None:
        _tell_map_objects(map_path, map_objects, mode, above_road[n_user:])
    if mode == "2d":
        if meshes:
            raise ValueError("static_meshes are 3D occluders: pass mode='3d'")
        keep = np.flatnonzero(blocks_in_2d(above_road, DRIVER_EYE_HEIGHT))
        statics = load_static_occluders([geoms[k] for k in keep])
        return statics, (keep if len(keep) < len(geoms) else None)
    statics = load_static_occluders(geoms)
    solids = static_solids(statics, tops, meshes, np.where(np.isnan(bases), -1.0, bases))
    return replace(statics, solids=solids), None


def _tell_map_objects(map_path: Any, map_objects: list, mode: Mode, above_road: np.ndarray) -> None:
    """One warning when the map's road objects add no static occluder: the map holds none, or (2D) none reaches
    the driver's eye height."""
    name = "the recording's map" if map_path is True else f"the map {os.fspath(map_path)}"
    if not map_objects:
        warnings.warn(
            f"map_occluders: {name} holds no road object with an extent and a height (<object> with an outline, "
            "length and width, or radius, and a height), so it adds no static occluder",
            VisibilityInputWarning,
            stacklevel=4,
        )
    elif mode == "2d" and not blocks_in_2d(above_road, DRIVER_EYE_HEIGHT).any():
        warnings.warn(
            f"map_occluders: none of the {len(map_objects)} road objects of {name} reaches the driver's eye "
            f"({DRIVER_EYE_HEIGHT:g} m above the road; the highest reaches {np.max(above_road):.2f} m), so in 2D "
            "none blocks the view (mode='3d' sees over and under them)",
            VisibilityInputWarning,
            stacklevel=4,
        )


def map_source(map_path: str | os.PathLike | bool, recording: Any) -> tuple[str | os.PathLike, str | None]:
    """``(path, xml)`` for :func:`.mapobjects.read_map_objects`: a file, or (``True``) the recording's own map."""
    if map_path is True:
        xml = getattr(getattr(recording, "map", None), "odr_xml", None)
        if not isinstance(xml, str):
            raise OptionError(
                "map_occluders",
                "{given} needs a recording that carries an OpenDRIVE map; give one as {path}",
                given=Setting("map_occluders", True),
                path=Setting("map_occluders", "FILE.xodr"),
            )
        return "the recording's OpenDRIVE map", xml
    if map_path is False:
        raise OptionError.plain("map_occluders", "map_occluders must be a path, True (the recording's map) or None")
    return map_path, None


@dataclass(frozen=True)
class Finisher:
    """What the 3D mode and the 2D height rule add to the engines' columns, where a chunk ran: static occluder
    positions in the full list (``positions``: the full position of each static the engines saw, None: same) and
    the ``can_see`` column (``three_d``). Called like a sink, it passes the columns on to ``inner``."""

    positions: np.ndarray | None
    three_d: bool
    inner: Callable[[int, Any], Any] | None = None

    def columns(self, columns: dict | None) -> dict | None:
        if columns is None:
            return None
        out = dict(columns)
        if self.positions is not None:
            lengths, values = out["static_occluder_idxs"]
            out["static_occluder_idxs"] = (lengths, self.positions[values])
        if self.three_d:
            out["can_see"] = np.asarray(out["visibility"]) > 0.0
        return out

    def __call__(self, k: int, columns: dict | None) -> Any:
        return self.inner(k, self.columns(columns))  # type: ignore[misc]

    def write_empty(self) -> None:
        self.inner.write_empty()  # type: ignore[union-attr]


def with_can_see(table: pl.DataFrame, mode: Mode) -> pl.DataFrame:
    """In 3D, the ``can_see`` column (bool: some direction sees the target, ``visibility > 0``) after
    ``visibility``; in 2D the table as it is."""
    if mode != "3d":
        return table
    return table.with_columns(can_see=pl.col("visibility") > 0.0)
