"""Who may block the view and who is looked for: the ``occluders=`` and ``targets=`` choices, resolved once per
recording into one boolean per object row.

A choice is given in the user's terms, in one of these forms:

- ``None``: every object (the default);
- a group name (:data:`GROUPS`, e.g. ``"vehicles"``) or an omega-prime (OSI) ``type`` or ``subtype`` name
  (``"PEDESTRIAN"``, ``"HEAVY_TRUCK"``, case does not matter), or a list of such names (their union); a row whose
  ``type`` is null matches no name, a vehicle whose ``subtype`` is null is a vehicle of no named subtype (so it is
  among ``"vehicles"``);
- a list of object ``idx``;
- a polars expression over the moving-object table giving one boolean per row (``pl.col("type") == 2``, or
  ``pl.col("length") > 6``); it may differ from frame to frame, a null counts as false.

Static occluders always block.
"""

from __future__ import annotations

import numbers
from collections.abc import Sequence
from typing import Any

import numpy as np
import polars as pl

from .errors import OptionError

TYPES = {"UNKNOWN": 0, "OTHER": 1, "VEHICLE": 2, "PEDESTRIAN": 3, "ANIMAL": 4}
"""omega-prime's (OSI's) moving-object ``type`` values by name."""

SUBTYPES = {
    "UNKNOWN": 0, "OTHER": 1, "SMALL_CAR": 2, "COMPACT_CAR": 3, "CAR": 4, "LUXURY_CAR": 5, "DELIVERY_VAN": 6,
    "HEAVY_TRUCK": 7, "SEMITRAILER": 8, "TRAILER": 9, "MOTORBIKE": 10, "BICYCLE": 11, "BUS": 12, "TRAM": 13,
    "TRAIN": 14, "WHEELCHAIR": 15, "SEMITRACTOR": 16, "STANDUP_SCOOTER": 17, "MICROMOBILITY_DEVICE": 18,
    "WORK_MACHINE": 19, "WATERCRAFT": 20, "AIRCRAFT": 21, "LAND_VEHICLE": 22,
}  # fmt: skip
"""omega-prime's (OSI's) vehicle classification, the ``subtype`` column, by name."""

TWO_WHEELERS = ("BICYCLE", "MOTORBIKE", "STANDUP_SCOOTER", "MICROMOBILITY_DEVICE")


def _subtype_in(names: Sequence[str]) -> pl.Expr:
    """Vehicles of these subtypes; a vehicle whose subtype is null or NaN is of none of them."""
    return (pl.col("type") == TYPES["VEHICLE"]) & pl.col("subtype").is_in([SUBTYPES[n] for n in names]).fill_null(False)


GROUPS: dict[str, Any] = {
    "all": lambda: pl.col("idx").is_not_null(),
    "vehicles": lambda: (pl.col("type") == TYPES["VEHICLE"]) & ~_subtype_in([*TWO_WHEELERS, "WHEELCHAIR"]),
    "pedestrians": lambda: pl.col("type") == TYPES["PEDESTRIAN"],
    "cyclists": lambda: _subtype_in(["BICYCLE"]),
    "motorcyclists": lambda: _subtype_in(["MOTORBIKE"]),
    "two_wheelers": lambda: _subtype_in(TWO_WHEELERS),
    "vulnerable": lambda: (pl.col("type") == TYPES["PEDESTRIAN"]) | _subtype_in([*TWO_WHEELERS, "WHEELCHAIR"]),
    "animals": lambda: pl.col("type") == TYPES["ANIMAL"],
}
"""Group names: ``vehicles`` are omega-prime vehicles but two-wheelers and wheelchairs (as nuPlan's occlusion
managers, which let only vehicles occlude); ``two_wheelers`` are bicycles, motorbikes, stand-up scooters and other
micromobility devices; ``vulnerable`` road users are pedestrians, two-wheelers and wheelchairs."""

RoleSpec = str | Sequence[str] | Sequence[int] | pl.Expr | None


