"""The 3D columns of a moving-object table: ``z, height, roll, pitch`` next to ``x, y, length, width, yaw``.

Asked for by ``load_objects(..., three_d=True)`` (``mode="3d"``). ``height``, ``length`` and ``width`` are
required (a ``ValueError`` names the missing ones). Defaults, each announced by one
:class:`~.objects.VisibilityInputWarning`: without ``roll`` and ``pitch`` the boxes are level (0), without ``z``
they stand on the ground z = 0 (``z = height / 2``). Rows with a NaN or infinite 3D value, or a height <= 0, are
skipped like rows with a NaN pose. A table whose heights all equal the widths (as omega-prime 0.3.7 writes MCAP
files) gets a warning.
"""

from __future__ import annotations

import warnings

import numpy as np
import polars as pl

from .objects import VisibilityInputWarning

REQUIRED_3D = ("length", "width", "height")
DEFAULTED_3D = ("z", "roll", "pitch")


def read_boxes3d(
    df: pl.DataFrame, x: np.ndarray, y: np.ndarray, yaw: np.ndarray
) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """The 3D boxes (shape (n, 9), :mod:`.boxes`'s columns) of every row, which rows are usable, and the
    problems of the others (for the skip message)."""
    missing = [c for c in REQUIRED_3D if c not in df.columns]
    if missing:
        raise ValueError(
            f"mode='3d' needs the column(s) {missing} (metres; with z, roll, pitch: OSI's 3D bounding box); "
            f"columns present: {df.columns}"
        )
    values = {c: df[c].cast(pl.Float64).fill_null(np.nan).to_numpy() for c in (*REQUIRED_3D, *DEFAULTED_3D) if c in df}
    absent = [c for c in DEFAULTED_3D if c not in df.columns]
    if absent:
        warnings.warn(
            f"the table has no {absent} column(s): 3D boxes are taken "
            + ("level (roll = pitch = 0)" if set(absent) & {"roll", "pitch"} else "")
            + (" and " if "z" in absent and set(absent) & {"roll", "pitch"} else "")
            + ("standing on the ground z = 0 (z = height / 2)" if "z" in absent else ""),
            VisibilityInputWarning,
            stacklevel=4,
        )
    height = values["height"]
    same = np.isfinite(height) & (height == values["width"])
    if len(height) and same.all():
        warnings.warn(
            "every row's height equals its width: the heights look like a copy of the widths (omega-prime 0.3.7 "
            "writes an object's width into the MCAP height field), so the 3D result may be wrong",
            VisibilityInputWarning,
            stacklevel=4,
        )
    z = values.get("z", height / 2)
    roll = values.get("roll", np.zeros(len(height)))
    pitch = values.get("pitch", np.zeros(len(height)))
    boxes = np.column_stack([x, y, z, values["length"], values["width"], height, roll, pitch, yaw])
    finite = np.isfinite(boxes).all(axis=1)
    positive = finite & (boxes[:, 3:6] > 0).all(axis=1)
    problems = []
    if (~finite).any():
        problems.append(f"{int((~finite).sum())} NaN or infinite 3D value(s) (z, length, width, height, roll, pitch)")
    if (finite & ~positive).any():
        problems.append(f"{int((finite & ~positive).sum())} box(es) with a length, width or height <= 0")
    return boxes, positive, problems
