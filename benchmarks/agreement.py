"""The two 2D engines against each other on the families of issue 29, offline and at scale (the test suite runs a
few hundred frames of the same generators).

Dense overlapping traffic with nearly collinear edges (``tests/reference.py: dense_traffic``: 40 cars within ±60 m,
bodies laid on a car's edge 0 to 50 µm off or turned by 1e-9 to 1e-8 rad), half at map coordinates (x, y of 1e5 to
1e6), with and without a polygon column; and walls with needles and corners collinear with the viewpoint
(``walls_with_needles``) against the 20,000-ray reference. Prints the rows and frames checked, the rows over 1e-6
apart, occluder lists that differ, the worst difference, and the frames VisiLibity handed to the sweep.

Usage::

    uv run python benchmarks/agreement.py --chunks 100 --scenes 400
"""

from __future__ import annotations

import argparse
import re
import sys
import warnings
from pathlib import Path

import numpy as np
import polars as pl

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "tests"))
from conftest import boxes_table, scene_table
from reference import dense_traffic, reference_visibility, walls_with_needles
from test_engines_vs_reference import with_polygons

from omega_prime_visibility import get_visibility_df

FALLBACK = re.compile(r"(\d+) frame\(s\) computed with engine='sweep'")


def both(table: pl.DataFrame, statics=None) -> tuple[pl.DataFrame, pl.DataFrame, int]:
    """VisiLibity's and the sweep's tables, and the frames VisiLibity handed to the sweep."""
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        visilibity = get_visibility_df(table, 0, statics, engine="visilibity", progress=False, workers=1)
        sweep = get_visibility_df(table, 0, statics, engine="sweep", progress=False, workers=1)
    handed = sum(int(m.group(1)) for w in caught if (m := FALLBACK.match(str(w.message))))
    return visilibity, sweep, handed


def compare(visilibity: pl.DataFrame, sweep: pl.DataFrame) -> tuple[np.ndarray, int]:
    difference = np.abs(visilibity["visibility"].to_numpy() - sweep["visibility"].to_numpy())
    lists = ("occluder_idxs", "static_occluder_idxs")
    mismatched = sum(int(visilibity[c].to_list()[i] != sweep[c].to_list()[i]) for c in lists for i in range(len(sweep)))
    return difference, mismatched


def dense(chunks: int, frames: int) -> None:
    rows = bad = mismatched = handed = 0
    worst = 0.0
    for k in range(chunks):
        rng = np.random.default_rng(10_000 + k)
        offset = (0.0, 0.0) if k % 2 == 0 else (rng.uniform(1e5, 1e6), rng.uniform(1e5, 1e6))
        table = pl.concat([boxes_table(dense_traffic(rng, offset=offset).tolist(), f) for f in range(frames)])
        if k % 4 >= 2:
            table = with_polygons(table)
        visilibity, sweep, n = both(table)
        difference, m = compare(visilibity, sweep)
        rows, bad, mismatched, handed = (
            rows + len(difference),
            bad + int((difference > 1e-6).sum()),
            mismatched + m,
            handed + n,
        )
        worst = max(worst, float(difference.max()))
    print(f"dense traffic: {chunks * frames} frames, {rows} rows: {bad} rows over 1e-6 apart (target 0), {mismatched}"
          f" occluder lists differ (target 0), worst {worst:.2g}; {handed} frames handed to the sweep")  # fmt: skip


def walls(scenes: int) -> None:
    rows = bad = mismatched = crumbs = 0
    worst = 0.0
    for k in range(scenes):
        observer, objects, statics, transparent = walls_with_needles(np.random.default_rng(20_000 + k))
        visilibity, sweep, _ = both(scene_table(observer, objects, True), statics)
        difference, m = compare(visilibity, sweep)
        ref = reference_visibility(observer, objects, statics, transparent, n_rays=20_000).visibility
        for table in (visilibity, sweep):
            seen, want = table["visibility"].to_numpy(), ref[table["idx"].to_numpy()]
            worst = max(worst, float(np.abs(seen - want).max()))
            crumbs += int(np.sum((want == 0) & (seen > 0) & (seen < 1e-6)))
        rows, bad, mismatched = rows + len(difference), bad + int((difference > 1e-6).sum()), mismatched + m
    print(f"walls with needles and collinear corners: {scenes} scenes, {rows} rows: {bad} rows over 1e-6 apart"
          f" (target 0), {mismatched} occluder lists differ (target 0); worst against the reference {worst:.2g}"
          f" (target < 5e-4); {crumbs} crumbs (0 < visibility < 1e-6 where the rays see none; target 0)")  # fmt: skip


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--chunks", type=int, default=20, help="recordings of dense traffic")
    parser.add_argument("--frames", type=int, default=20, help="frames per recording")
    parser.add_argument("--scenes", type=int, default=40, help="scenes of walls")
    args = parser.parse_args(argv)
    dense(args.chunks, args.frames)
    walls(args.scenes)


if __name__ == "__main__":
    main()
