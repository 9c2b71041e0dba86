"""A campaign of highD's size, every vehicle as observer, timed beside issue 52's targets:
``uv run python benchmarks/bench_highd.py`` (in ``make bench``; ``--frames`` for a shorter recording).

highD (60 recordings, about 1 M object rows each, 25 Hz) is measured here on a synthetic recording of its size,
written with omega-prime's writer (``Recording.to_mcap``): six lanes (three each way, 3.75 m), 420 m, 25,000 frames
at 25 Hz, vehicles entering at one end and leaving at the other (cars 4.2-5 m, every sixth a 12-16 m truck), each
lane at its own speed with 1.2-2.8 s headways, so about 40 vehicles are on the road at once and none overlap.

Measured: ``batch FOLDER --ego all --engine sweep --workers 2`` on two copies of it (each file on its own core,
as a campaign runs), the peak memory of the workers, the output's rows and bytes; the campaign's time for 60
recordings is stated from it (30 rounds of two files). Then ``run --ego all --engine sweep -o out.parquet`` on
one file, the issue's "today". Warm (kernels compiled); the machine may be shared, compare figures of one run.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

import numpy as np
import polars as pl

SCRIPT = Path(sys.executable).parent / "omega-prime-visibility"
LANES, LANE_WIDTH, ROAD = 6, 3.75, 420.0
DT = 0.04  # 25 Hz
CAMPAIGN_FILES, CAMPAIGN_TARGET_MIN, MEMORY_TARGET_GIB = 60, 15.0, 4.0


def highd_table(frames: int = 25_000, seed: int = 3) -> pl.DataFrame:
    """The synthetic highD-sized recording's object table (omega-prime's columns; ``idx`` one per vehicle).

    Examples
    --------
    >>> t = highd_table(500)
    >>> 30 < t.group_by("frame").len()["len"].mean() < 50
    True
    """
    rng = np.random.default_rng(seed)
    columns: dict[str, list[np.ndarray]] = {k: [] for k in ("frame", "idx", "x", "y", "length", "width", "yaw")}
    idx = 0
    for lane in range(LANES):
        forward = lane < LANES // 2
        speed = (22.0, 27.0, 32.0)[lane % 3]
        crossing = ROAD / speed / DT  # frames on the road
        start = -crossing  # already on the road at frame 0
        while start < frames:
            length, width = (rng.uniform(12, 16), 2.5) if idx % 6 == 5 else (rng.uniform(4.2, 5.0), 1.9)
            seen = np.arange(max(0, int(np.ceil(start))), min(frames, int(start + crossing)))
            travelled = (seen - start) * DT * speed
            columns["frame"].append(seen)
            columns["idx"].append(np.full(len(seen), idx))
            columns["x"].append(travelled if forward else ROAD - travelled)
            columns["y"].append(np.full(len(seen), (lane + 0.5) * LANE_WIDTH + (0.5 if not forward else 0.0)))
            columns["length"].append(np.full(len(seen), length))
            columns["width"].append(np.full(len(seen), width))
            columns["yaw"].append(np.full(len(seen), 0.0 if forward else np.pi))
            idx += 1
            start += rng.uniform(1.2, 2.8) / DT + (length + 2.0) / speed / DT
    table = pl.DataFrame({k: np.concatenate(v) for k, v in columns.items()}).sort("frame", "idx")
    zero = pl.lit(0.0)
    speed_x = pl.when(pl.col("yaw") == 0.0).then(1.0).otherwise(-1.0)
    return table.with_columns(
        total_nanos=pl.col("frame").cast(pl.Int64) * int(DT * 1e9), z=pl.lit(0.75), height=pl.lit(1.5),
        vel_x=speed_x * 25.0, vel_y=zero, vel_z=zero, acc_x=zero, acc_y=zero, acc_z=zero, roll=zero, pitch=zero,
        type=pl.lit(2, pl.Int64), role=pl.lit(0, pl.Int64), subtype=pl.lit(4, pl.Int64),
    )  # fmt: skip


def write_highd(path: Path, frames: int) -> int:
    """Write the recording with omega-prime's writer; its object rows."""
    import omega_prime

    table = highd_table(frames)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # omega-prime's note on the OSI version it declares
        omega_prime.Recording(table, host_vehicle_idx=0).to_mcap(path)
    return table.height


