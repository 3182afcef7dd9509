"""Shared CLI conventions: bad input gives one clear line on stderr and exit status 2."""

from __future__ import annotations

from typing import Any, NoReturn

import click
import typer
from typer.core import TyperCommand

USAGE_ERROR = 2


def fail(message: str) -> NoReturn:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(USAGE_ERROR)


class OneLineErrors(TyperCommand):
    """Use as `@app.command(cls=OneLineErrors)`: a malformed option or argument of the command (click's
    own checks: unknown option, not an integer...) prints one `error:` line too, not a usage box."""

    def make_context(self, info_name: str | None, args: list[str], parent: click.Context | None = None,
                     **extra: Any) -> click.Context:
        try:
            return super().make_context(info_name, args, parent=parent, **extra)
        except click.UsageError as exc:
            fail(exc.format_message())

    def invoke(self, ctx: click.Context) -> Any:
        try:  # typer converts option values (int, float, ...) here, after parsing
            return super().invoke(ctx)
        except click.UsageError as exc:
            fail(exc.format_message())
