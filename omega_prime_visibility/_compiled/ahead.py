"""The ahead-of-time build of the reader's and the engines' kernels: found, checked, loaded.

``omega-prime-visibility compile`` (which ``make run`` and building the package run) compiles every kernel the MCAP
reader and the engines (``visilibity``, ``sweep``, ``raycast3d``, ``silhouette3d``) call from Python into one
extension module with numba's ahead-of-time compiler (:mod:`.ahead_build`), for each argument type it was called
with. The module needs neither numba nor LLVM to load. It is compiled for :func:`processor_level`: x86-64-v3 (AVX2
and FMA, the processors of the last ten years) where the machine building it has those instructions and says so
(Linux), else the processor family's baseline (x86-64 without AVX, or aarch64); a build for x86-64-v3 is loaded only
where the machine has them too, a baseline build everywhere. Its manifest names the sources it was built from
(:func:`.sources.sources_key`): after any edit of a kernel's sources, or under another numpy, it is left aside and
numba's cache serves (compiling what the edit touched) until ``compile`` runs again.

Examples
--------
>>> built = exports_of("omega_prime_visibility.no_such_module:kernel")
>>> built
[]
"""

from __future__ import annotations

import functools
import hashlib
import importlib.machinery
import importlib.util
import json
import os
import platform
import sys
import threading
from collections.abc import Callable
from pathlib import Path

import numpy as np

from . import sources
from .sources import remembered_sources_key

FOLDER = "ahead"
"""The build's folder under the package's copy of its kernels (:data:`.sources.BUNDLE`) or the user's cache."""
MODULE = "omega_prime_visibility_ahead"
"""The extension module's name (its file: ``omega_prime_visibility_ahead-<digest>.cpython-311-x86_64-linux-gnu.so``,
named by its SHA-256)."""
SWITCH = "OMEGA_PRIME_VISIBILITY_AHEAD"
"""``OMEGA_PRIME_VISIBILITY_AHEAD=0`` leaves the build aside (every kernel from numba, as before it was built)."""
FORMAT = 2
"""The version of the build's layout and of its argument keys (:func:`.kernel.value_key`): a build of another is
left aside. 2: the manifest holds the processor level (a package that reads format 1 would not check it, and must
never load a build for x86-64-v3 on a machine without those instructions)."""
SUFFIXES = tuple(importlib.machinery.EXTENSION_SUFFIXES)
"""The file endings this Python loads extensions by (a build for another Python is left aside)."""
MANIFEST = "manifest.json"
"""What the build holds: its format, the sources' key, numpy's major version, numba's version, the processor level
(:func:`processor_level`), the extension's file name and SHA-256 and, per kernel, its exports and their argument
types (:func:`.kernel.value_key`)."""

X86_64_V3 = "x86-64-v3"
"""The processor level a build on a machine with :data:`V3_FLAGS` is compiled for (LLVM's name for it)."""
V3_FLAGS = frozenset("avx avx2 bmi1 bmi2 f16c fma abm movbe xsave cx16 lahf_lm popcnt pni sse4_1 sse4_2 ssse3".split())
"""The instructions of x86-64-v3 (and of v2 below it) as Linux's ``/proc/cpuinfo`` names them (``abm``: LZCNT,
``pni``: SSE3)."""
CPUINFO = Path("/proc/cpuinfo")

_LOCK = threading.Lock()
_EXPORTS: dict[str, list[tuple[tuple, Callable]]] | None = None


def folders() -> list[Path]:
    """Where a build is looked for, in order: the user's cache (where ``compile`` builds it), then the package's
    copy of its kernels (a fresh user's)."""
    return [sources.kernels_cache() / FOLDER, sources.BUNDLE / FOLDER]


def exports_of(name: str) -> list[tuple[tuple, Callable]]:
    """The built machine code of the kernel ``name`` (``"module:qualname"``): one ``(argument types, function)``
    pair per argument types it was built for, or none (no build, or one for other sources)."""
    global _EXPORTS
    if _EXPORTS is None:
        with _LOCK:
            if _EXPORTS is None:
                _EXPORTS = _load()
    return _EXPORTS.get(name, [])


