"""mkdocs hook: the `<!-- generated: cli -->` block of a page
(docs/hooks/generated_block.py) holds the reference of every `soccer-lab` command.

It is typer's own generator (the one `typer soccer_lab.app.cli utils docs` runs), called in this process on the CLI's
click group, so every command is found as `soccer-lab --help` finds it (the root group loads its commands
only when asked) and a failure stops the build instead of leaving the page empty.
"""

from __future__ import annotations

from generated_block import has_block, with_block  # docs/hooks/, on sys.path as mkdocs loads hooks

NAME = "cli"


def cli_reference() -> str:
    import typer
    import typer.main
    from typer.cli import get_docs_for_click

    from soccer_lab.app.cli import app

    command = typer.main.get_command(app)
    context = typer.Context(command, info_name="soccer-lab")
    text = get_docs_for_click(obj=command, ctx=context, name="soccer-lab")
    # Each command one level down, under the page's own title: `## soccer-lab`, `### soccer-lab evolve`, ...
    return "\n".join("#" + line if line.startswith("#") else line for line in text.strip().splitlines())


def on_page_markdown(markdown: str, **_: object) -> str:
    return with_block(markdown, NAME, cli_reference()) if has_block(markdown, NAME) else markdown
