"""The compiled kernels' cache follows the package's sources (omega_prime_visibility/_compiled.py)."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from omega_prime_visibility._compiled import (
    PACKAGE,
    remembered_sources,
    remembered_sources_key,
    source_stamps,
    sources_key,
)

PROBE = (
    "import os, pathlib, omega_prime_visibility as o;"
    " o._compiled.sources.BUNDLE = pathlib.Path(os.environ.get('PROBE_BUNDLE') or o._compiled.BUNDLE);"
    " from omega_prime_visibility.geometry.kernels import wrap_positive;"
    " wrap_positive(-1.0); s = wrap_positive.stats;"
    " print(s.cache_path); print(sum(s.cache_hits.values())); print(sum(s.cache_misses.values()))"
)


def run_probe(cwd: Path | None = None, bundle: str = "/nonexistent", **env: str) -> list[str]:
    """Call one kernel in a fresh process: numba's cache folder for it, its cache hits and misses. The package's
    copy of the kernels is ``bundle`` ("" for the package's own)."""
    clean = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME", "PYTHONPATH")}
    clean["PROBE_BUNDLE"] = bundle
    if cwd is not None:
        clean["PYTHONPATH"] = str(cwd)
    out = subprocess.run(
        [sys.executable, "-c", PROBE], env={**clean, **env}, capture_output=True, text=True, check=True, cwd=cwd
    )
    return out.stdout.split()


def test_the_key_changes_with_any_source_and_only_then(tmp_path: Path) -> None:
    copy = tmp_path / "pkg"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    key = sources_key(copy)
    assert key == sources_key(PACKAGE) and len(key) == 16
    # a module one kernel calls into changes (as after a git pull): a new folder, no stale machine code
    kernels = copy / "geometry" / "kernels.py"
    kernels.write_text(kernels.read_text() + "\n# changed\n")
    assert sources_key(copy) != key
    kernels.write_text(kernels.read_text().removesuffix("\n# changed\n"))
    assert sources_key(copy) == key
    # a module kernels reach only through an import inside a function counts too
    (copy / "geometry" / "helper_constants.py").write_text("TOLERANCE = 1e-9\n")
    assert sources_key(copy) == key  # nothing imports it yet
    kernels.write_text(kernels.read_text() + "\ndef _late():\n    from .helper_constants import TOLERANCE\n")
    changed = sources_key(copy)
    (copy / "geometry" / "helper_constants.py").write_text("TOLERANCE = 1e-6\n")
    assert sources_key(copy) not in (key, changed)


def test_the_key_is_remembered_by_the_sources_sizes_and_times(tmp_path: Path, monkeypatch) -> None:
    from omega_prime_visibility._compiled import sources

    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "cache"))
    monkeypatch.setattr(sources, "BUNDLE", tmp_path / "no-package-copy")
    copy = tmp_path / "pkg"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    key, stamps = sources_key(copy), source_stamps(copy)
    assert remembered_sources(copy) == (key, stamps)  # computed, then remembered
    found = sorted((tmp_path / "cache" / "omega-prime-visibility" / "sources").iterdir())
    by_contents = [m for m in found if m.name.startswith("contents-")]
    memos = [m for m in found if m not in by_contents]  # (by sizes and times; by contents for new times)
    assert [json.loads(m.read_text()) for m in memos + by_contents] == [{"key": key, "stamps": stamps}] * 2
    memos[0].write_text(json.dumps({"key": "0123456789abcdef", "stamps": {}}))  # what was remembered is used ...
    assert remembered_sources_key(copy) == "0123456789abcdef"
    memos[0].write_text("garbage")  # ... unless it is no key
    by_contents[0].unlink()
    assert remembered_sources_key(copy) == key
    # an edited kernel module (a git pull): a new size or time, so the key is computed anew
    kernels = copy / "geometry" / "kernels.py"
    kernels.write_text(kernels.read_text() + "\n# changed\n")
    assert remembered_sources(copy) == (sources_key(copy), source_stamps(copy))
    assert remembered_sources_key(copy) != key
    # nowhere to remember it: still the right key
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "pkg" / "__init__.py" / "cannot"))
    assert remembered_sources_key(copy) == sources_key(copy)


