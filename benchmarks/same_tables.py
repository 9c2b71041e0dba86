"""Check that a change leaves the output identical to the bit: compute a fixed set of tables with one version of the
package and compare them with another's (``polars.DataFrame.equals``).

Scenes: the bundled and the upstream ``highway_merge.mcap`` (every object as observer, with the upstream README's
wall, both engines), random crowded highways (:func:`bench.crowded_highway`, with and without a polygon column,
overlapping vehicles), the tidy synthetic highway with every object as observer, and the urban junction of
``scenarios/urban.py`` with its buildings (the ego, and every road user on a few frames; both engines); in 3D, both
engines on the bundled recording, the crowded highway's typical sensor set and the town with its buildings' heights.

Usage (the reference from an older commit, unpacked outside the repository)::

    git archive <commit> | tar -x -C /tmp/base
    PYTHONPATH=/tmp/base uv run python benchmarks/same_tables.py --write /tmp/tables --data ../shared/data
    uv run python benchmarks/same_tables.py --compare /tmp/tables
"""

from __future__ import annotations

import argparse
import sys
import warnings
from collections.abc import Iterator
from pathlib import Path

import polars as pl
import shapely

sys.path.insert(0, str(Path(__file__).resolve().parent))
sys.path.insert(0, str(Path(__file__).resolve().parent.parent / "scenarios"))
from bench import crowded_highway, synthetic_highway, with_polygons
from urban import urban_scene

REPO = Path(__file__).resolve().parent.parent
SHARED_DATA = REPO.parent / "shared" / "data"
WALL = shapely.from_wkt("POLYGON ((-220 10, -120 10, -120 0, -220 0, -220 10))")


def tables(data: Path) -> Iterator[tuple[str, pl.DataFrame]]:
    """``(name, table)`` for every checked case, computed with the package on ``sys.path``."""
    import omega_prime

    from omega_prime_visibility import VisibilityInputWarning, get_visibility_df

    warnings.simplefilter("ignore", VisibilityInputWarning)
    recordings = [("bundled", REPO / "highway_merge.mcap"), ("upstream", data / "highway_merge.mcap")]
    for name, path in recordings:
        if not path.exists():
            print(f"skipped {path} (absent)")
            continue
        df = omega_prime.Recording.from_file(str(path), compute_polygons=True)._df
        for engine in ("visilibity", "sweep"):
            yield f"{name}-all-{engine}", get_visibility_df(df, "all", engine=engine, progress=False, workers=1)
            yield f"{name}-wall-{engine}", get_visibility_df(df, 0, [WALL], engine=engine, progress=False, workers=1)
    for seed in range(3):
        boxes = crowded_highway(50, 60, seed=seed)
        for label, table in (("polygons", with_polygons(boxes)), ("boxes", boxes)):
            for engine in ("visilibity", "sweep"):
                out = get_visibility_df(table, 0, engine=engine, progress=False, workers=1)
                yield f"crowded-{seed}-{label}-{engine}", out
        yield f"crowded-{seed}-all-sweep", get_visibility_df(boxes, "all", engine="sweep", workers=1, progress=False)
    yield "tidy-all-sweep", get_visibility_df(synthetic_highway(50, 100), "all", engine="sweep", progress=False)
    town, buildings = urban_scene(frames=40)
    few = town.filter(pl.col("frame").is_in([0, 25]))
    for engine in ("visilibity", "sweep"):
        yield f"urban-ego-{engine}", get_visibility_df(town, 0, buildings, engine=engine, progress=False, workers=1)
        yield f"urban-all-{engine}", get_visibility_df(few, "all", buildings, engine=engine, progress=False, workers=1)
    try:  # sensors (from stop 21 on)
        from omega_prime_visibility import Sensor
    except ImportError:
        return
    offset = [Sensor("nose", x=2.0, y=0.4, yaw=0.3), Sensor("tail", x=-2.0)]  # all around, without range
    boxes = with_polygons(crowded_highway(50, 60, seed=4))
    for sensors in ("roof", "typical"):
        for engine in ("visilibity", "sweep"):
            out = get_visibility_df(boxes, 0, engine=engine, progress=False, workers=1, sensors=sensors)
            yield f"crowded-4-{sensors}-{engine}", out
    yield "crowded-4-offset-sweep", get_visibility_df(boxes, 0, engine="sweep", progress=False, sensors=offset)
    yield "crowded-4-all-roof-sweep", get_visibility_df(boxes, "all", engine="sweep", progress=False, sensors="roof")
    bundled = omega_prime.Recording.from_file(str(REPO / "highway_merge.mcap"), compute_polygons=True)._df
    for engine in ("visilibity", "sweep"):
        out = get_visibility_df(bundled, "all", [WALL], engine=engine, progress=False, workers=1, sensors=offset)
        yield f"bundled-all-offset-wall-{engine}", out
    # 3D: both engines on the bundled recording (every object as observer), the crowded highway's sensors and the
    # town's buildings raised to their heights
    from urban import building_heights

    heights = building_heights(buildings)
    tall = pl.col("idx") % 7 * 0.25 + 1.4  # cars and vans of 1.4 to 2.9 m, on the ground
    raised = crowded_highway(50, 60, seed=4).with_columns(height=tall, z=tall / 2, roll=pl.lit(0.0), pitch=pl.lit(0.0))
    for engine in ("silhouette3d", "raycast3d"):
        three = {"engine": engine, "mode": "3d", "progress": False, "workers": 1}
        yield f"bundled-all-{engine}", get_visibility_df(bundled, "all", **three)
        yield f"crowded-4-typical-{engine}", get_visibility_df(raised, 0, sensors="typical", **three)
        yield f"urban-ego-{engine}", get_visibility_df(town, 0, buildings, static_occluder_heights=heights, **three)


def main(argv: list[str] | None = None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    mode = parser.add_mutually_exclusive_group(required=True)
    mode.add_argument("--write", type=Path, help="write the reference tables to this folder")
    mode.add_argument("--compare", type=Path, help="compare with the tables in this folder")
    parser.add_argument("--data", type=Path, default=SHARED_DATA, help="folder of the upstream highway_merge.mcap")
    args = parser.parse_args(argv)
    differ = 0
    for name, table in tables(args.data):
        path = (args.write or args.compare) / f"{name}.parquet"
        if args.write:
            args.write.mkdir(parents=True, exist_ok=True)
            table.write_parquet(path)
            print(f"wrote {name}: {table.height} rows")
            continue
        same = path.exists() and pl.read_parquet(path).equals(table)
        differ += not same
        print(f"{name:<32} {table.height:>8} rows  {'identical' if same else 'DIFFERENT'}")
    if args.compare:
        print("all identical" if not differ else f"{differ} table(s) differ")
        raise SystemExit(1 if differ else 0)


if __name__ == "__main__":
    main()
