"""Where numba keeps the compiled kernels: one folder per version of the package's sources.

numba checks a cached kernel against the file it is defined in only. A kernel that calls (and so compiles in) one
from another module would keep the old machine code after that other module changed: after an upgrade in place or
a ``git pull`` in a clone, silently wrong numbers. Keying the cache folder by a hash of every source a kernel can
reach rules that out; a new version compiles once into a new folder (``~/.cache/omega-prime-visibility/numba/<key>``,
or under ``$XDG_CACHE_HOME``). ``NUMBA_CACHE_DIR``, when set, is the user's choice and is left alone; where no
cache folder can be written, numba's default (next to the sources) applies.
"""

from __future__ import annotations

import ast
import hashlib
import inspect
import os
import re
import sys
import threading
import time
from pathlib import Path

PACKAGE = Path(__file__).resolve().parent
USES_NUMBA = re.compile(rb"^\s*(?:import numba|from numba[ .])", re.MULTILINE)


def kernel_sources(root: Path = PACKAGE) -> list[Path]:
    """The modules compiled kernels can reach: those that use numba, and every module of the package they import
    (at any depth, imports inside functions included). Front ends (plots, batch, CLI) are not among them, so
    editing those does not recompile anything."""
    modules = {path.relative_to(root).with_suffix("").as_posix().replace("/", "."): path for path in root.rglob("*.py")}
    modules = {name.removesuffix(".__init__"): path for name, path in modules.items()}

    def imported(name: str) -> set[str]:
        tree = ast.parse(modules[name].read_bytes())
        package = name if modules[name].name == "__init__.py" else name.rpartition(".")[0]
        found = set()
        for node in ast.walk(tree):
            if isinstance(node, ast.ImportFrom):
                base = package.split(".")
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
        return {m for m in found if m in modules}

    todo = [name for name, path in modules.items() if USES_NUMBA.search(path.read_bytes())]
    reached: set[str] = set()
    while todo:
        name = todo.pop()
        if name not in reached:
            reached.add(name)
            todo.extend(imported(name) - reached)
    return sorted(modules[name] for name in reached)


def sources_key(root: Path = PACKAGE) -> str:
    """16 hex digits of the SHA-256 of the :func:`kernel_sources` under ``root`` (names and contents).

    Examples
    --------
    >>> len(sources_key()), sources_key() == sources_key()
    (16, True)
    """
    digest = hashlib.sha256()
    for path in kernel_sources(root):
        digest.update(path.relative_to(root).as_posix().encode() + b"\0")
        digest.update(path.read_bytes() + b"\0")
    return digest.hexdigest()[:16]


def cache_base() -> Path:
    """``~/.cache/omega-prime-visibility`` (or under ``$XDG_CACHE_HOME``)."""
    return Path(os.environ.get("XDG_CACHE_HOME") or Path.home() / ".cache") / "omega-prime-visibility"


def cache_folder(key: str) -> Path:
    """The cache folder for the sources with this key."""
    return cache_base() / "numba" / key


def remembered_sources_key(root: Path = PACKAGE) -> str:
    """:func:`sources_key`, remembered by the names, sizes and modification times of every source under ``root``:
    a few milliseconds per import instead of parsing them all (any edit, checkout or upgrade changes a time or a
    size, and so computes it anew). Where nothing can be remembered, it is computed."""
    stats = hashlib.sha256()
    for path in sorted(root.rglob("*.py")):
        info = path.stat()
        stats.update(f"{path.relative_to(root).as_posix()}\0{info.st_size}\0{info.st_mtime_ns}\0".encode())
    memo = cache_base() / "source-keys" / stats.hexdigest()[:32]
    try:
        key = memo.read_text(encoding="ascii").strip()
        if re.fullmatch(r"[0-9a-f]{16}", key):
            return key
    except (OSError, UnicodeDecodeError):
        pass
    key = sources_key(root)
    try:
        memo.parent.mkdir(parents=True, exist_ok=True)
        partial = memo.with_name(f"{memo.name}.{os.getpid()}.partial")
        partial.write_text(key, encoding="ascii")
        os.replace(partial, memo)  # whole or not at all, as two processes may start at once
    except OSError:
        pass
    return key


OWN_FOLDER = "OMEGA_PRIME_VISIBILITY_NUMBA_CACHE"
"""Set beside ``NUMBA_CACHE_DIR`` when this package chose that folder, so that a worker process inheriting both
knows the folder is the package's own and not the user's choice."""


