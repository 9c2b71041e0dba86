"""``omega-prime-visibility compile`` (cli/compile_kernels.py): the warm-up takes every path a real call takes, so
nothing is left to compile afterwards."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest
from conftest import REPO

# In a fresh process: warm one engine up, note every kernel's compiled signatures, then make the calls users make
# on a real recording; print the kernels that needed a signature the warm-up did not compile.
PROBE = """
import json, os, sys, warnings
import shapely
warnings.simplefilter("ignore")
os.environ["OMEGA_PRIME_VISIBILITY_AHEAD"] = "0"  # (numba's dispatchers compile every call: none is left out)
from omega_prime_visibility._compiled.kernel import Kernel
from omega_prime_visibility.cli.compile_kernels import compile_engine
from omega_prime_visibility import get_visibility_df, visible_area_over_time
from omega_prime_visibility.inputs.io import read_recording

def signatures():
    found = {}
    for name, module in list(sys.modules.items()):
        if name.startswith("omega_prime_visibility"):
            for attr, value in vars(module).items():
                if isinstance(value, Kernel) and value._dispatcher is not None:
                    found[f"{name}.{attr}"] = {str(s) for s in value.signatures}
    return found

engine = sys.argv[1]
compile_engine("reader")  # make run compiles the reader with the engines
compile_engine(engine)
before = signatures()
r = read_recording("highway_merge.mcap")
wall = shapely.LineString([(60, -5.4), (140, -5.4)])
mode = "3d" if "3d" in engine else "2d"
meshes = []
if engine.startswith("raycast3d"):  # the ray engines sample only meshes: one on the road ahead
    import trimesh

    meshes = [trimesh.creation.box(extents=(3.0, 2.0, 2.0)).apply_translation((120.0, -1.0, 1.0))]
for ego, sensors in ((0, None), (0, "typical"), ([0, 1], None)):
    get_visibility_df(
        r, ego, [wall], engine=engine, mode=mode, sensors=sensors, progress=False, workers=1, static_meshes=meshes
    )
if mode == "2d":
    visible_area_over_time(r, 0, "typical", [wall])