def test_a_fresh_user_takes_the_key_from_the_package_copy_by_the_sources_contents(tmp_path: Path, monkeypatch) -> None:
    # the build noted the key of these sources by their contents; a fresh user, whose files have other times (an
    # install, a container), takes it from there instead of parsing every source (a second of a first call)
    from omega_prime_visibility._compiled import sources

    copy = tmp_path / "pkg"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    key, stamps = sources_key(copy), source_stamps(copy)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "build"))
    bundled = tmp_path / "bundle"
    memo = sources.contents_memo(copy)
    (bundled / "sources").mkdir(parents=True)
    sources.write_memo(bundled / "sources" / memo.name, (key, stamps))
    monkeypatch.setattr(sources, "BUNDLE", bundled)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "fresh"))
    for path in copy.rglob("*.py"):
        os.utime(path, ns=(1, 1))  # (the files' times of another machine)
    parsed = sources.key_and_stamps
    monkeypatch.setattr(sources, "key_and_stamps", lambda root: pytest.fail("parsed the sources"))
    assert remembered_sources(copy) == (key, stamps)
    # an edit: other contents, so it is computed anew, not taken from the copy
    kernels = copy / "geometry" / "kernels.py"
    kernels.write_text(kernels.read_text() + "\n# changed\n")
    monkeypatch.setattr(sources, "key_and_stamps", parsed)
    assert remembered_sources(copy) == (sources_key(copy), source_stamps(copy)) != (key, stamps)


def test_an_edit_stamps_anew_the_kernels_that_reach_it_and_only_those(tmp_path: Path) -> None:
    copy = tmp_path / "pkg"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    stamps = source_stamps(copy)
    assert stamps == source_stamps(PACKAGE) and all(len(v) == 16 for v in stamps.values())
    # the sweep's interval kernel: its own module and the sweep's callers change, the reader and 3D do not
    edited = copy / "engines" / "sweep" / "heap_sweep.py"
    edited.write_text(edited.read_text() + "\n# changed\n")
    after = source_stamps(copy)
    changed = {name for name in stamps if after[name] != stamps[name]}
    assert {"engines/sweep/heap_sweep.py", "engines/sweep/observe.py"} <= changed
    assert not changed & {"inputs/osi_wire.py", "geometry/kernels.py", "threed/boxes.py", "engines/imaging/lines.py"}
    # a shared building block: every module calling it changes, modules that never reach it keep their stamps
    shared = copy / "geometry" / "kernels.py"
    shared.write_text(shared.read_text() + "\n# changed\n")
    again = source_stamps(copy)
    changed = {name for name in after if again[name] != after[name]}
    assert {"geometry/kernels.py", "engines/sweep/heap_sweep.py", "engines/visilibity/attribution.py"} <= changed
    assert "inputs/osi_wire.py" not in changed
    # reached only through another module (heap_sweep imports geometry.occlusion, which imports candidates)
    assert "candidates" not in (copy / "engines" / "sweep" / "heap_sweep.py").read_text()
    indirect = copy / "geometry" / "candidates.py"
    indirect.write_text(indirect.read_text() + "\n# changed\n")
    assert source_stamps(copy)["engines/sweep/heap_sweep.py"] != again["engines/sweep/heap_sweep.py"]


def test_editing_a_front_end_does_not_recompile_the_kernels(tmp_path: Path) -> None:
    copy = tmp_path / "pkg"
    shutil.copytree(PACKAGE, copy, ignore=shutil.ignore_patterns("__pycache__"))
    key = sources_key(copy)
    for front_end in ("cli/run.py", "plot/frame.py", "batch/run.py", "analysis/intervals.py"):
        path = copy / front_end
        if path.exists():
            path.write_text(path.read_text() + "\n# changed\n")
    assert sources_key(copy) == key


def test_kernels_are_cached_in_the_folder_of_their_module(tmp_path: Path) -> None:
    folder, hits, misses = run_probe(XDG_CACHE_HOME=str(tmp_path))
    expected = tmp_path / "omega-prime-visibility" / "kernels" / "geometry"
    assert (folder, hits, misses) == (str(expected), "0", "1")
    assert list(expected.glob("kernels.wrap_positive-*.nbi")), "the kernel called was not cached there"
    assert run_probe(XDG_CACHE_HOME=str(tmp_path)) == [str(expected), "1", "0"]  # the next process loads it


