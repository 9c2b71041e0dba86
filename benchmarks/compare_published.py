"""Compare this package with the published ``omega-prime-visibility==0.1.0`` on speed, accuracy and robustness.

Both distributions import as ``omega_prime_visibility``, so the published one lives in its own throwaway environment
and is only ever run in a subprocess with that environment's interpreter. Set it up once (it is never a dependency of
this project)::

    uv venv /tmp/pub --python python3
    printf '[extra-build-dependencies]\\nvisilibity = ["swig"]\\n' > /tmp/pub-uv.toml   # visilibity builds with SWIG
    uv pip install --python /tmp/pub/bin/python --config-file /tmp/pub-uv.toml omega-prime-visibility==0.1.0

This file has two modes.

Runner (with the published package's interpreter)::

    /tmp/pub/bin/python benchmarks/compare_published.py --input TABLE.parquet|REC.mcap --ego 0 \\
        [--static-wkt WKT ...] --out OUT.parquet

reads a moving-object table (parquet with ``frame, total_nanos, idx, x, y, length, width, yaw``; box outlines are
built with the corners of omega-prime's ``bbx_to_polygon``, as ``Recording.from_file(..., compute_polygons=True)``
does) or an omega-prime MCAP, runs the published ``get_visibility_df`` on it and writes its table (``frame, idx,
visibility, occluder_idxs, static_occluder_idxs``) to ``OUT.parquet`` and the wall time and failures to ``OUT.json``.

Driver (with ours)::

    uv run python benchmarks/compare_published.py --driver [--published-python /tmp/pub/bin/python]

builds the scenes, times every engine of ours and the published package on exactly the same polars table (with the
same ``polygon`` column), scores both against the independent brute-force ray caster in ``tests/reference.py``, runs
the robustness cases and prints markdown tables.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import subprocess
import sys
import tempfile
import time
import warnings
from collections import Counter
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
import polars as pl
import shapely

REPO = Path(__file__).resolve().parent.parent
UPSTREAM_MCAP = REPO.parent / "shared" / "data" / "highway_merge.mcap"
WALL_WKT = "POLYGON ((-220 10, -120 10, -120 0, -220 0, -220 10))"
OUT_COLUMNS = ["frame", "idx", "visibility", "occluder_idxs", "static_occluder_idxs"]
OFF = 0.05  # a row is "off" when its visibility is wrong by more than this
TINY = 1e-3  # occluders blocking less than this share of the extent may be missed by the reference's rays


# ----------------------------------------------------------------------------------------------------------------
# Shared: reading an input table
# ----------------------------------------------------------------------------------------------------------------


def box_polygons(df: pl.DataFrame) -> pl.DataFrame:
    """Add a ``polygon`` column of shapely boxes from ``x, y, length, width, yaw``.

    Same corners in the same (clockwise) order as omega-prime's ``bbx_to_polygon`` (what
    ``Recording.from_file(..., compute_polygons=True)`` uses); rows with a NaN or infinite pose, for which
    omega-prime raises, get an empty polygon instead.
    """
    x, y, length, width, yaw = (df[c].cast(pl.Float64).to_numpy() for c in ("x", "y", "length", "width", "yaw"))
    dxl, dxw = length / 2 * np.cos(yaw), width / 2 * np.sin(yaw)
    dyl, dyw = length / 2 * np.sin(yaw), width / 2 * np.cos(yaw)
    corners = [(dxl - dxw, dyl + dyw), (dxl + dxw, dyl - dyw), (-dxl + dxw, -dyl - dyw), (-dxl - dxw, -dyl + dyw)]
    ring = np.stack([np.column_stack([x + dx, y + dy]) for dx, dy in corners], axis=1)
    finite = np.isfinite(ring).all(axis=(1, 2))
    polys = np.full(len(ring), shapely.Polygon(), dtype=object)
    polys[finite] = shapely.polygons(ring[finite])
    return df.with_columns(pl.Series("polygon", list(polys), dtype=pl.Object))


def load_table(path: str) -> pl.DataFrame:
    """The moving-object table of a parquet file or an MCAP, with a ``polygon`` column of shapely polygons."""
    if path.endswith(".mcap"):
        import omega_prime

        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return omega_prime.Recording.from_file(path, compute_polygons=True)._df
    return box_polygons(pl.read_parquet(path))


# ----------------------------------------------------------------------------------------------------------------
# Runner: the published package, in its own interpreter
# ----------------------------------------------------------------------------------------------------------------


def run_published(args: argparse.Namespace) -> None:
    """Run the published ``get_visibility_df`` on one input and write its table and timing.

    Whole table first (a warm-up on two frames, then up to ``--repeat`` timed calls). With ``--per-frame``, or when
    the whole call raises, ``get_visibility_df_for_frame`` runs frame by frame with exceptions caught per frame, and
    every frame's start and result are appended to ``OUT.jsonl`` as they happen, so that the driver can tell which
    frame killed the interpreter and resume after it.
    """
    import importlib.metadata

    import omega_prime_visibility as pub

    version = importlib.metadata.version("omega-prime-visibility")
    if Path(pub.__file__).resolve().is_relative_to(REPO):
        raise SystemExit(f"imported this repository's package ({pub.__file__}), not the published one")
    df = load_table(args.input)
    statics = [shapely.from_wkt(w) for w in args.static_wkt] or None
    ego_frames = df.filter(pl.col("idx") == args.ego)["frame"].unique().sort().to_list()
    if args.frames_only:
        wanted = set(args.frames_only)
        ego_frames = [f for f in ego_frames if f in wanted]
    meta: dict = {"version": version, "module": pub.__file__, "mode": "whole", "error": None, "crashed_frames": {}}
    out = None
    with warnings.catch_warnings(record=True) as log:
        warnings.simplefilter("always")
        if not args.per_frame:
            try:
                warm = df.filter(pl.col("frame").is_in(ego_frames[:2]))
                pub.get_visibility_df(warm, args.ego, statics, hide_progress=True)
                best, spent = np.inf, 0.0
                for _ in range(args.repeat):
                    t = time.perf_counter()
                    out = pub.get_visibility_df(df, args.ego, statics, hide_progress=True)
                    elapsed = time.perf_counter() - t
                    best, spent = min(best, elapsed), spent + elapsed
                    if spent > args.budget:
                        break
                meta["seconds"] = best
            except Exception as exc:
                meta["error"] = f"{type(exc).__name__}: {exc}"[:300]
                out = None
        if out is None:  # frame by frame, so that one bad frame does not lose the others
            meta["mode"] = "per-frame"
            parts, seconds = [], 0.0
            with Path(args.out).with_suffix(".jsonl").open("a") as progress:
                for f in ego_frames:
                    progress.write(json.dumps({"start": f}) + "\n")
                    progress.flush()
                    t = time.perf_counter()
                    try:
                        part = pub.get_visibility_df_for_frame(df, args.ego, f, statics)
                    except Exception as exc:
                        meta["crashed_frames"][str(f)] = f"{type(exc).__name__}: {exc}"[:200]
                        progress.write(json.dumps({"done": f, "error": meta["crashed_frames"][str(f)]}) + "\n")
                        continue
                    seconds += time.perf_counter() - t
                    rows = part.select(OUT_COLUMNS[1:]).rows() if part.height else []
                    progress.write(json.dumps({"done": f, "seconds": time.perf_counter() - t, "rows": rows}) + "\n")
                    progress.flush()
                    if part.height:
                        parts.append(part.select(OUT_COLUMNS))
            meta["seconds"] = seconds
            out = pl.concat(parts, how="vertical_relaxed") if parts else None
        caught = Counter(f"{w.category.__name__}: {str(w.message)[:60]}" for w in log)
    if out is None:
        out = pl.DataFrame(schema={"frame": pl.Int64, "idx": pl.Int64, "visibility": pl.Float64})
    out = out.select([c for c in OUT_COLUMNS if c in out.columns])
    out.write_parquet(args.out)
    meta.update(rows=out.height, ego_frames=len(ego_frames), warnings=dict(caught))
    Path(args.out).with_suffix(".json").write_text(json.dumps(meta, indent=1))


# ----------------------------------------------------------------------------------------------------------------
# Driver: scenes, our package, the subprocess, the reference and the tables
# ----------------------------------------------------------------------------------------------------------------


@dataclass
class Scene:
    name: str
    source: str  # path given to the runner (MCAP or parquet)
    ego: int
    statics_wkt: list[str] = field(default_factory=list)
    note: str = ""


@dataclass
class Result:
    """One package (or engine) on one scene."""

    package: str
    out: pl.DataFrame | None
    seconds: float | None
    crashes: str
    mode: str = ""
    warnings: dict = field(default_factory=dict)


def box_rows(boxes: list[tuple[int, int, float, float, float, float, float]]) -> pl.DataFrame:
    """A table from ``(frame, idx, x, y, length, width, yaw)`` tuples."""
    cols = list(zip(*boxes, strict=True))
    return pl.DataFrame(
        {
            "frame": pl.Series(cols[0], dtype=pl.Int64),
            "total_nanos": pl.Series([f * 40_000_000 for f in cols[0]], dtype=pl.Int64),
            "idx": pl.Series(cols[1], dtype=pl.Int64),
            "x": pl.Series(cols[2], dtype=pl.Float64),
            "y": pl.Series(cols[3], dtype=pl.Float64),
            "length": pl.Series(cols[4], dtype=pl.Float64),
            "width": pl.Series(cols[5], dtype=pl.Float64),
            "yaw": pl.Series(cols[6], dtype=pl.Float64),
        }
    )


def robustness_tables() -> dict[str, tuple[pl.DataFrame, str]]:
    """Small 3-frame scenes (ego idx 0 at the origin, 4.5 m x 1.9 m, things moving +1 m per frame)."""
    car = (4.5, 1.9, 0.0)

    def frames(objs: list[tuple[int, float, float, tuple[float, float, float]]], drop=(), nan_ego=()) -> pl.DataFrame:
        rows = []
        for f in range(3):
            for i, x, y, (length, width, yaw) in objs:
                if (f, i) in drop:
                    continue
                xx = np.nan if (i == 0 and f in nan_ego) else x + f
                rows.append((f, i, xx, y, length, width, yaw))
        return box_rows(rows)

    base = [(0, 0.0, 0.0, car), (1, 15.0, 0.0, car), (2, 30.0, 0.5, car), (3, 10.0, 3.5, car)]
    return {
        "frame 1 holds only the ego": (frames(base, drop={(1, 1), (1, 2), (1, 3)}), ""),
        "NaN ego position in frame 1 (empty polygon)": (frames(base, nan_ego={1}), ""),
        "two targets overlap each other": (
            frames([*base[:2], (2, 16.5, 1.0, car), (3, 30.0, 0.0, car)]),
            "idx 1 and 2 overlap",
        ),
        "a target overlaps the ego's box": (
            frames([base[0], (1, 3.5, 1.0, car), (2, 20.0, 1.0, car), (3, 10.0, -3.5, car)]),
            "idx 1 overlaps the ego, observer outside it",
        ),
        "observer inside another object": (
            frames([base[0], (1, 2.0, 0.0, (12.0, 2.5, 0.0)), (2, 20.0, 0.0, car), (3, 10.0, 4.0, car)]),
            "idx 1 covers the observer; ours and the reference treat it as transparent",
        ),
    }


def subprocess_env() -> dict[str, str]:
    """Our environment minus whatever points Python at this project's venv."""
    drop = ("VIRTUAL_ENV", "PYTHONPATH", "PYTHONHOME", "UV_PROJECT_ENVIRONMENT", "CONDA_PREFIX")
    return {k: v for k, v in os.environ.items() if k not in drop}


