"""The `soccer-lab` command line. Each command lives in its own module here and is imported only when it
runs or shows its help: `soccer-lab --help` imports none of them, and a command's help imports that command's
options, not the engine, the app or the plotting it runs with (benchmarks/cli_help.py times every help)."""

from __future__ import annotations

import importlib
from functools import cache
from typing import Any, NamedTuple

import typer
import typer.main

from soccer_lab.app.cli.common import TYPER_SETTINGS, CommandList, OneLineErrors


class Entry(NamedTuple):
    """Where a command lives, and the line `soccer-lab --help` shows for it (its short help)."""

    module: str
    attribute: str  # the command's function, or the typer.Typer of a group of commands
    summary: str


COMMANDS = {
    "serve": Entry("soccer_lab.app.cli.serve", "serve_command", "Start the app: the UI, the JSON API and the rerun viewer."),
    "play": Entry("soccer_lab.app.cli.play", "play_command", "Play a rulebase's games and print how each went."),
    "match": Entry("soccer_lab.app.cli.match", "match_command",
                   "Play two rulebases against each other and print wins, draws, losses and goals."),
    "evolve": Entry("soccer_lab.app.cli.evolve", "evolve_command", "Evolve a goal-scoring rulebase with the messy-coded GA."),
    "random-search": Entry("soccer_lab.app.cli.evolve", "random_search_command",
                           "The baseline: the same evaluations spent on random rulebases."),
    "experiment": Entry("soccer_lab.app.cli.experiment", "experiment_command",
                        "Reproduce the chapter's experiments and judge its findings."),
    "rules": Entry("soccer_lab.app.cli.rules", "app", "Work with rulebases: check, infer, export, decode, usage, simplify."),
    "lineage": Entry("soccer_lab.app.cli.lineage", "lineage_command",
                     "A player's family tree: its ancestors and where each of its rules came from."),
}


@cache
def load_command(name: str) -> Any:
    """The click command `name` is, built from its module (imported now)."""
    entry = COMMANDS[name]
    target = getattr(importlib.import_module(entry.module), entry.attribute)
    if isinstance(target, typer.Typer):
        command = typer.main.get_command(target)
    else:
        alone = typer.Typer(**TYPER_SETTINGS)
        alone.command(name, cls=OneLineErrors)(target)
        command = typer.main.get_command(alone)
    command.name, command.short_help = name, entry.summary
    return command


class LazyCommands(CommandList):
    """The root group: lists COMMANDS by their summaries, imports a command's module only when it is used."""

    def list_commands(self, ctx: Any) -> list[str]:
        return list(COMMANDS)

    def get_command(self, ctx: Any, name: str) -> Any:
        return load_command(name) if name in COMMANDS else None

    def summary(self, ctx: Any, name: str) -> str:
        return COMMANDS[name].summary


app = typer.Typer(name="soccer-lab", cls=LazyCommands, no_args_is_help=True, pretty_exceptions_enable=False,
                  **TYPER_SETTINGS)


@app.callback()
def soccer_lab() -> None:
    """Evolve, inspect and teach fuzzy-rule robot soccer players."""


def main() -> None:
    app()
