"""How often and how badly road users are occluded, near and far, and by whom: statistics over a visibility table
(a recording, or a campaign's tables concatenated), as dataset realism checks compare them between datasets.

Each (frame, target) row is *visible*, *partly* hidden, *hidden* or *out of view* by the one definition of
:mod:`~.classes` (by default exact: hidden when nothing of it is seen, visible when all of it in view is; other
bounds with ``partly=``); its distance is between the observer's and the target's
bounding-box centres (metres) in that frame, banded by ``bands`` (default ``< 20 m``, ``20 to 50 m`` and
``>= 50 m``; a band holds its lower bound).
"""

from __future__ import annotations

import math

import polars as pl

from .classes import EXACT, check_partly
from .classes import class_shares as _shares
from .combine import polars_table

TYPE_NAMES = {0: "unknown", 1: "other", 2: "vehicle", 3: "pedestrian", 4: "animal"}
"""omega-prime's (OSI's) ``type`` of a moving object, by value."""


def occlusion_statistics(
    visibility: pl.DataFrame | pl.LazyFrame,
    objects: pl.DataFrame | pl.LazyFrame,
    *,
    ego_idx: int | None = None,
    bands: tuple[float, ...] = (20.0, 50.0),
    partly: tuple[float, float] = EXACT,
    bins: int = 10,
) -> dict[str, pl.DataFrame]:
    """Shares of visible, partly occluded and hidden rows by distance band and target type; the visibility
    histogram; the types of the objects that occlude.

    Parameters
    ----------
    visibility : polars.DataFrame or LazyFrame
        A visibility table (``frame, total_nanos, [idx_ego,] idx, visibility, occluder_idxs``); through sensors,
        combine them first (:func:`~.combine.seen_by_any`).
    objects : polars.DataFrame or LazyFrame
        The recording's moving-object table: ``total_nanos, idx, x, y, type`` (omega-prime's).
    ego_idx : int, optional
        The observer, when ``visibility`` has no ``idx_ego`` column.
    bands : tuple of float
        Ascending distance bounds, metres.
    partly : (float, float)
        Bounds of *partly hidden* on the seen share of the part in view (:mod:`~.classes`): at or below the first
        is hidden, at or above the second visible; default ``(0, 1)``.
    bins : int
        Bins of the histogram over [0, 1].

    Returns
    -------
    dict of polars.DataFrame
        ``"by_band"``: ``band, target_type, rows, visible, partly, hidden, out_of_view`` (shares of the band's rows,
        per type and ``"all"``; ``out_of_view`` is 0 for a table without the sensors' ``in_view``);
        ``"histogram"``: ``bin_start, bin_end, rows, share``; ``"occluder_types"``: ``occluder_type, rows, occluders``
        (``rows``: the rows in which at least one object of that type occludes the target, each row counted once
        per type; ``occluders``: the occluding objects of that type summed over the rows, so a row hidden by two
        cars counts 1 and 2), most rows first.

    Examples
    --------
    >>> objects = pl.DataFrame({"total_nanos": [0, 0, 0], "idx": [0, 1, 2], "x": [0.0, 10.0, 60.0],
    ...     "y": [0.0, 0.0, 0.0], "type": [2, 2, 3]})
    >>> table = pl.DataFrame({"frame": [0, 0], "total_nanos": [0, 0], "idx": [1, 2], "visibility": [1.0, 0.0],
    ...     "occluder_idxs": [[], [1]]})
    >>> stats = occlusion_statistics(table, objects, ego_idx=0)
    >>> stats["by_band"].filter(pl.col("target_type") == "all").select("band", "rows", "visible", "hidden").rows()
    [('< 20 m', 1, 1.0, 0.0), ('>= 50 m', 1, 0.0, 1.0)]
    >>> stats["occluder_types"].rows()
    [('vehicle', 1, 1)]
    """
    _checked(bands, partly, bins)
    rows = rows_with_distance(polars_table(visibility, "visibility"), polars_table(objects, "objects"), ego_idx)
    return statistics_of_rows(rows, bands=bands, partly=partly, bins=bins)