def test_importing_the_package_is_quick_and_sets_the_cache_before_numba_loads(tmp_path: Path) -> None:
    # the package imported first: numba is not loaded by it (import stays quick), and when a kernel loads numba
    # later, numba caches in the package's folder all the same
    probe = (
        "import sys, omega_prime_visibility as o; print('numba' in sys.modules, 'polars' in sys.modules);"
        " from omega_prime_visibility.geometry.kernels import wrap_positive; wrap_positive(-1.0);"
        " print(wrap_positive.stats.cache_path)"
    )
    clean = {k: v for k, v in os.environ.items() if k not in ("NUMBA_CACHE_DIR", "XDG_CACHE_HOME")}
    out = subprocess.run([sys.executable, "-c", probe], env={**clean, "XDG_CACHE_HOME": str(tmp_path)},
                         capture_output=True, text=True, check=True).stdout.split()  # fmt: skip
    assert out == ["False", "False", str(tmp_path / "omega-prime-visibility" / "kernels" / "geometry")]
    # numba loaded before the package: the locator is put in place at once
    probe = (
        "import numba; import omega_prime_visibility; from omega_prime_visibility.geometry.kernels import"
        " wrap_positive; wrap_positive(-1.0); print(wrap_positive.stats.cache_path)"
    )
    out = subprocess.run([sys.executable, "-c", probe], env={**clean, "XDG_CACHE_HOME": str(tmp_path / "b")},
                         capture_output=True, text=True, check=True).stdout.split()  # fmt: skip
    assert out == [str(tmp_path / "b" / "omega-prime-visibility" / "kernels" / "geometry")]


def test_a_cache_folder_the_user_chose_is_left_alone(tmp_path: Path) -> None:
    folder, _, misses = run_probe(NUMBA_CACHE_DIR=str(tmp_path / "mine"), XDG_CACHE_HOME=str(tmp_path / "xdg"))
    assert folder.startswith(str(tmp_path / "mine")) and misses == "1"
    assert (
        list((tmp_path / "mine").rglob("*.nbi"))
        and not (tmp_path / "xdg" / "omega-prime-visibility" / "kernels").exists()
    )


def test_kernels_compiled_elsewhere_load_here_unless_their_sources_differ(tmp_path: Path) -> None:
    # compiled in another copy of the package (as when it is built), kept as its copy (_kernels), then used by a
    # process of this copy whose own cache is empty: loaded, not compiled
    from omega_prime_visibility._compiled import copies

    built = tmp_path / "build"
    shutil.copytree(PACKAGE, built / PACKAGE.name, ignore=shutil.ignore_patterns("__pycache__", "_kernels"))
    assert run_probe(cwd=built, bundle="", XDG_CACHE_HOME=str(tmp_path / "builder"))[1:] == ["0", "1"]
    compiled = tmp_path / "builder" / "omega-prime-visibility" / "kernels"
    installed = tmp_path / "site"
    shutil.copytree(built, installed)  # the installed package: elsewhere on disk
    copied = copies.copy_current(compiled / "geometry", installed / PACKAGE.name / "_kernels" / "geometry",
                                        "geometry")  # fmt: skip
    assert copied >= 1
    folder, hits, misses = run_probe(cwd=installed, bundle="", XDG_CACHE_HOME=str(tmp_path / "user"))
    assert (hits, misses) == ("1", "0") and folder == str(
        tmp_path / "user" / "omega-prime-visibility" / "kernels" / "geometry"
    )
    # the package's copy for other sources (a module it reaches edited since): not taken, compiled anew
    shared = installed / PACKAGE.name / "geometry" / "kernels.py"
    shared.write_text(shared.read_text() + "\n# changed\n")
    assert run_probe(cwd=installed, bundle="", XDG_CACHE_HOME=str(tmp_path / "user2"))[1:] == ["0", "1"]
    # the user's cache of other sources, where the package's copy is current: the copy replaces it
    shared.write_text(shared.read_text().removesuffix("\n# changed\n"))
    assert run_probe(cwd=installed, bundle="", XDG_CACHE_HOME=str(tmp_path / "user2"))[1:] == ["1", "0"]