def tree(pid: int) -> list[int]:
    """``pid`` and all its descendants."""
    found, todo = [], [pid]
    while todo:
        found.append(current := todo.pop())
        try:
            todo += [int(c) for c in Path(f"/proc/{current}/task/{current}/children").read_text().split()]
        except OSError:
            pass
    return found


def timed(command: list[str]) -> tuple[float, float]:
    """Seconds and the peak memory of a command: the largest resident set (GiB) any one of its processes reached,
    sampled every 0.2 s."""
    started = time.perf_counter()
    process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    peak = 0
    while process.poll() is None:
        for pid in tree(process.pid):
            try:
                status = Path(f"/proc/{pid}/status").read_text()
                peak = max(peak, int(status.split("VmHWM:")[1].split()[0]))  # KiB, the process's own peak
            except (OSError, IndexError, ValueError):
                continue
        time.sleep(0.2)
    seconds = time.perf_counter() - started
    if process.returncode != 0:
        raise SystemExit(f"{command[1]} failed: {process.stderr.read().decode()[-500:]}")
    return seconds, peak / 2**20


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=25_000, help="frames of the synthetic recording")
    args = parser.parse_args()
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    with tempfile.TemporaryDirectory() as folder:
        inputs, out = Path(folder) / "in", Path(folder) / "out"
        inputs.mkdir()
        started = time.perf_counter()
        rows = write_highd(inputs / "highd_01.mcap", args.frames)
        shutil.copy(inputs / "highd_01.mcap", inputs / "highd_02.mcap")
        written = time.perf_counter() - started
        megabytes = (inputs / "highd_01.mcap").stat().st_size / 1e6
        print(f"synthetic highD recording: {args.frames} frames, {rows:,} object rows, {megabytes:.0f} MB (written in"
              f" {written:.0f} s)")  # fmt: skip
        command = [str(SCRIPT), "batch", str(inputs), "-o", str(out), "--ego", "all", "--engine", "sweep"]
        seconds, peak = timed([*command, "--workers", "2", "--no-progress"])
        result = out / "highd_01.mcap.parquet"  # (beside it: its objects, the batch's summary)
        result_rows = pl.scan_parquet(result).select(pl.len()).collect().item()
        size = result.stat().st_size
        campaign = seconds * CAMPAIGN_FILES / 2 / 60
        print(f"batch --ego all --engine sweep, 2 files on 2 workers: {seconds:.0f} s ({seconds / 2:.0f} s a file)")
        target = f"(target <= {CAMPAIGN_TARGET_MIN:.0f})"
        print(f"  a campaign of {CAMPAIGN_FILES} such recordings: {campaign:.1f} min {target}")
        print(f"  peak memory of a worker: {peak:.2f} GiB (target <= {MEMORY_TARGET_GIB:.0f})")
        print(f"  output: {result_rows:,} rows in {size / 1e6:.0f} MB a file, {size / result_rows:.1f} bytes a row")
        one = Path(folder) / "run.parquet"
        seconds, peak = timed([str(SCRIPT), "run", str(inputs / "highd_01.mcap"), "--ego", "all", "--engine", "sweep",
                               "--no-progress", "-o", str(one)])  # fmt: skip
        stored = sum(f.stat().st_size for f in ([one] if one.is_file() else one.rglob("*.parquet")))  # (parts)
        print(f"run --ego all --engine sweep -o out.parquet, one file: {seconds:.0f} s, peak {peak:.2f} GiB, "
              f"{stored / 1e6:.0f} MB")  # fmt: skip


if __name__ == "__main__":
    main()