def call_runner(
    python: str, scene: Scene, workdir: Path, per_frame: bool = False, frames: list[int] | None = None
) -> tuple[int, dict, str, list[dict]]:
    """One runner subprocess: return code, its JSON (with the table as ``meta["table"]``), stderr, progress lines."""
    out = workdir / f"pub_{abs(hash((scene.name, per_frame, str(frames)))):x}.parquet"
    for suffix in (".parquet", ".json", ".jsonl"):
        out.with_suffix(suffix).unlink(missing_ok=True)
    cmd = [python, str(Path(__file__).resolve()), "--input", scene.source, "--ego", str(scene.ego), "--out", str(out)]
    for w in scene.statics_wkt:
        cmd += ["--static-wkt", w]
    if per_frame:
        cmd.append("--per-frame")
    if frames is not None:
        cmd += ["--frames-only", *map(str, frames)]
    proc = subprocess.run(cmd, capture_output=True, text=True, cwd=workdir, env=subprocess_env(), timeout=900)
    meta = json.loads(out.with_suffix(".json").read_text()) if proc.returncode == 0 else {}
    if proc.returncode == 0:
        meta["table"] = pl.read_parquet(out)
    jsonl = out.with_suffix(".jsonl")
    progress = [json.loads(line) for line in jsonl.read_text().splitlines() if line.strip()] if jsonl.exists() else []
    return proc.returncode, meta, proc.stderr, progress


