"""Exact visibility and occlusion of road users in omega-prime traffic recordings.

>>> from omega_prime_visibility import get_visibility_df

Importing the package is quick: each public name loads its module (and polars, numba, omega-prime or the
plotting libraries it needs) when it is first used.
"""

import sys
from collections.abc import Callable
from importlib import import_module
from typing import Any

from . import _compiled  # noqa: F401 (first: the kernels' cache follows the sources, see _compiled)

_WHERE = {
    "ENGINES": "engines.registry",
    "ENGINES_3D": "engines.registry",
    "Observation": "engines",
    "Reason": "engines",
    "Viewpoint": "engines",
    "OptionError": "query",
    "Query": "query",
    "SCHEMA": "table.schema",
    "Sensor": "inputs.sensors",
    "VisibilityInputWarning": "inputs.objects",
    "camera": "inputs.sensors",
    "camera_visibility": "analysis.levels",
    "campaign_statistics": "batch.campaign",
    "get_visibility_df": "api",
    "kitti_levels": "analysis.levels",
    "lidar": "inputs.sensors",
    "lidar_levels": "analysis.levels",
    "get_visibility_df_for_frame": "api",
    "occluded_conflicts": "analysis.conflicts",
    "occlusion_statistics": "analysis.statistics",
    "read_recording": "inputs.io",
    "run_batch": "batch",
    "seen_by_any": "analysis.combine",
    "target_summary": "analysis.summary",
    "visible_intervals": "analysis.intervals",
    "write_csv": "table.output",
    "write_kitti": "export.kitti",
    "write_mcap": "export.mcap",
    # the Metric imports omega-prime, which takes seconds
    "metrics": "metric",
    "occluded_conflicts_metric": "metric",
    "visibility": "metric",
    # the pictures need matplotlib/altair (the 'plot' extra)
    "animate": "plot",
    "plot_camera": "plot",
    "plot_frame": "plot",
    "save_timeline": "plot",
    "timeline_chart": "plot",
    "write_report": "plot",
    # the visible area builds on the sweep engine's kernels
    "visible_area": "analysis.area",
    "visible_area_over_time": "analysis.area",
}
"""Where each public name lives (loaded on first use, PEP 562)."""

__all__ = sorted(_WHERE)


def _lazy_names(package: str, where: dict[str, str]) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """A package's ``__getattr__`` and ``__dir__`` (PEP 562) that load each name of ``where`` (name -> module,
    relative to ``package``) on first use, then keep it as a plain attribute; the package, ``batch`` and ``plot``
    share them.

    >>> getattr_, dir_ = _lazy_names("json", {"JSONEncoder": "encoder"})
    >>> getattr_("JSONEncoder").__module__, "JSONEncoder" in dir_()
    ('json.encoder', True)
    """

    def __getattr__(name: str) -> Any:
        if name in where:
            value = getattr(import_module(f".{where[name]}", package), name)
            setattr(sys.modules[package], name, value)  # once loaded, a plain attribute
            return value
        raise AttributeError(f"module {package!r} has no attribute {name!r}")

    def __dir__() -> list[str]:
        return sorted({*vars(sys.modules[package]), *where})

    return __getattr__, __dir__


_getattr, _dir = _lazy_names(__name__, _WHERE)


def __getattr__(name: str) -> Any:
    """The public names of :data:`_WHERE`, and ``__version__`` (read when first asked: importlib.metadata is two
    thirds of the package's import)."""
    if name == "__version__":
        from importlib.metadata import PackageNotFoundError, version

        try:
            value = version("omega-prime-visibility")
        except PackageNotFoundError:  # (the sources used without installing them)
            value = "0+unknown"
        globals()["__version__"] = value
        return value
    return _getattr(name)


def __dir__() -> list[str]:
    return sorted({*_dir(), "__version__"})
