"""``compile``: compile the engines' kernels now, once per version of the package, so later calls start at once.

``make run`` calls it; building the package (pip) runs it too. A copy of the kernels is kept inside the installed
package (:data:`.._compiled.BUNDLE`, where it can be written): a container image or a shared install that ran it
once gives every user and worker whose own cache lacks them kernels ready to load (on the same CPU).

Each engine is run on a small made-up scene through every path a real call takes (a polygon column with overlapping
and touching outlines, a wall, every object as observer, the typical sensor set, the visible area, a camera and a
lidar), two engines at a time on two cores.
"""

from __future__ import annotations

import multiprocessing
import os
import time
from concurrent.futures import FIRST_COMPLETED, ProcessPoolExecutor, wait
from pathlib import Path
from typing import Annotated

import numpy as np
import polars as pl
import typer

from .. import _compiled
from .._compiled import ahead
from ..engines.registry import ENGINES, ENGINES_3D
from .app import app
from .common import fail

DEFAULT = ("reader", "visilibity", "sweep", "raycast3d", "silhouette3d", "area", "imaging")
AREA = "area"
"""The area measure's engine (``measure="area"``), compiled like the others."""
READER = "reader"
"""The MCAP reader's kernels (:mod:`..inputs.osi_wire`), compiled like an engine's."""
IMAGING = "imaging"
"""The counting engine of cameras and lidars (:mod:`..engines.imaging`), compiled like the others."""
AHEAD = "ahead"
"""The ahead-of-time build of the kernels of the reader and of every engine (see :mod:`.._compiled.ahead`), made
once those are compiled."""
AHEAD_OF = (READER, "visilibity", "sweep", "raycast3d", "silhouette3d")
"""The paths the build ahead of time holds: the reader's and every engine's (48 kernels and argument types; the 3D
engines' 16 of them take 30 s more of compiling on one core, and save a 3D call numba's import and its cache's
loading, 0.6 s)."""
HEARTBEAT_S = 5.0
"""Seconds between the lines saying that compiling goes on."""


def warm_up_table(frames: int = 3) -> pl.DataFrame:
    """A made-up recording's table: an ego and six cars on a two-lane road, two of them overlapping (as tracker
    output does), one touching another, with omega-prime's ``polygon`` column and the 3D columns.

    Examples
    --------
    >>> t = warm_up_table(2)
    >>> t.height, t["idx"].n_unique(), t["polygon"].dtype
    (14, 7, Object)
    """
    import shapely

    base = np.array(
        # x, y, length, width, height, yaw: the ego, cars ahead, an overlapping pair, a touching pair, a truck
        [[0, 0, 4.5, 1.8, 1.5, 0], [15, 0.2, 4.6, 1.85, 1.5, 0.02], [30, 3.5, 4.6, 1.8, 1.45, 0],
         [31.5, 3.9, 4.6, 1.8, 1.45, 0.1], [-20, 3.5, 4.7, 1.9, 1.55, 0], [-15.3, 3.5, 4.7, 1.9, 1.55, 0],
         [45, 0, 16.5, 2.55, 4.0, 0]]
    )  # fmt: skip
    rows = []
    for frame in range(frames):
        for idx, (x, y, length, width, height, yaw) in enumerate(base):
            x = x + 2.5 * frame
            box = shapely.affinity.rotate(
                shapely.box(x - length / 2, y - width / 2, x + length / 2, y + width / 2), yaw, use_radians=True
            )
            rows.append(
                {"frame": frame, "total_nanos": frame * 100_000_000, "idx": idx, "x": x, "y": y, "z": height / 2,
                 "length": length, "width": width, "height": height, "roll": 0.0, "pitch": 0.0, "yaw": yaw,
                 "polygon": box}
            )  # fmt: skip
    return pl.DataFrame(rows, schema_overrides={"polygon": pl.Object})