def _name_expression(name: str, option: str) -> tuple[pl.Expr, set[str]]:
    """The expression a group, type or subtype name stands for, and the columns it reads."""
    key = name.strip()
    if key.lower() in GROUPS:
        needs = {"idx"} if key.lower() == "all" else {"type"} if key.lower() in ("pedestrians", "animals") else None
        return GROUPS[key.lower()](), {"type", "subtype"} if needs is None else needs
    upper = key.upper()
    if upper in TYPES:
        return pl.col("type") == TYPES[upper], {"type"}
    if upper in SUBTYPES:
        return _subtype_in([upper]), {"type", "subtype"}
    raise OptionError.plain(
        option,
        f"{option}: unknown object kind {name!r}; use a group ({', '.join(GROUPS)}), an omega-prime type "
        f"({', '.join(TYPES)}) or subtype (e.g. CAR, HEAVY_TRUCK, BICYCLE), or idx",
    )


def canonical_name(name: str) -> str:
    """One spelling of a group, type or subtype name: groups in lower case, the others in upper case.

    Examples
    --------
    >>> canonical_name(" Vehicles"), canonical_name("heavy_truck")
    ('vehicles', 'HEAVY_TRUCK')
    """
    key = name.strip()
    return key.lower() if key.lower() in GROUPS else key.upper()


def check_names(names: Sequence[str], option: str) -> None:
    """Raise the error :func:`role_mask` would for an unknown name, before any table is read."""
    for name in names:
        _name_expression(name, option)


def _is_idx(value: object) -> bool:
    return isinstance(value, numbers.Integral) and not isinstance(value, bool)


def role_mask(df: pl.DataFrame, spec: RoleSpec, option: str) -> np.ndarray | None:
    """One boolean per row of ``df`` for the choice ``spec`` (None: every row), see the module docstring.

    Parameters
    ----------
    df : polars.DataFrame
        The moving-object table (``idx``, and ``type``/``subtype`` for names).
    spec : str, list of str, list of int, polars.Expr or None
        The choice.
    option : str
        Its name in the user's call (``"occluders"``, ``"targets"``), for error messages.

    Raises
    ------
    ValueError
        An unknown name, an idx that never occurs, a table without the column a name needs, an expression that
        is not boolean or not one value per row.

    Examples
    --------
    >>> df = pl.DataFrame({"idx": [0, 1, 2], "type": [2, 3, 2], "subtype": [4, 0, 11]})
    >>> role_mask(df, "vehicles", "occluders").tolist(), role_mask(df, [1, 2], "targets").tolist()
    ([True, False, False], [False, True, True])
    >>> role_mask(df, pl.col("type") == 3, "targets").tolist()
    [False, True, False]
    """
    if spec is None:
        return None
    if isinstance(spec, pl.Expr):
        return _expression_mask(df, spec, option)
    if isinstance(spec, str):
        spec = [spec]
    if isinstance(spec, np.ndarray):
        spec = spec.tolist()
    if not isinstance(spec, Sequence) or isinstance(spec, bytes) or not len(spec):
        raise OptionError.plain(
            option,
            f"{option} takes a group or type name, a list of names, a list of idx or a polars expression, not {spec!r}",
        )
    if all(_is_idx(v) for v in spec):
        present = np.unique(df["idx"].cast(pl.Int64).to_numpy())
        wanted = np.asarray(spec, dtype=np.int64)
        missing = sorted(set(wanted.tolist()) - set(present.tolist()))
        if missing:
            raise OptionError.plain(option, f"idx {missing[:10]} never occur(s) in the recording")
        return df["idx"].cast(pl.Int64).is_in(wanted.tolist()).to_numpy()
    if not all(isinstance(v, str) for v in spec):
        raise OptionError.plain(option, f"{option} takes either names or idx, not a mix: {list(spec)!r}")
    expression, needed = pl.lit(False), set()
    for name in spec:
        one, columns = _name_expression(name, option)
        expression, needed = expression | one, needed | columns
    missing_columns = sorted(needed - set(df.columns))
    if missing_columns:
        raise OptionError.plain(
            option,
            f"{option}={list(spec)!r} needs the column(s) {missing_columns} of omega-prime's object table "
            "(a Recording has them); give a list of idx or a polars expression instead",
        )
    for column in sorted(needed - {"idx"}):
        if not (df.schema[column].is_integer() or df.schema[column].is_float() or df.schema[column] == pl.Null):
            raise OptionError.plain(
                option,
                f"{option}={list(spec)!r} reads the column {column!r} as omega-prime's integer codes, but it holds "
                f"{df.schema[column]} values",
            )
    return _expression_mask(df, expression, option)


