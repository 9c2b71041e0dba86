"""The ahead-of-time build (_compiled/ahead.py, _compiled/ahead_build.py): it holds the kernels and argument types
called, gives the same bits as numba, is taken only for exactly those types and the current sources, and the
default call on the bundled recording runs from it without importing numba."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pyarrow.parquet as pq
import pytest
from conftest import REPO

from omega_prime_visibility._compiled import ahead, ahead_build, kernel
from omega_prime_visibility.geometry import sorting


@pytest.fixture(scope="module")
def small_build(tmp_path_factory) -> Path:
    """A build of two sorting kernels, for float64 keys and for read-only int64 keys."""
    folder = tmp_path_factory.mktemp("build") / ahead.FOLDER
    calls: dict = {}
    old = kernel.CALLED
    kernel.CALLED = calls
    try:
        sorting.argsort_stable(np.array([2.0, 1.0, 2.0]))
        keys = np.array([3, 1, 2])
        keys.flags.writeable = False
        sorting.sorted_values(keys)
    finally:
        kernel.CALLED = old
    ahead_build.build(calls, folder)
    return folder


@pytest.fixture
def from_build(small_build: Path, monkeypatch):
    """Kernels taking the small build (and nothing else) in this test."""
    monkeypatch.setattr(ahead, "folders", lambda: [small_build])
    monkeypatch.setattr(ahead, "_EXPORTS", None)
    for k in (sorting.argsort_stable, sorting.sorted_values):
        monkeypatch.setattr(k, "_built", None)
    return small_build


def _copy_of(build: Path, tmp_path: Path) -> tuple[Path, dict]:
    """A copy of the build ``build`` in ``tmp_path`` and its manifest, to be changed by a test."""
    copy = tmp_path / ahead.FOLDER
    copy.mkdir()
    for path in build.iterdir():
        copy.joinpath(path.name).write_bytes(path.read_bytes())
    return copy, json.loads((copy / ahead.MANIFEST).read_text())


def test_the_build_holds_what_was_called(small_build: Path) -> None:
    manifest = json.loads((small_build / ahead.MANIFEST).read_text())
    assert manifest["key"] == ahead.remembered_sources_key()
    names = sorted(manifest["kernels"])
    assert names == [
        "omega_prime_visibility.geometry.sorting:argsort_stable",
        "omega_prime_visibility.geometry.sorting:sorted_values",
    ]
    readonly_ints = manifest["kernels"][names[1]][0]["arguments"]
    assert readonly_ints == ["tuple", ["array", "<i8", 1, "C", True, True]]


def test_built_code_gives_numbas_bits(from_build) -> None:
    ((_, built),) = ahead.exports_of("omega_prime_visibility.geometry.sorting:argsort_stable")
    rng = np.random.default_rng(5)
    for keys in (rng.normal(size=1000) * 1e6, np.round(rng.normal(size=500), 1), np.array([]), np.zeros(7)):
        assert np.array_equal(built(keys), sorting.argsort_stable.dispatcher(keys))
        assert np.array_equal(built(keys), np.argsort(keys, kind="stable"))


def test_the_build_is_taken_only_for_the_types_it_holds(from_build, monkeypatch) -> None:
    taken = []
    ((key, built),) = ahead.exports_of("omega_prime_visibility.geometry.sorting:argsort_stable")
    monkeypatch.setattr(sorting.argsort_stable, "_built", [(key, lambda *a: taken.append(1) or built(*a))])
    keys = np.array([0.5, -1.0, 0.25])
    assert sorting.argsort_stable(keys).tolist() == [1, 2, 0] and taken == [1]
    # another dtype, a strided view, read-only values: numba's own machine code, never the build's
    for other in (keys.astype(np.float32), np.repeat(keys, 2)[::2], np.array([2, 0, 1])):
        assert np.array_equal(sorting.argsort_stable(other), np.argsort(other, kind="stable"))
    keys.flags.writeable = False
    assert sorting.argsort_stable(keys).tolist() == [1, 2, 0]
    assert taken == [1]


def test_a_build_of_other_sources_is_left_aside(small_build: Path, tmp_path: Path, monkeypatch) -> None:
    stale, manifest = _copy_of(small_build, tmp_path)
    manifest["key"] = "0" * 16
    (stale / ahead.MANIFEST).write_text(json.dumps(manifest))
    monkeypatch.setattr(ahead, "folders", lambda: [stale])
    monkeypatch.setattr(ahead, "_EXPORTS", None)
    assert ahead.current_build() is None
    assert ahead.exports_of("omega_prime_visibility.geometry.sorting:argsort_stable") == []


def test_a_damaged_build_is_left_aside(small_build: Path, tmp_path: Path, monkeypatch) -> None:
    damaged = tmp_path / ahead.FOLDER
    damaged.mkdir()
    for path in small_build.iterdir():
        data = path.read_bytes()
        damaged.joinpath(path.name).write_bytes(data if path.name == ahead.MANIFEST else data[: len(data) // 3])
    monkeypatch.setattr(ahead, "folders", lambda: [damaged])
    monkeypatch.setattr(ahead, "_EXPORTS", None)
    assert ahead.exports_of("omega_prime_visibility.geometry.sorting:argsort_stable") == []
    monkeypatch.setattr(sorting.argsort_stable, "_built", None)
    assert sorting.argsort_stable(np.array([1.0, 0.0])).tolist() == [1, 0]


def test_the_switch_leaves_the_build_aside(from_build, monkeypatch) -> None:
    monkeypatch.setenv(ahead.SWITCH, "0")
    assert ahead.exports_of("omega_prime_visibility.geometry.sorting:argsort_stable") == []


CALL = """
import sys
from omega_prime_visibility.cli import main
ego, out, *more = sys.argv[1:]
sys.argv = ["omega-prime-visibility", "run", "highway_merge.mcap", "--ego", ego, "-o", out, *more]
try:
    main()
