"""From a recording to per-frame scene arrays: input checks with clear errors, grouping by frame once.

Data flows one way: :func:`load_objects` validates the moving-object table a single time and sorts it by
``(frame, idx)``; :meth:`ObjectTable.frame_objects` then hands out one :class:`FrameObjects` per frame as slices
of the same arrays (no per-frame filtering of the table). Static geometry, shared by all frames, is loaded by
:mod:`.statics`.
"""

from __future__ import annotations

import os
import warnings
from typing import Any

import numpy as np
import polars as pl

from ..geometry.rings import box_rings
from .columns import BOX_COLUMNS, MAX_COORDINATE, check_columns, check_times, float_columns, whole_numbers
from .objects import ObjectTable, OnInvalid, VisibilityInputWarning
from .outlines import MIN_AREA, corner_rings, corners_column, polygon_rings
from .reader import TraceRecording
from .roles import RoleSpec, kinds_present, role_mask
from .roles import describe as describe_choice


def _report(problem: str, on_invalid: OnInvalid) -> None:
    if on_invalid == "raise":
        raise ValueError(problem)
    warnings.warn(problem, VisibilityInputWarning, stacklevel=4)


def as_lazy(data: Any) -> pl.LazyFrame:
    """Accept an ``omega_prime.Recording``, a polars ``DataFrame`` or ``LazyFrame``, a pandas ``DataFrame`` or a
    pyarrow ``Table`` (converted; shapely objects kept as they are), or the path of a recording; return a LazyFrame
    (nothing is collected, so a caller can read just the frames it needs)."""
    if isinstance(data, str | os.PathLike):
        from .io import read_recording

        data = read_recording(data)
    if isinstance(data, pl.LazyFrame):
        return data
    if isinstance(data, pl.DataFrame):
        return data.lazy()
    if isinstance(data, TraceRecording):  # its box corners, without shapely outlines
        return data.table.lazy()
    inner = getattr(data, "_df", None)
    if isinstance(inner, pl.DataFrame | pl.LazyFrame):
        return inner.lazy()
    module = type(data).__module__
    if module.startswith(("pandas", "geopandas")) and hasattr(data, "columns") and hasattr(data, "dtypes"):
        return _from_pandas(data).lazy()
    if module.startswith("pyarrow") and type(data).__name__ == "Table":
        return pl.from_arrow(data).lazy()
    raise TypeError(
        "expected an omega_prime.Recording, a polars, pandas or pyarrow table of moving objects or a recording's "
        f"path, got {type(data)!r}"
    )


def _from_pandas(frame: Any) -> pl.DataFrame:
    """A pandas (or geopandas) DataFrame as polars: columns of Python objects (shapely outlines) become object
    columns, the others convert as polars converts them."""
    columns = []
    for name in frame.columns:
        values = frame[name]
        if values.dtype == object or str(values.dtype) == "geometry":
            columns.append(pl.Series(str(name), np.asarray(values, dtype=object), dtype=pl.Object))
        else:
            columns.append(pl.from_pandas(values).alias(str(name)))
    return pl.DataFrame(columns)


def as_polars(data: Any) -> pl.DataFrame:
    """:func:`as_lazy`, collected."""
    if isinstance(data, pl.DataFrame):
        return data
    return as_lazy(data).collect()


def check_yaw_units(yaw: np.ndarray) -> None:
    """Warn when headings lie beyond a full turn: omega-prime's ``yaw`` is radians in ``[-pi, pi]``, and 90, 180
    or -90 on every object are degrees (sensors refuse such angles; an object's heading is only warned about, as
    an unwrapped track can pass 2 pi)."""
    finite = yaw[np.isfinite(yaw)]
    beyond = np.abs(finite) > 2.0 * np.pi + 1e-9
    if beyond.any():
        largest = float(finite[np.argmax(np.abs(finite))])
        warnings.warn(
            f"yaw: {int(beyond.sum())} of {len(yaw)} object row(s) have a heading beyond a full turn (up to "
            f"{largest:g}); yaw is radians counter-clockwise from +x, and {largest:g} looks like degrees "
            f"({largest:g}° is {np.radians(largest):.4g} rad): convert with numpy.radians",
            VisibilityInputWarning,
            stacklevel=4,
        )


