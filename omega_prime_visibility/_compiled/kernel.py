"""The package's kernels: numba functions that run from the package's ahead-of-time build where it fits, and are
compiled (or loaded from numba's cache) by numba otherwise.

``@njit(cache=True)`` stands where ``@numba.njit(cache=True)`` would: it wraps the function in a :class:`Kernel`
without importing numba. Called from Python, a kernel takes the ahead-of-time build's machine code (:mod:`.ahead`)
when the build holds it for exactly these argument types and for the current sources; else numba's dispatcher,
made on first need, as before. The default engine's path thus runs without importing numba at all (0.3 s of a short
call, and a quarter of a second more loading its cached kernels). Inside other kernels numba sees a kernel as its
dispatcher (the two are registered together), so kernels call each other as numba functions always do.

Examples
--------
>>> import numpy as np
>>> @njit(cache=False)
... def twice(values):
...     return values * 2.0
>>> twice(np.array([1.0, 2.5])).tolist()
[2.0, 5.0]
>>> twice.py_func(3.0), twice.__name__
(6.0, 'twice')
"""

from __future__ import annotations

import functools
import importlib
import threading
from collections.abc import Callable
from typing import Any

import numpy as np

_LOCK = threading.RLock()
CALLED: dict[Kernel, set[tuple]] | None = None
"""While the ahead-of-time build records what the default path calls (:func:`record_calls`): each kernel called
from Python and the argument types (:func:`value_key`) it was called with; None otherwise."""


def njit(**options: Any) -> Callable[[Callable], Kernel]:
    """The decorator of every kernel: ``numba.njit(**options)`` made when first needed (see the module's text)."""

    def wrap(py_func: Callable) -> Kernel:
        return Kernel(py_func, options)

    return wrap


class Kernel:
    """A kernel: its Python function, numba's options for it, and (made on first need) numba's dispatcher.

    Attributes other than those here (``signatures``, ``overloads``, ``targetoptions``, ...) are the dispatcher's.
    """

    def __init__(self, py_func: Callable, options: dict[str, Any]) -> None:
        functools.update_wrapper(self, py_func)
        self.py_func = py_func
        self.options = options
        self._dispatcher = None
        self._built: list[tuple[tuple, Callable]] | None = None
        code = py_func.__code__
        self._arguments = code.co_argcount
        self._defaults = py_func.__defaults__ or ()

    @property
    def dispatcher(self):
        """numba's dispatcher of this kernel (numba imported and the dispatcher made on first use)."""
        if self._dispatcher is None:
            with _LOCK:
                if self._dispatcher is None:
                    numba = _numba()
                    self._dispatcher = numba.njit(**self.options)(self.py_func)
        return self._dispatcher

    def __call__(self, *args, **keywords):
        if keywords:
            return self.dispatcher(*args, **keywords)
        if len(args) < self._arguments and len(args) + len(self._defaults) >= self._arguments:
            args = args + self._defaults[len(args) - self._arguments :]  # (as numba fills them in)
        if CALLED is not None:  # (numba compiles them, so the build knows their signatures)
            _note(self, args)
            return self.dispatcher(*args)
        built = self._built
        if built is None:
            built = self._built = _ahead_exports(self)
        if built:
            key = value_key(args)
            for expected, function in built:
                if key == expected:
                    return function(*args)
        return self.dispatcher(*args)

    def __getattr__(self, name: str):
        if name.startswith("__") or name in ("_dispatcher", "_built", "py_func", "options"):
            raise AttributeError(name)
        return getattr(self.dispatcher, name)

    def __reduce__(self):
        return _kernel, (self.__module__, self.__qualname__)

    def __repr__(self) -> str:
        return f"<kernel {self.__module__}.{self.__qualname__}>"


def _kernel(module: str, qualname: str) -> Kernel:
    found: Any = importlib.import_module(module)
    for part in qualname.split("."):
        found = getattr(found, part)
    return found


def _ahead_exports(kernel: Kernel) -> list[tuple[tuple, Callable]]:
    from .ahead import exports_of  # (reads the build's manifest once per process)

    return exports_of(f"{kernel.__module__}:{kernel.__qualname__}")


def _note(kernel: Kernel, args: tuple) -> None:
    key = value_key(args)
    if key is not None:
        CALLED.setdefault(kernel, set()).add(key)


def record_calls() -> dict[Kernel, set[tuple]]:
    """Start noting each kernel called from Python with the argument types it was called with (the ahead-of-time
    build exports just those); the notes so far."""
    global CALLED
    if CALLED is None:
        CALLED = {}
    return CALLED


_NUMBA_READY = False


def _numba():
    """numba, imported, with :class:`Kernel` registered as its dispatcher to numba's typing (once)."""
    global _NUMBA_READY
    import numba

    if not _NUMBA_READY:
        with _LOCK:
            if not _NUMBA_READY:
                from numba.core import types
                from numba.extending import typeof_impl

                @typeof_impl.register(Kernel)
                def _typeof_kernel(value, context):
                    return types.Dispatcher(value.dispatcher)

                _NUMBA_READY = True
    return numba


def value_key(value: Any) -> tuple | None:
    """What numba's type of a Python value (or tuple of values) is made of, as plain data: an array's dtype, number
    of dimensions, layout, read-only flag and alignment; a scalar's dtype; a tuple's elements; None for a value of
    another kind (a list, a string): no ahead-of-time build fits it. :func:`.ahead_build.type_key` gives the same of
    a numba type.

    Examples
    --------
    >>> value_key(np.zeros((2, 3))[:, 1])
    ('array', '<f8', 1, 'A', False, True)
    >>> value_key((1, 2.0, True, None))
    ('tuple', ('scalar', '<i8'), ('scalar', '<f8'), ('scalar', '|b1'), ('none',))
    >>> value_key([1, 2]) is None
    True
    """
    kind = type(value)
    if kind is np.ndarray:
        flags = value.flags
        if not value.dtype.isnative or value.dtype.fields is not None or value.dtype.kind not in "biufc":
            return None
        layout = "C" if flags.c_contiguous else "F" if flags.f_contiguous else "A"
        return ("array", value.dtype.str, value.ndim, layout, not flags.writeable, bool(flags.aligned))
    if kind is bool:
        return ("scalar", "|b1")
    if kind is int:
        return ("scalar", "<i8") if -(2**63) <= value < 2**63 else None
    if kind is float:
        return ("scalar", "<f8")
    if value is None:
        return ("none",)
    if kind is tuple:
        keys = tuple(value_key(v) for v in value)
        return None if None in keys else ("tuple", *keys)
    if isinstance(value, np.generic) and value.dtype.kind in "biuf" and value.dtype.isnative:
        return ("scalar", value.dtype.str)
    return None
