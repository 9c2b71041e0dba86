"""Compiling the ahead-of-time build (:mod:`.ahead`) with numba's ahead-of-time compiler (``numba.pycc``).

The kernels and argument types to build are those the reader's and the engines' paths called from Python while they
ran (:func:`.kernel.record_calls`), each with the signature numba compiled for those types, so the build holds
exactly what such a call uses. This module imports numba (and needs setuptools, as numba's ahead-of-time compiler does).
"""

from __future__ import annotations

import json
import os
import shutil
import tempfile
import warnings
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from . import ahead, kernel
from .sources import remembered_sources_key


def type_key(numba_type) -> tuple | None:
    """:func:`.kernel.value_key` of the values numba types as ``numba_type``; None for a type the build leaves to
    numba (records, lists, omitted arguments).

    Examples
    --------
    >>> from numba import types
    >>> type_key(types.Array(types.float64, 2, "C", readonly=True))
    ('array', '<f8', 2, 'C', True, True)
    >>> type_key(types.Tuple((types.int64, types.none)))
    ('tuple', ('scalar', '<i8'), ('none',))
    """
    from numba.core import types
    from numba.np.numpy_support import as_dtype

    kind = type(numba_type)
    if kind is types.Array:  # (exactly: no subclass of it, no literal, no named tuple)
        if type(numba_type.dtype) not in (types.Boolean, types.Integer, types.Float, types.Complex):
            return None
        readonly = not numba_type.mutable
        key = ("array", as_dtype(numba_type.dtype).str, numba_type.ndim, numba_type.layout, readonly)
        return (*key, numba_type.aligned)
    if kind in (types.Boolean, types.Integer, types.Float):
        return ("scalar", as_dtype(numba_type).str)
    if kind is types.NoneType:
        return ("none",)
    if kind in (types.Tuple, types.UniTuple):
        keys = tuple(type_key(t) for t in numba_type.types)
        return None if None in keys else ("tuple", *keys)
    return None


def exports(calls: dict[kernel.Kernel, set[tuple]]) -> list[tuple[str, object, kernel.Kernel, tuple]]:
    """Each kernel and argument types called (``calls``) as ``(export name, numba signature, kernel, argument
    types)``, in a stable order; argument types numba compiled no signature for (or that the build cannot hold) are
    left out."""
    found = []
    for k in sorted(calls, key=lambda k: (k.__module__, k.__qualname__)):
        if set(k.options) - BUILT_OPTIONS:  # (numba's ahead-of-time compiler takes no options)
            continue
        overloads = {type_key_of_arguments(args): result for args, result in k.dispatcher.overloads.items()}
        for key in sorted(calls[k], key=repr):
            result = overloads.get(key)
            if result is not None and key is not None:
                found.append((f"kernel_{len(found)}", result.signature, k, key))
    return found


BUILT_OPTIONS = {"cache", "inline"}
"""The kernel options the build keeps as numba's dispatcher does (a kernel with others, such as
``error_model="numpy"``, is left to numba: the ahead-of-time compiler would drop them)."""


def type_key_of_arguments(arguments: tuple) -> tuple | None:
    """:func:`type_key` of a signature's argument types, as :func:`.kernel.value_key` makes it of the arguments."""
    keys = tuple(type_key(t) for t in arguments)
    return None if None in keys else ("tuple", *keys)


def build(calls: dict[kernel.Kernel, set[tuple]], folder: Path, covers: Sequence[str] = ()) -> Path:
    """Compile the kernels ``calls`` names into the ahead-of-time build in ``folder`` (replaced whole: another
    process sees the old build or the new one, never a part), noting the paths that called them (``covers``, the
    names ``compile`` gives them); the folder."""
    numba = kernel._numba()  # (kernels' globals typed as their dispatchers)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # (numba says its ahead-of-time compiler is to be replaced)
        from numba.pycc import CC

    chosen = exports(calls)
    if not chosen:
        raise ValueError("no kernel was called: nothing to build ahead of time")
    folder.parent.mkdir(parents=True, exist_ok=True)
    partial = Path(tempfile.mkdtemp(prefix=f".{folder.name}.", dir=folder.parent))
    try:
        compiler = CC(ahead.MODULE)
        compiler.output_dir = str(partial)
        level = ahead.processor_level()
        compiler.target_cpu = level  # x86-64-v3 where this machine has it (loaded only where it is), else the baseline
        for name, signature, k, _ in chosen:
            compiler.export(name, signature)(k.py_func)
        compiler.compile()
        (extension,) = partial.glob(f"{ahead.MODULE}.*")
        sha256 = ahead.digest(extension)
        named = extension.with_name(f"{ahead.MODULE}-{sha256[:16]}{extension.name.removeprefix(ahead.MODULE)}")
        extension.rename(named)  # (named by its digest: a process reading an older manifest never loads this one)
        manifest = {"format": ahead.FORMAT, "key": remembered_sources_key(), "numpy": int(np.__version__.split(".")[0])}
        manifest |= {"numba": numba.__version__, "cpu": level, "extension": named.name, "sha256": sha256}
        manifest["covers"] = list(covers)
        manifest["kernels"] = {}
        for name, _, k, key in chosen:
            entries = manifest["kernels"].setdefault(f"{k.__module__}:{k.__qualname__}", [])
            entries.append({"export": name, "arguments": key})
        (partial / ahead.MANIFEST).write_text(json.dumps(manifest), encoding="utf-8")
        old = folder.with_name(f".{folder.name}.{os.getpid()}.old")
        if folder.exists():
            os.replace(folder, old)
        os.replace(partial, folder)
        shutil.rmtree(old, ignore_errors=True)
    finally:
        shutil.rmtree(partial, ignore_errors=True)
    return folder
