"""Where each object's label goes so that no two labels overlap: beside its object, or not at all.

Pure geometry on boxes in pixels (``(x0, y0, x1, y1)``, y up); no plotting library is imported here.
"""

from __future__ import annotations

from collections.abc import Sequence

Box = tuple[float, float, float, float]
GAP = 2.0  # pixels between an object and its label


def _overlaps(a: Box, b: Box) -> bool:
    return a[0] < b[2] and b[0] < a[2] and a[1] < b[3] and b[1] < a[3]


def _inside(a: Box, area: Box) -> bool:
    return a[0] >= area[0] and a[1] >= area[1] and a[2] <= area[2] and a[3] <= area[3]


def candidates(obj: Box, size: tuple[float, float]) -> list[Box]:
    """Label boxes of ``size`` (width, height) beside ``obj``: above, below, right, left, in that order.

    >>> candidates((0, 0, 10, 4), (6, 2))[0]
    (2.0, 6.0, 8.0, 8.0)
    """
    w, h = size
    cx, cy = (obj[0] + obj[2]) / 2, (obj[1] + obj[3]) / 2
    return [
        (cx - w / 2, obj[3] + GAP, cx + w / 2, obj[3] + GAP + h),
        (cx - w / 2, obj[1] - GAP - h, cx + w / 2, obj[1] - GAP),
        (obj[2] + GAP, cy - h / 2, obj[2] + GAP + w, cy + h / 2),
        (obj[0] - GAP - w, cy - h / 2, obj[0] - GAP, cy + h / 2),
    ]


def place_labels(
    objects: Sequence[Box], sizes: Sequence[tuple[float, float]], area: Box, may_cover: Sequence[bool] | None = None
) -> list[Box | None]:
    """A box for each label (in the order given, which is the order of priority), or None where it is dropped.

    Each label goes beside its own object (:func:`candidates`), inside ``area``, overlapping no label placed
    before it, and covering no other object; only a label with ``may_cover`` True (the ego's, the target's, what
    hides it: default all) takes a place over another object when there is no clear one. A label with no such
    place is dropped: in a crowd the road users keep their colour, and the labels that remain stay readable.

    >>> ego, car = (0, 0, 10, 4), (0, 7, 10, 11)  # the car just above the ego: the ego's label goes below
    >>> place_labels([ego, car], [(8, 3), (8, 3)], (-50, -50, 50, 50))
    [(1.0, -5.0, 9.0, -2.0), (1.0, 13.0, 9.0, 16.0)]
    >>> walled = [(0, 0, 10, 4), (-12, -8, 22, -1), (-12, 5, 22, 12), (-12, -1, -1, 5), (11, -1, 22, 5)]
    >>> place_labels(walled, [(8, 3)] * 5, (-50, -50, 50, 50), [False, True, True, True, True])[0] is None
    True
    """
    placed: list[Box] = []
    out: list[Box | None] = []
    cover = [True] * len(objects) if may_cover is None else list(may_cover)
    for k, (obj, size) in enumerate(zip(objects, sizes, strict=True)):
        others = [o for j, o in enumerate(objects) if j != k]
        free = [c for c in candidates(obj, size) if _inside(c, area) and not any(_overlaps(c, p) for p in placed)]
        clear = [c for c in free if not any(_overlaps(c, o) for o in others)]
        choice = (clear or (free if cover[k] else []) or [None])[0]
        if choice is not None:
            placed.append(choice)
        out.append(choice)
    return out