def load_objects(
    data: Any,
    *,
    on_invalid: OnInvalid = "warn",
    three_d: bool = False,
    occluders: RoleSpec = None,
    targets: RoleSpec = None,
) -> ObjectTable:
    """Validate the moving-object table once and group it by frame.

    Parameters
    ----------
    data : omega_prime.Recording, polars.DataFrame or polars.LazyFrame
        Needs ``frame, total_nanos, idx, x, y`` and either a ``polygon`` column of shapely polygons or
        ``length, width, yaw`` (metres, radians) to build box outlines around ``(x, y)``.
    on_invalid : {"warn", "raise"}
        What to do with rows that cannot be used (NaN or infinite pose, zero-size or invalid outline): skip them
        with a :class:`VisibilityInputWarning` naming how many and which, or raise ``ValueError``.
    three_d : bool
        Also read the 3D boxes (``z, height, roll, pitch`` with ``length, width, yaw``; see :mod:`.threed.scene`);
        rows with NaN 3D values are skipped like NaN poses.
    occluders, targets : optional
        Which objects may block the view and which get rows (:mod:`.roles`); None: all of them.

    Raises
    ------
    ValueError
        Missing columns, an empty table, duplicate ``(frame, idx)`` rows, or (with ``on_invalid="raise"``) a bad row.
    """
    df = as_polars(data)
    use_polygon = check_columns(df)
    if df.height == 0:
        raise ValueError("the moving-object table is empty: there is nothing to compute visibility for")
    for name in ("frame", "total_nanos", "idx"):
        if df[name].null_count():
            raise ValueError(f"column {name!r} has {df[name].null_count()} null value(s)")
    frame, idx = whole_numbers(df, "frame"), whole_numbers(df, "idx")
    step, idx_step = np.diff(frame), np.diff(idx)
    if not ((step > 0) | ((step == 0) & (idx_step >= 0))).all():  # recordings usually come sorted already
        df = df.with_columns(pl.Series("_frame", frame), pl.Series("_idx", idx)).sort("_frame", "_idx")
        frame, idx = df["_frame"].to_numpy(), df["_idx"].to_numpy()
        df = df.drop("_frame", "_idx")
    dup = (np.diff(frame) == 0) & (np.diff(idx) == 0)
    if dup.any():
        k = int(np.flatnonzero(dup)[0])
        raise ValueError(f"object idx {idx[k]} appears more than once in frame {frame[k]}: (frame, idx) must be unique")
    blocks, wanted = role_mask(df, occluders, "occluders"), role_mask(df, targets, "targets")
    for option, choice, mask, outcome in (
        ("targets", targets, wanted, "the table has no rows ("),
        ("occluders", occluders, blocks, "no road user blocks the view (only static occluders do; "),
    ):
        if mask is not None and not mask.any():  # a choice that matches nothing is never silent
            warnings.warn(
                f"{option}={describe_choice(choice)!r} matches no object of the recording, so {outcome}"
                f"present: {kinds_present(df)})",
                VisibilityInputWarning,
                stacklevel=3,
            )
    floats = float_columns(df, ("x", "y", "yaw", *BOX_COLUMNS))
    x, y = floats["x"], floats["y"]
    yaw = floats.get("yaw", np.zeros(df.height))
    check_yaw_units(yaw)
    good = np.isfinite(x) & np.isfinite(y)
    problems = []
    if (~good).any():
        problems.append(f"{int((~good).sum())} NaN or infinite position(s) (x, y)")
    far = good & ((np.abs(x) > MAX_COORDINATE) | (np.abs(y) > MAX_COORDINATE))
    if far.any():
        problems.append(f"{int(far.sum())} position(s) beyond {MAX_COORDINATE:g} m (no map coordinate is that large)")
        good &= ~far
    notes: list[str] = []
    replaced = np.zeros(0, dtype=np.int64)
    corners = None if use_polygon else corners_column(df)
    if use_polygon or corners is not None:
        boxes = None  # each row's box, for outlines that cannot be used
        if all(c in df.columns for c in BOX_COLUMNS):
            length, width = floats["length"], floats["width"]
            boxes = (x, y, np.where(length * width >= MIN_AREA, length, np.nan), width, yaw)
        if use_polygon:
            rings, ok, reasons, notes, replaced = polygon_rings(df["polygon"].to_numpy(), good, boxes, on_invalid)
        else:
            rings, ok, reasons, notes, replaced = corner_rings(corners, good, boxes, on_invalid)
        problems += reasons
    else:
        length, width = floats["length"], floats["width"]
        pose_ok = np.isfinite(yaw) & np.isfinite(length) & np.isfinite(width)
        if (good & ~pose_ok).any():
            problems.append(f"{int((good & ~pose_ok).sum())} NaN or infinite yaw/length/width")
        size_ok = pose_ok & (length > 0) & (width > 0) & (length * width >= MIN_AREA)
        if (good & pose_ok & ~size_ok).any():
            problems.append(
                f"{int((good & pose_ok & ~size_ok).sum())} zero-size or negative box(es) (length or width <= 0)"
            )
        ok = good & size_ok
        rings = box_rings(x[ok], y[ok], length[ok], width[ok], yaw[ok])
    boxes3d = None
    if three_d:
        from .boxes3d import read_boxes3d

        boxes3d, ok3d, problems3d = read_boxes3d(df, x, y, yaw)
        if (ok & ~ok3d).any():
            problems += problems3d
            rings = rings.take(np.flatnonzero(ok3d[ok]))  # the rings are those of the rows usable in 2D
            ok = ok & ok3d
    if len(replaced):
        notes[-1] += ", e.g. " + ", ".join(f"(frame {frame[i]}, idx {idx[i]})" for i in replaced[:5])
    if notes and ok.all():
        warnings.warn("; ".join(notes), VisibilityInputWarning, stacklevel=3)
    if not ok.all():
        bad = np.flatnonzero(~ok)
        examples = ", ".join(f"(frame {frame[i]}, idx {idx[i]})" for i in bad[:5])
        if not ok.any():  # nothing left to compute with: said here, not as an ego that never occurs
            raise ValueError(f"none of the {len(ok)} object row(s) is usable: {'; '.join(problems)}; e.g. {examples}")
        _report(
            f"skipping {len(bad)} of {len(ok)} object row(s): {'; '.join(problems)}; e.g. {examples}"
            + "".join(f"; {note}" for note in notes),
            on_invalid,
        )
    frame, idx = frame[ok], idx[ok]
    total_nanos = whole_numbers(df, "total_nanos")[ok]
    position = np.column_stack([x[ok], y[ok]])
    heading_known = np.isfinite(yaw[ok])
    yaw = np.where(heading_known, yaw[ok], 0.0)
    frame_starts = np.concatenate([[0], np.flatnonzero(np.diff(frame)) + 1, [len(frame)]]).astype(np.int64)
    if len(frame) == 0:
        frame_starts = np.zeros(1, dtype=np.int64)
    check_times(frame, total_nanos, frame_starts)
    if boxes3d is not None:
        boxes3d = boxes3d[ok]
    blocks, wanted = (None if mask is None else mask[ok] for mask in (blocks, wanted))
    known = None if heading_known.all() else heading_known
    return ObjectTable(frame, total_nanos, idx, position, yaw, rings, frame_starts, boxes3d, blocks, wanted, known)


