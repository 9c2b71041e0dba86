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
    " of one recording; 'batch INPUTS -o FOLDER' computes many, locally or on a dask cluster, and 'statistics"
    " FOLDER' sums them up; 'animate' renders a GIF or MP4 and 'report' an interactive HTML page; 'engines' lists"
    " the engines and 'compile' prepares them (make run does). Add --help after a command for its options."
)
ORDER = ("run", "batch", "statistics", "animate", "report", "engines", "compile")


class CommandsInOrder(typer.core.TyperGroup):
    """The commands listed in :data:`ORDER` (the order a new user needs them), whatever order they register in."""

    def list_commands(self, ctx) -> list[str]:
        return sorted(super().list_commands(ctx), key=lambda name: ORDER.index(name) if name in ORDER else len(ORDER))


app = typer.Typer(cls=CommandsInOrder, add_completion=False, no_args_is_help=True, help=HELP, rich_markup_mode=None)
# an argument's metavar names it (RECORDING, INPUTS); typer would add its type as a tag (<path>, <list[str]>)
typer.core.TyperArgument.display_type_rich = lambda self, ctx: None


def _usage_name(self) -> str:
    """An argument in the usage line as click writes it, RECORDING or [RECORDING] (typer writes a required one in
    braces, {RECORDING}, which reads as a placeholder to type with its braces)."""
    name = self.display_name_raw if self.required else f"[{self.display_name_raw}]"
    return name + ("..." if self.nargs != 1 else "")


if hasattr(typer.core.TyperArgument, "_usage_display_name"):
    typer.core.TyperArgument._usage_display_name = _usage_name
else:  # typer before 0.29 (pinned below it for omega-prime's own command line) writes the usage in make_metavar
    _typer_metavar = typer.core.TyperArgument.make_metavar

    def _make_metavar(self, ctx, *, usage: bool = False) -> str:
        if not usage:
            return _typer_metavar(self, ctx, usage=usage)
        var = self.metavar or (self.name or "").upper()
        name = var if self.required else f"[{var}]"
        return name + ("..." if self.nargs != 1 and not var.endswith("...") else "")

    typer.core.TyperArgument.make_metavar = _make_metavar


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
