"""numba's cache locator for the package's kernels (see :mod:`omega_prime_visibility._compiled` for the policy).

A kernel of the module ``engines/sweep/heap_sweep.py`` is cached in ``<kernels>/engines/sweep/``, under the module's
stamp (a hash of every source it can reach), wherever the package lies: a cache compiled in the build folder, in a
container image or in another clone is valid in this one. Where the user's cache lacks a module's kernels (or holds
them for other sources) and the package's copy (:data:`.sources.BUNDLE`) has them, they are copied first; numba
then checks them as always (numba's version, the CPU, the signature and the function's bytecode) and compiles
anew where one does not fit.

Loaded by numba's caching (never by importing the package), so it may import numba.
"""

from __future__ import annotations

import threading
from pathlib import Path

from numba.core import caching, config
from numba.core.caching import _CacheLocator

from . import sources

_LOCK = threading.Lock()
_SEEDED: set[str] = set()
"""The folders (relative to the package) whose kernels this process took from the package's copy already."""


def register(caching) -> None:
    """Put :class:`PackageLocator` first among the locators of numba's caching module ``caching`` (once)."""
    if PackageLocator not in caching.CacheImpl._locator_classes:
        caching.CacheImpl._locator_classes = [PackageLocator, *caching.CacheImpl._locator_classes]


class PackageLocator(_CacheLocator):
    """Where numba caches a kernel defined in the package: under :func:`.sources.kernels_cache`, in the folder of
    the module's place in the package, stamped with the module's :func:`.sources.source_stamps` entry. Kernels
    outside the package, or with ``NUMBA_CACHE_DIR`` set (the user's choice), go to numba's own locators."""

    def __init__(self, py_func, py_file: str, relative: str, stamp: str) -> None:
        self._py_file = py_file
        self._lineno = py_func.__code__.co_firstlineno
        self._relative = relative
        self._stamp = stamp
        self._cache_path = str(sources.kernels_cache() / (Path(relative).parent.as_posix().strip(".") or "_root"))

    def get_cache_path(self) -> str:
        return self._cache_path

    def get_source_stamp(self) -> str:
        return self._stamp

    def get_disambiguator(self) -> str:
        return str(self._lineno)

    @classmethod
    def from_function(cls, py_func, py_file: str):
        if config.CACHE_DIR:
            return None
        try:
            relative = Path(py_file).resolve().relative_to(sources.PACKAGE).as_posix()
        except ValueError:
            return None
        stamp = sources.remembered_sources()[1].get(relative)
        if stamp is None:  # (a module the import graph does not see as using numba)
            return None
        self = cls(py_func, py_file, relative, stamp)
        try:
            self.ensure_cache_path()
        except OSError:  # no cache can be written: numba's own locators decide
            return None
        self._seed()
        return self

    def _seed(self) -> None:
        folder = Path(self._relative).parent.as_posix().strip(".") or "_root"
        with _LOCK:
            if folder in _SEEDED:
                return
            _SEEDED.add(folder)
        from .copies import copy_current  # (here: copies imports numba, which may be loading it now)

        copy_current(sources.BUNDLE / folder, Path(self._cache_path), folder)


register(caching)  # on import (by numba's caching module's loading, or by the package when numba came first)
