"""The package's cache locator put first among numba's without importing numba when the package is imported
(importing the package stays quick): the moment numba loads its caching module, or at once where it has."""

from __future__ import annotations

import importlib.abc
import importlib.machinery
import sys

LOCATOR = f"{__package__}.locator"


def install_locator() -> None:
    """Put the package's cache locator (:class:`.locator.PackageLocator`) first among numba's, now if numba's
    caching module is loaded, else the moment it is (numba reads its locators when a kernel is defined)."""
    caching = sys.modules.get("numba.core.caching")
    if caching is not None:
        from . import locator  # noqa: F401  (it registers itself)
    elif not any(isinstance(finder, _AfterNumbaCaching) for finder in sys.meta_path):
        sys.meta_path.insert(0, _AfterNumbaCaching())


class _AfterNumbaCaching(importlib.abc.MetaPathFinder):
    """Finds ``numba.core.caching`` as the other finders do, and registers the package's locator right after the
    module has run."""

    def find_spec(self, name, path, target=None):
        if name != "numba.core.caching":
            return None
        spec = importlib.machinery.PathFinder.find_spec(name, path, target)
        if spec is None or spec.loader is None:
            return spec
        sys.meta_path.remove(self)  # once
        spec.loader = _ThenRegister(spec.loader)
        return spec


class _ThenRegister(importlib.abc.Loader):
    def __init__(self, loader) -> None:
        self.loader = loader

    def create_module(self, spec):
        return self.loader.create_module(spec)

    def exec_module(self, module) -> None:
        self.loader.exec_module(module)
        if LOCATOR not in sys.modules:  # (else it is loading numba itself, and registers at its end)
            from . import locator  # noqa: F401  (it registers itself)
