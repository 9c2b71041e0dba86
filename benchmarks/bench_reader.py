"""Reading recordings: the MCAP reader of our own against omega-prime's ``Recording.from_file``, side by side on
the urban junction of ``scenarios/urban.py`` written as an MCAP file (600 frames, about 159,000 object rows), the
same messages as an OSI trace (``.osi``), and
from a path to the table in a fresh process (``run`` with the sweep engine, kernels compiled). Each figure is
printed next to its target (issue 41).

Usage::

    uv run python benchmarks/bench_reader.py [--frames 600] [--repeat 3]
"""

from __future__ import annotations

import argparse
import struct
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scenarios"))
from urban import urban_scene, write_mcap

REPO = Path(__file__).resolve().parent.parent


def best(function, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        function()
        times.append(time.perf_counter() - start)
    return min(times)


def fresh(*args: str) -> float:
    """Seconds of a fresh process running the command line ``args``."""
    start = time.perf_counter()
    subprocess.run([sys.executable, *args], check=True, capture_output=True, cwd=REPO)
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=600)
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    import omega_prime
    from mcap.reader import make_reader

    from omega_prime_visibility.inputs.osi_trace import read_osi
    from omega_prime_visibility.inputs.reader import read_mcap, warm_up

    warm_up()
    with tempfile.TemporaryDirectory() as folder:
        path, buildings = Path(folder) / "urban.mcap", Path(folder) / "buildings.wkt"
        table, blocks = urban_scene(frames=args.frames)
        write_mcap(table, path)
        buildings.write_text("".join(f"{g.wkt}\n" for g in blocks))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            theirs = best(lambda: omega_prime.Recording.from_file(str(path), compute_polygons=True), args.repeat)
        ours = best(lambda: read_mcap(path), args.repeat)
        rows = read_mcap(path)._df.height
        print(f"urban junction as MCAP: {rows} object rows, {path.stat().st_size / 1e6:.1f} MB")
        print(f"  omega-prime Recording.from_file: {theirs:.2f} s")
        print(f"  our reader:                      {ours:.2f} s, {theirs / ours:.1f}x faster (target: at least 10x)")
        trace = Path(folder) / "urban_gt.osi"  # the same messages, each preceded by its length
        with open(path, "rb") as f:
            messages = [m.data for _, _, m in make_reader(f).iter_messages(topics=["ground_truth"])]
        trace.write_bytes(b"".join(struct.pack("<I", len(m)) + m for m in messages))
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            theirs_osi = best(lambda: omega_prime.Recording.from_file(str(trace), compute_polygons=True), args.repeat)
        ours_osi = best(lambda: read_osi(trace), args.repeat)
        print(f"the same as an OSI trace: omega-prime {theirs_osi:.2f} s, ours {ours_osi:.2f} s, "
              f"{theirs_osi / ours_osi:.1f}x faster (target: at least 10x)")  # fmt: skip
        out = Path(folder) / "vis.parquet"
        cli = ["-m", "omega_prime_visibility.cli", "run", str(path), "--ego", "0", "--static", str(buildings)]
        cli += ["--engine", "sweep", "--no-progress", "-o", str(out)]
        fresh(*cli)  # kernels compiled, file in the page cache
        whole = min(fresh(*cli) for _ in range(args.repeat))
        print(
            f"  run, path to table (sweep, fresh process): {whole:.2f} s (targets: at most 3 s; at most a third of "
            f"omega-prime's reading, {theirs / 3:.2f} s)"
        )
        bundled = ["-m", "omega_prime_visibility.cli", "run", "highway_merge.mcap", "--engine", "sweep", "--rows", "0"]
        fresh(*bundled)
        print(f"  run of the bundled recording, warm: {min(fresh(*bundled) for _ in range(args.repeat)):.2f} s "
              "(target: at most 1.5 s)")  # fmt: skip
        importing = min(fresh("-c", "import omega_prime_visibility") for _ in range(args.repeat))
        print(f"  import omega_prime_visibility: {importing:.2f} s (target: at most 0.5 s)")


if __name__ == "__main__":
    main()