def describe_rc(rc: int, stderr: str = "") -> str:
    """What a failed subprocess died of, with the last line it printed."""
    if rc < 0:
        try:
            what = f"interpreter killed by {signal.Signals(-rc).name}"
        except ValueError:
            what = f"interpreter killed by signal {-rc}"
    else:
        what = f"interpreter exited with status {rc}"
    last = stderr.strip().splitlines()[-1:]
    return what + (f" ({last[0].strip()[:100]})" if last else "")


def run_published_side(python: str, scene: Scene, df: pl.DataFrame, workdir: Path) -> Result:
    """The published package via its own interpreter.

    Whole table first. If that raises, the runner itself goes on frame by frame; if the interpreter dies, the
    frames are run frame by frame in a new process, and after each death again from the frame after the one that
    killed it, so that every crashing frame is counted and all others are scored.
    """
    package = "published 0.1.0"
    rc, meta, err, progress = call_runner(python, scene, workdir)
    if rc == 0 and meta["mode"] == "whole":
        table = meta["table"]
        return Result(package, table, meta["seconds"], "0", "whole", meta.get("warnings", {}))
    whole_error = meta.get("error") if rc == 0 else describe_rc(rc, err)
    frames = df.filter(pl.col("idx") == scene.ego)["frame"].unique().sort().to_list()
    done: dict[int, dict] = {}
    crashed: dict[int, str] = {}
    warns: Counter[str] = Counter(meta.get("warnings", {}))
    calls = 0
    while True:
        started = None
        for entry in progress:
            if "start" in entry:
                started = entry["start"]
            else:
                done[entry["done"]] = entry
                started = None
        if rc != 0 and started is not None:
            crashed[started] = describe_rc(rc, err)
        elif rc != 0 and calls:  # died outside any frame: give up on the rest
            crashed.update({f: describe_rc(rc, err) for f in frames if f not in done and f not in crashed})
        remaining = [f for f in frames if f not in done and f not in crashed]
        if not remaining or calls > len(frames):
            break
        rc, meta, err, progress = call_runner(python, scene, workdir, per_frame=True, frames=remaining)
        warns.update(meta.get("warnings", {}))
        calls += 1
    rows = [(f, *row) for f, entry in sorted(done.items()) if "rows" in entry for row in entry["rows"]]
    crashed.update({f: e["error"] for f, e in done.items() if "error" in e})
    schema = {
        "frame": pl.Int64,
        "idx": pl.Int64,
        "visibility": pl.Float64,
        "occluder_idxs": pl.List(pl.Int64),
        "static_occluder_idxs": pl.List(pl.Int64),
    }
    table = pl.DataFrame(rows, schema=schema, orient="row")
    parts = [f"whole call failed: {whole_error}"] if whole_error else []
    if crashed:
        kinds = Counter(v.split(":")[0].split(" (")[0] for v in crashed.values())
        first_f, first_v = min(crashed.items())
        parts.append(
            f"{len(crashed)} of {len(frames)} frames failed: "
            + ", ".join(f"{k} x{n}" for k, n in kinds.items())
            + f" (first, frame {first_f}: {first_v[:120]})"
        )
    seconds = sum(e.get("seconds", 0.0) for e in done.values())
    return Result(package, table, seconds, "; ".join(parts) or "0", "frame by frame", dict(warns))