def observer_sizes(objects: ObjectTable, egos: np.ndarray) -> dict[int, tuple[float, float]]:
    """Each observer's length and width (metres): the median extent of its outline along and across its
    heading, over the frames where it occurs (observers that never occur are left out)."""
    rows = np.flatnonzero(np.isin(objects.idx, egos))
    rings = objects.rings.take(rows)
    heading = np.repeat(objects.yaw[rows], rings.sizes)
    rel = rings.coords - np.repeat(objects.position[rows], rings.sizes, axis=0)
    along = rel[:, 0] * np.cos(heading) + rel[:, 1] * np.sin(heading)
    across = -rel[:, 0] * np.sin(heading) + rel[:, 1] * np.cos(heading)
    first = rings.offsets[:-1]
    if len(first) == 0:
        return {}
    length = np.maximum.reduceat(along, first) - np.minimum.reduceat(along, first)
    width = np.maximum.reduceat(across, first) - np.minimum.reduceat(across, first)
    owner = objects.idx[rows]
    order = np.argsort(owner, kind="stable")
    idx, starts = np.unique(owner[order], return_index=True)
    groups = np.split(order, starts[1:])
    return {int(i): (float(np.median(length[g])), float(np.median(width[g]))) for i, g in zip(idx, groups, strict=True)}
