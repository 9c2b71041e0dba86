"""Which engines there are and which one a question takes: the registries (names to engine classes, loaded on
first use), each mode's default, the area measure's own engine. Engines never import this module (as polars keeps
its engine configuration apart from the engines); a new engine is one module and one line here.
"""

from __future__ import annotations

from collections.abc import Callable

from ..inputs.errors import OptionError, Setting
from ..threed.mode import Mode
from . import Engine


def _visilibity() -> type:
    from .visilibity import VisiLibityEngine

    return VisiLibityEngine


def _sweep() -> type:
    from .sweep import SweepEngine

    return SweepEngine


ENGINES: dict[str, Callable[[], type]] = {"visilibity": _visilibity, "sweep": _sweep}


def _raycast3d(setting: str) -> Callable[[], type]:
    def load() -> type:
        from .raycast3d import FastRaycastEngine, HighRaycastEngine, RaycastEngine

        return {"default": RaycastEngine, "high": HighRaycastEngine, "fast": FastRaycastEngine}[setting]

    return load


def _silhouette3d() -> type:
    from .silhouette3d import SilhouetteEngine

    return SilhouetteEngine


ENGINES_3D: dict[str, Callable[[], type]] = {
    "raycast3d": _raycast3d("default"),
    "raycast3d-high": _raycast3d("high"),
    "raycast3d-fast": _raycast3d("fast"),
    "silhouette3d": _silhouette3d,
}
"""The 3D engines (``mode="3d"``): Embree ray casting at three settings, and the exact box engine."""


def _area() -> type:
    from .area import AreaEngine

    return AreaEngine


ENGINES_AREA: dict[str, Callable[[], type]] = {"area": _area}
"""The engine of the area measure (``measure="area"``): exact polygon clipping of footprints and shadows."""


ENGINE_TITLES = {
    "visilibity": "VisiLibity",
    "sweep": "sweep",
    "raycast3d": "3D ray casting",
    "raycast3d-high": "3D ray casting (high)",
    "raycast3d-fast": "3D ray casting (fast)",
    "silhouette3d": "3D silhouettes",
    "area": "area",
}
"""How pictures and pages name each engine (``engine=`` takes the keys)."""


def get_engine(name: str) -> type[Engine]:
    """The engine class registered under ``name`` (2D, 3D or the area measure's)."""
    try:
        return {**ENGINES, **ENGINES_3D, **ENGINES_AREA}[name]()
    except KeyError:
        known = f"available: {', '.join(sorted(ENGINES))} (3D: {', '.join(sorted(ENGINES_3D))})"
        raise OptionError.plain("engine", f"unknown engine {name!r}; {known}") from None


DEFAULT_ENGINES = {"2d": "visilibity", "3d": "silhouette3d"}
"""Each mode's default engine; in 3D the exact engine, or the ray engine when meshes are given (:data:`MESH_ENGINE`)."""
MESH_ENGINE = "raycast3d"
"""The 3D default where static meshes are given: meshes are not convex prisms, so they are ray-cast."""


def check_mode(mode: str) -> Mode:
    """``mode`` if it is "2d" or "3d" (any case), else a ValueError."""
    m = str(mode).lower()
    if m not in DEFAULT_ENGINES:
        raise OptionError.plain("mode", f"mode must be '2d' or '3d', not {mode!r}")
    return m  # type: ignore[return-value]


def resolve_engine(engine: str | None, mode: Mode, meshes: bool = False) -> str:
    """The engine for ``mode``: the given name (checked against that mode's registry) or the mode's default
    (in 3D with static meshes, :data:`MESH_ENGINE`)."""
    if engine is None:
        return MESH_ENGINE if meshes and mode == "3d" else DEFAULT_ENGINES[mode]
    names = ENGINES_3D if mode == "3d" else ENGINES
    if engine not in names:
        other = "3d" if mode == "2d" else "2d"
        hint = f" ({engine!r} is a {other} engine: pass {{other}})" if engine in {**ENGINES, **ENGINES_3D} else ""
        raise OptionError(
            "engine",
            f"unknown engine {engine!r} for {{mode}}; available: {', '.join(sorted(names))}{hint}",
            mode=Setting("mode", mode),
            other=Setting("mode", other),
        )
    return engine


MEASURES = ("angle", "area")
"""What ``visibility`` measures: the share of the target's angular extent (``"angle"``, the default) or of its
footprint's area (``"area"``, 2D only, :mod:`..engines.area`)."""


AREA_SETTINGS = {
    "area": Setting("measure", "area"),
    "angle": Setting("measure", "angle"),
    "two_d": Setting("mode", "2d"),
    "engine": Setting("engine"),
}


def resolve_measure(measure: str, engine: str | None, mode: Mode, meshes: bool = False) -> str:
    """The engine for ``measure`` (and ``engine``, ``mode``): the area measure has its own engine, ``"area"``.

    Raises
    ------
    ValueError
        An unknown measure, the area measure in 3D or with another engine, or an unknown engine.
    """
    if measure not in MEASURES:
        raise OptionError.plain("measure", f"unknown measure {measure!r}; use 'angle' (the default) or 'area'")
    if measure == "angle":
        return resolve_engine(engine, mode, meshes)
    if mode == "3d":
        raise OptionError(
            "measure", "{area} measures footprints in 2D; use {two_d} (or {angle} in 3D)", **AREA_SETTINGS
        )
    if engine not in (None, "area"):
        raise OptionError(
            "measure",
            f"{{area}} has its own exact engine (polygon clipping); leave {{engine}} unset, not {engine!r}",
            **AREA_SETTINGS,
        )
    return "area"