def run_ours(df: pl.DataFrame, scene: Scene, engine: str, repeat: int = 3) -> Result:
    from omega_prime_visibility import get_visibility_df

    statics = [shapely.from_wkt(w) for w in scene.statics_wkt] or None
    caught: Counter[str] = Counter()
    with warnings.catch_warnings(record=True) as log:
        warnings.simplefilter("always")
        try:
            get_visibility_df(df, scene.ego, statics, engine=engine, progress=False)  # warm-up / numba compile
            best = np.inf
            for _ in range(repeat):
                t = time.perf_counter()
                out = get_visibility_df(df, scene.ego, statics, engine=engine, progress=False)
                best = min(best, time.perf_counter() - t)
        except Exception as exc:
            return Result(f"ours ({engine})", None, None, f"{type(exc).__name__}: {str(exc)[:150]}")
        caught.update(f"{w.category.__name__}: {str(w.message)[:60]}" for w in log)
    return Result(f"ours ({engine})", out.select(OUT_COLUMNS), best, "0", warnings=dict(caught))


FrameGeometry = dict[int, tuple[np.ndarray, dict[int, shapely.Geometry]]]


def reference_table(
    df: pl.DataFrame, scene: Scene, frames: list[int], n_rays: int
) -> tuple[pl.DataFrame, FrameGeometry]:
    """Brute-force visibility and occluders of every target of the given frames (observer: ego centre).

    Objects with an unusable row (NaN pose) are left out; objects covering the observer are transparent (as the ego),
    and get visibility NaN and ``inside=True``. Also returns each frame's observer and outlines by idx.
    """
    from reference import reference_visibility

    statics = [shapely.from_wkt(w) for w in scene.statics_wkt]
    rows, geometry = [], {}
    for f in frames:
        fr = df.filter(pl.col("frame") == f).sort("idx")
        ok = np.isfinite(fr["x"].to_numpy()) & np.isfinite(fr["y"].to_numpy())
        fr = fr.filter(pl.Series(ok))
        ego = fr.filter(pl.col("idx") == scene.ego)
        if ego.height == 0:
            continue
        observer = ego.select("x", "y").to_numpy()[0]
        polys = list(fr["polygon"])
        idx = fr["idx"].to_list()
        geometry[f] = (observer, dict(zip(idx, polys, strict=True)))
        inside = np.asarray(shapely.intersects(np.asarray(polys, dtype=object), shapely.Point(observer)), dtype=bool)
        transparent = inside | (fr["idx"] == scene.ego).to_numpy()
        ref = reference_visibility(observer, polys, statics, transparent, n_rays=n_rays)
        for k, i in enumerate(idx):
            if i == scene.ego:
                continue
            occ = {idx[j]: v for j, v in ref.occluders[k].items()}
            rows.append(
                {
                    "frame": f,
                    "idx": i,
                    "ref": float(ref.visibility[k]),
                    "inside": bool(inside[k]),
                    "ref_occ": json.dumps({str(j): v for j, v in occ.items()}),
                    "ref_static": json.dumps({str(j): v for j, v in ref.static_occluders[k].items()}),
                }
            )
    schema = {"frame": pl.Int64, "idx": pl.Int64, "ref": pl.Float64, "inside": pl.Boolean}
    return pl.DataFrame(rows, schema={**schema, "ref_occ": pl.String, "ref_static": pl.String}), geometry


