"""Telling a user that kernels compile: which engine paths ran to the end with this version of the kernels (notes
beside the cache), the announcement on stderr, and a heartbeat while it lasts."""

from __future__ import annotations

import inspect
import os
import sys
import threading
import time
from pathlib import Path

from . import sources
from .sources import PACKAGE, kernels_cache, numba_cache_dir, remembered_sources_key


def kernel_folder() -> Path | None:
    """The folder the package's kernels are cached in by this process: the user's ``NUMBA_CACHE_DIR`` when set,
    else :func:`kernels_cache` where it can be written, else None (numba's default, next to the sources)."""
    if numba_cache_dir():
        return Path(numba_cache_dir())
    folder = kernels_cache()
    try:
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".writable-{os.getpid()}"
        probe.touch()
        probe.unlink()
    except OSError:
        return None
    return folder


def compiled_before(source: Path) -> bool:
    """Whether numba's own cache (next to the sources, or under ``NUMBA_CACHE_DIR``) holds kernels of the module
    ``source`` (a ``.py`` file), or of any module in it (a folder)."""
    import numba
    from numba.core.caching import UserProvidedCacheLocator

    folder = source if source.is_dir() else source.parent
    if numba.config.CACHE_DIR:
        cached = Path(numba.config.CACHE_DIR) / UserProvidedCacheLocator.get_suitable_cache_subpath(str(folder / "_"))
    else:
        cached = folder / "__pycache__"
    pattern = "*.nbi" if source.is_dir() else f"{source.stem}.*.nbi"
    return any(cached.glob(pattern))


ANNOUNCE = True
"""Whether :func:`announce_compilation` speaks (``omega-prime-visibility compile`` says it all itself)."""


def marker_name(path_key: str) -> str:
    """The name of the file saying that one path of an engine (``path_key``, e.g. ``"sweep"`` or
    ``"sweep+sensors"``) ran to the end with this version of the kernels (:func:`sources_key`)."""
    return f".ran-{remembered_sources_key()}-{path_key}"


def marker(path_key: str) -> Path | None:
    """Where :func:`mark_compiled` notes that a path of an engine ran to the end; None where numba caches next to
    the sources."""
    folder = kernel_folder()
    return folder / marker_name(path_key) if folder is not None else None


def has_run(path_key: str) -> bool | None:
    """Whether this path of an engine ran to the end with this version of the kernels, here or where the package's
    copy (:data:`.sources.BUNDLE`) was compiled, so its kernels are there; None where numba caches next to the
    sources."""
    done = marker(path_key)
    if done is None:
        return None
    bundled = not numba_cache_dir() and (sources.BUNDLE / marker_name(path_key)).exists()
    return done.exists() or bundled


def announce_compilation(name: str, engine_class: type, path_key: str | None = None) -> bool:
    """Say on stderr that an engine's kernels are about to be compiled, when this path of it (``path_key``, default
    the engine's name) never ran to the end with these sources (a first run stays silent for up to a minute or two
    otherwise); return whether it said so. Without a cache folder of our own, whether the engine's own modules have
    cached kernels decides."""
    if not ANNOUNCE:
        return False
    ran = has_run(path_key or name)
    if ran:
        return False
    if ran is None:
        module = Path(inspect.getfile(engine_class))
        source = module.parent if module.parent != PACKAGE / "engines" else module  # its subpackage, or its module
        if compiled_before(source):
            return False
    through = " for sensors" if (path_key or "").endswith("+sensors") else ""
    print(
        f"omega-prime-visibility: compiling the {name} engine's kernels{through}, once per version of the package "
        "(up to a minute or two; later runs start at once)",
        file=sys.stderr,
        flush=True,
    )
    return True


HEARTBEAT_S = 5.0
"""Seconds between the lines that tell a first call is still compiling (never silent longer)."""


class Heartbeat:
    """A line on stderr every :data:`HEARTBEAT_S` seconds, from :meth:`start` until :meth:`stop`, saying that
    ``what`` is still compiling (a first call's progress bar stays at 0 % meanwhile)."""

    def __init__(self, what: str) -> None:
        self.what = what
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None

    def start(self) -> Heartbeat:
        started = time.perf_counter()

        def beat() -> None:
            while not self._stop.wait(HEARTBEAT_S):
                print(f"omega-prime-visibility: ... {time.perf_counter() - started:.0f} s, still compiling {self.what}",
                      file=sys.stderr, flush=True)  # fmt: skip

        self._thread = threading.Thread(target=beat, name="compile-heartbeat", daemon=True)
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=1.0)
            self._thread = None


def mark_compiled(path_key: str) -> None:
    """Note that this path of an engine ran to the end (see :func:`marker`); a read-only cache is left alone."""
    done = marker(path_key)
    if done is not None:
        try:
            done.touch()
        except OSError:
            pass