def compile_engine(name: str) -> float:
    """Run engine ``name`` on :func:`warm_up_table` through every path a real call takes; return the seconds."""
    import warnings

    import shapely

    from ..analysis.area import visible_area_over_time
    from ..api import get_visibility_df

    _compiled.progress.ANNOUNCE = False  # the command says what it compiles
    started = time.perf_counter()
    if name == READER:
        from ..inputs.reader import warm_up

        warm_up()
        _compiled.mark_compiled(f"compile-{name}")
        return time.perf_counter() - started
    table = warm_up_table()
    wall = shapely.LineString([(-40.0, -3.0), (80.0, -3.0)])
    if name == IMAGING:  # a small camera and lidar, through a whole frame's rows
        from ..inputs.lidars import uniform
        from ..inputs.sensors import camera, lidar

        sensors = [camera("cam", 64, 36, 1.2, x=1.0), lidar("lid", uniform(4, -10, 10, 90), range=60.0)]
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            get_visibility_df(table, 0, [wall], mode="3d", sensors=sensors, progress=False, workers=1)
        _compiled.mark_compiled(f"compile-{name}")
        return time.perf_counter() - started
    mode = "3d" if name in ENGINES_3D else "2d"
    meshes = [warm_up_mesh()] if name.startswith("raycast3d") else []  # the ray engines sample only meshes
    choice = {"engine": None, "measure": "area"} if name == AREA else {"engine": name, "static_meshes": meshes}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        for ego, sensors in ((0, None), ("all", None), (0, "typical")):
            get_visibility_df(table, ego, [wall], mode=mode, sensors=sensors, progress=False, workers=1, **choice)
        if name == AREA:  # frames without static occluders take the compiled path
            get_visibility_df(table, 0, mode=mode, progress=False, workers=1, **choice)
        elif mode == "2d":  # who blocks and who is looked for: the views' kernels
            get_visibility_df(
                table, 0, [wall], targets=[1, 2], occluders=[0, 1, 3], progress=False, workers=1, **choice
            )
        if mode == "2d":
            visible_area_over_time(table, 0, "typical", [wall])
    _compiled.mark_compiled(f"compile-{name}")  # every path of it ran: compile says so next time
    return time.perf_counter() - started


def compile_ahead(folder: Path | str | None = None) -> float:
    """Run the paths of :data:`AHEAD_OF` noting the kernels they call from Python, then build those
    ahead of time into ``folder`` (default: the user's cache, see :mod:`.._compiled.ahead`); return the seconds."""
    from .._compiled import ahead_build, kernel

    started = time.perf_counter()
    calls = kernel.record_calls()
    for name in AHEAD_OF:
        compile_engine(name)
    ahead_build.build(calls, Path(folder) if folder else _compiled.kernels_cache() / ahead.FOLDER, AHEAD_OF)
    return time.perf_counter() - started


def warm_up_mesh():
    """A small mesh (a 2 m cube beside the road of the warm-up table) for the ray engines' sampling kernels."""
    import trimesh

    return trimesh.creation.box(extents=(2.0, 2.0, 2.0)).apply_translation((25.0, -6.0, 1.0))