def blocks_somewhere(observer: np.ndarray, blocker: shapely.Geometry, target: shapely.Polygon, n: int = 20001) -> bool:
    """Focused ray cast: is ``blocker`` hit strictly before ``target`` along some direction?

    For an occluder the reference's evenly spread rays missed: ``n`` rays through the part of the target's angular
    extent that the blocker's extent overlaps (the whole target extent for a non-polygon or observer-covering
    blocker), against these two geometries only.
    """
    from reference import angular_extent_reference, nearest_hit_distances

    t_start, t_width = angular_extent_reference(observer, target)
    windows = [(0.0, t_width)]
    if isinstance(blocker, shapely.Polygon) and not blocker.intersects(shapely.Point(observer)):
        b_start, b_width = angular_extent_reference(observer, blocker)
        d = (b_start - t_start) % (2 * np.pi)
        windows = [(max(0.0, s), min(t_width, s + b_width)) for s in (d, d - 2 * np.pi)]
    for lo, hi in windows:
        if hi <= lo:
            continue
        angles = t_start + lo + (np.arange(n) + 0.5) * ((hi - lo) / n)
        dist = nearest_hit_distances(observer, [blocker, target], angles)
        if np.any(dist[:, 0] < dist[:, 1] - 1e-9 * (1.0 + dist[:, 1])):
            return True
    return False


