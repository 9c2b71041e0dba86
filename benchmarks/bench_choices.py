"""Who blocks, who is looked for, and the area measure (``occluders=``, ``targets=``, ``measure=``), against the
default, on the crowded highway (benchmarks/bench.py) with N = 50 objects and a polygon column, one core, warm.

20 % of the objects (never the ego) are typed pedestrians; the time of each choice is printed beside its target.
Rerun: ``uv run python benchmarks/bench_choices.py [--frames 500] [--engine sweep]``.
"""

from __future__ import annotations

import argparse
import time

import numpy as np
import polars as pl
from bench import crowded_highway, with_polygons

from omega_prime_visibility import get_visibility_df


def typed(table: pl.DataFrame, share: float, seed: int = 1) -> pl.DataFrame:
    """``table`` with omega-prime ``type``/``subtype`` columns: a ``share`` of the idx (not 0) pedestrians."""
    ids = np.unique(table["idx"].to_numpy())
    rng = np.random.default_rng(seed)
    walkers = rng.choice(ids[1:], size=round(share * len(ids)), replace=False)
    is_walker = pl.col("idx").is_in(walkers.tolist())
    return table.with_columns(
        type=pl.when(is_walker).then(3).otherwise(2), subtype=pl.when(is_walker).then(0).otherwise(4)
    )


def best_of(repeat: int, **kwargs) -> tuple[float, int]:
    """Fastest of ``repeat`` warm runs, seconds, and the number of rows."""
    get_visibility_df(**kwargs)
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        out = get_visibility_df(**kwargs)
        times.append(time.perf_counter() - start)
    return min(times), out.height


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=500)
    parser.add_argument("--engine", default="sweep")
    parser.add_argument("--repeat", type=int, default=3)
    args = parser.parse_args()
    table = typed(with_polygons(crowded_highway(50, args.frames)), 0.2)
    ids = np.unique(table["idx"].to_numpy())
    few = np.random.default_rng(2).choice(ids[1:], size=5, replace=False).tolist()  # 10 % of the objects
    common = {"df": table, "ego_idx": 0, "engine": args.engine, "workers": 1, "progress": False}
    base, _rows = best_of(args.repeat, **common)
    print(f"crowded highway N = 50, polygon column, {args.frames} frames, engine {args.engine}, one core, warm")
    print(f"{'choice':<44}{'ms/frame':>10}{'x default':>11}   target")
    print(f"{'default (everything blocks, all targets)':<44}{1e3 * base / args.frames:>10.3f}{1.0:>11.2f}   -")
    cases = [
        ('occluders="vehicles" (20 % pedestrians)', {"occluders": "vehicles"}, "<= 1.00"),
        ("targets: 10 % of the objects", {"targets": few}, "<= 0.35"),
        ('measure="area"', {"measure": "area", "engine": None}, "<= 3.00"),
    ]
    for label, extra, target in cases:
        seconds, _ = best_of(args.repeat, **(common | extra))
        print(f"{label:<44}{1e3 * seconds / args.frames:>10.3f}{seconds / base:>11.2f}   {target}")


if __name__ == "__main__":
    main()
