"""The plotting libraries are an optional extra: import them with an error that says how to install them."""

from __future__ import annotations

import importlib
from types import ModuleType

EXTRA_HINT = "pip install 'omega-prime-visibility[plot]'"


def require(module: str, purpose: str = "plotting") -> ModuleType:
    """Import ``module``; if it is missing, raise ``ImportError`` naming the ``plot`` extra.

    >>> require("math").pi > 3
    True
    """
    try:
        return importlib.import_module(module)
    except ImportError as e:
        top = module.split(".")[0]
        raise ImportError(
            f"{purpose} needs {top!r}, which is not installed; it comes with the 'plot' extra: {EXTRA_HINT}"
        ) from e
