"""Speed benchmarks, printed next to their targets (run with ``make bench``).

Figures are microseconds per (frame, target) row, end to end through ``get_visibility_df`` (table built), on one
core, after a warm-up call (numba compilation excluded). Synthetic highway: N boxes on four lanes with realistic
gaps, the ego (idx 0) in an inner lane, all driving at lane speed.
"""

from __future__ import annotations

import argparse
import os
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import polars as pl

from omega_prime_visibility import ENGINES, VisibilityInputWarning, get_visibility_df

REPO = Path(__file__).resolve().parent.parent
TARGETS_US = {("visilibity", 50): 40.0, ("sweep", 50): 2.0, ("sweep", 200): 3.0}
CROWDED_RUNS = (("sweep", 50), ("sweep", 200), ("visilibity", 50))


def tracks(t, x, y, length, width, yaw) -> pl.DataFrame:
    """An object table from times ``t`` (s, shape (f,)), x positions (f, n) and per-object ``y, length, width,
    yaw`` (n,) that stay constant (metres, radians)."""
    n_frames, n_objects = x.shape
    return pl.DataFrame(
        {
            "frame": np.repeat(np.arange(n_frames), n_objects),
            "total_nanos": np.repeat((t * 1e9).astype(np.int64), n_objects),
            "idx": np.tile(np.arange(n_objects), n_frames),
            "x": x.ravel(),
            "y": np.tile(y, n_frames),
            "length": np.tile(length, n_frames),
            "width": np.tile(width, n_frames),
            "yaw": np.tile(yaw, n_frames),
        }
    )


