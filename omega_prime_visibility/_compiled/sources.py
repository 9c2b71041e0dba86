"""What the kernels are compiled from: each numba module's stamp (a hash of every source its kernels can reach),
one key for them all, and where they are kept (the user's cache, the package's copy).

Examples
--------
>>> from omega_prime_visibility._compiled.sources import source_stamps
>>> len(source_stamps()["geometry/kernels.py"])
16
"""

from __future__ import annotations

import ast
import hashlib
import json
import os
import re
import sys
from pathlib import Path

PACKAGE = Path(__file__).resolve().parents[1]
USES_NUMBA = re.compile(rb"^\s*(?:import numba|from numba[ .]|from \.+_compiled\.kernel import )", re.MULTILINE)
"""A module holding kernels: it imports numba or the package's kernel decorator (:mod:`.kernel`)."""
CACHE_MODULES = "_compiled"
"""This subpackage (numba's locator for the package among it): it uses numba but holds no kernels, so editing it
compiles nothing."""


def python_sources(root: Path = PACKAGE) -> list[Path]:
    """The ``.py`` files under ``root``, sorted, leaving out caches and kernel copies (``__pycache__``, ``_kernels``,
    hidden folders), whose folders other processes may be writing or removing meanwhile."""
    found = []
    for folder, subfolders, files in os.walk(root):  # (a folder gone meanwhile is skipped)
        subfolders[:] = [d for d in subfolders if not d.startswith((".", "__pycache__", "_kernels"))]
        found.extend(Path(folder) / name for name in files if name.endswith(".py"))
    return sorted(found)


def import_graph(root: Path = PACKAGE) -> tuple[dict[str, Path], dict[str, set[str]]]:
    """The package's modules under ``root`` (dotted names relative to it, ``""`` for the package itself) and, for
    each, the package's modules it imports (imports inside functions included)."""
    names = {path: path.relative_to(root).with_suffix("").as_posix().replace("/", ".") for path in python_sources(root)}
    modules = {name: path for path, name in names.items()}
    modules = {name.removesuffix("__init__").rstrip("."): path for name, path in modules.items()}

    def imported(name: str) -> set[str]:
        tree = ast.parse(modules[name].read_bytes())
        package = name if modules[name].name == "__init__.py" else name.rpartition(".")[0]
        found = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                base = package.split(".") if package else []
                base = base[: len(base) - node.level + 1] if node.level else []
                stem = ".".join(filter(None, [*base, node.module or ""]))
                if node.level == 0 and not stem.startswith(root.name):
                    continue
                stem = stem.removeprefix(root.name).lstrip(".")
                found |= {stem} | {f"{stem}.{alias.name}".lstrip(".") for alias in node.names}
            elif isinstance(node, ast.Import):
                found |= {
                    a.name.removeprefix(root.name).lstrip(".") for a in node.names if a.name.startswith(root.name)
                }
        return {m for m in found if m in modules and m != name}

    return modules, {name: imported(name) for name in modules}


def kernel_closures(root: Path = PACKAGE) -> dict[Path, list[Path]]:
    """For each module under ``root`` that uses numba, the modules its kernels can reach: itself and every module
    of the package it imports, at any depth. Front ends (plots, batch, CLI) are among none of them, so editing
    those compiles nothing."""
    modules, imports = import_graph(root)
    closures = {}
    for name, path in modules.items():
        if name.startswith(CACHE_MODULES) or not USES_NUMBA.search(path.read_bytes()):
            continue
        reached, todo = set(), [name]
        while todo:
            if (current := todo.pop()) not in reached:
                reached.add(current)
                todo.extend(imports[current] - reached)
        closures[path] = sorted(modules[m] for m in reached if not m.startswith(CACHE_MODULES))
    return closures


def kernel_sources(root: Path = PACKAGE) -> list[Path]:
    """Every module some kernel can reach (the union of :func:`kernel_closures`)."""
    return sorted({path for closure in kernel_closures(root).values() for path in closure})


def _digest(paths: list[Path], root: Path) -> str:
    digest = hashlib.sha256()
    for path in paths:
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def sources_key(root: Path = PACKAGE) -> str:
    """16 hex digits of the SHA-256 of the :func:`kernel_sources` under ``root`` (names and contents): one name
    for this version of all the kernels.

    Examples
    --------
    >>> len(sources_key()), sources_key() == sources_key()
    (16, True)
    """
    return _digest(kernel_sources(root), root)


def source_stamps(root: Path = PACKAGE) -> dict[str, str]:
    """Each numba module's stamp: 16 hex digits of the SHA-256 of its :func:`kernel_closures` (names and contents),
    by its path relative to ``root`` (``"engines/sweep/heap_sweep.py"``). A cached kernel is used only under the
    stamp it was compiled with.

    Examples
    --------
    >>> stamps = source_stamps()
    >>> stamps["geometry/kernels.py"] != stamps["engines/sweep/heap_sweep.py"]
    True
    """
    return {
        path.relative_to(root).as_posix(): _digest(closure, root) for path, closure in kernel_closures(root).items()
    }


