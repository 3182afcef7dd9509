"""`soccer-lab rules ...`: check, infer, export, decode rule text."""

from __future__ import annotations

import typer

app = typer.Typer(help="Work with rulebases: check, infer, export, decode.", no_args_is_help=True)
