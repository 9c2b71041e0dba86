"""One row per target: how much of the time it was seen, and by whom it was hidden (what ``run`` prints)."""

from __future__ import annotations

import polars as pl

from .classes import EXACT, class_shares, describe
from .combine import every_listed


def target_summary(table: pl.DataFrame, *, partly: tuple[float, float] = EXACT) -> pl.DataFrame:
    """Per target (and observer and sensor, where the table has them), over its frames.

    Parameters
    ----------
    table
        A visibility table (``get_visibility_df``'s, with or without ``idx_ego``/``sensor``, or ``seen_by_any``'s).
    partly : (float, float)
        The bounds of *partly hidden* on the seen share of the part in view (:mod:`~.classes`); by default
        ``(0, 1)``: hidden when nothing of it is seen, visible when all of it is.

    Returns
    -------
    polars.DataFrame
        ``[idx_ego,] idx, [sensor,] frames, mean_visibility, min_visibility, visible_share, partly_hidden_share,
        hidden_share, [out_of_view_share, partly_out_of_view_share,] occluders, static_occluders``, sorted by the
        keys. The shares are of the target's frames, by the one definition of :mod:`~.classes`: *hidden* and *partly
        hidden* mean that something is in front of it; where the table has the sensors' ``in_view``, frames in
        which no part of the target is in view are counted apart in ``out_of_view_share``, and frames in which part
        of it lies outside the view in ``partly_out_of_view_share`` (such a frame is *visible* when nothing hides
        the rest). ``occluders``: every object idx that hid some of it in some frame, ascending
        (``static_occluders`` the same by the static occluder's position in the list given).

    Examples
    --------
    >>> import polars as pl
    >>> t = pl.DataFrame({"frame": [0, 1, 2, 3], "idx": [7, 7, 7, 7], "visibility": [1.0, 0.5, 0.0, 0.0],
    ...                   "occluder_idxs": [[], [3], [3, 4], [4]], "static_occluder_idxs": [[], [], [], [0]]})
    >>> target_summary(t).row(0)
    (7, 4, 0.375, 0.0, 0.25, 0.25, 0.5, [3, 4], [0])
    """
    missing = [c for c in ("idx", "visibility", "occluder_idxs") if c not in table.columns]
    if missing:
        raise ValueError(f"a visibility table needs the columns {missing}; it has {table.columns}")
    by = [c for c in ("idx_ego", "idx", "sensor") if c in table.columns]
    shares = class_shares(table.columns, partly)
    aggregations = [
        pl.len().cast(pl.Int64).alias("frames"),
        pl.col("visibility").mean().alias("mean_visibility"),
        pl.col("visibility").min().alias("min_visibility"),
        shares["visible"].alias("visible_share"),
        shares["partly_hidden"].alias("partly_hidden_share"),
        shares["hidden"].alias("hidden_share"),
    ]
    if "in_view" in table.columns:
        aggregations += [
            shares["out_of_view"].alias("out_of_view_share"),
            shares["partly_out_of_view"].alias("partly_out_of_view_share"),
        ]
    for column, name in (("occluder_idxs", "occluders"), ("static_occluder_idxs", "static_occluders")):
        if column in table.columns:
            aggregations.append(every_listed(column).alias(name))
    return table.group_by(by).agg(aggregations).sort(by)


DEFINITION = describe()
"""The default definition in words (what ``run`` prints under the summary)."""