after = signatures()
print(json.dumps({k: sorted(v - before.get(k, set())) for k, v in after.items() if v - before.get(k, set())}))
"""


@pytest.mark.parametrize("engine", ["visilibity", "sweep"])
def test_after_the_warm_up_a_real_recording_compiles_nothing(engine) -> None:
    out = subprocess.run(
        [sys.executable, "-c", PROBE, engine], cwd=REPO, capture_output=True, text=True, timeout=900, check=True
    )
    missed = json.loads(out.stdout.strip().splitlines()[-1])
    assert missed == {}, f"compiled only by the real call, not by the warm-up: {missed}"


def test_compile_names_an_unknown_engine_in_one_line() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "omega_prime_visibility.cli", "compile", "sweap"], capture_output=True, text=True
    )
    assert out.returncode == 2 and out.stderr.startswith("error: unknown engine 'sweap'")
    assert len(out.stderr.strip().splitlines()) == 1


def test_warm_up_table_is_a_valid_recording_table() -> None:
    from omega_prime_visibility.cli.compile_kernels import warm_up_table

    table = warm_up_table(3)
    assert table.height == 21 and table["frame"].n_unique() == 3
    overlapping = table.filter(table["frame"] == 0, table["idx"].is_in([2, 3]))["polygon"].to_list()
    assert overlapping[0].intersection(overlapping[1]).area > 0  # tracker-style overlap, on purpose


def test_compile_is_never_silent_for_long(monkeypatch) -> None:
    # a line at least every HEARTBEAT_S seconds while an engine compiles (here: 0.05 s, so even a warm engine, which
    # takes seconds to start in its fresh process, shows a few), then the engine's own line
    from typer.testing import CliRunner

    from omega_prime_visibility.cli import app, compile_kernels

    monkeypatch.setattr(compile_kernels, "HEARTBEAT_S", 0.05)
    result = CliRunner().invoke(app, ["compile", "sweep", "--jobs", "1"])
    assert result.exit_code == 0, result.output
    lines = [line for line in result.output.splitlines() if not line.startswith("a copy is kept with the package")]
    first = lines[0].startswith("compiling the kernels of sweep, 1 at a time")
    assert first or lines[0].startswith("the kernels of sweep are compiled already")  # (another test compiled it)
    assert any(line.strip().startswith("... ") and "still compiling sweep" in line for line in lines[1:-2])
    assert lines[-2].strip().startswith("sweep: done in")
    assert lines[-1].startswith("compiled in" if first else "checked in")
    # once compiled, compile says so instead of announcing minutes of work
    again = CliRunner().invoke(app, ["compile", "sweep", "--jobs", "1"]).output.splitlines()
    again = [line for line in again if not line.startswith("a copy is kept with the package")]
    assert again[0] == "the kernels of sweep are compiled already for this version; checking them"
    assert again[-1].startswith("checked in") and "a minute or two" not in "\n".join(again)


def test_compile_keeps_a_copy_of_the_current_kernels_with_the_package(tmp_path, monkeypatch) -> None:
    # compile leaves a copy of the user's cached kernels with the package: those stamped for the current sources
    # (with their data files and the notes of which engine paths ran), not an older version's
    import pickle

    import numba

    from omega_prime_visibility import _compiled
    from omega_prime_visibility._compiled import copies

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(_compiled.sources, "BUNDLE", tmp_path / "package" / "_kernels")
    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    cache = _compiled.kernels_cache()
    stamps = _compiled.remembered_sources()[1]

    def index(folder, name, stamp, data):
        (cache / folder).mkdir(parents=True, exist_ok=True)
        with open(cache / folder / name, "wb") as f:
            pickle.dump(numba.__version__, f)
            f.write(pickle.dumps((stamp, {("sig",): data})))
        (cache / folder / data).write_bytes(b"code")

    index("geometry", "kernels.f-12.py311.nbi", stamps["geometry/kernels.py"], "kernels.f-12.py311.1.nbc")
    index("engines/sweep", "heap_sweep.g-3.py311.nbi", "0123456789abcdef", "heap_sweep.g-3.py311.1.nbc")  # stale
    key = _compiled.remembered_sources_key()
    (cache / f".ran-{key}-sweep").touch()
    (cache / ".ran-fedcba9876543210-sweep").touch()  # another version's note
    (tmp_path / "package" / "_kernels" / "old").mkdir(parents=True)  # what the copy held before: replaced
    kept = copies.bundle()
    assert kept == tmp_path / "package" / "_kernels"
    files = sorted(p.relative_to(kept).as_posix() for p in kept.rglob("*") if p.is_file())
    memo = f"sources/{_compiled.sources.contents_memo().name}"  # (the sources' key by their contents)
    assert files == [f".ran-{key}-sweep", "geometry/kernels.f-12.py311.1.nbc", "geometry/kernels.f-12.py311.nbi", memo]
    assert _compiled.has_run("sweep") and not _compiled.has_run("visilibity")
    # a user whose cache is empty copies the current one back, never the stale one
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "other-user"))
    user = _compiled.kernels_cache() / "geometry"
    assert copies.copy_current(kept / "geometry", user, "geometry") == 1
    assert (user / "kernels.f-12.py311.1.nbc").read_bytes() == b"code"
    assert copies.copy_current(kept / "geometry", user, "geometry") == 0  # current already: kept as it is
    assert _compiled.has_run("sweep")  # (the package's copy ran it) and stays silent


def test_compile_builds_the_default_call_ahead_of_time_only_where_no_build_fits(monkeypatch) -> None:
    # make run calls compile every time: a build that fits is kept, not made again (45 s)
    from pathlib import Path

    from typer.testing import CliRunner

    from omega_prime_visibility._compiled import ahead, copies
    from omega_prime_visibility.cli import app
    from omega_prime_visibility.cli.compile_kernels import AHEAD_OF

    monkeypatch.setattr(ahead, "current_build", lambda: (Path("/fits"), {"covers": list(AHEAD_OF)}))
    monkeypatch.setattr(copies, "bundle", lambda: None)
    out = CliRunner().invoke(app, ["compile", "reader", "visilibity", "--jobs", "1"]).output
    assert "ahead" not in out and out.splitlines()[-1].startswith(("checked in", "compiled in")), out
