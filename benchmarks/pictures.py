"""How long pictures take, printed next to their targets: ``uv run python benchmarks/pictures.py``.

Targets (issue 25): one ``plot_frame`` on a loaded recording (drawn to pixels) in at most 1 s, whatever the size of
its map (the esmini trace ``pedestrian.osi`` on ``fabriksgatan.xodr``, whose lanes have 680,000 vertices, when
../shared/data is there; its lanes are prepared once per recording, by a first call); 200 frames of the bundled
recording rendered to a GIF (960 x 540) in at most 10 s on 2 cores, timed end to end through ``animate``
(visibility and visible region of every frame, drawing, GIF encoding) after one warm-up frame has compiled the
engines; with the six sensors of ``"typical"`` in at most 15 s (issue 42); one report in at most 5 s; the first
picture of a recording in a fresh process (kernels compiled, the recording read) within 1 s of a later one.
``--runs`` takes the best of several. The machine is shared: figures vary by tens of percent between runs,
so compare figures measured in one run.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time
import warnings
from pathlib import Path

from omega_prime_visibility import animate, plot_frame, write_report
from omega_prime_visibility.inputs.io import read_recording

REPO = Path(__file__).resolve().parent.parent
SHARED = REPO.parent / "shared" / "data"
GIF_TARGET_S = 10.0
SENSORS_GIF_TARGET_S = 15.0
REPORT_TARGET_S = 5.0
FRAME_TARGET_S = 1.0
FIRST_EXTRA_TARGET_S = 1.0
FIRST_PICTURE = """
import time, warnings
import matplotlib
matplotlib.use("Agg")
from omega_prime_visibility import plot_frame, read_recording
warnings.simplefilter("ignore")
r = read_recording({path!r})
times = []
for frame in (0, 10):
    start = time.perf_counter()
    ax = plot_frame(r, 0, frame)
    ax.figure.canvas.draw()
    times.append(time.perf_counter() - start)
print(times[0], times[1])
"""


def first_picture_extra() -> tuple[float, float]:
    """Seconds of the first ``plot_frame`` of the bundled recording in a fresh process, and of the next one."""
    import subprocess

    code = FIRST_PICTURE.format(path=str(REPO / "highway_merge.mcap"))
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.split()
    return float(out[0]), float(out[1])


def plot_frame_seconds(r, runs: int) -> float:
    """Best time of ``plot_frame`` on frame 0 of ``r``, drawn to pixels, after one call (lanes prepared, kernels
    compiled)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    def once() -> None:
        ax = plot_frame(r, 0, 0)
        ax.figure.canvas.draw()
        plt.close(ax.figure)

    once()
    return min(timed(once) for _ in range(runs))


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
    frame_times = [("plot_frame, bundled recording", plot_frame_seconds(r, max(args.runs, 3)))]
    if (SHARED / "pedestrian.osi").exists():
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            street = read_recording(SHARED / "pedestrian.osi", SHARED / "fabriksgatan.xodr")
        frame_times.append(("plot_frame, pedestrian.osi + map", plot_frame_seconds(street, max(args.runs, 3))))
    for name, seconds in frame_times:
        print(f"{name:<34}{seconds:>8.2f} s   target ≤ {FRAME_TARGET_S:g} s", flush=True)
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
        sensors = min(
            timed(lambda: animate(r, 0, out / "s.gif", frames=slice(0, 200), sensors="typical", progress=False))
            for _ in range(args.runs)
        )
        report = min(timed(lambda: write_report(r, 0, out / "r.html", progress=False)) for _ in range(args.runs))
    first, later = min(first_picture_extra() for _ in range(args.runs))
    print(f"{'200 frames -> GIF (960 x 540)':<34}{gif:>8.1f} s   target ≤ {GIF_TARGET_S:g} s   ({size:.2f} MB)")
    print(f"{'  the same with sensors typical':<34}{sensors:>8.1f} s   target ≤ {SENSORS_GIF_TARGET_S:g} s")
    print(f"{'200 frames -> MP4 (960 x 540)':<34}{mp4:>8.1f} s   (no target)")
    print(f"{'HTML report, 201 frames':<34}{report:>8.1f} s   target ≤ {REPORT_TARGET_S:g} s")
    print(
        f"{'first picture, fresh process':<34}{first:>8.2f} s   later {later:.2f} s: {first - later:+.2f} s"
        f"   target ≤ +{FIRST_EXTRA_TARGET_S:g} s"
    )


if __name__ == "__main__":
    main()