def occluders_consistent(
    got: list | None, want_json: str, observer: np.ndarray, target: shapely.Polygon, blockers: dict
) -> bool:
    """Every occluder the reference sees blocking more than TINY of the extent is listed, and every listed one
    blocks along some direction: seen by the reference's rays, or else by :func:`blocks_somewhere`.

    ``blockers`` maps the ids the lists use (object idx or static position) to geometries."""
    want = {int(k): v for k, v in json.loads(want_json).items()}
    have = set(got or [])
    if not {k for k, v in want.items() if v > TINY} <= have:
        return False
    return all(k in blockers and blocks_somewhere(observer, blockers[k], target) for k in have - set(want))


def score(res: Result, ref: pl.DataFrame, geometry: FrameGeometry, statics: list[shapely.Geometry]) -> dict:
    """Accuracy of one result on the reference rows (rows covering the observer excluded)."""
    scored = ref.filter(~pl.col("inside"))
    if res.out is None:
        return {"checked": 0, "missing": scored.height}
    out = res.out.with_columns(pl.col("frame").cast(pl.Int64), pl.col("idx").cast(pl.Int64))
    j = scored.join(out, on=["frame", "idx"], how="left")
    have = j.filter(pl.col("visibility").is_not_null() & pl.col("visibility").is_not_nan())
    err = (have["visibility"] - have["ref"]).abs().to_numpy()
    cols = ("frame", "idx", "occluder_idxs", "ref_occ", "static_occluder_idxs", "ref_static")
    static_map = dict(enumerate(statics))
    occ = []
    for f, i, a, b, c, d in zip(*(have[c].to_list() for c in cols), strict=True):
        o, polys = geometry[f]
        occ.append(
            occluders_consistent(a, b, o, polys[i], polys) and occluders_consistent(c, d, o, polys[i], static_map)
        )
    return {
        "checked": have.height,
        "missing": j.height - have.height,
        "mae": float(err.mean()) if len(err) else np.nan,
        "off": float((err > OFF).mean()) if len(err) else np.nan,
        "max": float(err.max()) if len(err) else np.nan,
        "occ": float(np.mean(occ)) if occ else np.nan,
    }