def statistics_of_rows(
    rows: pl.LazyFrame, *, bands: tuple[float, ...] = (20.0, 50.0), partly=EXACT, bins: int = 10
) -> dict[str, pl.DataFrame]:
    """:func:`occlusion_statistics` of rows that already have ``distance`` and ``target_type`` (from
    :func:`rows_with_distance`, e.g. several recordings' rows concatenated)."""
    low, high = _checked(bands, partly, bins)
    labels = _band_labels(bands)
    band = pl.col("distance").cut(list(bands), labels=labels, left_closed=True)
    shares = class_shares(rows.collect_schema().names(), (low, high))
    v = pl.col("visibility")
    banded = rows.with_columns(band=band.cast(pl.String))
    by_type = banded.group_by("band", "target_type").agg(shares)
    overall = banded.group_by("band").agg(shares).with_columns(target_type=pl.lit("all"))
    order = pl.col("band").replace_strict({label: k for k, label in enumerate(labels)}, return_dtype=pl.Int32)
    by_band = pl.concat([by_type, overall.select(by_type.collect_schema().names())]).sort(
        order, pl.col("target_type") != "all", "target_type"
    )
    edges = [k / bins for k in range(bins + 1)]
    binned = rows.select(bin=(v * bins).floor().clip(0, bins - 1).cast(pl.Int64)).group_by("bin").agg(rows=pl.len())
    histogram = (
        pl.LazyFrame({"bin": list(range(bins))})
        .join(binned, on="bin", how="left")
        .with_columns(pl.col("rows").fill_null(0).cast(pl.Int64))  # (a UInt32 sum would wrap beyond 2^32 rows)
        .with_columns(
            bin_start=pl.col("bin").replace_strict(dict(enumerate(edges[:-1])), return_dtype=pl.Float64),
            bin_end=pl.col("bin").replace_strict(dict(enumerate(edges[1:])), return_dtype=pl.Float64),
            share=pl.col("rows") / pl.max_horizontal(pl.col("rows").sum(), 1),  # an empty table: shares 0
        )
        .select("bin_start", "bin_end", "rows", "share")
    )
    occluder_types = (
        _counted(rows, pl.col("occluder_types").list.unique(), "rows")
        .join(_counted(rows, pl.col("occluder_types"), "occluders"), on="occluder_type", how="left")
        .sort("rows", "occluders", "occluder_type", descending=[True, True, False])
    )
    return {
        "by_band": by_band.collect(),
        "histogram": histogram.collect(),
        "occluder_types": occluder_types.collect(),
    }


def _counted(rows: pl.LazyFrame, types: pl.Expr, name: str) -> pl.LazyFrame:
    """How often each occluder type occurs in the lists ``types``, one count per element, as column ``name``."""
    return (
        rows.select(types.alias("occluder_type"))
        .explode("occluder_type")
        .drop_nulls("occluder_type")
        .group_by("occluder_type")
        .agg(pl.len().cast(pl.Int64).alias(name))
    )


def class_shares(names: list[str], partly: tuple[float, float] = EXACT) -> list[pl.Expr]:
    """In a ``group_by(...).agg`` over rows with the columns ``names``: ``rows`` and the shares of them
    ``visible``, ``partly`` hidden, ``hidden`` and ``out_of_view`` (:mod:`~.classes`)."""
    shares = _shares(names, partly)
    return [
        pl.len().cast(pl.Int64).alias("rows"),
        shares["visible"].alias("visible"),
        shares["partly_hidden"].alias("partly"),
        shares["hidden"].alias("hidden"),
        shares["out_of_view"].alias("out_of_view"),
    ]


