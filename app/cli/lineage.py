"""`soccer-lab lineage RUN_DIR`: a player's family tree from a run folder's lineage records: the ancestors
whose genes it carries (each with fitness, goals and how it was made), each of its rules with the ancestor
it came from, its chromosome in compact notation; as text, and as an SVG or Graphviz DOT file. The player's
true quality (re-played on the common fresh starts, app/runs/true_quality.py) stands beside its one-game
fitness; --rules writes the player as a rulebase file every tool opens (`rules ...`, `play`, the UI)."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Optional

import typer

from soccer_lab.app.cli.common import fail

if TYPE_CHECKING:
    from soccer_lab.fuzzy.rule import Rulebase
    from soccer_lab.fuzzy.vocabulary import Vocabulary

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
RulesOut = Annotated[Optional[Path], typer.Option(
    "--rules", help="Also write the player's rules to this file: rule text, or rulebase JSON when it ends in .json "
    "(opens in soccer-lab rules ..., play and the app).", show_default=False)]
Dot = Annotated[Optional[Path], typer.Option("--dot", help="Also write the tree as a Graphviz DOT file.",
                                             show_default=False)]


def lineage_command(run_dir: RunDir, generation: Generation = None, index: Index = None,
                    generations: Generations = None, svg: Svg = None, dot: Dot = None,
                    rules: RulesOut = None) -> None:
    """A player's family tree: by default the run's best so far; --generation G for that generation's best,
    with --index I for any of its players."""
    from soccer_lab.app.lineage.family_tree import RunLineage, player_quality_line
    from soccer_lab.app.lineage.drawing import tree_dot, tree_svg, tree_text
    from soccer_lab.ga.lineage import LineageError

    try:
        lineage = RunLineage.from_folder(run_dir)
        view = lineage.family_tree(lineage.place(generation, index), generations)
    except LineageError as exc:
        fail(str(exc))
    typer.echo(tree_text(view), nl=False)
    rulebase = view.codec.decode(view.tree.individual.chromosome)
    typer.echo(player_quality_line(run_dir, rulebase, view.vocabulary))
    for path, text in ((svg, lambda: tree_svg(view, with_rules=True)), (dot, lambda: tree_dot(view)),
                       (rules, lambda: _rulebase_file_text(rules, rulebase, view.vocabulary))):
        if path is not None:
            try:
                path.write_text(text())
            except OSError as exc:
                fail(f"cannot write {path}: {exc.strerror or exc}")
            typer.echo(f"wrote {path}")


def _rulebase_file_text(path: Path, rulebase: "Rulebase", vocabulary: "Vocabulary") -> str:
    from soccer_lab.app.rulebase_files import JSON_SUFFIX, rulebase_json, rulebase_text

    return (rulebase_json if path.suffix.lower() == JSON_SUFFIX else rulebase_text)(rulebase, vocabulary)
