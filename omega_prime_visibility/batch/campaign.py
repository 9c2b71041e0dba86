"""Statistics over a whole campaign: every result of a batch output folder, per recording and overall.

Each result holds its recording's path and the options it was computed with (parquet metadata, see :mod:`.files`).
The distances and the targets' types come from the moving objects batch writes beside each result
(``<result>.objects.parquet``), or, for results without them, from the recordings themselves (read without a map).
Results computed with different options are refused, naming the options that differ: their numbers do not compare.
"""

from __future__ import annotations

import warnings
from pathlib import Path

import polars as pl
import pyarrow as pa
import pyarrow.parquet as pq

from ..analysis.classes import EXACT
from ..analysis.combine import every_listed
from ..analysis.statistics import class_shares, rows_with_distance, statistics_of_rows
from ..inputs.objects import VisibilityInputWarning
from .files import OPTIONS_KEY, RECORDING_KEY, stored_observer
from .options import FileOptions
from .run import SUMMARY_NAME
from .task import conflicts_path, mcap_path, objects_path


def campaign_statistics(
    folder: str | Path,
    *,
    bands: tuple[float, ...] = (20.0, 50.0),
    partly: tuple[float, float] = EXACT,
    bins: int = 10,
) -> dict[str, pl.DataFrame]:
    """:func:`~omega_prime_visibility.occlusion_statistics` over every result in a batch output ``folder``.

    Returns
    -------
    dict of polars.DataFrame
        ``"by_band"``, ``"histogram"`` and ``"occluder_types"`` over all recordings together, and
        ``"by_recording"``: ``recording, rows, visible, partly, hidden, out_of_view`` (shares of the recording's
        rows) and ``mcap`` (the path of the recording with the answer drawn in, ``batch --mcap``; else null), and
        ``"conflicts"``: every result's occluded conflicts with its ``recording`` (written by ``batch --conflicts``;
        empty without them).
    """
    frames, conflicts, drawn = [], [], {}
    for result, options, recording in _results(Path(folder)):
        if mcap_path(result).is_file():  # (batch --mcap)
            drawn[recording] = str(mcap_path(result).resolve())
        if conflicts_path(result).is_file():
            conflicts.append(pl.read_parquet(conflicts_path(result)).with_columns(recording=pl.lit(recording)))
        ego, table, stored = options.get("ego"), _table(result), objects_path(result)
        seen_from = stored_observer(result)  # (batch stores whom each result is seen from)
        if ego is None and seen_from is not None and isinstance(seen_from[0], int):
            ego = seen_from[0]  # the host vehicle, or the fallback where the recording names none
        knows_ego = isinstance(ego, int) or "idx_ego" in table.collect_schema().names()
        if knows_ego and stored.is_file():  # written by batch beside the result: no need to read the MCAP
            objects = pl.scan_parquet(stored)
        else:  # an older result, or the host vehicle as ego: the recording says
            objects, host = _objects(recording)
            ego = ego if isinstance(ego, int) else host if host is not None else options.get("fallback_ego")
        rows = rows_with_distance(table, objects, ego if isinstance(ego, int) else None)
        frames.append(rows.with_columns(recording=pl.lit(recording)))
    rows = pl.concat(frames, how="vertical_relaxed")
    stats = statistics_of_rows(rows, bands=bands, partly=partly, bins=bins)
    shares = class_shares(rows.collect_schema().names(), partly)
    by_recording = rows.group_by("recording").agg(shares).sort("recording").collect()
    stats["by_recording"] = by_recording.with_columns(
        mcap=pl.col("recording").replace_strict(drawn, default=None, return_dtype=pl.String)
    )
    stats["conflicts"] = (
        pl.concat(conflicts, how="vertical_relaxed") if conflicts else pl.DataFrame(schema={"recording": pl.String})
    )
    return stats


def _results(folder: Path) -> list[tuple[Path, dict, str]]:
    """Every complete result under ``folder`` with its recording; checks the options agree."""
    if not folder.is_dir():
        raise ValueError(f"{folder} is not a folder of batch results")
    found, unreadable = [], []
    for path in sorted(folder.rglob("*.parquet")):
        if path.name == SUMMARY_NAME or path.name.startswith("."):
            continue
        try:
            metadata = pq.read_metadata(path).metadata or {}
        except (OSError, pa.ArrowException):  # not a parquet file (batch writes its results whole)
            unreadable.append(str(path.relative_to(folder)))
            continue
        if OPTIONS_KEY in metadata and RECORDING_KEY in metadata:
            found.append((path, FileOptions.stored(metadata[OPTIONS_KEY]), metadata[RECORDING_KEY].decode()))
    if unreadable:
        warnings.warn(
            f"{folder}: skipping {len(unreadable)} file(s) that are not readable parquet files, not batch results: "
            + ", ".join(unreadable[:5])
            + (", ..." if len(unreadable) > 5 else ""),
            VisibilityInputWarning,
            stacklevel=3,
        )
    if not found:
        summary = folder / SUMMARY_NAME
        if summary.is_file():
            counts = pl.read_parquet(summary, columns=["status"])["status"].value_counts(sort=True).rows()
            listed = ", ".join(f"{n} {status}" for status, n in counts)
            raise ValueError(f"{folder} holds no finished results: its batch summary lists {listed} (see {summary})")
        raise ValueError(f"{folder} holds no batch results (run omega-prime-visibility batch ... -o {folder} first)")
    first_path, first, _ = found[0]
    for path, options, _ in found[1:]:
        differ = sorted(k for k in set(first) | set(options) if first.get(k) != options.get(k))
        if differ:
            raise ValueError(
                f"the results in {folder} were computed with different options ({', '.join(differ)}: "
                f"{first_path.name} and {path.name}); statistics over them would not compare like with like"
            )
    return found


def _table(result: Path) -> pl.LazyFrame:
    """A result's table; through sensors, one row per (frame, target): the best visibility and every occluder."""
    table = pl.scan_parquet(result)
    names = table.collect_schema().names()
    if "sensor" not in names:
        return table
    keys = [k for k in ("frame", "total_nanos", "idx_ego", "idx") if k in names]
    best = [pl.col("visibility").max(), every_listed("occluder_idxs")]
    if "in_view" in names:  # so that a target out of every sensor's view is told apart from a hidden one
        best.append(pl.col("in_view").max())
    return table.group_by(keys).agg(best).sort(keys)


def _objects(recording: str) -> tuple[pl.LazyFrame, int | None]:
    """The recording's moving objects (positions and types) and its host vehicle."""
    from ..inputs.io import RecordingReadError, read_recording
    from ..inputs.scene import as_lazy

    try:
        r = read_recording(Path(recording))
    except (RecordingReadError, OSError) as e:
        raise ValueError(f"cannot read the recording {recording} of a batch result: {e}") from None
    host = None if r.host_vehicle_idx is None else int(r.host_vehicle_idx)
    return as_lazy(r).select("total_nanos", "idx", "x", "y", "type"), host
