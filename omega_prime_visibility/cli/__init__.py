"""Command line: ``omega-prime-visibility run RECORDING --ego 0`` prints or writes the visibility table of one
recording; ``batch INPUTS... -o OUTDIR`` computes many, locally or on a dask cluster; ``animate`` renders a GIF
or MP4, ``report`` an interactive HTML page."""

from __future__ import annotations

import sys

import typer

from ..engines import ENGINES, ENGINES_3D
from . import batch, compile_kernels, pictures, run, statistics  # noqa: F401  (each registers its commands on the app)
from .app import HELP, app
from .batch import print_summary
from .common import fail

__all__ = ["HELP", "app", "fail", "main", "print_summary"]


@app.command(short_help="list the available engines")
def engines() -> None:
    """List the available engines."""
    for name in sorted(ENGINES):
        typer.echo(name)
    for name in sorted(ENGINES_3D):
        typer.echo(f"{name} (--mode 3d)")


def main() -> None:
    """The ``omega-prime-visibility`` command."""
    app(sys.argv[1:])
