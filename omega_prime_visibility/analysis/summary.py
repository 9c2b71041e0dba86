"""One row per target: how much of the time it was seen, and by whom it was hidden (what ``run`` prints)."""

from __future__ import annotations

import polars as pl

from ..table.schema import STATUSES
from .combine import every_listed

OUT_OF_VIEW = ("out_of_fov", "out_of_range")
assert set(OUT_OF_VIEW) <= set(STATUSES)


def target_summary(table: pl.DataFrame) -> pl.DataFrame:
    """Per target (and observer and sensor, where the table has them), over its frames.

    Parameters
    ----------
    table
        A visibility table (``get_visibility_df``'s, with or without ``idx_ego``/``sensor``, or ``seen_by_any``'s).

    Returns
    -------
    polars.DataFrame
        ``[idx_ego,] idx, [sensor,] frames, mean_visibility, min_visibility, hidden_share, partly_hidden_share,
        [out_of_view_share,] occluders, static_occluders``, sorted by the keys. ``hidden_share`` is the share of the
        target's frames in which nothing of it is seen *because something is in front of it*; where the table has
        the sensors' ``status``, frames in which the target is outside every direction the sensor looks
        (``out_of_fov``, ``out_of_range``) are counted apart in ``out_of_view_share``, never as hidden.
        ``partly_hidden_share``: frames with visibility strictly between 0 and 1. ``occluders``: every object idx
        that hid some of it in some frame, ascending (``static_occluders`` the same by static occluder position).

    Examples
    --------
    >>> import polars as pl
    >>> t = pl.DataFrame({"frame": [0, 1, 2, 3], "idx": [7, 7, 7, 7], "visibility": [1.0, 0.5, 0.0, 0.0],
    ...                   "occluder_idxs": [[], [3], [3, 4], [4]], "static_occluder_idxs": [[], [], [], [0]]})
    >>> target_summary(t).row(0)
    (7, 4, 0.375, 0.0, 0.5, 0.25, [3, 4], [0])
    """
    missing = [c for c in ("idx", "visibility", "occluder_idxs") if c not in table.columns]
    if missing:
        raise ValueError(f"a visibility table needs the columns {missing}; it has {table.columns}")
    by = [c for c in ("idx_ego", "idx", "sensor") if c in table.columns]
    aggregations = [
        pl.len().alias("frames"),
        pl.col("visibility").mean().alias("mean_visibility"),
        pl.col("visibility").min().alias("min_visibility"),
    ]
    if "status" in table.columns:
        status = pl.col("status").cast(pl.String)
        aggregations += [
            (status == "occluded").mean().alias("hidden_share"),
            (status == "partly_visible").mean().alias("partly_hidden_share"),
            status.is_in(OUT_OF_VIEW).mean().alias("out_of_view_share"),
        ]
    else:
        visibility = pl.col("visibility")
        aggregations += [
            (visibility == 0.0).mean().alias("hidden_share"),
            ((visibility > 0.0) & (visibility < 1.0)).mean().alias("partly_hidden_share"),
        ]
    for column, name in (("occluder_idxs", "occluders"), ("static_occluder_idxs", "static_occluders")):
        if column in table.columns:
            aggregations.append(every_listed(column).alias(name))
    return table.group_by(by).agg(aggregations).sort(by)
