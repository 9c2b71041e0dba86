"""The command-line application object and the options before any command (``--version``); the commands register
themselves on it from their modules."""

from __future__ import annotations

import warnings
from typing import Annotated

import typer

from .common import show_warning

# plain help (no rich markup): option types are shown as the metavars below, never as <str>/<bool> tags, and
# text in square brackets is printed as written
HELP = (
    "Exact visibility of road users in traffic recordings. 'run RECORDING' prints or writes the visibility table"
    " of one recording; 'batch INPUTS -o FOLDER' computes many, locally or on a dask cluster; 'animate' renders a"
    " GIF or MP4 and 'report' an interactive HTML page. Add --help after a command for its options."
)
ORDER = ("run", "batch", "statistics", "animate", "report", "engines", "compile")


class CommandsInOrder(typer.core.TyperGroup):
    """The commands listed in :data:`ORDER` (the order a new user needs them), whatever order they register in."""

    def list_commands(self, ctx) -> list[str]:
        return sorted(super().list_commands(ctx), key=lambda name: ORDER.index(name) if name in ORDER else len(ORDER))


app = typer.Typer(cls=CommandsInOrder, add_completion=False, no_args_is_help=True, help=HELP, rich_markup_mode=None)
# an argument's metavar names it (RECORDING, INPUTS); typer would add its type as a tag (<path>, <list[str]>)
typer.core.TyperArgument.display_type_rich = lambda self, ctx: None


def _print_version(asked: bool) -> None:
    if asked:
        from .. import __version__

        typer.echo(f"omega-prime-visibility {__version__}")
        raise typer.Exit()


@app.callback()
def _options(
    version: Annotated[
        bool, typer.Option("--version", callback=_print_version, is_eager=True, help="print the version and exit")
    ] = False,
) -> None:
    """The options before the command; warnings are shown as one line each, without Python's source line."""
    warnings.showwarning = show_warning