def test_compiled_before_looks_where_numba_caches(tmp_path: Path, monkeypatch) -> None:
    import numba
    from numba.core.caching import UserProvidedCacheLocator

    from omega_prime_visibility._compiled import compiled_before

    engine = tmp_path / "sweep"
    (engine / "__pycache__").mkdir(parents=True)
    (engine / "heap.py").write_text("")
    monkeypatch.setattr(numba.config, "CACHE_DIR", "")
    assert not compiled_before(engine) and not compiled_before(engine / "heap.py")
    (engine / "__pycache__" / "heap.visible_angles-190.py311.nbi").write_bytes(b"")
    assert compiled_before(engine) and compiled_before(engine / "heap.py")
    assert not compiled_before(engine / "other.py")  # another module of the folder: not yet
    cache = tmp_path / "cache"
    monkeypatch.setattr(numba.config, "CACHE_DIR", str(cache))
    assert not compiled_before(engine)  # numba now caches elsewhere
    sub = cache / UserProvidedCacheLocator.get_suitable_cache_subpath(str(engine / "heap.py"))
    sub.mkdir(parents=True)
    (sub / "heap.visible_angles-190.py311.nbi").write_bytes(b"")
    assert compiled_before(engine)


def test_a_first_run_says_it_compiles_and_a_later_one_does_not(monkeypatch, capsys, tmp_path) -> None:
    from conftest import boxes_table

    from omega_prime_visibility import Sensor, _compiled, get_visibility_df

    # a fresh cache folder's markers (the kernels themselves stay where they are)
    monkeypatch.setattr(_compiled.progress, "marker", lambda key: tmp_path / f".ran-{key}")
    monkeypatch.setattr(_compiled.sources, "BUNDLE", tmp_path / "no-copy")  # nor the package's copy of them
    table = boxes_table([(0, 0, 4, 2, 0), (10, 0, 4, 2, 0)])
    for cold in (True, False):
        get_visibility_df(table, 0, engine="sweep")
        said = capsys.readouterr().err
        assert ("compiling the sweep engine's kernels" in said) == cold, said
    assert (tmp_path / ".ran-sweep").exists()
    # the sensors' path compiles kernels of its own: its first run says so too, once
    for cold in (True, False):
        get_visibility_df(table, 0, engine="sweep", sensors=[Sensor("front", fov=1.0)])
        assert ("compiling the sweep engine's kernels" in capsys.readouterr().err) == cold
    # an engine without kernel modules of its own (silhouette3d uses threed's) is announced once, not every time
    boxes = table.with_columns(z=0.75, height=1.5, roll=0.0, pitch=0.0)
    for cold in (True, False):
        get_visibility_df(boxes, 0, mode="3d", engine="silhouette3d")
        assert ("compiling the silhouette3d engine's kernels" in capsys.readouterr().err) == cold
    # a run that fails half-way leaves no marker: the next one still announces
    from omega_prime_visibility.table import compute as api

    def broken(*args, **kwargs):
        raise RuntimeError("killed half-way")

    monkeypatch.setattr(api, "run", broken)
    with pytest.raises(RuntimeError, match="half-way"):
        get_visibility_df(table, 0, engine="visilibity")
    assert "compiling the visilibity engine's kernels" in capsys.readouterr().err
    assert not (tmp_path / ".ran-visilibity").exists()


def test_a_first_call_is_never_silent_while_it_compiles(monkeypatch, capsys) -> None:
    # the heartbeat says every HEARTBEAT_S seconds that the kernels are still compiling, and stops when told
    import time

    from omega_prime_visibility import _compiled

    monkeypatch.setattr(_compiled.progress, "HEARTBEAT_S", 0.05)
    beat = _compiled.Heartbeat("the sweep engine's kernels").start()
    time.sleep(0.3)
    beat.stop()
    said = capsys.readouterr().err.splitlines()
    assert len(said) >= 3 and all("still compiling the sweep engine's kernels" in line for line in said)
    time.sleep(0.15)
    assert capsys.readouterr().err == ""  # stopped: silent


def test_compile_writes_the_packages_bytecode() -> None:
    import importlib.util

    import omega_prime_visibility.plot.labels as module
    from omega_prime_visibility.cli.compile_kernels import compile_bytecode

    cached = Path(importlib.util.cache_from_source(module.__file__))
    cached.unlink(missing_ok=True)
    assert compile_bytecode() and cached.is_file()  # (PYTHONDONTWRITEBYTECODE is set here: no import writes it)