def cache_base() -> Path:
    """``~/.cache/omega-prime-visibility`` (or under ``$XDG_CACHE_HOME``)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "omega-prime-visibility"


def numba_cache_dir() -> str:
    """numba's cache folder setting (``NUMBA_CACHE_DIR``), ``""`` when unset; read without importing numba where
    numba is not loaded yet (its setting comes from the environment then)."""
    numba = sys.modules.get("numba")
    if numba is not None and hasattr(numba, "config"):
        return numba.config.CACHE_DIR
    return os.environ.get("NUMBA_CACHE_DIR", "")


def kernels_cache() -> Path:
    """The user's cache of the package's kernels: ``~/.cache/omega-prime-visibility/kernels``."""
    return cache_base() / "kernels"


BUNDLE = PACKAGE / "_kernels"
"""The package's own copy of its compiled kernels, laid out as :func:`kernels_cache` is: written when the package is
built (setup.py) and by ``omega-prime-visibility compile``; a user, container or dask worker whose cache lacks a
module's kernels starts from it instead of compiling, as long as the machine's CPU is the one they were compiled on
(else numba compiles anew)."""


_THIS_PROCESS: dict[Path, tuple[str, dict[str, str]]] = {}
"""The package's own (:data:`PACKAGE`) key and stamps, once looked up: numba asks for every kernel it defines."""


def remembered_sources(root: Path = PACKAGE) -> tuple[str, dict[str, str]]:
    """:func:`sources_key` and :func:`source_stamps`, remembered by the names, sizes and modification times of every
    source under ``root``: a few milliseconds per process instead of parsing them all (any edit, checkout or upgrade
    changes a time or a size, and so computes them anew), and for the package itself once per process. Where
    nothing can be remembered, they are computed."""
    if root == PACKAGE and PACKAGE in _THIS_PROCESS:
        return _THIS_PROCESS[PACKAGE]
    found = _remembered(root)
    if root == PACKAGE:
        _THIS_PROCESS[PACKAGE] = found
    return found


def _remembered(root: Path) -> tuple[str, dict[str, str]]:
    paths = python_sources(root)
    stats = hashlib.sha256()
    for path in paths:
        info = path.stat()
        stats.update(f"{path.relative_to(root).as_posix()}\0{info.st_size}\0{info.st_mtime_ns}\0".encode())
    memo = cache_base() / "sources" / stats.hexdigest()[:32]
    found = _read_memo(memo)
    if found is not None:
        return found
    # the sources' contents (a few milliseconds to hash): remembered by an earlier process, or by the package's copy
    # of its kernels, whose sources are these (a fresh user, container or node, whose files have new times)
    by_contents = f"contents-{_digest(paths, root)}"
    found = _read_memo(memo.with_name(by_contents)) or _read_memo(BUNDLE / "sources" / by_contents)
    if found is None:
        found = key_and_stamps(root)
        write_memo(memo.with_name(by_contents), found)
    write_memo(memo, found)
    return found


def key_and_stamps(root: Path = PACKAGE) -> tuple[str, dict[str, str]]:
    """:func:`sources_key` and :func:`source_stamps` at once (the import graph parsed once)."""
    closures = kernel_closures(root)
    reached = sorted({path for closure in closures.values() for path in closure})
    stamps = {path.relative_to(root).as_posix(): _digest(closure, root) for path, closure in closures.items()}
    return _digest(reached, root), stamps


def _read_memo(memo: Path) -> tuple[str, dict[str, str]] | None:
    try:
        known = json.loads(memo.read_text(encoding="ascii"))
        if re.fullmatch(r"[0-9a-f]{16}", known["key"]) and isinstance(known["stamps"], dict):
            return known["key"], known["stamps"]
    except (OSError, UnicodeDecodeError, ValueError, KeyError, TypeError):
        pass
    return None


def write_memo(memo: Path, found: tuple[str, dict[str, str]]) -> None:
    """Note the key and stamps ``found`` in the file ``memo`` (whole or not at all; not where it cannot be written)."""
    try:
        memo.parent.mkdir(parents=True, exist_ok=True)
        partial = memo.with_name(f"{memo.name}.{os.getpid()}.partial")
        partial.write_text(json.dumps({"key": found[0], "stamps": found[1]}), encoding="ascii")
        os.replace(partial, memo)  # whole or not at all, as two processes may start at once
    except OSError:
        pass


def contents_memo(root: Path = PACKAGE) -> Path:
    """The user cache's note of the key and stamps of the current sources, by their contents (the package's copy of
    its kernels carries it: :func:`.copies.bundle`)."""
    return cache_base() / "sources" / f"contents-{_digest(python_sources(root), root)}"


def remembered_sources_key(root: Path = PACKAGE) -> str:
    """:func:`sources_key`, remembered (:func:`remembered_sources`)."""
    return remembered_sources(root)[0]