@app.command("compile", short_help="compile the engines' kernels now (make run does it)")
def compile_kernels(
    engines: Annotated[
        list[str] | None,
        typer.Argument(
            metavar="ENGINES", help=f"engines to compile (default: {' '.join(DEFAULT)})", show_default=False
        ),
    ] = None,
    jobs: Annotated[
        int | None,
        typer.Option(metavar="N", help="engines compiled at once (default: 2, or 1 on one core)", show_default=False),
    ] = None,
) -> None:
    """Compile the engines' kernels into the cache now, so that the first real call starts at once (and the
    package's Python bytecode, where it is missing).

    The kernels are kept per version of the package (see Getting started); compiling again is quick when they are
    there already. Run it once on every fresh cluster node before a batch.
    """
    names = list(engines or DEFAULT)
    unknown = [n for n in names if n not in ENGINES and n not in ENGINES_3D and n not in (AREA, READER, IMAGING)]
    if unknown:
        known = sorted(ENGINES) + sorted(ENGINES_3D) + [AREA, READER, IMAGING]
        raise fail(f"unknown engine {unknown[0]!r}; available: {known}")
    if jobs is not None and jobs < 1:
        raise fail(f"--jobs takes a number of processes, at least 1, not {jobs}")
    jobs = jobs or min(2, len(os.sched_getaffinity(0)))
    ready = [n for n in names if _compiled.has_run(f"compile-{n}")]
    todo = [n for n in names if n not in ready]
    built = ahead.current_build()  # (one that fits, holding these paths, made for this processor level, is kept)
    kept = built is not None and built[1].get("covers") == list(AHEAD_OF)
    kept = kept and built[1].get("cpu", "") == ahead.processor_level()
    ahead_todo = all(n in names for n in AHEAD_OF) and not kept
    then = f", then the engines' ahead of time ({AHEAD})" if ahead_todo else ""
    if not todo:
        typer.echo(f"the kernels of {', '.join(names)} are compiled already for this version; checking them{then}")
    else:
        already = f"; {', '.join(ready)} compiled already" if ready else ""
        typer.echo(
            f"compiling the kernels of {', '.join(todo)}, {jobs} at a time (once per version of the package;"
            f" a minute or two each on a busy 2-core machine){then}{already}"
        )
    started = time.perf_counter()
    spawn = multiprocessing.get_context("spawn")
    # each engine in a fresh process, as on a new installation; the build ahead of time in a pool of its own (a
    # crash of numba's compiler there stops it alone); this one reports
    with (
        ProcessPoolExecutor(jobs, mp_context=spawn, max_tasks_per_child=1) as pool,
        ProcessPoolExecutor(1, mp_context=spawn) as own,
    ):
        futures = {pool.submit(compile_engine, name): name for name in names}
        pending, finished = set(futures), set()
        while pending:  # a line at least every HEARTBEAT_S seconds: never silent for long
            done, pending = wait(pending, timeout=HEARTBEAT_S, return_when=FIRST_COMPLETED)
            finished |= {futures[f] for f in done}
            if ahead_todo and AHEAD not in futures.values() and all(n in finished for n in AHEAD_OF):
                ahead_build = own.submit(compile_ahead)  # once those paths' kernels are compiled
                futures[ahead_build] = AHEAD
                pending.add(ahead_build)
            for future in done:
                try:
                    seconds = future.result()
                except Exception as e:
                    if futures[future] == AHEAD:  # (the kernels are compiled: a call loads them from numba's cache)
                        reason = (str(e).strip().splitlines() or [type(e).__name__])[-1]
                        typer.echo(
                            f"  {AHEAD}: not built ({reason}; it needs a C compiler, $CC, and setuptools); calls"
                            " load numba's cache instead"
                        )
                        continue
                    if isinstance(e, ValueError):
                        raise fail(f"{futures[future]}: {e}") from None
                    raise
                typer.echo(f"  {futures[future]}: done in {seconds:.0f} s")
            if pending and not done:
                busy = ", ".join(sorted(futures[f] for f in pending if f.running()))
                typer.echo(f"  ... {time.perf_counter() - started:.0f} s, still compiling {busy}")
    typer.echo(
        f"{'compiled' if todo else 'checked'} in {time.perf_counter() - started:.0f} s; later calls start at once"
    )
    from .._compiled.copies import bundle  # (it imports numba: here, not when the command line starts)

    kept = bundle()
    if kept is not None:  # a fresh user cache (a container, a dask worker, another user) starts from it
        typer.echo(f"a copy is kept with the package ({kept}): an empty user cache starts from it")
    compile_bytecode()


def compile_bytecode() -> bool:
    """Write the package's Python bytecode beside its sources where it is missing or stale (an editable install,
    such as ``make run``'s, has none, and where ``PYTHONDONTWRITEBYTECODE`` is set no run writes it: every run
    compiled the package's modules from source again, 0.1 s of a short run). True if all of it is there now (a
    package in a folder this user may not write keeps what it has).

    Examples
    --------
    >>> compile_bytecode()
    True
    """
    import compileall

    package = Path(__file__).resolve().parents[1]
    return bool(compileall.compile_dir(package, quiet=2))