finally:
    print("numba imported" if "numba" in sys.modules else "numba not imported", file=sys.stderr)
"""


NOTE_AND_BUILD = """
import sys
from pathlib import Path
from omega_prime_visibility._compiled import ahead_build, kernel
from omega_prime_visibility.cli import main
folder, out = sys.argv[1:3]
calls = kernel.record_calls()
for mode in ("2d", "3d"):  # the default engine of each
    sys.argv = ["omega-prime-visibility", "run", "highway_merge.mcap", "--ego", "0", "-o", out, "--mode", mode]
    try:
        main()
    except SystemExit as stop:
        assert not stop.code, stop.code
ahead_build.build(calls, Path(folder))
"""


def test_the_default_calls_run_from_the_build_without_numba(tmp_path: Path) -> None:
    cache = tmp_path / "cache"
    folder = cache / "omega-prime-visibility" / "kernels" / ahead.FOLDER
    # what compile does (compile_ahead), for the default calls of 2D and 3D only: noted while they run, then built;
    # every object as observer then takes kernels the build lacks from numba, in the same process
    done = subprocess.run([sys.executable, "-c", NOTE_AND_BUILD, str(folder), str(tmp_path / "noted.parquet")],
                          cwd=REPO, capture_output=True, text=True, timeout=1200)  # fmt: skip
    assert done.returncode == 0, done.stderr[-2000:]
    # a user whose cache holds only the build (no package copy): nothing of numba's is loaded, the table is numba's
    env = os.environ | {"XDG_CACHE_HOME": str(cache)}
    env.pop("NUMBA_CACHE_DIR", None)
    for ego, mode in (("0", "2d"), ("all", "2d"), ("0", "3d")):
        out = tmp_path / f"built-{ego}-{mode}.parquet"
        done = subprocess.run([sys.executable, "-c", CALL, ego, str(out), "--mode", mode], cwd=REPO, env=env,
                              capture_output=True, text=True, timeout=600)  # fmt: skip
        assert done.returncode == 0, done.stderr[-2000:]
        if ego == "0":
            assert done.stderr.strip().endswith("numba not imported"), done.stderr[-2000:]
        reference = tmp_path / f"numba-{ego}-{mode}.parquet"
        off = {ahead.SWITCH: "0", "XDG_CACHE_HOME": os.environ.get("XDG_CACHE_HOME", str(Path.home() / ".cache"))}
        done = subprocess.run([sys.executable, "-c", CALL, ego, str(reference), "--mode", mode], cwd=REPO,
                              env=env | off, capture_output=True, text=True, timeout=1200)  # fmt: skip
        assert done.returncode == 0 and done.stderr.strip().endswith("numba imported"), done.stderr[-2000:]
        assert pq.read_table(out).equals(pq.read_table(reference))


def test_kernels_with_options_the_build_would_drop_are_left_to_numba() -> None:
    from omega_prime_visibility._compiled.kernel import njit

    @njit(cache=False, error_model="numpy")
    def ratio(a, b):
        return a / b

    calls: dict = {}
    old, kernel.CALLED = kernel.CALLED, calls
    try:
        assert ratio(1.0, 0.0) == np.inf  # (numpy's error model: no ZeroDivisionError)
        sorting.sorted_values(np.array([2.0, 1.0]))
    finally:
        kernel.CALLED = old
    assert [k for _, _, k, _ in ahead_build.exports(calls)] == [sorting.sorted_values]


def test_types_the_build_never_stands_for() -> None:
    from numba.core import types

    point = types.NamedUniTuple(types.float64, 2, __import__("collections").namedtuple("Point", "x y"))
    for numba_type in (types.IntegerLiteral(3), types.BooleanLiteral(True), point, types.unicode_type):
        assert ahead_build.type_key(numba_type) is None
    unaligned = types.Array(types.float64, 1, "C", aligned=False)
    assert ahead_build.type_key(unaligned) == ("array", "<f8", 1, "C", False, False)


@pytest.mark.parametrize(
    "change",
    [{"format": ahead.FORMAT + 1}, {"numba": "0.1.0"}, {"numpy": 1}, {"extension": "x.cpython-27.so"}, {"sha256": ""}],
)
def test_a_build_for_another_numba_numpy_python_or_format_is_left_aside(
    small_build: Path, tmp_path: Path, monkeypatch, change
) -> None:
    other, manifest = _copy_of(small_build, tmp_path)
    monkeypatch.setattr(ahead, "folders", lambda: [other])
    assert ahead.current_build() is not None
    (other / ahead.MANIFEST).write_text(json.dumps(manifest | change))
    assert ahead.current_build() is None


def test_the_package_copy_keeps_a_build_the_user_cache_lacks(small_build: Path, tmp_path: Path, monkeypatch) -> None:
    import shutil

    from omega_prime_visibility._compiled import copies, sources

    package = tmp_path / "package" / "_kernels"
    shutil.copytree(small_build, package / ahead.FOLDER)
    monkeypatch.setattr(sources, "BUNDLE", package)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setattr(copies.config, "CACHE_DIR", "")
    sources.kernels_cache().mkdir(parents=True)
    assert copies.bundle() == package
    assert ahead.read_manifest(package / ahead.FOLDER) == ahead.read_manifest(small_build)


def test_the_processor_level_is_x86_64_v3_only_where_every_processor_has_its_instructions(tmp_path, monkeypatch):
    monkeypatch.setattr(ahead.platform, "machine", lambda: "x86_64")
    # x86-64-v3 (AVX, AVX2, BMI1, BMI2, F16C, FMA, LZCNT, MOVBE, XSAVE) and v2 under it, as Linux names them
    v3 = "avx avx2 bmi1 bmi2 f16c fma abm movbe xsave cx16 lahf_lm popcnt pni sse4_1 sse4_2 ssse3".split()
    assert set(v3) <= ahead.V3_FLAGS
    info = tmp_path / "cpuinfo"
    every = " ".join(sorted(ahead.V3_FLAGS | {"fpu", "sse2", "avx512f"}))
    info.write_text(f"processor\t: 0\nflags\t\t: {every}\n\nprocessor\t: 1\nflags\t\t: {every}\n")
    assert ahead.processor_level(info) == ahead.X86_64_V3
    info.write_text(f"processor\t: 0\nflags\t\t: {every}\n\nprocessor\t: 1\nflags\t\t: {every.replace('fma', 'f')}\n")
    assert ahead.processor_level(info) == ""  # (one processor without FMA)
    assert ahead.processor_level(tmp_path / "none") == ""
    info.write_text("processor\t: 0\n")
    assert ahead.processor_level(info) == ""  # (no flags said)
    monkeypatch.setattr(ahead.platform, "machine", lambda: "aarch64")
    info.write_text(f"flags\t\t: {every}\n")
    assert ahead.processor_level(info) == ""


def test_a_build_for_x86_64_v3_is_taken_only_where_the_machine_has_it(small_build: Path, tmp_path: Path, monkeypatch):
    """The build records the level it was compiled for; one for x86-64-v3 is left aside on a machine without those
    instructions (its code would stop at the first one), a baseline build is taken everywhere."""
    assert ahead.read_manifest(small_build)["cpu"] == ahead.processor_level()
    other, manifest = _copy_of(small_build, tmp_path)
    monkeypatch.setattr(ahead, "folders", lambda: [other])
    for built, here, taken in [("x86-64-v3", "x86-64-v3", True), ("x86-64-v3", "", False), ("", "", True),
                               ("", "x86-64-v3", True), ("znver9", "x86-64-v3", False)]:  # fmt: skip
        (other / ahead.MANIFEST).write_text(json.dumps(manifest | {"cpu": built}))
        monkeypatch.setattr(ahead, "processor_level", lambda cpuinfo=None, level=here: level)
        assert (ahead.current_build() is not None) == taken, (built, here)
