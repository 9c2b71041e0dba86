"""Command line: ``omega-prime-visibility run RECORDING --ego 0`` prints or writes the visibility table of one
recording; ``batch INPUTS... -o OUTDIR`` computes many, locally or on a dask cluster; ``animate`` renders a GIF
or MP4, ``report`` an interactive HTML page."""

from __future__ import annotations

import atexit
import gc
import sys

from ..batch.forkserver import start_early

start_early(sys.argv)  # a local batch: its workers' fork server imports while the command line does (below)

import typer  # noqa: E402

from ..engines.registry import ENGINES, ENGINES_3D  # noqa: E402
from . import batch, compile_kernels, pictures, run, statistics  # noqa: E402, F401  (each registers its commands)
from .app import HELP, app  # noqa: E402
from .batch import print_summary  # noqa: E402
from .common import fail  # noqa: E402

__all__ = ["HELP", "app", "fail", "main", "print_summary"]


@app.command(short_help="list the available engines")
def engines() -> None:
    """List the available engines, each mode's default marked, and the area measure's own."""
    from ..engines.registry import DEFAULT_ENGINES, MESH_ENGINE

    for name in sorted(ENGINES):
        typer.echo(f"{name} (--mode 2d{', the default' if name == DEFAULT_ENGINES['2d'] else ''})")
    for name in sorted(ENGINES_3D):
        default = ", the default" if name == DEFAULT_ENGINES["3d"] else ""
        meshes = ", the default with static meshes" if name == MESH_ENGINE else ""
        typer.echo(f"{name} (--mode 3d{default}{meshes})")
    typer.echo("area (--measure area: its own exact engine, chosen by itself)")


def main() -> None:
    """The ``omega-prime-visibility`` command.

    On the first call the objects made so far (the imported modules') are frozen out of the garbage collector's
    way, and at the interpreter's exit what is left: a short run spent a fifth of its time collecting and tearing
    down garbage that was none. (A process that calls this again, a notebook or a test, freezes nothing of its
    runs before it exits.)
    """
    global _FROZEN
    if not _FROZEN:
        gc.freeze()
        atexit.register(gc.freeze)
        _FROZEN = True
    app(sys.argv[1:])


_FROZEN = False
