"""Exact visibility and occlusion of road users in omega-prime traffic recordings.

>>> from omega_prime_visibility import get_visibility_df
"""

from importlib.metadata import PackageNotFoundError
from importlib.metadata import version as _version

from . import _compiled  # noqa: F401 (first: the kernels' cache follows the sources, see _compiled)
from .analysis.combine import seen_by_any
from .analysis.conflicts import occluded_conflicts
from .analysis.intervals import visible_intervals
from .analysis.statistics import occlusion_statistics
from .analysis.summary import target_summary
from .api import get_visibility_df, get_visibility_df_for_frame
from .batch import run_batch
from .batch.campaign import campaign_statistics
from .engines import ENGINES, ENGINES_3D, Observation, Reason, Viewpoint
from .inputs.objects import VisibilityInputWarning
from .inputs.sensors import Sensor
from .query import OptionError, Query
from .table.output import write_csv
from .table.schema import SCHEMA

try:
    __version__ = _version("omega-prime-visibility")
except PackageNotFoundError:  # (the sources used without installing them)
    __version__ = "0+unknown"

__all__ = [
    "ENGINES",
    "ENGINES_3D",
    "SCHEMA",
    "Observation",
    "OptionError",
    "Query",
    "Reason",
    "Sensor",
    "Viewpoint",
    "VisibilityInputWarning",
    "animate",
    "campaign_statistics",
    "get_visibility_df",
    "get_visibility_df_for_frame",
    "metrics",
    "occluded_conflicts",
    "occluded_conflicts_metric",
    "occlusion_statistics",
    "plot_frame",
    "run_batch",
    "save_timeline",
    "seen_by_any",
    "target_summary",
    "timeline_chart",
    "visibility",
    "visible_area",
    "visible_area_over_time",
    "visible_intervals",
    "write_csv",
    "write_report",
]

PLOTTING = ("animate", "plot_frame", "save_timeline", "timeline_chart", "write_report")


def __getattr__(name: str):
    # the Metric imports omega-prime, which takes seconds: load it only when asked for
    if name in ("visibility", "occluded_conflicts_metric", "metrics"):
        from . import metric

        return getattr(metric, name)
    # the pictures need matplotlib/altair (the 'plot' extra): load them only when asked for
    if name in PLOTTING:
        from . import plot

        return getattr(plot, name)
    # the visible area builds on the sweep engine's kernels: load them only when asked for
    if name in ("visible_area", "visible_area_over_time"):
        from .analysis import area

        return getattr(area, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