def synthetic_highway(n_objects: int, n_frames: int, seed: int = 0, dt: float = 0.04) -> pl.DataFrame:
    """Boxes on a 4-lane highway (lane width 3.5 m), moving in +x; idx 0 is the ego in lane 1.

    Cars 4.2-5 m x 1.8-2 m, every 8th object a 12-18 m x 2.5 m truck; gaps of 8-40 m within a lane.
    Columns: frame, total_nanos, idx, x, y, length, width, yaw (no polygon column). Vehicles keep their speed, so
    over long runs faster ones drive through slower ones in the same lane (overlaps, as in messy real data).
    """
    rng = np.random.default_rng(seed)
    lanes = np.arange(n_objects) % 4
    lanes[0] = 1
    truck = (np.arange(n_objects) % 8) == 7
    length = np.where(truck, rng.uniform(12, 18, n_objects), rng.uniform(4.2, 5.0, n_objects))
    width = np.where(truck, 2.5, rng.uniform(1.8, 2.0, n_objects))
    x0 = np.zeros(n_objects)
    for lane in range(4):
        members = np.flatnonzero(lanes == lane)
        gaps = rng.uniform(8, 40, len(members)) + length[members]
        pos = np.cumsum(gaps)
        x0[members] = pos - pos[len(pos) // 2]
    speed = 22.0 + 2.0 * lanes + rng.uniform(-1, 1, n_objects)
    y = 3.5 * lanes + rng.uniform(-0.3, 0.3, n_objects)
    t = np.arange(n_frames) * dt
    x = x0[None, :] + speed[None, :] * t[:, None]
    return tracks(t, x, y, length, width, np.zeros(n_objects))


def crowded_highway(n_objects: int, n_frames: int, seed: int = 0, dt: float = 0.04) -> pl.DataFrame:
    """Vehicles dropped at random on 4 lanes (3.5 m wide) within ±150 m of the ego (idx 0, at x = 0 in lane 1).

    15 % are 12 m x 2.5 m trucks, the rest cars of about 4.5 m x 1.9 m; each keeps a random speed (18-32 m/s) and a
    small random heading (±0.03 rad), so vehicles overlap from the start and drive through each other, as
    tracked data does. Columns: frame, total_nanos, idx, x, y, length, width, yaw (no polygon column; see
    :func:`with_polygons`).
    """
    rng = np.random.default_rng(seed)
    lanes = rng.integers(0, 4, n_objects)
    lanes[0] = 1
    truck = rng.random(n_objects) < 0.15
    truck[0] = False
    length = np.where(truck, 12.0, rng.normal(4.5, 0.2, n_objects))
    width = np.where(truck, 2.5, rng.normal(1.9, 0.05, n_objects))
    x0 = rng.uniform(-150, 150, n_objects)
    x0[0] = 0.0
    speed = rng.uniform(18, 32, n_objects)
    y = 3.5 * lanes + rng.uniform(-0.4, 0.4, n_objects)
    yaw = rng.uniform(-0.03, 0.03, n_objects)
    t = np.arange(n_frames) * dt
    x = x0[None, :] + (speed - speed[0])[None, :] * t[:, None]  # the ego's frame of reference: it stays at 0
    return tracks(t, x, y, length, width, yaw)


def with_polygons(table: pl.DataFrame) -> pl.DataFrame:
    """``table`` with a ``polygon`` column of shapely Polygons (polars Object dtype), built as omega-prime's
    ``Recording.from_file(..., compute_polygons=True)`` does: the closed box ring front-left, front-right,
    rear-right, rear-left (clockwise) from ``x, y, length, width, yaw`` (metres, radians)."""
    import shapely

    x, y, length, width, yaw = (table[c].to_numpy() for c in ("x", "y", "length", "width", "yaw"))
    dxl, dyl = 0.5 * length * np.cos(yaw), 0.5 * length * np.sin(yaw)
    dxw, dyw = 0.5 * width * np.sin(yaw), 0.5 * width * np.cos(yaw)
    corners = [(dxl - dxw, dyl + dyw), (dxl + dxw, dyl - dyw), (-dxl + dxw, -dyl - dyw), (-dxl - dxw, -dyl + dyw)]
    corners.append(corners[0])
    coords = np.stack([np.stack([x + dx, y + dy], axis=1) for dx, dy in corners], axis=1)
    return table.with_columns(pl.Series("polygon", shapely.polygons(coords), dtype=pl.Object))


def time_rows(table, engine: str, repeat: int = 3, **kwargs) -> tuple[float, int]:
    """Best-of-``repeat`` seconds and row count of one ``get_visibility_df`` call."""
    get_visibility_df(table, 0, engine=engine, progress=False, **kwargs)  # warm-up / compile
    best = np.inf
    for _ in range(repeat):
        t = time.perf_counter()
        out = get_visibility_df(table, 0, engine=engine, progress=False, **kwargs)
        best = min(best, time.perf_counter() - t)
    return best, out.height


def crowded(frames: int, engines: list[str]) -> None:
    """The crowded family (:func:`crowded_highway`): µs per (frame, target) for each of ``CROWDED_RUNS``, with
    and without a polygon column (:func:`with_polygons`), one core, warm."""
    print(f"crowded highway, {frames} frames, one core, warm; µs per (frame, target), end to end")
    print(f"{'scene':<34}{'polygon column':>16}{'length/width/yaw':>18}   target")
    for engine, n in CROWDED_RUNS:
        if engine not in engines:
            continue
        boxes = crowded_highway(n, frames)
        cells = []
        for table in (with_polygons(boxes), boxes):
            with warnings.catch_warnings():  # overlapping vehicles: some contain the observer now and then
                warnings.simplefilter("ignore", VisibilityInputWarning)
                secs, rows = time_rows(table, engine, workers=1)
            cells.append(secs / rows * 1e6)
        target = f"{engine} ≤ {TARGETS_US[(engine, n)]:g}"
        print(f"{f'crowded {engine} N={n}':<34}{cells[0]:>16.2f}{cells[1]:>18.2f}   {target}")


def peak_rss_gib() -> float:
    """Peak resident memory of this process and of its finished child processes, GiB (the larger of the two)."""
    import resource

    own = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    children = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss
    return max(own, children) / 2**20


def long_recording(engine: str, frames: int, workers: int) -> None:
    """A drone-dataset-sized track file: ``frames`` x 50 objects, no polygon column; one ego, then everyone."""
    import tempfile

    table = synthetic_highway(50, frames)
    get_visibility_df(table.filter(pl.col("frame") < 50), 0, engine=engine, progress=False)  # compile
    t = time.perf_counter()
    out = get_visibility_df(table, 0, engine=engine, progress=False, workers=workers)
    secs = time.perf_counter() - t
    print(
        f"{frames} frames x 50 objects, one ego, {workers} workers: {secs:.1f} s for {out.height} rows (target < 20 s)"
    )
    del out
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "all.parquet"
        t = time.perf_counter()
        lazy = get_visibility_df(table, "all", engine=engine, progress=True, workers=workers, output=path)
        secs = time.perf_counter() - t
        rows = lazy.select(pl.len()).collect().item()
        size = path.stat().st_size / 2**20
    print(
        f"{frames} frames x 50 objects, every object as observer: {secs:.1f} s for {rows} rows, "
        f"parquet {size:.0f} MiB, peak memory {peak_rss_gib():.2f} GiB (targets < 300 s, < 4 GiB)"
    )


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100, help="frames per synthetic run")
    parser.add_argument("--engines", default=",".join(sorted(ENGINES)))
    parser.add_argument(
        "--long", type=int, default=0, help="also run the long-recording benchmark with this many frames"
    )
    parser.add_argument("--long-engine", default="sweep" if "sweep" in ENGINES else "visilibity")
    parser.add_argument("--workers", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--crowded-frames", type=int, default=500, help="frames per crowded-highway run")
    parser.add_argument("--crowded-only", action="store_true", help="run only the crowded-highway family")
    args = parser.parse_args(argv)
    engines = args.engines.split(",")
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    if args.crowded_only:
        crowded(args.crowded_frames, engines)
        return
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores; µs per (frame, target), end to end")
    print(f"{'scene':<34}" + "".join(f"{e:>14}" for e in engines) + "   target")
    for n in (10, 50, 200):
        table = synthetic_highway(n, args.frames)
        cells = []
        for e in engines:
            secs, rows = time_rows(table, e)
            cells.append(secs / rows * 1e6)
        target = "  ".join(f"{e} ≤ {TARGETS_US[(e, n)]:g}" for e in engines if (e, n) in TARGETS_US)
        print(f"{f'synthetic highway N={n}':<34}" + "".join(f"{c:>14.1f}" for c in cells) + f"   {target}")
    mcap = REPO / "highway_merge.mcap"
    if mcap.exists():
        import omega_prime

        r = omega_prime.Recording.from_file(str(mcap), compute_polygons=True)
        cells = []
        for e in engines:
            secs, rows = time_rows(r._df, e)
            cells.append(f"{secs * 1e3:.0f} ms/{rows}")
        line = f"{'highway_merge.mcap (whole file)':<34}" + "".join(f"{c:>14}" for c in cells) + " rows"
        print(line + "   visilibity < 300 ms")
    crowded(args.crowded_frames, engines)
    if args.long:
        long_recording(args.long_engine, args.long, args.workers)


if __name__ == "__main__":
    main()
