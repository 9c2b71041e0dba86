"""Writing the MCAP of the answer (issue 51), printed next to its target: at most the time of computing the table
itself, on the bundled recording and on the urban junction of ``scenarios/urban.py`` (written as an omega-prime
MCAP first, its buildings as static occluders). Printed: the MCAP's writing (``write_mcap`` after the table, in
the same process, warm: each step once before it is timed), the table in that process, and ``run RECORDING --ego
0`` from the path in a fresh process (the issue's "today's run": reading, computing, printing; kernels compiled).

Usage::

    uv run python benchmarks/bench_export.py
"""

from __future__ import annotations

import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent / "scenarios"))
import urban  # noqa: E402

from omega_prime_visibility import get_visibility_df, write_mcap  # noqa: E402


def best(step, repeat: int = 2) -> tuple[float, object]:
    out, took = None, float("inf")
    for _ in range(repeat):
        start = time.perf_counter()
        out = step()
        took = min(took, time.perf_counter() - start)
    return took, out


def shell_run(path: Path, static: Path | None) -> float:
    """Seconds of ``omega-prime-visibility run PATH --ego 0`` in a fresh process."""
    command = [sys.executable, "-m", "omega_prime_visibility", "run", str(path), "--ego", "0", "--no-progress"]
    command += ["--static", str(static)] if static is not None else []
    subprocess.run(command, check=True, capture_output=True)  # (once: files in the page cache)
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True)
    return time.perf_counter() - start


def measure(name: str, path: Path, folder: Path, statics: dict, static_file: Path | None = None) -> None:
    took_run = shell_run(path, static_file)
    took_table, table = best(lambda: get_visibility_df(path, 0, progress=False, **statics))
    count = [0]

    def write() -> None:
        count[0] += 1
        write_mcap(path, table, folder / f"{path.stem}-{count[0]}.mcap", ego_idx=0,
                   static_occluder_polys=statics.get("static_occluder_polys", ()),
                   static_occluder_heights=statics.get("static_occluder_heights"))  # fmt: skip

    took_mcap, _ = best(write)
    mark = "ok" if took_mcap <= took_run else "MISSED"
    print(f"{name:<44} MCAP {took_mcap:6.2f} s   table {took_table:6.2f} s in process, run {took_run:6.2f} s   "
          f"target: MCAP <= run  {mark}")  # fmt: skip


def main() -> None:
    print("## Writing the MCAP of the answer (issue 51), warm, from the recording's path")
    with tempfile.TemporaryDirectory() as folder, warnings.catch_warnings():
        warnings.simplefilter("ignore")
        folder = Path(folder)
        measure("bundled highway_merge.mcap (201 frames)", HERE.parent / "highway_merge.mcap", folder, {})
        table, blocks = urban.urban_scene()
        town = folder / "urban.mcap"
        urban.write_mcap(table, town)
        statics = {"static_occluder_polys": blocks}
        wkt = folder / "buildings.wkt"
        wkt.write_text("".join(f"{g.wkt}\n" for g in blocks))
        measure("urban junction (600 frames, ~265 road users)", town, folder, statics, wkt)


if __name__ == "__main__":
    main()
