"""The `soccer-lab` command line. Each command group lives in its own module here."""

from __future__ import annotations

import typer

app = typer.Typer(
    name="soccer-lab",
    help="Evolve, inspect and teach fuzzy-rule robot soccer players.",
    no_args_is_help=True,
    add_completion=False,
    pretty_exceptions_enable=False,
)


def _register() -> None:
    # Imported here so that `soccer-lab --help` lists every command and each module stays independent.
    from app.cli import rules

    app.add_typer(rules.app, name="rules")
    from app.cli import evolve, play
    from app.cli.common import OneLineErrors

    app.command("evolve", cls=OneLineErrors)(evolve.evolve_command)
    app.command("random-search", cls=OneLineErrors)(evolve.random_search_command)
    app.command("play", cls=OneLineErrors)(play.play_command)
    from app.cli import experiment

    app.command("experiment", cls=OneLineErrors)(experiment.experiment_command)
    from app.cli import serve

    app.command("serve", cls=OneLineErrors)(serve.serve_command)
    from app.cli import lineage

    app.command("lineage", cls=OneLineErrors)(lineage.lineage_command)


def main() -> None:
    _register()
    app()
