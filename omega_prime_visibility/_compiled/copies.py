"""Copies of cached kernels between the user's cache and the package's (:data:`.sources.BUNDLE`): only those
stamped for the current sources and numba, each file whole."""

from __future__ import annotations

import os
import pickle
import shutil
from pathlib import Path

import numba
from numba.core import config

from . import ahead, sources


def index_of(path: Path) -> tuple[str, object, dict] | None:
    """numba's cache index file (``.nbi``) read: its numba version, source stamp and overloads (signature and
    machine -> data file name); None where it cannot be read."""
    try:
        with open(path, "rb") as f:
            version = pickle.load(f)
            stamp, overloads = pickle.loads(f.read())
    except Exception:
        return None
    return version, stamp, overloads


def copy_current(source: Path, target: Path, folder: str) -> int:
    """Copy from the cache folder ``source`` into ``target`` every kernel index (with its data files) that is
    stamped for the current sources and numba, where ``target``'s own is missing or stamped otherwise; ``folder``
    is their place in the package. The number of indexes copied. Data files first, then the index, each whole (a
    process reading meanwhile sees the old entry or the new one)."""
    if not source.is_dir():
        return 0
    stamps = sources.remembered_sources()[1]
    prefix = "" if folder == "_root" else f"{folder}/"
    copied = 0
    for index in sorted(source.glob("*.nbi")):
        module = index.name.split(".", 1)[0]
        expected = stamps.get(f"{prefix}{module}.py")
        found = index_of(index)
        if expected is None or found is None or found[:2] != (numba.__version__, expected):
            continue
        own = index_of(target / index.name)
        if own is not None and own[:2] == (numba.__version__, expected):
            continue
        try:
            target.mkdir(parents=True, exist_ok=True)
            for name in sorted(set(found[2].values())):
                _copy_whole(source / name, target / name)
            _copy_whole(index, target / index.name)
        except OSError:
            continue
        copied += 1
    return copied


def _copy_whole(source: Path, target: Path) -> None:
    partial = target.with_name(f".{target.name}.{os.getpid()}.partial")
    try:
        shutil.copyfile(source, partial)
        os.replace(partial, target)
    finally:
        partial.unlink(missing_ok=True)


def bundle() -> Path | None:
    """Copy the user's cached kernels of the current sources into :data:`.sources.BUNDLE` (in place of what it
    held), with the notes of which engine paths ran and the ahead-of-time build (:mod:`.ahead`); the copy's
    folder, or None where the package's folder cannot be written or the user chose ``NUMBA_CACHE_DIR``."""
    source = sources.kernels_cache()
    if config.CACHE_DIR or not source.is_dir():
        return None
    target = sources.BUNDLE
    partial = target.with_name(f".{target.name}.{os.getpid()}.partial")
    try:
        shutil.rmtree(partial, ignore_errors=True)
        partial.mkdir()
        for folder in sorted(p for p in source.rglob("*") if p.is_dir()):
            relative = folder.relative_to(source).as_posix()
            copy_current(folder, partial / relative, relative)
        key = sources.remembered_sources_key()
        for done in source.glob(f".ran-{key}-*"):
            shutil.copyfile(done, partial / done.name)
        memo = sources.contents_memo()  # the sources' key and stamps by their contents: no fresh user parses them
        sources.write_memo(memo, sources.remembered_sources())
        (partial / "sources").mkdir()
        shutil.copyfile(memo, partial / "sources" / memo.name)
        built = ahead.current_build()  # the engines' kernels built ahead of time (here, or the user's)
        if built is not None:
            shutil.copytree(built[0].parent, partial / ahead.FOLDER)
        shutil.rmtree(target, ignore_errors=True)
        os.replace(partial, target)
    except OSError:
        shutil.rmtree(partial, ignore_errors=True)
        return None
    return target