def within_frames(spec: RoleSpec, all_idx: np.ndarray, option: str) -> RoleSpec:
    """A choice for a part of the recording (some of its frames): a list of idx is checked against ``all_idx``
    (every idx of the whole recording) and becomes an expression, so that an idx that does not occur in the part
    selects nothing there rather than being refused; other forms are returned as they are."""
    if isinstance(spec, np.ndarray):
        spec = spec.tolist()
    if isinstance(spec, pl.Expr | str) or not isinstance(spec, Sequence) or not len(spec):
        return spec
    if not all(_is_idx(v) for v in spec):
        return spec
    missing = sorted(set(int(v) for v in spec) - set(np.asarray(all_idx).tolist()))
    if missing:
        raise OptionError.plain(option, f"idx {missing[:10]} never occur(s) in the recording")
    return pl.col("idx").cast(pl.Int64).is_in([int(v) for v in spec])


def _expression_mask(df: pl.DataFrame, expression: pl.Expr, option: str) -> np.ndarray:
    try:
        result = df.select(expression.alias("_mask")).to_series()
    except pl.exceptions.PolarsError as e:
        first = str(e).strip().splitlines()[0] if str(e).strip() else type(e).__name__
        raise OptionError.plain(
            option, f"{option}: the expression cannot be evaluated on the object table ({first})"
        ) from None
    if result.dtype != pl.Boolean:
        raise OptionError.plain(option, f"the expression must give a boolean per row, not {result.dtype}")
    if len(result) != df.height:
        raise OptionError.plain(
            option, f"{option}: the expression must give one value per row, not {len(result)} for {df.height}"
        )
    return result.fill_null(False).to_numpy().astype(bool)


def describe(spec: RoleSpec) -> str | list | None:
    """A JSON-able record of a choice (for stored batch options): names and idx as given, an expression as its
    text."""
    if spec is None or isinstance(spec, str):
        return spec
    if isinstance(spec, pl.Expr):
        return f"expression: {spec}"
    return list(spec.tolist() if isinstance(spec, np.ndarray) else spec)


def kinds_present(df: pl.DataFrame) -> str:
    """What a table holds, for a message about a choice that matched nothing: the objects of each ``type`` (by
    name, with their idx) where the table has that column, else the idx.

    Examples
    --------
    >>> kinds_present(pl.DataFrame({"idx": [0, 1, 1, 4], "type": [2, 3, 3, 2]}))
    'VEHICLE idx [0, 4]; PEDESTRIAN idx [1]'
    >>> kinds_present(pl.DataFrame({"idx": [7, 8]}))
    'idx [7, 8]'
    """

    def listed(values: list) -> str:
        return f"{values[:20]}{' ...' if len(values) > 20 else ''}"

    if "type" not in df.columns:
        return f"idx {listed(sorted(df['idx'].unique().to_list()))}"
    names = {v: k for k, v in TYPES.items()}
    groups = df.select(pl.col("type").cast(pl.Int64, strict=False), pl.col("idx").cast(pl.Int64)).unique()
    parts = []
    for kind, idx in groups.group_by("type").agg(pl.col("idx").sort()).sort("type").iter_rows():
        name = "no type" if kind is None else names.get(kind, f"type {kind}")
        parts.append(f"{name} idx {listed(idx)}")
    return "; ".join(parts)