def current_build() -> tuple[Path, dict] | None:
    """The extension and manifest of the build that fits: made by this format of the build, for the current
    sources, numpy major version, numba and Python, its file whole (its SHA-256); None where none fits.

    >>> found = current_build()
    >>> found is None or found[0].parent.name == FOLDER
    True
    """
    key = remembered_sources_key()
    for folder in folders():
        manifest = read_manifest(folder)
        if manifest is None or [manifest.get(k) for k in ("format", "key", "numpy")] != [FORMAT, key, _numpy_major()]:
            continue
        name = manifest.get("extension")
        if manifest.get("numba") != installed_numba() or not isinstance(name, str) or not name.endswith(SUFFIXES):
            continue
        if manifest.get("cpu", "") not in ("", processor_level()):  # (a build for x86-64-v3 on a machine without)
            continue
        try:  # (the file is named by its digest: a build replaced meanwhile is another file, never this one)
            if manifest.get("sha256") == digest(folder / name):
                return folder / name, manifest
        except OSError:
            pass
    return None


def processor_level(cpuinfo: Path | None = None) -> str:
    """The processor level builds are made for and may be loaded on here: :data:`X86_64_V3` on an x86-64 machine
    whose ``/proc/cpuinfo`` (or ``cpuinfo``) lists every one of :data:`V3_FLAGS` for every processor, else ``""``
    (the family's baseline: any machine of it runs such a build).

    >>> import tempfile
    >>> with tempfile.TemporaryDirectory() as tmp:
    ...     info = Path(tmp) / "cpuinfo"
    ...     _ = info.write_text("flags : fpu sse2 avx avx2")  # (a processor without BMI, FMA, ...)
    ...     processor_level(info)
    ''
    """
    if cpuinfo is None:
        return _machine_level()
    if platform.machine().lower() not in ("x86_64", "amd64"):
        return ""
    try:
        text = cpuinfo.read_text(encoding="utf-8", errors="replace")
    except OSError:
        return ""
    flags = [set(line.partition(":")[2].split()) for line in text.splitlines() if line.startswith("flags")]
    return X86_64_V3 if flags and all(V3_FLAGS <= one for one in flags) else ""


@functools.cache
def _machine_level() -> str:
    return processor_level(CPUINFO) if sys.platform.startswith("linux") else ""


def read_manifest(folder: Path) -> dict | None:
    """The build's manifest in ``folder``, or None where there is none or it cannot be read."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, ValueError):
        return None
    return manifest if isinstance(manifest, dict) else None


def installed_numba() -> str | None:
    """The version of the numba installed beside the package, read from its distribution's folder name without
    importing numba (the build is used only with the numba it was compiled by: their machine code is the same)."""
    spec = importlib.util.find_spec("numba")
    if spec is None or spec.origin is None:
        return None
    found = sorted(Path(spec.origin).parent.parent.glob("numba-*.dist-info"))
    return found[0].name.removeprefix("numba-").removesuffix(".dist-info") if len(found) == 1 else None


def _numpy_major() -> int:
    return int(np.__version__.split(".")[0])


def digest(path: Path) -> str:
    """The SHA-256 of the file ``path`` (the manifest holds the extension's: a damaged file is never loaded)."""
    return hashlib.sha256(path.read_bytes()).hexdigest()


def _load() -> dict[str, list[tuple[tuple, Callable]]]:
    if os.environ.get(SWITCH, "1").strip().lower() in ("0", "no", "false"):
        return {}
    found = current_build()
    if found is None:
        return {}
    path, manifest = found
    try:
        spec = importlib.util.spec_from_file_location(MODULE, path)
        module = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(module)
        return {
            name: [(_as_key(entry["arguments"]), getattr(module, entry["export"])) for entry in entries]
            for name, entries in manifest["kernels"].items()
        }
    except Exception:  # a damaged build, of any kind: numba serves
        return {}


def _as_key(data) -> tuple:
    """A key read back from JSON (lists) as :func:`.kernel.value_key` makes it (tuples)."""
    if isinstance(data, list):
        return tuple(_as_key(item) for item in data)
    return data
