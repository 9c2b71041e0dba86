"""One meaning of *visible*, *partly hidden*, *hidden* and *out of view*, for every table and page.

A row of a visibility table (a target in a frame, through a sensor or not) is classed by what is in front of it,
from the share of the target's part *in view* that is seen, ``seen = visibility / in_view`` (``in_view`` is 1
without sensors):

- ``out_of_view``: no part of it is in view (``in_view == 0``: outside the sensor's field of view, or beyond its
  range); nothing hides it, so it is never counted as hidden;
- ``hidden``: part of it is in view and ``seen <= partly[0]`` (by default 0: nothing of it is seen, because
  something is in front of it);
- ``visible``: ``seen >= partly[1]`` (by default 1: all of its part in view is seen);
- ``partly_hidden``: in between (by default ``0 < seen < 1``: something in front hides some of it).

The part of a target outside the sensor's view is never "hidden": a target cut by the field of view's edge with
nothing in front of it is *visible*, and counted in ``partly_out_of_view`` (``0 < in_view < 1``) as well. The
bounds ``partly=(low, high)`` (``0 <= low < high <= 1``) are a parameter of every summary, statistic and page; the
default ``(0, 1)`` is the exact one, which the sensors' ``status`` column follows too.
"""

from __future__ import annotations

import math

import polars as pl

CLASSES = ("visible", "partly_hidden", "hidden", "out_of_view")
"""The classes of a row, in the order pages show them."""

EXACT = (0.0, 1.0)
"""The default bounds ``partly=(low, high)``: hidden when nothing is seen, visible when all in view is seen."""


def check_partly(partly: object) -> tuple[float, float]:
    """``partly`` as two floats, refused unless ``0 <= low < high <= 1``.

    Examples
    --------
    >>> check_partly((0.1, 0.9))
    (0.1, 0.9)
    >>> check_partly((0.9, 0.1))
    Traceback (most recent call last):
    ...
    ValueError: partly takes (low, high) bounds of the seen share with 0 <= low < high <= 1, not (0.9, 0.1)
    """
    ok = isinstance(partly, tuple | list) and len(partly) == 2
    ok = ok and all(isinstance(v, int | float) and not isinstance(v, bool) and math.isfinite(v) for v in partly)
    if not (ok and 0 <= partly[0] < partly[1] <= 1):
        raise ValueError(f"partly takes (low, high) bounds of the seen share with 0 <= low < high <= 1, not {partly!r}")
    return float(partly[0]), float(partly[1])


def _in_view(names: list[str]) -> pl.Expr:
    return pl.col("in_view") if "in_view" in names else pl.lit(1.0)


def occlusion_class(names: list[str], partly: tuple[float, float] = EXACT) -> pl.Expr:
    """An expression giving each row's class (one of :data:`CLASSES`, as a string) in a table with the columns
    ``names`` (``visibility``, and ``in_view`` where sensors were used).

    Examples
    --------
    >>> t = pl.DataFrame({"visibility": [1.0, 0.5, 0.0, 0.0, 0.5], "in_view": [1.0, 1.0, 1.0, 0.0, 0.5]})
    >>> t.select(occlusion_class(t.columns))["class"].to_list()
    ['visible', 'partly_hidden', 'hidden', 'out_of_view', 'visible']
    """
    low, high = check_partly(partly)
    in_view = _in_view(names)
    seen = pl.col("visibility") / in_view
    return (
        pl.when(in_view <= 0.0)
        .then(pl.lit("out_of_view"))
        .when(seen <= low)
        .then(pl.lit("hidden"))
        .when(seen >= high)
        .then(pl.lit("visible"))
        .otherwise(pl.lit("partly_hidden"))
        .alias("class")
    )


def class_shares(names: list[str], partly: tuple[float, float] = EXACT) -> dict[str, pl.Expr]:
    """In a ``group_by(...).agg``: the share of the group's rows in each class, by class name (:data:`CLASSES`),
    and ``partly_out_of_view`` (rows with part of the target outside the view, ``0 < in_view < 1``; always 0
    without sensors). Alias them as the table needs.

    Examples
    --------
    >>> t = pl.DataFrame({"idx": [1, 1, 1, 1], "visibility": [1.0, 0.5, 0.0, 0.0], "in_view": [1.0, 0.5, 1.0, 0.0]})
    >>> shares = class_shares(t.columns)
    >>> t.group_by("idx").agg(**shares).row(0)
    (1, 0.5, 0.0, 0.25, 0.25, 0.25)
    """
    category = occlusion_class(names, partly)
    in_view = _in_view(names)
    shares = {name: (category == name).mean() for name in CLASSES}
    shares["partly_out_of_view"] = ((in_view > 0.0) & (in_view < 1.0)).mean()
    return shares


def describe(partly: tuple[float, float] = EXACT) -> str:
    """The definition in words, for a page that shows shares.

    Examples
    --------
    >>> describe()[:58]
    'visible: all of its part in view is seen; partly hidden: s'
    >>> describe((0.1, 0.9))[:70]
    'visible: at least 90 % of its part in view is seen; partly hidden: mor'
    """
    low, high = check_partly(partly)
    if (low, high) == EXACT:
        text = (
            "visible: all of its part in view is seen; partly hidden: something in front hides some of it; "
            "hidden: nothing of it is seen, something is in front"
        )
    else:
        text = (
            f"visible: at least {high:.0%} of its part in view is seen; partly hidden: more than {low:.0%} and less "
            f"than {high:.0%}; hidden: at most {low:.0%}"
        ).replace("%", " %")
    return text + "; out of view: no part of it is in the view (never counted as hidden)"