def _checked(bands, partly, bins) -> tuple[float, float]:
    values = list(bands) if isinstance(bands, tuple | list) else None
    if not values or any(not (isinstance(b, int | float) and math.isfinite(b) and b > 0) for b in values):
        raise ValueError(f"bands takes ascending positive distances in metres, e.g. (20, 50), not {bands!r}")
    if sorted(set(values)) != values:
        raise ValueError(f"bands must be strictly ascending, not {bands!r}")
    if not (isinstance(bins, int) and bins >= 1):
        raise ValueError(f"bins must be a positive whole number, not {bins!r}")
    return check_partly(partly)


def _band_labels(bands) -> list[str]:
    def metres(b: float) -> str:
        return f"{b:g} m"

    inner = [f"{bands[k - 1]:g} to {metres(bands[k])}" for k in range(1, len(bands))]
    return [f"< {metres(bands[0])}", *inner, f">= {metres(bands[-1])}"]


def _type_name() -> pl.Expr:
    return pl.col("type").replace_strict(TYPE_NAMES, default="unknown", return_dtype=pl.String)


def rows_with_distance(table: pl.LazyFrame, objects: pl.LazyFrame, ego_idx: int | None) -> pl.LazyFrame:
    """The visibility table's rows with ``distance`` (metres, observer to target centre) and ``target_type``."""
    names = table.collect_schema().names()
    missing = [c for c in ("total_nanos", "idx", "visibility", "occluder_idxs") if c not in names]
    if missing:
        raise ValueError(f"the visibility table lacks the column(s) {missing}")
    object_names = objects.collect_schema().names()
    missing = [c for c in ("total_nanos", "idx", "x", "y", "type") if c not in object_names]
    if missing:
        raise ValueError(f"the object table lacks the column(s) {missing} (give the recording's moving objects)")
    if "sensor" in names:
        raise ValueError("the table has one row per sensor: combine them first with seen_by_any(table)")
    if "idx_ego" not in names:
        if ego_idx is None:
            raise ValueError("the visibility table has no idx_ego column: pass ego_idx (the observer it was made for)")
        table = table.with_columns(idx_ego=pl.lit(ego_idx, dtype=pl.Int64))
    egos = table.select(pl.col("idx_ego").unique().cast(pl.Int64)).collect()["idx_ego"]
    known = objects.select(pl.col("idx").cast(pl.Int64)).filter(pl.col("idx").is_in(egos.implode())).unique()
    missing = sorted(set(egos.drop_nulls().to_list()) - set(known.collect()["idx"].to_list()))
    if missing:
        raise ValueError(f"observer idx {missing[:5]} never occur(s) in the object table: no distances to measure")
    where = objects.select(
        pl.col("total_nanos").cast(pl.Int64), pl.col("idx").cast(pl.Int64), "x", "y", target_type=_type_name()
    )
    table = table.with_columns(pl.col("idx", "idx_ego").cast(pl.Int64))
    table = table.with_row_index("_row")
    occluder_types = (
        table.select("_row", "total_nanos", pl.col("occluder_idxs").alias("idx"))
        .explode("idx")
        .drop_nulls("idx")
        .join(where.select("total_nanos", "idx", "target_type"), on=["total_nanos", "idx"], how="left")
        .group_by("_row")
        .agg(occluder_types=pl.col("target_type").fill_null("unknown"))
    )
    return (
        table.join(where, on=["total_nanos", "idx"], how="left")
        .join(
            where.select("total_nanos", pl.col("idx").alias("idx_ego"), x_ego="x", y_ego="y"),
            on=["total_nanos", "idx_ego"],
            how="left",
        )
        .join(occluder_types, on="_row", how="left")
        .with_columns(
            distance=((pl.col("x") - pl.col("x_ego")) ** 2 + (pl.col("y") - pl.col("y_ego")) ** 2).sqrt(),
            occluder_types=pl.col("occluder_types").fill_null([]),
        )
        .drop("_row")
    )
