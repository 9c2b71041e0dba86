"""How long a new user waits for each engine's first command-line call after installing, and for a warm one,
printed next to issue 52's targets: ``uv run python benchmarks/first_call.py``.

Each engine: ``omega-prime-visibility run highway_merge.mcap --ego 0 --engine NAME -o x.parquet`` (the bundled
recording, 201 frames, 7 objects; ``--mode 3d`` for the 3D engines) in a fresh process, first with an empty user
cache (a private ``XDG_CACHE_HOME``: a fresh user, container or cluster node; the kernels come from the package's
copy, which ``make run`` and the package's build leave in ``omega_prime_visibility/_kernels``), then again, seven
times (warm: mostly importing polars and numpy, and the work; every engine's kernels come from the build made ahead
of time, numba is never imported). Then ``omega-prime-visibility compile`` into another empty
cache, as ``make run`` does it (with the package's copy current it only checks). Wall time; the machine may be
shared, so compare figures of one run. CI reports the same first call after ``pip install -e`` (.ci/pip_check.py).
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

REPO = Path(__file__).resolve().parent.parent
COLD_TARGET_S, WARM_TARGET_S = 5.0, 0.5
WARM_RUNS = 7
"""Warm calls timed per engine, their median printed (a shared machine's single call varies by a third)."""
ENGINES = {"visilibity": "2d", "sweep": "2d", "raycast3d": "3d", "silhouette3d": "3d"}


def timed_run(engine: str, mode: str, cache: Path, out: Path) -> float:
    command = [sys.executable, "-m", "omega_prime_visibility.cli", "run", str(REPO / "highway_merge.mcap")]
    command += ["--ego", "0", "--engine", engine, "--mode", mode, "--no-progress", "-o", str(out)]
    env = {k: v for k, v in os.environ.items() if k != "NUMBA_CACHE_DIR"} | {"XDG_CACHE_HOME": str(cache)}
    started = time.perf_counter()
    subprocess.run(command, env=env, check=True, capture_output=True)
    return time.perf_counter() - started


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("engines", nargs="*", default=list(ENGINES), help="engines to time (default: all)")
    args = parser.parse_args()
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores, load {os.getloadavg()[0]:.1f}")
    print(f"{'engine':14} {'cold first call':>16} {'target':>8} {'warm call':>10} {'target':>8}   (warm: median of"
          f" {WARM_RUNS}; every engine from the build made ahead of time, without numba)")  # fmt: skip
    with tempfile.TemporaryDirectory() as folder:
        for engine in args.engines:
            cache = Path(folder) / engine
            cold = timed_run(engine, ENGINES[engine], cache, Path(folder) / f"{engine}.parquet")
            warm = statistics.median(
                timed_run(engine, ENGINES[engine], cache, Path(folder) / f"{engine}.parquet") for _ in range(WARM_RUNS)
            )
            print(f"{engine:14} {cold:15.1f}s {COLD_TARGET_S:7.1f}s {warm:9.2f}s {WARM_TARGET_S:7.1f}s")
        env = dict(os.environ) | {"XDG_CACHE_HOME": str(Path(folder) / "all")}
        started = time.perf_counter()
        subprocess.run([sys.executable, "-m", "omega_prime_visibility.cli", "compile"], env=env, check=True)
        print(f"omega-prime-visibility compile (all engines, as make run does): {time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
