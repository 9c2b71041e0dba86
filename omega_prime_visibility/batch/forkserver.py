"""The fork server a batch's local worker processes start from: what it imports once (:data:`PRELOAD`), and
starting it while the command line is still importing (:func:`start_early`).

Light on purpose: the command line imports it before anything else.
"""

from __future__ import annotations

import itertools
import multiprocessing
import multiprocessing.forkserver
from collections.abc import Sequence

PRELOAD = [
    "omega_prime_visibility.api",
    "omega_prime_visibility.inputs.io",
    "omega_prime_visibility.inputs.reader",
    "omega_prime_visibility.batch.task",
]
"""What every file needs, imported before the first one. Not omega-prime (2 to 3 s): MCAP files are read without
it, and a batch of OSI traces imports it with the first trace."""


def context() -> multiprocessing.context.BaseContext:
    """The start method of the workers: forkserver where available (its server imports :data:`PRELOAD` once, not
    every worker), else spawn. Not fork: workers use polars, whose thread pool does not survive a plain fork of a
    process that used it."""
    if "forkserver" not in multiprocessing.get_all_start_methods():
        return multiprocessing.get_context("spawn")
    forkserver = multiprocessing.get_context("forkserver")
    # safe: importing starts none of polars' worker threads, and no polars work runs in the fork server
    forkserver.set_forkserver_preload(PRELOAD)
    return forkserver


def start_early(argv: Sequence[str]) -> bool:
    """Start the fork server now if ``argv`` is a shell ``batch`` that will compute in local worker processes (no
    dask scheduler, not one worker): it imports :data:`PRELOAD` on another core while this process imports the
    command line (0.4 s of a short batch). True if started.

    >>> start_early(["omega-prime-visibility", "run", "a.mcap"]), start_early(["x", "batch", "in", "--workers", "1"])
    (False, False)
    """
    args = list(argv[1:])
    # a worker starting up imports the command line again as its main module (multiprocessing marks the process
    # "_inheriting" meanwhile, the mark its own check of this uses): nothing to start there
    if multiprocessing.parent_process() is not None or getattr(multiprocessing.current_process(), "_inheriting", 0):
        return False
    if not args or args[0] != "batch" or "forkserver" not in multiprocessing.get_all_start_methods():
        return False
    if any(a.startswith(("--scheduler", "--help")) for a in args) or "--workers=1" in args:
        return False
    if any(a == "--workers" and b == "1" for a, b in itertools.pairwise(args)):
        return False
    context()
    multiprocessing.forkserver.ensure_running()
    return True
