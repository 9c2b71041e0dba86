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
import json, sys, warnings
import numba, shapely
warnings.simplefilter("ignore")
from omega_prime_visibility.cli.compile_kernels import compile_engine
from omega_prime_visibility import get_visibility_df, visible_area_over_time
from omega_prime_visibility.inputs.io import read_recording

def signatures():
    found = {}
    for name, module in list(sys.modules.items()):
        if name.startswith("omega_prime_visibility"):
            for attr, value in vars(module).items():
                if isinstance(value, numba.core.registry.CPUDispatcher):
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


def test_an_empty_user_cache_starts_from_the_packages_copy(tmp_path, monkeypatch) -> None:
    # compile leaves a copy of the kernels with the package; a user (a container, a dask worker) whose own cache is
    # empty gets it before numba looks, and one whose cache holds kernels keeps its own
    from omega_prime_visibility import _compiled

    monkeypatch.setattr(_compiled, "BUNDLE", tmp_path / "package" / "_kernels")
    key = "0123456789abcdef"
    compiled = tmp_path / "cache" / key
    (compiled / "engines_x").mkdir(parents=True)
    (compiled / "engines_x" / "kernels.f-12.py311.nbi").write_bytes(b"index")
    (compiled / "engines_x" / "kernels.f-12.py311.1.nbc").write_bytes(b"code")
    (compiled / ".writable-1").touch()
    (tmp_path / "package" / "_kernels" / "fedcba9876543210").mkdir(parents=True)  # an older version's copy
    kept = _compiled.bundle(compiled)
    assert kept == tmp_path / "package" / "_kernels" / key
    assert sorted(p.name for p in (tmp_path / "package" / "_kernels").iterdir()) == [key]  # the old one removed
    assert not list(kept.rglob(".writable-*"))
    fresh = tmp_path / "user" / key
    fresh.mkdir(parents=True)
    assert _compiled.seed_from_bundle(fresh)
    assert (fresh / "engines_x" / "kernels.f-12.py311.1.nbc").read_bytes() == b"code"
    (fresh / "engines_x" / "kernels.f-12.py311.1.nbc").write_bytes(b"mine")
    assert not _compiled.seed_from_bundle(fresh)  # it holds kernels: left as it is
    assert (fresh / "engines_x" / "kernels.f-12.py311.1.nbc").read_bytes() == b"mine"
    assert not _compiled.seed_from_bundle(tmp_path / "user" / "ffffffffffffffff")  # no copy for these sources
