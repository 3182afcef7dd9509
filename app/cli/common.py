"""Shared CLI conventions: bad input gives one clear line on stderr and exit status 2."""

from __future__ import annotations

from typing import Any, NoReturn

import typer
from typer._click.exceptions import UsageError  # typer vendors click: its errors are not click's
from typer.core import TyperCommand, TyperGroup

USAGE_ERROR = 2
# Every Typer of the CLI takes these: help as plain text wrapped to the terminal (rich's tables cut long option
# names at 80 columns, and importing rich costs every --help); no shell-completion options.
TYPER_SETTINGS: dict[str, Any] = {"rich_markup_mode": None, "add_completion": False}


def fail(message: str) -> NoReturn:
    typer.echo(f"error: {message}", err=True)
    raise typer.Exit(USAGE_ERROR)


class OneLineErrors(TyperCommand):
    """Use as `@app.command(cls=OneLineErrors)`: a malformed option or argument of the command (click's
    own checks: unknown option, not an integer...) prints one `error:` line too, not a usage box. Its help
    lists the options under their panel's heading (`rich_help_panel`, e.g. "Game"), plain text wrapped to
    the terminal."""

    def format_options(self, ctx: Any, formatter: Any) -> None:
        sections: dict[str, list[tuple[str, str]]] = {}
        for param in self.get_params(ctx):
            record = param.get_help_record(ctx)
            if record is not None:
                heading = ("Arguments" if param.param_type_name == "argument"
                           else getattr(param, "rich_help_panel", None) or "Options")
                sections.setdefault(heading, []).append(record)
        for heading, records in sections.items():
            with formatter.section(heading):
                formatter.write_dl(records)

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


class CommandList(TyperGroup):
    """A group of commands (`typer.Typer(cls=CommandList)`) whose help lists each command with the first
    paragraph of its help whole, wrapped (click cuts it at 45 columns with "..."), as its short help."""

    def get_command(self, ctx: Any, name: str) -> Any:
        command = super().get_command(ctx, name)
        if command is not None and not command.short_help:
            command.short_help = " ".join((command.help or "").split("\n\n")[0].split())
        return command

    def format_commands(self, ctx: Any, formatter: Any) -> None:
        with formatter.section("Commands"):
            formatter.write_dl([(name, self.summary(ctx, name)) for name in self.list_commands(ctx)])

    def summary(self, ctx: Any, name: str) -> str:
        return self.get_command(ctx, name).short_help
