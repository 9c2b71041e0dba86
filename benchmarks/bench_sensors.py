"""Sensor benchmarks, printed next to their targets (``make bench`` runs them after ``bench.py``).

All figures on one core, warm (a first call compiles), end to end through ``get_visibility_df`` or
``visible_area_over_time``, on the crowded highway of ``bench.py`` given with a polygon column (what
``Recording.from_file(..., compute_polygons=True)`` gives):

- the sweep engine with the typical 6-sensor set: µs per (frame, target, sensor), target ≤ 3; with one 360°
  sensor at the centre (``roof``): µs per (frame, target), target within 10 % of the figure without sensors;
- the visible area of the typical set: ms of CPU per frame, target ≤ 2; alone (``visible_area_over_time`` without a
  road: the union's area only) and with the road area it hides (a road outline given: the union's geometry, as
  ``visible_area`` builds it, and its difference with the road);
- a city map: 5,000 building footprints over 10 km x 10 km and the crowded road through it; per-frame time with
  the typical set against the same scene with the buildings beyond 300 m of the ego removed, target ≤ 1.5x; and
  the same without a range (one 360° sensor without limit), where every building can matter.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import shapely
import shapely.affinity

sys.path.insert(0, str(Path(__file__).resolve().parent))
from bench import crowded_highway, with_polygons

from omega_prime_visibility import Sensor, VisibilityInputWarning, get_visibility_df
from omega_prime_visibility.analysis.area import visible_area_over_time


def best_of(fn, repeat: int = 3, clock=time.perf_counter) -> tuple[float, object]:
    """Best time (seconds; wall time, or ``clock``) of ``repeat`` calls after a warm-up call, and the last result."""
    out = fn()
    best = np.inf
    for _ in range(repeat):
        t = clock()
        out = fn()
        best = min(best, clock() - t)
    return best, out


def city(n_buildings: int, seed: int = 1) -> list[shapely.Polygon]:
    """Building footprints (10-40 m squares, random orientation) spread over 10 km x 10 km around the origin,
    none on the road corridor (|y - 5| < 20 m) the traffic drives along."""
    rng = np.random.default_rng(seed)
    out = []
    while len(out) < n_buildings:
        x, y = rng.uniform(-5000, 5000, 2)
        if abs(y - 5) < 20:
            continue
        size = rng.uniform(10, 40)
        box = shapely.box(x - size / 2, y - size / 2, x + size / 2, y + size / 2)
        out.append(shapely.affinity.rotate(box, rng.uniform(0, 90)))
    return out


def row(label: str, figure: float, unit: str, target: str) -> None:
    print(f"{label:<58}{figure:>10.2f} {unit:<22}{target}")


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--n", type=int, default=50)
    args = parser.parse_args(argv)
    warnings.simplefilter("ignore", VisibilityInputWarning)

    table = with_polygons(crowded_highway(args.n, args.frames))
    run = {"engine": "sweep", "workers": 1, "progress": False}
    print(f"sensors: crowded highway N={args.n}, {args.frames} frames, polygon column, sweep, one core, warm, CPU time")
    # CPU time, best of 5: one process, one thread, so the wall time on a quiet machine, and steadier on a busy one
    cpu = {"repeat": 5, "clock": time.process_time}
    plain, out = best_of(lambda: get_visibility_df(table, 0, **run), **cpu)
    per_target = plain / out.height * 1e6
    row("no sensors (the observer's centre, all around)", per_target, "µs/(frame, target)", "(reference)")
    roofed, out = best_of(lambda: get_visibility_df(table, 0, sensors="roof", **run), **cpu)
    ratio = roofed / plain
    row("roof: one 360° sensor at the centre", roofed / out.height * 1e6, "µs/(frame, target)", f"x{ratio:.2f} ≤ 1.10")
    typical, out = best_of(lambda: get_visibility_df(table, 0, sensors="typical", **run), **cpu)
    row("typical: 6 sensors", typical / out.height * 1e6, "µs/(frame, target, sensor)", "≤ 3")
    area, out = best_of(lambda: visible_area_over_time(table, 0, "typical"), clock=time.process_time)
    row("visible area of the typical set", area / out.height * 1e3, "ms/frame", "≤ 2")
    road = shapely.box(-250.0, -1.75, 250.0, 12.25)  # the four lanes
    area, out = best_of(lambda: visible_area_over_time(table, 0, "typical", road=road), clock=time.process_time)
    row("  with the hidden road area: the union's geometry", area / out.height * 1e3, "ms/frame", "≤ 2")

    buildings = city(5000)
    ego_track = table.filter(table["idx"] == 0)
    ego = shapely.points(np.c_[ego_track["x"], ego_track["y"]])
    reach = shapely.buffer(shapely.multipoints(shapely.get_coordinates(ego)), 300.0)
    near = [b for b in buildings if b.intersects(reach)]
    print(f"city map: {len(buildings)} buildings over 10 km x 10 km ({len(near)} within 300 m of the ego's track)")
    full, _ = best_of(lambda: get_visibility_df(table, 0, buildings, sensors="typical", **run), repeat=1)
    cropped, _ = best_of(lambda: get_visibility_df(table, 0, near, sensors="typical", **run), repeat=1)
    row("typical set, whole map", full / args.frames * 1e3, "ms/frame", "")
    row("typical set, buildings beyond 300 m removed", cropped / args.frames * 1e3, "ms/frame", "")
    row("  ratio", full / cropped, "x", "≤ 1.5")
    unlimited, _ = best_of(
        lambda: get_visibility_df(table, 0, buildings, sensors=Sensor("all_around"), **run), repeat=1
    )
    row("one 360° sensor without range, whole map", unlimited / args.frames * 1e3, "ms/frame", "(every building)")


if __name__ == "__main__":
    main()
