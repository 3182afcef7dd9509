"""`soccer-lab lineage RUN_DIR`: a player's family tree from a run folder's lineage records: the ancestors
whose genes it carries (each with fitness, goals and how it was made), each of its rules with the ancestor
it came from, its chromosome in compact notation; as text, and as an SVG or Graphviz DOT file."""

from __future__ import annotations

from pathlib import Path
from typing import Annotated, Optional

import typer

from app.cli.common import fail

RunDir = Annotated[Path, typer.Argument(
    help="A run folder (what soccer-lab evolve --out wrote, or the app's runs/<id>).", show_default=False)]
Generation = Annotated[Optional[int], typer.Option(
    "--generation", "-g", min=0, help="The generation of the player. (default: the generation of the best so far)",
    show_default=False)]
Index = Annotated[Optional[int], typer.Option(
    "--index", "-i", min=0, help="The player's place in its generation (0 first). (default: the generation's best)",
    show_default=False)]
Generations = Annotated[Optional[int], typer.Option(
    "--generations", "-n", min=0, help="How many generations back to follow. (default: to generation 0)",
    show_default=False)]
Svg = Annotated[Optional[Path], typer.Option("--svg", help="Also draw the tree, rules and chromosome to this SVG file.",
                                             show_default=False)]
Dot = Annotated[Optional[Path], typer.Option("--dot", help="Also write the tree as a Graphviz DOT file.",
                                             show_default=False)]


def lineage_command(run_dir: RunDir, generation: Generation = None, index: Index = None,
                    generations: Generations = None, svg: Svg = None, dot: Dot = None) -> None:
    """A player's family tree: by default the run's best so far; --generation G for that generation's best,
    with --index I for any of its players."""
    from app.lineage import RunLineage
    from app.lineage_drawing import tree_dot, tree_svg, tree_text
    from ga.lineage import LineageError

    try:
        lineage = RunLineage.from_folder(run_dir)
        view = lineage.family_tree(lineage.place(generation, index), generations)
    except LineageError as exc:
        fail(str(exc))
    typer.echo(tree_text(view), nl=False)
    for path, text in ((svg, lambda: tree_svg(view, with_rules=True)), (dot, lambda: tree_dot(view))):
        if path is not None:
            try:
                path.write_text(text())
            except OSError as exc:
                fail(f"cannot write {path}: {exc.strerror or exc}")
            typer.echo(f"wrote {path}")
