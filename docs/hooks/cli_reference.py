"""mkdocs hooks: the CLI reference page is written from the commands themselves (their ``--help``), so it never
drifts from the code (a page holding the line ``<!-- cli-reference -->`` gets it in that place); the docstrings'
cross-reference roles (``:func:`name```, written for readers of the source) are shown as plain code."""

from __future__ import annotations

import re

import click
import typer

MARKER = "<!-- cli-reference -->"
WIDTH = 76  # columns: the help blocks fit the content column of the site (about 80 characters of code)


def cli_reference() -> str:
    """Markdown with the help of the program and of every command, as a shell user sees it."""
    from omega_prime_visibility.cli import app

    command = typer.main.get_command(app)
    parts = []
    with click.Context(command, info_name="omega-prime-visibility", terminal_width=WIDTH) as ctx:
        parts.append(f"```text\n{command.get_help(ctx)}\n```")
        for name in command.list_commands(ctx):
            sub = command.get_command(ctx, name)
            with click.Context(sub, info_name=name, parent=ctx, terminal_width=WIDTH) as sub_ctx:
                parts.append(f"## `{name}`\n\n```text\n{sub.get_help(sub_ctx)}\n```")
    return "\n\n".join(parts)


def on_page_markdown(markdown: str, **kwargs) -> str:
    return markdown.replace(MARKER, cli_reference()) if MARKER in markdown else markdown


ROLE = re.compile(r":(?:func|mod|class|data|meth|attr|obj):(<code>)~?\.*")


def on_page_content(html: str, **kwargs) -> str:
    return ROLE.sub(r"\1", html)
