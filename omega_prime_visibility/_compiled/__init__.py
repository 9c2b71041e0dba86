"""Where numba keeps the compiled kernels, and when a kernel must be compiled anew.

numba checks a cached kernel against the file it is defined in only. A kernel that calls (and so compiles in) one
from another module would keep the old machine code after that other module changed: after an upgrade in place or
a ``git pull`` in a clone, silently wrong numbers. Here each module's kernels are stamped with a hash of every
source they can reach (:func:`.sources.source_stamps`): editing a module compiles again the kernels that reach it, and
only those. The kernels are kept under ``~/.cache/omega-prime-visibility/kernels/`` (or under
``$XDG_CACHE_HOME``), in folders named after the modules' places in the package, so a cache compiled anywhere
else (when the package was built, in another clone) is valid here too: the package's own copy
(:data:`.sources.BUNDLE`, written when it is built or by ``omega-prime-visibility compile``) fills an empty user cache.
``NUMBA_CACHE_DIR``, when set, is the user's choice and is left alone; where no cache folder can be written,
numba's default (next to the sources) applies. numba itself is not imported here (importing the package stays
quick): the package's locator is put first among numba's when numba loads its caching module
(:mod:`.hook`, :mod:`.locator`).

Every kernel is declared with :func:`.kernel.njit`, which makes numba's dispatcher only when first needed: the
kernels the reader and the engines call from Python (2D and 3D) run from a build made ahead of time (:mod:`.ahead`,
built by ``compile`` with :mod:`.ahead_build`) without importing numba, where that build holds them for the current
sources.
"""

from .hook import install_locator
from .progress import (
    Heartbeat,
    announce_compilation,
    compiled_before,
    has_run,
    kernel_folder,
    mark_compiled,
    marker,
    marker_name,
)
from .sources import (
    BUNDLE,
    PACKAGE,
    cache_base,
    kernel_closures,
    kernel_sources,
    kernels_cache,
    remembered_sources,
    remembered_sources_key,
    source_stamps,
    sources_key,
)

__all__ = [
    "BUNDLE",
    "PACKAGE",
    "Heartbeat",
    "announce_compilation",
    "cache_base",
    "compiled_before",
    "has_run",
    "install_locator",
    "kernel_closures",
    "kernel_folder",
    "kernel_sources",
    "kernels_cache",
    "mark_compiled",
    "marker",
    "marker_name",
    "remembered_sources",
    "remembered_sources_key",
    "source_stamps",
    "sources_key",
]

install_locator()  # on import, before any kernel is defined (the package imports this first)