def pick_frames(df: pl.DataFrame, ego: int, max_rows: int) -> list[int]:
    """Evenly spaced ego frames holding at most ``max_rows`` target rows in all."""
    frames = df.filter(pl.col("idx") == ego)["frame"].unique().sort().to_numpy()
    per_frame = df.filter(pl.col("frame").is_in(frames)).group_by("frame").len()["len"].max() - 1
    k = int(min(len(frames), max(1, max_rows // max(per_frame, 1))))
    return sorted({int(frames[i]) for i in np.linspace(0, len(frames) - 1, k).round().astype(int)})


def fmt(v: float | None, spec: str) -> str:
    return "–" if v is None or not np.isfinite(v) else format(v, spec)


def driver(args: argparse.Namespace) -> None:
    os.environ.setdefault("NUMBA_NUM_THREADS", "1")
    sys.path[:0] = [str(REPO / "benchmarks"), str(REPO / "tests")]
    from bench import synthetic_highway

    import omega_prime_visibility as ours

    if not Path(ours.__file__).resolve().is_relative_to(REPO):
        raise SystemExit(f"driver imported {ours.__file__}, not this repository's package: run it with `uv run`")
    engines = args.engines.split(",") if args.engines else sorted(ours.ENGINES)
    python = args.published_python
    have_pub = Path(python).exists()
    if not have_pub:
        print(f"NOTE: {python} not found: the published package is skipped (see the module docstring to set it up)\n")
    else:
        probe = "import importlib.metadata as m; print(m.version('omega-prime-visibility'))"
        version = subprocess.run([python, "-c", probe], capture_output=True, text=True, env=subprocess_env())
        print(f"published: omega-prime-visibility {version.stdout.strip() or '?'} run by {python}")
    print(f"ours: {ours.__file__} (engines {', '.join(engines)})\n", flush=True)
    workdir = Path(args.workdir or tempfile.mkdtemp(prefix="compare_published_"))
    workdir.mkdir(parents=True, exist_ok=True)
    t_start = time.perf_counter()

    scenes: list[tuple[Scene, pl.DataFrame]] = []
    bundled = REPO / "highway_merge.mcap"
    if bundled.exists():
        scenes.append((Scene("bundled highway_merge.mcap", str(bundled), 0), load_table(str(bundled))))
    if UPSTREAM_MCAP.exists():
        up = load_table(str(UPSTREAM_MCAP))
        scenes.append((Scene("upstream highway_merge.mcap", str(UPSTREAM_MCAP), 0), up))
        scenes.append((Scene("upstream highway_merge.mcap + wall", str(UPSTREAM_MCAP), 0, [WALL_WKT]), up))
    else:
        print(f"NOTE: {UPSTREAM_MCAP} not found: upstream recording skipped\n")
    for n in args.sizes:
        table = synthetic_highway(n, args.frames, seed=0)
        path = workdir / f"synthetic_{n}.parquet"
        table.write_parquet(path)
        scenes.append((Scene(f"synthetic highway N={n}, {args.frames} frames", str(path), 0), box_polygons(table)))
    if args.scenes:
        scenes = [(s, d) for s, d in scenes if any(k in s.name for k in args.scenes.split(","))]

    lines = [
        "| scene | package | rows out (scored) | µs/row | mean abs err | rows off > 0.05 | max abs err "
        "| occluder lists ok | crashes |",
        "|---|---|---|---:|---:|---:|---:|---:|---|",
    ]
    notes = []
    for scene, df in scenes:
        results = [run_ours(df, scene, e) for e in engines]
        if have_pub:
            results.append(run_published_side(python, scene, df, workdir))
        frames = pick_frames(df, scene.ego, args.max_ref_rows)
        t = time.perf_counter()
        ref, geometry = reference_table(df, scene, frames, args.ref_rays)
        n_frames = df.filter(pl.col("idx") == scene.ego)["frame"].n_unique()
        notes.append(
            f"{scene.name}: reference on {ref.height} rows of {len(frames)}/{n_frames} frames "
            f"({time.perf_counter() - t:.0f} s)"
        )
        for r in results:
            s = score(r, ref, geometry, [shapely.from_wkt(w) for w in scene.statics_wkt])
            rows = r.out.height if r.out is not None else 0
            us = r.seconds / rows * 1e6 if r.seconds and rows else None
            crash = r.crashes + (f"; {s['missing']} scored rows missing" if s["missing"] else "")
            if r.mode not in ("", "whole"):
                crash += f" (timed {r.mode})"
            lines.append(
                f"| {scene.name} | {r.package} | {rows} ({s['checked']}) | {fmt(us, ',.1f')} "
                f"| {fmt(s.get('mae'), '.2e')} | {fmt(s.get('off', np.nan) * 100, '.1f')} % "
                f"| {fmt(s.get('max'), '.3f')} | {fmt(s.get('occ', np.nan) * 100, '.1f')} % | {crash} |"
            )
            for w, c in r.warnings.items():
                notes.append(f"{scene.name}, {r.package}: {c} x {w}")
        print("\n".join(lines[-len(results) :]), flush=True)

    print(f"\n## Accuracy and speed ({time.perf_counter() - t_start:.0f} s so far)\n")
    print("\n".join(lines))
    print(
        f"\nReference: tests/reference.py, {args.ref_rays} rays per target, observer at the ego centre, ego "
        f"transparent; at most {args.max_ref_rows} rows per scene (evenly spaced frames). µs/row: best of up to 3 "
        "warm calls of get_visibility_df on the same polars table (omega-prime `polygon` column), wall time / rows "
        f"out, {os.cpu_count()} cores, NUMBA_NUM_THREADS={os.environ['NUMBA_NUM_THREADS']}. Occluder lists ok: every "
        f"object/static the rays see blocking > {TINY:g} of the extent is listed, and every listed one blocks along "
        "some direction (seen by the reference's rays, else by 20001 rays focused on the overlap of the two extents)."
    )
    print("\n".join(f"- {n}" for n in notes))

    if args.skip_robustness:
        return
    print("\n## Robustness (3-frame scenes, ego idx 0)\n")
    print("| case | package | outcome | rows out | rows expected | max abs err vs reference | what came out |")
    print("|---|---|---|---:|---:|---:|---|")
    for name, (table, note) in robustness_tables().items():
        path = workdir / f"robust_{abs(hash(name)):x}.parquet"
        table.write_parquet(path)
        scene = Scene(name, str(path), 0, note=note)
        df = box_polygons(table)
        ego_frames = [int(f) for f in df.filter(pl.col("idx") == 0)["frame"].unique().sort()]
        ref, geometry = reference_table(df, scene, ego_frames, args.ref_rays)
        results = [run_ours(df, scene, e, repeat=1) for e in engines]
        if have_pub:
            results.append(run_published_side(python, scene, df, workdir))
        for r in results:
            s = score(r, ref, geometry, [shapely.from_wkt(w) for w in scene.statics_wkt])
            rows = r.out.height if r.out is not None else 0
            outcome = r.crashes if r.crashes != "0" else "ok"
            if r.warnings:
                outcome += "; warns: " + "; ".join(f"{c} x {w}" for w, c in r.warnings.items())
            shown = ""
            if r.out is not None:
                o = r.out.sort("frame", "idx")
                shown = ", ".join(
                    f"f{f}/#{i}: {fmt(v, '.3f')}" for f, i, v in o.select("frame", "idx", "visibility").iter_rows()
                )
            ref_s = ", ".join(
                f"f{f}/#{i}: {'inside' if ins else fmt(v, '.3f')}"
                for f, i, v, ins in ref.select("frame", "idx", "ref", "inside").iter_rows()
            )
            print(
                f"| {name} | {r.package} | {outcome} | {rows} | {ref.height} | {fmt(s.get('max'), '.3f')} "
                f"| {shown or '–'} |"
            )
        print(f"| {name} | reference | {note or '–'} | | {ref.height} | | {ref_s} |")
    print(f"\ntotal {time.perf_counter() - t_start:.0f} s")


def main(argv: list[str] | None = None) -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--driver", action="store_true", help="build scenes, run both packages, print tables (ours)")
    g = p.add_argument_group("driver")
    g.add_argument("--published-python", default="/tmp/pub/bin/python")
    g.add_argument("--frames", type=int, default=30, help="frames per synthetic highway")
    g.add_argument("--sizes", type=int, nargs="+", default=[10, 50, 200], help="synthetic highway sizes")
    g.add_argument("--ref-rays", type=int, default=20000)
    g.add_argument("--max-ref-rows", type=int, default=2000)
    g.add_argument("--engines", default="", help="comma-separated engines of ours (default: all in ENGINES)")
    g.add_argument("--scenes", default="", help="only scenes whose name contains one of these comma-separated words")
    g.add_argument("--skip-robustness", action="store_true")
    g.add_argument("--workdir", default="", help="where inputs and the runner's outputs go (default: a temp dir)")
    r = p.add_argument_group("runner (published package's interpreter)")
    r.add_argument("--input", help="parquet object table or omega-prime MCAP")
    r.add_argument("--ego", type=int, default=0)
    r.add_argument("--static-wkt", action="append", default=[], help="static occluder as WKT (repeatable)")
    r.add_argument("--out", help="output parquet; timing and failures go to the same name with .json")
    r.add_argument("--repeat", type=int, default=3, help="timed calls (best is kept), within --budget seconds")
    r.add_argument("--budget", type=float, default=20.0)
    r.add_argument("--per-frame", action="store_true", help="call get_visibility_df_for_frame frame by frame")
    r.add_argument("--frames-only", type=int, nargs="+", help="only these frames (implies --per-frame)")
    args = p.parse_args(argv)
    if args.driver:
        driver(args)
    elif args.input and args.out:
        run_published(args)
    else:
        p.error("give --driver, or --input and --out")


if __name__ == "__main__":
    main()
