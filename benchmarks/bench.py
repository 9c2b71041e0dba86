"""Speed benchmarks, printed next to their targets (run with ``make bench``).

Figures are microseconds per (frame, target) row, end to end through ``get_visibility_df`` (table built), on one
core, after a warm-up call (numba compilation excluded). Synthetic highway: N boxes on four lanes with realistic
gaps, the ego (idx 0) in an inner lane, all driving at lane speed. Then the crowded family, the small real scene
against the published 0.1.0 (when its throwaway environment exists, see ``compare_published.py``) and, with
``--long``, a long recording with every object as observer streamed to a parquet dataset. On a machine shared
with other programs, wall times grow with their load: the CPU times printed beside them say what this process
itself spent.
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
TARGETS_US = {("visilibity", 50): 40.0, ("sweep", 50): 2.0, ("sweep", 200): 1.5}  # 200: issue 52 (it was 3)
SMALL_TARGETS = {"sweep": 150, "visilibity": 15}  # times faster than the published 0.1.0 on highway_merge.mcap
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


def time_rows(table, engine: str, repeat: int = 3, cpu: bool = False, **kwargs) -> tuple[float, int]:
    """Best-of-``repeat`` seconds (wall, or with ``cpu`` this process's CPU time) and row count of one
    ``get_visibility_df`` call."""
    clock = time.process_time if cpu else time.perf_counter
    get_visibility_df(table, 0, engine=engine, progress=False, **kwargs)  # warm-up / compile
    best = np.inf
    for _ in range(repeat):
        t = clock()
        out = get_visibility_df(table, 0, engine=engine, progress=False, **kwargs)
        best = min(best, clock() - t)
    return best, out.height


def crowded(frames: int, engines: list[str]) -> None:
    """The crowded family (:func:`crowded_highway`): µs per (frame, target) for each of ``CROWDED_RUNS``, with
    and without a polygon column (:func:`with_polygons`), one core, warm; wall time, and in brackets this
    process's CPU time (which other programs on a shared machine inflate less)."""
    print(f"crowded highway, {frames} frames, one core, warm; µs per (frame, target), end to end, wall (CPU)")
    print(f"{'scene':<34}{'polygon column':>18}{'length/width/yaw':>20}   target")
    for engine, n in CROWDED_RUNS:
        if engine not in engines:
            continue
        boxes = crowded_highway(n, frames)
        cells = []
        for table in (with_polygons(boxes), boxes):
            with warnings.catch_warnings():  # overlapping vehicles: some contain the observer now and then
                warnings.simplefilter("ignore", VisibilityInputWarning)
                secs, rows = time_rows(table, engine, workers=1)
                cpu, _ = time_rows(table, engine, workers=1, cpu=True)
            cells.append(f"{secs / rows * 1e6:.2f} ({cpu / rows * 1e6:.2f})")
        target = f"{engine} ≤ {TARGETS_US[(engine, n)]:g}"
        print(f"{f'crowded {engine} N={n}':<34}{cells[0]:>18}{cells[1]:>20}   {target}")


def small_scene(engines: list[str], published_python: str) -> None:
    """The upstream ``highway_merge.mcap`` (433 frames, 6 objects) with the upstream README's wall, ego 0, warm:
    ours against the published 0.1.0 in the same run (its interpreter from a throwaway environment, see
    ``compare_published.py``); the speed-up next to its target."""
    from compare_published import UPSTREAM_MCAP, WALL_WKT, load_table

    if not UPSTREAM_MCAP.exists():
        print(f"small scene: {UPSTREAM_MCAP} not found, skipped")
        return
    import shapely

    df = load_table(str(UPSTREAM_MCAP))
    wall = [shapely.from_wkt(WALL_WKT)]
    published = None
    if Path(published_python).exists():
        import json
        import subprocess
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            out = Path(tmp) / "pub.parquet"
            cmd = [published_python, str(REPO / "benchmarks" / "compare_published.py"), "--input", str(UPSTREAM_MCAP)]
            cmd += ["--ego", "0", "--static-wkt", WALL_WKT, "--out", str(out), "--repeat", "3"]
            subprocess.run(cmd, check=True, capture_output=True, env={**os.environ, "PYTHONPATH": ""})
            published = json.loads(out.with_suffix(".json").read_text())["seconds"]
    line = "upstream highway_merge.mcap + wall, 433 frames x 6 objects, ego 0, warm: published 0.1.0 "
    print(line + (f"{published * 1e3:.0f} ms" if published else f"not run ({published_python} not found)"))
    for engine in engines:
        secs, _ = time_rows(df, engine, repeat=5, static_occluder_polys=wall)
        cpu, _ = time_rows(df, engine, repeat=5, cpu=True, static_occluder_polys=wall)
        ratio = f"{published / secs:.0f}x faster" if published else "–"
        target = SMALL_TARGETS.get(engine)
        print(
            f"  {engine:<12}{secs * 1e3:>7.1f} ms ({cpu * 1e3:.1f} ms CPU, {secs / 433 * 1e6:.0f} µs per frame): "
            f"{ratio}   target ≥ {target}x"
        )


class MemorySampler:
    """Peak memory of this process and its children (the workers), sampled every ``interval`` seconds (Linux;
    reading PSS walks the page tables, so not too often).

    ``pss`` sums the proportional set sizes (pages shared between the main process and its forked workers
    counted once); ``rss`` sums the resident set sizes (shared pages counted in every process that maps them).
    """

    def __init__(self, interval: float = 2.0) -> None:
        import threading

        self.interval, self.pss, self.rss = interval, 0.0, 0.0
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)

    def __enter__(self) -> MemorySampler:
        self._thread.start()
        return self

    def __exit__(self, *exc) -> None:
        self._stop.set()
        self._thread.join()

    def _run(self) -> None:
        while not self._stop.wait(self.interval):
            pss = rss = 0
            for pid in [os.getpid(), *self._children(os.getpid())]:
                try:
                    for line in Path(f"/proc/{pid}/smaps_rollup").read_text().splitlines():
                        key, _, value = line.partition(":")
                        if key in ("Pss", "Rss"):
                            kib = int(value.split()[0])
                            pss, rss = (pss + kib, rss) if key == "Pss" else (pss, rss + kib)
                except (OSError, ValueError):
                    continue  # a worker that just ended
            self.pss, self.rss = max(self.pss, pss / 2**20), max(self.rss, rss / 2**20)

    @staticmethod
    def _children(pid: int) -> list[int]:
        try:
            return [int(c) for c in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
        except OSError:
            return []


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
    with tempfile.TemporaryDirectory() as tmp, warnings.catch_warnings():
        warnings.simplefilter("ignore", VisibilityInputWarning)  # vehicles drive through each other
        path = Path(tmp) / "all.parquet"
        t, cpu = time.perf_counter(), os.times()
        with MemorySampler() as memory:
            lazy = get_visibility_df(table, "all", engine=engine, progress=False, workers=workers, output=path)
        secs, done = time.perf_counter() - t, os.times()
        rows = lazy.select(pl.len()).collect().item()
        size = sum(p.stat().st_size for p in path.iterdir()) / 2**20
    main_cpu = done.user + done.system - cpu.user - cpu.system
    workers_cpu = done.children_user + done.children_system - cpu.children_user - cpu.children_system
    print(
        f"{frames} frames x 50 objects, every object as observer: {secs:.1f} s for {rows} rows (target ≤ 20 s), "
        f"parquet dataset {size:.0f} MiB; CPU: workers {workers_cpu:.0f} s, main process {main_cpu:.1f} s; "
        f"peak memory of main + workers {memory.pss:.2f} GiB PSS ({memory.rss:.2f} GiB summed RSS, counting the "
        "pages the workers share with the main process in each) (target ≤ 2 GiB)"
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
    parser.add_argument("--published-python", default="/tmp/pub/bin/python", help="the published package's python")
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
    small_scene(engines, args.published_python)
    if args.long:
        long_recording(args.long_engine, args.long, args.workers)


if __name__ == "__main__":
    main()
