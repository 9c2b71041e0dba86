"""How long pictures take, printed next to their targets: ``uv run python benchmarks/pictures.py``.

The issue's target: 200 frames of the bundled recording rendered to a GIF in at most 20 s on 2 cores. Timed end to
end through ``animate`` (visibility and visible region of every frame, drawing, GIF encoding), after the recording
is loaded and one warm-up frame has compiled the engines; ``--runs`` takes the best of several. The machine is
shared: figures vary by tens of percent between runs, so compare figures measured in one run.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

from omega_prime_visibility import animate, write_report
from omega_prime_visibility.inputs.io import read_recording

REPO = Path(__file__).resolve().parent.parent
GIF_TARGET_S = 20.0


def timed(fn) -> float:
    t = time.perf_counter()
    fn()
    return time.perf_counter() - t


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--runs", type=int, default=1, help="best of this many runs")
    args = parser.parse_args()
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        r = read_recording(REPO / "highway_merge.mcap")
    print(f"python {sys.version.split()[0]}, {os.cpu_count()} cores; bundled highway_merge.mcap, ego 0")
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder)
        animate(r, 0, out / "warm.gif", frames=[0], progress=False)  # numba compilation, matplotlib fonts
        gif = min(
            timed(lambda: animate(r, 0, out / "a.gif", frames=slice(0, 200), progress=False)) for _ in range(args.runs)
        )
        size = (out / "a.gif").stat().st_size / 1e6
        mp4 = min(
            timed(lambda: animate(r, 0, out / "a.mp4", frames=slice(0, 200), progress=False)) for _ in range(args.runs)
        )
        report = min(timed(lambda: write_report(r, 0, out / "r.html", progress=False)) for _ in range(args.runs))
    print(f"{'200 frames -> GIF (640 x 288)':<34}{gif:>8.1f} s   target ≤ {GIF_TARGET_S:g} s   ({size:.2f} MB)")
    print(f"{'200 frames -> MP4 (640 x 288)':<34}{mp4:>8.1f} s   (no target)")
    print(f"{'HTML report, 201 frames':<34}{report:>8.1f} s   (no target)")


if __name__ == "__main__":
    main()
