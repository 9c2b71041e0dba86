"""Cameras and lidars, printed next to their targets (issue 50), warm (kernels compiled), end to end through
``get_visibility_df(mode="3d")`` from a table in memory:

- a 1920 x 1080 camera (90° horizontal field of view, 1.5 m ahead of the ego's centre, 1.4 m up) on one core:
  µs per (frame, camera, target), target <= 50, in town (the urban junction of ``scenarios/urban.py``, its
  buildings with their heights, about 265 road users a frame) and among the 50 cars and trucks of the crowded
  highway;
- a 128-channel lidar with 2,048 azimuths (262,144 beams a turn, 120 m) on the roof: ms per frame, target <= 5;
- the six cameras and the lidar of the ``nuscenes`` layout over the town's 600 frames on two cores: s, target
  <= 30;
- against casting every pixel's ray one by one (the tests' brute-force caster, numpy, all bodies per ray) at
  480 x 270 on a few town frames: how many times faster the engine is at the same resolution.

Usage::

    uv run python benchmarks/bench_imaging.py [--frames 600]
"""

from __future__ import annotations

import argparse
import math
import sys
import time
import warnings
from pathlib import Path

import numpy as np
import polars as pl

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent / "scenarios"), str(HERE.parent / "tests")]
import imaging_reference as reference  # noqa: E402
from bench import crowded_highway  # noqa: E402
from urban import building_heights, urban_scene  # noqa: E402

from omega_prime_visibility import VisibilityInputWarning, get_visibility_df  # noqa: E402
from omega_prime_visibility.inputs.sensors import camera, lidar, nuscenes  # noqa: E402


def town(frames: int) -> tuple[pl.DataFrame, dict]:
    table, blocks = urban_scene(frames)
    return table, {"static_occluder_polys": blocks, "static_occluder_heights": building_heights(blocks)}


def highway(frames: int) -> pl.DataFrame:
    table = crowded_highway(50, frames)
    height = pl.when(pl.col("length") > 10).then(3.5).otherwise(1.5)
    return table.with_columns(height=height, z=height / 2, roll=pl.lit(0.0), pitch=pl.lit(0.0))


def timed(table: pl.DataFrame, sensors: list, workers: int = 1, **options) -> tuple[float, pl.DataFrame]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", VisibilityInputWarning)
        kw = dict(mode="3d", sensors=sensors, progress=False, workers=workers, **options)
        get_visibility_df(table.filter(pl.col("frame") < 2), 0, **kw)  # compiled, warm
        start = time.perf_counter()
        out = get_visibility_df(table, 0, **kw)
        return time.perf_counter() - start, out


def line(what: str, value: float, unit: str, target: float) -> None:
    mark = "ok" if value <= target else "MISSED"
    print(f"{what:<64} {value:9.2f} {unit:<6} target <= {target:g} {unit}  {mark}")


FRONT = camera("front", 1920, 1080, math.radians(90), x=1.5, z=1.4)
ROOF = lidar("roof", "os1-128", z=1.9, range=120.0)


def reference_ratio(table: pl.DataFrame, statics: dict, frames: int = 3) -> None:
    """The engine against the brute-force caster on the same 480 x 270 camera, the first ``frames`` town frames."""
    small = camera("front", 480, 270, math.radians(90), x=1.5, z=1.4)
    part = table.filter(pl.col("frame") < frames)
    took, out = timed(part, [small], **statics)
    blocks, heights = statics["static_occluder_polys"], statics["static_occluder_heights"]
    prisms = []
    for block, top in zip(blocks, heights, strict=True):  # the caster takes convex footprints: cut them
        from omega_prime_visibility.threed.bodies import convex_parts

        prisms += [(part_ring, 0.0, top) for part_ring in convex_parts(block)]
    start = time.perf_counter()
    image = small.camera
    for frame in range(frames):
        rows = part.filter(pl.col("frame") == frame).sort("idx")
        boxes = rows.select("x", "y", "z", "length", "width", "height", "roll", "pitch", "yaw").to_numpy()
        ego = rows.filter(pl.col("idx") == 0).row(0, named=True)
        heading = ego["yaw"]
        eye = np.array([ego["x"] + 1.5 * math.cos(heading), ego["y"] + 1.5 * math.sin(heading), 1.4])
        others = boxes[rows["idx"].to_numpy() != 0]
        rays = reference.camera_rays(image.width, image.height, image.fx, image.fy, image.cx, image.cy, heading, 0.0)
        counts = reference.cast(eye, rays, others, prisms)
        ours = out.filter(pl.col("frame") == frame).sort("idx")["pixels"].to_numpy()
        assert np.array_equal(ours, counts.first), "the engine and the caster disagree"
    slow = time.perf_counter() - start
    print(f"{'480 x 270 camera, town, vs the brute-force caster (same counts)':<64} {slow / took:9.0f} x faster "
          f"({took / frames * 1e3:.1f} ms against {slow / frames * 1e3:.0f} ms a frame)")  # fmt: skip


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=600, help="town frames (600: all of it)")
    args = parser.parse_args(argv)
    print("## Cameras and lidars (issue 50), warm, through get_visibility_df(mode='3d')")
    table, statics = town(args.frames)
    took, out = timed(table, [FRONT], **statics)
    line("1920 x 1080 camera, town, one core: per (frame, camera, target)", took / out.height * 1e6, "µs", 50)
    cars = highway(args.frames)
    took, out = timed(cars, [FRONT])
    line(
        "1920 x 1080 camera, crowded highway, one core: per (frame, camera, target)", took / out.height * 1e6, "µs", 50
    )
    took, out = timed(table, [ROOF], **statics)
    line("128-channel lidar, 2,048 azimuths, town, one core: per frame", took / args.frames * 1e3, "ms", 5)
    took, out = timed(cars, [ROOF])
    line("128-channel lidar, 2,048 azimuths, crowded highway, one core: per frame", took / args.frames * 1e3, "ms", 5)
    took, out = timed(table, nuscenes(), workers=2, **statics)
    line(f"six cameras and a lidar (nuscenes), town, {args.frames} frames, two cores", took, "s", 30)
    reference_ratio(table, statics)


if __name__ == "__main__":
    main()