def use_versioned_cache() -> str | None:
    """Point numba's cache at :func:`cache_folder` of the current sources (unless the user chose a folder with
    ``NUMBA_CACHE_DIR``); return the folder used, or ``None`` when the user's folder or numba's default applies.

    numba itself is not imported here (importing the package stays quick): where it is not imported yet, the folder
    goes into ``NUMBA_CACHE_DIR``, which numba reads when it is imported; where it is, into its config."""
    numba = sys.modules.get("numba")
    chosen = numba.config.CACHE_DIR if numba is not None else os.environ.get("NUMBA_CACHE_DIR", "")
    if chosen and chosen != os.environ.get(OWN_FOLDER):  # the user's own folder
        return None
    try:
        folder = cache_folder(remembered_sources_key())
        folder.mkdir(parents=True, exist_ok=True)
        probe = folder / f".writable-{os.getpid()}"
        probe.touch()
        probe.unlink()
    except (OSError, RuntimeError, KeyError):  # no home, a read-only file system: numba's default
        return None
    seed_from_bundle(folder)
    os.environ["NUMBA_CACHE_DIR"] = os.environ[OWN_FOLDER] = str(folder)
    if numba is not None:
        numba.config.CACHE_DIR = str(folder)
    return str(folder)


BUNDLE = PACKAGE / "_kernels"
"""Where ``omega-prime-visibility compile`` leaves a copy of the compiled kernels, inside the installed package: a
user, container or dask worker whose own cache is empty starts from it (:func:`seed_from_bundle`) instead of
compiling, as long as the machine's CPU is the one they were compiled on (else numba compiles anew)."""


def seed_from_bundle(folder: Path) -> bool:
    """Fill an empty cache ``folder`` from :data:`BUNDLE`'s copy for the same sources (its name is the sources'
    key); True if it did. A copy made while another process compiles is harmless: numba checks every entry."""
    bundled = BUNDLE / folder.name
    if not bundled.is_dir() or any(folder.rglob("*.nbi")):
        return False
    try:
        import shutil

        shutil.copytree(bundled, folder, dirs_exist_ok=True)
    except OSError:
        return False
    return True


def bundle(folder: str | os.PathLike | None = None) -> Path | None:
    """Copy the cache folder of the current sources (default: the one in use) into :data:`BUNDLE`, replacing
    older versions' copies; the copy's folder, or None where the package's folder cannot be written."""
    import shutil

    source = Path(folder or os.environ.get("NUMBA_CACHE_DIR") or cache_folder(remembered_sources_key()))
    if not source.is_dir():
        return None
    target = BUNDLE / source.name
    partial = BUNDLE / f".{source.name}.{os.getpid()}.partial"
    try:
        BUNDLE.mkdir(exist_ok=True)
        shutil.copytree(source, partial, ignore=shutil.ignore_patterns(".writable-*"))
        shutil.rmtree(target, ignore_errors=True)
        os.replace(partial, target)
        for old in BUNDLE.iterdir():  # other versions' kernels: never used again
            if old.name != target.name:
                shutil.rmtree(old, ignore_errors=True)
    except OSError:
        shutil.rmtree(partial, ignore_errors=True)
        return None
    return target


def compiled_before(source: Path) -> bool:
    """Whether numba's cache holds kernels of the module ``source`` (a ``.py`` file), or of any module in it (a
    folder)."""
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


def marker(path_key: str) -> Path | None:
    """The file saying that one path of an engine (``path_key``, e.g. ``"sweep"`` or ``"sweep+sensors"``) ran to the
    end with the current cache, so its kernels are there; None where numba caches next to the sources."""
    import numba

    folder = numba.config.CACHE_DIR
    return Path(folder) / f".ran-{path_key}" if folder else None


def announce_compilation(name: str, engine_class: type, path_key: str | None = None) -> bool:
    """Say on stderr that an engine's kernels are about to be compiled, when this path of it (``path_key``, default
    the engine's name) never ran to the end with these sources (a first run stays silent for up to a minute or two
    otherwise); return whether it said so. Without a cache folder of our own, whether the engine's own modules have
    cached kernels decides."""
    if not ANNOUNCE:
        return False
    done = marker(path_key or name)
    if done is not None:
        if done.exists():
            return False
    else:
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


CACHE_FOLDER = use_versioned_cache()  # on import, before any kernel is defined (the package imports this first)
