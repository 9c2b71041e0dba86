"""Exact visibility and occlusion of road users in omega-prime traffic recordings.

>>> from omega_prime_visibility import get_visibility_df
"""

from .api import get_visibility_df, get_visibility_df_for_frame
from .batch import run_batch
from .combine import seen_by_any
from .engines import ENGINES, Observation, Reason, Viewpoint
from .intervals import visible_intervals
from .scene import VisibilityInputWarning
from .sensors import Sensor
from .table import SCHEMA

__all__ = [
    "ENGINES",
    "SCHEMA",
    "Observation",
    "Reason",
    "Sensor",
    "Viewpoint",
    "VisibilityInputWarning",
    "get_visibility_df",
    "get_visibility_df_for_frame",
    "metrics",
    "run_batch",
    "seen_by_any",
    "visibility",
    "visible_intervals",
]


def __getattr__(name: str):
    # the Metric imports omega-prime, which takes seconds: load it only when asked for
    if name in ("visibility", "metrics"):
        from . import metric

        return getattr(metric, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
