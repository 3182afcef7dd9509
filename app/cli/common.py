"""Shared CLI conventions: bad input gives one clear line on stderr and exit status 2."""

from __future__ import annotations

from typing import Any, NoReturn

import typer
from typer._click.exceptions import UsageError  # typer vendors click: its errors are not click's
from typer.core import TyperCommand

USAGE_ERROR = 2


def fail(message: str) -> NoReturn:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(USAGE_ERROR)


class OneLineErrors(TyperCommand):
    """Use as `@app.command(cls=OneLineErrors)`: a malformed option or argument of the command (click's
    own checks: unknown option, not an integer...) prints one `error:` line too, not a usage box."""

    def make_context(self, info_name: str | None, args: list[str], parent: Any = None, **extra: Any) -> Any:
        try:
            return super().make_context(info_name, args, parent=parent, **extra)
        except UsageError as exc:
            fail(exc.format_message())

    def invoke(self, ctx: Any) -> Any:
        try:  # typer converts option values (int, float, ...) here, after parsing
            return super().invoke(ctx)
        except UsageError as exc:
            fail(exc.format_message())
